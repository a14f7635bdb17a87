"""``coinwall section | correlation | kam``: Poincaré sections, heads/tails correlation P(n), KAM boundary."""

from __future__ import annotations

import json
import math
import os

from coinwall.forward.formats.output import check_paths, write_all
from .common import check_positive_count, check_seed, load_table, progress_bar, table_arguments

__all__ = ["register"]


def register(subparsers):
    """Add the ``section``, ``correlation`` and ``kam`` subcommands."""

    section = subparsers.add_parser("section", help="bottom-wall Poincaré section θ_c vs φ_c of many orbits")
    table_arguments(section)
    section.add_argument("--orbits", type=int, default=60, help="number of orbits (default 60)")
    section.add_argument("--collisions", type=int, default=2000, help="collisions per orbit (default 2000)")
    section.add_argument("--seed", type=int, default=None, help="seed of the random start states")
    section.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                         help=".png (figure), .csv (theta,phi,orbit) or .json (repeatable)")
    section.add_argument("--json", action="store_true", help="print a JSON summary (no progress bar)")
    section.set_defaults(run=_cmd_section)

    corr = subparsers.add_parser("correlation", help="heads/tails correlation P(n), decay time τ, bounces needed")
    table_arguments(corr)
    corr.add_argument("--bounces", type=int, default=1_000_000, help="counted collisions in total (default 1e6)")
    corr.add_argument("--max-lag", type=int, default=40, help="largest n (default 40)")
    corr.add_argument("--orbits", type=int, default=100, help="independent orbits (default 100)")
    corr.add_argument("--count", choices=["bottom", "all"], default="bottom",
                      help="n counts bottom collisions (default) or collisions with either wall")
    corr.add_argument("--seed", type=int, default=None, help="seed of the random start states")
    corr.add_argument("-o", "--output", action="append", default=[], metavar="FILE", help=".png or .json (repeatable)")
    corr.add_argument("--json", action="store_true", help="print the result as JSON (no progress bar)")
    corr.set_defaults(run=_cmd_correlation)

    kam = subparsers.add_parser("kam", help="KAM boundary ε_c(H) of the elliptic billiard vs the paper's 1/H + 17/H²")
    kam.add_argument("--H", required=True, metavar="H1,H2,...", help="comma-separated wall distances (units of κ)")
    kam.add_argument("--orbits", type=int, default=100, help="orbits per (ε, H) (default 100)")
    kam.add_argument("--collisions", type=int, default=1000, help="collisions per orbit (default 1000)")
    kam.add_argument("--steps", type=int, default=7, help="bisection steps in log ε (default 7)")
    kam.add_argument("--regular-max", type=float, default=0.01, help="criterion: regular fraction below this (0.01)")
    kam.add_argument("--bracket", default="0.05,50", metavar="LOW,HIGH", help="initial ε bracket (default 0.05,50)")
    kam.add_argument("--seed", type=int, default=0, help="seed (default 0)")
    kam.add_argument("-o", "--output", action="append", default=[], metavar="FILE", help=".png or .json (repeatable)")
    kam.add_argument("--json", action="store_true", help="print the result as JSON (no progress bar)")
    kam.set_defaults(run=_cmd_kam)


# ---------------------------------------------------------------------------------------------------- helpers
def _png(draw):
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    draw(ax)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    return buffer.getvalue()


# ---------------------------------------------------------------------------------------------------- section
def _cmd_section(args):
    import io

    import numpy as np

    from coinwall.forward.dynamics.poincare import poincare_section

    check_positive_count("--orbits", args.orbits)
    check_positive_count("--collisions", args.collisions)
    check_seed(args.seed)
    check_paths(args.output, (".png", ".csv", ".json"))
    _, table = load_table(args)
    bar = progress_bar(args, args.orbits, "orbit")
    try:
        result = poincare_section(table, args.orbits, args.collisions, seed=args.seed,
                                  progress=(lambda done: bar.update(done - bar.n)) if bar is not None else None)
    finally:
        if bar is not None:
            bar.close()
    files = {}
    for path in args.output:
        ext = os.path.splitext(path)[1].lower()
        if ext == ".png":
            files[path] = _png(lambda ax: result.plot(ax=ax, title=f"{args.wall} {' '.join(args.param)}, H = {args.H:g}"))
        elif ext == ".csv":
            text = io.StringIO()
            text.write("theta_c,phi_c,orbit\n")
            np.savetxt(text, np.column_stack([result.theta, result.phi, result.orbit]), delimiter=",",
                       fmt=["%.17g", "%.17g", "%d"])
            files[path] = text.getvalue().encode()
        else:
            files[path] = json.dumps(dict(result.to_dict(), wall=args.wall, params=args.param)).encode()
    write_all(files)
    summary = {"wall": args.wall, "params": args.param, "kappa": args.kappa, "H": table.H, "orbits": result.orbits,
               "collisions": result.collisions, "points": int(result.theta.size), "notes": list(result.notes),
               "outputs": args.output}
    if args.json:
        print(json.dumps(summary, indent=1))
    else:
        print(f"section    {result!r}")
        if args.output:
            print(f"wrote      {', '.join(args.output)}")
    return 0


# ---------------------------------------------------------------------------------------------------- correlation
def _cmd_correlation(args):
    from coinwall.forward.dynamics.correlation import correlation
    from coinwall.forward.errors import InvalidArgument

    check_positive_count("--bounces", args.bounces)
    check_positive_count("--max-lag", args.max_lag)
    check_positive_count("--orbits", args.orbits)
    check_seed(args.seed)
    if args.max_lag >= args.bounces:
        raise InvalidArgument(f"--max-lag ({args.max_lag}) must be smaller than --bounces ({args.bounces})")
    check_paths(args.output, (".png", ".json"))
    _, table = load_table(args)
    bar = progress_bar(args, args.bounces, "bounce")
    try:
        result = correlation(table, args.bounces, args.max_lag, orbits=args.orbits, count=args.count, seed=args.seed,
                             progress=(lambda done: bar.update(done - bar.n)) if bar is not None else None)
    finally:
        if bar is not None:
            bar.close()
    doc = dict(result.to_dict(), wall=args.wall, params=args.param, kappa=args.kappa)
    files = {}
    for path in args.output:
        if path.lower().endswith(".png"):
            files[path] = _png(lambda ax: result.plot(ax=ax))
        else:
            files[path] = json.dumps(doc).encode()
    write_all(files)
    if args.json:
        print(json.dumps(doc, indent=1, allow_nan=False))
        return 0
    print(f"table      {table!r}")
    print(f"bounces    {result.bounces} ({result.count} collisions) in {result.orbits} orbits, seed {args.seed}")
    print(f"heads      {result.heads_fraction:.4f} ± {result.heads_stderr:.4f}")
    print("n   P(n)      ±")
    for n, (p, e) in enumerate(zip(result.P, result.P_stderr)):
        print(f"{n:<3d} {p:.5f}  {e:.5f}")
    print(f"tau        {result.tau:.4g} ± {result.tau_stderr:.2g} (fit P(n) − ½ = A exp(−n/τ), A = {result.amplitude:.3g})")
    print(f"n_needed   {result.n_needed} (first n with |P(n) − ½| < 0.01; fit: {result.n_needed_fit:.3g})")
    for note in result.notes:
        print(f"note       {note}")
    return 0


# ---------------------------------------------------------------------------------------------------- kam
def _floats(text, name):
    from coinwall.forward.errors import InvalidArgument

    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        values = []
    if not values or not all(math.isfinite(v) for v in values):
        raise InvalidArgument(f"{name} must be comma-separated numbers, got {text!r}")
    return values


def _cmd_kam(args):
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.dynamics.kam import kam_boundary

    H = _floats(args.H, "--H")
    bracket = _floats(args.bracket, "--bracket")
    if len(bracket) != 2:
        raise InvalidArgument(f"--bracket must be two numbers LOW,HIGH, got {args.bracket!r}")
    check_positive_count("--orbits", args.orbits)
    check_positive_count("--collisions", args.collisions)
    if args.steps < 0:
        raise InvalidArgument(f"--steps must be a non-negative integer, got {args.steps}")
    check_seed(args.seed)
    check_paths(args.output, (".png", ".json"))
    bar = progress_bar(args, len(H) * (args.steps + 2), "eval")
    try:
        result = kam_boundary(H, bracket=tuple(bracket), steps=args.steps, orbits=args.orbits,
                              collisions=args.collisions, regular_max=args.regular_max, seed=args.seed,
                              progress=(lambda: bar.update(1)) if bar is not None else None)
    finally:
        if bar is not None:
            bar.close()
    files = {}
    for path in args.output:
        if path.lower().endswith(".png"):
            files[path] = _png(lambda ax: result.plot(ax=ax))
        else:
            files[path] = json.dumps(result.to_dict()).encode()
    write_all(files)
    if args.json:
        print(json.dumps(result.to_dict(), indent=1, allow_nan=False))
        return 0
    print(result.table())
    print(f"criterion  regular fraction < {result.regular_max:g} among {result.orbits} orbits × {result.collisions} "
          f"collisions (orbit regular if λ/collision ≤ 3 ln N / N)")
    print("caveat     near the boundary the regular region is small islands (~1 %) and not monotonic in ε: "
          "ε_c moves with --seed and --orbits (docs/dynamics.md, 'Criterion sensitivity')")
    if args.output:
        print(f"wrote      {', '.join(args.output)}")
    return 0
