"""SVG: the outline reader, and the names coinwall's SVG writer gives its marks.

The reader takes every closed shape (a path ending in ``Z``, polygon, rect, circle, ellipse), under
the transforms of its groups; open paths and lines are counted and ignored.  Béziers and arcs are
flattened on the exact geometry (arcs by the SVG 1.1 endpoint-to-centre conversion, implementation
notes F.6.5).  SVG's y axis points down; the body frame's points up, so y is flipped.

**Drawing coordinates.**  A point given by the caller (``com``) is in the drawing's own coordinates:
the user units of the SVG as written in the file, y down, i.e. the ``cx``, ``cy`` a circle placed
directly in the ``<svg>`` element would have there (the viewBox offset changes nothing; a
``transform`` on the root applies, as it does to every shape and to ``data-coinwall-com``).  They are
not converted to a physical unit: a drawing with ``width="60mm" viewBox="0 0 600 600"`` takes ``com``
in its 0.1 mm user units.  The reader records the map from these coordinates to its own (y up) as
``recorded["frame"]``, a 3×3 affine matrix.

**Limits.**  The file is read by :mod:`.inputfile` (a regular file of at most 32 MiB) and parsed by
``defusedxml`` with entities and external references forbidden (a DOCTYPE naming the SVG DTD is
fine).  Elements nest at most :data:`~.inputfile.MAX_NESTING` deep; a drawing has at most
``MAX_SEGMENTS`` path segments, :data:`~.geometry.MAX_POINTS` points once curves are flattened and
:data:`~.geometry.MAX_SHAPES` shapes.  Every number must be finite and at most
:data:`~.geometry.MAX_COORDINATE` in absolute value, a shape at least :data:`~.geometry.MIN_SIZE`
across, every transform applied to a shape invertible, and path data must start with a moveto.
Each violation is one :class:`~coinwall.forward.errors.InvalidOutline` naming the file and the element.

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
from .geometry import (
    MAX_COORDINATE,
    MIN_SIZE,
    UNIT_LENGTHS,
    Drawing,
    PointBudget,
    check_coordinates,
    ellipse_points,
)
from .inputfile import MAX_NESTING, read_bytes
from .svgpath import MAX_SEGMENTS, NUMBER, WSP, checked_number, svg_numbers, svg_path

__all__ = [
    "ANNOTATION_CLASS",
    "CENTRE_OF_MASS_ID",
    "COM_ATTRIBUTE",
    "KAPPA_ATTRIBUTE",
    "MAX_SEGMENTS",
    "OUTLINE_ID",
    "SKIPPED_ELEMENTS",
    "SVG_NAMESPACE",
    "UNITS_ATTRIBUTE",
    "read_svg",
    "svg_path",
    "svg_transform",
    "svg_unit",
]

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

#: a transform whose 2×2 part has a condition number above this flattens shapes: refused
_SINGULAR = 1e12

_NUMBER = NUMBER  # the number syntax of SVG attributes
_checked, _numbers = checked_number, svg_numbers
_NUMBER_AT = re.compile(_NUMBER)
# the transform list of SVG 1.1 (section 7.6, with SVG 2's optional separator between transforms, as browsers
# read it): wsp* transform (comma-wsp* transform)* wsp*, each name with exactly its numbers
_COMMA_WSP = rf"(?:{WSP}+,?{WSP}*|,{WSP}*)"
_ONE_TRANSFORM = re.compile(rf"(matrix|translate|scale|rotate|skewX|skewY){WSP}*\({WSP}*"
                            rf"({_NUMBER}(?:{_COMMA_WSP}{_NUMBER})*)?{WSP}*\)")
_BETWEEN = re.compile(rf"{WSP}*,?{WSP}*")
_ARGUMENTS = {"matrix": (6,), "translate": (1, 2), "scale": (1, 2), "rotate": (1, 3), "skewX": (1,), "skewY": (1,)}


def _transform_list(text):
    """``[(name, numbers), ...]`` of an SVG transform list, or InvalidOutline naming what breaks the grammar.

    SVG applies a transform list whole or not at all: a browser ignores an attribute with an error anywhere in
    it (``scale(2) evil(1)``, ``rotate(30, 5)``, ``translate(1 2 3)``), so reading the valid part would draw
    another shape than the file shows.  coinwall refuses such a list instead of guessing.
    """
    items, pos, text = [], 0, text or ""
    pos = _BETWEEN.match(text, 0).end() if text.strip(" \t\r\n") else len(text)
    while pos < len(text):
        match = _ONE_TRANSFORM.match(text, pos)
        if not match:
            raise InvalidOutline(f"SVG transform {text!r} is not a valid transform list: {text[pos:pos + 20]!r} at "
                                 f"character {pos + 1} is not one of matrix(a b c d e f), translate(x [y]), scale(x [y]), "
                                 "rotate(a [x y]), skewX(a), skewY(a) (numbers separated by commas or spaces); a viewer "
                                 "ignores the whole attribute, so coinwall does not read half of it: fix or remove it")
        name = match.group(1)
        numbers = [_checked(float(v), v) for v in _NUMBER_AT.findall(match.group(2) or "")]
        if len(numbers) not in _ARGUMENTS[name]:
            counts = " or ".join(str(n) for n in _ARGUMENTS[name])
            raise InvalidOutline(f"SVG transform {text!r} is not a valid transform list: {name} takes {counts} "
                                 f"numbers, got {len(numbers)}; a viewer ignores the whole attribute, so coinwall "
                                 "does not read half of it: fix or remove it")
        items.append((name, numbers))
        pos = _BETWEEN.match(text, match.end()).end()
    return items


def svg_transform(text):
    """3×3 matrix of an SVG ``transform`` attribute (the whole list, checked against SVG's grammar first)."""
    total = np.eye(3)
    for name, v in _transform_list(text):
        m = np.eye(3)
        if name == "matrix":
            m[:2, :] = np.array(v).reshape(3, 2).T
        elif name == "translate":
            m[0, 2], m[1, 2] = v[0], (v[1] if len(v) > 1 else 0.0)
        elif name == "scale":
            m[0, 0], m[1, 1] = v[0], (v[1] if len(v) > 1 else v[0])
        elif name == "rotate":
            a = math.radians(v[0])
            rot = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
            if len(v) == 3:
                shift, back = np.eye(3), np.eye(3)
                shift[:2, 2], back[:2, 2] = v[1:3], [-v[1], -v[2]]
                rot = shift @ rot @ back
            m = rot
        elif name == "skewX":
            m[0, 1] = math.tan(math.radians(v[0]))
        else:
            m[1, 0] = math.tan(math.radians(v[0]))
        total = total @ m
    if not np.all(np.abs(total) <= MAX_COORDINATE):
        raise InvalidOutline(f"SVG transform {text!r} has entries that are not finite or larger than "
                             f"{MAX_COORDINATE:g}")
    return total


def _check_invertible(matrix, where):
    """Refuse a transform that flattens shapes to a line or a point (``scale(0)``, a singular matrix)."""
    linear = matrix[:2, :2]
    with np.errstate(all="ignore"):
        singular = not np.linalg.cond(linear) <= _SINGULAR
    if singular:
        raise InvalidOutline(f"the transform of {where} is singular (matrix {_matrix_text(linear)}): it flattens the "
                             "shape to a line or a point, e.g. scale(0)")


def _matrix_text(linear):
    return "[" + ", ".join(f"{v:.6g}" for v in np.ravel(linear)) + "]"




def _length(value, default=0.0):
    """A coordinate or length attribute (a number with an optional unit); absent → ``default``; anything
    else (``nan``, ``inf``, text) is refused rather than read as the default."""
    if value is None or not value.strip():
        return default
    match = _LENGTH.match(value)
    if not match:
        raise InvalidOutline(f"{value!r} is not a number (a length such as 12 or 12px)")
    return _checked(float(match.group(1)), match.group(1))


def _number_list(text, what):
    """All numbers of a list attribute (``points``); text that is not numbers and separators is refused."""
    values = _numbers(text)
    rest = _NUMBER_AT.sub(" ", text or "").replace(",", " ").strip(" \t\r\n")
    if rest:
        raise InvalidOutline(f"{what} holds {rest.split()[0][:20]!r}, which is not a number")
    return values


_LENGTH = re.compile(rf"^{WSP}*(" + _NUMBER + rf"){WSP}*([a-zA-Z%]*){WSP}*$")


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
        if match and 0 < float(match.group(1)) <= MAX_COORDINATE:  # inf or 1e999: no size
            sizes[name] = (float(match.group(1)), match.group(2).lower())
    box = _number_list(root.get("viewBox"), "viewBox")  # text in it is refused, not skipped: it sets the scale
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


def _parse(path):
    """The root element of the SVG file ``path``, parsed without entities or external references."""
    import xml.etree.ElementTree as ET

    import defusedxml
    import defusedxml.ElementTree as DET

    data = read_bytes(path, what="body file", error=InvalidOutline)
    try:
        # a DOCTYPE naming the SVG DTD is common (Inkscape, Illustrator) and harmless: it is not fetched
        return DET.fromstring(data, forbid_dtd=False, forbid_entities=True, forbid_external=True)
    except defusedxml.EntitiesForbidden as exc:
        raise InvalidOutline(f"body file {path!r}: the SVG declares the entity {exc.name!r}; coinwall reads no "
                             "entity declarations (they can expand without bound or read other files)") from None
    except defusedxml.DefusedXmlException as exc:
        raise InvalidOutline(f"body file {path!r}: the SVG refers to something outside it ({exc}); coinwall "
                             "reads self-contained SVG only") from None
    except ET.ParseError as exc:
        raise InvalidOutline(f"body file {path!r} is not valid SVG (XML error: {exc})") from None
    except LookupError as exc:
        raise InvalidOutline(f"body file {path!r}: the XML declaration names an encoding Python does not know "
                             f"({exc}); save the file as UTF-8") from None
    except (ValueError, RecursionError, MemoryError) as exc:
        raise InvalidOutline(f"body file {path!r} is not valid SVG ({type(exc).__name__}: "
                             f"{str(exc).splitlines()[0][:120] if str(exc) else 'no detail'})") from None


def _describe(elem, tag):
    return f"<{tag} id={elem.get('id')!r}>" if elem.get("id") else f"<{tag}>"


def _recorded_number(root, attribute, path, positive=False):
    """A number recorded on the root (``data-coinwall-kappa``): finite (and positive if asked), else refused."""
    text = root.get(attribute)
    if text is None:
        return None
    match = _LENGTH.match(text)
    value = float(match.group(1)) if match else math.nan
    if not math.isfinite(value) or (positive and value <= 0) or abs(value) > MAX_COORDINATE:
        valid = "a positive finite number" if positive else "a finite number"
        raise InvalidOutline(f"body file {path!r}: the root records {attribute}={text!r}; it must be {valid}")
    return value


def _shapes_of(elem, tag, matrix, add, budget, where):
    """Add the closed shapes of one element (``add(matrix, points, where)``); returns its open shapes."""
    open_count = 0
    if tag == "path":
        for pts, closed in svg_path(elem.get("d"), budget):
            if closed:
                add(matrix, pts, where)
            else:
                open_count += 1
    elif tag in ("polygon", "polyline"):
        v = _number_list(elem.get("points"), "points")
        if len(v) % 2:
            raise InvalidOutline(f"points holds {len(v)} numbers, an odd count: x and y must come in pairs")
        budget.take(len(v) // 2, where)
        pts = np.array(v[: len(v) // 2 * 2]).reshape(-1, 2)
        closed = tag == "polygon" or (len(pts) > 2 and np.allclose(pts[0], pts[-1]))
        if len(pts) >= 3 and closed:
            add(matrix, pts, where)
        elif len(pts):
            open_count += 1
    elif tag == "rect":
        x, y = _length(elem.get("x")), _length(elem.get("y"))
        w, h = _length(elem.get("width")), _length(elem.get("height"))
        if w > 0 and h > 0:  # rounded corners (rx, ry) are ignored: the hull differs by < rx
            budget.take(4, where)
            add(matrix, [[x, y], [x + w, y], [x + w, y + h], [x, y + h]], where)
    elif tag in ("circle", "ellipse"):
        cx, cy = _length(elem.get("cx")), _length(elem.get("cy"))
        if tag == "circle":
            rx = ry = _length(elem.get("r"))
        else:
            rx, ry = _length(elem.get("rx")), _length(elem.get("ry"))
        if rx > 0 and ry > 0:
            if max(rx, ry) < MIN_SIZE:
                raise InvalidOutline(f"radius {max(rx, ry):.3g} is smaller than {MIN_SIZE:g} drawing units")
            pts = ellipse_points((cx, cy), rx, ry, 0.0, 0.0, TWO_PI, max(rx, ry))
            budget.take(len(pts), where)
            add(matrix, pts, where)
    elif tag == "line":
        open_count += 1
    return open_count


def read_svg(path, element=None) -> Drawing:
    """The closed shapes of an SVG file (of the element with id ``element`` if given), and what it records."""
    if element is not None and (not isinstance(element, str) or not element):
        raise InvalidArgument(f"`element` must be the id of an SVG element (a string), got {element!r}")
    root = _parse(path)
    if root.tag.rsplit("}", 1)[-1] != "svg":
        raise InvalidOutline(f"body file {path!r}: the root element is <{root.tag.rsplit('}', 1)[-1]}>, not <svg>")
    with np.errstate(all="ignore"):  # overflow and nan are checked on every shape (check_coordinates)
        return _read_root(path, root, element)


def _read_root(path, root, element):
    shapes, open_count, recorded, found, ids = [], 0, {}, [], []
    budget = PointBudget(path)
    try:
        unit, page = svg_unit(root)
    except InvalidOutline as exc:
        raise InvalidOutline(f"body file {path!r}, <svg>: {exc}") from None
    if unit is not None:
        recorded["unit"] = unit
    if page is not None and element is None:
        recorded["page"] = page
    kappa = _recorded_number(root, KAPPA_ATTRIBUTE, path, positive=True)
    if kappa is not None:
        recorded["kappa"] = kappa
        recorded["units"] = root.get(UNITS_ATTRIBUTE, "")
    flip = np.diag([1.0, -1.0, 1.0])  # SVG y points down; the body frame's y points up

    def apply(matrix, pts, where="<svg>", check_size=False):
        _check_invertible(matrix, where)
        pts = np.asarray(pts, float).reshape(-1, 2)
        full = flip @ matrix
        pts = check_coordinates(pts @ full[:2, :2].T + full[:2, 2], "after its transforms")
        if check_size and len(pts):
            size = float(np.ptp(pts, axis=0).max())
            if 0 < size < MIN_SIZE:
                raise InvalidOutline(f"{where} measures {size:.3g} drawing units, less than {MIN_SIZE:g}")
        return pts

    def add(matrix, pts, where):
        budget.shape(where)
        shapes.append(apply(matrix, pts, where, check_size=True))

    try:
        # drawing coordinates (user units, y down, as a child of the root writes them) -> the reader's frame
        frame = svg_transform(root.get("transform"))
        _check_invertible(frame, "<svg>")
        recorded["frame"] = flip @ frame
        if root.get(COM_ATTRIBUTE) is not None:
            com = _number_list(root.get(COM_ATTRIBUTE), COM_ATTRIBUTE)
            if len(com) != 2:
                raise InvalidOutline(f"{COM_ATTRIBUTE}={root.get(COM_ATTRIBUTE)!r} must be two numbers x,y")
            recorded["com"] = apply(frame, com)[0]
    except InvalidOutline as exc:
        raise InvalidOutline(f"body file {path!r}, <svg>: {exc}") from None

    def visit(elem, matrix, inside, depth):
        nonlocal open_count
        tag = elem.tag.rsplit("}", 1)[-1] if isinstance(elem.tag, str) else ""
        if tag in SKIPPED_ELEMENTS or not tag:  # comments and processing instructions have no str tag
            return
        if depth > MAX_NESTING:
            raise InvalidOutline(f"body file {path!r}: elements are nested more than {MAX_NESTING} deep; coinwall "
                                 "reads drawings nested at most that deep (ungroup the drawing)")
        where = _describe(elem, tag)
        try:
            matrix = matrix @ svg_transform(elem.get("transform"))
            classes = (elem.get("class") or "").split()
            if ANNOTATION_CLASS in classes:
                if elem.get("id") == CENTRE_OF_MASS_ID and tag == "circle":
                    recorded["com"] = apply(matrix, [_length(elem.get("cx")), _length(elem.get("cy"))], where)[0]
                return
            if elem.get("id"):
                ids.append(elem.get("id"))
            if element is not None and elem.get("id") == element:
                inside = True
                found.append(tag)
            if inside:
                open_count += _shapes_of(elem, tag, matrix, add, budget, where)
        except InvalidOutline as exc:
            if str(exc).startswith("body file"):
                raise
            raise InvalidOutline(f"body file {path!r}, {where}: {exc}") from None
        except (ZeroDivisionError, OverflowError, ValueError) as exc:  # math on extreme numbers in Python floats
            raise InvalidOutline(f"body file {path!r}, {where}: cannot be read ({type(exc).__name__}: {exc})") from None
        for child in elem:
            visit(child, matrix, inside, depth + 1)

    visit(root, np.eye(3), element is None, 0)
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
