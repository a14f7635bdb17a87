"""``coinwall critical``: the exact critical offset ``b_c = −min_θ (b + b'')`` of a wall."""

from __future__ import annotations

import json
import math

from coinwall.inverse.tolerances import OFFSET_TOLERANCE

from .common import add_command, wall_arguments

__all__ = ["register"]

_DESCRIPTION = """\
The exact critical offset b_c = -min over θ of (b + b''), and the angles where the minimum is
attained (where b + b'' is minimal on whole arcs, as for the stick, those intervals).  b0 + b + b''
is the radius of curvature of the body with wall b0 + b: below b_c no convex body has that wall,
at b_c the curvature is infinite at those angles.  b_c = inf means a concave kink of the wall (b'
jumps down), which no offset repairs.  The minimum is sought over all angles, not only at the
extrema of b where the paper's Appendix estimated it: for a formula, from certified bounds of
b + b'' on cells of the whole period, so b_c comes with a certified tolerance and every angle where
the minimum is attained is listed, each with the width within which it is known (JSON: angle_errors).
Walls given as samples get the certified interval the data allow."""

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
    from coinwall.forward.display import format_number, format_within
    from coinwall.inverse import critical_offset
    from coinwall.inverse.critical import format_critical_angles

    from .common import load_wall, wall_options, wall_params

    wall = load_wall(args.wall, args.param, **wall_options(args))
    result = critical_offset(wall)
    finite = math.isfinite(result.b_c)
    if args.json:
        doc = {"wall": args.wall, "params": wall_params(wall),
               "b_c": result.b_c if finite else None, "b_c_infinite": not finite,
               "b_c_tolerance": result.b_c_tolerance,
               "angles": list(result.angles), "intervals": [list(i) for i in result.intervals]}
        if result.lower is not None:
            statistical = wall.sample_data.sd is not None
            doc.update({"b_c_lower": result.lower, "b_c_upper": result.upper, "assumption": result.assumption,
                        "interval": "confidence" if statistical else "certified",
                        "angle_tolerance": result.angle_tolerance,
                        "samples": int(wall.samples[0].size), "samples_used": result.samples_used})
        if result.angle_errors:
            doc.update({"angle_errors": list(result.angle_errors), "spread": result.spread})
        if result.uncertified:
            doc["uncertified"] = [list(w) for w in result.uncertified]
        print(json.dumps(doc, indent=1, allow_nan=False))
        return 0
    print(f"wall       {wall!r}")
    if finite:
        # the shortest decimal the certificate allows (a data wall prints its interval below)
        line = f"b_c        {format_within(result.b_c, result.b_c_tolerance)}"
        if result.angle_errors:
            outside = " outside the angles noted below" if result.uncertified else ""
            line += f" (certified to ±{result.b_c_tolerance:.1g}{outside})"
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
        angles, _ = format_critical_angles(result.angles)
        print(f"angles     {angles} (rad, every angle where b + b'' may be smallest, "
              f"each to ±{result.angle_tolerance:.2g})")
    else:
        angles, spread = format_critical_angles(result.angles, result.angle_errors)
        every = f"; every minimiser within {spread} of one" if spread else ""
        print(f"angles     {angles} (rad, where b + b'' is smallest{every})")
    for lo, hi in result.intervals:
        print(f"interval   b + b'' is minimal on [{format_number(lo)}, {format_number(hi)}]")
    if result.uncertified:
        where = ", ".join(f"θ = {0.5 * (lo + hi):.6g} ± {0.5 * (hi - lo):.0e}" if hi - lo < 1e-6 else
                          f"[{format_number(lo)}, {format_number(hi)}]" for lo, hi in result.uncertified)
        print(f"note       not certified at {where}: b + b'' has no bound there that narrows (b'' unbounded, or "
              "two branches of a max equal on an arc); its sampled values stand in")
    return 0
