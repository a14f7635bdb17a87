"""``coinwall solve``: wall function + offset b0 -> body outline (the inverse problem)."""

from __future__ import annotations

import json
import math

# the tolerances solve_body itself works to; a number below its own tolerance prints as 0
from coinwall.inverse.tolerances import (
    AREA_TOLERANCE,
    DEFAULT_POINTS,
    DEFICIT_TOLERANCE,
    DIRECTION_TOLERANCE,
    OFFSET_TOLERANCE,
)

from .common import add_command, count, describe_written, format_angles, number, wall_arguments

__all__ = ["register"]

_CASES = {"convex": "Case I: convex body",
          "critical": "Case II: critical, convex, infinite curvature at the critical angles",
          "corner": "Case III: no body has this wall; the largest body under it has corners"}

_DESCRIPTION = """\
Solve the inverse problem: the body whose support function about its centre of mass is the wall
b0 + b(θ) (lengths in units of the radius of gyration κ).  Prints the exact critical offset
b_c = -min(b + b'') and where it is attained, the regime (the paper's Appendix: Case I convex,
Case II critical, Case III corners), the body's size, every corner (direction, distance R_c,
half-width of the window of wall angles it governs, largest wall deficit) and the closed-loop check
max |wall(body) - wall|, with the other solver's agreement.  Below b_c the body is the largest
convex body whose wall never exceeds the prescribed one.  Without WALL: the paper's ellipse wall,
eps = 1, at b0 = -0.5 (Fig. 4)."""

_EXAMPLE = """\
coinwall solve "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=1 --b0 -0.6 -o body.json -o figures/body.svg"""


def register(subparsers):
    """Add the ``solve`` subcommand."""
    parser = add_command(subparsers, "solve", help="wall function + offset b0 -> body outline (the inverse problem)",
                         description=_DESCRIPTION, example=_EXAMPLE)
    wall_arguments(parser, optional=True)
    parser.add_argument("--b0", default=None, metavar="B0",
                        help="offset added to the wall (default 0), or 'self-consistent': the offset at which the "
                             "uniform body has κ = 1")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="write the body; format by extension: .svg .dxf .json .csv .png .pdf (repeatable); "
                             "missing folders are created")
    parser.add_argument("--points", type=count, default=DEFAULT_POINTS,
                        help=f"outline nodes (default {DEFAULT_POINTS})")
    parser.add_argument("--method", choices=["envelope", "polar"], default="envelope",
                        help="solver (default envelope; the other one is the cross-check)")
    parser.add_argument("--no-cross-check", action="store_true", help="skip the cross-check with the other solver")
    parser.add_argument("--kappa", type=number, default=None, metavar="VALUE",
                        help="radius of gyration in --units: .svg/.dxf drawn at real size (default: units of kappa)")
    parser.add_argument("--units", choices=["mm", "cm", "in"], default=None, help="unit of --kappa")
    parser.add_argument("--tolerance", type=number, default=None, metavar="T",
                        help="largest deviation of approximated outlines (DXF polyline) in output units")
    parser.add_argument("--cut", action="store_true",
                        help="cut-ready .svg/.dxf: one closed contour on one layer (CUT), no marks or notes")
    parser.add_argument("--nearest", choices=["largest", "least-squares"], default="largest",
                        help="below b_c: the largest body under the wall (default) or the convex body whose wall "
                             "is nearest in least squares (coinwall fit's programme)")
    parser.add_argument("--allow-unrealizable", action="store_true",
                        help="write a real-size drawing (--kappa, --units) even when no mass distribution inside "
                             "the body gives it κ = 1")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")
    parser.set_defaults(run=run)


def _offset(text, wall):
    """--b0 as given: a number, or 'self-consistent' (the offset of the uniform body with κ = 1)."""
    from coinwall.forward.errors import InvalidArgument

    if isinstance(text, (int, float)):
        return float(text)
    if text.strip().lower() == "self-consistent":
        from coinwall.inverse import self_consistent_offset

        found = self_consistent_offset(wall)
        if found.b0 is None:
            raise InvalidArgument("`b0`: no offset gives a uniform body with κ = 1 and its centroid at the origin "
                                  f"(searched b0 in [{found.searched[0]:.6g}, {found.searched[1]:.6g}])")
        return float(found.b0)
    try:
        return number(text)
    except ValueError:
        raise InvalidArgument(f"`b0` must be a number or 'self-consistent', got {text!r}") from None


def _wall_and_offset(args):
    """The wall text, its parameters and b0: as given, a case's own offset, or the built-in example."""
    from .. import EXAMPLE

    if args.wall is None:
        params = [f"{k}={v}" for k, v in EXAMPLE["params"].items()]
        return EXAMPLE["wall"], params, EXAMPLE["b0"] if args.b0 is None else args.b0
    b0 = 0.0 if args.b0 is None else args.b0
    if args.wall.startswith("case:") and args.b0 is None:
        from ..catalog import get_case

        b0 = get_case(args.wall).b0  # a case comes with the offset it is meant for
    return args.wall, args.param, b0


def run(args):
    """Solve, write the outputs, print the summary."""
    from coinwall.forward.display import format_number
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.formats.output import existing_files
    from coinwall.inverse import realizability, solve_body
    from coinwall.inverse.export import ExportOptions, check_outputs, export_body

    from .common import check_body_finite, load_wall, wall_options

    wall_text, params, b0 = _wall_and_offset(args)
    if args.wall is None and not args.json:
        print("No wall given: solving the built-in example, the paper's ellipse wall with eps = 1 at the "
              "critical offset b0 = -0.5 (paper Fig. 4).")
    # bad input fails before any work; missing folders are created only once everything else is good
    ExportOptions(kappa=args.kappa, units=args.units, tolerance=args.tolerance)
    wall = load_wall(wall_text, params, **wall_options(args))
    check_outputs(args.output)
    b0 = _offset(b0, wall)
    body = solve_body(wall, b0, method=args.method, points=args.points, cross_check=not args.no_cross_check)
    fit = None
    if args.nearest == "least-squares" and body.regime == "corner":
        body, fit = _nearest_least_squares(wall, body)
    if args.output:  # before anything else uses the body: a NaN never reaches a file
        check_body_finite(body)
    physical = realizability(body)
    if args.kappa is not None and not physical.realizable and not args.allow_unrealizable and any(
            path.lower().endswith((".svg", ".dxf", ".pdf")) for path in args.output):
        raise InvalidArgument(
            f"`kappa`: no mass distribution inside this body gives it κ = 1 (κ_max = {physical.kappa_max:.4g} κ), "
            "so a part cut at this size would not have this wall; use --b0 self-consistent (the uniform body "
            "with κ = 1) or --allow-unrealizable")
    replaced = existing_files(args.output)
    result = export_body(body, args.output, kappa=args.kappa, units=args.units,
                         tolerance=args.tolerance, cut=args.cut) if args.output else None
    status = 1 if body.warnings else 0
    if args.json:
        doc = body.to_dict()
        doc.update({"kappa_uniform": physical.kappa_uniform,
                    "kappa_max": physical.kappa_max if math.isfinite(physical.kappa_max) else None,
                    "realizable": physical.realizable, "nearest": args.nearest})
        if fit is not None:
            doc.update({"rms_residual": fit.rms_residual, "max_residual": fit.max_residual})
        print(json.dumps(doc, indent=1, allow_nan=False))
        _print_warnings(body)
        return status

    scale = max(1.0, wall.scale)
    if math.isinf(body.b_c):
        b_c = "inf (a concave kink: no offset gives a convex body)"
    else:
        # data: to the digits their interval allows (0 within it)
        known = OFFSET_TOLERANCE * scale if body.wall.samples is None else max(OFFSET_TOLERANCE * scale,
                                                                                body.b_c_tolerance)
        b_c = format_number(body.b_c, known, 12 if body.wall.samples is None else 6)
    import numpy as np

    radius = np.hypot(*body.outline.polygon(16).T)  # between nodes too: a polygon's edge comes nearer
    size = max(1.0, float(body.R.max()))
    print(f"wall       {body.wall!r}")
    print(f"offset     b0 = {body.b0:g}")
    interval = located = ""
    tolerance = OFFSET_TOLERANCE * scale
    if body.b_c_lower is not None and math.isfinite(body.b_c):
        interval = (f" (estimate), certified in [{format_number(body.b_c_lower, tolerance, 6)}, "
                    f"{format_number(body.b_c_upper, tolerance, 6)}] by the samples' intervals")
        located = " (every angle where the least b + b'' may be)"
    elif body.statistics is not None:
        found = body.statistics
        interval = (f" (estimate), {found.level:.0%} confidence interval [{format_number(found.lower, tolerance, 6)}, "
                    f"{format_number(found.upper, tolerance, 6)}] assuming {found.assumption}")
        located = " (where the least b + b'' may be)"
    from coinwall.inverse.critical import format_critical_angles

    angles, spread = format_critical_angles(body.critical_angles, body.critical_angle_errors)
    print(f"critical   b_c = {b_c}{interval} at θ = {angles}" + (f" (each {spread})" if spread else "") + located)
    if body.regime_decided:
        regime = f"{body.regime} ({_CASES[body.regime]})"
    else:
        regime = (f"undecided: the data allow {' or '.join(body.regimes)} at b0 = {body.b0:g}; the body is the "
                  f"simplest one within the samples' intervals ({body.regime})")
    print(f"regime     {regime}")
    print(f"body       {body.x.size} nodes, area {format_number(body.area, AREA_TOLERANCE * size**2)}, "
          f"perimeter {format_number(body.perimeter)}, R from {format_number(radius.min(), 1e-12 * size)} to "
          f"{format_number(radius.max())} (units of κ, along the whole outline)")
    for c in body.corners:
        forced = "" if c.length is None else \
            f"; every body within the samples' intervals turns through it within {c.length:.2g} of boundary"
        print(f"corner     at direction {format_angles([c.direction], DIRECTION_TOLERANCE)} rad, "
              f"distance {format_number(c.distance)}, window ±{format_number(c.half_width)} rad, "
              f"largest wall deficit {format_number(c.max_deficit, DEFICIT_TOLERANCE * wall.scale, 3)}{forced}")
    if body.possible_corners:
        shown = ", ".join(f"{0.5 * (p.window[0] + p.window[1]) % (2 * math.pi):.4g}" for p in body.possible_corners[:8])
        more = f" and {len(body.possible_corners) - 8} more" if len(body.possible_corners) > 8 else ""
        print(f"possible   {len(body.possible_corners)} corner(s) the data allow but do not force, at θ ≈ {shown}"
              f"{more} rad")
    cut = [c.max_deficit for c in body.corners if c.max_deficit > 0]
    where = " outside the corner windows" if cut else ""
    at = " at the samples" if body.wall.samples is not None else ""
    check = f"max |wall(body) − wall|{at}{where} = {body.max_wall_error:.2e} ({body.method})"
    if body.cross_check is not None:
        other = {"envelope": "polar solver", "polar": "envelope solver",
                 "halfplanes": "scipy's HalfspaceIntersection (at the samples)"}.get(body.method, "other solver")
        check += f"; {other} agrees to {body.cross_check:.1e}"
    if cut:
        check += f"; inside them the body's wall is lower, by up to {max(cut):.3g} (the corners' deficits)"
    print(f"check      {check}")
    print(f"outline    convex: {'yes' if body.convex else 'NO'}, simple (valid): {'yes' if body.valid else 'NO'}")
    if body.outline_tolerance is not None:
        print(f"band       the outline is within {body.outline_tolerance:.3g} κ (Hausdorff distance) of every body whose "
              "wall lies in the samples' intervals, the true one among them (outline_tolerance, certified)")
    if fit is not None:
        print(f"fit        nearest convex body in least squares: rms residual {fit.rms_residual:.3g}, "
              f"max {fit.max_residual:.3g}")
    kmax = f"{physical.kappa_max:.6g}" if math.isfinite(physical.kappa_max) else "— (centre of mass not inside)"
    print(f"physical   κ of the uniform body {physical.kappa_uniform:.6g} κ, κ_max {kmax} κ: "
          + ("some mass distribution gives this wall" if physical.realizable
             else "NO mass distribution inside the body gives κ = 1"))
    for note in body.notes:
        print(f"note       {note}")
    if result is not None:
        for line in describe_written(result, replaced):
            print(line)
    _print_warnings(body)
    return status


def _print_warnings(body):
    import sys

    for warning in body.warnings:
        print(f"warning: {warning}", file=sys.stderr)


def _nearest_least_squares(wall, largest):
    """Below b_c: the convex body whose wall is nearest in least squares (inverse.fit), from the wall's
    samples (a sampled wall) or from 1,024 uniform samples of it."""
    import numpy as np

    from coinwall.inverse.fit import fit_convex

    if wall.samples is not None:
        theta, values = wall.samples
    else:
        theta = np.linspace(0.0, 2 * np.pi, 1024, endpoint=False)
        values = wall(theta)
    fit = fit_convex(theta, values, largest.b0)
    return fit.body, fit
