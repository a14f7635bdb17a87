"""Measured walls: the simplest convex body whose wall is as close to noisy samples as their noise allows.

Noisy samples are not support values of any convex body: their discrete radius of curvature
(:mod:`inverse.discrete`) changes sign everywhere and the half-plane intersection cuts a corner at
every dip.  The fit has two stages.

**1. The least-squares projection** (Prince & Willsky 1990; its convergence is proved by Gardner,
Kiderlen & Milanfar, Ann. Statist. 34, 2006): among convex polygons whose edges have the measured
directions as outward normals, the one whose support values ``p_j`` are closest to the data,

    minimise  Σ_j w_j (p_j − ȳ_j)²   subject to   ρ_j(p) ≥ 0  for every j,

where ``ρ_j`` is the discrete radius of curvature, linear in p (three neighbours), ``ȳ_j`` the mean of
the samples at angle j and ``w_j`` their number; the offset b0 enters as ``y = b0 + b``.  It is a
projection onto a polyhedral cone, solved through its dual, a non-negative least squares problem
(``scipy.optimize.nnls``; casadi's sparse HiGHS QP did not finish this 1,000-variable problem in 40
minutes and OSQP solves only to ~1e-4, while NNLS is exact on its active set and takes ~0.6 s for
1,000 directions).  The projection is nearest to the data, but it is a polygon: wherever the noise dips
it has a run of ``ρ = 0`` (a vertex window) and an edge, so on its own it reports a corner at every dip
(19–175 on bodies with 0, 5 or 9).  It is kept as :attr:`FitResult.least_squares`.

**2. The corners the noise supports.**  A corner is a window of normal angles over which the boundary
does not move; the data can never prove a window *exactly* sharp (a rounding of small enough radius
changes the wall by less than any noise), so the question asked is the one a reader asks of a plot:
does the boundary turn here much faster than next to it?  Concretely:

* the noise ``σ`` is given (``sigma=``, ``coinwall fit --sigma-b``) or estimated from the projection's
  residuals, ``σ² = RSS/(N − k)`` with ``k`` its number of edges: the degrees of freedom of a projection
  onto a polyhedral cone are the dimension of the face it lands on (Meyer & Woodroofe, Ann. Statist. 28,
  2000), which for this cone is the number of ``ρ_j > 0``;
* the candidates are the projection's vertex windows (runs of ``ρ = 0``; a vertex between two edges with
  no sample inside its window is no candidate).  Neighbouring candidates are merged, cheapest first,
  while making them one vertex (``ρ = 0`` on the lines between them too) raises χ² = RSS/σ² by no more
  than the threshold below: an edge the data do not support.  The cost is always counted from the
  projection, so a chain of cheap merges cannot add up to an expensive one;
* each candidate (window of width W) is then tested by a likelihood ratio: the fit with ``ρ ≥ r`` forced
  over its window, ``r`` half the radius of curvature next to it (the boundary length within W on either
  side, divided by W, on the less curved side, measured on the fit with the corner, where an edge that
  the noise split across nearby directions is whole again), against the fit with the corner.  The
  χ² growth is compared with the one-degree-of-freedom quantile at ``CORNER_LEVEL / m`` (Bonferroni over
  the m candidates): a true vertex flanked by edges or by arcs of radius R cannot be rounded to R/2 or to
  half its neighbouring edge without a visible misfit, while a dip of the noise on a smooth arc can
  (there ``r`` is half the arc's own radius, which the true body satisfies).  Each test is a local
  least-squares problem (the window and up to 40 lines either side move, the rest stays at the
  projection), solved exactly by Lawson & Hanson's least-distance reduction to one NNLS;
* the body returned is the least-squares body with exactly those corners (``ρ = 0`` forced over each
  supported window: its lines through one point) and ``ρ ≥ r`` elsewhere (the radius each rejected
  candidate was tested with, or that of its neighbours), so its own corners are the reported ones and
  it is strictly convex in between.  Its χ² is checked against ``N + 3√(2N)``; if the floors would break
  that, they are halved (then dropped), and a note says so.

Why this and not the alternatives: merging vertices by their positional uncertainty alone (lines with
noise σ over a window fix a vertex to about ``σ√12/(W√N_W)`` along the edge) fails both ways, since a
one-sample window has a huge uncertainty and would swallow real edges, while a real vertex split by a
noise-made edge is fixed far better by the union of its lines; the likelihood ratio of the merge asks
the right question directly.  "The fewest pieces within 3σ" is a combinatorial search, and an ``L∞``
band of 3σ is broken by chance in 0.27 % of the samples, i.e. in 93 % of data sets of 1,000.  The regime follows
from the tests: ``critical`` when a corner is supported, ``convex`` when none is and no candidate comes
close, ``undecided`` when some candidate costs more than chance gives at ``UNDECIDED_LEVEL`` but less
than the threshold (the data allow both).  The resolution is what it is: at σ = 1 % of the size and 360
samples, a polygon's vertex with a window below ~0.5 rad cannot be told from a rounding of half its
neighbouring edge (the wall differs by about ``r W²/8 ≈ σ`` over 25 samples); such a vertex is reported
as ``possible`` or not at all.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument, InvalidWall

from .fitcorners import Cluster, Structure, cluster_runs

__all__ = ["MAX_DIRECTIONS", "CornerTest", "FitResult", "fit_convex"]

#: Most distinct measured directions a fit takes (NNLS is dense: ~0.6 s at 1,000, ~26 s at 3,000).
MAX_DIRECTIONS = 2000
#: A candidate corner is tested against the window rounded with this fraction of its neighbourhood's radius.
ROUNDING_FRACTION = 0.5
#: Chance that any one of the candidates of a fit is called a corner when the body is round there.
CORNER_LEVEL = 0.01
#: Candidates whose rounding costs more than chance gives at this level (but are no corners) leave the
#: regime of a body without corners undecided.
UNDECIDED_LEVEL = 0.5


@dataclass(frozen=True)
class CornerTest:
    """A candidate corner of a fit and its test.

    Attributes
    ----------
    window : (float, float)
        Normal angles ``[start, end]`` of the lines through the candidate vertex (unwrapped, ``end > start``).
    lines : int
        How many measured directions pass through it.
    radius : float
        The radius of curvature the window was forced to have (``ROUNDING_FRACTION`` × its neighbourhood's).
    statistic : float
        How much χ² grows when it is forced to (the likelihood ratio of "rounded" against "corner").
    verdict : str
        ``"corner"`` (statistic above the threshold of the fit), ``"possible"`` (above what chance gives at
        ``UNDECIDED_LEVEL``, not above the threshold) or ``"round"``.

    Examples
    --------
    A smooth wall with noise: every candidate corner tests as round.

    >>> import numpy as np
    >>> theta = np.radians(np.arange(360.0))
    >>> wall = np.sqrt((1 + np.cos(theta) ** 2) / 2)      # the ellipse x² + 2y² = 1: b_c = −0.5
    >>> from coinwall.inverse.fit import fit_convex
    >>> fit = fit_convex(theta, wall + 1e-3 * np.random.default_rng(0).standard_normal(360), sigma=1e-3)
    >>> sorted({test.verdict for test in fit.tests})
    ['round']
    """

    window: tuple
    lines: int
    radius: float
    statistic: float
    verdict: str

    def to_dict(self) -> dict:
        return {"window": list(self.window), "lines": self.lines, "radius": self.radius,
                "statistic": self.statistic, "verdict": self.verdict}


@dataclass(frozen=True, repr=False)
class FitResult:
    """A convex fit of noisy wall samples: the simplest body the noise allows.

    Attributes
    ----------
    theta : ndarray
        The distinct measured directions in [0, 2π), sorted.
    data : ndarray
        The mean of the samples at each direction (``b``, without the offset).
    counts : ndarray
        How many samples each direction had.
    fitted : ndarray
        The fitted wall at ``theta`` (``b``, without the offset): support values of a convex body with
        exactly the supported corners and a positive radius of curvature elsewhere.
    b0 : float
        The offset used.
    rms_residual, max_residual : float
        Of the fitted wall against every sample.
    wall : coinwall.forward.Wall
        The fitted wall (samples ``theta, fitted``), reusable wherever a wall is expected.
    body : coinwall.inverse.Body
        The body of the fitted wall at ``b0`` (its outline, corners …).
    least_squares : ndarray
        The plain least-squares projection (``ρ ≥ 0`` only) at ``theta``, without the offset: nearest to
        the data, but with a vertex window wherever the noise dips.
    sigma : float
        The noise of one sample used by the tests: given, or estimated from the projection's residuals.
    sigma_given : bool
        Whether ``sigma`` was given.
    chi2, chi2_bound : float
        ``Σ (residual/σ)²`` of the fitted wall over every sample, and ``N + 3√(2N)``: what N samples of
        noise σ stay below except with probability ~0.2 %.  The fitted wall keeps to it when it can.
    regime : str
        What the data say, the same as :attr:`body`'s: ``"corner"`` (``b0`` below the confidence interval of
        ``b_c``), ``"critical"`` (a corner is supported: rounding it off costs more than the noise allows),
        ``"convex"`` (``b0`` above the interval, no corner supported and no candidate close) or
        ``"undecided"`` (``b0`` inside the interval with no corner supported, or a candidate the data neither
        confirm nor rule out; the body's :attr:`~coinwall.inverse.Body.regimes` lists what they allow).
    threshold : float
        The χ² growth above which a candidate is a corner (Bonferroni over the candidates).
    tests : tuple of CornerTest
        Every candidate corner and its test.
    notes : tuple of str
        What the fit had to give up, if anything.
    critical : coinwall.inverse.noise.NoisyCritical
        ``b_c`` as an estimate with a confidence interval (from the samples and their noise).

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.radians(np.arange(360.0))
    >>> wall = np.sqrt((1 + np.cos(theta) ** 2) / 2)      # the ellipse x² + 2y² = 1: b_c = −0.5
    >>> from coinwall.inverse.fit import fit_convex
    >>> fit = fit_convex(theta, wall + 1e-3 * np.random.default_rng(0).standard_normal(360), sigma=1e-3)
    >>> fit
    FitResult(360 samples at 360 directions, σ 0.001, rms residual 0.00085, max 0.00302; convex, 0 corners)
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
    least_squares: np.ndarray = None
    sigma: float = math.nan
    sigma_given: bool = False
    chi2: float = math.nan
    chi2_bound: float = math.nan
    regime: str = ""
    threshold: float = math.nan
    tests: tuple = ()
    notes: tuple = ()
    critical: object = None

    @property
    def corners(self) -> int:
        """How many corners the data support (those of :attr:`body`)."""
        return sum(t.verdict == "corner" for t in self.tests)

    def to_dict(self) -> dict:
        return {"samples": int(self.counts.sum()), "directions": int(self.theta.size), "b0": self.b0,
                "rms_residual": self.rms_residual, "max_residual": self.max_residual,
                "sigma": self.sigma, "sigma_source": "given" if self.sigma_given else "estimated",
                "chi2": self.chi2, "chi2_bound": self.chi2_bound, "regime": self.regime,
                "body_regime": self.regime, "regimes": list(self.body.regimes),
                "regime_decided": self.regime != "undecided",
                "b_c_confidence": self.critical.to_dict() if self.critical is not None else None,
                "b_c": self.body.b_c if math.isfinite(self.body.b_c) else None,
                "corners": [c.to_dict() for c in self.body.corners], "threshold": self.threshold,
                "candidates": [t.to_dict() for t in self.tests], "notes": list(self.notes),
                "warnings": list(self.body.warnings)}

    @safe_repr
    def __repr__(self) -> str:
        return (f"FitResult({int(self.counts.sum())} samples at {self.theta.size} directions, σ {self.sigma:.3g}, "
                f"rms residual {self.rms_residual:.3g}, max {self.max_residual:.3g}; {self.regime}, "
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


def _threshold(candidates: int, level: float) -> float:
    """χ² (one degree of freedom) exceeded by chance with probability ``level`` over ``candidates`` tests."""
    from statistics import NormalDist

    return NormalDist().inv_cdf(1.0 - 0.5 * level / max(candidates, 1)) ** 2


def fit_convex(theta, b, b0: float = 0.0, *, sigma: float | None = None, sd=None,
               tail: float | None = None) -> FitResult:
    """The simplest convex body whose wall is as close to the samples ``(θ_i, b_i)`` as their noise allows.

    Parameters
    ----------
    theta, b : array_like
        Samples; angles in radians, any order, repeats allowed (they are averaged, with weights).
    b0 : float
        Offset: the fitted support function is ``b0 + b`` (below the samples' critical offset this is
        the nearest convex body in least squares, beside the largest body under the wall).
    sigma : float, optional
        The noise of one sample (standard deviation, units of the wall).  Default: estimated from the
        residuals of the least-squares projection.
    sd : float or array_like, optional
        The standard deviation of each sample (instead of ``sigma``); the tests use their root mean square.
    tail : float, optional
        The tail bound of the confidence interval of ``b_c`` (:func:`coinwall.inverse.noise.noisy_critical`).

    Returns
    -------
    FitResult
        The body with the corners the noise supports (:attr:`FitResult.tests` has every candidate and its
        likelihood ratio), the regime the data support, and the plain least-squares projection.

    Raises
    ------
    InvalidWall
        Samples that are not finite, too few directions, a gap of π or more, more than
        :data:`MAX_DIRECTIONS` directions, or an offset that puts the centre of mass outside.
    InvalidArgument
        A ``sigma`` that is not a positive finite number, or one below the precision of the values.

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.radians(np.arange(360.0))
    >>> wall = np.sqrt((1 + np.cos(theta) ** 2) / 2) + 1e-3 * np.random.default_rng(0).standard_normal(360)
    >>> fit = fit_convex(theta, wall, sigma=1e-3)
    >>> fit.regime, fit.corners, bool(fit.critical.lower <= -0.5 <= fit.critical.upper)
    ('convex', 0, True)
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
    if sd is not None:
        sd = np.broadcast_to(np.asarray(sd, float), b.shape)
        if not (np.all(np.isfinite(sd)) and np.all(sd > 0)):
            raise InvalidArgument("`b_sd`: every standard deviation must be a positive finite number")
        sigma = float(np.sqrt(np.mean(sd**2)))
    if sigma is not None:
        if isinstance(sigma, bool) or not isinstance(sigma, (int, float, np.floating, np.integer)) \
                or not math.isfinite(sigma) or sigma <= 0:
            raise InvalidArgument(f"`sigma`: the noise must be a positive finite number, got {sigma!r}")
        sigma = float(sigma)
        if b.size and sigma < 1e-13 * float(np.max(np.abs(b))):
            raise InvalidArgument(f"`sigma` {sigma:.3g}: a noise below the precision of the values themselves "
                                  f"(~1e-13 of {float(np.max(np.abs(b))):.3g}) is none: fit exact samples without it")
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
    projection = (weights * target + constraint.T @ multipliers) / weights
    projection = _polish(curvature, counts.astype(float), target, projection, multipliers > 0)
    scale = max(1.0, float(np.max(np.abs(projection))))

    # the noise: given, or from the projection's residuals with its degrees of freedom (its edges)
    structure = Structure(directions, counts.astype(float), target, projection, 1.0)
    rho_tol = 1e-9 * scale / np.minimum(gaps, np.roll(gaps, 1)) ** 2
    zero = structure.rho <= rho_tol
    total = int(counts.sum())
    rss_projection = float(np.sum((b0 + b - projection[index]) ** 2))
    edges = int(np.count_nonzero(~zero))
    if sigma is None:
        dof = max(total - edges, 1)
        sigma_used = max(math.sqrt(rss_projection / dof), 1e-12 * scale)
    else:
        sigma_used = sigma
    structure.sigma = sigma_used

    clusters = sorted((Cluster(s - 1, s + length) for s, length in cluster_runs(zero)), key=lambda c: c.first)
    threshold = _threshold(len(clusters), CORNER_LEVEL)
    clusters = structure.merge(clusters, threshold)
    threshold = _threshold(len(clusters), CORNER_LEVEL)
    marginal = _threshold(len(clusters), UNDECIDED_LEVEL)
    for c in clusters:
        c.radius, c.statistic = structure.rounding_test(c, ROUNDING_FRACTION)
        c.corner = c.statistic > threshold

    # the simplest body: the supported corners, strictly convex elsewhere, as near the data as that allows
    bound = total + 3.0 * math.sqrt(2.0 * total)
    notes = []
    support, chi2 = projection, rss_projection / sigma_used**2
    if clusters:
        for factor in (1.0, 0.5, 0.25, 0.0):
            candidate = structure.body_fit(clusters, factor)
            if candidate is None:  # pragma: no cover
                continue
            value = float(np.sum((b0 + b - candidate[index]) ** 2)) / sigma_used**2
            if value <= bound or factor == 0.0:
                support, chi2 = candidate, value
                if factor < 1.0:
                    notes.append(f"the rounded parts of the body were allowed a radius of curvature down to {factor:g} "
                                 "of the tested one to stay within the noise")
                break
    if chi2 > bound:
        notes.append(f"the residuals exceed the noise: χ² = {chi2:.4g} > {bound:.4g} for σ = {sigma_used:.3g}"
                     + (" (given)" if sigma is not None else ""))
    # b_c with its confidence interval, and the regime from both: below the interval a corner is certain (at the
    # confidence level), a supported corner makes it critical, above the interval it is convex unless a candidate
    # is marginal; inside it the data do not decide (unless the interval is as narrow as the solvers' accuracy)
    from .noise import noisy_critical
    from .tolerances import OFFSET_TOLERANCE, WALL_ACCURACY

    spread = np.sqrt(np.bincount(index, sd**2) / counts**2) if sd is not None else sigma_used / np.sqrt(counts)
    found = noisy_critical(directions, mean, np.maximum(spread, 1e-13 * scale), tail=tail)
    tol = OFFSET_TOLERANCE * scale
    corners = sum(c.corner for c in clusters)
    if b0 < found.lower - tol:
        regimes = ("corner",)
    elif corners:
        regimes = ("critical",)
    elif b0 > found.upper + tol:
        regimes = ("critical", "convex") if any(c.statistic > marginal for c in clusters) else ("convex",)
    elif found.upper - found.lower <= 2.0 * WALL_ACCURACY * scale:  # b_c fixed to the solvers' own accuracy
        regimes = ("critical",)
    else:
        regimes = ("corner", "critical", "convex")
    regime = regimes[0] if len(regimes) == 1 else "undecided"
    fitted = support - b0
    residual = b - fitted[index]
    from coinwall.forward.wall import Wall

    # NNLS meets the constraints to its own tolerance, amplified by 1/Δ² where directions crowd: the
    # fitted wall says so, so that ρ_j ≈ 0 reads as a vertex window and not as a cut
    accuracy = 1e-9 * max(1.0, float(np.max(np.abs(support))))
    wall = Wall.from_samples(directions, fitted, rounding=accuracy)
    body = solve_body(wall, b0)
    # one answer: the body says what the fit says
    body = dataclasses.replace(body, regime=regimes[0] if len(regimes) == 1 else "critical", regimes=regimes)
    tests = tuple(CornerTest((float(structure.angle(c.first)), float(structure.angle(c.last))),
                             int(c.last - c.first + 1), c.radius, c.statistic,
                             "corner" if c.corner else ("possible" if c.statistic > marginal else "round"))
                  for c in clusters)
    return FitResult(directions, mean, counts, fitted, b0, float(np.sqrt(np.mean(residual**2))),
                     float(np.max(np.abs(residual))), wall, body, projection - b0, sigma_used, sigma is not None,
                     chi2, bound, regime, threshold, tests, tuple(notes), found)
