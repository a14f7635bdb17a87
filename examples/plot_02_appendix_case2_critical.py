"""
Appendix Case II: the critical body of Fig. 4 (ε = 1, b0 = b_c = −1/2)
======================================================================

At the critical offset :math:`b_0 = b_c = -1/(1+\\varepsilon)` the radius of curvature
:math:`\\rho = b_0 + b + b''` touches zero at θ = 0 and π: the body of the paper's Fig. 4 is convex
but its curvature is infinite at the two tips, where :math:`R(0) = b_0 + 1 = 1/2`. The envelope and
the polar solver (the paper's :math:`R(\\alpha)` equation) are run against each other
(``cross_check=True``).
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Wall, critical_offset, solve_body

eps = 1.0
wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": eps})
critical = critical_offset(wall)
b0 = critical.b_c
body = solve_body(wall, b0, cross_check=True)
print(critical)
print(body, "cross-check:", body.cross_check)

fig, (ax_body, ax_polar) = plt.subplots(1, 2, figsize=(11, 4), width_ratios=[1.2, 1])
body.plot(ax=ax_body)
ax_body.set_title(f"body at b0 = b_c = {b0:g} ({body.regime})")
ax_body.set_xlabel("x / κ   (+ centre of mass)")

order = np.argsort(body.alpha)
ax_polar.plot(body.alpha[order], body.R[order], "k-", label="R(α), envelope solver")
ax_polar.plot(
    critical.angles,
    [b0 + wall(a) for a in critical.angles],
    "o",
    color="tab:red",
    label="b0 + b at the critical angles",
)
ax_polar.set_xticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
ax_polar.set(
    xlabel="polar angle α (rad)",
    ylabel="radius R (κ)",
    title=f"envelope vs polar solver: {body.cross_check:.1e} κ",
)
ax_polar.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False
)
fig.suptitle("Ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = 1 — Appendix Case II (paper Fig. 4)")
fig.tight_layout()
