"""The 3-D coin between two walls: side-up P(n) and τ(H) against the planar paper's coin.

Run:  PYTHONPATH=. python tests/benchmarks/reproduce_coin3d.py [--smoke]

The body is the ellipsoid of revolution with semi-axes 1 (across) and 0.1 (along the axis, the coin's
normal): its meridian section is the paper's ε = 99 ellipse, in units of the ellipsoid's κ₁.  For
H = 1.2, 1.5, 2 D the planar P(n) of the section (coinwall.forward.dynamics.analysis.correlation, 40 orbits, 400,000
bottom collisions) is printed beside the 3-D coin's (coinwall.forward.dynamics.coin3d.correlation3d, the same 40
Liouville-random starts, 25,000 impacts each) at ℓz = ℓ3 = 0, 0.2, 0.5 rad/s (speed 1 in (θ, η)).  The numbers
are in docs/coin3d.md.
"""

import argparse
import time

import numpy as np

from coinwall.forward.dynamics.analysis.correlation import correlation
from coinwall.forward.dynamics.billiard.table import Billiard, random_states
from coinwall.forward.dynamics.coin3d.correlation3d import side_correlation
from coinwall.forward.dynamics.coin3d.top import TopTable
from coinwall.forward.revolution import ellipsoid
from coinwall.forward.wall import Wall


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--smoke", action="store_true", help="a few seconds: one H, few orbits")
    args = parser.parse_args(argv)
    orbits, bounces, impacts, ratios = (40, 400_000, 25_000, (1.2, 1.5, 2.0))
    if args.smoke:
        orbits, bounces, impacts, ratios = (4, 8_000, 3_000, (1.5,))
    body = ellipsoid(1.0, 0.1)
    k1 = body.kappa1
    D = 2.0 / k1
    wall = Wall.from_expression("sqrt(a**2*cos(t)**2 + c**2*sin(t)**2)/k", {"a": 1.0, "c": 0.1, "k": k1})
    print("| H/D | model | P(1) | P(2) | P(3) | P(5) | heads | P∞ | τ (floor impacts) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for ratio in ratios:
        H = ratio * D
        bil = Billiard(wall, H)
        t0 = time.time()
        planar = correlation(bil, bounces=bounces, max_lag=10, orbits=orbits, seed=1)
        P = planar.P
        print(f"| {ratio:g} | planar section | {P[1]:.4f} | {P[2]:.4f} | {P[3]:.4f} | {P[5]:.4f} | "
              f"{planar.heads_fraction:.3f} | ½ | {planar.tau:.3f} ± {planar.tau_stderr:.3f} |")
        starts = random_states(bil, orbits, seed=1)
        # planar θp (from the downward normal to the long axis) -> the normal's tilt: cos θ = −sin θp
        th = np.arccos(np.clip(-np.sin(starts[:, 0]), -1, 1))
        w = starts[:, 2] * np.cos(starts[:, 0]) / np.maximum(np.sin(th), 1e-300)
        states = np.column_stack([th, starts[:, 1], w, starts[:, 3]])
        table = TopTable(body, g=0.0, e=1.0, H=H)
        for lam in (0.0, 0.2, 0.5):
            r = side_correlation(table, states, lam, lam, impacts)
            P = r["P"]
            print(f"| {ratio:g} | 3-D, ℓz = ℓ3 = {lam:g} | {P[0]:.4f} | {P[1]:.4f} | {P[2]:.4f} | {P[4]:.4f} | "
                  f"{r['heads']:.3f} | {r['P_inf']:.3f} | {r['tau']:.3f} ± {r['tau_stderr']:.3f} |")
        print(f"(H = {ratio:g} D: {time.time() - t0:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
