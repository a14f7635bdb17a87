"""A linear-time test that a closed polygon is simple and convex, before shapely's general one.

A closed polygon whose edge directions turn the same way at every vertex (each turn in [0, π)) and
turn by exactly one full revolution in all is the boundary of a convex polygon traversed once, so it
is simple: its tangent angle is monotone and covers 2π once (the discrete form of the theorem that a
closed curve of total curvature 2π is convex, e.g. do Carmo, *Differential Geometry of Curves and
Surfaces*, §5-7).  A polygon that winds twice turns by 4π, a figure eight turns both ways, and any
dent turns back at some vertex: those (and any doubtful case: a reversal, a zero-length edge left
after merging repeated points) are left to shapely, which decides every polygon.

The test costs one ``arctan2`` per vertex (~10 ms at 4·10⁵ vertices, against ~150 ms for shapely's
validity and hull check); numpy has no such predicate, and shapely's own ``is_valid`` is the general
O(n log n) one, hence this hand-written pre-check.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["simple_convex"]

#: How far the total turning may be from ±2π (it is a multiple of 2π up to the rounding of the turns).
_TURN_TOLERANCE = 1e-6


def simple_convex(points) -> bool:
    """True when the closed polygon through ``points`` is certainly simple and convex.

    Parameters
    ----------
    points : array_like, shape (n, 2)
        The vertices in order; the last joins the first (a repeated first point at the end is allowed).

    Returns
    -------
    bool
        True: every turn has one sign and the turns add up to one revolution, so the polygon is simple
        and convex.  False means *undecided*, not "not convex": decide with a general test.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3 or not np.all(np.isfinite(pts)):
        return False
    edges = np.diff(pts, axis=0, append=pts[:1])
    edges = edges[np.any(edges != 0.0, axis=1)]  # repeated points add no edge
    if len(edges) < 3:
        return False
    heading = np.arctan2(edges[:, 1], edges[:, 0])
    turn = np.diff(heading, append=heading[:1])
    turn = np.where(turn > math.pi, turn - 2 * math.pi, np.where(turn <= -math.pi, turn + 2 * math.pi, turn))
    total = float(np.sum(turn))
    if abs(total - 2 * math.pi) < _TURN_TOLERANCE:  # counter-clockwise
        return bool(np.all(turn >= 0.0) and np.all(turn < math.pi - _TURN_TOLERANCE))
    if abs(total + 2 * math.pi) < _TURN_TOLERANCE:  # clockwise
        return bool(np.all(turn <= 0.0) and np.all(turn > -math.pi + _TURN_TOLERANCE))
    return False
