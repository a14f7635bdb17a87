"""The ``coinwall`` command line: parse, call the library, print or write.

Bad input (any :class:`forward.CoinwallError`) becomes one line on stderr and
exit status 2; outputs are written all-or-nothing.
"""

from __future__ import annotations

import argparse

from .common import describe_written, load_wall, wall_arguments
import json
import math
import sys

__all__ = ["main"]


def _fmt_angles(angles):
    return ", ".join(f"{a:.6g}" for a in angles) or "—"


def _cmd_solve(args):
    from .. import EXAMPLE
    from coinwall.inverse import solve_body
    from coinwall.inverse.export import ExportOptions, check_outputs, export_body

    if args.wall is None:
        wall_text, params = EXAMPLE["wall"], [f"{k}={v}" for k, v in EXAMPLE["params"].items()]
        b0 = EXAMPLE["b0"] if args.b0 is None else args.b0
        if not args.json:
            print("No wall given: solving the built-in example, the paper's ellipse wall with eps = 1 at the "
                  "critical offset b0 = -0.5 (paper Fig. 4).")
    else:
        wall_text, params, b0 = args.wall, args.param, (0.0 if args.b0 is None else args.b0)
        if wall_text.startswith("case:") and args.b0 is None:
            from ..catalog import get_case

            b0 = get_case(wall_text).b0  # a case comes with the offset it is meant for
    check_outputs(args.output)  # fail on a bad output before any work
    ExportOptions(kappa=args.kappa, units=args.units, tolerance=args.tolerance)  # and on a bad scale
    wall = load_wall(wall_text, params)
    body = solve_body(wall, b0, method=args.method, points=args.points, cross_check=not args.no_cross_check)
    result = export_body(body, args.output, kappa=args.kappa, units=args.units,
                         tolerance=args.tolerance) if args.output else None
    if args.json:
        print(json.dumps(body.summary(), indent=1, allow_nan=False))
        return 0
    case = {"convex": "Case I: convex body", "critical": "Case II: critical, convex, infinite curvature at the "
            "critical angles", "corner": "Case III: no body has this wall; the largest body under it has corners"}
    print(f"wall       {body.wall!r}")
    print(f"offset     b0 = {body.b0:g}")
    bc = "inf (a concave kink: no offset gives a convex body)" if math.isinf(body.b_c) else f"{body.b_c:.12g}"
    print(f"critical   b_c = {bc} at θ = {_fmt_angles(body.critical_angles)}")
    print(f"regime     {body.regime} ({case[body.regime]})")
    print(f"body       {body.x.size} nodes, area {body.area:.6g}, perimeter {body.perimeter:.6g}, "
          f"R from {body.R.min():.6g} to {body.R.max():.6g} (units of κ)")
    for c in body.corners:
        print(f"corner     at direction {c.direction:.6g} rad, distance {c.distance:.6g}, window ±{c.half_width:.6g} "
              f"rad, largest wall deficit {c.max_deficit:.3g}")
    check = f"max |wall(body) − wall| = {body.max_wall_error:.2e} ({body.method})"
    if body.cross_check is not None:
        check += f"; {'polar' if body.method == 'envelope' else 'envelope'} solver agrees to {body.cross_check:.1e}"
    print(f"check      {check}")
    for note in body.notes:
        print(f"note       {note}")
    if result is not None:
        for line in describe_written(result):
            print(line)
    return 0


def _cmd_critical(args):
    from coinwall.inverse import critical_offset

    wall = load_wall(args.wall, args.param)
    result = critical_offset(wall)
    finite = math.isfinite(result.b_c)
    if args.json:
        print(json.dumps({"b_c": result.b_c if finite else None, "b_c_infinite": not finite,
                          "angles": list(result.angles), "intervals": [list(i) for i in result.intervals]},
                         indent=1, allow_nan=False))
        return 0
    print(f"wall       {wall!r}")
    print(f"b_c        {result.b_c:.15g}" if finite else "b_c        inf (a concave kink: no convex body for any b0)")
    print(f"angles     {_fmt_angles(result.angles)} (rad, where b + b'' is smallest)")
    for lo, hi in result.intervals:
        print(f"interval   b + b'' is minimal on [{lo:.6g}, {hi:.6g}]")
    return 0


def _cmd_wall(args):
    import io

    import numpy as np

    from coinwall.forward import load_outline, wall_functions
    from coinwall.forward.formats.output import check_paths, write_all
    from coinwall.forward.formats.bodyfile import outline_from_polar
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.expression import parse_param

    if args.H is not None and not (math.isfinite(args.H) and args.H > 0):
        raise InvalidArgument(f"--H must be a positive number, got {args.H}")
    if args.samples < 8:
        raise InvalidArgument(f"--samples must be at least 8, got {args.samples}")
    if (args.body is None) == (args.polar is None):
        raise InvalidArgument("give a body file or --polar EXPR (R(α) about the centre of mass), not both or neither")
    if args.kappa is not None and not (math.isfinite(args.kappa) and args.kappa > 0):
        raise InvalidArgument(f"--kappa must be a positive length, got {args.kappa}")
    com = None
    if args.com is not None:
        try:
            com = tuple(float(v) for v in args.com.split(","))
        except ValueError:
            com = ()
        if len(com) != 2 or not all(math.isfinite(v) for v in com):
            raise InvalidArgument(f"--com must be two numbers X,Y, got {args.com!r}")
    outputs = args.output or []
    check_paths(outputs, (".csv", ".json", ".png"))
    if args.polar is not None:
        if args.layer is not None or args.kappa is not None:
            raise InvalidArgument("--layer and --kappa apply to body files, not to --polar")
        outline, note = outline_from_polar(args.polar, dict(parse_param(p) for p in args.param), com=com)
        source = f"R(α) = {args.polar}"
    else:
        if args.param:
            raise InvalidArgument("--param applies to --polar expressions, not to a body file")
        outline, note = load_outline(args.body, layer=args.layer, com=com, kappa=args.kappa)
        source = args.body
    theta = np.linspace(0, 2 * math.pi, args.samples, endpoint=False)
    lower, upper = wall_functions(outline, theta, args.H)
    files = {}
    for path in outputs:
        ext = path.lower().rsplit(".", 1)[-1]
        if ext == "csv":
            text = io.StringIO()
            cols = [theta, lower] + ([upper] if upper is not None else [])
            text.write("theta,b" + (",t" if upper is not None else "") + "\n")
            np.savetxt(text, np.column_stack(cols), delimiter=",", fmt="%.17g")
            data = text.getvalue().encode()
        elif ext == "json":
            doc = {"theta": theta.tolist(), "b": lower.tolist(), "note": note}
            if upper is not None:
                doc.update(H=args.H, t=upper.tolist())
            data = json.dumps(doc).encode()
        else:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(10, 4.2))
            pts = outline.polygon(4) if len(outline.nodes) < 4096 else outline.nodes
            pts = np.vstack([pts, pts[:1]])
            ax0.plot(pts[:, 0], pts[:, 1], "k-")
            ax0.plot([0], [0], "r+", ms=10)
            ax0.set_aspect("equal")
            ax0.set_title("body (units of κ), + centre of mass")
            ax1.plot(theta, lower, label="b(θ)")
            if upper is not None:
                ax1.plot(theta, upper, label=f"t(θ) = H − b(θ+π), H = {args.H:g}")
            ax1.set_xlabel("θ (rad)")
            ax1.legend(loc="best", fontsize=8)
            fig.tight_layout()
            buffer = io.BytesIO()
            fig.savefig(buffer, format="png", dpi=100)
            plt.close(fig)
            data = buffer.getvalue()
        files[path] = data
    write_all(files)
    summary = {"body": source, "note": note, "samples": int(theta.size), "b_min": float(lower.min()),
               "b_max": float(lower.max()), "outputs": outputs}
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        print(f"body       {source} ({note})")
        print(f"wall       b(θ) from {lower.min():.6g} to {lower.max():.6g} on {theta.size} angles")
        if outputs:
            print(f"wrote      {', '.join(outputs)}")
    return 0


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit status 2, as for every bad input
        self.exit(2, f"coinwall: error: {message}\n")


def _parser():
    from coinwall.inverse.solve import DEFAULT_POINTS

    parser = _Parser(prog="coinwall", description="Rigid bodies between parallel walls as billiards "
                     "(Balazs, Chatterjee, Jackson): wall function -> body outline, and back.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    solve = sub.add_parser("solve", help="wall function + offset b0 -> body outline (the inverse problem)")
    wall_arguments(solve, optional=True)
    solve.add_argument("--b0", type=float, default=None, help="offset added to the wall (default 0)")
    solve.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                       help="write the body; format by extension: .svg .dxf .json .csv .png (repeatable)")
    solve.add_argument("--points", type=int, default=DEFAULT_POINTS, help=f"outline nodes (default {DEFAULT_POINTS})")
    solve.add_argument("--method", choices=["envelope", "polar"], default="envelope",
                       help="solver (default envelope; the other one is the cross-check)")
    solve.add_argument("--no-cross-check", action="store_true", help="skip the cross-check with the other solver")
    solve.add_argument("--kappa", type=float, default=None, metavar="VALUE",
                       help="radius of gyration in --units: .svg/.dxf drawn at real size (default: units of kappa)")
    solve.add_argument("--units", choices=["mm", "cm", "in"], default=None, help="unit of --kappa")
    solve.add_argument("--tolerance", type=float, default=None, metavar="T",
                       help="largest deviation of approximated outlines (DXF polyline) in output units")
    solve.add_argument("--json", action="store_true", help="print the summary as JSON")
    solve.set_defaults(run=_cmd_solve)

    critical = sub.add_parser("critical", help="exact critical offset b_c = -min(b + b'')")
    wall_arguments(critical)
    critical.add_argument("--json", action="store_true", help="print JSON")
    critical.set_defaults(run=_cmd_critical)

    wall = sub.add_parser("wall", help="body outline (.json/.csv/.svg/.dxf, or --polar R(α)) -> wall function b(θ)")
    wall.add_argument("body", nargs="?", default=None,
                      help="body file: .json from solve, .csv x,y points, .svg (closed paths, polygons, rects, "
                           "circles, ellipses) or .dxf (LWPOLYLINE POLYLINE SPLINE CIRCLE ELLIPSE ARC)")
    wall.add_argument("--polar", default=None, metavar="EXPR",
                      help="instead of a file: the outline R(α) about the centre of mass, an expression in t")
    wall.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                      help="parameter of the --polar expression (repeatable)")
    wall.add_argument("--layer", default=None, help="DXF layer to read (default: all layers)")
    wall.add_argument("--com", default=None, metavar="X,Y",
                      help="centre of mass in drawing coordinates (default: as recorded by coinwall, else centroid)")
    wall.add_argument("--kappa", type=float, default=None,
                      help="radius of gyration in drawing units (default: as recorded by coinwall, else 1)")
    wall.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                      help=".csv (theta,b[,t]: feeds 'coinwall solve'), .json or .png")
    wall.add_argument("--H", type=float, default=None, help="wall distance: also write the upper wall t(θ)")
    wall.add_argument("--samples", type=int, default=720, help="number of angles (default 720)")
    wall.add_argument("--json", action="store_true", help="print JSON")
    wall.set_defaults(run=_cmd_wall)

    # The other subcommands live in their own modules, each with ``register(subparsers)``.
    from . import catalog, correlation, export, kam, section, simulate

    for module in (export, simulate, section, correlation, kam, catalog):
        module.register(sub)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``coinwall`` command; returns the exit status."""
    from coinwall.forward.errors import CoinwallError

    args = _parser().parse_args(argv)
    try:
        return args.run(args)
    except CoinwallError as exc:
        print(f"coinwall: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
