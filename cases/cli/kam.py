"""``coinwall kam``: the KAM boundary of the elliptic billiard."""

from __future__ import annotations

import json
import os
import sys

from .common import (
    add_command,
    count,
    device_argument,
    number,
    progress_bar,
    seed_argument,
    written_lines,
)

__all__ = ["register"]


DESCRIPTION = """\
KAM boundary ε_c(H) of the elliptic billiard, against the paper's fit ε ≈ 1/H + 17/H² (eq. 20).

The wall family is the paper's ellipse wall b(θ) = sqrt((1+eps*cos(t)**2)/(1+eps)), i.e.
sqrt((1 + ε cos²θ)/(1 + ε)): the support function of the ellipse x² + (1+ε) y² = 1, in units of κ.
For each wall distance H, ε is bisected in log ε inside --bracket: at each ε, ORBITS
Liouville-random orbits are classified by their largest Lyapunov exponent (regular if λ per
collision ≤ 3 ln N / N over N = --collisions), and the motion counts as fully chaotic when the
regular fraction is below --regular-max.  Near the boundary the regular orbits are small islands,
so ε_c moves with --seed and --orbits (docs/dynamics.md, "Criterion sensitivity")."""

EXAMPLE = 'coinwall kam --H 2,3,4 --orbits 100 --collisions 1000 -o kam.svg'


def register(subparsers):
    """Add the ``kam`` subcommand."""
    kam = add_command(subparsers, "kam", help="KAM boundary ε_c(H) of the elliptic billiard vs the paper's 1/H + 17/H²",
                      description=DESCRIPTION, example=EXAMPLE)
    kam.add_argument("--H", required=True, metavar="H1,H2,...", help="comma-separated wall distances (units of κ)")
    kam.add_argument("--orbits", type=count, default=100, help="orbits per (ε, H) (default 100)")
    kam.add_argument("--collisions", type=count, default=1000, help="collisions per orbit (default 1000)")
    kam.add_argument("--steps", type=count, default=7, help="bisection steps in log ε (default 7)")
    kam.add_argument("--regular-max", type=number, default=0.01, help="criterion: regular fraction below this (0.01)")
    kam.add_argument("--bracket", default="0.05,50", metavar="LOW,HIGH", help="initial ε bracket (default 0.05,50)")
    seed_argument(kam, "the random start states")
    kam.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                     help="figure (.png, .svg, .pdf) or .json (repeatable)")
    kam.add_argument("--json", action="store_true", help="print the result as JSON (no progress bar)")
    device_argument(kam)
    kam.set_defaults(run=_cmd_kam)


def _floats(text, name):
    from coinwall.forward.validation import parse_number_list

    return parse_number_list(name.lstrip("-").replace("-", "_") if name.startswith("--") else name, text)


def _cmd_kam(args):
    from coinwall.forward.dynamics.analysis.kam import kam_boundary
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, write_all

    H = _floats(args.H, "--H")
    bracket = _floats(args.bracket, "--bracket")
    check_paths(args.output, FIGURE_FORMATS + (".json",))
    with progress_bar(args, len(H) * (args.steps + 2), "eval") as bar:
        result = kam_boundary(H, bracket=tuple(bracket), steps=args.steps, orbits=args.orbits,
                              collisions=args.collisions, regular_max=args.regular_max, seed=args.seed,
                              device=args.device, progress=(lambda: bar.update(1)) if bar is not None else None)
    files = {}
    for path in args.output:
        if os.path.splitext(path)[1].lower() in FIGURE_FORMATS:
            files[path] = figure_bytes(result.plot().figure, path)
        else:
            files[path] = json.dumps(dict(result.to_dict(), seed=args.seed)).encode()
    written = write_all(files)
    missing = result.not_found()
    status = 1 if missing else 0  # a bracket without the boundary is no answer: said, and exit status 1
    if args.json:
        print(json.dumps(dict(result.to_dict(), seed=args.seed), indent=1, allow_nan=False))
        for line in missing:
            print(f"warning: {line} (--bracket)", file=sys.stderr)
        return status
    print(result.table())
    print(f"criterion  regular fraction < {result.regular_max:g} among {result.orbits} orbits × {result.collisions} "
          f"collisions, seed {args.seed} (orbit regular if λ/collision ≤ 3 ln N / N)")
    print("caveat     near the boundary the regular region is small islands (~1 %) and not monotonic in ε: "
          "ε_c moves with --seed and --orbits (docs/dynamics.md, 'Criterion sensitivity')")
    if args.output:
        for line in written_lines(written, written.replaced):
            print(line)
    for line in missing:
        print(f"warning: {line} (--bracket)", file=sys.stderr)
    return status
