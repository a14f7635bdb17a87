"""Benchmark of the spinning-top billiard kernel (coinwall.forward.dynamics.coin3d.top).

Run:  python tests/benchmarks/bench_coin3d.py [--impacts N] [--smoke]

Three timings of the same orbits in one process (compile time excluded by a warm-up run; best of 3):

* the compiled kernel (impacts per second), a coin on a floor with gravity (e = 1) and between two walls
  without gravity, with precession (ℓz = 0.4, ℓ3 = 0.9);
* its plain-numpy twin (``method="reference"``) and the direct 3-D simulation (rigid3d) on the first
  impacts of the same orbits: the ratios kernel / twin and kernel / 3-D are the headline numbers;
* the planar limit ℓz = ℓ3 = 0 against the planar field kernel (coinwall.forward.dynamics.floor.field) on the
  same coin section, a floor with gravity: how much the 3-D generality costs.
"""

import argparse
import math
import time

from coinwall.forward.dynamics.coin3d.rigid3d import Rigid3D, from_reduced, simulate_3d
from coinwall.forward.dynamics.coin3d.top import TopTable, top_run
from coinwall.forward.dynamics.floor.field import FieldTable, field_run
from coinwall.forward.revolution import coin
from coinwall.forward.wall import Wall

START = [1.0, 3.0, 0.7, 0.3]


def best(fn, rounds=3):
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--impacts", type=int, default=200_000, help="impacts of the kernel runs")
    parser.add_argument("--slow-impacts", type=int, default=100, help="impacts of the twin and the 3-D runs")
    parser.add_argument("--smoke", action="store_true", help="a few seconds: every code path once")
    args = parser.parse_args(argv)
    if args.smoke:
        args.impacts, args.slow_impacts = 2000, 5
    body = coin(1.0, 0.3)
    k1 = body.kappa1
    print("| case | kernel | twin | 3-D | kernel/twin | kernel/3-D |")
    print("|---|---|---|---|---|---|")
    for label, g, H in (("floor, g = 1, e = 1", 1.0, None), ("two walls H = 6, g = 0", 0.0, 6.0)):
        table = TopTable(body, g=g, e=1.0, H=H)
        top_run(table, START, 0.4, 0.9, 10)  # warm-up (compile or load from numba's cache)
        tk = best(lambda: top_run(table, START, 0.4, 0.9, args.impacts)) / args.impacts
        tr = best(lambda: top_run(table, START, 0.4, 0.9, args.slow_impacts, method="reference"), 1) / args.slow_impacts
        system = Rigid3D(body, g=g * k1, e=1.0, H=None if H is None else H * k1)
        state = from_reduced(system, START, 0.4, 0.9)
        t3 = best(lambda: simulate_3d(system, state, args.slow_impacts), 1) / args.slow_impacts
        print(f"| {label} | {1 / tk:,.0f}/s ({tk * 1e6:.2f} µs) | {tr * 1e3:.2f} ms | {t3 * 1e3:.2f} ms | "
              f"{tr / tk:,.0f}× | {t3 / tk:,.0f}× |")
    wall = Wall.from_expression("(r*abs(sin(t)) + d*abs(cos(t)))/k", {"r": 1.0, "d": 0.15, "k": k1})
    planar = FieldTable(wall, g=0.0, e=1.0, H=6.0)
    top = TopTable(body, g=0.0, e=1.0, H=6.0)
    field_run(planar, START, 10)
    top_run(top, START, 0.0, 0.0, 10)
    tp = best(lambda: field_run(planar, START, args.impacts)) / args.impacts
    tt = best(lambda: top_run(top, START, 0.0, 0.0, args.impacts)) / args.impacts
    print(f"\nplanar limit (two walls H = 6, g = 0): field kernel {tp * 1e6:.2f} µs, top kernel {tt * 1e6:.2f} µs "
          f"per impact: top / field = {tt / tp:.2f}")
    if math.isfinite(tt):
        return 0
    return 1


if __name__ == "__main__":
    raise SystemExit(main())
