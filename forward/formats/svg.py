"""SVG: the outline reader, and the names coinwall's SVG writer gives its marks.

The reader takes every closed shape (a path ending in ``Z``, polygon, rect, circle, ellipse), under
the transforms of its groups; open paths and lines are counted and ignored.  Béziers and arcs are
flattened on the exact geometry (arcs by the SVG 1.1 endpoint-to-centre conversion, implementation
notes F.6.5).  SVG's y axis points down; the body frame's points up, so y is flipped.

**Units.**  ``width``/``height`` with an absolute unit (mm, cm, in, pt, pc, px, m) and a ``viewBox`` give
the physical length of one drawing coordinate (the viewBox is fitted into the page uniformly, as
``preserveAspectRatio`` does by default); without a viewBox a coordinate is one px (1/96 in), as the
SVG specification says.  A unitless ``width`` is a screen size, not a physical unit: such a drawing
records no unit.  The page area (viewBox, else ``width`` × ``height``) lets the loader recognise a
page-sized background rectangle.

**One shape.**  ``element`` restricts the reader to the element with that ``id`` (and what it holds).

The writer (:mod:`coinwall.inverse.export.svg`) records the scale on the root element
(``KAPPA_ATTRIBUTE``, ``UNITS_ATTRIBUTE``) and marks the centre of mass with a circle of id
``CENTRE_OF_MASS_ID`` (a cut-ready drawing, which has no marks, records it in ``COM_ATTRIBUTE``);
every mark carries the class ``ANNOTATION_CLASS``, so that the reader skips marks and reads the
recorded centre of mass and scale back.
"""

from __future__ import annotations

import math
import re

import numpy as np

from ..angles import TWO_PI
from ..errors import InvalidArgument, InvalidOutline
from .geometry import UNIT_LENGTHS, Drawing, cubic_points, ellipse_points

__all__ = ["SVG_NAMESPACE", "KAPPA_ATTRIBUTE", "UNITS_ATTRIBUTE", "COM_ATTRIBUTE", "ANNOTATION_CLASS",
           "CENTRE_OF_MASS_ID", "svg_unit",
           "OUTLINE_ID", "SKIPPED_ELEMENTS", "read_svg", "svg_transform", "svg_path"]

SVG_NAMESPACE = "http://www.w3.org/2000/svg"
#: root attribute: the length of κ in drawing units (the drawing's scale)
KAPPA_ATTRIBUTE = "data-coinwall-kappa"
#: root attribute: the unit of the drawing ("mm", "cm", "in" or "kappa")
UNITS_ATTRIBUTE = "data-coinwall-units"
#: root attribute: the centre of mass "x,y" in SVG coordinates (cut-ready drawings, which have no marks)
COM_ATTRIBUTE = "data-coinwall-com"
#: class of coinwall's marks (centre of mass, dimension): not outline
ANNOTATION_CLASS = "coinwall-annotation"
#: id of the circle at the centre of mass
CENTRE_OF_MASS_ID = "centre-of-mass"
#: id of the outline path
OUTLINE_ID = "outline"
#: elements whose content is never drawn as such
SKIPPED_ELEMENTS = frozenset({"defs", "clipPath", "mask", "symbol", "marker", "pattern", "metadata", "title",
                              "desc", "style"})

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_TRANSFORM = re.compile(r"(matrix|translate|scale|rotate|skewX|skewY)\s*\(([^)]*)\)")


def _numbers(text):
    return [float(v) for v in re.findall(_NUMBER, text or "")]


def svg_transform(text):
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
    dt = (t2 - t1) % TWO_PI
    if not sweep and dt > 0:
        dt -= TWO_PI
    return ellipse_points(centre, rx, ry, phi, t1, dt, size)


def svg_path(d):
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
            current.extend(cubic_points(pos, c1, c2, end, size_guess))
            pos, last_ctrl = end, c2
        elif up in "QT":
            if up == "Q":
                q = base + [scan.number(), scan.number()]
            else:
                q = 2 * pos - last_ctrl if last_ctrl is not None and last_cmd in "QT" else pos.copy()
            end = base + [scan.number(), scan.number()]
            current.extend(cubic_points(pos, pos + 2 * (q - pos) / 3, end + 2 * (q - end) / 3, end, size_guess))
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


_LENGTH = re.compile(r"^\s*(" + _NUMBER + r")\s*([a-zA-Z%]*)\s*$")


def svg_unit(root):
    """The drawing unit of an SVG root element and the page area in drawing coordinates.

    Returns
    -------
    ((str, float) or None, float or None)
        ``(unit name, length of one drawing coordinate in mm)`` when ``width``/``height`` state an
        absolute unit, else None; the area of the viewBox (else ``width`` × ``height``), else None.
    """
    sizes = {}
    for name in ("width", "height"):
        match = _LENGTH.match(root.get(name) or "")
        if match and float(match.group(1)) > 0:
            sizes[name] = (float(match.group(1)), match.group(2).lower())
    box = _numbers(root.get("viewBox"))
    has_box = len(box) == 4 and box[2] > 0 and box[3] > 0
    page = box[2] * box[3] if has_box else (
        sizes["width"][0] * sizes["height"][0] if len(sizes) == 2 and sizes["width"][1] in ("", "px")
        and sizes["height"][1] in ("", "px") else None)
    units = [u for _, u in sizes.values() if u in UNIT_LENGTHS]
    if not units:
        return None, page
    if not has_box:  # no viewBox: one user unit is one CSS px, whatever the page size
        return ("px", UNIT_LENGTHS["px"]), page
    per_coordinate = [value * UNIT_LENGTHS[u] / box[2 if name == "width" else 3]
                      for name, (value, u) in sizes.items() if u in UNIT_LENGTHS]
    return (units[0], min(per_coordinate)), page  # min: the viewBox is fitted in ("meet", the default)


def read_svg(path, element=None) -> Drawing:
    """The closed shapes of an SVG file (of the element with id ``element`` if given), and what it records."""
    if element is not None and (not isinstance(element, str) or not element):
        raise InvalidArgument(f"`element` must be the id of an SVG element (a string), got {element!r}")
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise InvalidOutline(f"body file {path!r} is not valid SVG (XML error: {exc})") from None
    if root.tag.rsplit("}", 1)[-1] != "svg":
        raise InvalidOutline(f"body file {path!r}: the root element is <{root.tag.rsplit('}', 1)[-1]}>, not <svg>")
    shapes, open_count, recorded, found, ids = [], 0, {}, [], []
    unit, page = svg_unit(root)
    if unit is not None:
        recorded["unit"] = unit
    if page is not None and element is None:
        recorded["page"] = page
    kappa = root.get(KAPPA_ATTRIBUTE)
    if kappa is not None and _numbers(kappa):
        recorded["kappa"] = _numbers(kappa)[0]
        recorded["units"] = root.get(UNITS_ATTRIBUTE, "")
    flip = np.diag([1.0, -1.0, 1.0])  # SVG y points down; the body frame's y points up

    def apply(matrix, pts):
        pts = np.asarray(pts, float).reshape(-1, 2)
        full = flip @ matrix
        return pts @ full[:2, :2].T + full[:2, 2]

    if _numbers(root.get(COM_ATTRIBUTE)):
        recorded["com"] = apply(svg_transform(root.get("transform")), _numbers(root.get(COM_ATTRIBUTE))[:2])[0]

    def visit(elem, matrix, inside):
        nonlocal open_count
        tag = elem.tag.rsplit("}", 1)[-1]
        if tag in SKIPPED_ELEMENTS:
            return
        matrix = matrix @ svg_transform(elem.get("transform"))
        classes = (elem.get("class") or "").split()
        if ANNOTATION_CLASS in classes:
            if elem.get("id") == CENTRE_OF_MASS_ID and tag == "circle":
                recorded["com"] = apply(matrix, [_length(elem.get("cx")), _length(elem.get("cy"))])[0]
            return
        if elem.get("id"):
            ids.append(elem.get("id"))
        if element is not None and elem.get("id") == element:
            inside = True
            found.append(tag)
        if not inside:
            for child in elem:
                visit(child, matrix, inside)
            return
        size = 1.0
        if tag == "path":
            for pts, closed in svg_path(elem.get("d")):
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
                shapes.append(apply(matrix, ellipse_points((cx, cy), rx, ry, 0.0, 0.0, TWO_PI, size)))
        elif tag == "line":
            open_count += 1
        for child in elem:
            visit(child, matrix, inside)

    visit(root, np.eye(3), element is None)
    if element is not None and not found:
        shown = ", ".join(repr(i) for i in ids[:12]) + (", ..." if len(ids) > 12 else "")
        raise InvalidOutline(f"body file {path!r}: no element with id {element!r} (ids in the file: "
                             f"{shown or 'none'})")
    if element is not None and not shapes:
        raise InvalidOutline(f"body file {path!r}: element {element!r} (<{found[0]}>) holds no closed shape "
                             f"(path ending in Z, polygon, rect, circle or ellipse)")
    if not shapes:
        extra = f" ({open_count} open shape{'s' if open_count != 1 else ''} ignored)" if open_count else ""
        raise InvalidOutline(f"body file {path!r}: the SVG has no closed shape (path ending in Z, polygon, "
                             f"rect, circle or ellipse){extra}")
    what = f"SVG: {len(shapes)} closed shape{'s' if len(shapes) != 1 else ''}"
    if element is not None:
        what += f" in element {element!r}"
    if open_count:
        what += f", {open_count} open shape{'s' if open_count != 1 else ''} ignored"
    return Drawing(shapes, [], recorded, what)
