"""Benchmark of the field kernel with friction against the frictionless one, per event, in one process.

Run:  python tests/benchmarks/bench_toss.py [--impacts N] [--grid N] [--rounds R] [--smoke]

One thread, compile time excluded (one warm-up run each), the runs alternate for R rounds and each is timed in
CPU time (``time.process_time``: a slow phase of the shared machine that takes the CPU away is not counted); the
numbers are medians over the rounds, the ratios medians of the per-round ratios.

* **Per impact, in flight.**  The coin (case:coin, ε = 99) between a floor and a ceiling (H = 3), g = 1, e = 1:
  the billiard kernel (g = 0, the yardstick of the earlier rounds) and the field kernel without friction on N
  impacts of one orbit, through the compiled ``_run`` directly (the toss set-up with both walls); then the
  field kernel without and with μ = 0.3 on the floor on the same 200-impact stretches from N/200 starts of the
  same energy (with friction every floor impact is Stronge's law by Routh's integration; the slip takes energy
  away, so one long orbit would end on the floor: the stretches are short enough to stay in the air, and the
  share of contact events among the records is printed).
* **Per event, whole tosses.**  A basin map's launches (the grid of ``coinwall toss``'s default box, N × N),
  each followed until it is decided: the coin at e = 0.6 and case:egg's wall at e = 0.8 (as its Fourier series:
  the kernel of every Fourier wall is compiled once), without friction and with
  μ = 0.3 (the egg with a rolling resistance of 0.01 κ, under which it settles).  An event is a record of the
  kernel: an impact, or with friction a contact event (lift-off, rolling, slipping, a corner, a face), each of
  which is an integration of the contact phase up to it.  Also the time per toss.
"""

import argparse
import sys
import time

import numpy as np

from coinwall.forward.dynamics.billiard.kernel import compiled
from coinwall.forward.dynamics.billiard.table import Billiard, random_states
from coinwall.forward.dynamics.floor.field import FieldTable, field_run, field_run_many
from coinwall.forward.dynamics.floor.fieldkernel import _kernel


def _billiard_runner(table, n):
    comp = compiled(table)
    state = np.ascontiguousarray(random_states(table, 1, seed=1)[0])
    out = [np.empty(n) for _ in range(5)] + [np.empty(n, dtype=np.int8)]
    last = np.empty(2)

    def run(count=n):
        done, _status = comp.module._run(state, 0, -1, count, *comp.args(table), *out, last)
        if done != count:
            raise RuntimeError(f"the billiard orbit stopped after {done} of {count} collisions")
        return done
    run(10)
    return run


def _field_runner(table, start, n):
    comp = _kernel(table)
    state = np.ascontiguousarray(np.append(start, 0.0) if len(start) == 4 else start, dtype=float)
    out = [np.empty(n) for _ in range(6)] + [np.empty(n, dtype=np.int8)]
    summary = np.empty(9)

    def run(count=n):
        done, _status = comp.module._run(state, 0, -1, count, *comp.args(table), False, table.chatter,
                                         *comp.wall_args(table), True, *out, summary)
        if done != count:
            raise RuntimeError(f"the field orbit stopped after {done} of {count} impacts")
        return done
    run(10)
    return run


def _toss_runner(table, n):
    """The tosses of an n × n grid of the default box (v0 ∈ [0, 3], ω0 ∈ [0, 8], b0 + 2 max b high)."""
    land = table.landscape
    theta0 = float(land.minima[land.names.index("heads")] if "heads" in land.names else land.minima[0])
    height = max(1.0, 2.0 * float(np.max(table.wall(np.linspace(0, 2 * np.pi, 1024, endpoint=False)))))
    V, W = np.meshgrid(np.linspace(0.0, 3.0, n), np.linspace(0.0, 8.0, n))
    states = np.column_stack([np.full(V.size, theta0), np.full(V.size, height), W.ravel(), V.ravel()])
    field_run_many(table, states[:2], 10)
    result = {}

    def run():
        out = field_run_many(table, states, 10_000, workers=1)
        result["decided"] = float(np.isin(out["status"], (1, 2, 3)).mean())
        return int(out["impacts"].sum())
    return run, result


def _median_table(runners, rounds):
    times = {name: [] for name in runners}
    counts = {}
    for _ in range(rounds):
        for name, run in runners.items():
            start = time.process_time()
            counts[name] = run()
            times[name].append(time.process_time() - start)
    return {name: (np.median(ts), counts[name], np.array(ts)) for name, ts in times.items()}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--impacts", type=int, default=1_000_000)
    parser.add_argument("--grid", type=int, default=40)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--smoke", action="store_true",
                        help="a run of a few seconds through every part of the benchmark (numbers meaningless)")
    args = parser.parse_args(argv)
    import numba

    from coinwall.cases.ellipse import ellipse_wall
    from coinwall.forward import Wall

    numba.set_num_threads(1)
    n, grid, rounds = (20_000, 4, 1) if args.smoke else (args.impacts, args.grid, args.rounds)
    coin = ellipse_wall(99.0)
    toss = [0.3, 1.5, 2.0, 1.5]
    plain = FieldTable(coin, g=1.0, e=1.0, H=3.0)
    rough = FieldTable(coin, g=1.0, e=1.0, H=3.0, mu=0.3, settle=False)
    stretch = 200
    rng = np.random.default_rng(1)
    m = max(1, n // stretch)
    angle = rng.uniform(0, 2 * np.pi, m)
    speed = np.sqrt(2 * (plain.energy(1.5, 2.0, 1.5) - plain.g * 1.5))  # the orbit's energy, from the middle
    starts = np.column_stack([rng.uniform(0, 2 * np.pi, m), np.full(m, 1.5), speed * np.cos(angle),
                              speed * np.sin(angle)])

    def stretches(table):
        field_run_many(table, starts[:2], 10)
        return lambda: int(field_run_many(table, starts, stretch, workers=1)["impacts"].sum())

    runners = {"billiard kernel (g = 0)": _billiard_runner(Billiard(coin, 3.0), n),
               "field kernel, one orbit": _field_runner(plain, toss, n),
               "field, stretches, no friction": stretches(plain),
               "field, stretches, μ = 0.3": stretches(rough)}
    table = _median_table(runners, rounds)
    base = table["field kernel, one orbit"][2] / table["field kernel, one orbit"][1]
    print(f"per impact in flight: the coin, H = 3, g = 1, e = 1, {n} impacts, {rounds} alternating rounds, CPU time, "
          "one thread (medians)")
    for name, (t, count, ts) in table.items():
        print(f"  {name:30s} {t / count * 1e9:8.1f} ns/record  ({np.median(ts / count / base):.2f}x the field kernel's "
              f"orbit; {count} records)")
    a, b = table["field, stretches, no friction"], table["field, stretches, μ = 0.3"]
    print(f"  friction / no friction on the same stretches: {np.median((b[2] / b[1]) / (a[2] / a[1])):.2f}x per record")
    kinds = np.concatenate([field_run(rough, s, stretch).side for s in starts[:min(m, 200)]])
    print(f"  (with friction: {np.mean(kinds >= 2):.4f} of the records of 200 stretches are contact events, "
          f"{np.mean(kinds == 0):.3f} floor impacts)")

    egg = Wall.from_fourier(1.0, cos=[0.05, 0.06], sin=[0.0, 0.0, 0.04])  # case:egg's wall, one Fourier kernel
    cases = {"coin e=0.6": (FieldTable(coin, g=1.0, e=0.6), FieldTable(coin, g=1.0, e=0.6, mu=0.3)),
             "egg e=0.8": (FieldTable(egg, g=1.0, e=0.8), FieldTable(egg, g=1.0, e=0.8, mu=0.3, rolling=0.01))}
    for label, (plain, rough) in cases.items():
        (run0, res0), (run1, res1) = _toss_runner(plain, grid), _toss_runner(rough, grid)
        table = _median_table({"no friction": run0, "friction": run1}, rounds)
        (t0, c0, ts0), (t1, c1, ts1) = table["no friction"], table["friction"]
        tosses = grid * grid
        print(f"whole tosses, {label}, {grid} x {grid} launches of the default box, decided "
              f"{res0['decided']:.3f} without friction, {res1['decided']:.3f} with")
        print(f"  no friction           {t0 / c0 * 1e9:9.1f} ns/event  {c0 / tosses:7.1f} events/toss  "
              f"{t0 / tosses * 1e6:9.1f} µs/toss")
        print(f"  {'μ = 0.3' + (', rolling 0.01' if rough.rolling else ''):21s} {t1 / c1 * 1e9:9.1f} ns/event  "
              f"{c1 / tosses:7.1f} events/toss  {t1 / tosses * 1e6:9.1f} µs/toss  "
              f"({np.median((ts1 / c1) / (ts0 / c0)):.2f}x per event, {np.median(ts1 / ts0):.2f}x per toss)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
