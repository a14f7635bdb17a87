"""The spectral method for smooth walls: Fourier modes in θ times Legendre modes across the mapped cylinder.

On the rectangle (θ, s) of :mod:`.mesh` the Dirichlet form of :mod:`.fem` is

    k(u, v) = ∫∫ [ w u_θ v_θ − a (u_θ v_s + u_s v_θ) + (1 + a²)/w · u_s v_s ] dθ ds,   m(u, v) = ∫∫ w u v,

with a = lo'(θ) + s·w'(θ).  Every coefficient is a function of θ times 1, s or s², so in the Galerkin basis
φ_{i,n}(θ, s) = e_i(θ) p_n(s) (e_i: 1, cos mθ, sin mθ, m ≤ M; p_n = L_{n−1}(2s − 1) − L_{n+1}(2s − 1),
n ≤ N, Legendre polynomials vanishing on both walls) both matrices are sums of Kronecker products of a
θ-matrix ∫ c(θ) e_i^(α) e_j^(β) dθ (trapezoid rule on 4M + 64 points: exact up to the coefficient's own
Fourier tail, which decays geometrically for an analytic wall) and an s-matrix ∫ s^k p_n^(α) p_n'^(β) ds
(Gauss–Legendre on N + 24 points: exact, the integrand is a polynomial).  Not sin(nπs): a mapped state
has u_ss ≠ 0 on the walls (the cross term a·u_θs), so its sine coefficients decay only like n⁻³ and the
eigenvalues converge algebraically (measured: 2e-6 relative at N = 24); polynomials converge
exponentially.  The basis functions have definite parities — mirror: cos even, sin odd; half_turn:
(−1)^m; swap (θ + π, 1 − s): (−1)^(m+n+1), as p_n(1 − s) = (−1)^(n+1) p_n(s) — so each class is a
subset of the basis and is solved densely on its own.

Convergence is exponential in M and N for analytic walls and only algebraic at a kink (b'' a point
mass): walls with kinks or curvature jumps are refused (use ``"fem"``); so is a strip that fell apart.
The matrices are dense, (2M + 1)N square, but only one class's block is ever formed (from the Kronecker
factors, :func:`_block`): a thousand levels of the ε = 0.55 ellipse (N = 29, 9,367 modes, eight classes of
~1,170) need about a sixth of the memory of P4 elements and a quarter of their time
(``tests/benchmarks/bench_quantum_default.py``).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InvalidArgument
from ..validation import check_memory

__all__ = ["spectral_levels", "spectral_modes"]


def spectral_modes(strip, cells: int):
    """``(M, N)``: Fourier modes 0..M in θ and polynomial modes 1..N across for a resolution ``cells`` (= N).

    M follows from N: the highest level resolved across, λ ≈ (Nπ/w_max)², needs θ-modes up to √λ; with
    a margin of 1.5 and 8 modes."""
    n = int(cells)
    return math.ceil(1.5 * n * math.pi / strip.width_max) + 8, n


def _theta_basis(M, theta):
    """Values and θ-derivatives of e_i = (1/√(2π), cos mθ/√π, sin mθ/√π), and each's (m, is_sine)."""
    m = np.arange(1, M + 1)
    arg = np.outer(theta, m)
    c, s = np.cos(arg) / math.sqrt(math.pi), np.sin(arg) / math.sqrt(math.pi)
    values = np.hstack([np.full((theta.size, 1), 1 / math.sqrt(2 * math.pi)), c, s])
    slopes = np.hstack([np.zeros((theta.size, 1)), -s * m, c * m])
    modes = np.concatenate([[0], m, m])
    sine = np.concatenate([[False], np.zeros(M, bool), np.ones(M, bool)])
    return values, slopes, modes, sine


def _matrices(strip, M, N):
    q = 4 * M + 64
    theta = np.arange(q) * (2 * math.pi / q)
    _, dlo, width, dwidth = strip.walls(theta)
    values, slopes, modes, sine = _theta_basis(M, theta)
    weight = 2 * math.pi / q

    def t(c, a, b):
        return (a * (c * weight)[:, None]).T @ b

    nodes, gauss = np.polynomial.legendre.leggauss(N + 24)
    s, ws = 0.5 * (nodes + 1), 0.5 * gauss
    n = np.arange(1, N + 1)
    # φ_n = L_{n−1}(x) − L_{n+1}(x), x = 2s − 1 (zero at both walls), dφ_n/ds = −2(2n + 1) L_n(x)
    legendre = np.array([np.polynomial.legendre.legval(nodes, np.eye(N + 2)[j]) for j in range(N + 2)]).T
    sin = legendre[:, n - 1] - legendre[:, n + 1]
    cos = -2.0 * (2 * n + 1) * legendre[:, n]

    def x(k, a, b):
        return (a * (ws * s**k)[:, None]).T @ b

    return _kron_terms(t, x, values, slopes, width, dlo, dwidth, sin, cos), modes, sine, n


def _kron_terms(t, x, values, slopes, width, dlo, dwidth, sin, cos):
    """The stiffness and mass matrices as lists of Kronecker factors ``(θ-matrix, s-matrix)``."""
    stiffness = [(t(width, slopes, slopes), x(0, sin, sin)),
                 (-t(dlo, values, slopes), x(0, cos, sin)), (-t(dlo, slopes, values), x(0, sin, cos)),
                 (-t(dwidth, values, slopes), x(1, cos, sin)), (-t(dwidth, slopes, values), x(1, sin, cos)),
                 (t((1 + dlo**2) / width, values, values), x(0, cos, cos)),
                 (t(2 * dlo * dwidth / width, values, values), x(1, cos, cos)),
                 (t(dwidth**2 / width, values, values), x(2, cos, cos))]
    return stiffness, [(t(width, values, values), x(0, sin, sin))]


def _block(terms, index, N):
    """Rows and columns ``index`` of Σ kron(A, B) over ``terms``, symmetrised, without the whole product.

    Entry (i·N + a, j·N + b) of kron(A, B) is A[i, j]·B[a, b]: a class's block costs its own size squared
    per term, not the whole basis's (8× less work and memory for the ellipse's eight classes)."""
    i, a = np.divmod(index, N)
    block = sum(A[np.ix_(i, i)] * B[np.ix_(a, a)] for A, B in terms)
    return 0.5 * (block + block.T)


def _class_indices(M, N, names, characters):
    """``(character, basis indices)`` of each symmetry class (the parities in the module docstring)."""
    modes = np.concatenate([[0], np.arange(1, M + 1), np.arange(1, M + 1)])
    sine = np.concatenate([[False], np.zeros(M, bool), np.ones(M, bool)])
    m_all = np.repeat(modes, N)
    n_all = np.tile(np.arange(1, N + 1), modes.size)
    sine_all = np.repeat(sine, N)
    parity = {"swap": (-1.0) ** (m_all + n_all + 1), "mirror": np.where(sine_all, -1.0, 1.0),
              "half_turn": (-1.0) ** m_all}
    out = []
    for character in characters:
        member = np.ones(m_all.size, bool)
        for name, sign in zip(names, character):
            member &= parity[name] == sign
        out.append((character, np.flatnonzero(member)))
    return out


def spectral_levels(strip, levels, cells, symmetry=True, progress=None):
    """The lowest ``levels`` eigenvalues by the spectral method, class by class.

    Returns ``(values, characters, names)`` with ``characters`` (levels, r) of ±1 for ``names``.
    """
    from scipy.linalg import eigh

    from .symmetry import class_labels

    wall = strip.table.wall
    if wall.kinks or wall.breaks:
        raise InvalidArgument("`method` 'spectral' needs a smooth wall (this one has kinks or curvature jumps, "
                              "where Fourier modes converge only algebraically): use 'fem'")
    if not strip.periodic:
        raise InvalidArgument("`method` 'spectral' needs a strip open at every angle (this one fell apart): use 'fem'")
    M, N = spectral_modes(strip, cells)
    size = (2 * M + 1) * N
    names = strip.symmetries if symmetry else ()
    classes = _class_indices(M, N, names, class_labels(names))
    largest = max(index.size for _, index in classes)
    # dense, class by class: one class's stiffness and mass blocks, a product being added and eigh's copy,
    # beside the θ-factors (9 of them, (2M + 1)² each); measured: 160 MB peak at 9,367 modes in 8 classes
    check_memory(f"`cells` = {N} with the spectral method ({size} modes, dense {largest} × {largest} blocks)",
                 4.0 * 8.0 * largest * largest + 9 * 8.0 * (2 * M + 1) ** 2)
    (stiffness, mass), modes, sine, n = _matrices(strip, M, N)
    found_values, found_chars = [], []
    for character, index in classes:
        if index.size == 0:
            continue
        count = min(index.size, levels)
        values = eigh(_block(stiffness, index, N), _block(mass, index, N), eigvals_only=True,
                      subset_by_index=(0, count - 1))
        found_values.append(values)
        found_chars.append(np.tile(np.array(character, dtype=int), (values.size, 1)))
        if progress is not None:
            progress(1)
    values = np.concatenate(found_values)
    characters = np.vstack(found_chars).reshape(values.size, len(names))
    order = np.argsort(values, kind="stable")[:levels]
    return values[order], characters[order], tuple(names), M, N
