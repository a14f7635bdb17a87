"""
The coin in 3-D: the caught coin against 350,757 real flips
===========================================================

A coin launched with its angular momentum at the angle ψ from its normal precesses, and caught in a flat hand
it shows the side it started with with probability P(ψ) = ½ + arcsin(cot²ψ)/π (Diaconis, Holmes & Montgomery,
SIAM Rev. 49 (2007) 211). :func:`~coinwall.forward.dynamics.coin3d.simulate_caught` flies the precessing coin
itself (the 3-D body of revolution reduced to the (θ, η) billiard with the spinning top's potential,
:doc:`/coin3d`) and counts; it knows nothing of the formula.

Bartoš et al. (2023) caught 350,757 flips by 48 people: 50.77 % landed on their starting side.
:func:`coinwall.cases.bartos.bartos_fits` turns that into ψ in two ways: all flips as one binomial
(ψ = 81.2°, 95 % interval [80.3°, 82.2°]), and with the spread between the tossers, who differ far beyond
binomial noise (Pearson χ² = 265 on 47 degrees of freedom): the quasi-binomial interval with dispersion
φ = 265/47 = 5.6, [79.1°, 83.9°], 2.5 times wider. Left: the simulation against DHM's formula, with the
data's ψ and both intervals. Right: each tosser's share against both intervals of the pool.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from coinwall.cases.bartos import bartos_fits, plot_bartos
from coinwall.forward.dynamics.coin3d import dhm_same_side, simulate_caught

fits = bartos_fits()
print(fits)
binomial, spread = fits.overall, fits.overall_overdispersed

angles = np.array([50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0])
simulated = [simulate_caught(math.radians(psi), 20_000, seed=int(psi)) for psi in angles]
for psi, (p, se) in zip(angles, simulated):
    print(f"ψ = {psi:g}°: simulated {p:.4f} ± {se:.4f}, DHM {float(dhm_same_side(math.radians(psi))):.4f}")

fig, ax = plt.subplots(figsize=(12, 4.8), layout="constrained")
grid = np.linspace(46.0, 90.0, 400)
ax.plot(grid, dhm_same_side(np.radians(grid)), "k-", lw=1.2, label="DHM: ½ + arcsin(cot²ψ)/π")
p, se = np.array(simulated).T
ax.errorbar(angles, p, yerr=2 * se, fmt="o", ms=4, label="simulated caught coin (20,000 tosses, ±2σ)")
ax.axvspan(spread.psi_low, spread.psi_high, color="tab:orange", alpha=0.2,
           label=f"real flips, with the spread between tossers: [{spread.psi_low:.1f}°, {spread.psi_high:.1f}°]")
ax.axvspan(binomial.psi_low, binomial.psi_high, color="tab:orange", alpha=0.45,
           label=f"real flips as one binomial: [{binomial.psi_low:.1f}°, {binomial.psi_high:.1f}°]")
ax.axvline(binomial.psi, color="tab:orange", lw=1.2)
ax.set_xlabel("ψ, angle between angular momentum and the coin's normal (degrees)")
ax.set_ylabel("P(same side) (dimensionless)")
ax.set_title(f"the caught coin: P(same side) = {binomial.p:.4f} in the data ⇒ ψ = {binomial.psi:.2f}°")
ax.legend(loc="lower left")

plot_bartos(fits)
plt.show()
