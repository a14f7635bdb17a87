"""SVG export: the outline as one closed path of the solver's own cubic Béziers, to scale.

The path is the exact outline: its only deviation is the rounding of the
printed control points, and since a Bézier curve is a convex combination of
its control points, the largest rounding error of a control point bounds the
deviation of the curve; that bound is reported.  Coordinates are in output
units (κ, or the physical unit of the scale); with a scale the ``width`` and
``height`` attributes carry the unit (``width="53.2mm"``), so the drawing
prints at real size.  y is flipped so the picture has the usual mathematical
orientation.  The centre of mass is marked (a circle with id ``CENTRE_OF_MASS_ID``); marks
carry the class ``ANNOTATION_CLASS`` and the root element records the scale
(``KAPPA_ATTRIBUTE``, ``UNITS_ATTRIBUTE``), so that ``coinwall wall``
(:mod:`coinwall.forward.formats.svg`, where these names live) skips the marks
and reads the drawing back in units of κ.  Optionally the largest diameter is
drawn with its length.

A cut-ready drawing (``ExportOptions(cut=True)``, ``--cut``) holds the outline path only, in a group
``CUT_LAYER_ID`` (a layer for Inkscape), with no fill, no marks, no title and no description; the centre
of mass is kept in a root attribute (``COM_ATTRIBUTE``) that nothing draws.
"""

from __future__ import annotations

from xml.sax.saxutils import escape

import numpy as np

from coinwall.forward.formats.svg import (
    ANNOTATION_CLASS,
    CENTRE_OF_MASS_ID,
    COM_ATTRIBUTE,
    KAPPA_ATTRIBUTE,
    OUTLINE_ID,
    SVG_NAMESPACE,
    UNITS_ATTRIBUTE,
)

from .flatten import largest_diameter
from .options import ExportOptions

__all__ = ["EXTENSION", "CUT_LAYER_ID", "write", "svg_text", "svg_document"]

EXTENSION = ".svg"
#: id (and Inkscape layer label) of the group holding the one contour of a cut-ready drawing
CUT_LAYER_ID = "CUT"
_INKSCAPE = "http://www.inkscape.org/namespaces/inkscape"
_DIGITS = 12


def _fmt(v: float) -> str:
    return f"{v:.{_DIGITS}g}"


def svg_document(body, options: ExportOptions | None = None, size_px: int = 400):
    """The SVG text for ``body`` and a report ``{"path": deviation bound, ...}``."""
    options = options or ExportOptions()
    scale = options.scale
    nodes = scale * body.outline.nodes
    controls = scale * body.outline.controls
    diameter, end_a, end_b = largest_diameter(body.outline)
    diameter *= scale
    extent = float(np.max(np.abs(np.vstack([nodes, controls.reshape(-1, 2)])))) or scale
    half = 1.12 * extent
    stroke = 2 * half / size_px

    def xy(p):
        return f"{_fmt(p[0])},{_fmt(-p[1])}"

    printed = []

    def track(p):
        printed.append((p, (float(_fmt(p[0])), -float(_fmt(-p[1])))))
        return xy(p)

    n = len(nodes)
    parts = [f"M {track(nodes[0])}"]
    for i in range(n):
        parts.append(f"C {track(controls[i, 0])} {track(controls[i, 1])} {track(nodes[(i + 1) % n])}")
    path = " ".join(parts) + " Z"
    rounding = max(float(np.hypot(p[0] - q[0], p[1] - q[1])) for p, q in printed)

    if options.kappa is not None:
        size = f'width="{_fmt(2 * half)}{options.units}" height="{_fmt(2 * half)}{options.units}"'
        unit_text = f"kappa = {options.kappa:g} {options.units}; coordinates in {options.units}"
    else:
        size = f'width="{size_px}" height="{size_px}"'
        unit_text = "coordinates in units of kappa (radius of gyration), no physical scale"
    title = f"coinwall body: b0={body.b0:g}, regime {body.regime}; {unit_text}"
    report = {"path": rounding, "tolerance": options.tolerance_for(diameter), "diameter": diameter,
              "units": options.unit_name}
    if options.cut:
        lines = [
            f'<svg xmlns="{SVG_NAMESPACE}" xmlns:inkscape="{_INKSCAPE}" {size} '
            f'viewBox="{_fmt(-half)} {_fmt(-half)} {_fmt(2 * half)} {_fmt(2 * half)}" '
            f'{KAPPA_ATTRIBUTE}="{_fmt(scale)}" {UNITS_ATTRIBUTE}="{options.unit_name}" {COM_ATTRIBUTE}="0,0">',
            f'<g id="{CUT_LAYER_ID}" inkscape:groupmode="layer" inkscape:label="{CUT_LAYER_ID}">',
            f'<path id="{OUTLINE_ID}" d="{path}" fill="none" stroke="#000" stroke-width="{_fmt(stroke)}"/>',
            "</g>", "</svg>"]
        return "\n".join(lines) + "\n", report
    lines = [
        f'<svg xmlns="{SVG_NAMESPACE}" {size} '
        f'viewBox="{_fmt(-half)} {_fmt(-half)} {_fmt(2 * half)} {_fmt(2 * half)}" '
        f'{KAPPA_ATTRIBUTE}="{_fmt(scale)}" {UNITS_ATTRIBUTE}="{options.unit_name}">',
        f"<title>{escape(title)}</title>",
        f'<path id="{OUTLINE_ID}" d="{path}" fill="#dde6f0" stroke="#123" stroke-width="{_fmt(stroke)}"/>',
        f'<circle id="{CENTRE_OF_MASS_ID}" class="{ANNOTATION_CLASS}" cx="0" cy="0" r="{_fmt(3 * stroke)}" '
        f'fill="none" stroke="#c00" stroke-width="{_fmt(stroke)}"><title>centre of mass</title></circle>',
        f'<path class="{ANNOTATION_CLASS}" d="M {_fmt(-5 * stroke)},0 H {_fmt(5 * stroke)} '
        f'M 0,{_fmt(-5 * stroke)} V {_fmt(5 * stroke)}" stroke="#c00" stroke-width="{_fmt(stroke)}"/>',
    ]
    if options.dimension:
        a, b = scale * end_a, scale * end_b
        mid = (a + b) / 2
        label = f"D = {diameter:.4g} {options.units or 'kappa'}"
        lines.append(f'<g class="{ANNOTATION_CLASS}" stroke="#555" stroke-width="{_fmt(stroke)}">'
                     f'<line x1="{_fmt(a[0])}" y1="{_fmt(-a[1])}" x2="{_fmt(b[0])}" y2="{_fmt(-b[1])}" '
                     f'stroke-dasharray="{_fmt(4 * stroke)}"/>'
                     f'<text x="{_fmt(mid[0])}" y="{_fmt(-mid[1] - 4 * stroke)}" font-size="{_fmt(12 * stroke)}" '
                     f'text-anchor="middle" stroke="none" fill="#333">{escape(label)}</text></g>')
    lines.append(f"<desc>{escape('largest diameter ' + f'{diameter:.6g}' + ' ' + options.unit_name)}; "
                 f"path = exact Bezier outline, rounding of control points at most {rounding:.1e}</desc>")
    lines.append("</svg>")
    return "\n".join(lines) + "\n", report


def svg_text(body, size_px: int = 400, options: ExportOptions | None = None) -> str:
    """SVG text of ``body`` (used for notebooks by ``Body._repr_svg_``)."""
    return svg_document(body, options, size_px)[0]


def write(body, stream, options: ExportOptions | None = None):
    """Write the SVG to a binary ``stream``; returns the deviation report."""
    text, report = svg_document(body, options)
    stream.write(text.encode("utf-8"))
    return report
