"""
Heads–tails tunnelling: the doublet splitting
=============================================

Just above the diameter D = b(0) + b(π) = 2 the strip of the ellipse wall has two narrow necks at
θ = 0 and π (the body standing on its long axis). The low states live around θ = π/2 (heads) and 3π/2
(tails), and come in doublets: the even and odd combinations, whose splitting Δλ is the heads–tails
tunnelling rate. :func:`coinwall.doublet_splitting` computes it directly and by Herring's flux formula
(Δλ from the states' values in the necks), against the WKB estimate :math:`e^{-S}`. Left: Δλ falls
exponentially as the necks close. Right: :math:`|\\psi|^2` of the lower state of the pair at H = 2.4, in the
strip: two lobes, heads and tails, joined only through the necks.
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Wall, doublet_splitting, quantum_spectrum
from coinwall.forward.quantum.figures import plot_density, plot_splittings

eps = 0.55
wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": eps})
splittings = [doublet_splitting(wall, H) for H in (2.7, 2.6, 2.5, 2.4, 2.3, 2.25)]
for s in splittings:
    print(s)

spectrum = quantum_spectrum(wall, H=2.4, levels=2, method="fem")  # |ψ|² needs the elements

fig, (ax_split, ax_psi) = plt.subplots(1, 2, figsize=(12, 4.2), width_ratios=[1, 1.4])
plot_splittings(splittings, ax=ax_split)
ax_split.set_title("doublet splitting Δλ = λ₋ − λ₊ of the lowest pair")
plot_density(spectrum, 0, ax=ax_psi)
ax_psi.set_xticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
ax_psi.set_xlabel("orientation θ (rad)")
gap = spectrum.eigenvalues[1] - spectrum.eigenvalues[0]
ax_psi.set_title(f"|ψ|² of level 1 at H = 2.4 κ; Δλ = {gap:.2e} / κ²")
fig.suptitle(
    f"Heads–tails tunnelling of the ellipse ε = {eps:g} (wall sqrt((1+ε cos²θ)/(1+ε)), D = 2 κ)"
)
fig.tight_layout()
