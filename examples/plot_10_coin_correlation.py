"""
The coin: heads–tails correlation P(n) and its decay time τ(H)
==============================================================

The paper's coin is the ellipse wall with ε = 99 (a thin disc seen edge-on: diameter D = b(0) + b(π) = 2).
Between walls just over D apart it can turn over only rarely. :func:`coinwall.correlation` estimates
P(n), the probability that the face shown at a bottom collision is shown again n bottom collisions later,
over Liouville-random orbits, and fits :math:`P(n) - \\tfrac12 = A e^{-n/\\tau}`. The right panel repeats
this for several H and fits the paper's law :math:`\\tau \\propto 1/(H - D)`
(:func:`~coinwall.forward.dynamics.fit_tau_law`). Small counts (10⁵ bounces per H) keep this quick; the
measured numbers with 10⁶ bounces are in :doc:`/dynamics`.
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Billiard, correlation, get_case
from coinwall.forward.dynamics import fit_tau_law

case = get_case("coin")
wall = case.wall()
D = wall(0.0) + wall(np.pi)

result = correlation(Billiard(wall, H=2.2), bounces=200_000, max_lag=30, orbits=50, seed=1)
print(result)

H_values = np.array([2.1, 2.2, 2.4, 2.6, 3.0])
runs = [
    correlation(Billiard(wall, H=H), bounces=100_000, max_lag=40, orbits=50, seed=1)
    for H in H_values
]
tau = np.array([r.tau for r in runs])
tau_err = np.array([r.tau_stderr for r in runs])
law = fit_tau_law(H_values, tau, tau_err, D)
print(law)

fig, (ax_p, ax_tau) = plt.subplots(1, 2, figsize=(11, 4.2))
result.plot(ax=ax_p)
ax_p.set_title(
    f"|P(n) − ½| at H = 2.2 κ = 1.1 D: τ = {result.tau:.2f} ± {result.tau_stderr:.2f}"
)
ax_p.set_xlabel("lag n (bottom collisions)")

ax_tau.errorbar(H_values, tau, yerr=tau_err, fmt="o", label="measured τ (10⁵ bounces per H)")
grid = np.linspace(H_values[0] - 0.03, H_values[-1], 200)
ax_tau.plot(grid, law.c / (grid - D), "k-", lw=1, label=f"τ = {law.c:.3f}/(H − D)")
ax_tau.set_yscale("log")
ax_tau.set(
    xlabel="wall distance H (κ)",
    ylabel="decay time τ (bottom collisions)",
    title=f"τ(H); free power p = {law.power:.2f} ± {law.power_stderr:.2f}",
)
ax_tau.legend(fontsize=8)
fig.suptitle("The coin: ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = 99, diameter D = 2 κ")
fig.tight_layout()
