"""``coinwall export`` (re-export a solved body to DXF/SVG at a physical scale) and ``coinwall mass``."""

from __future__ import annotations

import json
import math
from .common import describe_written, parse_com

__all__ = ["register"]

_REEXPORT = (".svg", ".dxf")


class _StoredBody:
    """The parts of a solved body that the drawing exporters use, read back from ``solve``'s JSON."""

    def __init__(self, outline, b0, regime):
        self.outline, self.b0, self.regime = outline, b0, regime


def _stored_body(path):
    from coinwall.forward.formats.bodyfile import load_outline
    from coinwall.forward.errors import InvalidOutline

    if not path.lower().endswith(".json"):
        raise InvalidOutline(f"body file {path!r}: export reads the .json written by 'coinwall solve -o BODY.json'")
    outline, note = load_outline(path)
    if not note.startswith("exact"):
        raise InvalidOutline(f"body file {path!r}: no Bézier 'controls'; write it with 'coinwall solve -o BODY.json'")
    with open(path, encoding="utf-8") as fh:
        doc = json.load(fh)
    b0 = doc.get("b0", 0.0)
    if not isinstance(b0, (int, float)) or not math.isfinite(b0):
        raise InvalidOutline(f"body file {path!r}: 'b0' must be a finite number, got {b0!r}")
    return _StoredBody(outline, float(b0), str(doc.get("regime", "unknown")))


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


def _cmd_export(args):
    from coinwall.inverse.export import check_outputs, export_body

    _check_drawing_outputs(args.output)
    check_outputs(args.output)
    body = _stored_body(args.body)
    result = export_body(body, args.output, kappa=args.kappa, units=args.units, tolerance=args.tolerance,
                         dimension=args.dimension)
    if args.json:
        print(json.dumps({"outputs": result.paths, "reports": result.reports}, indent=1))
        return 0
    scale = f"kappa = {args.kappa:g} {args.units}" if args.kappa else "units of kappa (no physical scale)"
    print(f"body       {args.body} (b0 = {body.b0:g}, regime {body.regime}); {scale}")
    for line in describe_written(result):
        print(line)
    return 0


def _cmd_mass(args):
    from coinwall.forward.formats.bodyfile import load_outline
    from coinwall.forward.expression import parse_param
    from coinwall.forward.massprops import mass_properties, outline_moments
    from coinwall.inverse.realizability import kappa_max

    params = dict(parse_param(p) for p in args.param)
    outline, note = load_outline(args.body, layer=args.layer, com=parse_com(args.com), kappa=args.kappa)
    exact = outline_moments(outline)
    props = mass_properties(outline, args.density, params) if args.density else None
    kmax, support = kappa_max(outline)
    doc = {"body": args.body, "note": note, "uniform": exact.as_dict(),
           "density": props.as_dict() if props else None,
           "kappa_max": kmax if math.isfinite(kmax) else None,
           "kappa_max_support": support.tolist(),
           "realizable": bool(math.isfinite(kmax) and kmax >= 1.0)}
    if args.json:
        print(json.dumps(doc, indent=1))
        return 0
    print(f"body       {args.body} ({note})")
    print(f"uniform    area {exact.area:.10g}, centroid ({exact.centre[0]:.6g}, {exact.centre[1]:.6g}), "
          f"kappa {exact.kappa:.10g} (about the centroid; 1 for a self-consistent uniform body)")
    if props:
        print(f"density    {args.density}: mass {props.mass:.10g}, centre of mass ({props.centre[0]:.6g}, "
              f"{props.centre[1]:.6g}), kappa {props.kappa:.10g} ({props.elements} triangles, scikit-fem)")
    if math.isfinite(kmax):
        verdict = "some mass distribution gives this wall" if kmax >= 1 else "no mass distribution reaches kappa = 1"
        print(f"range      kappa in (0, {kmax:.10g}] for mass inside the outline with centre of mass at the "
              f"origin: {verdict}")
    else:
        print("range      the origin is not inside the body: no mass distribution has its centre of mass there")
    return 0


def register(subparsers):
    """Add ``export`` and ``mass`` to the ``coinwall`` command line."""
    export = subparsers.add_parser("export", help="re-export a solved body (.json from solve) to .dxf/.svg at a "
                                                  "physical scale")
    export.add_argument("body", help="BODY.json written by 'coinwall solve -o BODY.json'")
    export.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="output .dxf or .svg (repeatable)")
    export.add_argument("--kappa", type=float, default=None, metavar="VALUE",
                        help="radius of gyration in --units: draw at real size (default: units of kappa)")
    export.add_argument("--units", choices=["mm", "cm", "in"], default=None, help="unit of --kappa")
    export.add_argument("--tolerance", type=float, default=None, metavar="T",
                        help="largest deviation of the DXF polyline from the exact outline, in output units "
                             "(default 1e-4 x largest diameter)")
    export.add_argument("--dimension", action="store_true", help="draw the largest diameter (SVG)")
    export.add_argument("--json", action="store_true", help="print the report as JSON")
    export.set_defaults(run=_cmd_export)

    mass = subparsers.add_parser("mass", help="mass properties of a body (uniform or a density rho(x, y)) and "
                                              "the range of kappa a mass distribution can reach")
    mass.add_argument("body", help="body file: .json/.csv/.svg/.dxf (as for 'coinwall wall')")
    mass.add_argument("--density", default=None, metavar="EXPR",
                      help="density rho(x, y) in x, y, r (body units), e.g. \"1 + 4*r**8\"")
    mass.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                      help="parameter of the density (repeatable)")
    mass.add_argument("--layer", default=None, help="DXF layer to read")
    mass.add_argument("--com", default=None, metavar="X,Y", help="centre of mass in drawing coordinates")
    mass.add_argument("--kappa", type=float, default=None, help="radius of gyration in drawing units")
    mass.add_argument("--json", action="store_true", help="print JSON")
    mass.set_defaults(run=_cmd_mass)
