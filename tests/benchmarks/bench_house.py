"""Benchmark of the package's house-keeping: Benettin's method in arrays, and the start of the command line.

Run:  python tests/benchmarks/bench_house.py [--smoke] [--orbits 100] [--collisions 1000] [--repeat 3]
(after ``pip install -e ".[test]"``; ``--smoke`` runs every part at a size of a few seconds).

1. Lyapunov exponents of ``orbits`` Liouville-random orbits of the ellipse wall (ε = 3, H = 3):
   :func:`coinwall.forward.dynamics.analysis.lyapunov.lyapunov_many` (one kernel call per renormalisation round,
   bookkeeping on arrays) against the baseline, the same method with a Python loop over the orbits in
   every round (tests/benettin_loop.py, the library's implementation before), in the same process on the
   same states, one thread; the time inside the compiled kernel is measured by wrapping
   ``CompiledKernel.call``, and overhead = total − kernel.  The exponents agree to the bit or within one
   rounding (the same arithmetic, in places in another order).
2. ``coinwall --help`` in a fresh interpreter (best of ``repeat``) against ``python -c pass`` (the
   interpreter's own start, the baseline), alternately, so that a slow phase of the shared machine hits
   both; and whether numpy was imported.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests"))  # the per-orbit loop, tests/benettin_loop.py

from _clock import KernelClock, log  # noqa: E402
from benettin_loop import lyapunov_loop  # noqa: E402

from coinwall.forward.dynamics.analysis.islands import ELLIPSE_WALL  # noqa: E402
from coinwall.forward.dynamics.analysis.lyapunov import lyapunov_many  # noqa: E402
from coinwall.forward.dynamics.billiard.table import Billiard, random_states  # noqa: E402
from coinwall.forward.wall import Wall  # noqa: E402


def timed(function):
    with KernelClock() as clock:
        start = time.perf_counter()
        result = function()
        total = time.perf_counter() - start
    return total, clock.seconds, result


def part_lyapunov(orbits, collisions, repeat):
    table = Billiard(Wall.from_expression(ELLIPSE_WALL, {"eps": 3.0}), 3.0)
    states = random_states(table, orbits, 0)
    lyapunov_many(table, states[:2], 20, workers=1)  # compile/load the kernel first
    lyapunov_loop(table, states[:2], 20, workers=1)
    rows = []
    for _ in range(repeat):  # alternately: a slow phase of the machine hits both
        rows.append((timed(lambda: lyapunov_loop(table, states, collisions, seed=0, workers=1)),
                     timed(lambda: lyapunov_many(table, states, collisions, seed=0, workers=1))))
    (loop_s, loop_k, loop), (many_s, many_k, many) = min(rows, key=lambda r: r[0][0] + r[1][0])
    # the same arithmetic in a different order in places (whole arrays): equal, or one rounding apart
    same = (loop[0] == many.per_collision) | (np.isnan(loop[0]) & np.isnan(many.per_collision))
    spread = np.abs(loop[0] - many.per_collision)[~same]
    ulps = float(np.max(spread / np.spacing(np.abs(loop[0][~same])))) if spread.size else 0.0
    out = {"orbits": orbits, "collisions": collisions, "loop_s": loop_s, "loop_kernel_s": loop_k,
           "lyapunov_many_s": many_s, "lyapunov_many_kernel_s": many_k, "loop_overhead_s": loop_s - loop_k,
           "lyapunov_many_overhead_s": many_s - many_k, "speedup": loop_s / many_s,
           "overhead_ratio": (loop_s - loop_k) / max(many_s - many_k, 1e-9),
           "orbits_not_identical": int(np.count_nonzero(~same)), "largest_difference_ulps": ulps}
    log(f"lyapunov {orbits} orbits x {collisions} collisions: loop {loop_s:.3f} s (kernel {loop_k:.3f} s), "
        f"lyapunov_many {many_s:.3f} s (kernel {many_k:.3f} s): {out['speedup']:.2f}x faster, overhead "
        f"{out['overhead_ratio']:.1f}x smaller; {out['orbits_not_identical']} of {orbits} exponents not identical, "
        f"by at most {ulps:g} ulp")
    return out


def part_startup(repeat):
    check = ("import sys, runpy\nsys.argv = ['coinwall', '--help']\ntry:\n    runpy.run_module('coinwall', "
             "run_name='__main__')\nexcept SystemExit:\n    pass\nsys.stderr.write(str('numpy' in sys.modules))")
    numpy = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True).stderr.strip()
    base, help_ = [], []
    for _ in range(repeat):
        for command, into in (([sys.executable, "-c", "pass"], base), ([sys.executable, "-m", "coinwall", "--help"],
                                                                        help_)):
            start = time.perf_counter()
            subprocess.run(command, capture_output=True, check=True)
            into.append(time.perf_counter() - start)
    out = {"python_s": min(base), "help_s": min(help_), "help_minus_python_s": min(help_) - min(base),
           "numpy_imported": numpy == "True"}
    log(f"coinwall --help {out['help_s']:.3f} s, python -c pass {out['python_s']:.3f} s (ours: "
        f"{out['help_minus_python_s']:.3f} s); numpy imported: {out['numpy_imported']}")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="small sizes: checks that the script runs")
    parser.add_argument("--orbits", type=int, default=100)
    parser.add_argument("--collisions", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", help="write the numbers here")
    args = parser.parse_args()
    orbits, collisions, repeat = (10, 100, 1) if args.smoke else (args.orbits, args.collisions, args.repeat)
    out = {"loadavg_before": os.getloadavg()}
    out["lyapunov"] = part_lyapunov(orbits, collisions, repeat)
    out["startup"] = part_startup(2 if args.smoke else max(repeat, 5))
    out["loadavg_after"] = os.getloadavg()
    print(json.dumps(out, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
