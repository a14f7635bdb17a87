"""Benchmark of the field kernel per collision against the field-free billiard kernel.

Run:  python tests/benchmarks/bench_toss.py [--collisions N] [--rounds R]

Same wall (the coin, ε = 99), same strip (H = 3), same start, one thread, compile time excluded (one
warm-up run each); best of R rounds.  Three lines: the billiard kernel; the field kernel with g = 0, e = 1
(the same billiard, the cost of the field kernel's generality); the field kernel with g = 1 and a start
energy high enough to meet the ceiling (the toss set-up with both walls).
"""

import argparse
import time

import numpy as np

from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard import Billiard, random_states, simulate
from coinwall.forward.dynamics.field import FieldTable, field_run


def best(fn, rounds):
    fn()
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--collisions", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    n = args.collisions
    wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    table = Billiard(wall, 3.0)
    state = random_states(table, 1, seed=1)[0]
    free = FieldTable(wall, g=0.0, e=1.0, H=3.0)
    grav = FieldTable(wall, g=1.0, e=1.0, H=3.0)
    t_bil = best(lambda: simulate(table, state, n), args.rounds)
    t_free = best(lambda: field_run(free, state, n), args.rounds)
    t_grav = best(lambda: field_run(grav, [0.3, 1.5, 2.0, 1.5], n), args.rounds)
    flight = field_run(grav, [0.3, 1.5, 2.0, 1.5], n)
    E0 = grav.energy(1.5, 2.0, 1.5)
    drift = float(np.max(np.abs(flight.energy - E0)) / E0)
    print(f"collisions            {n}")
    print(f"billiard kernel       {t_bil / n * 1e9:8.1f} ns/collision")
    print(f"field kernel g=0 e=1  {t_free / n * 1e9:8.1f} ns/collision  ({t_free / t_bil:.2f}x the billiard)")
    print(f"field kernel g=1 e=1  {t_grav / n * 1e9:8.1f} ns/collision  ({t_grav / t_bil:.2f}x; "
          f"ceiling {np.mean(flight.side == 1):.3f} of the impacts; max |ΔE|/E {drift:.2e})")


if __name__ == "__main__":
    main()
