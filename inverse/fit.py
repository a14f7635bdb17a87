"""Measured walls: the convex body whose wall is closest to noisy samples, in least squares.

Noisy samples are not support values of any convex body: their discrete radius of curvature
(:mod:`inverse.discrete`) changes sign everywhere and the half-plane intersection cuts a corner at
every dip.  The estimator here is the classical one for support-function data (Prince & Willsky 1990;
its convergence is proved by Gardner, Kiderlen & Milanfar, Ann. Statist. 34, 2006): among convex
polygons whose edges have the measured directions as outward normals, the one whose support values
``p_j`` are closest to the data,

    minimise  Σ_j w_j (p_j − ȳ_j)²   subject to   ρ_j(p) ≥ 0  for every j,

where ``ρ_j`` is the discrete radius of curvature, linear in p (three neighbours), ``ȳ_j`` the mean of
the samples at angle j and ``w_j`` their number.  ``ρ ≥ 0`` is convexity *as a measure*: vertex
windows (runs of ρ = 0) and corners are allowed, nothing is smoothed.  The offset b0 enters as
``y = b0 + b``.

The programme is a projection onto a polyhedral cone, solved through its dual, a non-negative least
squares problem (``scipy.optimize.nnls``: ``p = y + Aᵀλ`` with ``λ ≥ 0`` minimising ``‖y + Aᵀλ‖``).
Why not casadi's QP interface: its sparse HiGHS back end did not finish this 1,000-variable problem in
40 minutes here, and OSQP solves only to ~1e-4; NNLS is exact to rounding on the active set (the ρ = 0
windows come out as vertex windows) and takes ~0.6 s for 1,000 directions.  It is dense (cubic in
the number of directions), hence the limit :data:`MAX_DIRECTIONS`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument, InvalidWall

__all__ = ["MAX_DIRECTIONS", "FitResult", "fit_convex"]

#: Most distinct measured directions a fit takes (NNLS is dense: ~0.6 s at 1,000, ~26 s at 3,000).
MAX_DIRECTIONS = 2000


@dataclass(frozen=True, repr=False)
class FitResult:
    """A least-squares convex fit of wall samples.

    Attributes
    ----------
    theta : ndarray
        The distinct measured directions in [0, 2π), sorted.
    data : ndarray
        The mean of the samples at each direction (``b``, without the offset).
    counts : ndarray
        How many samples each direction had.
    fitted : ndarray
        The fitted wall at ``theta`` (``b``, without the offset): support values of a convex body.
    b0 : float
        The offset used.
    rms_residual, max_residual : float
        Of the fitted wall against every sample.
    wall : coinwall.forward.Wall
        The fitted wall (samples ``theta, fitted``), reusable wherever a wall is expected.
    body : coinwall.inverse.Body
        The body of the fitted wall at ``b0`` (its regime, corners, outline …).
    """

    theta: np.ndarray
    data: np.ndarray
    counts: np.ndarray
    fitted: np.ndarray
    b0: float
    rms_residual: float
    max_residual: float
    wall: object
    body: object

    def to_dict(self) -> dict:
        return {"samples": int(self.counts.sum()), "directions": int(self.theta.size), "b0": self.b0,
                "rms_residual": self.rms_residual, "max_residual": self.max_residual,
                "regime": self.body.regime, "b_c": self.body.b_c if math.isfinite(self.body.b_c) else None,
                "corners": [c.to_dict() for c in self.body.corners], "warnings": list(self.body.warnings)}

    @safe_repr
    def __repr__(self) -> str:
        return (f"FitResult({int(self.counts.sum())} samples at {self.theta.size} directions, rms residual "
                f"{self.rms_residual:.3g}, max {self.max_residual:.3g}; {self.body.regime}, "
                f"{len(self.body.corners)} corners)")

    def plot(self, axes=None):
        """Data, fit and residual against θ (matplotlib, imported here); returns the two axes."""
        from coinwall.forward.formats.figure import new_figure

        if axes is None:
            _, axes = new_figure(2, 1, figsize=(7, 5), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
        top, bottom = axes
        top.plot(self.theta, self.b0 + self.data, ".", ms=2, color="0.5", label="samples b0 + b")
        top.plot(self.theta, self.b0 + self.fitted, "-", lw=1, color="tab:blue", label="convex fit")
        top.set_ylabel("wall b0 + b (κ)")
        top.legend(loc="upper center", bbox_to_anchor=(0.5, 1.22), ncol=2, frameon=False)
        bottom.plot(self.theta, self.data - self.fitted, ".", ms=2, color="tab:red")
        bottom.axhline(0.0, color="0.3", lw=0.5)
        bottom.set_xlabel("wall angle θ (rad)")
        bottom.set_ylabel("residual (κ)")
        return axes


def _curvature_matrix(theta):
    """The discrete radius of curvature ρ = A p as a sparse matrix (inverse.discrete.discrete_curvature)."""
    from scipy import sparse

    n = theta.size
    after = np.diff(np.append(theta, theta[0] + TWO_PI))
    before = np.roll(after, 1)
    norm = np.tan(before / 2) + np.tan(after / 2)
    i = np.arange(n)
    values = np.concatenate([1 / np.sin(before), -(np.cos(before) / np.sin(before) + np.cos(after) / np.sin(after)),
                             1 / np.sin(after)]) / np.tile(norm, 3)
    return sparse.csr_matrix((values, (np.tile(i, 3), np.concatenate([(i - 1) % n, i, (i + 1) % n]))), shape=(n, n))


def _polish(curvature, weights, target, support, active):
    """Make the active constraints hold to rounding: the least-squares solution with ``ρ_j = 0`` exactly
    on the active set (the KKT system ``p = y − W⁻¹A_Sᵀμ``, ``A_S W⁻¹ A_Sᵀ μ = A_S y``, sparse and
    banded).  NNLS leaves ``ρ_j`` of order its own tolerance on the active set, which the discrete
    geometry, with its rounding-level test for vertex windows, would read as small cuts.  The polished
    solution is kept only if every constraint still holds."""
    from scipy import sparse
    from scipy.sparse.linalg import spsolve

    if not active.any():
        return support
    rows = curvature[np.flatnonzero(active)]
    system = (rows @ sparse.diags(1.0 / weights) @ rows.T).tocsc()
    try:
        mu = np.atleast_1d(spsolve(system, rows @ target))
    except RuntimeError:  # pragma: no cover - a singular active set: keep the NNLS solution
        return support
    polished = target - (rows.T @ mu) / weights
    rho = curvature @ polished
    scale = float(np.max(np.abs(curvature).sum(axis=1))) * 8 * np.finfo(float).eps * max(1.0, np.max(np.abs(target)))
    if np.all(np.isfinite(polished)) and rho.min() >= -scale:
        return polished
    return support


def fit_convex(theta, b, b0: float = 0.0) -> FitResult:
    """The convex body whose wall is closest to the samples ``(θ_i, b_i)`` in least squares.

    Parameters
    ----------
    theta, b : array_like
        Samples; angles in radians, any order, repeats allowed (they are averaged, with weights).
    b0 : float
        Offset: the fitted support function is ``b0 + b`` (below the samples' critical offset this is
        the nearest convex body in least squares, beside the largest body under the wall).

    Raises
    ------
    InvalidWall
        Samples that are not finite, too few directions, a gap of π or more, more than
        :data:`MAX_DIRECTIONS` directions, or an offset that puts the centre of mass outside.
    """
    from scipy.optimize import nnls

    from .solve import solve_body
    from .support import check_offset

    theta = np.asarray(theta, dtype=float).ravel()
    b = np.asarray(b, dtype=float).ravel()
    if theta.size != b.size:
        raise InvalidWall(f"samples: {theta.size} angles but {b.size} wall values")
    if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(b))):
        raise InvalidWall("samples: every angle and wall value must be finite")
    b0 = check_offset(b0, float(np.max(np.abs(b))) if b.size else 1.0)
    reduced = np.mod(theta, TWO_PI)
    reduced[reduced >= TWO_PI] = 0.0
    directions, index, counts = np.unique(np.round(reduced, 12), return_inverse=True, return_counts=True)
    if directions.size < 8:
        raise InvalidWall(f"samples: {directions.size} distinct angles; a fit needs at least 8")
    if directions.size > MAX_DIRECTIONS:
        raise InvalidArgument(f"`theta`: {directions.size} distinct directions; a fit takes at most {MAX_DIRECTIONS} "
                              "(average or thin the samples first)")
    gaps = np.diff(np.append(directions, directions[0] + TWO_PI))
    if gaps.max() >= math.pi * (1 - 1e-9):
        raise InvalidWall(f"samples: no sample between θ = {directions[np.argmax(gaps)]:.4g} and the next angle "
                          f"{gaps.max():.4g} rad further: the lines do not bound a body")
    mean = np.bincount(index, weights=b) / counts
    weights = np.sqrt(counts.astype(float))
    target = b0 + mean
    curvature = _curvature_matrix(directions)
    # weighted projection: q = √w p, minimise ‖q − √w y‖ subject to A W^{-1/2} q ≥ 0; dual is NNLS
    constraint = (curvature @ np.diag(1.0 / weights)) if counts.max() > 1 else curvature.toarray()
    constraint = np.asarray(constraint)
    multipliers, _ = nnls(constraint.T, -weights * target, maxiter=50 * directions.size)
    support = (weights * target + constraint.T @ multipliers) / weights
    support = _polish(curvature, counts.astype(float), target, support, multipliers > 0)
    fitted = support - b0
    residual = b - fitted[index]
    from coinwall.forward.wall import Wall

    # NNLS meets the constraints to its own tolerance, amplified by 1/Δ² where directions crowd: the
    # fitted wall says so, so that ρ_j ≈ 0 reads as a vertex window and not as a cut
    accuracy = 1e-9 * max(1.0, float(np.max(np.abs(support))))
    wall = Wall.from_samples(directions, fitted, rounding=accuracy)
    body = solve_body(wall, b0)
    return FitResult(directions, mean, counts, fitted, b0, float(np.sqrt(np.mean(residual**2))),
                     float(np.max(np.abs(residual))), wall, body)
