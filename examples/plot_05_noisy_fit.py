"""
Noisy samples: the nearest convex body (least squares)
======================================================

Measured walls are noisy, and noise is not the support function of any convex body. The least-squares
fit :func:`coinwall.inverse.fit.fit_convex` finds the support function of a convex body nearest to the
samples; its ``body`` is then solved as usual. Here: 360 samples of the ellipse wall (ε = 1) with
Gaussian noise σ = 0.01 κ, at the offset b0 = −0.4 (close to b_c = −0.5, where the body is thin and
noise matters most), against the exact body of the noise-free wall.
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Wall, solve_body
from coinwall.inverse.fit import fit_convex

eps, b0, sigma = 1.0, -0.4, 0.01
exact_wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": eps})
rng = np.random.default_rng(0)
theta = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
noisy = exact_wall(theta) + sigma * rng.standard_normal(theta.size)

fit = fit_convex(theta, noisy, b0=b0)
exact = solve_body(exact_wall, b0)
print(fit)

fig, (ax_wall, ax_body) = plt.subplots(1, 2, figsize=(11, 4.2), width_ratios=[1.2, 1])
ax_wall.plot(theta, b0 + noisy, ".", ms=3, color="0.6", label=f"360 samples, σ = {sigma:g} κ")
ax_wall.plot(
    fit.theta, b0 + fit.fitted, "-", color="tab:blue", label="least-squares convex fit"
)
ax_wall.plot(theta, b0 + exact_wall(theta), "k--", lw=1, label="noise-free wall")
ax_wall.set_xticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
ax_wall.set(
    xlabel="θ (rad)",
    ylabel="b0 + b(θ) (κ)",
    title=f"rms residual {fit.rms_residual:.4f} κ (σ = {sigma:g} κ)",
)
ax_wall.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=3, frameon=False
)

for body, style, label in ((exact, "k--", "noise-free body"), (fit.body, "-", "fitted body")):
    pts = body.outline.polygon(8)
    pts = np.vstack([pts, pts[:1]])
    ax_body.plot(pts[:, 0], pts[:, 1], style, lw=1.2, label=f"{label} ({body.regime})")
ax_body.plot([0], [0], "r+", ms=10)
ax_body.set_aspect("equal")
ax_body.set(xlabel="x / κ", ylabel="y / κ", title=f"bodies at b0 = {b0:g}")
ax_body.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.25), ncol=2, frameon=False
)
fig.suptitle("Ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = 1, from noisy samples")
fig.tight_layout()
