"""The library's entry points for bodies: ``load_outline(path)`` and ``outline_from_polar(text)``.

Every reader ends in the same place: a closed convex :class:`Outline` in units of κ with the centre of
mass at the origin, and a note saying what was done.

* **Convex hull.**  Non-convex outlines are replaced by their convex hull (the paper's rule: concave
  parts never touch a wall); the note says so.
* **Centre of mass.**  In this order: ``com=(x, y)`` given by the caller; the centre of mass recorded
  in a file written by coinwall (the JSON/CSV of ``solve``, the centre-of-mass mark of its SVG, the
  POINT on its DXF's centre-of-mass layer); otherwise the centroid of the drawn shape (uniform
  density).  A polar expression R(α) is measured from the centre of mass, like the paper's R(α).
* **Scale.**  Coordinates are divided by ``kappa`` (the radius of gyration in drawing units) when
  given, else by the scale recorded by coinwall's own SVG/DXF export, else drawing units are taken
  as units of κ.
* **Curves** are flattened with a chord error below :data:`~.geometry.FLATNESS` times the size of the
  shape (see :mod:`.geometry`).
"""

from __future__ import annotations

import os

import numpy as np

from ..angles import TWO_PI
from ..errors import CoinwallError, InvalidArgument, InvalidOutline
from ..outline import Outline
from ..validation import check_count, check_positive
from .bodyjson import read_body_json
from .dxf import read_dxf
from .geometry import Drawing, convex_hull, polygon_area_centroid, shapes_area_centroid
from .points import read_points_csv
from .svg import read_svg

__all__ = ["OUTLINE_FORMATS", "load_outline", "outline_from_polar", "check_com"]

#: file extensions load_outline reads
OUTLINE_FORMATS = (".json", ".csv", ".svg", ".dxf")
_NON_CONVEX = 1e-7  # relative area excess of the hull that counts as "not convex"


def check_com(com) -> np.ndarray:
    """``com`` as a finite point ``(x, y)`` (a float array of shape (2,))."""
    try:
        centre = np.asarray(com, dtype=float).reshape(2)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`com` must be two numbers (x, y), got {com!r}") from None
    if not np.all(np.isfinite(centre)):
        raise InvalidArgument(f"`com` must be finite, got {com!r}")
    return centre


def _finish(path, drawing: Drawing, com, kappa):
    """Hull, centre of mass, scale → (Outline, note)."""
    shapes, loose, recorded, what = drawing
    everything = [np.asarray(s, float) for s in shapes + loose if len(s)]
    if not everything:
        raise InvalidOutline(f"body file {path!r}: no outline found ({what})")
    points = np.vstack(everything)
    if not np.all(np.isfinite(points)):
        raise InvalidOutline(f"body file {path!r}: outline coordinates are not finite")
    notes = [what]
    hull, _ = convex_hull(points)
    hull_area = polygon_area_centroid(hull)[0] if len(hull) > 2 else 0.0
    drawn = shapes_area_centroid(shapes) if shapes else None
    if drawn is not None and hull_area > 0 and (hull_area - drawn[0]) > _NON_CONVEX * hull_area:
        notes.append(f"non-convex outline replaced by its convex hull (area {drawn[0]:.6g} -> {hull_area:.6g})")
    elif drawn is None and loose:
        notes.append("outline = convex hull of all entities")
    if com is not None:
        centre = check_com(com)
        notes.append(f"centre of mass given at ({centre[0]:.6g}, {centre[1]:.6g})")
    elif recorded.get("com") is not None:
        centre = np.asarray(recorded["com"], float)
        notes.append("centre of mass as recorded in the file")
    else:
        if drawn is not None:
            centre = drawn[1]
        elif hull_area > 0:
            centre = polygon_area_centroid(hull)[1]
        else:
            centre = hull.mean(axis=0)
        notes.append(f"centre of mass = centroid ({centre[0]:.6g}, {centre[1]:.6g}), uniform density")
    if kappa is not None:
        scale = check_positive("kappa", kappa)
        notes.append(f"kappa = {scale:g} drawing units")
    elif recorded.get("kappa") is not None:
        scale = float(recorded["kappa"])
        notes.append(f"kappa = {scale:g} {recorded.get('units', '')} as recorded in the file".replace("  ", " "))
    else:
        scale = 1.0
        notes.append("drawing units taken as units of kappa")
    return Outline.from_polygon((hull - centre) / scale), "; ".join(notes)


def load_outline(path: str, *, layer: str | None = None, com=None, kappa: float | None = None):
    """Outline from a file, in units of κ with the centre of mass at the origin.

    Parameters
    ----------
    path : str
        ``.json`` (from ``coinwall solve``, or ``{"outline"|"points": [[x, y], ...]}``),
        ``.csv`` (x, y columns; a header row is skipped), ``.svg`` (closed paths,
        polygons, rects, circles, ellipses) or ``.dxf`` (LWPOLYLINE, POLYLINE, SPLINE,
        CIRCLE, ELLIPSE, ARC).
    layer : str, optional
        DXF layer to read (default: every layer).
    com : (float, float), optional
        Centre of mass in drawing coordinates (default: recorded by coinwall, else the centroid).
    kappa : float, optional
        Radius of gyration in drawing units (default: recorded by coinwall, else 1).

    Returns
    -------
    (Outline, str)
        The convex outline and a note saying what was done.

    Raises
    ------
    InvalidOutline
        Missing, empty, damaged or unsupported files; no closed shape; nothing on the layer.
    InvalidArgument
        A bad ``com``, ``kappa`` or ``layer``.
    """
    if not isinstance(path, str) or not os.path.isfile(path):
        raise InvalidOutline(f"body file {path!r} does not exist")
    ext = os.path.splitext(path)[1].lower()
    if ext not in OUTLINE_FORMATS:
        raise InvalidOutline(f"body file {path!r}: unsupported extension {ext or '(none)'!r}; "
                             f"use {', '.join(OUTLINE_FORMATS)}")
    if layer is not None and ext != ".dxf":
        raise InvalidArgument(f"`layer` applies to DXF files, not to {path!r}")
    if layer is not None and not isinstance(layer, str):
        raise InvalidArgument(f"`layer` must be a layer name (a string), got {layer!r}")
    # the arguments are checked before the file is read: their errors are the caller's, not the file's
    if com is not None:
        check_com(com)
    if kappa is not None:
        check_positive("kappa", kappa)
    if os.path.getsize(path) == 0:
        raise InvalidOutline(f"body file {path!r} is empty")
    try:
        if ext == ".svg":
            return _finish(path, read_svg(path), com, kappa)
        if ext == ".dxf":
            return _finish(path, read_dxf(path, layer), com, kappa)
        if ext == ".json":
            points, controls, recorded, what = read_body_json(path)
            if controls is not None and com is None and kappa is None:
                return Outline(points, controls), "exact Bézier outline (coinwall JSON, units of kappa)"
        else:
            points, coinwall = read_points_csv(path)
            recorded = {"com": (0.0, 0.0)} if coinwall else {}
            what = "coinwall CSV points" if coinwall else "CSV points"
    except (OSError, ValueError, TypeError, IndexError) as exc:
        if isinstance(exc, CoinwallError):
            raise
        raise InvalidOutline(f"body file {path!r} is not readable: {exc}") from None
    if points.ndim != 2 or points.shape[1] != 2 or len(points) < 2 or not np.all(np.isfinite(points)):
        raise InvalidOutline(f"body file {path!r}: the outline must be at least 2 finite [x, y] points")
    closed = [points] if len(points) >= 3 else []
    return _finish(path, Drawing(closed, [] if closed else [points], recorded, what), com, kappa)


def outline_from_polar(text: str, params=None, *, samples: int = 4096, com=None):
    """Outline of the polar curve R(α) (an expression in ``t``), R measured from the centre of mass.

    The expression is parsed by :mod:`coinwall.forward.expression`, never evaluated as Python.
    A convex smooth curve (curvature numerator ``R² + 2R'² − R R'' ≥ 0`` everywhere on
    the grid, no kinks) becomes a cubic Hermite/Bézier outline with the exact
    derivatives (shape error O(Δα⁴)); otherwise the convex hull of ``samples`` points.

    Parameters
    ----------
    text : str
        R(α) as an expression in ``t``.
    params : dict, optional
        Values of the expression's parameters.
    samples : int
        Nodes on [0, 2π), at least 16.
    com : (float, float), optional
        Centre of mass in the coordinates of the curve (default: the pole).

    Returns
    -------
    (Outline, str)
    """
    from ..wall import Wall

    samples = check_count("samples", samples, minimum=16)
    radius = Wall.from_expression(text, params or {})
    alpha = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    r, r1, r2 = radius.derivatives(alpha)
    if np.min(r) <= 0:
        k = int(np.argmin(r))
        raise InvalidOutline(f"polar outline {text!r}: R(α) must be positive, got R = {r[k]:.6g} "
                             f"at α = {alpha[k]:.6g}")
    c, s = np.cos(alpha), np.sin(alpha)
    points = np.column_stack([r * c, r * s])
    convex_curve = np.min(r * r + 2 * r1 * r1 - r * r2) >= 0 and not radius.kinks
    if convex_curve and com is None:
        tangent = np.column_stack([r1 * c - r * s, r1 * s + r * c])
        step = np.full(samples, TWO_PI / samples)
        return Outline.from_hermite(points, tangent, tangent, step), \
            f"polar R(α) = {text}: convex, exact-derivative Bézier outline on {samples} nodes; pole = centre of mass"
    outline, note = _finish(f"polar:{text}", Drawing([points], [], {"com": (0.0, 0.0)},
                                                     f"polar R(α) = {text} on {samples} points"), com, None)
    return outline, note.replace("centre of mass as recorded in the file", "pole = centre of mass") \
        .replace("; drawing units taken as units of kappa", "")
