"""``coinwall export``: re-export a solved body (the .json of ``solve``) to DXF/SVG at a physical scale."""

from __future__ import annotations

import json
import math

from coinwall.inverse.tolerances import REALIZABLE_TOLERANCE

from .common import add_command, describe_written, number

__all__ = ["register"]

_REEXPORT = (".svg", ".dxf")


class _StoredBody:
    """The parts of a solved body that the drawing exporters use, read back from ``solve``'s JSON."""

    def __init__(self, outline, b0, regime, outline_tolerance=None):
        self.outline, self.b0, self.regime = outline, b0, regime
        self.outline_tolerance = outline_tolerance  # a body from samples: how well they fix its outline


def _stored_body(path):
    from coinwall.forward.errors import InvalidOutline
    from coinwall.forward.formats import load_outline
    from coinwall.forward.formats.inputfile import read_json

    if not path.lower().endswith(".json"):
        raise InvalidOutline(f"body file {path!r}: export reads the .json written by 'coinwall solve -o BODY.json'")
    outline, note = load_outline(path)
    if not note.startswith("exact"):
        raise InvalidOutline(f"body file {path!r}: no Bézier 'controls'; write it with 'coinwall solve -o BODY.json'")
    doc = read_json(path, what="body file", error=InvalidOutline)
    b0 = doc.get("b0", 0.0)
    if not isinstance(b0, (int, float)) or not math.isfinite(b0):
        raise InvalidOutline(f"body file {path!r}: 'b0' must be a finite number, got {b0!r}")
    band = doc.get("outline_tolerance")
    if band is not None and not (isinstance(band, (int, float)) and math.isfinite(band) and band >= 0):
        raise InvalidOutline(f"body file {path!r}: 'outline_tolerance' must be a number ≥ 0 or null, got {band!r}")
    return _StoredBody(outline, float(b0), str(doc.get("regime", "unknown")), band)


def _check_drawing_outputs(paths):
    import os

    from coinwall.forward.errors import OutputError

    if not paths:
        raise OutputError("export needs at least one -o FILE (.svg or .dxf)")
    for path in paths:
        ext = os.path.splitext(path)[1].lower()
        if ext not in _REEXPORT:
            raise OutputError(f"output {path!r}: export writes {', '.join(_REEXPORT)}; got {ext or '(none)'!r} "
                              f"(for .json/.csv/.png use 'coinwall solve -o')")


def _physical(outline):
    """κ of the uniform lamina and κ_max (inverse.realizability) of a stored outline."""
    from coinwall.forward.massprops import outline_moments
    from coinwall.inverse.realizability import kappa_max

    kmax, _ = kappa_max(outline)
    kappa_uniform = outline_moments(outline).kappa if outline.area > 0 else 0.0
    return float(kappa_uniform), float(kmax)


def run(args):
    """Read the body, write the drawings, print what was written."""
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.formats.output import existing_files
    from coinwall.inverse.export import ExportOptions, check_outputs, export_body

    _check_drawing_outputs(args.output)
    ExportOptions(kappa=args.kappa, units=args.units, tolerance=args.tolerance, dimension=args.dimension,
                  cut=args.cut)
    body = _stored_body(args.body)
    kappa_uniform, kmax = _physical(body.outline)
    realizable = bool(math.isfinite(kmax) and kmax >= 1.0 - REALIZABLE_TOLERANCE)
    if args.kappa is not None and not realizable and not args.allow_unrealizable:
        raise InvalidArgument(
            f"`kappa`: no mass distribution inside this body gives it κ = 1 (κ_max = {kmax:.4g} κ), so a part cut "
            "at this size would not have this wall; solve it again with --b0 self-consistent, or pass "
            "--allow-unrealizable")
    check_outputs(args.output)
    replaced = existing_files(args.output)
    result = export_body(body, args.output, kappa=args.kappa, units=args.units, tolerance=args.tolerance,
                         dimension=args.dimension, cut=args.cut)
    if args.json:
        print(json.dumps({"outputs": result.paths, "reports": result.reports, "kappa_uniform": kappa_uniform,
                          "kappa_max": kmax if math.isfinite(kmax) else None,
                          "realizable": realizable}, indent=1, allow_nan=False))
        return 0
    scale = f"kappa = {args.kappa:g} {args.units}" if args.kappa else "units of kappa (no physical scale)"
    print(f"body       {args.body} (b0 = {body.b0:g}, regime {body.regime}); {scale}")
    print(f"physical   κ of the uniform body {kappa_uniform:.6g} κ, κ_max {kmax:.6g} κ")
    for line in describe_written(result, replaced):
        print(line)
    return 0


_DESCRIPTION = """\
Re-export a body solved by `coinwall solve -o BODY.json` (its exact Bézier outline) as a drawing:
.svg (an exact Bézier path) or .dxf (an exact SPLINE and an LWPOLYLINE within --tolerance), at a
physical scale: with --kappa VALUE --units mm|cm|in the body is drawn at real size, the radius of
gyration being VALUE units.  With --cut the drawing is cut-ready: one closed contour (DXF: one
LWPOLYLINE within --tolerance) on layer CUT and nothing else.  Prints the deviation each file achieves."""

_EXAMPLE = """\
coinwall solve "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=1 --b0 -0.4 -o body.json
coinwall export body.json --kappa 10 --units mm -o drawings/body.dxf -o drawings/body.svg --dimension"""


def register(subparsers):
    """Add the ``export`` subcommand."""
    parser = add_command(subparsers, "export", help="re-export a solved body (.json from solve) to .dxf/.svg at "
                                                    "a physical scale", description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("body", help="BODY.json written by 'coinwall solve -o BODY.json'")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="output .dxf or .svg (repeatable; missing folders are created)")
    parser.add_argument("--kappa", type=number, default=None, metavar="VALUE",
                        help="radius of gyration in --units: draw at real size (default: units of kappa)")
    parser.add_argument("--units", choices=["mm", "cm", "in"], default=None, help="unit of --kappa")
    parser.add_argument("--tolerance", type=number, default=None, metavar="T",
                        help="largest deviation of the DXF polyline from the exact outline, in output units "
                             "(default 1e-4 x largest diameter)")
    parser.add_argument("--dimension", action="store_true", help="draw the largest diameter (SVG)")
    parser.add_argument("--cut", action="store_true",
                        help="cut-ready drawing: one closed contour on one layer (CUT) and nothing else (no spline "
                             "copy, centre-of-mass cross, text or dimension)")
    parser.add_argument("--allow-unrealizable", action="store_true",
                        help="draw at real size even when no mass distribution inside the body gives it κ = 1")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    parser.set_defaults(run=run)
