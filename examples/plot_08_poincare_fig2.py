"""
Poincaré section of a nearly circular ellipse (paper Fig. 2)
============================================================

At every collision with the bottom wall, :func:`coinwall.poincare_section` records the contact angle
θ_c and the angle of incidence φ_c (signed: the direction of motion along the wall). For the nearly
circular ellipse ε = 0.03 between walls H = 3 κ apart (the named case ``ellipse-0.03``, the paper's
first figure) almost every orbit lies on an invariant curve: the motion is nearly integrable, with
small resonance islands.
"""

import matplotlib.pyplot as plt

from coinwall import Billiard, get_case, poincare_section

case = get_case("ellipse-0.03")
table = Billiard(case.wall(), H=case.H)
section = poincare_section(table, orbits=40, collisions=1000, seed=1)
print(case)
print(section)

fig, ax = plt.subplots(figsize=(8, 5))
section.plot(
    ax=ax,
    markersize=1.0,
    title=f"ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = 0.03, H = {case.H:g} κ\n"
    f"{section.orbits} orbits × {section.collisions} collisions",
)
fig.tight_layout()
