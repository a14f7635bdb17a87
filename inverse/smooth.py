"""The smooth solver's toolbox: the body of a wall known everywhere, and the checks of a solved body.

:func:`solve_smooth` runs the envelope or polar construction (:data:`METHODS`) on a grid of normal angles
and checks the outline against the wall on a second grid; :func:`shape_check`, :func:`outline_support` and
:func:`body_warnings` are the checks every solved body gets (the sampled path of :mod:`.sampled` uses them
too).  :func:`coinwall.inverse.solve.solve_body` chooses the path.  The tolerances are those of
:mod:`.tolerances`.
"""

from __future__ import annotations

import math
import time

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.outline import support_function

from .body import Body
from .corners import Corner, corner_deficit
from .critical import critical_offset, regime_of
from .envelope import envelope_nodes
from .polar import polar_nodes
from .support import sample_support
from .tolerances import AREA_TOLERANCE, DEFICIT_TOLERANCE, DIRECTION_TOLERANCE, WALL_ACCURACY

__all__ = ["METHODS", "body_warnings", "outline_support", "shape_check", "solve_smooth"]


def _envelope(wall, b0, points, regime, samples=None):
    if samples is None:
        samples = sample_support(wall, b0, points)
    nodes, _ = envelope_nodes(samples, wall, b0, case_three=(regime == "corner"))
    return nodes, {}


def _polar(wall, b0, points, regime, samples=None):
    nodes, solution = polar_nodes(wall, b0, points)
    return nodes, {"folds": solution.folds, "polar_residual": solution.residual}


#: Solvers by name; each maps (wall, b0, points, regime, samples) to (Nodes, extras); ``samples``
#: (the support function on the envelope grid, or None) saves evaluating the wall twice.
METHODS = {"envelope": _envelope, "polar": _polar}


def _check_grid(n_nodes, windows, offset):
    """Angles for the wall check, between the construction angles, and a mask of those outside corner windows."""
    theta = (np.arange(n_nodes) + offset) * TWO_PI / n_nodes
    keep = np.ones(theta.size, bool)
    for lo, hi in windows:
        keep &= np.mod(theta - lo, TWO_PI) > hi - lo
    return theta, keep


def solve_smooth(wall, b0: float, *, method: str, points: int, cross_check: bool, started: float,
                 accuracy: float | None = None, critical=None) -> Body:
    """The body of a wall known everywhere (a formula, or data shown to be smooth): the envelope or
    polar construction on a grid of ``points`` normal angles, checked against the wall on a second grid.
    ``critical``: the wall's :class:`~.critical.CriticalOffset`, when the caller has it (data: their certified one)."""
    # the envelope grid doubles as the bracketing grid of the critical offset
    samples = sample_support(wall, b0, points) if (method == "envelope" or cross_check) else None
    if critical is None:
        critical = critical_offset(wall)
    regime = regime_of(b0, critical.b_c, wall.scale, critical.b_c_tolerance)
    geometry = regime
    if wall.samples is not None and samples is not None and regime != "corner" \
            and float(np.min(samples.h + samples.h2)) < -1e-12 * max(1.0, wall.scale):
        # data read through their interpolant: the construction follows the interpolant's own curvature,
        # which may dip below 0 where the data are critical within their accuracy (a corner, not a fold)
        geometry = "corner"
    nodes, extras = METHODS[method](wall, b0, points, geometry, samples)
    scale = max(1.0, float(np.max(np.hypot(*nodes.x.T))))
    nodes = nodes.collapse(1e-12 * scale)
    outline = nodes.outline()

    corners = []
    widths = nodes.window_widths()
    for i in np.flatnonzero(widths > DIRECTION_TOLERANCE):
        px, py = nodes.x[i]
        lo, hi = float(nodes.phi_in[i]), float(nodes.phi_out[i])
        deficit, where = corner_deficit(wall, b0, nodes.x[i], lo, hi)
        direction = float(np.mod(math.atan2(py, px), TWO_PI))
        direction = 0.0 if direction >= TWO_PI else direction  # np.mod(-1e-17, 2π) rounds to 2π
        # a deficit at the rounding level of the wall is none: the corner is the wall's own
        deficit = deficit if deficit > 64 * np.finfo(float).eps * wall.scale else 0.0
        corners.append(Corner(direction, 0.5 * (hi - lo), float(math.hypot(px, py)),
                              deficit, (float(np.mod(lo, TWO_PI)), float(np.mod(lo, TWO_PI) + hi - lo)),
                              where))
    deficit_windows = [c.window for c in corners if c.max_deficit > DEFICIT_TOLERANCE * wall.scale]

    area = outline.area
    notes = []
    if area <= AREA_TOLERANCE * scale**2:
        # a segment (the stick) has no interior; shapely calls such a polygon invalid
        valid, convex = True, True
        notes.append("the body is a segment (zero area)")
    else:
        valid, convex = shape_check(outline.polygon(4))  # every piece, not only the nodes
    theta, keep = _check_grid(max(points, 256), deficit_windows, offset=0.5 + 1 / math.pi)
    prescribed = b0 + wall(theta)
    lowest = float(np.min(prescribed)) if samples is None else min(float(np.min(prescribed)), float(np.min(samples.h)))
    body_wall = outline_support(outline, theta, convex=convex and valid)
    # the loop is closed on the whole outline: outside the corner windows the body's wall is the
    # prescribed one; inside them it may only be lower (a corner cuts the wall, never exceeds it)
    error = np.abs(body_wall - prescribed)[keep]
    excess = (body_wall - prescribed)[~keep]
    max_wall_error = max(float(np.max(error)) if error.size else 0.0, float(np.max(excess)) if excess.size else 0.0)

    cross = None
    if cross_check:
        other = "polar" if method == "envelope" else "envelope"
        other_nodes, _ = METHODS[other](wall, b0, points, geometry, samples)
        other_outline = other_nodes.collapse(1e-12 * scale).outline()
        cross = float(np.max(np.abs(support_function(other_outline, theta) - support_function(outline, theta))))

    rho_in, rho_out = nodes.rho_in, nodes.rho_out
    with np.errstate(divide="ignore"):
        curvature = np.where((widths > DIRECTION_TOLERANCE) | (np.minimum(rho_in, rho_out) <= 0), np.inf,
                             1.0 / rho_out)
    x, y = nodes.x[:, 0], nodes.x[:, 1]
    com_inside = lowest > 0  # on the check grid and the construction grid
    if not com_inside:
        notes.append("the centre of mass lies on the boundary (b0 + b = 0 somewhere)")
    if accuracy is None:
        accuracy = WALL_ACCURACY * max(1.0, wall.scale)
    return Body(
        wall=wall, b0=b0, b_c=critical.b_c, critical_angles=critical.angles,
        critical_angle_errors=critical.angle_errors, regime=regime, method=method,
        outline=outline, x=x, y=y, K=curvature,
        phi_in=np.mod(nodes.phi_in, TWO_PI), phi_out=np.mod(nodes.phi_in, TWO_PI) + widths,
        corners=tuple(corners), folds=tuple(extras.get("folds", ())), max_wall_error=max_wall_error,
        cross_check=cross, polar_residual=extras.get("polar_residual"), convex=convex, valid=valid,
        com_inside=com_inside,
        seconds=time.perf_counter() - started, notes=tuple(notes), b_c_tolerance=critical.b_c_tolerance,
        accuracy=accuracy, warnings=body_warnings(max_wall_error, cross, convex, valid, accuracy))


def shape_check(points) -> tuple[bool, bool]:
    """``(valid, convex)`` of the closed polygon through ``points`` (shapely): simple, and with no more
    area in its convex hull than in itself (to 1e-9)."""
    from .convexity import simple_convex

    if simple_convex(points):  # linear time; shapely below decides what it leaves open
        return True, True
    from shapely.geometry import Polygon

    polygon = Polygon(points)
    valid = bool(polygon.is_valid)
    return valid, bool(valid and polygon.area >= polygon.convex_hull.area * (1 - 1e-9))


def outline_support(outline, theta, per_segment: int = 8, *, convex: bool = False):
    """The support function of ``outline`` at ``theta``, seen from every piece of it.

    :func:`~coinwall.forward.outline.support_function` is exact for a convex outline but only looks
    near where a convex outline would touch; a spike or a loop elsewhere would pass unseen.  The
    largest projection of points along every segment catches those; for a convex outline it never
    exceeds the exact value, so the larger of the two is exact there and honest everywhere.  An outline
    already checked to be simple and convex (``convex=True``) needs only the exact search.
    """
    if convex:
        return support_function(outline, theta)
    points = outline.polygon(per_segment)
    directions = np.stack([np.cos(theta), np.sin(theta)])
    dense = np.empty(np.size(theta))
    block = max(1, 4_000_000 // max(1, len(points)))  # bounded memory: points × angles per block
    for start in range(0, dense.size, block):
        dense[start:start + block] = np.max(points @ directions[:, start:start + block], axis=0)
    return np.maximum(support_function(outline, theta), dense)


def body_warnings(max_wall_error, cross, convex, valid, accuracy) -> tuple:
    """What makes a solved body not the answer: the checks of the whole result, as sentences."""
    warnings = []
    if not valid:
        warnings.append("the outline is not a simple closed curve (it crosses itself)")
    elif not convex:
        warnings.append("the outline is not convex")
    if not max_wall_error <= accuracy:  # also catches nan
        warnings.append(f"the body's wall differs from the prescribed one by {max_wall_error:.3g} "
                        f"(accuracy {accuracy:.3g})")
    if cross is not None and not cross <= accuracy:
        warnings.append(f"the two solvers disagree by {cross:.3g} (accuracy {accuracy:.3g})")
    return tuple(warnings)
