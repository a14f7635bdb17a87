"""A kernel of one git revision against another's, in one process, alternately; CPU time.

Run:  python tests/benchmarks/kernel_ab.py REV_A REV_B [--kernel billiard|field] [--collisions N] [--rounds R]

For work on a kernel: the compiled texts at each revision (``git show``; a revision is anything git names: a
commit, a branch, ``HEAD``; ``.`` is the working tree) are joined to the coin's wall (ε = 99) like the kernel
and run on the same orbit at H = 3, alternately for R rounds, after one warm-up run each.  ``billiard``: the
certified search (``forward/dynamics/billiard/_search.py``) and the billiard kernel (``_kernel.py``) from the
orbit of ``bench_billiard.py``.  ``field``: the search and the field kernel (``forward/dynamics/floor/_field_kernel.py``)
on the toss set-up of ``bench_toss.py`` (g = 1, e = 1, a start that meets the ceiling).  It prints the median
ns per collision of each and the median of the per-round ratios B / A.  A single timing on a shared machine
moves by tens of per cent from day to day and by a few per cent from round to round; a ratio between two
kernels run alternately in one process moves by ~±0.02.  Both revisions run with the arguments and the cell
table of the working tree (``cellbounds.py`` unchanged since either): the script refuses otherwise.
"""

import argparse
import pathlib
import statistics
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
# where each kernel's files lie, and where they lay before forward/dynamics/ was divided into rooms
FOLDERS = {"_search.py": ("forward/dynamics/billiard",), "_kernel.py": ("forward/dynamics/billiard", "forward/dynamics"),
           "cellbounds.py": ("forward/dynamics/billiard", "forward/dynamics"),
           "_field_kernel.py": ("forward/dynamics/floor", "forward/dynamics"),
           "_friction_kernel.py": ("forward/dynamics/floor",), "_contact_kernel.py": ("forward/dynamics/floor",)}


def _show(revision, name):
    """The text of the kernel file ``name`` at ``revision`` (``.``: the working tree), wherever its room was then."""
    for folder in FOLDERS[name]:
        if revision == ".":
            path = ROOT / folder / name
            if path.exists():
                return path.read_text(encoding="utf-8")
            continue
        done = subprocess.run(["git", "-C", str(ROOT), "show", f"{revision}:{folder}/{name}"], capture_output=True,
                              text=True)
        if done.returncode == 0:
            return done.stdout
    raise SystemExit(f"kernel_ab: {revision} has no {name} in {' or '.join(FOLDERS[name])}")


def _code(text):
    """A module's text without its relative imports (they changed when the kernel moved into its room)."""
    return [line for line in text.splitlines() if not line.startswith("from .")]


def kernel_text(revision, kernel="billiard"):
    """The compiled part of ``kernel`` at ``revision``: the search's text, then the kernel's (after their markers)."""
    from coinwall.forward.dynamics.billiard.kernel import _MARKER, _SEARCH_MARKER
    from coinwall.forward.dynamics.floor import fieldkernel

    if revision != "." and subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--verify", "--quiet",
                                           f"{revision}^{{commit}}"], capture_output=True).returncode != 0:
        raise SystemExit(f"kernel_ab: {revision!r} names no commit of this repository")
    if _code(_show(revision, "cellbounds.py")) != _code(_show(".", "cellbounds.py")):
        raise SystemExit(f"kernel_ab: {revision} has another cellbounds.py than the working tree: its kernel "
                         "would read a cell table it was not written for")
    if kernel == "billiard":
        parts = [("_kernel.py", _MARKER)]
    else:  # the field kernel is three texts since friction came (fieldkernel.FIELD_SOURCE); before, it took
        # other arguments (no μ, no rolling resistance, no horizontal velocity), so it is not compared
        parts = [("_friction_kernel.py", fieldkernel._FRICTION_MARKER), ("_contact_kernel.py", fieldkernel._CONTACT_MARKER),
                 ("_field_kernel.py", fieldkernel._MARKER)]
        if revision != "." and subprocess.run(["git", "-C", str(ROOT), "cat-file", "-e",
                                               f"{revision}:forward/dynamics/floor/_friction_kernel.py"],
                                              capture_output=True).returncode != 0:
            raise SystemExit(f"kernel_ab: {revision} has no friction kernel: its field kernel takes other "
                             "arguments; compare two revisions that have forward/dynamics/floor/_friction_kernel.py")
    text = "".join(_show(revision, name).partition(marker)[2] for name, marker in parts)
    search = _show(revision, "_search.py").partition(_SEARCH_MARKER)[2]
    if not text or not search:
        raise SystemExit(f"kernel_ab: {revision}'s kernel files have no marker line")
    return search + text


def runners(kernel, revisions, collisions):
    """One function per revision that runs its kernel once on the benchmark's orbit (returns CPU seconds)."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    from coinwall.cases.ellipse import ellipse_wall
    from coinwall.forward.dynamics.billiard.kernel import HEADER, compiled
    from coinwall.forward.dynamics.billiard.table import Billiard, random_states
    from coinwall.forward.dynamics.billiard.wallcode import load_module, wall_source

    wall = ellipse_wall(99.0)
    source, _ = wall_source(wall, "@njit(**OPTIONS)\n")
    modules = [load_module(HEADER + source + kernel_text(rev, kernel), f"coinwall_ab_{kernel}") for rev in revisions]
    if kernel == "billiard":
        from bench_billiard import _cpu_run

        table = Billiard(wall, 3.0)
        args, state = compiled(table).args(table), random_states(table, 1, 1)[0]
        return [lambda m=module: _cpu_run(m, state, collisions, args)[0] for module in modules]
    import time

    import numpy as np

    from coinwall.forward.dynamics.floor.field import FieldTable
    from coinwall.forward.dynamics.floor.fieldkernel import _kernel

    table = FieldTable(wall, g=1.0, e=1.0, H=3.0)  # e = 1 between floor and ceiling: the orbit never settles
    comp = _kernel(table)
    state = np.array([0.3, 1.5, 2.0, 1.5, 0.0])  # θ, η, θ̇, η̇, ξ̇
    out = [np.empty(collisions) for _ in range(6)] + [np.empty(collisions, dtype=np.int8)]
    summary = np.empty(9)

    def field_run(module):
        start = time.process_time()
        done = module._run(state, 0, -1, collisions, *comp.args(table), False, table.chatter, *comp.wall_args(table),
                           True, *out, summary)[0]
        if done != collisions:
            raise SystemExit(f"kernel_ab: the field orbit stopped after {done} of {collisions} impacts")
        return time.process_time() - start
    return [lambda m=module: field_run(m) for module in modules]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("a", metavar="REV_A")
    parser.add_argument("b", metavar="REV_B")
    parser.add_argument("--kernel", choices=["billiard", "field"], default="billiard")
    parser.add_argument("--collisions", type=int, default=300_000)
    parser.add_argument("--rounds", type=int, default=9)
    args = parser.parse_args(argv)
    import numba

    numba.set_num_threads(1)
    n = args.collisions
    runs = runners(args.kernel, (args.a, args.b), n)
    for run in runs:  # compile or load
        run()
    times = [[], []]
    for _ in range(args.rounds):
        for k, run in enumerate(runs):
            times[k].append(run() / n * 1e9)
    ratios = [b / a for a, b in zip(*times)]
    print(f"{args.kernel} kernel, coin eps = 99, H = 3, {n} collisions a run, {args.rounds} alternating rounds, CPU "
          f"time, one thread: {args.a} {statistics.median(times[0]):.0f} ns/collision, {args.b} "
          f"{statistics.median(times[1]):.0f} ns/collision, ratio B/A {statistics.median(ratios):.3f} (rounds: "
          f"{', '.join(f'{r:.3f}' for r in ratios)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
