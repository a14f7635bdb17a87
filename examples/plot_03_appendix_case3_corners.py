"""
Appendix Case III: corners below the critical offset (ε = 1, b0 = −0.6)
========================================================================

Below :math:`b_c = -1/2` no convex body has the wall: :math:`\\rho = b_0 + b + b''` is negative near
θ = 0 and π. :func:`coinwall.solve_body` then returns the *largest convex body under the wall*. It has
two corners; over each corner's window of wall angles the body's wall is
:math:`R_c\\cos(\\theta - \\text{direction})`, below the prescribed one (the deficit, shaded).
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Wall, solve_body

eps, b0 = 1.0, -0.6
wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": eps})
body = solve_body(wall, b0)
print(body)
for corner in body.corners:
    print(
        f"corner at α = {corner.direction:.4f} rad, R_c = {corner.distance:.6f} κ, "
        f"half-width {corner.half_width:.6f} rad, deficit {corner.max_deficit:.3e} κ"
    )

theta = np.linspace(-np.pi / 2, 3 * np.pi / 2, 1441)
prescribed = b0 + wall(theta)
of_body = b0 + body.wall_of_body(theta)

fig, (ax_body, ax_wall) = plt.subplots(1, 2, figsize=(11, 4), width_ratios=[1.2, 1])
body.plot(ax=ax_body)
ax_body.set_title(f"largest convex body under the wall: b0 = {b0:g} < b_c = {body.b_c:g}")
ax_body.set_xlabel("x / κ   (+ centre of mass, ● corner)")

ax_wall.plot(theta, prescribed, "k-", lw=2, label="prescribed b0 + b(θ)")
ax_wall.plot(theta, of_body, "--", color="tab:orange", label="wall of the body")
ax_wall.fill_between(
    theta,
    of_body,
    prescribed,
    where=prescribed > of_body + 1e-12,
    color="tab:red",
    alpha=0.3,
    label="deficit (corner windows)",
)
ax_wall.set_xticks(np.arange(-1, 4) * np.pi / 2, ["−π/2", "0", "π/2", "π", "3π/2"])
ax_wall.set(
    xlabel="θ (rad)", ylabel="distance to the wall (κ)", title=f"{len(body.corners)} corners"
)
ax_wall.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False
)
fig.suptitle("Ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = 1 — Appendix Case III")
fig.tight_layout()
