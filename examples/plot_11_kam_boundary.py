"""
The KAM boundary ε_c(H) of the ellipse wall
===========================================

The paper fits the boundary beyond which no regular motion is seen as :math:`\\varepsilon_c = 1/H + 17/H^2`
(eq. 20). :func:`coinwall.kam_boundary` bisects in log ε for the smallest ε at which fewer than 1 % of
Liouville-random orbits are regular (Lyapunov exponent below 3 ln N/N after N collisions). This example
uses a coarse criterion (30 orbits × 400 collisions, 3 bisection steps in [0.15, 15]) to stay fast, so
the brackets are wide; the closed-form
curve ε*(H), where the vertical period-2 orbit turns unstable (:mod:`coinwall.forward.dynamics.analysis.islands`), is
drawn for comparison. :doc:`/dynamics` explains why the measured boundary moves with the criterion.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import NullFormatter

from coinwall import kam_boundary
from coinwall.forward.dynamics.analysis.islands import eps_star

boundary = kam_boundary(
    [3.0, 5.0, 8.0], bracket=(0.15, 15.0), steps=3, orbits=30, collisions=400, seed=0
)
print(boundary)

fig, ax = plt.subplots(figsize=(7, 4.8))
boundary.plot(ax=ax)
grid = np.linspace(2.5, 8.8, 100)
ax.plot(
    grid,
    [eps_star(H) for H in grid],
    "--",
    color="tab:red",
    label="ε*(H): vertical orbit unstable",
)
ax.set_yticks([0.2, 0.5, 1, 2, 5, 10], ["0.2", "0.5", "1", "2", "5", "10"])
ax.yaxis.set_minor_formatter(NullFormatter())
ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8, frameon=False)
ax.set_title(
    "KAM boundary of the ellipse wall sqrt((1+ε cos²θ)/(1+ε))\n"
    f"(criterion: regular < 1 % of {boundary.orbits} orbits × 400 collisions)"
)
fig.tight_layout()
