"""``solve_body`` for a wall given as samples, in one pass: intervals → certify → band → body → check.

* **intervals** — the samples as intervals ``b_i ± w_i`` (:mod:`coinwall.forward.sampledata`, made when the
  wall was read);
* **certify** — the interval of ``b_c``, the critical angles, the forced and possible corners and the regime
  at ``b0`` (:mod:`.certify`);
* **band** — the envelopes of every body consistent with the intervals and their largest gap, the outline
  tolerance (:mod:`.band`);
* **body** — the body returned, the first of these that stays inside every interval: the smooth solvers'
  body of the samples' trigonometric interpolant, where the data are smooth and force no corner; the
  half-plane body under the samples' values, with lines through one point within their intervals merged into
  one vertex (:mod:`.discrete`); the outer body under the intervals' upper ends, which is inside every interval
  whenever any convex body is.  Below ``b_c`` (Case III) no body is inside every interval, and the body is the
  largest one under the samples' values, with its corners' deficits;
* **check** — the body's wall against every sample's interval, its shape, and the outline tolerance it earns.
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
from .certify import certify
from .corners import Corner
from .discrete import (
    _through_point,
    discrete_support,
    halfspace_polygon,
    simplest_inside,
    support_polygon,
    vertex_owner,
)
from .smooth import body_warnings, outline_support, shape_check, solve_smooth
from .tolerances import WALL_ACCURACY

__all__ = ["MAX_BODY_LINES", "interpolant_agrees", "solve_samples"]

#: the half-plane body is built from the samples at the spacing that resolves b_c (all of them for most data),
#: at most this many; the lines it crosses beyond their intervals are added
MAX_BODY_LINES = 20_000
#: non-uniform samples read through a least-squares interpolant at most (beyond: the half-plane body)
MAX_LSQ_CHECK = 2_000


def interpolant_agrees(wall, support, bound=None) -> bool:
    """Whether the wall's trigonometric interpolant reads the data faithfully: its ``b + b''`` at every
    sample within what rounding and spacing allow of the discrete radius of curvature, and its own ``b_c``
    inside ``bound`` (a :class:`~.certify.CriticalBound`).

    A Fourier interpolant rings at every kink and vertex window (``b + b''`` overshoots by O(1) next to
    them); for smooth data the two agree to ``Δ²ρ''/12``, which the spacing error estimates.
    """
    theta, b = support.theta, support.b
    n = theta.size
    uniform = np.allclose(np.diff(theta), TWO_PI / n, rtol=0, atol=1e-9)
    if not uniform and n > MAX_LSQ_CHECK:
        # a least-squares interpolant of so many costs n·k² (~4 s at 5,000 samples, 256 harmonics)
        return False
    if uniform:
        k = np.arange(n // 2 + 1)
        rho_interpolant = b + np.fft.irfft(-(k**2) * np.fft.rfft(b), n)
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


def interval_excess(outline, theta, h, w, windows, convex=False):
    """How far the body's wall leaves the samples' intervals ``h_i ± w_i``: ``(largest excess, its angle)``,
    ≤ 0 when it stays inside every one.  Inside the cut windows (Case III corners) only an excess above the
    interval counts (a cut lowers the wall, never raises it)."""
    _, excess, where = _wall_errors(outline_support(outline, theta, convex=convex), theta, h, w, windows)
    return excess, where


def _wall_errors(body_wall, theta, h, w, windows):
    """``(largest wall error, largest interval excess, its angle)`` of the body's wall at the samples:
    ``|h_body − h_i|`` outside the cut windows and inside them only how far it *exceeds* the samples."""
    inside = np.zeros(theta.size, bool)
    for lo, hi in windows:
        inside |= np.mod(theta - lo, TWO_PI) <= hi - lo
    error = np.where(inside, body_wall - h, np.abs(body_wall - h))
    excess = error - w
    worst = int(np.argmax(excess))
    return max(float(np.max(error)), 0.0), float(excess[worst]), float(theta[worst])


def _snap_corners(points, normals, certificate, theta, h, w):
    """The polygon with the vertices over each forced corner's window replaced by one point within every
    interval of the window's lines (and of the line either side), where the result stays convex and inside
    every sample's interval; else unchanged."""
    if not certificate.corners:
        return points, normals
    keep = np.ones(points.shape[0], bool)
    extra = {}
    for found in certificate.corners:
        lo, hi = found.window
        idx = np.flatnonzero(np.mod(theta - lo, TWO_PI) <= hi - lo)
        idx = np.unique(np.concatenate([idx, [(idx[0] - 1) % theta.size, (idx[-1] + 1) % theta.size]]))
        # the point from at most 64 of the window's lines, spread over it (the check below looks at all)
        pick = idx[np.unique(np.linspace(0, idx.size - 1, min(idx.size, 64)).astype(int))]
        point = _through_point(theta[pick], h[pick], w[pick] + 1e-15 * max(1.0, float(np.max(np.abs(h)))))
        if point is None:
            continue
        cluster = np.unique(vertex_owner(normals, theta[idx]))
        if cluster.size > points.shape[0] - 2:
            continue
        first = int(cluster[0]) if not (0 in cluster and points.shape[0] - 1 in cluster) else \
            int(cluster[np.flatnonzero(np.diff(cluster) > 1)[0] + 1])
        keep[cluster] = False
        extra[first] = point
    if not extra:
        return points, normals
    rows, angles, fresh = [], [], []
    for k in range(points.shape[0]):
        if k in extra:
            if rows:
                fresh[-1] = True  # the edge into the new point is new
            rows.append(extra[k])
            angles.append(0.0)
            fresh.append(True)
        if keep[k]:
            rows.append(points[k])
            angles.append(normals[k])
            fresh.append(False)
    new = np.array(rows)
    if new.shape[0] < 3:
        return points, normals
    fresh = np.array(fresh)
    if extra and min(extra) == 0 or not keep[0]:
        fresh[-1] = True  # the last vertex's edge leads to a new first point
    edges = np.roll(new, -1, axis=0) - new
    angles = np.where(fresh, np.mod(np.arctan2(-edges[:, 0], edges[:, 1]), TWO_PI), np.array(angles))
    support = support_function(Outline.from_polygon(new), theta)
    tiny = 1e-9 * max(1.0, float(np.max(np.abs(h))))
    if shape_check(new)[1] and np.all(support <= h + w + tiny) and np.all(support >= h - w - tiny):
        return new, angles
    return points, normals


def _forced_corners(certificate, points, normals):
    """:class:`Corner` for each forced window: the body's vertex that supports the window's middle normal, with
    that vertex's own window of normals (which holds the forced one) and the certified length of the turn."""
    corners = []
    m = points.shape[0]
    for found in certificate.corners:
        mid = 0.5 * (found.window[0] + found.window[1])
        k = int(vertex_owner(normals, np.array([mid]))[0])
        start = float(np.mod(normals[(k - 1) % m], TWO_PI))
        width = float(np.mod(normals[k] - start, TWO_PI))
        p = points[k]
        direction = float(np.mod(math.atan2(p[1], p[0]), TWO_PI))
        corners.append(Corner(0.0 if direction >= TWO_PI else direction, 0.5 * width, float(math.hypot(*p)), 0.0,
                              (start, start + width), float(np.mod(mid, TWO_PI)), False, float(found.length)))
    return corners


def _cut_corners(polygon, theta, w):
    """Case III: the vertices of the half-plane body whose window holds samples it cuts below their intervals
    (their deficit beyond the sample's half-width), and vertex windows of two or more samples."""
    corners = []
    owner_w = w[np.searchsorted(theta, np.mod(polygon.deficit_angle, TWO_PI)) % theta.size]
    for k in np.flatnonzero(polygon.corner):
        deficit = float(polygon.deficit[k])
        lo, hi = float(polygon.cone_start[k]), float(polygon.cone_end[k])
        inside = np.count_nonzero(np.mod(theta - lo, TWO_PI) < hi - lo) - 1
        if deficit <= owner_w[k] and inside < 2:
            continue
        px, py = polygon.vertices[k]
        direction = float(np.mod(math.atan2(py, px), TWO_PI))
        start = float(np.mod(lo, TWO_PI))
        corners.append(Corner(0.0 if direction >= TWO_PI else direction, 0.5 * (hi - lo), float(math.hypot(px, py)),
                              deficit if deficit > owner_w[k] else 0.0, (start, start + hi - lo),
                              float(polygon.deficit_angle[k])))
    return corners


def _halfplane(theta, h, w, used, b0, *, lifted=False):
    """The half-plane body under the lines ``used`` (values ``h``, or their upper ends with ``lifted``), with the
    lines of the other samples it crosses beyond their intervals added, the worst in each vertex's window, until
    none is (at most four rounds).  Returns ``(polygon, used)``."""
    top = h + w
    scale = max(1.0, float(np.max(np.abs(h))))
    tiny = 1e-9 * scale
    for _ in range(5):
        t = theta[used]
        lines = top[used] if lifted else h[used]
        support = discrete_support(t, lines - b0, np.zeros(used.size) if lifted else w[used])
        polygon = support_polygon(t, lines, support.rounding * (0.0 if lifted else 1.0), support.rho + b0,
                                  centre=None)
        if used.size == theta.size:
            return polygon, used
        body_wall = support_function(Outline.from_polygon(polygon.vertices), theta)
        excess = np.maximum(body_wall - top, (h - w) - body_wall)
        crossing = np.flatnonzero(excess > tiny)
        if crossing.size == 0:
            return polygon, used
        # the worst crossing line in each vertex's window
        start = np.mod(polygon.cone_start, TWO_PI)
        order = np.argsort(start)
        owner = order[(np.searchsorted(start[order], theta[crossing], side="right") - 1) % order.size]
        ranked = np.lexsort((-excess[crossing], owner))
        first = np.ones(ranked.size, bool)
        first[1:] = owner[ranked][1:] != owner[ranked][:-1]
        used = np.union1d(used, crossing[ranked[first]])
    return polygon, used


def solve_samples(wall, b0: float, *, method: str, points: int, cross_check: bool, started: float) -> Body:
    """The body of a sampled wall at offset ``b0`` (see the module docstring)."""
    data = wall.sample_data
    if data.sd is not None:
        return _solve_noisy(wall, data, b0, started)
    theta, b, w = data.theta, data.b, data.halfwidth
    h = b0 + b
    lowest = int(np.argmin(h))
    if h[lowest] < -4.0 * w[lowest]:
        raise InvalidWall(
            f"b0 + b(θ) = {h[lowest]:.6g} < 0 at the sample θ = {theta[lowest]:.6g}: the centre of mass "
            f"would lie outside the body; choose b0 ≥ {-b[lowest]:.6g}")
    scale = max(1.0, float(np.max(np.abs(h))))
    tiny = 1e-9 * scale
    # ---------------------------------------------------------------- certify, band
    certificate = certify(theta, b, w, b0, wall.__dict__.get("_certified_bound"))
    bound, band = certificate.bound, certificate.band
    object.__setattr__(wall, "_certified_bound", bound)  # a wall is immutable: its data's bound is too
    consistent = certificate.regimes != ("corner",)
    notes = [*data.notes, _interval_note(data, bound, theta.size)]
    if bound.used.size < theta.size:
        notes.append(f"b_c was computed on {bound.used.size} of the {theta.size} samples (at least {bound.spacing:.3g} "
                     "rad apart: closer samples say less about curvature than their rounding hides)")
    if len(certificate.regimes) > 1:
        notes.append(f"regime undecided at b0 = {b0:.6g}: the data allow {' or '.join(certificate.regimes)} "
                     f"(b_c in [{bound.lower:.6g}, {bound.upper:.6g}])")
    elif certificate.corners and certificate.regime == "critical":
        largest = max(c.length / c.width for c in certificate.corners)
        notes.append(f"critical: every body within the samples' intervals has the {len(certificate.corners)} corner(s) "
                     f"below (each turns through its window along at most the length given, a mean radius of "
                     f"curvature ≤ {largest:.3g}); b0 − b_c lies in [{b0 - bound.upper:.3g}, {largest:.3g}]")

    # ---------------------------------------------------------------- body
    if theta.size <= MAX_BODY_LINES:
        used = np.arange(theta.size)
    else:  # dense data: the samples at the spacing that resolves b_c (the lines the body crosses are added)
        used = bound.used[np.linspace(0, bound.used.size - 1, min(MAX_BODY_LINES, bound.used.size)).astype(int)]
    body = smooth = None
    if consistent and not certificate.corners:
        smooth = _smooth_body(wall, data, bound, used, b0, method, points, cross_check, started, certificate, notes)
    if smooth is not None:
        body_wall = support_function(smooth.outline, theta) if smooth.convex and smooth.valid else \
            outline_support(smooth.outline, theta)
        error, excess, where = _wall_errors(body_wall, theta, h, w, [])
        allowed = min(WALL_ACCURACY * scale, 0.5 * band.tolerance)
        if excess <= tiny or excess <= allowed:
            if excess > tiny:
                notes.append(f"the smooth body's wall keeps within the samples' intervals widened by {excess:.2g} "
                             "(the smooth solvers' accuracy; the outline tolerance includes it)")
            body = dataclasses.replace(smooth, max_wall_error=max(smooth.max_wall_error, error))
            kind = "the body of the samples' trigonometric interpolant (the samples are smooth)"
        else:
            notes.append(f"the samples' interpolant's body leaves their intervals by {excess:.2g}; the body was "
                         "built from the sampled lines instead")
    cross = None
    if body is None:
        polygon = None
        if consistent:
            # the outer body is inside every interval; every vertex whose removal keeps it so is removed
            points_, normals = simplest_inside(band.outer, theta, h - w, band.outer_normals)
            points_, normals = _snap_corners(points_, normals, certificate, theta, h, w)
            kind = ("the simplest polygon inside every sample's interval: the outer body (under the intervals' upper "
                    "ends), with every vertex removed that the intervals do not need and each forced corner at the "
                    "point its lines pass through")
            corners = _forced_corners(certificate, points_, normals)
            if cross_check and theta.size <= MAX_BODY_LINES:
                # the outer body again, by scipy's HalfspaceIntersection: an independent construction
                other = Outline.from_polygon(halfspace_polygon(theta, h + w))
                cross = float(np.max(np.abs(support_function(other, theta) - (h + w)
                                            - (support_function(Outline.from_polygon(band.outer), theta) - (h + w)))))
        else:
            polygon, lines = _halfplane(theta, h, w, np.asarray(used), b0)
            points_ = polygon.vertices
            kind = (f"the largest body under the {lines.size} sampled support lines, with lines that pass through one "
                    "point within their intervals joined in one vertex")
            corners = _cut_corners(polygon, theta, w)
            if cross_check:
                other = Outline.from_polygon(halfspace_polygon(theta[lines], h[lines]))
                cross = float(np.max(np.abs(support_function(other, theta[lines])
                                            - support_function(Outline.from_polygon(points_), theta[lines]))))
        outline = Outline.from_polygon(points_)
        body = _polygon_body(wall, b0, certificate, outline, corners, cross, started)
        body_wall = outline_support(body.outline, theta, convex=body.convex and body.valid)
        if certificate.corners:
            notes.append("the samples force corners: the body was built from the sampled support lines")
        elif not consistent:
            notes.append("below b_c the body is built from the sampled support lines")
        notes.append("`points` does not apply to a body built from the sampled lines")
        if method == "polar":
            notes.append("the polar equation needs a smooth wall: these data were solved by the half-plane construction")

    # ---------------------------------------------------------------- check
    windows = [c.window for c in body.corners if c.max_deficit > 0]
    error, excess, where = _wall_errors(body_wall, theta, h, w, windows)
    error = max(error, body.max_wall_error if body.method != "halfplanes" else 0.0)
    accuracy = max(WALL_ACCURACY * scale, 8.0 * float(np.max(w)))
    warnings = list(body_warnings(error, body.cross_check, body.convex, body.valid, accuracy))
    outline_tolerance = None
    if consistent:
        over = max(excess, 0.0)
        outline_tolerance = band.tolerance + 2.0 * over
        notes.append(f"outline: within {outline_tolerance:.3g} of every body the samples allow (the largest distance "
                     f"between their envelopes{'' if over <= 0 else f', plus twice the body’s excess {over:.2g}'}); "
                     f"returned: {kind}")
        if excess > max(tiny, WALL_ACCURACY * scale):
            warnings.append(_outside_warning(excess, where))
    else:
        notes.append(f"below b_c no body is inside every sample's interval: the body is {kind}, and how far it is "
                     "from the largest body under the true wall is not certified (the wall between samples is unknown)")
        if excess > tiny:
            warnings.append(_outside_warning(excess, where))
    cuts = sum(1 for c in body.corners if c.max_deficit > 0)
    if cuts > max(8, theta.size // 50):
        notes.append(f"{cuts} corners cut the data: the samples look noisy; give their standard deviations "
                     "(--b-sd) or use `coinwall fit`")
    return dataclasses.replace(
        body, wall=wall, b0=b0, b_c=bound.estimate, critical_angles=bound.angles, regime=certificate.regime,
        regimes=certificate.regimes, b_c_lower=bound.lower, b_c_upper=bound.upper,
        b_c_tolerance=max(bound.estimate - bound.lower, bound.upper - bound.estimate), max_wall_error=error,
        accuracy=accuracy, warnings=tuple(warnings), notes=(*body.notes, *notes), outline_tolerance=outline_tolerance,
        possible_corners=certificate.possible, band=band, com_inside=bool(h[lowest] > 0),
        seconds=time.perf_counter() - started)


def _interval_note(data, bound, count):
    return (f"sampled wall ({count} angles as intervals, half-widths up to {float(np.max(data.halfwidth)):.2g}): "
            f"b_c = {bound.estimate:.6g}, certified in [{bound.lower:.6g}, {bound.upper:.6g}] (the lower end for every "
            f"wall within the samples' intervals; the upper end assuming {bound.assumption})")


def _outside_warning(excess, where):
    return (f"the body's wall leaves the samples' intervals by up to {excess:.3g} (at θ = {where:.6g}); the "
            "construction found no body inside all of them")


def _smooth_body(wall, data, bound, used, b0, method, points, cross_check, started, certificate, notes):
    """The smooth solvers' body of the samples' interpolant, where it reads the data (else None)."""
    from coinwall.forward.wall import Wall

    theta, b, w = data.theta, data.b, data.halfwidth
    n = theta.size
    if used.size < n and np.allclose(np.diff(theta), TWO_PI / n, rtol=0, atol=1e-9):
        # uniform data: every k-th sample, k a divisor of n, so the subset is uniform too (its interpolant an FFT)
        divisors = np.flatnonzero(n % np.arange(1, n // 8 + 1) == 0) + 1
        used = np.arange(0, n, int(divisors[np.argmin(np.abs(divisors - n / used.size))]))
    geo = wall if used.size == n else Wall.from_samples(theta[used], b[used], rounding=w[used])
    if not interpolant_agrees(geo, discrete_support(theta[used], b[used], w[used]), bound):
        notes.append("the samples' trigonometric interpolant does not read them faithfully (its b + b'' strays from "
                     "their discrete curvature by more than their rounding and spacing allow, or its b_c leaves their "
                     "interval: kinks, flat points or rounding): the body was built from the sampled lines")
        return None
    from .critical import CriticalOffset

    critical = CriticalOffset(bound.estimate, bound.angles, bound.intervals, bound.angle_tolerance,
                              max(bound.estimate - bound.lower, bound.upper - bound.estimate), bound.lower, bound.upper,
                              bound.assumption, int(bound.used.size))
    try:
        return solve_smooth(geo, b0, method=method, points=points, cross_check=cross_check, started=started,
                            critical=critical)
    except InvalidWall as exc:
        # the interpolant, not the data, fails between the samples (it dips below 0 where the data touch it)
        notes.append(f"the samples' trigonometric interpolant cannot be solved here ({exc}); the body was built "
                     "from the sampled lines instead")
        return None


def _polygon_body(wall, b0, certificate, outline, corners, cross, started):
    """A :class:`Body` of a half-plane polygon (its checks of shape; the wall's are the caller's)."""
    vertices = outline.nodes
    valid, convex = shape_check(vertices)
    x, y = vertices[:, 0], vertices[:, 1]
    # the normal window of each vertex: from the edge before it to the edge after it
    edges = np.roll(vertices, -1, axis=0) - vertices
    normal_out = np.mod(np.arctan2(-edges[:, 0], edges[:, 1]), TWO_PI)
    normal_in = np.roll(normal_out, 1)
    width = np.mod(normal_out - normal_in, TWO_PI)
    curvature = np.full(x.size, np.inf)
    return Body(wall=wall, b0=b0, b_c=certificate.bound.estimate, critical_angles=certificate.bound.angles,
                regime=certificate.regime, method="halfplanes", outline=outline, x=x, y=y, K=curvature,
                phi_in=normal_in, phi_out=normal_in + width, corners=tuple(corners), folds=(), max_wall_error=0.0,
                cross_check=cross, polar_residual=None, convex=convex, valid=valid, com_inside=True,
                seconds=time.perf_counter() - started)


def _solve_noisy(wall, data, b0, started):
    """Samples with standard deviations: b_c an estimate with a confidence interval (:mod:`.noise`), the body
    the simplest convex one the noise allows (:func:`.fit.fit_convex`), the regime from both."""
    from .fit import MAX_DIRECTIONS, fit_convex

    theta, b, sd = data.theta, data.b, data.sd
    if theta.size > MAX_DIRECTIONS:
        # the fit takes at most MAX_DIRECTIONS directions: the samples averaged in as many bins of angle
        bins = np.minimum((theta / TWO_PI * MAX_DIRECTIONS).astype(int), MAX_DIRECTIONS - 1)
        count = np.bincount(bins, minlength=MAX_DIRECTIONS)
        filled = count > 0
        weight = 1.0 / sd**2
        theta_f = (np.bincount(bins, theta * weight, MAX_DIRECTIONS) / np.bincount(bins, weight, MAX_DIRECTIONS))[filled]
        b_f = (np.bincount(bins, b * weight, MAX_DIRECTIONS) / np.bincount(bins, weight, MAX_DIRECTIONS))[filled]
        sd_f = 1.0 / np.sqrt(np.bincount(bins, weight, MAX_DIRECTIONS)[filled])
    else:
        theta_f, b_f, sd_f = theta, b, sd
    fit = fit_convex(theta_f, b_f, b0, sd=sd_f)
    found = fit.critical
    body = fit.body
    notes = [*data.notes,
             f"noisy samples ({theta.size} angles with standard deviations, typically {found.sd:.2g}): b_c = "
             f"{found.estimate:.6g}, {found.level:.0%} confidence interval [{found.lower:.6g}, {found.upper:.6g}] "
             f"assuming {found.assumption}",
             f"the body is the simplest convex body the noise allows (coinwall fit: {fit.corners} corner(s) supported "
             f"of {len(fit.tests)} candidates; rms residual {fit.rms_residual:.3g}); no outline tolerance is "
             "certified for statistical samples"]
    return dataclasses.replace(
        body, wall=wall, b0=b0, b_c=found.estimate, critical_angles=found.angles, regime=fit.body.regime,
        regimes=fit.body.regimes, b_c_lower=None, b_c_upper=None,
        b_c_tolerance=max(found.estimate - found.lower, found.upper - found.estimate), notes=tuple(notes),
        outline_tolerance=None, possible_corners=(), band=None, statistics=found,
        seconds=time.perf_counter() - started)
