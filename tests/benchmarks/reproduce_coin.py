"""Reproduce the paper's coin claims (section III): bounces needed at H = 1.1 D and 1.2 D, and τ ∝ 1/(H − D).

Run:  python tests/benchmarks/reproduce_coin.py [--bounces 1000000]

Variants (the paper does not say which κ it used):

* ``kappa=1``: the paper's dimensionless wall b(θ) = sqrt((1+ε cos²θ)/(1+ε)) with κ = 1,
  so D = 2 and H = 1.1·2, 1.2·2.
* ``kappa=uniform``: a uniform elliptic lamina with semi-axes a = 1, b = 1/sqrt(1+ε) has
  κ² = (a² + b²)/4; in units of that κ the wall is b(θ)/κ and D = 2/κ, H = 1.1·D, 1.2·D.

and both counting conventions (n in bottom collisions, n in collisions with either wall).
Output: a table pasted into docs/dynamics.md.
"""

from __future__ import annotations

import argparse
import math
import time

from coinwall.forward import Wall
from coinwall.forward.dynamics.analysis.correlation import correlation, fit_tau_law
from coinwall.forward.dynamics.billiard.table import Billiard

EPS = 99.0
WALL = "sqrt((1+eps*cos(t)**2)/(1+eps))/k"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--bounces", type=int, default=1_000_000)
    parser.add_argument("--orbits", type=int, default=100)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--smoke", action="store_true",
                        help="2,000 bounces of 4 orbits, κ = 1, three heights: checks the script")
    args = parser.parse_args()
    if args.smoke:
        args.bounces, args.orbits = 2000, 4
    kappa_uniform = math.sqrt((1.0 + 1.0 / (1.0 + EPS)) / 4.0)
    print(f"# eps = {EPS:g}, bounces = {args.bounces} per run, orbits = {args.orbits}, seed = {args.seed}")
    print(f"# kappa_uniform = sqrt((1 + 1/(1+eps))/4) = {kappa_uniform:.6f}")
    print("| κ variant | H/D | H (κ units) | count | τ ± err | n_needed (first n, |P−½|<0.01) | fit crossing | P(1) | paper |")
    print("|---|---|---|---|---|---|---|---|---|")
    taus = {}
    start = time.perf_counter()
    variants = (("κ = 1", 1.0),) if args.smoke else (("κ = 1", 1.0), ("κ uniform", kappa_uniform))
    for name, k in variants:
        wall = Wall.from_expression(WALL, {"eps": EPS, "k": k})
        D = 2.0 / k
        for ratio in ((1.1, 1.2, 1.5) if args.smoke else (1.05, 1.1, 1.2, 1.3, 1.5)):
            for count in ("bottom", "all"):
                r = correlation(Billiard(wall, ratio * D), args.bounces, 60, orbits=args.orbits, count=count,
                                seed=args.seed)
                taus.setdefault((name, count), []).append((ratio * D, r.tau, r.tau_stderr, D))
                paper = {1.1: "20", 1.2: "12"}.get(ratio, "")
                print(f"| {name} | {ratio:g} | {ratio * D:.4g} | {count} | {r.tau:.3f} ± {r.tau_stderr:.3f} | "
                      f"{r.n_needed} | {r.n_needed_fit:.1f} | {r.P[1]:.4f} ± {r.P_stderr[1]:.4f} | {paper} |", flush=True)
    print()
    print("| κ variant | count | τ = c/(H − D): c ± err | χ²/dof | free power p ± err |")
    print("|---|---|---|---|---|")
    for (name, count), rows in taus.items():
        H, tau, err, D = zip(*rows)
        law = fit_tau_law(H, tau, err, D[0])
        print(f"| {name} | {count} | {law.c:.4g} ± {law.c_stderr:.2g} | {law.chi2_dof:.3g} | "
              f"{law.power:.3f} ± {law.power_stderr:.3f} |")
    print(f"\n# total {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
