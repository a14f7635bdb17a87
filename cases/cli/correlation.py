"""``coinwall correlation``: the heads/tails correlation P(n) and its decay time."""

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
Heads/tails correlation of the coin (the paper's section III).

Heads: the arrow along the body axis points right at a collision, i.e. sin θ < 0.  P(n) is the
probability that the face (heads or tails) shown at a bottom-wall collision is shown again n
bottom-wall collisions later (with --count all, n counts collisions with either wall); P(0) = 1
and P(n) → ½ when the coin forgets.  Computed over ORBITS independent Liouville-random orbits
(error bars from their spread), with the decay time τ from a fit P(n) − ½ = A exp(−n/τ) and the
first n with |P(n) − ½| < 0.01.  Units: κ (radius of gyration)."""

EXAMPLE = 'coinwall correlation "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=99 --H 2.4 --bounces 200000 -o pn.pdf'


def register(subparsers):
    """Add the ``correlation`` subcommand."""
    corr = add_command(subparsers, "correlation", help="heads/tails correlation P(n), decay time τ, bounces needed",
                       description=DESCRIPTION, example=EXAMPLE)
    table_arguments(corr)
    corr.add_argument("--bounces", type=count, default=1_000_000, help="counted collisions in total (default 1e6)")
    corr.add_argument("--max-lag", type=count, default=40, help="largest n (default 40)")
    corr.add_argument("--orbits", type=count, default=100, help="independent orbits (default 100)")
    corr.add_argument("--count", choices=["bottom", "all"], default="bottom",
                      help="n counts bottom collisions (default) or collisions with either wall")
    seed_argument(corr, "the random start states")
    corr.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                      help="figure (.png, .svg, .pdf) or .json (repeatable)")
    corr.add_argument("--json", action="store_true", help="print the result as JSON (no progress bar)")
    device_argument(corr)
    add_allow_long(corr)
    corr.set_defaults(run=_cmd_correlation)


def _cmd_correlation(args):
    from coinwall.forward.dynamics.analysis.correlation import correlation
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, write_all

    check_paths(args.output, FIGURE_FORMATS + (".json",))
    from .budget import check_time
    from .simulate import NS_PER_COLLISION

    # a bottom bounce takes about two collisions (one with each wall); with --count all, one
    per_bounce = 2 if args.count == "bottom" else 1
    check_time(args, args.bounces * per_bounce * NS_PER_COLLISION["kernel"] * 1e-9,
               f"--bounces {args.bounces} (about {per_bounce} collision(s) each, {NS_PER_COLLISION['kernel']:g} ns "
               "per collision)", "fewer --bounces")
    wall, table = load_table(args)
    with progress_bar(args, args.bounces, "bounce") as bar:
        result = correlation(table, args.bounces, args.max_lag, orbits=args.orbits, count=args.count, seed=args.seed,
                             device=args.device,
                             progress=(lambda done: bar.update(done - bar.n)) if bar is not None else None)
    doc = dict(result.to_dict(), wall=args.wall, params=wall_params(wall), kappa=args.kappa)
    files = {}
    for path in args.output:
        if os.path.splitext(path)[1].lower() in FIGURE_FORMATS:
            files[path] = figure_bytes(result.plot(name=args.wall).figure, path)
        else:
            files[path] = json.dumps(doc).encode()
    written = write_all(files)
    if args.json:
        print(json.dumps(doc, indent=1, allow_nan=False))
        return 0
    print(f"table      {table!r}")
    print(f"bounces    {result.bounces} ({result.count} collisions) in {result.orbits} orbits, seed {args.seed}; the "
          f"errors (±) are from the spread between the {result.orbits} orbits"
          + (" (fewer than 10: rough)" if result.orbits < 10 else ""))
    print(f"heads      {result.heads_fraction:.4f} ± {result.heads_stderr:.4f}")
    print("n   P(n)      ±")
    for n, (p, e) in enumerate(zip(result.P, result.P_stderr)):
        print(f"{n:<3d} {p:.5f}  {e:.5f}")
    from coinwall.forward.estimates import finite_text

    print(f"tau        {finite_text(result.tau, missing='not determined (the fit failed)')} ± "
          f"{finite_text(result.tau_stderr, '.2g')} (fit P(n) − ½ = A exp(−n/τ), A = {finite_text(result.amplitude, '.3g')})")
    needed = result.n_needed if result.n_needed is not None else f"none up to n = {args.max_lag}"
    print(f"n_needed   {needed} (first n with |P(n) − ½| < 0.01; fit: {finite_text(result.n_needed_fit, '.3g')})")
    for note in result.notes:
        print(f"note       {note}")
    if args.output:
        for line in written_lines(written, written.replaced):
            print(line)
    return 0
