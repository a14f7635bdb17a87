"""DXF export (ezdxf): the outline as an exact closed SPLINE and as a closed LWPOLYLINE.

Layers
------
``OUTLINE``
    The solver's piecewise cubic Bézier outline as one cubic B-spline with
    knot multiplicity 3 at every node (:func:`ezdxf.math.bezier_to_bspline`):
    the same curve exactly, C⁰ at nodes, so corners stay corners.
``OUTLINE_POLYLINE``
    A closed LWPOLYLINE within the tolerance of the curve, every node a vertex.
``ANNOTATION_CENTRE_OF_MASS``
    A POINT at the centre of mass (the origin) and a small cross of LINEs.
``ANNOTATION_NOTES``
    A TEXT stating units and scale, the offset and the achieved deviations.

A cut-ready drawing (``ExportOptions(cut=True)``, ``--cut``) holds one entity only: the closed
LWPOLYLINE within the tolerance, on layer ``CUT``; laser and CNC software that cuts every layer cuts
the outline once and nothing else.  The centre of mass is then kept in the metadata only
(``coinwall_com``), which no CAM program draws.

``$INSUNITS`` is 4/5/1 for mm/cm/in with a physical scale, 0 (unitless) in
units of κ.  The scale and unit are also kept in ezdxf's metadata
(``coinwall_kappa``, ``coinwall_units``) so that ``coinwall wall`` reads the
drawing back in units of κ.  The layer and metadata names live with the
reader, in :mod:`coinwall.forward.formats.dxf`.

The same body gives the same bytes: ezdxf would stamp the file with the time
of creation and of saving (``$TDCREATE``, ``$TDUPDATE``, its metadata marker)
and random GUIDs; they are written with ezdxf's fixed values instead
(``write_fixed_meta_data_for_testing``: 2000-01-01, null GUIDs).  Handles are
assigned in order of creation, hence fixed too.
"""

from __future__ import annotations

import contextlib
import io

import numpy as np

from coinwall.forward.formats.dxf import B0_KEY, COM_KEY, KAPPA_KEY, LAYERS, UNITS_KEY

from .flatten import flatten_outline, largest_diameter
from .options import UNITS, ExportOptions

__all__ = ["EXTENSION", "write", "build_document", "LAYERS"]

EXTENSION = ".dxf"


@contextlib.contextmanager
def _fixed_metadata():
    """ezdxf writes fixed dates, GUIDs and markers inside this block (a global option, restored after)."""
    import ezdxf

    before = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = before


def _bspline(outline, scale):
    from ezdxf.math import Bezier4P, Vec3, bezier_to_bspline

    p0, p1, p2, p3 = (scale * q for q in outline._segments)
    curves = [Bezier4P([Vec3(float(q[0]), float(q[1]), 0.0) for q in quad]) for quad in zip(p0, p1, p2, p3)]
    return bezier_to_bspline(curves)


def _spline_deviation(bspline, outline, scale, per_segment=16):
    """Largest distance between the B-spline (as ezdxf evaluates it) and the Bézier outline."""
    n = len(outline.nodes)
    s = np.arange(per_segment) / per_segment
    exact = scale * outline.point(s).reshape(-1, 2)
    knots = (np.arange(n)[:, None] + s[None, :]).ravel()
    spline = np.array([tuple(v)[:2] for v in bspline.points(knots)])
    return float(np.max(np.hypot(*(spline - exact).T)))


def _annotate(msp, body, options, diameter, tolerance, poly_dev, spline_dev):
    """The centre-of-mass mark and the note, on the annotation layers."""
    mark = 0.02 * diameter
    msp.add_point((0.0, 0.0), dxfattribs={"layer": LAYERS["com"]})
    msp.add_line((-mark, 0), (mark, 0), dxfattribs={"layer": LAYERS["com"]})
    msp.add_line((0, -mark), (0, mark), dxfattribs={"layer": LAYERS["com"]})
    unit_text = f"kappa = {options.kappa:g} {options.units}" if options.kappa else "units of kappa (unscaled)"
    note = (f"coinwall body: b0={body.b0:g}, regime {body.regime}; {unit_text}; "
            f"polyline deviation {poly_dev:.3g} (tolerance {tolerance:.3g}); spline exact ({spline_dev:.1e})")
    band = getattr(body, "outline_tolerance", None)
    if band is not None:
        note += f"; from samples: outline within {band * options.scale:.3g} of every body they allow"
    msp.add_text(note, height=0.02 * diameter, dxfattribs={"layer": LAYERS["notes"]}).set_placement(
        (-0.5 * diameter, -0.65 * diameter))


def build_document(body, options: ExportOptions | None = None):
    """The ezdxf document for ``body`` and a report ``{"spline": dev, "polyline": dev, ...}``."""
    import ezdxf

    options = options or ExportOptions()
    scale = options.scale
    outline = body.outline
    diameter = largest_diameter(outline)[0] * scale
    tolerance = options.tolerance_for(diameter)
    if tolerance < 1e-12 * diameter:  # below double-precision rounding of the coordinates
        from coinwall.forward.errors import OutputError

        raise OutputError(f"`tolerance` {tolerance:.3g} {options.unit_name} is below the rounding of the "
                          f"coordinates ({1e-12 * diameter:.1g}); give a larger tolerance")

    with _fixed_metadata():  # the creation date and marker are set here
        doc = ezdxf.new("R2010", setup=False)
    doc.header["$INSUNITS"] = UNITS.get(options.units, 0)
    doc.header["$MEASUREMENT"] = 0 if options.units == "in" else 1
    msp = doc.modelspace()
    points, poly_dev = flatten_outline(outline, tolerance, scale)
    if options.cut:
        doc.layers.add(LAYERS["cut"], color=1)
        msp.add_lwpolyline([tuple(p) for p in points], format="xy", close=True, dxfattribs={"layer": LAYERS["cut"]})
        spline_dev = 0.0
    else:
        for key, color in (("spline", 5), ("polyline", 1), ("com", 3), ("notes", 7)):
            doc.layers.add(LAYERS[key], color=color)
        bspline = _bspline(outline, scale)
        spline = msp.add_spline(dxfattribs={"layer": LAYERS["spline"]})
        spline.apply_construction_tool(bspline)
        spline.dxf.flags = spline.PLANAR | spline.CLOSED
        spline_dev = _spline_deviation(bspline, outline, scale)
        msp.add_lwpolyline([tuple(p) for p in points], format="xy", close=True,
                           dxfattribs={"layer": LAYERS["polyline"]})
        _annotate(msp, body, options, diameter, tolerance, poly_dev, spline_dev)
    meta = doc.ezdxf_metadata()
    meta[KAPPA_KEY] = repr(scale)
    meta[UNITS_KEY] = options.unit_name
    meta[B0_KEY] = repr(float(body.b0))
    meta[COM_KEY] = "0,0"  # the body frame's origin is the centre of mass
    report = {"polyline": poly_dev, "tolerance": tolerance, "polyline_vertices": int(len(points)),
              "units": options.unit_name}
    if not options.cut:
        report = {"spline": spline_dev, **report}
    return doc, report


def write(body, stream, options: ExportOptions | None = None):
    """Write the DXF to a binary ``stream``; returns the deviation report."""
    doc, report = build_document(body, options)
    text = io.StringIO()
    with _fixed_metadata():  # the saving date, the GUIDs and the "written by" marker are set here
        doc.write(text)
    stream.write(text.getvalue().encode(doc.output_encoding))
    return report
