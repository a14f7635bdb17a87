"""
Appendix Case I: a smooth convex body (ε = 1, b0 = −0.3 > b_c)
===============================================================

The paper's Appendix solves the ellipse wall

.. math:: b(\\theta) = \\sqrt{\\frac{1 + \\varepsilon\\cos^2\\theta}{1 + \\varepsilon}}

at ε = 1 for three offsets around the critical one, :math:`b_c = -\\min(b + b'') = -1/(1+ε) = -1/2`.
Above it (Case I) the radius of curvature :math:`\\rho = b_0 + b + b''` is positive everywhere and
:func:`coinwall.solve_body` returns a smooth convex body whose wall is exactly the prescribed one.
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Wall, critical_offset, solve_body

eps, b0 = 1.0, -0.3
wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": eps})
b_c = critical_offset(wall).b_c
body = solve_body(wall, b0)
print(f"b_c = {b_c:.12g}; {body}")

theta = np.linspace(0.0, 2 * np.pi, 721)
b, _, d2b = wall.derivatives(theta)

fig, (ax_body, ax_wall, ax_rho) = plt.subplots(
    1, 3, figsize=(12, 3.8), width_ratios=[1.1, 1, 1]
)
body.plot(ax=ax_body)
ax_body.set_title(f"body: b0 = {b0:g} > b_c = {b_c:g} ({body.regime})")
ax_body.set_xlabel("x / κ   (+ centre of mass)")

ax_wall.plot(theta, b0 + b, "k-", lw=2.5, label="prescribed b0 + b(θ)")
ax_wall.plot(
    theta, b0 + body.wall_of_body(theta), "--", color="tab:orange", label="wall of the body"
)
ax_wall.set(
    xlabel="θ (rad)",
    ylabel="distance to the wall (κ)",
    title=f"closed loop: max |error| = {body.max_wall_error:.1e} κ",
)
ax_wall.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False
)

ax_rho.plot(theta, b0 + b + d2b, "k-")
ax_rho.axhline(0.0, color="tab:red", lw=0.8)
ax_rho.set(
    xlabel="θ (rad)", ylabel="radius of curvature ρ (κ)", title="ρ = b0 + b + b'' > 0: convex"
)
for ax in (ax_wall, ax_rho):
    ax.set_xticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
fig.suptitle("Ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = 1 — Appendix Case I")
fig.tight_layout()
