"""DXF: the outline reader, and the layer and metadata names coinwall's DXF writer uses.

The reader takes every LWPOLYLINE, POLYLINE, SPLINE, CIRCLE, ELLIPSE, LINE and ARC (``DXF_ENTITIES``)
on the chosen layer (default every layer but annotation layers, whose names start with ANNOTATION),
flattened on the exact geometry by ezdxf.  LINE and ARC entities are pieces of chains: their end
points are joined (within ``CHAIN_TOLERANCE`` times the size of the pieces) into closed loops, which
are outlines like a closed polyline; a chain that does not close is an error that names its gap.
``$INSUNITS`` (``INSUNITS``: 1 in, 2 ft, 4 mm, 5 cm, 6 m) is the drawing's unit; 0 or another code
records none.

The writer (:mod:`coinwall.inverse.export.dxf`) puts the outline on the layers of ``LAYERS``
(annotations on layers whose names say so), a POINT at the centre of mass on ``LAYERS["com"]`` and
the scale and the centre of mass in ezdxf's metadata (``KAPPA_KEY``, ``UNITS_KEY``, ``B0_KEY``,
``COM_KEY``), so that the reader finds the centre of mass and the scale again; a cut-ready drawing
holds its one contour on ``LAYERS["cut"]``.
ezdxf is imported inside the functions (it is slow to import).
"""

from __future__ import annotations

import numpy as np

from ..angles import TWO_PI
from ..errors import InvalidOutline
from .geometry import (
    CHAIN_TOLERANCE,
    FLATNESS,
    MAX_COORDINATE,
    MIN_SIZE,
    UNIT_LENGTHS,
    Drawing,
    PointBudget,
    check_coordinates,
    join_chains,
)
from .inputfile import read_bytes

__all__ = [
    "B0_KEY",
    "CHAIN_ENTITIES",
    "COM_KEY",
    "DXF_ENTITIES",
    "INSUNITS",
    "KAPPA_KEY",
    "LAYERS",
    "MAX_ENTITIES",
    "UNITS_KEY",
    "read_dxf",
]

#: DXF entity types read as outline
DXF_ENTITIES = ("LWPOLYLINE", "POLYLINE", "SPLINE", "CIRCLE", "ELLIPSE", "LINE", "ARC")
#: entity types joined end to end into closed chains
CHAIN_ENTITIES = ("LINE", "ARC")
#: layers of coinwall's drawing: exact spline, polyline within the tolerance, the centre-of-mass
#: annotation, the notes annotation, and the one layer of a cut-ready drawing
LAYERS = {"spline": "OUTLINE", "polyline": "OUTLINE_POLYLINE", "com": "ANNOTATION_CENTRE_OF_MASS",
          "notes": "ANNOTATION_NOTES", "cut": "CUT"}
#: ``$INSUNITS`` code -> unit name (:data:`~.geometry.UNIT_LENGTHS`); other codes record no unit
INSUNITS = {1: "in", 2: "ft", 4: "mm", 5: "cm", 6: "m"}
#: ezdxf metadata keys: κ in drawing units, the drawing's unit, the offset b0, the centre of mass "x,y"
KAPPA_KEY = "coinwall_kappa"
UNITS_KEY = "coinwall_units"
B0_KEY = "coinwall_b0"
COM_KEY = "coinwall_com"
#: entities (of any type) a DXF file may hold, counted in its text before ezdxf parses it: ezdxf takes
#: ~140 µs and ~1 kB per entity (2·10⁵ circles: 28 s, 0.24 GB), so this bound is ~3 s and ~25 MB
MAX_ENTITIES = 20_000
#: errors ezdxf (and the Python underneath it) raises on damaged files: truncated (StopIteration,
#: EOFError), bad numbers (ValueError), missing structure (KeyError, IndexError, DXFStructureError)
_PARSE_ERRORS = (StopIteration, EOFError, ValueError, TypeError, KeyError, IndexError, AttributeError,
                 UnicodeError, OverflowError, RecursionError)

def _check_shape_numbers(entity):
    """Refuse a circle or arc whose radius is not positive, an ellipse whose axis ratio is not in (0, 1] (the
    DXF reference's ranges): ezdxf draws a radius of −1 as a circle of radius 1, which is not what the file
    says."""
    kind = entity.dxftype()
    if kind in ("CIRCLE", "ARC"):
        radius = float(entity.dxf.radius)
        if not radius > 0:
            raise InvalidOutline(f"its radius is {radius:g}; a {kind.lower()}'s radius must be positive")
    elif kind == "ELLIPSE":
        ratio = float(entity.dxf.ratio)
        if not 0 < ratio <= 1:
            raise InvalidOutline(f"its axis ratio is {ratio:g}; an ellipse's minor-to-major ratio must be in (0, 1]")


def _dxf_points(entity, sagitta):
    """Points along a DXF entity (curves flattened on the exact geometry) and its closed flag.

    ezdxf's own ``flattening`` evaluates arcs, ellipses and splines exactly
    (its Bézier path conversion would approximate arcs, to ~1e-4).
    """
    kind = entity.dxftype()
    if kind == "LINE":
        return np.array([[entity.dxf.start.x, entity.dxf.start.y], [entity.dxf.end.x, entity.dxf.end.y]]), False
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


def _is_annotation(layer):
    """Whether a layer holds annotations: its name starts with ANNOTATION."""
    return layer.upper().startswith("ANNOTATION")


def _chains(path, pieces):
    """Closed loops of LINE/ARC pieces; an open chain is an error naming its gap."""
    everything = np.vstack(pieces)
    size = float(np.ptp(everything, axis=0).max()) if len(everything) else 0.0
    tolerance = CHAIN_TOLERANCE * max(size, 1e-300)
    loops, open_chains = join_chains(pieces, tolerance)
    if open_chains:
        points, gap = max(open_chains, key=lambda chain: chain[1])
        a, b = points[0], points[-1]
        raise InvalidOutline(f"body file {path!r}: the LINE/ARC chain from ({a[0]:.6g}, {a[1]:.6g}) to "
                             f"({b[0]:.6g}, {b[1]:.6g}) is open: its ends are {gap:.3g} apart (end points "
                             f"join within {tolerance:.2g}); close the outline in the drawing"
                             + (f" ({len(open_chains)} open chains)" if len(open_chains) > 1 else ""))
    return loops


def _count_entities(data: bytes) -> int:
    """Structures in DXF text: lines holding group code 0 followed by a name (an upper bound on entities)."""
    import re

    return len(re.findall(rb"(?m)^[ \t]*0\r?\n[ \t]*[A-Z_][A-Z_0-9]*\r?$", data))


def _load(path):
    """The ezdxf document of the DXF file ``path``, read through :mod:`.inputfile`; damaged files and
    files of more than MAX_ENTITIES entities are refused with one line."""
    import io

    import ezdxf

    data = read_bytes(path, what="body file", error=InvalidOutline)
    binary = data.startswith(b"AutoCAD Binary DXF")
    count = data.count(b"\x00") // 8 if binary else _count_entities(data)  # binary: a generous lower estimate
    if count > MAX_ENTITIES:
        raise InvalidOutline(f"body file {path!r} holds about {count} DXF entities; coinwall reads drawings of at "
                             f"most {MAX_ENTITIES} (pick the outline's layer into a file of its own)")
    try:
        if binary:
            from ezdxf.document import Drawing as Document
            from ezdxf.lldxf.tagger import binary_tags_loader

            return Document.load(binary_tags_loader(data, errors="surrogateescape"))
        if not data.lstrip()[:1].isdigit():
            raise InvalidOutline(f"body file {path!r} is not a DXF file (a DXF file starts with a group code, "
                                 "e.g. \"0\" then \"SECTION\")")
        from ezdxf.lldxf.validator import dxf_info

        # line ends: CRLF (as Windows CAD programs write) and lone CR are read as LF, which ezdxf's text reader needs
        data = data.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
        # the header names the encoding of DXF R2004 and older; it is ASCII, so read it as UTF-8 first.  From R2007
        # (AC1021) on, the standard fixes the text encoding to UTF-8 whatever $DWGCODEPAGE says (ezdxf's dxf_info
        # reports the code page there, which would turn a non-ASCII layer name into mojibake)
        info = dxf_info(io.StringIO(data.decode("utf-8", errors="ignore")))
        encoding = "utf-8" if (info.version or "") >= "AC1021" else (info.encoding or "utf-8")
        return ezdxf.read(io.StringIO(data.decode(encoding, errors="surrogateescape")))
    except InvalidOutline:
        raise
    except (ezdxf.DXFError, LookupError, *_PARSE_ERRORS) as exc:
        detail = str(exc).splitlines()[0][:160] if str(exc) else "the file ends too early"
        if not detail.startswith(type(exc).__name__):
            detail = f"{type(exc).__name__}: {detail}"
        raise InvalidOutline(f"body file {path!r} is not a valid DXF file: {detail}") from None


def read_dxf(path, layer=None) -> Drawing:
    """The outline entities of a DXF file (on ``layer`` if given), and what coinwall's export recorded."""
    import ezdxf
    from ezdxf import bbox

    doc = _load(path)
    msp = doc.modelspace()
    candidates = [e for e in msp if e.dxftype() in DXF_ENTITIES]
    if layer is not None:
        chosen = [e for e in candidates if e.dxf.layer.lower() == layer.lower()]
        if not chosen:
            layers = sorted({e.dxf.layer for e in candidates})
            raise InvalidOutline(f"body file {path!r}: nothing to read on layer {layer!r} (need one of "
                                 f"{', '.join(DXF_ENTITIES)}); layers with outline entities: "
                                 f"{', '.join(layers) or 'none'}")
    else:  # annotations are not outline: the centre-of-mass cross is made of LINEs
        chosen = [e for e in candidates if not _is_annotation(e.dxf.layer)]
    if not chosen:
        raise InvalidOutline(f"body file {path!r}: the DXF has no {', '.join(DXF_ENTITIES)} entity")
    shapes, loose, pieces = [], [], []
    budget = PointBudget(path)
    for entity in chosen:
        where = f"{entity.dxftype()} {entity.dxf.handle}"
        budget.shape(where)
        try:
            with np.errstate(all="ignore"):
                box = bbox.extents([entity])
                size = max(box.size.x, box.size.y) if box.has_data else 1.0
                if not (abs(box.extmin.x) <= MAX_COORDINATE and abs(box.extmin.y) <= MAX_COORDINATE
                        and abs(box.extmax.x) <= MAX_COORDINATE and abs(box.extmax.y) <= MAX_COORDINATE) \
                        and box.has_data:
                    raise InvalidOutline(f"coordinates are not finite or larger than {MAX_COORDINATE:g}")
                if 0 < size < MIN_SIZE:
                    raise InvalidOutline(f"it measures {size:.3g} drawing units, less than {MIN_SIZE:g}")
                _check_shape_numbers(entity)
                pts, flagged = _dxf_points(entity, max(FLATNESS * size, 1e-300))
                pts = check_coordinates(pts, "its points")
                extent = float(np.ptp(pts, axis=0).max()) if len(pts) else 0.0
                if 0 < extent < MIN_SIZE:
                    raise InvalidOutline(f"it measures {extent:.3g} drawing units, less than {MIN_SIZE:g}")
        except InvalidOutline as exc:
            raise InvalidOutline(f"body file {path!r}: {where}: {exc}") from None
        except (ZeroDivisionError, ezdxf.DXFError, *_PARSE_ERRORS) as exc:
            raise InvalidOutline(f"body file {path!r}: cannot read {where}: {exc}") from None
        budget.take(len(pts), where)
        if len(pts) < 2:
            continue
        if entity.dxftype() in CHAIN_ENTITIES:
            pieces.append(pts)
            continue
        closed = flagged or np.hypot(*(pts[0] - pts[-1])) <= 1e-9 * max(size, 1e-300)
        (shapes if closed and len(pts) > 3 else loose).append(pts[:-1] if closed else pts)
    if pieces:
        shapes.extend(_chains(path, pieces))
    recorded = {}
    code = doc.header.get("$INSUNITS", 0)
    if code in INSUNITS:
        recorded["unit"] = (INSUNITS[code], UNIT_LENGTHS[INSUNITS[code]])
    points = [e for e in msp.query("POINT") if e.dxf.layer.upper() == LAYERS["com"]]
    if points:
        location = points[0].dxf.location
        recorded["com"] = check_coordinates([location.x, location.y], f"body file {path!r}: the centre-of-mass "
                                            f"POINT {points[0].dxf.handle}")
    try:
        meta = doc.ezdxf_metadata()
        if KAPPA_KEY in meta:
            recorded["kappa"] = float(meta[KAPPA_KEY])
            recorded["units"] = meta.get(UNITS_KEY, "")
        if COM_KEY in meta and "com" not in recorded:
            recorded["com"] = np.array([float(v) for v in meta[COM_KEY].split(",")], float).reshape(2)
    except (KeyError, ValueError, TypeError, AttributeError):
        pass  # metadata written by another program: the file records no scale or centre of mass
    if "com" in recorded:
        recorded["com"] = check_coordinates(recorded["com"], f"body file {path!r}: the recorded centre of mass")
    kinds = sorted({e.dxftype() for e in chosen})
    where = f"layer {layer!r}" if layer is not None else "all layers"
    return Drawing(shapes, loose, recorded, f"DXF: {len(chosen)} entities ({', '.join(kinds)}) on {where}")
