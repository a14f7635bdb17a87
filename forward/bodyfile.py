"""Reading a body outline from a file (JSON written by coinwall, or CSV of x, y points)."""

from __future__ import annotations

import json
import os

import numpy as np

from .errors import InvalidOutline
from .outline import Outline

__all__ = ["load_outline", "wall_functions"]


def _convex(points):
    from scipy.spatial import ConvexHull, QhullError

    pts = np.asarray(points, float)
    try:
        hull = ConvexHull(pts)
    except (QhullError, ValueError):
        # a degenerate outline (a segment) has no 2-D hull: keep its two extreme points
        direction = pts[np.argmax(np.hypot(*(pts - pts[0]).T))] - pts[0]
        proj = (pts - pts[0]) @ direction
        return pts[[int(np.argmin(proj)), int(np.argmax(proj))]], False
    return pts[hull.vertices], len(hull.vertices) < len(pts)


def load_outline(path: str):
    """Outline from ``path`` (``.json`` from ``coinwall solve``, or ``.csv`` with x, y columns).

    A JSON file with Bézier ``controls`` gives the exact curve; bare points are
    replaced by their convex hull (the paper's rule: concave parts never touch
    a wall).  Returns ``(outline, note)`` where note says what was done.
    """
    if not os.path.isfile(path):
        raise InvalidOutline(f"body file {path!r} does not exist")
    ext = os.path.splitext(path)[1].lower()
    try:
        if ext == ".json":
            with open(path, encoding="utf-8") as fh:
                doc = json.load(fh)
            if not isinstance(doc, dict) or "outline" not in doc:
                raise InvalidOutline(f"body file {path!r}: no 'outline' list of [x, y] points")
            points = np.asarray(doc["outline"], dtype=float)
            controls = doc.get("controls")
            if controls is not None:
                controls = np.asarray(controls, dtype=float)
                if controls.shape == (len(points), 2, 2) and np.all(np.isfinite(controls)) \
                        and np.all(np.isfinite(points)):
                    return Outline(points, controls), "exact Bézier outline"
        elif ext == ".csv":
            points = np.loadtxt(path, delimiter=",", comments="#", skiprows=1, ndmin=2)[:, :2]
        else:
            raise InvalidOutline(f"body file {path!r}: unknown extension {ext!r}; use .json or .csv")
    except (OSError, ValueError, TypeError, IndexError) as exc:
        if isinstance(exc, InvalidOutline):
            raise
        raise InvalidOutline(f"body file {path!r} is not readable: {exc}") from None
    if points.ndim != 2 or points.shape[1] != 2 or len(points) < 2 or not np.all(np.isfinite(points)):
        raise InvalidOutline(f"body file {path!r}: the outline must be at least 2 finite [x, y] points")
    hull, replaced = _convex(points)
    note = "non-convex outline replaced by its convex hull" if replaced else "polygon outline"
    return Outline.from_polygon(hull), note


def wall_functions(outline: Outline, theta, H: float | None = None):
    """Lower wall ``b(θ) = h(θ)`` and, given the wall distance H, upper wall ``t(θ) = H − h(θ + π)``."""
    theta = np.asarray(theta, float)
    lower = outline.support(theta)
    upper = None if H is None else H - outline.support(theta + np.pi)
    return lower, upper
