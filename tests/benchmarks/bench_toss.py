"""Benchmark of the field kernel per collision against the field-free billiard kernel, and against today's.

Run:  python tests/benchmarks/bench_toss.py [--collisions N] [--rounds R] [--smoke]

Same wall (case:coin, the ellipse ε = 99), same strip (H = 3), one thread, compile time excluded (one warm-up
run each).  The compiled ``_run`` of each kernel is called directly (no Trajectory or Flight is built), the
runs alternate for R rounds and each is timed in CPU time (``time.process_time``: a slow phase of the shared
machine that takes the CPU away is not counted); the numbers are medians over the rounds, the ratios medians of
the per-round ratios.  Lines: the billiard kernel; the field kernel with g = 0, e = 1 (the same billiard, the
cost of the field kernel's generality); the field kernel with g = 1, e = 1 and a start energy high enough to
meet the ceiling (the toss set-up with both walls; the issue's target is this line within 1.5x the billiard);
and *today's* field kernel on that same flight: ``_field_kernel_baseline.py`` next to this file is a verbatim
copy of ``forward/dynamics/floor/_field_kernel.py`` before the kernels shared their search, compiled here the same way
(it reads the first 16 columns of the cell table).
"""

import argparse
import pathlib
import sys
import time

import numpy as np

from coinwall.forward.dynamics.billiard.kernel import HEADER, compiled
from coinwall.forward.dynamics.billiard.table import Billiard, random_states
from coinwall.forward.dynamics.billiard.wallcode import load_module, seal, wall_source
from coinwall.forward.dynamics.floor.field import _MARKER, FieldTable, _kernel, field_run

HERE = pathlib.Path(__file__).resolve().parent


def today_field_module(wall):
    """Today's field kernel (``_field_kernel_baseline.py``, verbatim) joined to ``wall``'s code."""
    text = (HERE / "_field_kernel_baseline.py").read_text(encoding="utf-8")
    _head, found, body = text.partition(_MARKER)
    if not found:
        raise RuntimeError("_field_kernel_baseline.py has lost its marker line")
    source, _ = wall_source(wall, "@njit(**OPTIONS)\n")
    return load_module(HEADER + source + body, "coinwall_bench_today_field")


def _billiard_runner(table, n):
    comp = compiled(table)
    state = np.ascontiguousarray(random_states(table, 1, seed=1)[0])
    out = [np.empty(n) for _ in range(5)] + [np.empty(n, dtype=np.int8)]
    last = np.empty(2)

    def run(count=n):
        done, status = comp.module._run(state, 0, -1, count, *comp.args(table), *out, last)
        return done
    run(10)
    seal(comp.module)
    return run


def _field_runner(table, start, n, module=None, columns=None):
    comp = _kernel(table)
    module = comp.module if module is None else module
    wall_args = list(comp.wall_args(table))
    if columns is not None:
        wall_args[1] = np.ascontiguousarray(wall_args[1][:, :columns])
    state = np.ascontiguousarray(start, dtype=float)
    out = [np.empty(n) for _ in range(5)] + [np.empty(n, dtype=np.int8)]
    summary = np.empty(8)

    def run(count=n):
        done, status = module._run(state, 0, -1, count, *comp.args(table), False, table.chatter, *wall_args, True,
                                   *out, summary)
        return done
    run(10)
    seal(module)
    return run


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
    toss = [0.3, 1.5, 2.0, 1.5]
    state = random_states(table, 1, seed=1)[0]
    runners = {"billiard kernel": _billiard_runner(table, n),
               "field kernel g=0 e=1": _field_runner(free, state, n),
               "field kernel g=1 e=1": _field_runner(grav, toss, n),
               "today's field kernel g=1 e=1": _field_runner(grav, toss, n, today_field_module(wall), 16)}
    times = {name: [] for name in runners}
    for _ in range(rounds):
        for name, run in runners.items():
            start = time.process_time()
            done = run()
            times[name].append(time.process_time() - start)
            if done != n:
                raise RuntimeError(f"{name} stopped after {done} of {n} collisions")
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
