"""Benchmark and accuracy study: walls from data.

Run:  python tests/benchmarks/bench_data.py [--figures docs/figures]

1. A sampled solve of 10,000 samples (a 7-gon's wall and the ellipse wall ε = 1, uniform angles),
   building the wall from the samples included, against evaluating the sampled wall on the same 10,000
   angles; interleaved, medians of 9 repeats, in the same run (the machine is shared).  Target < 0.2 s.
2. A least-squares fit of 1,000 noisy samples (σ = 0.01) against the same evaluation.  Target < 2 s.
3. Fit accuracy against σ and the number of samples n: the largest and the rms error of the fitted
   wall against the true one, averaged over seeds; the exponent in n is fitted and printed beside
   the rate −2/5 of Gardner, Kiderlen & Milanfar (2006) for this estimator in the plane.
With --figures DIR: fit_noise.png (data, fit, residual) and fit_rate.png (error against n and σ).
--smoke: 1,000 samples, one repeat, one seed and two small sample counts (a few seconds: checks the script).
"""

import argparse
import statistics
import time

import numpy as np

from coinwall import Wall, solve_body
from coinwall.inverse.fit import fit_convex

N = 10_000


def _timed(func):
    start = time.perf_counter()
    func()
    return time.perf_counter() - start


def interleaved(baseline, func, repeats=9):
    base, times = [], []
    for _ in range(repeats):
        base.append(_timed(baseline))
        times.append(_timed(func))
    return statistics.median(base), statistics.median(times)


def ellipse(theta):
    return np.sqrt((1 + np.cos(theta) ** 2) / 2)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figures", default=None)
    parser.add_argument("--smoke", action="store_true", help="small sizes, one repeat: checks the script")
    args = parser.parse_args()
    n_samples, repeats = (1000, 1) if args.smoke else (N, 9)
    counts, seeds = ((100, 200), 1) if args.smoke else ((125, 250, 500, 1000, 2000), 4)
    theta = np.linspace(0, 2 * np.pi, n_samples, endpoint=False)
    angles = 2 * np.pi * np.arange(7) / 7 + 0.1 * np.sin(np.arange(7))
    heptagon = np.stack([np.cos(angles), np.sin(angles)], axis=1) * (1 + 0.1 * np.cos(3 * np.arange(7)))[:, None]
    walls = {"7-gon": np.max(heptagon @ np.stack([np.cos(theta), np.sin(theta)]), axis=0), "ellipse": ellipse(theta)}
    print(f"sampled solve, {n_samples:,} uniform samples (wall built from the samples + solve_body, no cross-check)")
    for name, values in walls.items():
        wall = Wall.from_samples(theta, values)
        solve_body(wall, 0.0)  # warm: imports, first calls
        base, t = interleaved(lambda: wall(theta), lambda: solve_body(Wall.from_samples(theta, values), 0.0),
                              repeats=repeats)
        body = solve_body(Wall.from_samples(theta, values), 0.0)
        print(f"  {name:8s} eval {base * 1e3:6.2f} ms  solve {t * 1e3:7.1f} ms  ratio {t / base:6.1f}  "
              f"({body.method}, {body.regime}, {len(body.corners)} corners, wall error {body.max_wall_error:.1e})")

    rng = np.random.default_rng(0)
    n_fit = 200 if args.smoke else 1000
    theta1k = np.linspace(0, 2 * np.pi, n_fit, endpoint=False)
    noisy = ellipse(theta1k) + 0.01 * rng.standard_normal(n_fit)
    wall1k = Wall.from_samples(theta1k, ellipse(theta1k))
    fit_convex(theta1k, noisy)
    base, t = interleaved(lambda: wall1k(theta1k), lambda: fit_convex(theta1k, noisy), repeats=1 if args.smoke else 5)
    print(f"fit of {n_fit:,} noisy samples: eval {base * 1e3:.2f} ms, fit {t:.3f} s, ratio {t / base:.0f}")

    print(f"fit accuracy (ellipse wall, uniform angles; mean over {seeds} seeds)")
    print("     n      σ     rms error   max error   rms residual / σ")
    table = {}
    for sigma in (0.003, 0.01, 0.03):
        for n in counts:
            th = np.linspace(0, 2 * np.pi, n, endpoint=False)
            rms, worst, resid = [], [], []
            for seed in range(seeds):
                r = np.random.default_rng(100 + seed)
                fit = fit_convex(th, ellipse(th) + sigma * r.standard_normal(n))
                err = fit.fitted - ellipse(th)
                rms.append(np.sqrt(np.mean(err**2)))
                worst.append(np.max(np.abs(err)))
                resid.append(fit.rms_residual / sigma)
            table[sigma, n] = (np.mean(rms), np.mean(worst))
            print(f"  {n:5d} {sigma:6.3f}   {np.mean(rms):.3e}   {np.mean(worst):.3e}   {np.mean(resid):.3f}")
    for sigma in (0.003, 0.01, 0.03):
        ns = np.array(counts)
        slope = np.polyfit(np.log(ns), np.log([table[sigma, n][0] for n in ns]), 1)[0]
        print(f"  σ = {sigma}: rms error ∝ n^{slope:.2f}  (Gardner–Kiderlen–Milanfar: n^-0.40)")
    sig = np.array([0.003, 0.01, 0.03])
    slope = np.polyfit(np.log(sig), np.log([table[s, counts[-1]][0] for s in sig]), 1)[0]
    print(f"  n = {counts[-1]}: rms error ∝ σ^{slope:.2f}")

    if args.figures:
        from coinwall.forward.formats.figure import figure_bytes, new_figure

        fit = fit_convex(theta1k, noisy)
        fig, axes = new_figure(2, 1, figsize=(7, 5), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
        fit.plot(axes)
        axes[0].plot(theta1k, ellipse(theta1k), "--", color="tab:green", lw=0.8, label="true wall")
        axes[0].legend(loc="upper center", bbox_to_anchor=(0.5, 1.25), ncol=3, frameon=False)
        fig.tight_layout()
        with open(f"{args.figures}/fit_noise.png", "wb") as fh:
            fh.write(figure_bytes(fig, "fit_noise.png"))
        fig, ax = new_figure(figsize=(6, 4))
        for sigma in (0.003, 0.01, 0.03):
            ns = list(counts)
            ax.loglog(ns, [table[sigma, n][0] for n in ns], "o-", label=f"σ = {sigma}")
        ref = np.array([125, 2000.0])
        ax.loglog(ref, table[0.01, 125][0] * (ref / 125) ** -0.4, "k:", label="n^(−2/5) (GKM 2006)")
        ax.set_xlabel("number of samples n")
        ax.set_ylabel("rms error of the fitted wall (κ)")
        ax.legend(loc="lower left", fontsize=8)
        fig.tight_layout()
        with open(f"{args.figures}/fit_rate.png", "wb") as fh:
            fh.write(figure_bytes(fig, "fit_rate.png"))


if __name__ == "__main__":
    main()
