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
from .critical import regime_of
from .discrete import discrete_support, halfspace_polygon, sampled_critical_offset, support_polygon

__all__ = ["interpolant_agrees", "solve_samples"]


def interpolant_agrees(wall, support) -> bool:
    """Whether the wall's trigonometric interpolant reads the data faithfully: its ``b + b''`` at every
    sample within what rounding and spacing allow of the discrete radius of curvature.

    A Fourier interpolant rings at every kink and vertex window (``b + b''`` overshoots by O(1) next to
    them); for smooth data the two agree to ``Δ²ρ''/12``, which the spacing error estimates.
    """
    from coinwall.forward.wallbackends import MAX_LSQ_SAMPLES

    theta, b = support.theta, support.b
    n = theta.size
    uniform = np.allclose(np.diff(theta), TWO_PI / n, rtol=0, atol=1e-9)
    if not uniform and n > MAX_LSQ_SAMPLES:
        return False  # no interpolant is made of so many: the half-plane body, exact for the data, is used
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
    return bool(np.all(np.abs(rho_interpolant - support.rho) <= allowed))


def _closure(outline, theta, h, windows, convex=False):
    """Largest wall error on the samples: ``|h_body − h_i|`` outside the cut windows, and inside them
    only how far the body's wall *exceeds* the samples (a cut lowers the wall, never raises it)."""
    from .solve import outline_support

    body_wall = outline_support(outline, theta, convex=convex)
    inside = np.zeros(theta.size, bool)
    for lo, hi in windows:
        inside |= np.mod(theta - lo, TWO_PI) <= hi - lo
    error = np.abs(body_wall - h)[~inside]
    excess = (body_wall - h)[inside]
    return max(float(np.max(error)) if error.size else 0.0, float(np.max(excess)) if excess.size else 0.0)


def solve_samples(wall, b0: float, *, method: str, points: int, cross_check: bool, started: float) -> Body:
    """The body of a sampled wall at offset ``b0`` (see the module docstring)."""
    from .solve import WALL_ACCURACY, body_warnings, shape_check, solve_smooth

    theta, b = wall.samples
    h = b0 + b
    support = discrete_support(theta, b, wall.sample_rounding)
    scale = max(1.0, float(np.max(np.abs(h))))
    lowest = int(np.argmin(h))
    if h[lowest] < -4.0 * support.rounding[lowest]:
        raise InvalidWall(
            f"b0 + b(θ) = {h[lowest]:.6g} < 0 at the sample θ = {theta[lowest]:.6g}: the centre of mass would "
            f"lie outside the body; choose b0 ≥ {-b[lowest]:.6g}")
    # the data's rounding sets how well the body can match them
    accuracy = max(WALL_ACCURACY * scale, 8.0 * float(np.max(support.rounding)))
    critical = sampled_critical_offset(support)
    sampled_note = (f"sampled wall ({theta.size} samples): b_c = {critical.b_c:.6g} ± {critical.b_c_tolerance:.2g} "
                    f"from the discrete radius of curvature of the samples")

    if interpolant_agrees(wall, support):
        body = solve_smooth(wall, b0, method=method, points=points, cross_check=cross_check, started=started,
                            accuracy=accuracy)
        windows = [c.window for c in body.corners if c.max_deficit > 0]
        error = max(body.max_wall_error, _closure(body.outline, theta, h, windows, body.convex and body.valid))
        notes = (*body.notes, sampled_note,
                 "the samples are smooth: their trigonometric interpolant agrees with the discrete curvature, "
                 "and the body was solved from it")
        return dataclasses.replace(
            body, max_wall_error=error, notes=notes, seconds=time.perf_counter() - started,
            warnings=body_warnings(error, body.cross_check, body.convex, body.valid, accuracy))

    regime = regime_of(b0, critical.b_c, wall.scale, critical.b_c_tolerance)
    polygon = support_polygon(theta, h, support.rounding, support.rho + b0)
    outline = Outline.from_polygon(polygon.vertices)
    corners = []
    for k in np.flatnonzero(polygon.corner):
        px, py = polygon.vertices[k]
        lo, hi = float(polygon.cone_start[k]), float(polygon.cone_end[k])
        direction = float(np.mod(math.atan2(py, px), TWO_PI))
        start = float(np.mod(lo, TWO_PI))
        corners.append(Corner(0.0 if direction >= TWO_PI else direction, 0.5 * (hi - lo), float(math.hypot(px, py)),
                              float(polygon.deficit[k]), (start, start + hi - lo), float(polygon.deficit_angle[k])))
    windows = [c.window for c in corners if c.max_deficit > 0]
    valid, convex = shape_check(polygon.vertices)
    max_wall_error = _closure(outline, theta, h, windows, convex)

    cross = None
    if cross_check:
        # an independent construction of the same intersection; both are exact at the samples
        other = Outline.from_polygon(halfspace_polygon(theta, h))
        cross = float(np.max(np.abs(support_function(other, theta) - support_function(outline, theta))))

    with np.errstate(divide="ignore"):
        curvature = np.where(polygon.corner | (polygon.rho <= 0), np.inf, 1.0 / np.maximum(polygon.rho, 1e-300))
    notes = [sampled_note,
             f"the samples are not smooth (vertex windows, kinks or noise): the body is built from the "
             f"{theta.size} sampled support lines (their half-plane intersection, with edges joining vertex "
             "windows), exact at every sample; `points` does not apply"]
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
        convex=convex, valid=valid, com_inside=bool(h[lowest] > 0), seconds=time.perf_counter() - started,
        notes=tuple(notes), b_c_tolerance=critical.b_c_tolerance, accuracy=accuracy,
        warnings=body_warnings(max_wall_error, cross, convex, valid, accuracy))
