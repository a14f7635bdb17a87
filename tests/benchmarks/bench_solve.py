"""Benchmark: solve + verify a 10,000-node outline vs evaluating b, b', b'' on the same grid.

Run:  python tests/benchmarks/bench_solve.py [--smoke]
Both timings are taken in the same run, interleaved (eval, solve, eval, solve, ...) so that load
from other processes hits both alike; medians of the repeats.  Targets: absolute < 0.5 s, round trip
≤ 1e-10.  The ratio to the evaluation was tracked against "≤ 5" while the wall was evaluated by casadi's
block calls; since it is evaluated by numpy replaying casadi's algorithm (7–8× faster) the ratio measures
the evaluation's speed-up more than the solver's overhead (21–27 in docs/performance.md), and is printed,
not targeted.
The last line writes the JSON body of a 10⁵-node solve (``coinwall.inverse.export.jsonfile.write``) against
``json.dumps`` of the same document with ``indent=1`` (json's Python encoder), alternately, CPU time, best of 3.
``--smoke``: 1,000 nodes, 2 repeats (a few seconds: checks the script, not the numbers).
"""

import argparse
import io
import json
import statistics
import time

import numpy as np

from coinwall.forward import Wall
from coinwall.inverse import solve_body

N = 10_000
REPEATS = 15


def _timed(func):
    start = time.perf_counter()
    result = func()
    return time.perf_counter() - start, result


def median_times(baseline, func, repeats=REPEATS):
    """Medians of interleaved timings of ``baseline`` and ``func``, and the last result of ``func``."""
    base, times = [], []
    for _ in range(repeats):
        base.append(_timed(baseline)[0])
        elapsed, result = _timed(func)
        times.append(elapsed)
    return statistics.median(base), statistics.median(times), result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="1,000 nodes, 2 repeats: checks the script")
    args = parser.parse_args(argv)
    n, repeats = (1000, 2) if args.smoke else (N, REPEATS)
    wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
    for b0 in (0.0, -0.5, -0.6):
        t_eval, t_solve, body = median_times(lambda: wall.derivatives(theta), lambda: solve_body(wall, b0, points=n),
                                             repeats=repeats)
        _, t_cross, crossed = median_times(lambda: None, lambda: solve_body(wall, b0, points=n, cross_check=True),
                                           repeats=min(3, repeats))
        print(f"b0={b0:+.2f} regime={body.regime:8s} eval b,b',b''={t_eval * 1e3:7.2f} ms  "
              f"solve+verify={t_solve * 1e3:7.2f} ms  ratio={t_solve / t_eval:5.2f}  "
              f"round-trip error={body.max_wall_error:.1e}  "
              f"with polar cross-check={t_cross * 1e3:7.1f} ms (agree {crossed.cross_check:.1e})")
    json_writer(10 * n, repeats=min(3, repeats))


def json_writer(n, repeats=3):
    """The JSON body of an ``n``-node solve, written by the exporter and by ``json.dumps(..., indent=1)``."""
    from coinwall.inverse.export import jsonfile

    wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    body = solve_body(wall, -0.5, points=n)
    ours, indented = [], []
    for _ in range(repeats):
        start = time.process_time()
        stream = io.BytesIO()
        jsonfile.write(body, stream)
        ours.append(time.process_time() - start)
        start = time.process_time()
        text = json.dumps(jsonfile.body_document(body), indent=1, allow_nan=False)
        indented.append(time.process_time() - start)
    assert json.loads(stream.getvalue()) == json.loads(text)  # the same document
    print(f"JSON body of {len(body.points)} nodes ({len(stream.getvalue()) / 1e6:.1f} MB): exporter "
          f"{min(ours):.3f} s, json.dumps(indent=1) {min(indented):.3f} s, ratio {min(ours) / min(indented):.2f} "
          "(CPU time, best of each)")


if __name__ == "__main__":
    main()
