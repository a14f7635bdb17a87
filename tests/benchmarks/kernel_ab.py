"""The billiard kernel of one git revision against another's, in one process, alternately; CPU time.

Run:  python tests/benchmarks/kernel_ab.py REV_A REV_B [--collisions N] [--rounds R]

For work on the kernel: the texts of ``forward/dynamics/billiard/_kernel.py`` and ``_search.py`` at each revision (``git
show``; a revision is anything git names: a commit, a branch, ``HEAD``) are compiled against the coin's wall (ε =
99) like the kernel and run on the same orbit at H = 3, alternately for R rounds, after one warm-up run each.  It
prints the median ns per collision of each and the median of the per-round ratios B / A.  On this shared machine a
single timing moves by tens of per cent from day to day and by a few per cent from round to round; a ratio
between two kernels run alternately in one process moves by ~±0.02.  Both revisions must read the cell table of
the working tree (``cellbounds.py`` unchanged since either): the script refuses otherwise.
"""

import argparse
import pathlib
import statistics
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
# the kernel's room, and where its files lay before forward/dynamics/ was divided into rooms
FOLDERS = ("forward/dynamics/billiard", "forward/dynamics")


def _show(revision, name):
    """The text of the kernel file ``name`` at ``revision``, wherever the kernel's room was then."""
    for folder in FOLDERS:
        done = subprocess.run(["git", "-C", str(ROOT), "show", f"{revision}:{folder}/{name}"], capture_output=True,
                              text=True)
        if done.returncode == 0:
            return done.stdout
    raise SystemExit(f"kernel_ab: {revision} has no {name} in {' or '.join(FOLDERS)}")


def _code(text):
    """A module's text without its relative imports (they changed when the kernel moved into its room)."""
    return [line for line in text.splitlines() if not line.startswith("from .")]


def kernel_text(revision):
    """The compiled part of the kernel and the search at ``revision``: the search's text, then the kernel's."""
    from coinwall.forward.dynamics.billiard.kernel import _MARKER, _SEARCH_MARKER

    if subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--verify", "--quiet", f"{revision}^{{commit}}"],
                      capture_output=True).returncode != 0:
        raise SystemExit(f"kernel_ab: {revision!r} names no commit of this repository")
    if _code(_show(revision, "cellbounds.py")) != _code((ROOT / FOLDERS[0] / "cellbounds.py").read_text(encoding="utf-8")):
        raise SystemExit(f"kernel_ab: {revision} has another cellbounds.py than the working tree: its kernel "
                         "would read a cell table it was not written for")
    kernel = _show(revision, "_kernel.py").partition(_MARKER)[2]
    search = _show(revision, "_search.py").partition(_SEARCH_MARKER)[2]
    if not kernel or not search:
        raise SystemExit(f"kernel_ab: {revision}'s kernel files have no marker line")
    return search + kernel


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("a", metavar="REV_A")
    parser.add_argument("b", metavar="REV_B")
    parser.add_argument("--collisions", type=int, default=300_000)
    parser.add_argument("--rounds", type=int, default=9)
    args = parser.parse_args(argv)

    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    from bench_billiard import _cpu_run

    from coinwall.cases.ellipse import ellipse_wall
    from coinwall.forward.dynamics.billiard.kernel import HEADER, compiled
    from coinwall.forward.dynamics.billiard.table import Billiard, random_states
    from coinwall.forward.dynamics.billiard.wallcode import load_module, seal, wall_source

    table = Billiard(ellipse_wall(99.0), 3.0)
    run_args = compiled(table).args(table)
    source, _ = wall_source(table.wall, "@njit(**OPTIONS)\n")
    modules = [load_module(HEADER + source + kernel_text(rev), "coinwall_kernel_ab") for rev in (args.a, args.b)]
    state = random_states(table, 1, 1)[0]
    n = args.collisions

    def ns_per_collision(module):  # bench_billiard's run: it refuses an orbit that stopped early
        return _cpu_run(module, state, n, run_args)[0] / n * 1e9

    for module in modules:  # compile or load, then record the cache files (the next process trusts them)
        ns_per_collision(module)
        seal(module)
    times = [[], []]
    for _ in range(args.rounds):
        for k, module in enumerate(modules):
            times[k].append(ns_per_collision(module))
    ratios = [b / a for a, b in zip(*times)]
    print(f"coin eps = 99, H = 3, {n} collisions a run, {args.rounds} alternating rounds, CPU time, one thread: "
          f"{args.a} {statistics.median(times[0]):.0f} ns/collision, {args.b} {statistics.median(times[1]):.0f} "
          f"ns/collision, ratio B/A {statistics.median(ratios):.3f} (rounds: "
          f"{', '.join(f'{r:.3f}' for r in ratios)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
