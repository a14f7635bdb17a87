"""Benchmark: `coinwall solve` end to end (fresh processes), this tree against a baseline checkout.

Run:  python tests/benchmarks/bench_solve_cli.py [--base-python PATH] [--repeats 5] [--smoke]

Two commands, each timed as a whole process (interpreter start, imports, the solve with its default
cross-check, κ_max, the JSON summary, exit):

* a formula wall at 10⁵ outline points: ``coinwall solve "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=1
  --points 100000 --json``;
* the built-in example: ``coinwall solve --json``.

``--base-python`` names the Python of another checkout with coinwall installed (e.g. a worktree of an
older commit with its own venv); the two trees' runs alternate (base, this, base, this, …) so that load
from other processes hits both alike, and the ratio of the medians is reported.  Peak memory is the
process's VmHWM (/proc/self/status) at exit.  The two trees' JSON summaries are compared: every
number but the timing must agree to 1e-9 relative.  Bytecode is cached as for an installed package, and
each tree has one uncounted warm-up run.  ``--smoke``: 1,000 points, one run, no baseline.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

WALL = "sqrt((1+eps*cos(t)**2)/(1+eps))"
CHILD = """
import sys
from coinwall.cases.cli.main import main
try:
    status = main(sys.argv[1:])
finally:
    peak = [int(line.split()[1]) for line in open("/proc/self/status") if line.startswith("VmHWM")][0] / 1024
    print(f"VmHWM {peak:.1f}", file=sys.stderr)
sys.exit(status)
"""


#: bytecode is written and read, as for an installed package (an environment may set PYTHONDONTWRITEBYTECODE,
#: and then every run compiles each module of coinwall from source: ~0.3 s that a user does not pay)
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def run(python, argv):
    """One fresh process: (seconds end to end, peak MB, JSON document)."""
    start = time.perf_counter()
    # -P: the current folder is not put on sys.path, so each Python imports its own tree's coinwall wherever
    # the benchmark is started (from a checkout's root, `-c` would import that checkout for both)
    done = subprocess.run([python, "-P", "-c", CHILD, *argv], capture_output=True, text=True, env=ENV)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{python} coinwall {' '.join(argv)} exited {done.returncode}: {done.stderr[-2000:]}")
    peak = float(done.stderr.strip().splitlines()[-1].split()[1])
    return seconds, peak, json.loads(done.stdout)


def differences(a, b, path=""):
    """Paths where two JSON documents differ by more than 1e-9 relative (timings ignored)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for key in sorted(set(a) | set(b)):
            if key != "seconds":
                out += differences(a.get(key), b.get(key), f"{path}.{key}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: {len(a)} vs {len(b)} items"]
        return [d for k, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, f"{path}[{k}]")]
    if isinstance(a, float) and isinstance(b, float):
        close = math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12) or (math.isnan(a) and math.isnan(b))
        return [] if close else [f"{path}: {a!r} vs {b!r}"]
    return [] if a == b else [f"{path}: {a!r} vs {b!r}"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base-python", default=None, help="Python of the baseline checkout (coinwall installed)")
    parser.add_argument("--repeats", type=int, default=5, help="alternating runs of each tree (default 5)")
    parser.add_argument("--smoke", action="store_true", help="1,000 points, one run, no baseline")
    args = parser.parse_args(argv)
    points = 1000 if args.smoke else 100_000
    repeats = 1 if args.smoke else args.repeats
    base = None if args.smoke else args.base_python
    cases = {f"formula wall, {points:,} points": ["solve", WALL, "--param", "eps=1", "--points", str(points), "--json"],
             "built-in example": ["solve", "--json"]}
    for name, cli in cases.items():
        trees = ([("base", base)] if base else []) + [("this", sys.executable)]
        runs = {tree: [] for tree, _ in trees}
        docs = {}
        for _, python in ([] if args.smoke else trees):  # warm-up, not counted: bytecode, page cache
            run(python, cli)
        for _ in range(repeats):
            for tree, python in trees:
                seconds, peak, doc = run(python, cli)
                runs[tree].append((seconds, peak))
                docs[tree] = doc
        print(f"{name}: coinwall {' '.join(cli)}")
        for tree, _ in trees:
            times = [t for t, _ in runs[tree]]
            print(f"  {tree:4s}: {statistics.median(times):.2f} s (runs {', '.join(f'{t:.2f}' for t in times)}), "
                  f"peak {max(p for _, p in runs[tree]):.0f} MB")
        if base:
            ratio = statistics.median(t for t, _ in runs["base"]) / statistics.median(t for t, _ in runs["this"])
            diff = differences(docs["base"], docs["this"])
            agree = "agree" if not diff else "DIFFER: " + "; ".join(diff)
            print(f"  ratio base / this: {ratio:.2f}; summaries {agree}")


if __name__ == "__main__":
    main()
