"""What several subcommands share: the WALL and table arguments, loading them, the progress bar,
``--com``, and the lines that report written files."""

from __future__ import annotations

import math
import os
import sys

__all__ = ["wall_arguments", "table_arguments", "load_table", "load_wall", "progress_bar", "parse_com",
           "describe_written", "check_positive_count", "check_seed"]


def wall_arguments(parser, optional=False):
    """Add the positional WALL argument and ``--param`` to a subcommand parser."""
    parser.add_argument("wall", nargs="?" if optional else None,
                        help="wall b(θ): an expression in t (alias theta), e.g. \"sqrt((1+eps*cos(t)**2)/(1+eps))\", "
                             "or a file: .csv (theta,b samples) or .json (Fourier: {\"a0\", \"cos\", \"sin\"})")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="value of a parameter of the expression (repeatable)")


def table_arguments(parser):
    """Add WALL, ``--param``, ``--H``, ``--b0`` and ``--kappa``: the billiard table of the dynamics subcommands."""
    wall_arguments(parser)
    parser.add_argument("--H", type=float, required=True,
                        help="distance between the walls (units of κ, or of --kappa's length unit)")
    parser.add_argument("--b0", type=float, default=0.0, help="offset added to the wall (default 0)")
    parser.add_argument("--kappa", type=float, default=None, metavar="VALUE",
                        help="radius of gyration of a physical body, in the length unit of the wall, --H and --b0 "
                             "(all three are divided by it; results are in units of κ). Default: they already are "
                             "in units of κ")


def load_table(args):
    """The wall and the :class:`forward.billiard.Billiard` of a dynamics subcommand (``table_arguments``).

    With ``--kappa`` the wall, ``--H`` and ``--b0`` are lengths in the unit of κ's value and are
    divided by it: the billiard is always in units of κ (η = y/κ, paper eq. 8).
    """
    from coinwall.forward.dynamics.billiard import Billiard
    from coinwall.forward.errors import InvalidArgument

    for name, value in (("--H", args.H), ("--b0", args.b0)):
        if not math.isfinite(value):
            raise InvalidArgument(f"{name} must be a finite number, got {value}")
    kappa = args.kappa
    if kappa is not None and not (math.isfinite(kappa) and kappa > 0):
        raise InvalidArgument(f"--kappa must be a positive length, got {kappa}")
    wall = load_wall(args.wall, args.param)
    if kappa is None:
        return wall, Billiard(wall, args.H, args.b0)
    return wall, Billiard(wall.scaled(1.0 / kappa), args.H / kappa, args.b0 / kappa)


def load_wall(text, params):
    """The :class:`forward.Wall` named on the command line (expression, .csv samples, .json Fourier)."""
    from coinwall.forward import Wall
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.expression import parse_param
    from coinwall.forward.formats.wallfile import load_wall_file

    values = dict(parse_param(p) for p in params)
    if text.startswith("case:"):
        from ..catalog import get_case

        if values:
            raise InvalidWall(f"--param does not apply to {text!r}: a case fixes its own parameters")
        return get_case(text).wall()
    lower = text.lower()
    if lower.endswith(".csv") or lower.endswith(".json"):
        if values:
            raise InvalidWall(f"--param applies to expressions, not to the wall file {text!r}")
        return load_wall_file(text)
    return Wall.from_expression(text, values)


def progress_bar(args, total, unit):
    """A tqdm progress bar on stderr when stderr is a terminal and the output is not JSON, else None."""
    if args.json or not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    try:
        columns, lines = os.get_terminal_size(sys.stderr.fileno())
    except OSError:
        columns = lines = 0
    # a terminal that reports no size (0 × 0: some containers, CI and editor pseudo-terminals) makes
    # tqdm take −1 rows and silently hide the bar; give it a standard size instead
    size = {} if columns > 0 and lines > 0 else {"ncols": 80, "nrows": 24}
    return tqdm(total=total, unit=unit, unit_scale=True, file=sys.stderr, leave=False, **size)


def check_positive_count(name, value):
    from coinwall.forward.errors import InvalidArgument

    if value is None or value <= 0:
        raise InvalidArgument(f"{name} must be a positive integer, got {value}")


def check_seed(value):
    from coinwall.forward.errors import InvalidArgument

    if value is not None and value < 0:
        raise InvalidArgument(f"--seed must be a non-negative integer, got {value}")


def parse_com(text):
    from coinwall.forward.errors import InvalidArgument

    if text is None:
        return None
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 2 or not all(math.isfinite(v) for v in values):
        raise InvalidArgument(f"--com must be two numbers X,Y, got {text!r}")
    return tuple(values)


def describe_written(result):
    """One line per written file, with the deviation the exporter achieved (used by solve and export)."""
    lines = []
    for path in result.paths:
        report = result.reports.get(path, {})
        if "polyline" in report:
            lines.append(f"wrote      {path}: SPLINE exact (deviation {report['spline']:.1e}), LWPOLYLINE "
                         f"{report['polyline_vertices']} vertices, deviation {report['polyline']:.3g} "
                         f"<= tolerance {report['tolerance']:.3g} {report['units']}")
        elif "path" in report:
            lines.append(f"wrote      {path}: exact Bézier path (rounding {report['path']:.1e} {report['units']}), "
                         f"largest diameter {report['diameter']:.6g} {report['units']}")
        else:
            lines.append(f"wrote      {path}")
    return lines
