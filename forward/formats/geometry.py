"""Geometry shared by the outline readers: curves flattened to a chord error, areas and centroids.

Every reader turns its curves (SVG Béziers and arcs, DXF ellipses, circles) into points with a chord
error below ``FLATNESS`` times the size of the shape, so the support function of the points, hence
the wall, is exact to that relative accuracy.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["Drawing", "FLATNESS", "MAX_POINTS_PER_CURVE", "convex_hull", "polygon_area_centroid",
           "shapes_area_centroid", "steps_for_curvature", "cubic_points", "ellipse_points"]

#: chord error of flattened curves, relative to the size of the shape
FLATNESS = 1e-8
#: points per curve at most (a huge curvature bound must not exhaust memory)
MAX_POINTS_PER_CURVE = 200_000


class Drawing(NamedTuple):
    """What a drawing reader found, before hull, centre of mass and scale are applied.

    Attributes
    ----------
    shapes : list of ndarray
        Closed shapes, each an (m, 2) array of points (not repeating the first).
    loose : list of ndarray
        Open curves; they count for the convex hull only.
    recorded : dict
        What coinwall's own export recorded in the file: ``com`` (x, y), ``kappa`` and ``units``.
    what : str
        A note saying what was read.
    """

    shapes: list
    loose: list
    recorded: dict
    what: str


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

    polys = []
    for pts in shapes:
        if len(pts) >= 3:
            poly = Polygon(pts)
            if not poly.is_valid:
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
    n = math.ceil(math.sqrt(second_difference_bound / (8 * FLATNESS * size)))
    return int(min(max(n, 1), MAX_POINTS_PER_CURVE))


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
