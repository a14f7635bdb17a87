"""``coinwall critical``: the exact critical offset ``b_c = −min_θ (b + b'')`` of a wall."""

from __future__ import annotations

import json
import math

from coinwall.inverse.tolerances import OFFSET_TOLERANCE

from .common import add_command, format_angles, wall_arguments

__all__ = ["register"]

_DESCRIPTION = """\
The exact critical offset b_c = -min over θ of (b + b''), and the angles where the minimum is
attained (where b + b'' is minimal on whole arcs, as for the stick, those intervals).  b0 + b + b''
is the radius of curvature of the body with wall b0 + b: below b_c no convex body has that wall,
at b_c the curvature is infinite at those angles.  b_c = inf means a concave kink of the wall (b'
jumps down), which no offset repairs.  The minimum is sought over all angles, not only at the
extrema of b where the paper's Appendix estimated it."""

_EXAMPLE = """\
coinwall critical "0.2*cos(2*t) + 0.06*sin(3*t)"
coinwall critical "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=1 --json"""


def register(subparsers):
    """Add the ``critical`` subcommand."""
    parser = add_command(subparsers, "critical", help="exact critical offset b_c = -min(b + b'')",
                         description=_DESCRIPTION, example=_EXAMPLE)
    wall_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print JSON (full precision)")
    parser.set_defaults(run=run)


def run(args):
    """Compute the critical offset and print it."""
    from coinwall.forward.display import format_number
    from coinwall.inverse import critical_offset

    from .common import load_wall, wall_options

    wall = load_wall(args.wall, args.param, **wall_options(args))
    result = critical_offset(wall)
    finite = math.isfinite(result.b_c)
    if args.json:
        doc = {"b_c": result.b_c if finite else None, "b_c_infinite": not finite,
               "b_c_tolerance": result.b_c_tolerance,
               "angles": list(result.angles), "intervals": [list(i) for i in result.intervals]}
        if result.lower is not None:
            statistical = wall.sample_data.sd is not None
            doc.update({"b_c_lower": result.lower, "b_c_upper": result.upper, "assumption": result.assumption,
                        "interval": "confidence" if statistical else "certified",
                        "angle_tolerance": result.angle_tolerance,
                        "samples": int(wall.samples[0].size), "samples_used": result.samples_used})
        print(json.dumps(doc, indent=1, allow_nan=False))
        return 0
    print(f"wall       {wall!r}")
    if finite:
        tolerance = max(OFFSET_TOLERANCE * max(1.0, wall.scale), result.b_c_tolerance)
        line = f"b_c        {format_number(result.b_c, tolerance, 15)}"
        statistical = result.lower is not None and wall.sample_data.sd is not None
        if result.lower is not None:
            fine = OFFSET_TOLERANCE * max(1.0, wall.scale)
            kind = "confidence interval" if statistical else "certified in"
            line = (f"b_c        {format_number(result.b_c, fine, 6)} (best estimate), {kind} "
                    f"[{format_number(result.lower, fine, 6)}, {format_number(result.upper, fine, 6)}]")
        print(line)
        if statistical:
            print(f"assuming   {result.assumption}")
        elif result.lower is not None:
            used = "" if result.samples_used == wall.samples[0].size else \
                f" (computed on {result.samples_used} of the {wall.samples[0].size} samples, spaced where the " \
                "interval is narrowest)"
            print(f"certified  lower end: no wall within the samples' intervals has a smaller b_c (a linear "
                  f"programme){used}")
            print(f"assuming   upper end: {result.assumption}")
    else:
        print("b_c        inf (a concave kink: no convex body for any b0)")
    if result.lower is not None:  # data: every angle where the least b + b'' may lie, to the data's resolution
        print(f"angles     {format_angles(result.angles)} (rad, every angle where b + b'' may be smallest, "
              f"each to ±{result.angle_tolerance:.2g})")
    else:
        print(f"angles     {format_angles(result.angles)} (rad, where b + b'' is smallest)")
    for lo, hi in result.intervals:
        print(f"interval   b + b'' is minimal on [{format_number(lo)}, {format_number(hi)}]")
    return 0
