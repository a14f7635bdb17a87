"""
A body of constant width: the Reuleaux triangle
===============================================

A body of constant width w has :math:`h(\\theta) + h(\\theta + \\pi) = w` in every direction, so its
billiard strip between :math:`b_0 + b(\\theta)` and :math:`H - b_0 - b(\\theta + \\pi)` has the same width
:math:`H - w` at every angle: the body can never stand on edge more than on its side. The named case
``reuleaux-3`` is the Reuleaux triangle of width 2 (:func:`coinwall.get_case`), whose wall is made of
circle arcs (``Wall.from_arcs``: :math:`b + b''` jumps between 0 at the vertices and w on the arcs).
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Billiard, get_case, solve_body

case = get_case("reuleaux-3")
wall = case.wall()
body = solve_body(wall, case.b0)
print(case)
print(body)

H = 2.5
table = Billiard(wall, H, case.b0)
theta = np.linspace(0.0, 2 * np.pi, 1201)
lower, upper = table.lower(theta), table.upper(theta)
print("width h(θ) + h(θ+π):", np.ptp(wall(theta) + wall(theta + np.pi)), "spread")

fig, (ax_body, ax_strip) = plt.subplots(1, 2, figsize=(11, 4.2), width_ratios=[1, 1.3])
body.plot(ax=ax_body)
ax_body.set_xlabel("x / κ   (+ centre of mass, ● corner)")
ax_body.set_title(f"Reuleaux triangle, width 2 κ ({body.regime}, {len(body.corners)} corners)")

ax_strip.fill_between(
    theta, lower, upper, color="tab:blue", alpha=0.15, label="billiard strip"
)
ax_strip.plot(theta, lower, "k-", label="lower wall b0 + b(θ)")
ax_strip.plot(theta, upper, "k--", label="upper wall H − b0 − b(θ+π)")
ax_strip.set_xticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
ax_strip.set(
    xlabel="θ (rad)",
    ylabel="η = y / κ",
    title=f"H = {H:g} κ: the strip is {H - 2:g} κ wide everywhere",
)
ax_strip.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=3, frameon=False
)
fig.suptitle("Constant width: the Reuleaux triangle (case reuleaux-3) and its billiard")
fig.tight_layout()
