"""Benchmark: walls from dense data — ``coinwall critical`` and ``coinwall solve`` on 10⁶ samples.

Run (one core, as the target is stated):

    taskset -c 0 env OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_dense_data.py

Each input is a CSV of 10⁶ random angles (an ellipse's wall, a 9-gon's wall) written the way people
write them (17, 8 or 4 decimals).  Each command runs in this process (``main([...])``, the file read
included, the interpreter's start-up not), interleaved with a baseline in the same run — numpy's
``loadtxt`` of the same file, the least any reader of it must do — medians of ``--repeats``.  Target:
both commands under 10 s on one core.  The printed table goes into docs/performance.md.
"""

import argparse
import contextlib
import io
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import walldata as W  # noqa: E402

from coinwall.cases.cli.main import main as cli  # noqa: E402

COUNT = 1_000_000


def _write(path, theta, b, decimals):
    fmt = (lambda x: repr(float(x))) if decimals is None else (lambda x: f"{x:.{decimals}f}")
    with open(path, "w") as f:
        f.write("theta,b\n")
        f.write("".join(f"{fmt(t)},{fmt(v)}\n" for t, v in zip(theta, b)))


def _run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli(argv)
    if code == 2:
        raise SystemExit(f"coinwall {' '.join(argv)}: {err.getvalue().strip()}")
    return code, out.getvalue()


def _tolerance(doc):
    band = doc.get("outline_tolerance")
    return "—" if band is None else f"{band:.2g}"


def _timed(func):
    start = time.perf_counter()
    result = func()
    return time.perf_counter() - start, result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--count", type=int, default=COUNT)
    parser.add_argument("--smoke", action="store_true", help="10,000 samples, one repeat: checks the script")
    args = parser.parse_args()
    if args.smoke:
        args.count, args.repeats = 10_000, 1
    theta = W.random_angles(args.count, seed=7, sort=False)
    inputs = {
        "ellipse (1.25, 0.8), 17 digits": (W.smooth("ellipse", theta, semi_axes=(1.25, 0.8)), None),
        "ellipse (1.25, 0.8), 8 decimals": (W.smooth("ellipse", theta, semi_axes=(1.25, 0.8)), 8),
        "ellipse (1.25, 0.8), 4 decimals": (W.smooth("ellipse", theta, semi_axes=(1.25, 0.8)), 4),
        "irregular 9-gon, 8 decimals": (W.polygon(None, theta), 8),
    }
    print(f"{args.count:,} samples per file; medians of {args.repeats}, interleaved with the baseline")
    print("| input | loadtxt (baseline) | critical | ratio | solve | ratio | b_c interval (truth) | regime, corners "
          "| outline tolerance |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, (ref, decimals) in inputs.items():
            path = str(Path(tmp) / "wall.csv")
            _write(path, ref.theta, ref.b, decimals)
            _run(["critical", path])  # warm: imports, first calls
            base, crit, solve = [], [], []
            for _ in range(args.repeats):
                base.append(_timed(lambda: np.loadtxt(path, delimiter=",", skiprows=1))[0])
                crit.append(_timed(lambda: _run(["critical", path, "--json"]))[0])
                t, (code, out) = _timed(lambda: _run(["solve", path, "--json"]))
                solve.append(t)
            import json

            doc = json.loads(out)
            b, c, s = (statistics.median(x) for x in (base, crit, solve))
            print(f"| {name} | {b:.2f} s | {c:.2f} s | {c / b:.1f} | {s:.2f} s | {s / b:.1f} | "
                  f"[{doc['b_c_lower']:.6g}, {doc['b_c_upper']:.6g}] ({ref.b_c:.6g}) | "
                  f"{doc['regime']}{'' if doc['regime_decided'] else ' (undecided)'}, {len(doc['corners'])} "
                  f"(exit {code}) | {_tolerance(doc)} |")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
