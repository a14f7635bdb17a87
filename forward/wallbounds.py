"""Certified ranges of the radius of curvature ``ρ = b + b''`` of a formula wall on cells of angles.

:func:`curvature_ranges` gives, for a wall made from an expression, a Fourier series or circle arcs, a
function ``(lo, hi) ↦ (lower, upper)`` whose interval holds every value of ``b + b''`` on each cell
``[lo, hi]`` (a cell of width 0 is a point: the interval then bounds the rounding of evaluating it), and
the angles where cells must be cut (kinks, breaks, the ends of arcs: ``b''`` is a measure there, or
jumps).  What each kind rests on:

* **expression** — affine arithmetic on the formula's own algorithm (:mod:`coinwall.forward.affine`), every
  operation rounded outward;
* **Fourier series** — ``ρ = a0 + Σ (1 − k²)(a_k cos kθ + s_k sin kθ)`` at the cell's middle ``m`` with its
  slope, and Taylor's remainder bounded by ``M2 = Σ |1 − k²| k² √(a_k² + s_k²) ≥ max |ρ''|``:
  ``|ρ(θ) − ρ(m) − ρ'(m)(θ − m)| ≤ M2 (θ − m)² / 2``; the sums' rounding is bounded by
  ``(2K + 8) eps Σ |terms|`` (K harmonics) and the arguments' by ``eps |kθ|``;
* **arcs** — ``ρ`` is the radius of each piece, exactly.

:mod:`coinwall.inverse.criticalcells` searches these cells for the minimum of ``ρ``.
"""

from __future__ import annotations

import numpy as np

from .angles import TWO_PI
from .intervalmath import EPS, down, up

__all__ = ["CurvatureRanges", "curvature_ranges"]


class CurvatureRanges:
    """Certified ranges of ``b + b''`` on cells: call with ``(lo, hi)`` arrays, get ``(lower, upper)``.

    Attributes
    ----------
    cuts : ndarray
        Angles in [0, 2π) that no cell may straddle (kinks, breaks, ends of arcs), sorted.
    kinks : ndarray
        The cuts where ``b'`` jumps (a point mass of ``b''``): a set of minima is split there.
    method : str
        What the ranges rest on (``"affine arithmetic"``, ``"Taylor bound"``, ``"exact"``).
    """

    def __init__(self, func, cuts, kinks, method: str):
        self._func = func
        self.cuts = np.unique(np.mod(np.asarray(cuts, dtype=float), TWO_PI))
        self.kinks = np.unique(np.mod(np.asarray(kinks, dtype=float), TWO_PI))
        self.method = method

    def __call__(self, lo, hi, decide=None):
        """``(lower, upper)`` of ``b + b''`` on each cell ``[lo[i], hi[i]]``.

        ``decide``: per cell an angle (NaN for none) whose side of every kink or break the cell is on: a
        cell that ends at a kink gets the range of that side's formula up to the kink (its one-sided
        limit), not of both sides (:meth:`coinwall.forward.affine.AffineProgram.enclose`)."""
        return self._func(np.asarray(lo, dtype=float), np.asarray(hi, dtype=float), decide)


def curvature_ranges(wall) -> CurvatureRanges:
    """The certified ranges of ``ρ = b + b''`` of a formula wall.

    Parameters
    ----------
    wall : coinwall.forward.Wall
        A wall made from an expression, a Fourier series or circle arcs.

    Returns
    -------
    CurvatureRanges

    Raises
    ------
    ValueError
        For a wall made from samples (their geometry is the data's own: :mod:`coinwall.inverse.certify`).

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> ranges = curvature_ranges(Wall.from_expression("1 + 0.1*cos(3*t)"))
    >>> lower, upper = ranges(np.array([0.0]), np.array([0.0]))   # ρ(0) = 1 − 0.8·0.1 = 0.2
    >>> bool(lower[0] <= 0.2 <= upper[0] and upper[0] - lower[0] < 1e-14)
    True
    """
    from .wall import _ExpressionBackend
    from .wallbackends import _ArcsBackend, _FourierBackend

    backend = wall._backend
    kinks = [k.angle for k in wall.kinks]
    cuts = kinks + list(wall.breaks)
    if isinstance(backend, _ExpressionBackend):
        return CurvatureRanges(_expression_ranges(backend.parsed), cuts, kinks, "affine arithmetic")
    if isinstance(backend, _ArcsBackend):
        return CurvatureRanges(_arcs_ranges(backend), cuts + list(backend.angles), kinks, "exact")
    if isinstance(backend, _FourierBackend) and wall.samples is None:
        return CurvatureRanges(_fourier_ranges(backend), cuts, kinks, "Taylor bound")
    raise ValueError(f"wall {wall.description!r}: certified ranges of b + b'' are for formula walls, not samples")


def _expression_ranges(parsed):
    import casadi as ca

    from .affine import AffineProgram

    t, b = parsed.symbol, parsed.expr
    d2 = ca.jacobian(ca.jacobian(b, t), t)
    # "cse": a value used twice is computed once, so that its two uses share their unknowns
    program = AffineProgram(ca.Function("rho", [t], [b + d2], {"cse": True}))

    def ranges(lo, hi, decide=None):
        return program.enclose(lo, hi, decide=decide)[0]
    return ranges


def _arcs_ranges(backend):
    radii = np.asarray(backend.radii, dtype=float)

    def ranges(lo, hi, decide=None):
        piece = backend._piece(0.5 * lo + 0.5 * hi)  # cells never straddle a piece's end
        return radii[piece], radii[piece]
    return ranges


def _fourier_ranges(backend):
    k = backend.k
    weight = 1.0 - k * k
    size = np.abs(backend.cos) + np.abs(backend.sin)
    second = float(np.sum(np.abs(weight) * k * k * np.hypot(backend.cos, backend.sin)))  # ≥ max |ρ''|
    terms0 = abs(backend.a0) + float(np.sum(np.abs(weight) * size))
    terms1 = float(np.sum(np.abs(weight) * k * size))
    terms2 = float(np.sum(np.abs(weight) * k * k * size))
    summing = (2 * k.size + 8) * EPS

    def ranges(lo, hi, decide=None):
        m = 0.5 * lo + 0.5 * hi
        h = up(np.maximum(hi - m, m - lo))
        b, d1, d2, d3 = backend._eval(m, (0, 1, 2, 3))
        rho, slope = b + d2, d1 + d3
        # rounding of the sums, and of the arguments k·m (|error| ≤ eps·|k m|, times |d/dθ| of each term)
        err0 = summing * terms0 + EPS * np.abs(m) * terms1
        err1 = summing * terms1 + EPS * np.abs(m) * terms2
        spread = (np.abs(slope) + err1) * h + 0.5 * second * h * h
        return down(rho - err0 - spread), up(rho + err0 + spread)
    return ranges
