"""``coinwall wall``: body outline (file, or ``--polar R(α)``) -> wall function b(θ) (the forward direction)."""

from __future__ import annotations

import json
import math

from .common import add_command, count, number, parse_com, parse_params, written_lines

__all__ = ["BODY_SIZE", "MAX_H", "MAX_SAMPLES", "SAMPLE_BYTES", "WALL_TOLERANCE", "register"]

#: the support function is exact to rounding: a value within 1e-12 of the largest |b| of zero is
#: rounding and prints as 0 (a centre of mass on the boundary gives b = 0 there); the scale solve_body
#: uses for the same purpose (collapsing nodes, zero area)
WALL_TOLERANCE = 1e-12

_TABLES = (".csv", ".json")

#: --samples: at least 8 angles; at most 10⁷: 260 bytes and 7 µs an angle (`coinwall wall --polar 1 --samples
#: 1000000 -o w.csv` peaks at 350 MB, 90 MB of it the interpreter), so about 2.6 GB and a minute at the bound
MAX_SAMPLES = 10_000_000
SAMPLE_BYTES = 300
#: the largest distance of the body from its centre of mass, in units of κ: from 1e-6 to 1e6 (a physical
#: body has at least 1, since κ never exceeds it; far outside, squares of coordinates overflow or vanish)
BODY_SIZE = (1e-6, 1e6)
#: --H: a wall distance in units of κ; beyond 1e15 the upper wall H − b(θ+π) keeps no digit of b
MAX_H = 1e15

_DESCRIPTION = """\
The forward direction: the wall function b(θ) of a body, i.e. its support function about the
centre of mass h(θ) = max over the body of x·(cos θ, sin θ), in units of the radius of gyration κ,
at uniform angles θ in [0, 2π); with --H the upper wall t(θ) = H - b(θ + π) too.  The body is a
drawing (.json from `coinwall solve`, .csv points, .svg, .dxf) or a polar curve R(α) about the
centre of mass.  Non-convex outlines are replaced by their convex hull (concave parts never touch a
wall).  Scale: --kappa is a length in --units, by default the drawing's own unit (SVG width/height over
its viewBox, DXF $INSUNITS); a drawing that records no unit is taken to be in --units.  Closed chains
of DXF LINE and ARC are outlines.  --element ID (SVG) or --layer NAME (DXF) picks one shape; several
shapes that each add to the hull are merged with a warning on stderr (exit status 0), and a
page-sized background rectangle is left out with a note.  The .csv output is a wall file that
`coinwall solve` reads back."""

_EXAMPLE = """\
coinwall wall --polar "1/sqrt(1+eps*sin(t)**2)" --param eps=1 --H 3 -o ellipse_wall.csv -o ellipse_wall.svg"""


def register(subparsers):
    """Add the ``wall`` subcommand."""
    parser = add_command(subparsers, "wall",
                         help="body outline (.json/.csv/.svg/.dxf, or --polar R(α)) -> wall function b(θ)",
                         description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("body", nargs="?", default=None,
                        help="body file: .json from solve, .csv x,y points, .svg (closed paths, polygons, rects, "
                             "circles, ellipses) or .dxf (LWPOLYLINE POLYLINE SPLINE CIRCLE ELLIPSE ARC)")
    parser.add_argument("--polar", default=None, metavar="EXPR",
                        help="instead of a file: the outline R(α) about the centre of mass, an expression in t")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="parameter of the --polar expression (repeatable)")
    parser.add_argument("--layer", default=None,
                        help="DXF layer to read (default: all layers but annotation layers, ANNOTATION*)")
    parser.add_argument("--element", default=None, metavar="ID", help="SVG: read only the element with this id")
    parser.add_argument("--com", default=None, metavar="X,Y",
                        help="centre of mass in drawing coordinates, as written in the file and in its units (SVG: "
                             "user units, y down; DXF: y up); default: as recorded by coinwall, else the centroid")
    parser.add_argument("--kappa", type=number, default=None,
                        help="radius of gyration in --units (default: as recorded by coinwall, else 1 drawing unit)")
    parser.add_argument("--units", choices=["mm", "cm", "m", "in", "pt", "px"], default=None,
                        help="unit of --kappa (default: the drawing's own unit, from SVG width/height and viewBox "
                             "or DXF $INSUNITS; a drawing that records none is taken to be in --units)")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help=".csv (theta,b[,t]: feeds 'coinwall solve'), .json, or a figure of the body and its "
                             "wall: .png, .svg or .pdf (repeatable; missing folders are created)")
    parser.add_argument("--H", type=number, default=None,
                        help="wall distance, > 0 and at most 1e15: also write the upper wall t(θ)")
    parser.add_argument("--samples", type=count, default=720,
                        help=f"number of angles, 8 to {MAX_SAMPLES:,} (default 720)")
    parser.add_argument("--json", action="store_true", help="print JSON (full precision)")
    parser.set_defaults(run=run)


def _load(args):
    """The outline named on the command line, its note and a description of where it came from."""
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.formats import outline_from_polar
    from coinwall.forward.formats.load import read_outline

    if (args.body is None) == (args.polar is None):
        raise InvalidArgument("give a body file or --polar EXPR (R(α) about the centre of mass), not both or neither")
    com = parse_com(args.com)
    if args.polar is not None:
        if any(v is not None for v in (args.layer, args.kappa, args.units, args.element)):
            raise InvalidArgument("--layer, --element, --kappa and --units apply to body files, not to --polar")
        outline, note = outline_from_polar(args.polar, parse_params(args.param), com=com)
        return outline, note, f"R(α) = {args.polar}", [], 0.0
    if args.param:
        raise InvalidArgument("--param applies to --polar expressions, not to a body file")
    reading = read_outline(args.body, layer=args.layer, element=args.element, com=com, kappa=args.kappa,
                           units=args.units)
    return reading.outline, reading.note, args.body, reading.warnings, reading.accuracy


def _table_bytes(path, theta, lower, upper, H, note, accuracy=0.0):
    """The samples as a wall file (.csv ``theta,b[,t]``) or a JSON document, full precision; ``accuracy`` > 0
    (a drawing's flattened curves) is written as the column ``b_halfwidth``, so that the wall read back is an
    interval that holds the drawing's own wall."""
    import io

    import numpy as np

    if path.lower().endswith(".csv"):
        text = io.StringIO()
        sigma = [np.full(theta.size, accuracy)] if accuracy > 0 else []
        text.write("theta,b" + (",t" if upper is not None else "") + (",b_halfwidth" if sigma else "") + "\n")
        np.savetxt(text, np.column_stack([theta, lower] + ([upper] if upper is not None else []) + sigma),
                   delimiter=",", fmt="%.17g")
        return text.getvalue().encode()
    doc = {"theta": theta.tolist(), "b": lower.tolist(), "note": note}
    if accuracy > 0:
        doc["b_halfwidth"] = accuracy
    if upper is not None:
        doc.update(H=H, t=upper.tolist())
    return json.dumps(doc, allow_nan=False).encode()


def run(args):
    """Compute the wall of the body, write the outputs, print the summary."""
    import numpy as np

    from coinwall.forward.display import format_number
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes, new_figure
    from coinwall.forward.formats.output import check_paths, refuse_non_finite, write_all
    from coinwall.forward.support import wall_functions
    from coinwall.forward.validation import check_count, check_memory, check_positive, check_range

    if args.H is not None:
        check_range("H", check_positive("H", args.H), 0.0, MAX_H, why="a wall distance in units of κ")
    H = args.H
    samples = check_count("samples", args.samples, minimum=8)  # "at least 8" for a small request, as before
    samples = check_count("samples", samples, minimum=8, maximum=MAX_SAMPLES)
    check_memory(f"`samples` = {samples} ({SAMPLE_BYTES} bytes per angle)", samples * SAMPLE_BYTES)
    if args.kappa is not None:
        check_positive("kappa", args.kappa)
    check_paths(args.output, _TABLES + FIGURE_FORMATS)
    outline, note, source, warnings, accuracy = _load(args)
    _check_size(outline, args.kappa)
    theta = np.linspace(0, 2 * math.pi, samples, endpoint=False)
    lower, upper = wall_functions(outline, theta, H)
    if upper is not None and not np.any(upper > lower):
        from coinwall.forward.errors import InvalidArgument

        narrowest = float(np.min(lower + (H - upper)))  # b(θ) + b(θ + π): the body's width across the walls
        raise InvalidArgument(f"--H {H:g} is below the body's narrowest width {narrowest:.6g}: the upper wall "
                              "H − b(θ + π) lies below the lower wall b(θ) at every angle (no strip the body fits in)")
    # a body read from a file is checked by its reader; this is the last guard before a file of nan rows
    refuse_non_finite("the wall", b=lower, **({} if upper is None else {"t": upper}))
    files = {}
    for path in args.output:
        if path.lower().endswith(_TABLES):
            files[path] = _table_bytes(path, theta, lower, upper, H, note, accuracy)
        else:
            import os

            from coinwall.forward.formats.style import house_style

            with house_style():
                fig, (body_axes, wall_axes) = new_figure(1, 2, figsize=(10, 4.4), layout="constrained")
                outline.plot(body_axes)
                outline.plot_wall(wall_axes, theta=theta, H=H)
                fig.suptitle(f"Wall of the body {os.path.basename(str(source))}: {theta.size} angles"
                             + (f", H = {H:g} κ" if H is not None else ""))
            files[path] = figure_bytes(fig, path)
    written = write_all(files)
    if args.json:
        print(json.dumps({"body": source, "note": note, "samples": int(theta.size), "b_min": float(lower.min()),
                          "b_max": float(lower.max()), "outputs": args.output, "warnings": warnings},
                         indent=1, allow_nan=False))
        _print_warnings(warnings)
        return 0
    tolerance = WALL_TOLERANCE * max(1.0, float(np.max(np.abs(lower))))
    print(f"body       {source} ({note})")
    print(f"wall       b(θ) from {format_number(lower.min(), tolerance)} to {format_number(lower.max(), tolerance)} "
          f"on {theta.size} angles")
    for line in written_lines(written, written.replaced):
        print(line)
    _print_warnings(warnings)
    return 0


def _check_size(outline, kappa):
    """The body, in units of κ, measures between 1e-6 and 1e6 from its centre of mass (``BODY_SIZE``).

    ``--kappa`` divides a drawing's coordinates; a tiny or huge κ gives numbers whose squares overflow or
    vanish (``--kappa 1e-300`` gave coordinates near 1e300 and overflowing squares).
    """
    import numpy as np

    from coinwall.forward.errors import InvalidArgument

    size = float(np.max(np.hypot(*np.asarray(outline.nodes, float).T)))
    low, high = BODY_SIZE
    if not low <= size <= high:
        scale = f" with --kappa {kappa:g}" if kappa is not None else ""
        raise InvalidArgument(f"the body reaches {size:.3g} radii of gyration from its centre of mass{scale}; "
                              f"it must be between {low:g} and {high:g} κ (a physical body: at least 1)")


def _print_warnings(warnings):
    """Warnings on stderr; the exit status stays 0, since the wall of the merged hull is well defined."""
    import sys

    for warning in warnings:
        print(f"warning: {_as_flags(warning)}", file=sys.stderr)


def _as_flags(text):
    """The library names arguments (`element`); the command line names flags (--element)."""
    for name in ("element", "layer", "kappa", "units"):
        text = text.replace(f"`{name}`", f"--{name}")
    return text
