"""Benchmark of the field kernel per collision against the field-free billiard kernel.

Run:  python tests/benchmarks/bench_toss.py [--collisions N] [--rounds R] [--smoke]

Same wall (case:coin, the ellipse ε = 99), same strip (H = 3), one thread, compile time excluded (one warm-up
run each).  The compiled ``_run`` of each kernel is called directly (no Trajectory or Flight is built), the
runs alternate for R rounds and each is timed in CPU time (``time.process_time``: a slow phase of the shared
machine that takes the CPU away is not counted); the numbers are medians over the rounds, the ratios medians of
the per-round ratios.  Lines: the billiard kernel; the field kernel with g = 0, e = 1 (the same billiard, the
cost of the field kernel's generality); the field kernel with g = 1, e = 1 and a start energy high enough to
meet the ceiling (the toss set-up with both walls).  The field kernel of one git revision against another's:
``python tests/benchmarks/kernel_ab.py REV_A REV_B --kernel field``.
"""

import argparse
import sys
import time

import numpy as np

from coinwall.forward.dynamics.billiard.kernel import compiled
from coinwall.forward.dynamics.billiard.table import Billiard, random_states
from coinwall.forward.dynamics.floor.field import FieldTable, _kernel, field_run

#: the toss set-up's start (θ, η, v_θ, v_η): with g = 1, e = 1 its energy meets the ceiling at H = 3
TOSS = [0.3, 1.5, 2.0, 1.5]


def _timed(run, n, name):
    """``run`` as a function of no arguments that returns the CPU seconds of one run of ``n`` collisions."""
    def timed():
        start = time.process_time()
        done = run(n)
        seconds = time.process_time() - start
        if done != n:  # a rate over a run that stopped early would be meaningless
            raise RuntimeError(f"{name} stopped after {done} of {n} collisions")
        return seconds
    run(10)  # compile or load
    return timed


def _billiard_runner(table, n):
    comp = compiled(table)
    state = np.ascontiguousarray(random_states(table, 1, seed=1)[0])
    out = [np.empty(n) for _ in range(5)] + [np.empty(n, dtype=np.int8)]
    last = np.empty(2)

    def run(count):
        return comp.module._run(state, 0, -1, count, *comp.args(table), *out, last)[0]
    return _timed(run, n, "the billiard kernel")


def _field_runner(table, start, n, module=None):
    """A timed run of the field kernel (``module``: another revision's, loaded by kernel_ab.py) from ``start``."""
    comp = _kernel(table)
    module = comp.module if module is None else module
    wall_args = comp.wall_args(table)
    state = np.ascontiguousarray(start, dtype=float)
    out = [np.empty(n) for _ in range(5)] + [np.empty(n, dtype=np.int8)]
    summary = np.empty(8)

    def run(count):
        return module._run(state, 0, -1, count, *comp.args(table), False, table.chatter, *wall_args, True, *out,
                           summary)[0]
    return _timed(run, n, "the field kernel")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--collisions", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--smoke", action="store_true",
                        help="a run of a few seconds through every part of the benchmark (numbers meaningless)")
    args = parser.parse_args(argv)
    import numba

    from coinwall.cases.ellipse import ellipse_wall

    numba.set_num_threads(1)
    n, rounds = (20_000, 1) if args.smoke else (args.collisions, args.rounds)
    wall = ellipse_wall(99.0)
    table = Billiard(wall, 3.0)
    free = FieldTable(wall, g=0.0, e=1.0, H=3.0)
    grav = FieldTable(wall, g=1.0, e=1.0, H=3.0)
    toss = TOSS
    state = random_states(table, 1, seed=1)[0]
    runners = {"billiard kernel": _billiard_runner(table, n),
               "field kernel g=0 e=1": _field_runner(free, state, n),
               "field kernel g=1 e=1": _field_runner(grav, toss, n)}
    times = {name: [] for name in runners}
    for _ in range(rounds):
        for name, run in runners.items():
            times[name].append(run())
    base = np.array(times["billiard kernel"])
    print(f"collisions {n}, {rounds} alternating rounds, CPU time, one thread (medians)")
    for name, ts in times.items():
        ts = np.array(ts)
        print(f"{name:30s} {np.median(ts) / n * 1e9:8.1f} ns/collision  ({np.median(ts / base):.2f}x the billiard)")
    flight = field_run(grav, toss, n)
    E0 = grav.energy(1.5, 2.0, 1.5)
    drift = float(np.max(np.abs(flight.energy - E0)) / E0)
    print(f"(the g=1 flight: ceiling {np.mean(flight.side == 1):.3f} of the impacts; max |ΔE|/E {drift:.2e})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
