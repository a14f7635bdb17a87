"""The finite-element method: the Dirichlet Laplacian of the strip pulled back to the (θ, s) rectangle.

With η = lo(θ) + s·w(θ) (:mod:`.mesh`) the Jacobian of (θ, s) → (θ, η) is F = [[1, 0], [a, w]] with
``a = lo'(θ) + s·w'(θ)`` and det F = w.  The Dirichlet form ∫|∇ψ|² dθ dη and the mass ∫ψ² dθ dη become,
for ψ(θ, η) = u(θ, s),

    k(u, v) = ∫∫ [ w u_θ v_θ − a (u_θ v_s + u_s v_θ) + (1 + a²)/w · u_s v_s ] dθ ds,
    m(u, v) = ∫∫ w u v dθ ds,

exactly (F⁻¹F⁻ᵀ det F = [[w, −a], [−a, (1 + a²)/w]]).  The eigenvalues λ of k(u, v) = λ m(u, v) with u = 0
on both walls are those of −Δ on the strip, in units of 1/κ².  Lagrange elements of degree p on the
rectangle (coefficients smooth inside each element: the columns sit on the walls' kinks) converge like
h^(2p) for the eigenvalues; the quadrature is of degree 2p + 2.

The eigenproblem is solved class by class (:mod:`.symmetry`) by shift-invert Lanczos (ARPACK through
``scipy.sparse.linalg.eigsh`` with a sparse LU of K − σM), or densely when a class is small.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["DENSE_LIMIT", "assemble", "lowest_levels", "solve_classes"]

#: classes with at most this many free dofs are solved densely (LAPACK), the rest by shift-invert Lanczos
DENSE_LIMIT = 600


def assemble(strip_mesh):
    """The reduced stiffness and mass matrices ``(K, M)`` (free dofs × free dofs, CSR) of a :class:`StripMesh`."""
    from skfem import BilinearForm, asm

    basis = strip_mesh.basis
    x, s = np.asarray(basis.global_coordinates())
    angles, inverse = np.unique(x.ravel(), return_inverse=True)  # the coefficients depend on θ only
    _, slope_lo, width, slope_width = strip_mesh.strip.walls(angles)
    width = width[inverse].reshape(x.shape)
    slope = (slope_lo[inverse] + s.ravel() * slope_width[inverse]).reshape(x.shape)

    @BilinearForm
    def stiffness(u, v, w):
        ux, uy = u.grad
        vx, vy = v.grad
        return w["width"] * ux * vx - w["slope"] * (ux * vy + uy * vx) + (1.0 + w["slope"] ** 2) / w["width"] * uy * vy

    @BilinearForm
    def mass(u, v, w):
        return w["width"] * u * v

    reduce = strip_mesh.reduce
    stiff = asm(stiffness, basis, width=width, slope=slope)
    mass_matrix = asm(mass, basis, width=width)
    return (reduce.T @ stiff @ reduce).tocsr(), (reduce.T @ mass_matrix @ reduce).tocsr()


def lowest_levels(stiffness, mass, count, sigma=0.0):
    """The ``count`` smallest eigenvalues (ascending) and M-orthonormal eigenvectors of K u = λ M u."""
    n = stiffness.shape[0]
    count = min(count, n)
    if count <= 0:
        return np.empty(0), np.empty((n, 0))
    if n <= DENSE_LIMIT or count >= n - 1:
        from scipy.linalg import eigh

        values, vectors = eigh(stiffness.toarray(), mass.toarray(), subset_by_index=(0, count - 1))
        return values, vectors
    from scipy.sparse.linalg import ArpackNoConvergence, eigsh

    try:
        values, vectors = eigsh(stiffness.tocsc(), k=count, M=mass.tocsc(), sigma=sigma, which="LM",
                                ncv=min(n, max(2 * count + 1, 20)))
    except ArpackNoConvergence:
        from ..errors import InvalidArgument

        raise InvalidArgument(f"the eigensolver (ARPACK, shift-invert) did not converge on a class of {n} unknowns: "
                              "the problem is too badly conditioned (a strip far wider than the body puts levels "
                              "many orders of magnitude apart); ask for a smaller `H` or fewer `levels`") from None
    order = np.argsort(values)
    values, vectors = values[order], vectors[:, order]
    norms = np.sqrt(np.einsum("ij,ij->j", vectors, mass @ vectors))
    return values, vectors / norms


def solve_classes(stiffness, mass, bases, levels, progress=None):
    """The lowest ``levels`` eigenvalues of K u = λ M u over all classes, each class solved on its own.

    Each class gets its share of ``levels`` (plus a margin) first; a class whose highest computed level
    is below the overall ``levels``-th is asked for more until none is, so the merged list is complete.

    Returns
    -------
    values : ndarray (levels,)
    labels : ndarray (levels,) of int
        Index of each level's class in ``bases``.
    vectors : list of ndarray
        Each level's eigenvector on the free dofs (``basis @ class vector``).
    """
    reduced = [(b.T @ stiffness @ b).tocsr() for b in bases]
    masses = [(b.T @ mass @ b).tocsr() for b in bases]
    sizes = [b.shape[1] for b in bases]
    share = max(2, math.ceil(1.3 * levels / max(1, len(bases))) + 3)
    asked = [min(share, n) for n in sizes]
    found = [None] * len(bases)
    while True:
        for c, basis in enumerate(bases):
            if found[c] is None or found[c][0].size < asked[c]:
                found[c] = lowest_levels(reduced[c], masses[c], asked[c])
                if progress is not None:
                    progress(1)
        values = np.concatenate([f[0] for f in found])
        if values.size == 0:
            break
        cut = np.sort(values)[min(levels, values.size) - 1]
        short = [c for c, f in enumerate(found) if f[0].size == asked[c] and asked[c] < sizes[c] and f[0][-1] <= cut]
        if not short:
            break
        for c in short:
            asked[c] = min(sizes[c], 2 * asked[c])
    labels = np.concatenate([np.full(f[0].size, c) for c, f in enumerate(found)])
    index = np.concatenate([np.arange(f[0].size) for f in found])
    order = np.argsort(values, kind="stable")[:levels]
    vectors = [bases[labels[k]] @ found[labels[k]][1][:, index[k]] for k in order]
    return values[order], labels[order], vectors
