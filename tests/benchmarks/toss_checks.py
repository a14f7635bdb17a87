"""The toss that lands, the long runs behind docs/toss.md: the wedge limit, fairness against bounces and e, the
uncertainty exponent as e → 1, the egg's basin map with friction beside the frictionless one and the share of
decided tosses against μ; figures in the house style and the numbers printed (pasted into docs/toss.md).

Run:  python tests/benchmarks/toss_checks.py [--figures docs/figures] [--smoke]

``--smoke`` runs every part with tiny sizes (a few seconds; no figures unless --figures is given).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from coinwall.forward import Wall
from coinwall.forward.dynamics.floor.fairness import fairness, plot_fairness
from coinwall.forward.dynamics.floor.field import FieldTable
from coinwall.forward.dynamics.floor.uncertainty import plot_uncertainty, uncertainty_exponent
from coinwall.forward.dynamics.floor.wedge import plot_wedge, wedge_lyapunov
from coinwall.forward.formats.figure import figure_bytes

COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def write(ax, folder, name):
    if folder:
        path = os.path.join(folder, name)
        with open(path, "wb") as handle:
            handle.write(figure_bytes(ax.figure, path))
        print(f"wrote {path}")


def wedge(args):
    start = time.perf_counter()
    orbits, impacts = (2, 500) if args.smoke else (8, 20_000)
    angles = (45, 60) if args.smoke else (45, 50, 55, 60, 65, 70, 75, 80, 85)
    results = [wedge_lyapunov(a, orbits=orbits, impacts=impacts, method="map") for a in angles]
    few = (45, 60) if args.smoke else (45, 60, 75)
    results += [wedge_lyapunov(a, orbits=orbits, impacts=impacts // 4, method="kernel") for a in few]
    results += [wedge_lyapunov(a, orbits=orbits, impacts=impacts // 4, method="dumbbell", level=1e-2) for a in few]
    print("half-angle  method     lambda/impact  stderr   orbits x impacts  threshold 3logN/N")
    for r in results:
        print(f"{r.half_angle:8.0f}   {r.method:9s}  {r.exponent:12.4f}  {r.stderr:7.4f}  "
              f"{r.exponents.size} x {r.impacts:<8d}    {r.threshold:.2e}")
    print(f"wedge: {time.perf_counter() - start:.1f} s")
    write(plot_wedge(results), args.figures, "toss-wedge.png")


def fair(args):
    start = time.perf_counter()
    coin = Wall.from_expression(COIN, {"eps": 99.0})
    samples, bounces = (2000, 5) if args.smoke else (args.samples, 30)
    es = (0.6, 0.9) if args.smoke else (0.3, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95)
    results = []
    for e in es:
        r = fairness(FieldTable(coin, g=1.0, e=e), (2.0, 5.0), (0.05, 0.2), 1.2, bounces=bounces, samples=samples,
                     seed=1)
        results.append(r)
        print(f"e = {e:4.2f}: bias n=1 {r.bias[0]:+.4f} ± {r.stderr[0]:.4f}; n={bounces} {r.bias[-1]:+.4f} ± "
              f"{r.stderr[-1]:.4f}; undecided {r.undecided[-1]:.3f}; settled {r.settled[-1]:.3f}; fair to 0.01 "
              f"from {r.fair_after(0.01)}, to 0.001 from {r.fair_after(0.001)}")
    print(f"fairness: {time.perf_counter() - start:.1f} s ({samples} tosses per e)")
    write(plot_fairness(results), args.figures, "toss-fairness.png")


def goy(args):
    start = time.perf_counter()
    coin = Wall.from_expression(COIN, {"eps": 99.0})
    samples = 500 if args.smoke else 20_000
    eps = 10.0 ** -np.arange(2, 7)
    thin = FieldTable(Wall.from_expression(COIN, {"eps": 99.0}).scaled(1e-4), g=1.0, e=0.5)
    results = [uncertainty_exponent(thin, (0.0, 3.0), (0.0, 8.0), 3e-5, epsilons=eps[:3], samples=samples,
                                    catch=True)]
    for e in ((0.6,) if args.smoke else (0.3, 0.6, 0.8, 0.9)):
        results.append(uncertainty_exponent(FieldTable(coin, g=1.0, e=e), (0.0, 3.0), (0.0, 8.0), 1.2,
                                            epsilons=eps, samples=samples))
    for r in results:
        print(f"{r!r}  f = {np.array2string(r.fractions, precision=4)}")
    print(f"uncertainty: {time.perf_counter() - start:.1f} s")
    write(plot_uncertainty(results), args.figures, "toss-uncertainty.png")


def friction(args):
    """case:egg at e = 0.8 on coinwall toss's default grid (120 × 120 launches, v0 ∈ [0, 3], ω0 ∈ [0, 8], launch
    height b0 + 2 max b): the basin map without friction and with μ = 0.3 and a rolling resistance of 0.01 κ, side by
    side; and the share decided against μ (a 30 × 30 grid of the same box), with and without rolling resistance."""
    from coinwall.cases.asymmetric import egg_wall
    from coinwall.forward.dynamics.floor.toss import basin_map, plot_basins

    start = time.perf_counter()
    egg = egg_wall()
    n = 12 if args.smoke else 120
    height = 2.0 * float(np.max(egg(np.linspace(0, 2 * np.pi, 1024, endpoint=False))))
    maps = []
    for mu, rolling in ((0.0, 0.0), (0.3, 0.01)):
        tick = time.perf_counter()
        table = FieldTable(egg, g=1.0, e=0.8, mu=mu, rolling=rolling)
        result = basin_map(table, np.linspace(0, 3, n), np.linspace(0, 8, n), height)
        maps.append(result)
        print(f"egg e = 0.8, μ = {mu:g}, rolling {rolling:g}, {n} x {n}: {result!r}; undecided "
              f"{result.undecided_counts()}; {time.perf_counter() - tick:.1f} s")
    write(plot_basins(maps), args.figures, "toss-friction-basins.png")
    mus = (0.0, 0.1, 0.3) if args.smoke else (0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0)
    m = 4 if args.smoke else 30
    rows = []
    for rolling in (0.0, 0.01):
        shares = []
        for mu in mus:
            if mu == 0.0 and rolling > 0.0:
                shares.append(rows[0][1][0])  # no rolling resistance without friction: the same tosses
                continue
            table = FieldTable(egg, g=1.0, e=0.8, mu=mu, rolling=rolling)
            result = basin_map(table, np.linspace(0, 3, m), np.linspace(0, 8, m), height)
            shares.append(1.0 - result.fractions()["undecided"])
            print(f"  μ = {mu:4g}, rolling {rolling:4g}: decided {shares[-1]:.4f}, undecided {result.undecided_counts()}")
        rows.append((rolling, shares))
    from coinwall.forward.formats.figure import new_figure

    _, ax = new_figure(figsize=(6.4, 4.2), constrained_layout=True)
    for rolling, shares in rows:
        label = "Coulomb friction alone" if rolling == 0 else f"with rolling resistance {rolling:g} κ"
        ax.plot(mus, shares, "o-", label=label)
    ax.set_xscale("symlog", linthresh=0.05)
    ax.set_xlabel("coefficient of friction μ")
    ax.set_ylabel(f"share of the {m} × {m} map decided")
    ax.set_ylim(0, 1.02)
    ax.set_title("case:egg, e = 0.8: tosses decided against μ", fontsize=9)
    ax.legend(fontsize=8)
    write(ax, args.figures, "toss-friction-decided.png")
    print(f"friction: {time.perf_counter() - start:.1f} s")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--figures", default=None, help="folder for the figures (default: none written)")
    parser.add_argument("--samples", type=int, default=200_000, help="tosses per e for the fairness curve")
    parser.add_argument("--only", choices=["wedge", "fairness", "uncertainty", "friction"], default=None)
    parser.add_argument("--smoke", action="store_true", help="tiny sizes: exercise every code path in seconds")
    args = parser.parse_args()
    for name, part in (("wedge", wedge), ("fairness", fair), ("uncertainty", goy), ("friction", friction)):
        if args.only in (None, name):
            part(args)


if __name__ == "__main__":
    main()
