"""
Poincaré section of a mixed phase space (paper Fig. 3)
======================================================

The ellipse ε = 0.55 between walls H = 1.9 κ apart (case ``ellipse-0.55``): regular islands —
around the body bouncing on its flat side, θ_c = π/2 and 3π/2 — sit in a chaotic sea. The coin
cannot turn over here (H < b(0) + b(π) = 2), so the section covers only orbits on one side.
"""

import matplotlib.pyplot as plt

from coinwall import Billiard, get_case, poincare_section

case = get_case("ellipse-0.55")
table = Billiard(case.wall(), H=case.H)
section = poincare_section(table, orbits=40, collisions=1500, seed=1)
print(case)
print(section)

fig, ax = plt.subplots(figsize=(8, 5))
section.plot(
    ax=ax,
    markersize=1.0,
    title=f"ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = 0.55, H = {case.H:g} κ\n"
    f"{section.orbits} orbits × {section.collisions} collisions",
)
fig.tight_layout()
