"""Benchmark of a Monte Carlo design: the bounce toss's three-sided coin to ±0.005 in probability (95%).

Run:  python tests/benchmarks/bench_design.py [--tolerance 0.005] [--rounds 3] [--workers N] [--mu MU] [--smoke]

The family is the 2 × 2h rectangle ``abs(cos(t)) + h*abs(sin(t))``, h in [0.2, 2], the target P(edge) = 1/3, the
planar bounce toss with e = 0.5 and the default hand (``coinwall design ... --model bounce --e 0.5``), every core
(numba's threads); ``--mu 0.3`` puts Coulomb friction on the floor.  The kernel is compiled (and cached) by a
warm-up design at a coarse tolerance first, so the times are the solver's.  Each round, in one process: the
design (wall-clock), then, as the baseline, one ensemble of as many tosses as the design's final evaluation (the
cost of a single Monte Carlo estimate at that precision); the ratio says how many such estimates the solver
spent.  After the rounds the last design point is re-simulated with 400000 independent launches: its P(edge)
must be within 0.005 + 2 of its standard errors of 1/3, or the script exits 1.
"""

import argparse
import statistics
import sys
import time

from coinwall.inverse.design import Bounce, Family, design, resimulate
from coinwall.inverse.design.solvers import Ensemble


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tolerance", type=float, default=0.005)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--mu", type=float, default=0.0, help="friction at the floor (default 0)")
    parser.add_argument("--smoke", action="store_true", help="a coarse tolerance, one round (the test suite's run)")
    args = parser.parse_args(argv)
    if args.smoke:
        args.tolerance, args.rounds = 0.05, 1
    family = Family("planar", "abs(cos(t)) + h*abs(sin(t))", {"h": (0.2, 2.0)})
    model = Bounce(e=0.5, mu=args.mu, workers=args.workers)
    design(family, {"edge": 1 / 3}, model, tolerance=0.05, seed=99)  # compile and cache the kernel
    times, bases, ratios = [], [], []
    for r in range(args.rounds):
        start = time.perf_counter()
        found = design(family, {"edge": 1 / 3}, model, tolerance=args.tolerance, seed=r)
        elapsed = time.perf_counter() - start
        ens = Ensemble(model, family, ["edge"], seed=1000 + r)
        start = time.perf_counter()
        ens.evaluate(found.x, found.tosses)
        base = time.perf_counter() - start
        times.append(elapsed)
        bases.append(base)
        ratios.append(elapsed / base)
        p, h = found.probabilities["edge"]
        print(f"round {r}: h = {found.x[0]:.6f} ± {found.half_widths[0]:.4f}, P(edge) = {p:.4f} ± {h:.4f}, "
              f"{found.tosses} tosses at the point, {found.total_tosses} in all; design {elapsed:.2f} s, one "
              f"ensemble of {found.tosses} tosses {base:.3f} s, ratio {elapsed / base:.1f}")
    print(f"median design {statistics.median(times):.2f} s (tolerance ±{args.tolerance:g}), median ensemble "
          f"{statistics.median(bases):.3f} s, median ratio {statistics.median(ratios):.1f}")
    check = resimulate(found, 40_000 if args.smoke else 400_000, seed=7)
    p, se = check.probabilities["edge"]
    ok = abs(p - 1 / 3) <= args.tolerance + 2 * se
    print(f"re-simulated at h = {found.x[0]:.6f}: P(edge) = {p:.4f} ± {se:.4f} (standard error) with "
          f"{check.tosses} independent tosses: {'within' if ok else 'NOT within'} ±{args.tolerance:g} of 1/3")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
