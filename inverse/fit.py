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

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument, InvalidWall

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
        What the data say: ``"critical"`` (a corner is supported: rounding it off costs more than the
        noise allows), ``"convex"`` (no corner is supported and no candidate comes close) or
        ``"undecided"`` (no corner, but a candidate the data neither confirm nor rule out).
    threshold : float
        The χ² growth above which a candidate is a corner (Bonferroni over the candidates).
    tests : tuple of CornerTest
        Every candidate corner and its test.
    notes : tuple of str
        What the fit had to give up, if anything.
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

    @property
    def corners(self) -> int:
        """How many corners the data support (those of :attr:`body`)."""
        return sum(t.verdict == "corner" for t in self.tests)

    def to_dict(self) -> dict:
        return {"samples": int(self.counts.sum()), "directions": int(self.theta.size), "b0": self.b0,
                "rms_residual": self.rms_residual, "max_residual": self.max_residual,
                "sigma": self.sigma, "sigma_source": "given" if self.sigma_given else "estimated",
                "chi2": self.chi2, "chi2_bound": self.chi2_bound, "regime": self.regime,
                "body_regime": self.body.regime,
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


# ---------------------------------------------------------------------------------------------------- the pieces
def _stencil(theta):
    """The three diagonals of ρ = A p (coefficients of p_{j−1}, p_j, p_{j+1}) and ``tan(Δ₋/2) + tan(Δ₊/2)``
    (the length of the piece of line j is ``ρ_j`` times it)."""
    after = np.diff(np.append(theta, theta[0] + TWO_PI))
    before = np.roll(after, 1)
    norm = np.tan(before / 2) + np.tan(after / 2)
    return (1 / np.sin(before) / norm, -(np.cos(before) / np.sin(before) + np.cos(after) / np.sin(after)) / norm,
            1 / np.sin(after) / norm, norm)


def _lsi(E, f, G, h):
    """``min ‖E x − f‖`` subject to ``G x ≥ h`` (E of full column rank, or a 1-d array: a diagonal), by
    Lawson & Hanson's reduction to a least-distance programme whose dual is one non-negative least squares
    problem (Solving Least Squares Problems, 1974, ch. 23).  Returns x, or None when no x meets the
    constraints."""
    from scipy.linalg import cholesky, solve_triangular
    from scipy.optimize import nnls

    if E.ndim == 1:  # z = E x − f
        g = G / E[None, :]
        base = f
    else:  # z = R x − R⁻ᵀEᵀf with RᵀR = EᵀE
        r = cholesky(E.T @ E)
        base = solve_triangular(r, E.T @ f, trans="T")
        g = solve_triangular(r, G.T, trans="T").T
    hh = h - g @ base
    m = g.shape[1]
    matrix = np.vstack([g.T, hh[None, :]])
    rhs = np.zeros(m + 1)
    rhs[-1] = 1.0
    u, _ = nnls(matrix, rhs, maxiter=50 * max(10, matrix.shape[1]))
    residual = matrix @ u - rhs
    if abs(residual[-1]) < 1e-12:  # pragma: no cover - the constraints here always have a solution
        return None
    z = -residual[:m] / residual[-1] + base
    return z / E if E.ndim == 1 else solve_triangular(r, z)


def _runs(mask):
    """Cyclic runs of True: (start, length) pairs, the start in [0, n)."""
    n = mask.size
    if mask.all():
        return [(0, n)]
    if not mask.any():
        return []
    shift = int(np.flatnonzero(~mask)[0])
    rolled = np.roll(mask, -shift)
    edges = np.diff(np.concatenate([[0], rolled.astype(int), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(int((s + shift) % n), int(e - s)) for s, e in zip(starts, stops)]


@dataclass
class _Cluster:
    """Lines ``first .. last`` (unwrapped indices) through one candidate vertex; the lines strictly
    between them are its window's interior."""

    first: int
    last: int
    radius: float = 0.0
    statistic: float = 0.0
    corner: bool = False


def _margin(span):
    """Lines either side of a window that a local fit moves: its own width, at least 8, at most 40."""
    return int(min(max(8, span), 40))


class _Structure:
    """The least-squares projection's vertex windows, merged and tested (see the module docstring)."""

    def __init__(self, theta, weights, target, support, sigma):
        self.theta, self.weights, self.target, self.support, self.sigma = theta, weights, target, support, sigma
        self.n = theta.size
        self.lo, self.mid, self.hi, self.norm = _stencil(theta)
        self.rho = self.curvature(support)
        self.length = np.maximum(self.rho, 0.0) * self.norm  # the edges of the projection
        self.normals = np.column_stack([np.cos(theta), np.sin(theta)])

    def curvature(self, p):
        return self.lo * np.roll(p, 1) + self.mid * p + self.hi * np.roll(p, -1)

    def angle(self, k):
        """Unwrapped angle of line index k (any integer)."""
        k = np.asarray(k)
        return self.theta[k % self.n] + TWO_PI * (k // self.n)

    def lines(self, first, last):
        return np.arange(first, last + 1) % self.n

    def width(self, cluster):
        return float(self.angle(cluster.last) - self.angle(cluster.first))

    # ------------------------------------------------------------------------------------------ merging
    def merge_cost(self, left, right):
        """χ² increase when the two candidate vertices are made one: ρ = 0 on every line between them."""
        last = right.last if right.first >= left.last else right.last + self.n
        if self.angle(last) - self.angle(left.first) >= 0.9 * math.pi:
            return math.inf
        first = left.first
        if self.resolved(left, right, last):
            return math.inf

        def bounds(j):
            k = first + ((j - first) % self.n)
            return 0.0, first < k < last

        change, _, _ = self.local_fit(first, last, bounds, _margin(last - first))
        return max(change, 0.0) / self.sigma**2

    def resolved(self, left, right, last):
        """Whether the two vertices are plainly apart: the edges between them longer than 6 standard
        deviations of the difference of their positions (each fitted to its own lines, noise σ)."""
        stop = right.first if right.first >= left.last else right.first + self.n
        idx = self.lines(left.last, stop)
        d = self.length[idx] @ np.column_stack([-np.sin(self.theta[idx]), np.cos(self.theta[idx])])
        size = float(np.hypot(*d))
        if size == 0.0:
            return False
        spread = 0.0
        for first, end in ((left.first, left.last), (stop, last)):
            idx = self.lines(first, end)
            moment = (self.normals[idx] * self.weights[idx, None]).T @ self.normals[idx]
            if abs(np.linalg.det(moment)) < 1e-12 * np.trace(moment) ** 2:
                return False
            spread += float(d @ np.linalg.solve(moment, d)) / size**2
        return size > 6.0 * self.sigma * math.sqrt(spread)

    def merge(self, clusters, threshold):
        """Join neighbouring candidate vertices while the cheapest join costs at most ``threshold`` in χ²
        (the edge between them is not supported by the data); costs are counted from the projection, so a
        chain of cheap joins cannot add up to an expensive one."""
        clusters = list(clusters)
        m = len(clusters)
        costs = [self.merge_cost(clusters[k], clusters[(k + 1) % m]) if m > 1 else math.inf for k in range(m)]
        while len(clusters) > 1:
            k = int(np.argmin(costs))
            if costs[k] > threshold:
                break
            j = (k + 1) % len(clusters)
            if j == 0:  # the last joins the first across 2π: indices stay unwrapped from the last
                clusters[k] = _Cluster(clusters[k].first, clusters[0].last + self.n)
                del clusters[0], costs[0]
                k -= 1
            else:
                clusters[k] = _Cluster(clusters[k].first, clusters[j].last)
                del clusters[j], costs[j]
            m = len(clusters)
            for i in ((k - 1) % m, k % m):
                costs[i] = self.merge_cost(clusters[i], clusters[(i + 1) % m]) if m > 1 else math.inf
        return clusters

    # ------------------------------------------------------------------------------------------ testing
    def neighbourhood_radius(self, cluster, length):
        """Radius of curvature of the projection next to the window: its boundary length within one
        window-width of either side (the bounding edges included), divided by that width, on the less
        curved side."""
        w = self.width(cluster)
        if w >= math.pi:
            return float(length.sum() / TWO_PI)
        ks = np.arange(cluster.first - self.n, cluster.last + self.n + 1)
        angles = self.angle(ks)
        slack = 1e-12 * TWO_PI
        a, b = self.angle(cluster.first), self.angle(cluster.last)
        left = (angles >= a - w - slack) & (ks <= cluster.first)
        right = (ks >= cluster.last) & (angles <= b + w + slack)
        return float(min(length[ks[left] % self.n].sum(), length[ks[right] % self.n].sum()) / w)

    def local_fit(self, first, last, bounds, margin):
        """Least squares over the lines near first..last, the rest held at the projection, subject to
        ``ρ_j ≥ lower`` (``= 0`` where equality) for ``lower, equality = bounds(j)``; returns (the change
        of the weighted residual sum, indices, new values)."""
        n = self.n
        span = last - first + 1 + 2 * margin
        if span >= n - 2:
            region = np.arange(n)
            rows = region
        else:
            region = np.arange(first - margin, last + margin + 1) % n
            rows = np.arange(first - margin - 1, last + margin + 2) % n
        position = np.full(n, -1)
        position[region] = np.arange(region.size)
        G = np.zeros((rows.size, region.size))
        spec = [bounds(j) for j in rows]
        h = np.array([s[0] for s in spec], dtype=float)
        for offset, coef in ((-1, self.lo), (0, self.mid), (1, self.hi)):
            cols = (rows + offset) % n
            at = position[cols]
            free = at >= 0
            G[np.flatnonzero(free), at[free]] += coef[rows[free]]
            h[~free] -= coef[rows[~free]] * self.support[cols[~free]]
        equal = np.array([s[1] for s in spec], bool)
        if equal.any():  # ρ_j ≤ 0 as well: −ρ_j ≥ 0
            G = np.vstack([G, -G[equal]])
            h = np.concatenate([h, -h[equal]])
        sw = np.sqrt(self.weights[region])
        x = _lsi(sw, sw * self.target[region], G, h)
        if x is None:  # pragma: no cover
            return math.inf, region, self.support[region]
        before = float(np.sum(self.weights[region] * (self.support[region] - self.target[region]) ** 2))
        after = float(np.sum(self.weights[region] * (x - self.target[region]) ** 2))
        return after - before, region, x

    def rounding_test(self, cluster, fraction):
        """The likelihood ratio of the window rounded off against the corner: the change of χ² from the fit
        with ρ = 0 over the window (the corner, its lines through one point) to the fit with ρ ≥ ``fraction``
        × the radius of curvature next to it (measured on the corner's fit, where the edges that noise split
        across nearby directions are whole again), everything nearby free to follow."""
        first, last = cluster.first, cluster.last
        margin = _margin(last - first)

        def inside(j):
            k = first + ((j - first) % self.n)
            return first < k < last

        corner, region, values = self.local_fit(first, last, lambda j: (0.0, inside(j)), margin)
        support = self.support.copy()
        support[region] = values
        length = np.maximum(self.curvature(support), 0.0) * self.norm
        radius = fraction * self.neighbourhood_radius(cluster, length)
        rounded, _, _ = self.local_fit(first, last, lambda j: ((radius if inside(j) else 0.0), False), margin)
        return radius, max(rounded - corner, 0.0) / self.sigma**2

    # ------------------------------------------------------------------------------------------ the body
    def floors(self, clusters):
        """Smallest ρ_j of the simplest body: 0 on the lines of a corner, elsewhere the radius its
        (rejected) candidate was tested with, or that of the neighbouring candidates."""
        n = self.n
        floor = np.full(n, np.nan)
        owner = np.full(n, -1)
        for k, c in enumerate(clusters):
            inner = self.lines(c.first + 1, c.last - 1)
            floor[inner] = 0.0 if c.corner else c.radius
            owner[inner] = k
        for k, c in enumerate(clusters):
            if c.corner:
                floor[c.first % n] = 0.0
                floor[c.last % n] = 0.0
        m = len(clusters)
        for k in range(m):
            left, right = clusters[k], clusters[(k + 1) % m]
            stop = right.first if right.first >= left.last else right.first + n
            idx = [j % n for j in range(left.last, stop + 1) if np.isnan(floor[j % n])]
            if not idx:
                continue
            radii = [c.radius for c in (left, right) if not c.corner]
            if radii:
                value = min(radii)
            else:
                span = max(float(self.angle(stop) - self.angle(left.last)), float(np.max(self.norm)))
                value = float(self.length[self.lines(left.last, stop)].sum()) / span
            floor[idx] = value
        return floor

    def body_fit(self, clusters, factor):
        """Least squares with ρ = 0 exactly inside each corner window (its lines through one point: the
        support values there follow from the two bounding lines) and ρ ≥ the floors elsewhere."""
        from scipy import sparse

        n = self.n
        floor = self.floors(clusters)
        forced = np.zeros(n, bool)
        rows, cols, vals = [], [], []
        for c in clusters:
            if not c.corner:
                continue
            a, b = self.angle(c.first), self.angle(c.last)
            for j in range(c.first + 1, c.last):
                t = self.angle(j)
                forced[j % n] = True
                s = math.sin(b - a)
                rows += [j % n, j % n]
                cols += [c.first % n, c.last % n]
                vals += [math.sin(b - t) / s, math.sin(t - a) / s]
        free = np.flatnonzero(~forced)
        index = np.full(n, -1)
        index[free] = np.arange(free.size)
        rows += free.tolist()
        cols += free.tolist()
        vals += [1.0] * free.size
        B = sparse.csr_matrix((vals, (rows, index[np.array(cols)])), shape=(n, free.size))
        A = sparse.diags([self.lo[1:], self.mid, self.hi[:-1]], [-1, 0, 1], shape=(n, n)).tolil()
        A[0, n - 1] = self.lo[0]
        A[n - 1, 0] = self.hi[n - 1]
        constrained = free  # the forced lines meet their constraint exactly
        G = (A.tocsr()[constrained] @ B).toarray()
        h = factor * floor[constrained]
        sw = np.sqrt(self.weights)
        E = (sparse.diags(sw) @ B).toarray()
        x = _lsi(E, sw * self.target, G, h)
        if x is None:  # pragma: no cover
            return None
        return B @ x


def _threshold(candidates: int, level: float) -> float:
    """χ² (one degree of freedom) exceeded by chance with probability ``level`` over ``candidates`` tests."""
    from statistics import NormalDist

    return NormalDist().inv_cdf(1.0 - 0.5 * level / max(candidates, 1)) ** 2


def fit_convex(theta, b, b0: float = 0.0, *, sigma: float | None = None) -> FitResult:
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
        A ``sigma`` that is not a positive finite number.
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
    if sigma is not None:
        if isinstance(sigma, bool) or not isinstance(sigma, (int, float, np.floating, np.integer)) \
                or not math.isfinite(sigma) or sigma <= 0:
            raise InvalidArgument(f"`sigma`: the noise must be a positive finite number, got {sigma!r}")
        sigma = float(sigma)
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
    structure = _Structure(directions, counts.astype(float), target, projection, 1.0)
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

    clusters = sorted((_Cluster(s - 1, s + length) for s, length in _runs(zero)), key=lambda c: c.first)
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
    corners = sum(c.corner for c in clusters)
    if corners:
        regime = "critical"
    elif any(c.statistic > marginal for c in clusters):
        regime = "undecided"
    else:
        regime = "convex"
    fitted = support - b0
    residual = b - fitted[index]
    from coinwall.forward.wall import Wall

    # NNLS meets the constraints to its own tolerance, amplified by 1/Δ² where directions crowd: the
    # fitted wall says so, so that ρ_j ≈ 0 reads as a vertex window and not as a cut
    accuracy = 1e-9 * max(1.0, float(np.max(np.abs(support))))
    wall = Wall.from_samples(directions, fitted, rounding=accuracy)
    body = solve_body(wall, b0)
    tests = tuple(CornerTest((float(structure.angle(c.first)), float(structure.angle(c.last))),
                             int(c.last - c.first + 1), c.radius, c.statistic,
                             "corner" if c.corner else ("possible" if c.statistic > marginal else "round"))
                  for c in clusters)
    return FitResult(directions, mean, counts, fitted, b0, float(np.sqrt(np.mean(residual**2))),
                     float(np.max(np.abs(residual))), wall, body, projection - b0, sigma_used, sigma is not None,
                     chi2, bound, regime, threshold, tests, tuple(notes))
