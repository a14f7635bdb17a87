"""DXF: the outline reader, and the layer and metadata names coinwall's DXF writer uses.

The reader takes every LWPOLYLINE, POLYLINE, SPLINE, CIRCLE, ELLIPSE and ARC (``DXF_ENTITIES``) on
the chosen layer (default every layer), flattened on the exact geometry by ezdxf; the outline is
their convex hull.

The writer (:mod:`coinwall.inverse.export.dxf`) puts the outline on the layers of ``LAYERS``, a POINT
at the centre of mass on ``LAYERS["com"]`` and the scale in ezdxf's metadata (``KAPPA_KEY``,
``UNITS_KEY``, ``B0_KEY``), so that the reader finds the centre of mass and the scale again.
ezdxf is imported inside the functions (it is slow to import).
"""

from __future__ import annotations

import numpy as np

from ..angles import TWO_PI
from ..errors import InvalidOutline
from .geometry import FLATNESS, Drawing

__all__ = ["DXF_ENTITIES", "LAYERS", "KAPPA_KEY", "UNITS_KEY", "B0_KEY", "read_dxf"]

#: DXF entity types read as outline
DXF_ENTITIES = ("LWPOLYLINE", "POLYLINE", "SPLINE", "CIRCLE", "ELLIPSE", "ARC")
#: layers of coinwall's drawing: exact spline, polyline within the tolerance, centre of mass, notes
LAYERS = {"spline": "OUTLINE", "polyline": "OUTLINE_POLYLINE", "com": "CENTRE_OF_MASS", "notes": "NOTES"}
#: ezdxf metadata keys: κ in drawing units, the drawing's unit, the offset b0
KAPPA_KEY = "coinwall_kappa"
UNITS_KEY = "coinwall_units"
B0_KEY = "coinwall_b0"

def _dxf_points(entity, sagitta):
    """Points along a DXF entity (curves flattened on the exact geometry) and its closed flag.

    ezdxf's own ``flattening`` evaluates arcs, ellipses and splines exactly
    (its Bézier path conversion would approximate arcs, to ~1e-4).
    """
    kind = entity.dxftype()
    if kind in ("CIRCLE", "ARC", "ELLIPSE", "SPLINE"):
        pts = [(v.x, v.y) for v in entity.flattening(sagitta)]
        return np.array(pts, float).reshape(-1, 2), kind in ("CIRCLE",) or (
            kind == "ELLIPSE" and abs(abs(entity.dxf.end_param - entity.dxf.start_param) - TWO_PI) < 1e-12)
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


def read_dxf(path, layer=None) -> Drawing:
    """The outline entities of a DXF file (on ``layer`` if given), and what coinwall's export recorded."""
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
    points = [e for e in msp.query("POINT") if e.dxf.layer.upper() == LAYERS["com"]]
    if points:
        location = points[0].dxf.location
        recorded["com"] = np.array([location.x, location.y], float)
    try:
        meta = doc.ezdxf_metadata()
        if KAPPA_KEY in meta:
            recorded["kappa"] = float(meta[KAPPA_KEY])
            recorded["units"] = meta.get(UNITS_KEY, "")
    except (KeyError, ValueError, TypeError, AttributeError):
        pass
    kinds = sorted({e.dxftype() for e in chosen})
    where = f"layer {layer!r}" if layer is not None else "all layers"
    return Drawing(shapes, loose, recorded, f"DXF: {len(chosen)} entities ({', '.join(kinds)}) on {where}")
