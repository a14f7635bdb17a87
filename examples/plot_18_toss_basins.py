"""
The toss that lands: heads/tails basins and fairness against bounces
====================================================================

The paper ends its coin section with the casinos' remark that a bounce randomises the outcome. Here the
coin (the ellipse wall with ε = 99, a thin disc seen edge-on) is tossed in a field g onto a frictionless
floor with restitution e: :class:`~coinwall.forward.dynamics.floor.FieldTable` is the paper's billiard with
gravity and a floor, and a toss is decided once its energy falls below the barrier between heads and tails.

Top: :func:`~coinwall.forward.dynamics.floor.basin_map` over the launch velocity v0 and spin ω0 at e = 0.6
(the picture of Vulović & Prange, PRA 33, 576 (1986)): bands of heads and tails between Keller's hyperbolas
ω0·v0/g = π(n + ¼), π(n + ¾) (dashed), broken up where the coin bounces before it settles; right, the number
of floor impacts that took. Bottom: :func:`~coinwall.forward.dynamics.floor.fairness_curve`, a hand that
launches (v0, ω0) = (2, 5) ± (0.05, 0.2) and a croupier who stops the coin at its n-th floor impact: the
bias of heads against n for three restitutions, with two standard errors. Caught on landing (n = 1) the coin
keeps a bias of −0.024; at e = 0.6 and 0.9 the bounces bring it within 0.01 of ½, while at e = 0.3 the coin
settles after a few bounces with a larger bias than it was caught with. Units: lengths in κ, time in
units that make g = 1 (``coinwall toss``; :doc:`/toss` has the measured numbers).
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import get_case
from coinwall.forward.dynamics.floor import FieldTable, basin_map, fairness_curve

wall = get_case("coin").wall()
height = 1.2  # launch height of the centre of mass (κ)

table = FieldTable(wall, g=1.0, e=0.6)
basins = basin_map(table, np.linspace(0.0, 3.0, 160), np.linspace(0.0, 8.0, 160), height)
print(basins)
ax = basins.plot(title="coin ε = 99 (case:coin)")
ax.figure.set_size_inches(12, 5)

restitutions = (0.3, 0.6, 0.9)
results, fair_after = fairness_curve(wall, restitutions, (2.0, 5.0), (0.05, 0.2), height, bounces=15,
                                     samples=40_000, tolerance=0.01, seed=1)
for result, n in zip(results, fair_after):
    print(result, "| fair to 0.01 from bounce", n)

fig, ax = plt.subplots(figsize=(12, 4.6), layout="constrained")
for result in results:
    line, = ax.plot(result.bounces, result.bias, "o-", ms=3, label=f"e = {result.e:g}")
    ax.fill_between(result.bounces, result.bias - 2 * result.stderr, result.bias + 2 * result.stderr,
                    color=line.get_color(), alpha=0.2, lw=0)
ax.axhspan(-0.01, 0.01, color="0.5", alpha=0.15, lw=0, label="within 0.01 of ½")
ax.axhline(0.0, color="k", lw=0.8)
ax.set_xlabel("floor impact n at which the coin is stopped (count)")
ax.set_ylabel("P(heads) − ½ (dimensionless; band: ±2σ)")
ax.set_title(f"frictionless floor, hand (v0, ω0) = (2, 5) ± (0.05, 0.2), {results[0].samples:,} tosses per e")
ax.legend(loc="upper right", ncol=4)
