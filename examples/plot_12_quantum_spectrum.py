"""
The quantum coin: spectrum, symmetry classes and Weyl's law
===========================================================

The quantum body is the Dirichlet Laplacian on the billiard strip
:math:`b_0 + b(\\theta) < \\eta < H - b_0 - b(\\theta + \\pi)`, periodic in θ; its eigenvalues λ are in
units of 1/κ² (energy :math:`E = \\hbar^2\\lambda / 2M\\kappa^2`). :func:`coinwall.quantum_spectrum` solves it
one symmetry class at a time (``swap``: heads ↔ tails, ``mirror``: θ → −θ, ``half_turn``: θ → θ + π),
by the fastest accurate method for the strip: for a smooth wall open at every angle, as this one, a
spectral method (Fourier modes in θ × Legendre polynomials across the strip, exponentially convergent);
for a wall with a kink or a narrow neck, P4 finite elements on a mesh that follows the walls
(``method="fem"``; the title of the right panel names the method used). Left: the 80 lowest levels of
the ellipse ε = 0.55 at H = 2.5, by class. Right: the counting function N(λ) against Weyl's law.
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Wall, quantum_spectrum

eps, H = 0.55, 2.5
wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": eps})
spectrum = quantum_spectrum(wall, H=H, levels=80)
print(spectrum)

classes = sorted(set(spectrum.classes))
fig, (ax_levels, ax_count) = plt.subplots(1, 2, figsize=(11, 4.6), width_ratios=[1.2, 1])
for k, name in enumerate(classes):
    values = spectrum.eigenvalues[np.array(spectrum.classes) == name]
    ax_levels.hlines(values, k - 0.35, k + 0.35, color=plt.cm.tab10(k % 10), lw=1.2)
ax_levels.set_xticks(range(len(classes)), [c.replace(" ", "\n") for c in classes], fontsize=7)
ax_levels.set(
    ylabel="eigenvalue λ (1/κ²)", title=f"{len(spectrum)} lowest levels by symmetry class"
)

spectrum.plot(ax=ax_count)
solver = f"P{spectrum.order} elements" if spectrum.method == "fem" else "spectral method"  # the default picks
ax_count.set_title(f"counting function, {solver}, {spectrum.dofs} unknowns")
ax_count.set_ylabel("number of levels N(λ)")
fig.suptitle(
    f"Quantum billiard of the ellipse wall sqrt((1+ε cos²θ)/(1+ε)), ε = {eps:g}, H = {H:g} κ"
)
fig.tight_layout()
