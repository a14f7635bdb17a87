"""``solve_body`` for a wall given as samples: exact for the data, smooth where the data are smooth.

Samples are support lines (:mod:`inverse.discrete`).  Two outcomes:

* **smooth data** — the trigonometric interpolant's ``b + b''`` at the samples agrees with the discrete
  radius of curvature to within what rounding and spacing allow.  The interpolant is then a faithful
  reading of the data between the samples, and the smooth solver (envelope or polar, spectrally
  accurate) is used; the loop is closed on the samples as well as on the interpolant;
* **anything else** (polygons, vertex windows, kinks, Reuleaux-like pieces, noise) — the body is the
  intersection of the sampled half-planes, with vertex windows collapsed into exact corners and
  edges between them; no derivative of the data is ever taken.  The cross-check is an independent
  construction of the same intersection (scipy's ``HalfspaceIntersection``).
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.errors import InvalidWall
from coinwall.forward.outline import Outline, support_function

from .body import Body
from .corners import Corner
from .critical import _cyclic_runs, data_critical_offset
from .discrete import discrete_support, halfspace_polygon, machine_rounding, support_polygon
from .smooth import body_warnings, outline_support, shape_check, solve_smooth
from .tolerances import WALL_ACCURACY

__all__ = ["MAX_GEOMETRY_SAMPLES", "interpolant_agrees", "solve_samples"]

#: the half-plane body is built from every sample up to this many; denser data from the samples the certified
#: interval of b_c was computed on (dense data are thinned: coinwall.inverse.certify), with the lines they
#: leave out added where the body crosses them
MAX_GEOMETRY_SAMPLES = 100_000
#: non-uniform samples read through a least-squares interpolant at most (beyond: the half-plane body)
MAX_LSQ_CHECK = 2_000


def interpolant_agrees(wall, support, bound=None) -> bool:
    """Whether the wall's trigonometric interpolant reads the data faithfully: its ``b + b''`` at every
    sample within what rounding and spacing allow of the discrete radius of curvature.

    A Fourier interpolant rings at every kink and vertex window (``b + b''`` overshoots by O(1) next to
    them); for smooth data the two agree to ``Δ²ρ''/12``, which the spacing error estimates.
    """
    theta, b = support.theta, support.b
    n = theta.size
    uniform = np.allclose(np.diff(theta), TWO_PI / n, rtol=0, atol=1e-9)
    if not uniform and n > MAX_LSQ_CHECK:
        # a least-squares interpolant of so many costs n·k² (~4 s at 5,000 samples, 256 harmonics): the
        # half-plane body, exact for the data, is used
        return False
    if uniform:
        # b'' of the interpolant at the grid points, by FFT (the interpolant of Wall.from_samples)
        k = np.arange(n // 2 + 1)
        second = np.fft.irfft(-(k**2) * np.fft.rfft(b), n)
        rho_interpolant = b + second
    else:
        values, _, second = wall.derivatives(theta)
        rho_interpolant = values + second
    spacing = np.maximum.reduce([np.roll(support.spacing_error, s) for s in (-2, -1, 0, 1, 2)])
    allowed = 4.0 * (support.rho_tolerance + spacing) + 1e-9 * max(1.0, float(np.max(np.abs(b))))
    if not np.all(np.abs(rho_interpolant - support.rho) <= allowed):
        return False
    if bound is None:
        return True
    # the interpolant is a reading of the data only if it is one of the walls they allow: its own b_c (between
    # the samples too, where it rings next to a jump of the curvature) inside the certified interval
    if uniform:
        # the trigonometric interpolant on a grid 8 times finer, by zero padding (n log n, not n² evaluations)
        coef = np.fft.rfft(b)
        if n % 2 == 0:
            coef[-1] *= 0.5  # the Nyquist term splits between ±n/2
        m = 8 * n
        padded = np.zeros(m // 2 + 1, complex)
        padded[:coef.size] = coef * (1.0 - np.arange(coef.size) ** 2)
        own = -float(np.min(np.fft.irfft(padded, m) * (m / n)))
    else:
        fine = np.linspace(0.0, TWO_PI, 8 * n, endpoint=False)
        values, _, second = wall.derivatives(fine)
        own = -float(np.min(values + second))
    slack = 1e-9 * max(1.0, float(np.max(np.abs(b))))
    return bound.lower - slack <= own <= bound.upper + slack


def _corners_where_allowed(polygon, theta, b, w, b0, within):
    """``polygon`` with its corner flags kept only on vertices whose window meets a run of samples where zero
    curvature is within the data's tolerance (``ρ_i + b0 ≤ tol_i``), or that cut the data (a deficit: Case
    III); of several flagged vertices in one run, the one with the widest window stands for the run.  A deficit
    up to ``within`` (the body's wall still inside the line's interval) is no cut."""
    support = discrete_support(theta, b, w)
    zero = support.rho + b0 - support.rho_tolerance <= 0
    deficit = np.where(polygon.deficit > within, polygon.deficit, 0.0)
    polygon = dataclasses.replace(polygon, deficit=deficit)
    runs = []
    for start, length in _cyclic_runs(zero):
        lo = theta[(start - 1) % theta.size] if length < theta.size else 0.0
        hi = theta[(start + length) % theta.size] if length < theta.size else TWO_PI
        runs.append((lo, lo + np.mod(hi - lo, TWO_PI) if length < theta.size else TWO_PI))
    corner = polygon.corner.copy()
    best = {}
    for k in np.flatnonzero(corner):
        if polygon.deficit[k] > 0:
            continue
        lo, hi = float(polygon.cone_start[k]), float(polygon.cone_end[k])
        mid = np.mod(0.5 * (lo + hi), TWO_PI)
        # the run that holds the window's middle, else any run the window meets
        found = next((r for r, (a, c) in enumerate(runs) if np.mod(mid - a, TWO_PI) <= c - a), None)
        if found is None:
            found = next((r for r, (a, c) in enumerate(runs)
                          if np.mod(lo - a, TWO_PI) <= c - a or np.mod(hi - a, TWO_PI) <= c - a
                          or np.mod(a - lo, TWO_PI) <= hi - lo), None)
        if found is None:
            corner[k] = False
            continue
        if found in best:
            other = best[found]
            if hi - lo > polygon.cone_end[other] - polygon.cone_start[other]:
                corner[other] = False
                best[found] = k
            else:
                corner[k] = False
        else:
            best[found] = k
    return dataclasses.replace(polygon, corner=corner)


def interval_excess(outline, theta, h, w, windows, convex=False):
    """How far the body's wall leaves the samples' intervals ``h_i ± w_i``: ``(largest excess, its angle)``,
    ≤ 0 when it stays inside every one.  Inside the cut windows (Case III corners) only an excess above the
    interval counts (a cut lowers the wall, never raises it)."""
    _, excess, where = _wall_errors(outline, theta, h, w, windows, convex)
    return excess, where


def _wall_errors(outline, theta, h, w, windows, convex=False):
    """``(closure, interval excess, its angle)`` from one evaluation of the body's wall at the samples.

    The closure is the largest wall error, ``|h_body − h_i|`` outside the cut windows and inside them only how
    far the body's wall *exceeds* the samples (a cut lowers the wall, never raises it); the interval excess is
    the same less each sample's half-width ``w_i`` (see :func:`interval_excess`).
    """
    body_wall = outline_support(outline, theta, convex=convex)
    inside = np.zeros(theta.size, bool)
    for lo, hi in windows:
        inside |= np.mod(theta - lo, TWO_PI) <= hi - lo
    error = np.where(inside, body_wall - h, np.abs(body_wall - h))
    excess = error - w
    worst = int(np.argmax(excess))
    return max(float(np.max(error)), 0.0), float(excess[worst]), float(theta[worst])


def _polygon_body(polygon, regimes, bound, theta, b, w, b0, lifted=False):
    """The corners, outline and shape checks of a half-plane ``polygon`` of the samples ``(θ, b ± w)``.

    ``lifted``: the polygon's lines are the upper ends ``b + w`` and its deficits measured from them (a deficit
    up to ``2w`` then leaves the wall inside the interval); the corners report deficits from the values.
    """
    if regimes == ("convex",):
        # the data allow no corner at this offset (b0 is above every b_c they allow: the body's radius of
        # curvature is positive everywhere); a vertex whose window holds samples is their rounding, not a corner
        polygon = dataclasses.replace(polygon, corner=np.zeros_like(polygon.corner),
                                      deficit=np.zeros_like(polygon.deficit))
    else:
        # a vertex window is a corner only where the data, at the spacing that resolves their curvature (the
        # samples b_c was certified on), allow zero curvature; one corner per such run of samples
        # the interval of the line that stands farthest off each vertex (its deficit's angle)
        within = w[_nearest_sample(theta, polygon.deficit_angle)] * (2.0 if lifted else 1.0)
        polygon = _corners_where_allowed(polygon, theta[bound.used], b[bound.used], w[bound.used], b0, within)
    corners = []
    for k in np.flatnonzero(polygon.corner):
        px, py = polygon.vertices[k]
        lo, hi = float(polygon.cone_start[k]), float(polygon.cone_end[k])
        direction = float(np.mod(math.atan2(py, px), TWO_PI))
        start = float(np.mod(lo, TWO_PI))
        deficit = float(polygon.deficit[k])
        if lifted and deficit > 0:  # said from the sample's value, not from its upper end
            deficit -= float(w[_nearest_sample(theta, polygon.deficit_angle[k:k + 1])[0]])
        corners.append(Corner(0.0 if direction >= TWO_PI else direction, 0.5 * (hi - lo), float(math.hypot(px, py)),
                              deficit, (start, start + hi - lo), float(polygon.deficit_angle[k])))
    windows = [c.window for c in corners if c.max_deficit > 0]
    valid, convex = shape_check(polygon.vertices)
    return polygon, tuple(corners), Outline.from_polygon(polygon.vertices), convex, valid, windows


def _nearest_sample(theta, angles):
    """Index of the sample nearest each of ``angles`` (``theta`` ascending in [0, 2π); by bisection, so the
    cost is n log n, never a vertices × samples table)."""
    angles = np.mod(np.asarray(angles, dtype=float), TWO_PI)
    n = theta.size
    after = np.searchsorted(theta, angles) % n
    before = (after - 1) % n
    gap_after = np.abs(np.mod(angles - theta[after] + np.pi, TWO_PI) - np.pi)
    gap_before = np.abs(np.mod(angles - theta[before] + np.pi, TWO_PI) - np.pi)
    return np.where(gap_after <= gap_before, after, before)


def _widened_note(excess, used, count, accuracy):
    return (f"dense data: the body, built from {used} of the {count} samples, keeps within their intervals "
            f"widened by {excess:.2g} (the body's accuracy is {accuracy:.2g}; every sample is checked)")


def _outside_warning(excess, where):
    return (f"the body's wall leaves the samples' intervals by up to {excess:.3g} (at θ = {where:.6g}); the "
            "construction found no body inside all of them")


def _owner(polygon, theta):
    """The vertex of a :class:`~.discrete.SampledBody` polygon whose window holds each direction."""
    start = np.mod(polygon.cone_start, TWO_PI)
    order = np.argsort(start)
    return order[(np.searchsorted(start[order], np.mod(theta, TWO_PI), side="right") - 1) % order.size]


def _polygon_support(polygon, theta):
    """The support function of a :class:`~.discrete.SampledBody` polygon at ``theta``."""
    v = polygon.vertices[_owner(polygon, theta)]
    return v[:, 0] * np.cos(theta) + v[:, 1] * np.sin(theta)


def solve_samples(wall, b0: float, *, method: str, points: int, cross_check: bool, started: float) -> Body:
    """The body of a sampled wall at offset ``b0`` (see the module docstring)."""
    all_theta, all_b = wall.samples
    all_w = wall.sample_rounding if wall.sample_rounding is not None else machine_rounding(all_b)
    all_h = b0 + all_b
    lowest = int(np.argmin(all_h))
    if all_h[lowest] < -4.0 * all_w[lowest]:
        raise InvalidWall(
            f"b0 + b(θ) = {all_h[lowest]:.6g} < 0 at the sample θ = {all_theta[lowest]:.6g}: the centre of mass "
            f"would lie outside the body; choose b0 ≥ {-all_b[lowest]:.6g}")
    critical = data_critical_offset(wall)
    bound = wall.__dict__["_certified_bound"]
    # the geometry uses every sample up to MAX_GEOMETRY_SAMPLES (exact at each); denser data the samples the
    # certified interval was narrowest on, and every sample is still checked against the body at the end
    used = np.arange(all_theta.size) if all_theta.size <= MAX_GEOMETRY_SAMPLES else bound.used
    thinned = used.size < all_theta.size  # the interval check then allows the chords' sag (see below)
    theta, b = all_theta[used], all_b[used]
    h = b0 + b
    support = discrete_support(theta, b, all_w[used])
    scale = max(1.0, float(np.max(np.abs(all_h))))
    # the data's rounding sets how well the body can match them
    accuracy = max(WALL_ACCURACY * scale, 8.0 * float(np.max(all_w)))
    regimes = critical.regimes(b0, wall.scale)
    regime = regimes[0] if len(regimes) == 1 else "critical"
    sampled_note = (f"sampled wall ({all_theta.size} samples as intervals, half-widths up to {np.max(all_w):.2g}): "
                    f"b_c = {critical.b_c:.6g}, certified in [{critical.lower:.6g}, {critical.upper:.6g}] "
                    f"(the lower end for every wall within the samples' intervals; the upper end assuming "
                    f"{critical.assumption})")
    notes_data = [sampled_note]
    if used.size < all_theta.size:
        notes_data.append(f"dense data: the body was built from {used.size} of the {all_theta.size} samples "
                          f"(at least {bound.spacing:.3g} rad apart, where the interval of b_c is narrowest); "
                          "the body is checked against all of them")
    elif bound.used.size < all_theta.size:
        notes_data.append(f"b_c was computed on {bound.used.size} of the {all_theta.size} samples (at least "
                          f"{bound.spacing:.3g} rad apart: closer samples say less about curvature than their "
                          "rounding hides); the body uses all of them")
    if len(regimes) > 1:
        notes_data.append(f"regime undecided at b0 = {b0:.6g}: the data allow {' or '.join(regimes)} "
                          f"(b_c in [{critical.lower:.6g}, {critical.upper:.6g}])")
    extra = {"b_c_lower": critical.lower, "b_c_upper": critical.upper, "regimes": regimes}

    geo_wall = wall
    if used.size < all_theta.size:
        from coinwall.forward.wall import Wall

        geo_wall = Wall.from_samples(theta, b, rounding=all_w[used])
    body = None
    if interpolant_agrees(geo_wall, support, bound):
        try:
            body = solve_smooth(geo_wall, b0, method=method, points=points, cross_check=cross_check,
                                started=started, accuracy=accuracy)
        except InvalidWall as exc:
            # the interpolant, not the data, fails between the samples (it dips below 0 where the data touch it)
            notes_data.append(f"the samples' trigonometric interpolant cannot be solved here ({exc}); the body was "
                              "built from the sampled lines instead")
    if body is not None:
        windows = [c.window for c in body.corners if c.max_deficit > 0]
        closure, excess, where = _wall_errors(body.outline, all_theta, all_h, all_w, windows,
                                              body.convex and body.valid)
        error = max(body.max_wall_error, closure)
        notes = (*body.notes, *notes_data,
                 "the samples are smooth: their trigonometric interpolant agrees with the discrete curvature, "
                 "and the body was solved from it")
        warnings = body_warnings(error, body.cross_check, body.convex, body.valid, accuracy)
        if excess > WALL_ACCURACY * scale:  # the smooth solvers' own accuracy
            if thinned and excess <= accuracy:
                notes = (*notes, _widened_note(excess, used.size, all_theta.size, accuracy))
            else:
                warnings = (*warnings, _outside_warning(excess, where))
        if not warnings:
            return dataclasses.replace(
                body, wall=wall, max_wall_error=error, notes=notes, seconds=time.perf_counter() - started,
                regime=regime, b_c=critical.b_c, b_c_tolerance=critical.b_c_tolerance,
                critical_angles=critical.angles, warnings=(), **extra)
        # the interpolant reads the data, but its body fails a check here (near a critical angle within the
        # data's accuracy it may need corners narrower than the spacing): the lines' own body is exact
        notes_data.append(f"the body of the samples' trigonometric interpolant failed its checks "
                          f"({'; '.join(warnings)}); the body was built from the sampled lines instead")

    polygon = support_polygon(theta, h, support.rounding, support.rho + b0)
    if used.size < all_theta.size:
        # the lines left out by thinning may cut what the used ones leave (an edge's sliver), or the used ones'
        # vertex windows and edges may pass inside them (a wall below their intervals): add the lines the
        # polygon crosses or misses, and build it again
        for _ in range(4):
            wall_here = _polygon_support(polygon, all_theta)
            excess = np.maximum(wall_here - (all_h + all_w), (all_h - all_w) - wall_here)
            crossing = np.flatnonzero(excess > 0.5 * WALL_ACCURACY * scale)
            if crossing.size == 0:
                break
            # the worst crossing line in each vertex's window: lines far apart, so no vertex is made of two
            # lines closer than their rounding resolves
            owner = _owner(polygon, all_theta[crossing])
            order = np.lexsort((-excess[crossing], owner))
            first = np.ones(order.size, bool)
            first[1:] = owner[order][1:] != owner[order][:-1]
            crossing = crossing[order[first]]
            used = np.union1d(used, crossing)
            theta, b = all_theta[used], all_b[used]
            h = b0 + b
            support = discrete_support(theta, b, all_w[used])
            polygon = support_polygon(theta, h, support.rounding, support.rho + b0)
    polygon, corners, outline, convex, valid, windows = _polygon_body(polygon, regimes, bound, all_theta, all_b,
                                                                      all_w, b0)
    exact_for = "every sample"
    # the half-plane geometry's own rounding: two lines δ apart in angle meet with an error of ~ulp/δ (2e-10 of
    # the scale measured on 10,000 exact samples at random angles); a body built from thinned samples also
    # passes the left-out ones by the chords' sag (3e-8 measured on 10⁶ exact samples at random angles), which
    # the solver's accuracy bounds (lines crossed by more are added back above)
    tiny = 1e-9 * scale if used.size == all_theta.size else 0.5 * WALL_ACCURACY * scale
    strict, _ = interval_excess(outline, all_theta, all_h, all_w, [], convex)
    if strict > tiny:
        # the body leaves a sample's interval (a cut window, or the rounding of a window's lines adding up
        # between merges).  Built again under the intervals' upper ends h + w: first merged where one point
        # lies within every interval of a window, then unmerged.  The unmerged one is inside every interval
        # whenever any convex body is: such a body lies under every upper line, so the upper body's wall is
        # at least its wall, at least h − w.  Whichever is taken, the check below looks at every sample.
        w_used = all_w[used]
        upper = h + w_used
        # (label, merge within each line's interval about its value, or no merge: then the deficits are
        # measured from the upper ends, "lifted")
        for label, rounding, centre, lifted in (
                ("merged where one point lies within every interval of a window", w_used, h, False),
                ("unmerged", np.zeros(used.size), None, True)):
            raised = support_polygon(theta, upper, rounding, support.rho + b0, centre=centre)
            result = _polygon_body(raised, regimes, bound, all_theta, all_b, all_w, b0, lifted)
            if interval_excess(result[2], all_theta, all_h, all_w, [], result[3])[0] <= tiny:
                polygon, corners, outline, convex, valid, windows = result
                h = upper
                exact_for = f"the intervals' upper ends ({label})"
                notes_data.append(f"the body under the samples' values left their intervals (by up to "
                                  f"{strict:.2g}); it is the body under the intervals' upper ends, {label}, inside "
                                  "every interval")
                break
    max_wall_error, excess, where = _wall_errors(outline, all_theta, all_h, all_w, windows, convex)
    outside = ()
    if excess > tiny:
        if thinned and excess <= accuracy:
            notes_data.append(_widened_note(excess, used.size, all_theta.size, accuracy))
        else:
            outside = (_outside_warning(excess, where),)

    cross = None
    if cross_check:
        # an independent construction of the same intersection; both are exact at the samples
        other = Outline.from_polygon(halfspace_polygon(theta, h))
        cross = float(np.max(np.abs(support_function(other, theta) - support_function(outline, theta))))

    with np.errstate(divide="ignore"):
        curvature = np.where(polygon.corner | (polygon.rho <= 0), np.inf, 1.0 / np.maximum(polygon.rho, 1e-300))
    notes = [*notes_data,
             f"the samples are not smooth (vertex windows, kinks or noise): the body is built from the "
             f"{theta.size} sampled support lines (their half-plane intersection, with edges joining vertex "
             f"windows), exact at {exact_for}; `points` does not apply"]
    if method == "polar":
        notes.append("the polar equation needs a smooth wall: these data were solved by the half-plane construction")
    if polygon.edges:
        notes.append(f"{polygon.edges} edge(s) join vertex windows (the wall has a kink between their samples)")
    cuts = sum(1 for c in corners if c.max_deficit > 0)
    if cuts > max(8, theta.size // 50):
        notes.append(f"{cuts} corners cut the data: the samples look noisy; `coinwall fit` finds the nearest "
                     "convex body in least squares")
    x, y = polygon.vertices[:, 0], polygon.vertices[:, 1]
    return Body(
        wall=wall, b0=b0, b_c=critical.b_c, critical_angles=critical.angles, regime=regime, method="halfplanes",
        outline=outline, x=x, y=y, K=curvature, phi_in=np.mod(polygon.cone_start, TWO_PI),
        phi_out=np.mod(polygon.cone_start, TWO_PI) + (polygon.cone_end - polygon.cone_start),
        corners=tuple(corners), folds=(), max_wall_error=max_wall_error, cross_check=cross, polar_residual=None,
        convex=convex, valid=valid, com_inside=bool(all_h[lowest] > 0), seconds=time.perf_counter() - started,
        notes=tuple(notes), b_c_tolerance=critical.b_c_tolerance, accuracy=accuracy,
        warnings=(*body_warnings(max_wall_error, cross, convex, valid, accuracy), *outside), **extra)
