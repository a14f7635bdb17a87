"""Geometry shared by the outline readers: curves flattened to a chord error, areas and centroids.

Every reader turns its curves (SVG Béziers and arcs, DXF ellipses, circles) into points with a chord
error below ``FLATNESS`` times the size of the shape, so the support function of the points, hence
the wall, is exact to that relative accuracy.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = [
    "CHAIN_TOLERANCE",
    "FLATNESS",
    "MAX_COORDINATE",
    "MAX_POINTS",
    "MAX_POINTS_PER_CURVE",
    "MAX_REPAIR_POINTS",
    "MAX_SHAPES",
    "MIN_SIZE",
    "UNIT_LENGTHS",
    "Drawing",
    "PointBudget",
    "check_coordinates",
    "convex_hull",
    "cubic_points",
    "ellipse_points",
    "is_rectangle",
    "join_chains",
    "polygon_area_centroid",
    "shapes_area_centroid",
    "steps_for_curvature",
]

#: chord error of flattened curves, relative to the size of the shape
FLATNESS = 1e-8
#: points per curve at most (a huge curvature bound must not exhaust memory)
MAX_POINTS_PER_CURVE = 200_000
#: flattened points per drawing at most (a full circle is ~22 000 points at FLATNESS): the reader, the hull
#: and the union keep a few copies of them, ~0.5 GB at this bound (docs/cli-limits.md)
MAX_POINTS = 2_000_000
#: closed shapes and open curves per drawing at most (each is compared with the largest one's hull)
MAX_SHAPES = 5_000
#: a shape that crosses itself is repaired (shapely ``buffer(0)``) only up to this many points: the repair
#: grows with the square of the crossings (1 000 random points: 3.7 s, 0.28 GB; 3 000: 31 s, 2.1 GB)
MAX_REPAIR_POINTS = 1_000
#: drawing coordinates at most this large in absolute value (areas and moments, which square them, stay finite)
MAX_COORDINATE = 1e100
#: shapes at least this large (a smaller one has an area that underflows)
MIN_SIZE = 1e-100
#: length of one unit in millimetres: the units a drawing may record (SVG ``width``/``height``, DXF
#: ``$INSUNITS``) and a caller may give κ in; px and pt are the CSS units (1 px = 1/96 in, 1 pt = 1/72 in)
UNIT_LENGTHS = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4, "ft": 304.8, "pt": 25.4 / 72, "pc": 25.4 / 6,
                "px": 25.4 / 96}
#: end points of DXF LINE/ARC pieces closer than this times the size of the pieces are joined
CHAIN_TOLERANCE = 1e-6


class Drawing(NamedTuple):
    """What a drawing reader found, before hull, centre of mass and scale are applied.

    Attributes
    ----------
    shapes : list of ndarray
        Closed shapes, each an (m, 2) array of points (not repeating the first).
    loose : list of ndarray
        Open curves; they count for the convex hull only.
    recorded : dict
        What the file records: from coinwall's own export ``com`` (x, y), ``kappa`` and ``units``;
        from any drawing ``unit`` = (name, length of one drawing coordinate in mm) when it states a
        physical unit, and for SVG ``page`` = the area of the page (viewBox) in drawing coordinates and
        ``frame`` = the 3×3 affine map from the drawing's own coordinates (as written in the file, in
        which ``com`` is given) to those of the shapes (y up); absent means the same coordinates.
    what : str
        A note saying what was read.
    """

    shapes: list
    loose: list
    recorded: dict
    what: str


class PointBudget:
    """Counts the points and shapes a reader makes, and refuses the drawing once there are too many.

    Parameters
    ----------
    path : str
        The file, for the messages.
    points, shapes : int
        The bounds (default :data:`MAX_POINTS`, :data:`MAX_SHAPES`).
    """

    def __init__(self, path, points=MAX_POINTS, shapes=MAX_SHAPES):
        self.path, self.max_points, self.max_shapes = path, int(points), int(shapes)
        self.points = self.shapes = self.segments = 0  # segments: counted by the SVG path reader

    def take(self, count, where=""):
        """Count ``count`` more points; refuse once more than the bound were made."""
        from ..errors import InvalidOutline

        self.points += int(count)
        if self.points > self.max_points:
            raise InvalidOutline(f"body file {self.path!r}: more than {self.max_points} points after flattening "
                                 f"curves{' (at ' + where + ')' if where else ''}; coinwall reads drawings of at "
                                 "most that many points (a full circle or ellipse is ~22 000); simplify the "
                                 "drawing or pick one shape")

    def shape(self, where=""):
        """Count one more shape; refuse once there are more than the bound."""
        from ..errors import InvalidOutline

        self.shapes += 1
        if self.shapes > self.max_shapes:
            raise InvalidOutline(f"body file {self.path!r}: more than {self.max_shapes} shapes"
                                 f"{' (at ' + where + ')' if where else ''}; coinwall reads drawings of at most "
                                 "that many; pick one shape (SVG `element`, DXF `layer`)")


def check_coordinates(points, what):
    """``points`` if every coordinate is finite and at most :data:`MAX_COORDINATE` in absolute value;
    otherwise :class:`~coinwall.forward.errors.InvalidOutline` naming ``what``."""
    from ..errors import InvalidOutline

    pts = np.asarray(points, float)
    with np.errstate(invalid="ignore", over="ignore"):
        bad = ~(np.abs(pts) <= MAX_COORDINATE)
    if bad.any():
        value = pts.flat[int(np.flatnonzero(bad.ravel())[0])]
        reason = "not finite" if not math.isfinite(value) else f"larger than {MAX_COORDINATE:g} in absolute value"
        raise InvalidOutline(f"{what}: a coordinate is {reason} ({value:g})")
    return pts


def convex_hull(points):
    """Vertices of the convex hull of ``points`` and whether some points were not vertices.

    A degenerate outline (a segment) has no 2-D hull: its two extreme points are returned.
    """
    from scipy.spatial import ConvexHull, QhullError

    pts = np.asarray(points, float)
    try:
        hull = ConvexHull(pts)
    except (QhullError, ValueError):
        direction = pts[np.argmax(np.hypot(*(pts - pts[0]).T))] - pts[0]
        proj = (pts - pts[0]) @ direction
        return pts[[int(np.argmin(proj)), int(np.argmax(proj))]], False
    return pts[hull.vertices], len(hull.vertices) < len(pts)


def polygon_area_centroid(pts):
    """Area (≥ 0) and centroid of a simple polygon (shoelace formula); the mean of the vertices if flat."""
    x, y = pts[:, 0], pts[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    if abs(area) < 1e-300:
        return 0.0, pts.mean(axis=0)
    cx = ((x + xn) * cross).sum() / (6 * area)
    cy = ((y + yn) * cross).sum() / (6 * area)
    return abs(area), np.array([cx, cy])


def shapes_area_centroid(shapes):
    """Area and centroid of the union of closed shapes (shapely), or None if they enclose nothing."""
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    from ..errors import InvalidOutline

    polys = []
    for k, pts in enumerate(shapes):
        if len(pts) >= 3:
            poly = Polygon(pts)
            if not poly.is_valid:
                if len(pts) > MAX_REPAIR_POINTS:
                    raise InvalidOutline(f"shape {k + 1} ({len(pts)} points) crosses itself; coinwall repairs "
                                         f"self-crossing shapes of at most {MAX_REPAIR_POINTS} points (the repair "
                                         "grows with the square of the crossings): fix the drawing or pick one shape")
                poly = poly.buffer(0)
            if poly.area > 0:
                polys.append(poly)
    if not polys:
        return None
    union = unary_union(polys)
    return float(union.area), np.array([union.centroid.x, union.centroid.y])


def steps_for_curvature(second_difference_bound, size):
    """Uniform steps of a polynomial curve so the chord error ≤ FLATNESS·size (error ≤ M Δ²/8)."""
    if size <= 0 or second_difference_bound <= 0:
        return 1
    with np.errstate(over="ignore"):
        steps = math.sqrt(second_difference_bound / (8 * FLATNESS * size))
    if not steps <= MAX_POINTS_PER_CURVE:  # also inf (a curve vast next to its size estimate) and nan
        return MAX_POINTS_PER_CURVE
    return int(max(math.ceil(steps), 1))


def cubic_points(p0, p1, p2, p3, size):
    """Points of a cubic Bézier, end point included, start excluded."""
    m2 = 6 * max(np.hypot(*(p2 - 2 * p1 + p0)), np.hypot(*(p3 - 2 * p2 + p1)))
    s = np.linspace(0, 1, steps_for_curvature(m2, size) + 1)[1:, None]
    u = 1 - s
    return u**3 * p0 + 3 * u * u * s * p1 + 3 * u * s * s * p2 + s**3 * p3


def ellipse_points(centre, rx, ry, rotation, start, sweep, size):
    """Points of an elliptical arc (angles in radians), end point included, start excluded."""
    r = max(abs(rx), abs(ry))
    if r <= 0:
        return np.empty((0, 2))
    n = steps_for_curvature(r * abs(sweep) ** 2, size)
    t = start + sweep * np.linspace(0, 1, n + 1)[1:]
    c, s = math.cos(rotation), math.sin(rotation)
    x, y = rx * np.cos(t), ry * np.sin(t)
    return np.column_stack([centre[0] + c * x - s * y, centre[1] + s * x + c * y])


def is_rectangle(points, tolerance=1e-9):
    """Whether a closed shape is a rectangle: four corners (after dropping collinear points) at right angles.

    ``tolerance`` is relative to the size of the shape.
    """
    pts = np.asarray(points, float)
    size = float(np.ptp(pts, axis=0).max()) if len(pts) else 0.0
    # repeated points (a DXF polyline's pieces share their ends) are one point
    pts = pts[np.hypot(*(pts - np.roll(pts, 1, axis=0)).T) > tolerance * size] if size > 0 else pts
    if len(pts) < 4:
        return False
    if size <= 0:
        return False
    before, after = pts - np.roll(pts, 1, axis=0), np.roll(pts, -1, axis=0) - pts
    turn = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
    lengths = np.hypot(*before.T) * np.hypot(*after.T)
    keep = (np.abs(turn) > tolerance * np.maximum(lengths, size**2 * tolerance)) & (lengths > 0)
    corners = pts[keep]
    if len(corners) != 4:
        return False
    sides = np.roll(corners, -1, axis=0) - corners
    dots = np.sum(sides * np.roll(sides, -1, axis=0), axis=1)
    return bool(np.all(np.abs(dots) <= 1e-7 * np.sum(sides**2, axis=1).max()))


def join_chains(pieces, tolerance):
    """Join open pieces (arrays of points from start to end) whose end points meet into closed loops.

    Parameters
    ----------
    pieces : list of ndarray
        Each an (m, 2) array, m ≥ 2, ordered from one end to the other (either direction).
    tolerance : float
        End points closer than this meet.

    Returns
    -------
    (list of ndarray, list of (ndarray, float))
        The closed loops (points not repeating the first), and the open chains, each with the
        distance between its two ends (the gap that keeps it open).
    """
    unused = [np.asarray(p, float) for p in pieces if len(p) >= 2]

    def take(point):
        """The unused piece with an end at ``point``, oriented to start there, or None."""
        for k, piece in enumerate(unused):
            for candidate in (piece, piece[::-1]):
                if np.hypot(*(candidate[0] - point)) <= tolerance:
                    unused.pop(k)
                    return candidate
        return None

    loops, open_chains = [], []
    while unused:
        chain = [unused.pop(0)]
        while np.hypot(*(chain[-1][-1] - chain[0][0])) > tolerance or sum(len(p) for p in chain) < 4:
            after = take(chain[-1][-1])
            if after is not None:
                chain.append(after)
                continue
            before = take(chain[0][0])  # an open chain is followed both ways, so its gap is its whole gap
            if before is None:
                break
            chain.insert(0, before[::-1])
        points = np.vstack([chain[0]] + [piece[1:] for piece in chain[1:]])
        gap = float(np.hypot(*(points[-1] - points[0])))
        if gap <= tolerance and len(points) > 3:
            loops.append(points[:-1])
        else:
            open_chains.append((points, gap))
    return loops, open_chains
