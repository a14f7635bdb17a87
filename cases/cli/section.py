"""``coinwall section``: the bottom-wall Poincaré section of many orbits."""

from __future__ import annotations

import json
import os

from .budget import add_allow_long
from .common import (
    add_command,
    count,
    device_argument,
    load_table,
    progress_bar,
    seed_argument,
    table_arguments,
    wall_params,
    written_lines,
)

__all__ = ["register"]

DESCRIPTION = """\
Poincaré section of the billiard at the bottom wall (the paper's figures 2 and 3).

Follows ORBITS orbits from Liouville-random starts and records, at every collision with the
bottom wall b0 + b(θ), the contact angle θ_c (mod 2π, radians) and the angle of incidence φ_c
between the velocity after the reflection and the wall's inward normal (in [−π/2, π/2], positive
when θ increases).  Islands in the picture are regular motion; a uniform scatter is chaos.
Units: κ (radius of gyration)."""

EXAMPLE = 'coinwall section "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=0.55 --H 1.9 --orbits 60 -o section.svg'


def register(subparsers):
    """Add the ``section`` subcommand."""
    section = add_command(subparsers, "section", help="bottom-wall Poincaré section θ_c vs φ_c of many orbits",
                          description=DESCRIPTION, example=EXAMPLE)
    table_arguments(section)
    section.add_argument("--orbits", type=count, default=60, help="number of orbits (default 60)")
    section.add_argument("--collisions", type=count, default=2000, help="collisions per orbit (default 2000)")
    seed_argument(section, "the random start states")
    section.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                         help="figure (.png, .svg, .pdf), .csv (theta_c,phi_c,orbit) or .json (repeatable)")
    section.add_argument("--json", action="store_true", help="print a JSON summary (no progress bar)")
    device_argument(section)
    add_allow_long(section)
    section.set_defaults(run=_cmd_section)


def _cmd_section(args):
    from coinwall.forward.dynamics.analysis.poincare import poincare_section
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, write_all

    check_paths(args.output, FIGURE_FORMATS + (".csv", ".json"))
    _check_section_memory(args, FIGURE_FORMATS)
    from .budget import check_time
    from .simulate import NS_PER_COLLISION

    check_time(args, args.orbits * args.collisions * NS_PER_COLLISION["kernel"] * 1e-9,
               f"--orbits {args.orbits} × --collisions {args.collisions} ({NS_PER_COLLISION['kernel']:g} ns per "
               "collision)", "fewer --orbits or --collisions")
    wall, table = load_table(args)
    with progress_bar(args, args.orbits, "orbit") as bar:
        result = poincare_section(table, args.orbits, args.collisions, seed=args.seed,
                                  device=args.device,
                                  progress=(lambda done: bar.update(done - bar.n)) if bar is not None else None)
    files = {}
    for path in args.output:
        ext = os.path.splitext(path)[1].lower()
        if ext in FIGURE_FORMATS:
            ax = result.plot(name=args.wall)
            files[path] = figure_bytes(ax.figure, path)
        elif ext == ".csv":
            files[path] = result.to_csv().encode()
        else:
            files[path] = json.dumps(dict(result.to_dict(), wall=args.wall, params=wall_params(wall), seed=args.seed)).encode()
    written = write_all(files)
    summary = {"wall": args.wall, "params": wall_params(wall), "kappa": args.kappa, "H": table.H, "seed": args.seed,
               "orbits": result.orbits,
               "collisions": result.collisions, "points": int(result.theta.size), "notes": list(result.notes),
               "outputs": args.output}
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        print(f"section    {result!r}, seed {args.seed}")
        if args.output:
            for line in written_lines(written, written.replaced):
                print(line)
    return 0


# bytes per point of the section while it is written, by output kind (measured layouts, rounded up): the
# arrays themselves (θ_c, φ_c, orbit: 24), CSV text (~45 characters a row, held as text, its copy and its
# bytes), JSON (three Python floats and list slots per point, 96, and ~60 characters twice) and a figure
# (matplotlib copies each orbit's points into its line and path, ~100)
_POINT_BYTES = {"arrays": 24, ".csv": 135, ".json": 220, "figure": 100}


def _check_section_memory(args, figure_formats):
    """Refuse before any work a section whose points (at most one per collision) and outputs would not fit."""
    from coinwall.forward.validation import check_memory

    kinds = {os.path.splitext(path)[1].lower() for path in args.output}
    per_point = _POINT_BYTES["arrays"] + sum(_POINT_BYTES[k] for k in (".csv", ".json") if k in kinds)
    per_point += _POINT_BYTES["figure"] if kinds & set(figure_formats) else 0
    check_memory(f"--orbits {args.orbits} × --collisions {args.collisions} (up to one point per collision, "
                 f"{per_point} bytes per point with the outputs asked for)", float(per_point) * args.orbits
                 * args.collisions)
