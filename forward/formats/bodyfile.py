"""Reading a body outline: coinwall JSON/CSV, SVG and DXF drawings, point lists, a polar R(α).

Every reader ends in the same place: a closed convex :class:`Outline` in
units of κ with the centre of mass at the origin, and a note saying what
was done.

* **Convex hull.**  Non-convex outlines are replaced by their convex hull
  (the paper's rule: concave parts never touch a wall); the note says so.
* **Centre of mass.**  In this order: ``com=(x, y)`` given by the caller;
  the centre of mass recorded in a file written by coinwall (the JSON/CSV
  of ``solve``, the ``centre-of-mass`` mark of its SVG, the POINT on layer
  ``CENTRE_OF_MASS`` of its DXF); otherwise the centroid of the drawn
  shape (uniform density).  A polar expression R(α) is measured from the
  centre of mass, like the paper's R(α).
* **Scale.**  Coordinates are divided by ``kappa`` (the radius of gyration
  in drawing units) when given, else by the scale recorded by coinwall's
  own SVG/DXF export, else drawing units are taken as units of κ.
* **Curves** (SVG Béziers and arcs, DXF splines, arcs, ellipses, bulges)
  are flattened with a chord error below ``FLATNESS`` times the size of
  the shape, so the support function, hence the wall, is exact to that
  relative accuracy.
"""

from __future__ import annotations

import json
import math
import os
import re

import numpy as np

from ..errors import InvalidArgument, InvalidOutline
from ..outline import Outline

__all__ = ["load_outline", "outline_from_polar", "wall_functions", "FLATNESS", "OUTLINE_FORMATS",
           "DXF_ENTITIES"]

#: chord error of flattened curves, relative to the size of the shape
FLATNESS = 1e-8
#: file extensions load_outline reads
OUTLINE_FORMATS = (".json", ".csv", ".svg", ".dxf")
#: DXF entity types read as outline
DXF_ENTITIES = ("LWPOLYLINE", "POLYLINE", "SPLINE", "CIRCLE", "ELLIPSE", "ARC")
_NON_CONVEX = 1e-7  # relative area excess of the hull that counts as "not convex"
_MAX_POINTS_PER_CURVE = 200_000


# ---------------------------------------------------------------------------- geometry helpers
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


def _polygon_area_centroid(pts):
    x, y = pts[:, 0], pts[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    if abs(area) < 1e-300:
        return 0.0, pts.mean(axis=0)
    cx = ((x + xn) * cross).sum() / (6 * area)
    cy = ((y + yn) * cross).sum() / (6 * area)
    return abs(area), np.array([cx, cy])


def _shapes_area_centroid(shapes):
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


def _finish(path, shapes, loose, com, kappa, recorded, what):
    """Hull, centre of mass, scale → (Outline, note)."""
    everything = [np.asarray(s, float) for s in shapes + loose if len(s)]
    if not everything:
        raise InvalidOutline(f"body file {path!r}: no outline found ({what})")
    points = np.vstack(everything)
    if not np.all(np.isfinite(points)):
        raise InvalidOutline(f"body file {path!r}: outline coordinates are not finite")
    notes = [what]
    hull, _ = _convex(points)
    hull_area = _polygon_area_centroid(hull)[0] if len(hull) > 2 else 0.0
    drawn = _shapes_area_centroid(shapes) if shapes else None
    if drawn is not None and hull_area > 0 and (hull_area - drawn[0]) > _NON_CONVEX * hull_area:
        notes.append(f"non-convex outline replaced by its convex hull (area {drawn[0]:.6g} -> {hull_area:.6g})")
    elif drawn is None and loose:
        notes.append("outline = convex hull of all entities")
    if com is not None:
        centre = _check_com(com)
        notes.append(f"centre of mass given at ({centre[0]:.6g}, {centre[1]:.6g})")
    elif recorded.get("com") is not None:
        centre = np.asarray(recorded["com"], float)
        notes.append("centre of mass as recorded in the file")
    else:
        if drawn is not None:
            centre = drawn[1]
        elif hull_area > 0:
            centre = _polygon_area_centroid(hull)[1]
        else:
            centre = hull.mean(axis=0)
        notes.append(f"centre of mass = centroid ({centre[0]:.6g}, {centre[1]:.6g}), uniform density")
    if kappa is not None:
        scale = _check_kappa(kappa)
        notes.append(f"kappa = {scale:g} drawing units")
    elif recorded.get("kappa") is not None:
        scale = float(recorded["kappa"])
        notes.append(f"kappa = {scale:g} {recorded.get('units', '')} as recorded in the file".replace("  ", " "))
    else:
        scale = 1.0
        notes.append("drawing units taken as units of kappa")
    return Outline.from_polygon((hull - centre) / scale), "; ".join(notes)


def _check_com(com):
    try:
        centre = np.asarray(com, dtype=float).reshape(2)
    except (TypeError, ValueError):
        raise InvalidArgument(f"--com must be two numbers X,Y, got {com!r}") from None
    if not np.all(np.isfinite(centre)):
        raise InvalidArgument(f"--com must be finite, got {com!r}")
    return centre


def _check_kappa(kappa):
    if not isinstance(kappa, (int, float)) or not math.isfinite(kappa) or kappa <= 0:
        raise InvalidArgument(f"--kappa must be a positive finite length, got {kappa!r}")
    return float(kappa)


def _steps_for_curvature(second_difference_bound, size):
    """Uniform steps of a polynomial curve so the chord error ≤ FLATNESS·size (error ≤ M Δ²/8)."""
    if size <= 0 or second_difference_bound <= 0:
        return 1
    n = math.ceil(math.sqrt(second_difference_bound / (8 * FLATNESS * size)))
    return int(min(max(n, 1), _MAX_POINTS_PER_CURVE))


def _cubic_points(p0, p1, p2, p3, size):
    m2 = 6 * max(np.hypot(*(p2 - 2 * p1 + p0)), np.hypot(*(p3 - 2 * p2 + p1)))
    s = np.linspace(0, 1, _steps_for_curvature(m2, size) + 1)[1:, None]
    u = 1 - s
    return u**3 * p0 + 3 * u * u * s * p1 + 3 * u * s * s * p2 + s**3 * p3


def _ellipse_points(centre, rx, ry, rotation, start, sweep, size):
    """Points of an elliptical arc (angles in radians), end point included, start excluded."""
    r = max(abs(rx), abs(ry))
    if r <= 0:
        return np.empty((0, 2))
    n = _steps_for_curvature(r * abs(sweep) ** 2, size)
    t = start + sweep * np.linspace(0, 1, n + 1)[1:]
    c, s = math.cos(rotation), math.sin(rotation)
    x, y = rx * np.cos(t), ry * np.sin(t)
    return np.column_stack([centre[0] + c * x - s * y, centre[1] + s * x + c * y])


# ---------------------------------------------------------------------------- SVG
_SVG_SKIP = {"defs", "clipPath", "mask", "symbol", "marker", "pattern", "metadata", "title", "desc", "style"}
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_TRANSFORM = re.compile(r"(matrix|translate|scale|rotate|skewX|skewY)\s*\(([^)]*)\)")


def _numbers(text):
    return [float(v) for v in re.findall(_NUMBER, text or "")]


def _svg_transform(text):
    """3×3 matrix of an SVG ``transform`` attribute."""
    total = np.eye(3)
    for name, args in _TRANSFORM.findall(text or ""):
        v = _numbers(args)
        m = np.eye(3)
        try:
            if name == "matrix":
                m[:2, :] = np.array(v[:6]).reshape(3, 2).T
            elif name == "translate":
                m[0, 2], m[1, 2] = v[0], (v[1] if len(v) > 1 else 0.0)
            elif name == "scale":
                m[0, 0], m[1, 1] = v[0], (v[1] if len(v) > 1 else v[0])
            elif name == "rotate":
                a = math.radians(v[0])
                rot = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
                if len(v) >= 3:
                    shift, back = np.eye(3), np.eye(3)
                    shift[:2, 2], back[:2, 2] = v[1:3], [-v[1], -v[2]]
                    rot = shift @ rot @ back
                m = rot
            elif name == "skewX":
                m[0, 1] = math.tan(math.radians(v[0]))
            else:
                m[1, 0] = math.tan(math.radians(v[0]))
        except (IndexError, ValueError):
            raise InvalidOutline(f"SVG transform {text!r} is malformed") from None
        total = total @ m
    return total


class _PathScanner:
    """Tokens of SVG path data; arc flags may be written without separators ("a1 1 0 01.5.5")."""

    def __init__(self, text):
        self.text, self.pos = text, 0

    def _skip(self):
        while self.pos < len(self.text) and self.text[self.pos] in " \t\r\n,":
            self.pos += 1

    def command(self):
        self._skip()
        if self.pos < len(self.text) and self.text[self.pos].isalpha():
            self.pos += 1
            return self.text[self.pos - 1]
        return None

    def at_number(self):
        self._skip()
        return self.pos < len(self.text) and (self.text[self.pos] in "+-." or self.text[self.pos].isdigit())

    def number(self):
        self._skip()
        m = re.compile(_NUMBER).match(self.text, self.pos)
        if not m:
            raise InvalidOutline(f"SVG path data is malformed near {self.text[self.pos:self.pos + 20]!r}")
        self.pos = m.end()
        return float(m.group())

    def flag(self):
        self._skip()
        if self.pos < len(self.text) and self.text[self.pos] in "01":
            self.pos += 1
            return self.text[self.pos - 1] == "1"
        raise InvalidOutline(f"SVG path data: arc flag expected near {self.text[self.pos:self.pos + 20]!r}")


def _arc_points(p0, rx, ry, phi_deg, large, sweep, p1, size):
    """SVG elliptical arc (endpoint parametrisation, SVG 1.1 implementation notes F.6.5)."""
    if np.allclose(p0, p1):
        return np.empty((0, 2))
    rx, ry = abs(rx), abs(ry)
    if rx == 0 or ry == 0:
        return p1[None, :]
    phi = math.radians(phi_deg % 360)
    c, s = math.cos(phi), math.sin(phi)
    dx, dy = (p0 - p1) / 2
    x1, y1 = c * dx + s * dy, -s * dx + c * dy
    lam = x1 * x1 / (rx * rx) + y1 * y1 / (ry * ry)
    if lam > 1:
        rx, ry = rx * math.sqrt(lam), ry * math.sqrt(lam)
    num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1
    den = rx * rx * y1 * y1 + ry * ry * x1 * x1
    coef = math.sqrt(max(num / den, 0.0)) * (-1 if large == sweep else 1)
    cxp, cyp = coef * rx * y1 / ry, -coef * ry * x1 / rx
    centre = np.array([c * cxp - s * cyp, s * cxp + c * cyp]) + (p0 + p1) / 2
    t1 = math.atan2((y1 - cyp) / ry, (x1 - cxp) / rx)
    t2 = math.atan2((-y1 - cyp) / ry, (-x1 - cxp) / rx)
    dt = (t2 - t1) % (2 * math.pi)
    if not sweep and dt > 0:
        dt -= 2 * math.pi
    return _ellipse_points(centre, rx, ry, phi, t1, dt, size)


def _svg_path(d):
    """Subpaths of SVG path data as (points, closed) pairs."""
    scan = _PathScanner(d or "")
    subpaths, current, start, pos = [], [], np.zeros(2), np.zeros(2)
    last_ctrl, last_cmd, cmd = None, "", None
    size_guess = max(1e-300, max((abs(v) for v in _numbers(d)), default=1.0))

    def close_subpath(closed):
        if len(current) > 1:
            subpaths.append((np.array(current), closed))

    while True:
        new = scan.command()
        if new is None:
            if not scan.at_number():
                if scan.pos < len(scan.text.strip()) and scan.text[scan.pos:].strip():
                    raise InvalidOutline(f"SVG path data is malformed near {scan.text[scan.pos:scan.pos + 20]!r}")
                break
            if cmd is None:
                raise InvalidOutline("SVG path data must start with a moveto command")
            new = {"M": "L", "m": "l"}.get(cmd, cmd)
        cmd = new
        rel = cmd.islower()
        up = cmd.upper()
        if up not in "MLHVCSQTAZ":
            raise InvalidOutline(f"SVG path data: unknown command {cmd!r}")
        base = pos if rel else np.zeros(2)
        if up == "Z":
            close_subpath(True)
            current, pos = [], start.copy()
            last_ctrl, last_cmd = None, "Z"
            continue
        if up == "M":
            close_subpath(False)
            pos = base + [scan.number(), scan.number()]
            start, current = pos.copy(), [pos.copy()]
            last_ctrl, last_cmd = None, "M"
            continue
        if not current:
            current = [pos.copy()]
            start = pos.copy()
        if up == "L":
            pos = base + [scan.number(), scan.number()]
            current.append(pos.copy())
            last_ctrl = None
        elif up == "H":
            pos = np.array([(pos[0] if rel else 0.0) + scan.number(), pos[1]])
            current.append(pos.copy())
            last_ctrl = None
        elif up == "V":
            pos = np.array([pos[0], (pos[1] if rel else 0.0) + scan.number()])
            current.append(pos.copy())
            last_ctrl = None
        elif up in "CS":
            if up == "C":
                c1 = base + [scan.number(), scan.number()]
            else:
                c1 = 2 * pos - last_ctrl if last_ctrl is not None and last_cmd in "CS" else pos.copy()
            c2 = base + [scan.number(), scan.number()]
            end = base + [scan.number(), scan.number()]
            current.extend(_cubic_points(pos, c1, c2, end, size_guess))
            pos, last_ctrl = end, c2
        elif up in "QT":
            if up == "Q":
                q = base + [scan.number(), scan.number()]
            else:
                q = 2 * pos - last_ctrl if last_ctrl is not None and last_cmd in "QT" else pos.copy()
            end = base + [scan.number(), scan.number()]
            current.extend(_cubic_points(pos, pos + 2 * (q - pos) / 3, end + 2 * (q - end) / 3, end, size_guess))
            pos, last_ctrl = end, q
        else:
            rx, ry, rot = scan.number(), scan.number(), scan.number()
            large, sweep = scan.flag(), scan.flag()
            end = base + [scan.number(), scan.number()]
            current.extend(_arc_points(pos, rx, ry, rot, large, sweep, end, size_guess))
            pos, last_ctrl = end, None
        last_cmd = up
    close_subpath(False)
    out = []
    for pts, closed in subpaths:
        span = float(np.ptp(pts, axis=0).max()) if len(pts) else 0.0
        if not closed and len(pts) > 2 and np.hypot(*(pts[0] - pts[-1])) <= 1e-9 * max(span, 1e-300):
            closed = True
        out.append((pts, closed))
    return out


def _length(value, default=0.0):
    vals = _numbers(value) if value is not None else []
    return vals[0] if vals else default


def _read_svg(path):
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise InvalidOutline(f"body file {path!r} is not valid SVG (XML error: {exc})") from None
    if root.tag.rsplit("}", 1)[-1] != "svg":
        raise InvalidOutline(f"body file {path!r}: the root element is <{root.tag.rsplit('}', 1)[-1]}>, not <svg>")
    shapes, open_count, recorded = [], 0, {}
    kappa = root.get("data-coinwall-kappa")
    if kappa is not None and _numbers(kappa):
        recorded["kappa"] = _numbers(kappa)[0]
        recorded["units"] = root.get("data-coinwall-units", "")
    flip = np.diag([1.0, -1.0, 1.0])  # SVG y points down; the body frame's y points up

    def apply(matrix, pts):
        pts = np.asarray(pts, float).reshape(-1, 2)
        full = flip @ matrix
        return pts @ full[:2, :2].T + full[:2, 2]

    def visit(elem, matrix):
        nonlocal open_count
        tag = elem.tag.rsplit("}", 1)[-1]
        if tag in _SVG_SKIP:
            return
        matrix = matrix @ _svg_transform(elem.get("transform"))
        classes = (elem.get("class") or "").split()
        if "coinwall-annotation" in classes:
            if elem.get("id") == "centre-of-mass" and tag == "circle":
                recorded["com"] = apply(matrix, [_length(elem.get("cx")), _length(elem.get("cy"))])[0]
            return
        size = 1.0
        if tag == "path":
            for pts, closed in _svg_path(elem.get("d")):
                if closed:
                    shapes.append(apply(matrix, pts))
                else:
                    open_count += 1
        elif tag in ("polygon", "polyline"):
            v = _numbers(elem.get("points"))
            pts = np.array(v[: len(v) // 2 * 2]).reshape(-1, 2)
            closed = tag == "polygon" or (len(pts) > 2 and np.allclose(pts[0], pts[-1]))
            if len(pts) >= 3 and closed:
                shapes.append(apply(matrix, pts))
            elif len(pts):
                open_count += 1
        elif tag == "rect":
            x, y = _length(elem.get("x")), _length(elem.get("y"))
            w, h = _length(elem.get("width")), _length(elem.get("height"))
            if w > 0 and h > 0:  # rounded corners (rx, ry) are ignored: the hull differs by < rx
                shapes.append(apply(matrix, [[x, y], [x + w, y], [x + w, y + h], [x, y + h]]))
        elif tag in ("circle", "ellipse"):
            cx, cy = _length(elem.get("cx")), _length(elem.get("cy"))
            if tag == "circle":
                rx = ry = _length(elem.get("r"))
            else:
                rx, ry = _length(elem.get("rx")), _length(elem.get("ry"))
            size = max(rx, ry)
            if rx > 0 and ry > 0:
                shapes.append(apply(matrix, _ellipse_points((cx, cy), rx, ry, 0.0, 0.0, 2 * math.pi, size)))
        elif tag == "line":
            open_count += 1
        for child in elem:
            visit(child, matrix)

    visit(root, np.eye(3))
    if not shapes:
        extra = f" ({open_count} open shape{'s' if open_count != 1 else ''} ignored)" if open_count else ""
        raise InvalidOutline(f"body file {path!r}: the SVG has no closed shape (path ending in Z, polygon, "
                             f"rect, circle or ellipse){extra}")
    what = f"SVG: {len(shapes)} closed shape{'s' if len(shapes) != 1 else ''}"
    if open_count:
        what += f", {open_count} open shape{'s' if open_count != 1 else ''} ignored"
    return shapes, [], recorded, what


# ---------------------------------------------------------------------------- DXF
def _dxf_points(entity, sagitta):
    """Points along a DXF entity (curves flattened on the exact geometry) and its closed flag.

    ezdxf's own ``flattening`` evaluates arcs, ellipses and splines exactly
    (its Bézier path conversion would approximate arcs, to ~1e-4).
    """
    kind = entity.dxftype()
    if kind in ("CIRCLE", "ARC", "ELLIPSE", "SPLINE"):
        pts = [(v.x, v.y) for v in entity.flattening(sagitta)]
        return np.array(pts, float).reshape(-1, 2), kind in ("CIRCLE",) or (
            kind == "ELLIPSE" and abs(abs(entity.dxf.end_param - entity.dxf.start_param) - 2 * math.pi) < 1e-12)
    pts = []
    for piece in entity.virtual_entities():  # LINE and ARC pieces, bulges included
        if piece.dxftype() == "LINE":
            seg = [(piece.dxf.start.x, piece.dxf.start.y), (piece.dxf.end.x, piece.dxf.end.y)]
        elif piece.dxftype() == "ARC":
            seg = [(v.x, v.y) for v in piece.flattening(sagitta)]
        else:
            continue
        pts.extend(seg)
    return np.array(pts, float).reshape(-1, 2), bool(entity.closed if kind == "LWPOLYLINE" else entity.is_closed)


def _read_dxf(path, layer):
    import ezdxf
    from ezdxf import bbox

    try:
        doc = ezdxf.readfile(path)
    except IOError as exc:
        raise InvalidOutline(f"body file {path!r} is not readable: {exc}") from None
    except ezdxf.DXFError as exc:
        raise InvalidOutline(f"body file {path!r} is not a valid DXF file: {exc}") from None
    msp = doc.modelspace()
    candidates = [e for e in msp if e.dxftype() in DXF_ENTITIES]
    if layer is not None:
        chosen = [e for e in candidates if e.dxf.layer.lower() == layer.lower()]
        if not chosen:
            layers = sorted({e.dxf.layer for e in candidates})
            raise InvalidOutline(f"body file {path!r}: nothing to read on layer {layer!r} (need one of "
                                 f"{', '.join(DXF_ENTITIES)}); layers with outline entities: "
                                 f"{', '.join(layers) or 'none'}")
    else:
        chosen = candidates
    if not chosen:
        raise InvalidOutline(f"body file {path!r}: the DXF has no {', '.join(DXF_ENTITIES)} entity")
    shapes, loose = [], []
    for entity in chosen:
        try:
            box = bbox.extents([entity])
            size = max(box.size.x, box.size.y) if box.has_data else 1.0
            pts, flagged = _dxf_points(entity, max(FLATNESS * size, 1e-300))
        except (TypeError, ValueError, ZeroDivisionError, AttributeError) as exc:
            raise InvalidOutline(f"body file {path!r}: cannot read {entity.dxftype()} {entity.dxf.handle}: "
                                 f"{exc}") from None
        if len(pts) < 2:
            continue
        closed = flagged or np.hypot(*(pts[0] - pts[-1])) <= 1e-9 * max(size, 1e-300)
        (shapes if closed and len(pts) > 3 else loose).append(pts[:-1] if closed else pts)
    recorded = {}
    points = [e for e in msp.query("POINT") if e.dxf.layer.upper() == "CENTRE_OF_MASS"]
    if points:
        location = points[0].dxf.location
        recorded["com"] = np.array([location.x, location.y], float)
    try:
        meta = doc.ezdxf_metadata()
        if "coinwall_kappa" in meta:
            recorded["kappa"] = float(meta["coinwall_kappa"])
            recorded["units"] = meta.get("coinwall_units", "")
    except (KeyError, ValueError, TypeError, AttributeError):
        pass
    kinds = sorted({e.dxftype() for e in chosen})
    where = f"layer {layer!r}" if layer is not None else "all layers"
    return shapes, loose, recorded, f"DXF: {len(chosen)} entities ({', '.join(kinds)}) on {where}"


# ---------------------------------------------------------------------------- points and coinwall files
def _read_points_csv(path):
    with open(path, encoding="utf-8") as fh:
        first = fh.readline()
    coinwall = first.startswith("# coinwall body")
    data = np.genfromtxt(path, delimiter=",", comments="#", ndmin=2)
    data = data[~np.all(np.isnan(data), axis=1)]
    if data.size == 0 or data.shape[1] < 2:
        raise InvalidOutline(f"body file {path!r}: no x,y points")
    points = data[:, :2]
    return points, coinwall


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
    """
    if not isinstance(path, str) or not os.path.isfile(path):
        raise InvalidOutline(f"body file {path!r} does not exist")
    ext = os.path.splitext(path)[1].lower()
    if ext not in OUTLINE_FORMATS:
        raise InvalidOutline(f"body file {path!r}: unsupported extension {ext or '(none)'!r}; "
                             f"use {', '.join(OUTLINE_FORMATS)}")
    if layer is not None and ext != ".dxf":
        raise InvalidArgument(f"--layer applies to DXF files, not to {path!r}")
    if os.path.getsize(path) == 0:
        raise InvalidOutline(f"body file {path!r} is empty")
    try:
        if ext == ".svg":
            shapes, loose, recorded, what = _read_svg(path)
            return _finish(path, shapes, loose, com, kappa, recorded, what)
        if ext == ".dxf":
            shapes, loose, recorded, what = _read_dxf(path, layer)
            return _finish(path, shapes, loose, com, kappa, recorded, what)
        if ext == ".json":
            with open(path, encoding="utf-8") as fh:
                doc = json.load(fh)
            key = "outline" if isinstance(doc, dict) and "outline" in doc else "points"
            if not isinstance(doc, dict) or key not in doc:
                raise InvalidOutline(f"body file {path!r}: no 'outline' or 'points' list of [x, y] points")
            points = np.asarray(doc[key], dtype=float)
            controls = doc.get("controls")
            if controls is not None and com is None and kappa is None:
                controls = np.asarray(controls, dtype=float)
                if controls.shape == (len(points), 2, 2) and np.all(np.isfinite(controls)) \
                        and np.all(np.isfinite(points)):
                    return Outline(points, controls), "exact Bézier outline (coinwall JSON, units of kappa)"
            recorded = {"com": (0.0, 0.0)} if controls is not None else {}
            what = "JSON points"
        else:
            points, coinwall = _read_points_csv(path)
            recorded = {"com": (0.0, 0.0)} if coinwall else {}
            what = "coinwall CSV points" if coinwall else "CSV points"
    except (OSError, ValueError, TypeError, IndexError) as exc:
        if isinstance(exc, InvalidOutline):
            raise
        raise InvalidOutline(f"body file {path!r} is not readable: {exc}") from None
    if points.ndim != 2 or points.shape[1] != 2 or len(points) < 2 or not np.all(np.isfinite(points)):
        raise InvalidOutline(f"body file {path!r}: the outline must be at least 2 finite [x, y] points")
    closed = [points] if len(points) >= 3 else []
    return _finish(path, closed, [] if closed else [points], com, kappa, recorded, what)


def outline_from_polar(text: str, params=None, *, samples: int = 4096, com=None):
    """Outline of the polar curve R(α) (an expression in ``t``), R measured from the centre of mass.

    The expression is parsed by :mod:`forward.expression`, never evaluated as Python.
    A convex smooth curve (curvature numerator ``R² + 2R'² − R R'' ≥ 0`` everywhere on
    the grid, no kinks) becomes a cubic Hermite/Bézier outline with the exact
    derivatives (shape error O(Δα⁴)); otherwise the convex hull of ``samples`` points.

    Returns
    -------
    (Outline, str)
    """
    from ..wall import Wall

    if not isinstance(samples, int) or samples < 16:
        raise InvalidArgument(f"samples must be an integer >= 16, got {samples!r}")
    radius = Wall.from_expression(text, params or {})
    alpha = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    r, r1, r2 = radius.derivatives(alpha)
    if np.min(r) <= 0:
        k = int(np.argmin(r))
        raise InvalidOutline(f"polar outline {text!r}: R(α) must be positive, got R = {r[k]:.6g} at α = {alpha[k]:.6g}")
    c, s = np.cos(alpha), np.sin(alpha)
    points = np.column_stack([r * c, r * s])
    convex_curve = np.min(r * r + 2 * r1 * r1 - r * r2) >= 0 and not radius.kinks
    if convex_curve and com is None:
        tangent = np.column_stack([r1 * c - r * s, r1 * s + r * c])
        step = np.full(samples, 2 * math.pi / samples)
        return Outline.from_hermite(points, tangent, tangent, step), \
            f"polar R(α) = {text}: convex, exact-derivative Bézier outline on {samples} nodes; pole = centre of mass"
    outline, note = _finish(f"polar:{text}", [points], [], com, None, {"com": (0.0, 0.0)},
                            f"polar R(α) = {text} on {samples} points")
    return outline, note.replace("centre of mass as recorded in the file", "pole = centre of mass") \
        .replace("; drawing units taken as units of kappa", "")


def wall_functions(outline: Outline, theta, H: float | None = None):
    """Lower wall ``b(θ) = h(θ)`` and, given the wall distance H, upper wall ``t(θ) = H − h(θ + π)``."""
    theta = np.asarray(theta, float)
    lower = outline.support(theta)
    upper = None if H is None else H - outline.support(theta + np.pi)
    return lower, upper
