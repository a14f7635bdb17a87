"""``coinwall section``: the bottom-wall Poincaré section of many orbits."""

from __future__ import annotations

import json
import os

from coinwall.forward.formats.output import check_paths, write_all

from .common import check_positive_count, check_seed, load_table, progress_bar, table_arguments

__all__ = ["register"]


def register(subparsers):
    """Add the ``section`` subcommand."""
    section = subparsers.add_parser("section", help="bottom-wall Poincaré section θ_c vs φ_c of many orbits")
    table_arguments(section)
    section.add_argument("--orbits", type=int, default=60, help="number of orbits (default 60)")
    section.add_argument("--collisions", type=int, default=2000, help="collisions per orbit (default 2000)")
    section.add_argument("--seed", type=int, default=None, help="seed of the random start states")
    section.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                         help=".png (figure), .csv (theta,phi,orbit) or .json (repeatable)")
    section.add_argument("--json", action="store_true", help="print a JSON summary (no progress bar)")
    section.set_defaults(run=_cmd_section)


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
