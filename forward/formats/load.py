"""The library's entry points for bodies: ``load_outline(path)`` and ``outline_from_polar(text)``.

Every reader ends in the same place: a closed convex :class:`Outline` in units of κ with the centre of
mass at the origin, and a note saying what was done.

* **Convex hull.**  Non-convex outlines are replaced by their convex hull (the paper's rule: concave
  parts never touch a wall); the note says so.
* **Centre of mass.**  In this order: ``com=(x, y)`` given by the caller; the centre of mass recorded
  in a file written by coinwall (the JSON/CSV of ``solve``, the centre-of-mass mark of its SVG, the
  POINT on its DXF's centre-of-mass layer); otherwise the centroid of the drawn shape (uniform
  density).  A polar expression R(α) is measured from the centre of mass, like the paper's R(α).
* **Drawing coordinates.**  ``com`` and the points the notes print are in the file's own coordinates,
  as written, before any unit conversion: SVG user units with y pointing *down* (the coordinates of
  the viewBox, under a root ``transform`` if there is one; see :mod:`.svg`), DXF drawing units with y
  up, the x, y of a JSON/CSV file of points, the coordinates of a polar curve.  The readers turn the
  body to the mathematical orientation (an SVG is flipped so that y points up); ``com`` is mapped the
  same way (``recorded["frame"]``), so it names the same point of the drawing.
* **Scale (one rule).**  ``kappa`` is a length in ``units``; ``units`` defaults to the drawing's own
  unit (SVG ``width``/``height`` over its ``viewBox``, DXF ``$INSUNITS``).  Coordinates are converted
  from the drawing's unit to ``units`` and divided by ``kappa``; a drawing that records no unit is
  taken to be in ``units`` (and without ``units``, ``kappa`` is in its coordinates).  Without
  ``kappa``: the scale recorded by coinwall's own SVG/DXF export, else drawing units are taken as
  units of κ.
* **Which shapes.**  ``element`` (SVG id) or ``layer`` (DXF) picks one shape.  A page-sized background
  rectangle (SVG: a rectangle covering at least ``PAGE_FRACTION`` of the page; DXF: a rectangle
  enclosing every other shape) is left out with a note, and is an error if it is the only shape.
  Shapes lying inside the largest one do not change the hull and are noted; several shapes that
  each add to the hull are merged into it with a warning (:func:`read_outline` returns warnings).
* **Curves** are flattened with a chord error below :data:`~.geometry.FLATNESS` times the size of the
  shape (see :mod:`.geometry`).
"""

from __future__ import annotations

import math
import os
from typing import NamedTuple

import numpy as np

from ..angles import TWO_PI
from ..errors import CoinwallError, InvalidArgument, InvalidOutline
from ..outline import Outline
from ..validation import check_choice, check_count, check_positive
from .bodyjson import read_body_json
from .dxf import read_dxf
from .geometry import (
    FLATNESS,
    MAX_COORDINATE,
    MIN_SIZE,
    UNIT_LENGTHS,
    Drawing,
    convex_hull,
    is_rectangle,
    polygon_area_centroid,
    shapes_area_centroid,
)
from .inputfile import check_regular
from .points import read_points_csv
from .svg import read_svg

__all__ = [
    "OUTLINE_FORMATS",
    "PAGE_FRACTION",
    "OutlineReading",
    "check_com",
    "load_outline",
    "outline_from_polar",
    "read_outline",
]

#: file extensions load_outline reads
OUTLINE_FORMATS = (".json", ".csv", ".svg", ".dxf")
_NON_CONVEX = 1e-7  # relative area excess of the hull that counts as "not convex"
#: an SVG rectangle covering at least this fraction of the page is a background, not the body
PAGE_FRACTION = 0.9
_ADDS_TO_HULL = 1e-6  # relative area a shape must add to the largest shape's hull to count as merged
_COM_OUTSIDE = 1e-9  # a centre of mass this far outside the hull (relative to its size) is on its boundary


class OutlineReading(NamedTuple):
    """What :func:`read_outline` read.

    Attributes
    ----------
    outline : Outline
        Convex, in units of κ, centre of mass at the origin.
    note : str
        What was done (shapes read, hull, centre of mass, scale).
    warnings : list of str
        Choices the caller should know about: several shapes merged into one hull.
    accuracy : float
        How far the outline's support function may be from the drawing's (units of κ): the chord error of
        flattened curves (``FLATNESS`` times the size); 0 for an outline taken as it is written.
    """

    outline: Outline
    note: str
    warnings: list
    accuracy: float = 0.0


def check_com(com) -> np.ndarray:
    """``com`` as a finite point ``(x, y)`` (a float array of shape (2,))."""
    try:
        centre = np.asarray(com, dtype=float).reshape(2)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`com` must be two numbers (x, y), got {com!r}") from None
    if not np.all(np.isfinite(centre)):
        raise InvalidArgument(f"`com` must be finite, got {com!r}")
    return centre


def _hull_area(points):
    hull, _ = convex_hull(points)
    return polygon_area_centroid(hull)[0] if len(hull) > 2 else 0.0


def _inside_convex(polygon, points, tolerance=1e-9):
    """Whether every point lies in the convex polygon (within ``tolerance`` times its size)."""
    edges = np.roll(polygon, -1, axis=0) - polygon
    orientation = np.sign(_signed_area(polygon)) or 1.0
    rel = np.asarray(points, float)[:, None, :] - polygon[None, :, :]
    cross = orientation * (edges[None, :, 0] * rel[..., 1] - edges[None, :, 1] * rel[..., 0])
    size = float(np.ptp(polygon, axis=0).max())
    return bool(np.all(cross >= -tolerance * size * np.hypot(*edges.T)[None, :]))


def _signed_area(pts):
    """Signed area of a polygon (positive counter-clockwise)."""
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _background(path, shapes, loose, recorded, notes):
    """Drop a page-sized background rectangle from ``shapes`` (noted); an error if it is the only shape."""
    page = recorded.get("page")
    for k, shape in enumerate(shapes):
        if not is_rectangle(shape):
            continue
        area = polygon_area_centroid(shape)[0]
        others = [s for j, s in enumerate(shapes) if j != k] + list(loose)
        if page is not None:  # SVG: a rectangle covering the page
            if area < PAGE_FRACTION * page:
                continue
            if not others:
                raise InvalidOutline(f"body file {path!r}: the only shape is a rectangle covering "
                                     f"{area / page:.0%} of the page, a background, not a body; draw the body, "
                                     "or pick the rectangle with `element` if it is the body")
            notes.append(f"a background rectangle covering {area / page:.0%} of the page left out")
        else:  # DXF: a rectangle enclosing every other shape
            if not others:
                continue
            if not all(_inside_convex(shape, o) for o in others):
                continue
            notes.append("a rectangle enclosing every other shape (a frame) left out; pick it with `layer` if it "
                         "is the body")
        return [s for j, s in enumerate(shapes) if j != k]
    return shapes


def _merged(shapes, loose, notes, warnings, choose):
    """Note shapes inside the largest one; warn when several shapes each add to the hull."""
    parts = [np.asarray(s, float) for s in list(shapes) + list(loose) if len(s)]
    if len(parts) < 2:
        return
    areas = [_hull_area(p) if len(p) > 2 else 0.0 for p in parts]
    largest = int(np.argmax(areas))
    base = areas[largest]
    adding = [k for k, p in enumerate(parts) if k != largest
              and _hull_area(np.vstack([parts[largest], p])) > base * (1 + _ADDS_TO_HULL)]
    inside = len(parts) - 1 - len(adding)
    if adding:
        warnings.append(f"{len(adding) + 1} shapes merged into one convex hull (the wall is that of the hull); "
                        f"pick one with {choose}")
    if inside:
        notes.append(f"{inside} shape{'s' if inside != 1 else ''} inside the largest one (no effect on the hull)")


def _to_frame(frame, point):
    """A point in drawing coordinates (as written in the file) in the reader's frame (``recorded["frame"]``)."""
    point = np.asarray(point, float).reshape(2)
    if frame is None:
        return point
    frame = np.asarray(frame, float)
    with np.errstate(over="ignore", invalid="ignore"):  # a huge point lands at inf: outside, refused as such
        return frame[:2, :2] @ point + frame[:2, 2]


def _from_frame(frame, point):
    """A point in the reader's frame in drawing coordinates (the inverse of :func:`_to_frame`)."""
    point = np.asarray(point, float).reshape(2)
    if frame is None:
        return point
    frame = np.asarray(frame, float)
    return np.linalg.solve(frame[:2, :2], point - frame[:2, 2])


def _check_inside(path, hull, hull_area, centre, given, shown=None):
    """Refuse a centre of mass outside the body: the centre of mass of any mass distribution lies in the
    convex hull of the body (on its boundary at most, within ``_COM_OUTSIDE`` of its size).  The message
    gives the point as ``shown`` (in drawing coordinates), else as ``centre``."""
    if hull_area <= 0 or (np.all(np.isfinite(centre))
                          and _inside_convex(hull, centre[None, :], tolerance=_COM_OUTSIDE)):
        return
    shown = centre if shown is None else shown
    where = f"({shown[0]:.6g}, {shown[1]:.6g})"
    if given:
        raise InvalidArgument(f"`com` {where} lies outside the body of {path!r}; the centre of mass of a body lies "
                              "inside its outline")
    raise InvalidOutline(f"body file {path!r} records a centre of mass at {where}, outside the body; the centre of "
                         "mass of a body lies inside its outline")


def _scale(path, recorded, kappa, units, notes):
    """Drawing coordinates per unit κ, by the module's one rule (see the module docstring)."""
    drawing_unit = recorded.get("unit")
    if kappa is None:
        if recorded.get("kappa") is not None:
            value = recorded["kappa"]
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InvalidOutline(f"body file {path!r} records kappa = {value!r}; it must be a positive finite "
                                     "number (pass --kappa to override)")
            notes.append(f"kappa = {float(recorded['kappa']):g} {recorded.get('units', '')} as recorded in the file"
                         .replace("  ", " "))
            return float(recorded["kappa"])
        notes.append("drawing units taken as units of kappa")
        return 1.0
    kappa = float(kappa)
    if drawing_unit is None:
        notes.append(f"kappa = {kappa:g} {units or 'drawing units'}"
                     + (f"; the drawing records no unit: coordinates taken as {units}" if units else ""))
        return kappa
    name, millimetres = drawing_unit
    units = units or name
    coordinate = millimetres / UNIT_LENGTHS[units]  # one drawing coordinate in `units`
    notes.append(f"kappa = {kappa:g} {units}; drawing unit {name}, one coordinate = {coordinate:.6g} {units}")
    return kappa / coordinate


def _finish(path, drawing: Drawing, com, kappa, units=None, choose="`element` (SVG) or `layer` (DXF)"):
    """Background, hull, centre of mass, scale → OutlineReading."""
    shapes, loose, recorded, what = drawing
    notes, warnings = [what], []
    shapes = _background(path, list(shapes), list(loose), recorded, notes)
    _merged(shapes, loose, notes, warnings, choose)
    everything = [np.asarray(s, float) for s in shapes + list(loose) if len(s)]
    if not everything:
        raise InvalidOutline(f"body file {path!r}: no outline found ({what})")
    points = np.vstack(everything)
    if not np.all(np.isfinite(points)):
        raise InvalidOutline(f"body file {path!r}: outline coordinates are not finite")
    hull, _ = convex_hull(points)
    hull_area = polygon_area_centroid(hull)[0] if len(hull) > 2 else 0.0
    try:
        drawn = shapes_area_centroid(shapes) if shapes else None
    except InvalidOutline as exc:
        raise InvalidOutline(f"body file {path!r}: {exc}") from None
    if drawn is not None and hull_area > 0 and (hull_area - drawn[0]) > _NON_CONVEX * hull_area:
        notes.append(f"non-convex outline replaced by its convex hull (area {drawn[0]:.6g} -> {hull_area:.6g})")
    elif drawn is None and loose:
        notes.append("outline = convex hull of all entities")
    frame = recorded.get("frame")  # drawing coordinates -> the shapes' coordinates (SVG: y flipped)
    if com is not None:
        shown = check_com(com)
        centre = _to_frame(frame, shown)
        notes.append(f"centre of mass given at ({shown[0]:.6g}, {shown[1]:.6g})")
    elif recorded.get("com") is not None:
        centre = np.asarray(recorded["com"], float)
        shown = _from_frame(frame, centre)
        notes.append("centre of mass as recorded in the file")
    else:
        if drawn is not None:
            centre = drawn[1]
        elif hull_area > 0:
            centre = polygon_area_centroid(hull)[1]
        else:
            centre = hull.mean(axis=0)
        shown = _from_frame(frame, centre)  # in the coordinates `com` takes
        notes.append(f"centre of mass = centroid ({shown[0]:.6g}, {shown[1]:.6g}), uniform density")
    _check_inside(path, hull, hull_area, centre, com is not None, shown)
    scale = _scale(path, recorded, kappa, units, notes)
    size = float(np.ptp(hull, axis=0).max()) / scale
    if not MIN_SIZE <= size <= MAX_COORDINATE:
        error = InvalidArgument if kappa is not None else InvalidOutline
        raise error(f"body file {path!r}: the body measures {size:.3g} radii of gyration across"
                    f"{' with this `kappa`' if kappa is not None else ''}; coinwall reads bodies from {MIN_SIZE:g} to "
                    f"{MAX_COORDINATE:g} across")
    # the drawing readers flatten curves to a chord error below FLATNESS times the size of the shape (a drawing of
    # straight lines only gets the same bound: its support function is exact to it too)
    accuracy = FLATNESS * size if str(path).lower().endswith((".svg", ".dxf")) else 0.0
    return OutlineReading(Outline.from_polygon((hull - centre) / scale), "; ".join(notes), warnings, accuracy)


def read_outline(path: str, *, layer: str | None = None, element: str | None = None, com=None,
                 kappa: float | None = None, units: str | None = None) -> OutlineReading:
    """Outline from a file, in units of κ with the centre of mass at the origin, with notes and warnings.

    Parameters
    ----------
    path : str
        ``.json`` (from ``coinwall solve``, or ``{"outline"|"points": [[x, y], ...]}``),
        ``.csv`` (x, y columns; a header row is skipped), ``.svg`` (closed paths,
        polygons, rects, circles, ellipses) or ``.dxf`` (LWPOLYLINE, POLYLINE, SPLINE,
        CIRCLE, ELLIPSE, and closed chains of LINE and ARC).
    layer : str, optional
        DXF layer to read (default: every layer but annotation layers).
    element : str, optional
        SVG: the id of the element to read (default: the whole drawing).
    com : (float, float), optional
        Centre of mass in drawing coordinates, as written in the file and in its own units (SVG: user
        units, y pointing down; DXF, JSON, CSV: y up); default: recorded by coinwall, else the centroid.
    kappa : float, optional
        Radius of gyration in ``units`` (default: recorded by coinwall, else 1 drawing unit).
    units : str, optional
        Unit of ``kappa``, one of :data:`~.geometry.UNIT_LENGTHS` (default: the drawing's own unit).
        Needs ``kappa``.

    Returns
    -------
    OutlineReading
        The convex outline, a note saying what was done, and warnings (several shapes merged).

    Raises
    ------
    InvalidOutline
        Missing, empty, damaged or unsupported files; no closed shape; nothing on the layer or in the
        element; an open LINE/ARC chain; a background rectangle as the only shape.
    InvalidArgument
        A bad ``com``, ``kappa``, ``units``, ``layer`` or ``element``.
    """
    if not isinstance(path, str):
        raise InvalidOutline(f"body file must be a file name, got {path!r}")
    ext = os.path.splitext(path)[1].lower()
    if ext not in OUTLINE_FORMATS:
        raise InvalidOutline(f"body file {path!r}: unsupported extension {ext or '(none)'!r}; "
                             f"use {', '.join(OUTLINE_FORMATS)}")
    if layer is not None and ext != ".dxf":
        raise InvalidArgument(f"`layer` applies to DXF files, not to {path!r}")
    if layer is not None and not isinstance(layer, str):
        raise InvalidArgument(f"`layer` must be a layer name (a string), got {layer!r}")
    if element is not None and ext != ".svg":
        raise InvalidArgument(f"`element` applies to SVG files, not to {path!r}")
    # the arguments are checked before the file is read: their errors are the caller's, not the file's
    if com is not None:
        check_com(com)
    if kappa is not None:
        check_positive("kappa", kappa)
    if units is not None:
        check_choice("units", units, tuple(UNIT_LENGTHS))
        if kappa is None:
            raise InvalidArgument(f"`units` {units} needs `kappa` (the radius of gyration in {units})")
    # a FIFO, a device or a folder is refused here, before any reader opens it; each reader reads through
    # inputfile, which checks again on the open descriptor
    if check_regular(path, what="body file", error=InvalidOutline) == 0:
        raise InvalidOutline(f"body file {path!r} is empty")
    try:
        if ext == ".svg":
            return _finish(path, read_svg(path, element), com, kappa, units, "`element` (an SVG id)")
        if ext == ".dxf":
            return _finish(path, read_dxf(path, layer), com, kappa, units, "`layer`")
        if ext == ".json":
            points, controls, recorded, what = read_body_json(path)
            if controls is not None and com is None and kappa is None:
                # the hull of nodes and control points holds the curve: lenient, never refuses a valid body
                both = np.vstack([points, controls.reshape(-1, 2)])
                hull, _ = convex_hull(both)
                _check_inside(path, hull, polygon_area_centroid(hull)[0] if len(hull) > 2 else 0.0, np.zeros(2),
                              False)
                return OutlineReading(Outline(points, controls),
                                      "exact Bézier outline (coinwall JSON, units of kappa)", [])
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
    return _finish(path, Drawing(closed, [] if closed else [points], recorded, what), com, kappa, units)


def load_outline(path: str, *, layer: str | None = None, com=None, kappa: float | None = None,
                 units: str | None = None, element: str | None = None):
    """Outline from a file, in units of κ with the centre of mass at the origin, and a note.

    The same as :func:`read_outline`, with its warnings appended to the note. Concave parts of a drawing
    never touch a wall: the outline is the convex hull.

    Parameters
    ----------
    path : str
        ``.json`` (from ``coinwall solve``, or ``{"outline"|"points": [[x, y], ...]}``), ``.csv`` (x, y
        columns; a header row is skipped), ``.svg`` (closed paths, polygons, rects, circles, ellipses) or
        ``.dxf`` (LWPOLYLINE, POLYLINE, SPLINE, CIRCLE, ELLIPSE, and closed chains of LINE and ARC).
    layer : str, optional
        DXF layer to read (default: every layer but annotation layers).
    com : (float, float), optional
        Centre of mass in drawing coordinates, as written in the file and in its own units (SVG: user
        units, y pointing down; DXF, JSON, CSV: y up); default: recorded by coinwall, else the centroid.
    kappa : float, optional
        Radius of gyration in ``units`` (default: recorded by coinwall, else 1 drawing unit).
    units : str, optional
        Unit of ``kappa`` (``"mm"``, ``"cm"``, ``"in"``, ...; default: the drawing's own unit). Needs
        ``kappa``.
    element : str, optional
        SVG: the id of the element to read (default: the whole drawing).

    Returns
    -------
    (Outline, str)
        The convex outline and a note saying what was done.

    Raises
    ------
    InvalidOutline
        Missing, empty, damaged or unsupported files; no closed shape; nothing on the layer or in the
        element.
    InvalidArgument
        A bad ``com``, ``kappa``, ``units``, ``layer`` or ``element``.

    Examples
    --------
    A triangle drawn with a radius of gyration of 2 drawing units, moved to its centroid and scaled to κ:

    >>> from coinwall import load_outline
    >>> with open("triangle.csv", "w") as fh:
    ...     _ = fh.write("x,y\\n3,0\\n0,3\\n-3,-3\\n")
    >>> outline, note = load_outline("triangle.csv", kappa=2.0)
    >>> outline
    Outline(3 segments, area=3.375, perimeter=8.82952)
    >>> note
    'CSV points; centre of mass = centroid (-0, -0), uniform density; kappa = 2 drawing units'
    """
    reading = read_outline(path, layer=layer, element=element, com=com, kappa=kappa, units=units)
    note = "; ".join([reading.note] + [f"warning: {w}" for w in reading.warnings])
    return reading.outline, note


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

    Raises
    ------
    InvalidOutline
        Where R(α) is not positive.
    InvalidExpression, InvalidParameter
        For an expression that does not parse or a bad parameter.

    Examples
    --------
    >>> from coinwall import outline_from_polar
    >>> outline, note = outline_from_polar("1 + 0.2*cos(t)", samples=256)
    >>> outline.nodes.shape, note
    ((256, 2), 'polar R(α) = 1 + 0.2*cos(t): convex, exact-derivative Bézier outline on 256 nodes; pole = centre of mass')
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
    outline, note, *_ = _finish(f"polar:{text}", Drawing([points], [], {"com": (0.0, 0.0)},
                                                        f"polar R(α) = {text} on {samples} points"), com, None)
    return outline, note.replace("centre of mass as recorded in the file", "pole = centre of mass") \
        .replace("; drawing units taken as units of kappa", "")
