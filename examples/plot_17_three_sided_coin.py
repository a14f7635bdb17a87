"""
How thick is a three-sided coin?
================================

A coin thick enough lands on its edge as often as on either face. How thick depends on how it is tossed,
and :func:`coinwall.inverse.design.design` answers for each toss model (:doc:`/design`):

* **drop** — a random orientation, no bounce, the face below the centre of mass. For the planar coin (a
  thickness × width rectangle) P(edge) = (2/π) atan(thickness/width), a third at 1/√3 ≈ 0.577; for the
  cylinder the solid angle of its rim, a third at thickness/diameter = 1/(2√2) ≈ 0.354 (Yong &
  Mahadevan's dropped coin).
* **flip** — turning about a horizontal axis with a uniform phase: the cylinder flipped about a diameter is
  its planar section, a third at 1/√3 (Yong & Mahadevan's flipped coin).
* **bounce** — the coin flipped about a diameter and bouncing on a frictionless floor (restitution e),
  uniform density: the planar section's wall over the cylinder's transverse radius of gyration,
  ``(abs(cos(t)) + h*abs(sin(t)))/sqrt(0.25 + h**2/3)`` for radius 1 and half-thickness h. Monte Carlo, to
  ±0.01 here.

The left panel shows P(edge) against thickness/diameter for each model, the right one the thickness each
needs, beside the literature's two values. Bouncing makes the edge rarer: the coin must be thicker, the
more so the more elastic the floor. (Murray & Teare's and Hernández-Navarro & Piñero's numbers are not
drawn: only their abstracts were read; :doc:`/design` says what was compared.)
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from coinwall.inverse.design import Bounce, Drop, Family, Flip, design, design_curves

# the planar coin of width 2 and thickness 2h: thickness/width = h
planar = Family("planar", "abs(cos(t)) + h*abs(sin(t))", {"h": (0.05, 2.0)})
# the cylinder of radius 1 and thickness 2h: thickness/diameter = h
cylinder = Family("cylinder", None, {"thickness": (0.1, 4.0)}, {"radius": 1.0})
# the cylinder flipped about a diameter, bouncing: its section in units of its κ₁ (uniform density)
bouncing = Family("planar", "(abs(cos(t)) + h*abs(sin(t)))/sqrt(0.25 + h**2/3)", {"h": (0.2, 2.0)})

results = {
    "drop, planar": design(planar, {"edge": 1 / 3}, Drop()),
    "drop, cylinder": design(cylinder, {"edge": 1 / 3}, Drop()),
    "flip (cylinder about a diameter)": design(cylinder, {"edge": 1 / 3}, Flip()),
}
for e in (0.3, 0.6, 0.9):
    results[f"bounce, e = {e}"] = design(bouncing, {"edge": 1 / 3}, Bounce(e=e), tolerance=0.01, seed=1)

ratio = {}
for name, found in results.items():
    scale = 0.5 if found.family.kind == "cylinder" else 1.0  # thickness 2h over diameter 2 (or width 2)
    ratio[name] = (found.x[0] * scale, found.half_widths[0] * scale)
    print(f"{name:34s} thickness/diameter = {ratio[name][0]:.4f} ± {ratio[name][1]:.1g}")

fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.6), constrained_layout=True)
h = np.linspace(0.05, 2.0, 300)
ax.plot(h, 2 / np.pi * np.arctan(h), label="drop, planar = flip: (2/π) atan(t/d)")
ax.plot(h, h / np.sqrt(1 + h * h), label="drop, cylinder: solid angle of the rim")
for name, found in results.items():
    if name.startswith("bounce"):
        (_, xs, rows), = design_curves(found, points=15, tosses=4000)
        p, half = rows["edge"]
        ax.errorbar(xs, p, yerr=half, fmt="o-", ms=3, lw=1, capsize=2, label=f"{name} (±95%)")
ax.axhline(1 / 3, color="k", ls="--", lw=0.8)
ax.set_xlabel("thickness / diameter")
ax.set_ylabel("P(edge)")
ax.set_xlim(0, 2)
ax.legend(fontsize=8)
ax.set_title("the edge's share against the thickness, per toss model")

names = list(ratio)
values = [ratio[n][0] for n in names]
errors = [ratio[n][1] for n in names]
bx.barh(names, values, xerr=errors, color=["C0", "C1", "C0", "C2", "C3", "C4"], capsize=3)
bx.axvline(1 / (2 * math.sqrt(2)), color="C1", ls=":", lw=1.2, label="Yong & Mahadevan, dropped: 1/(2√2)")
bx.axvline(1 / math.sqrt(3), color="C0", ls=":", lw=1.2, label="Yong & Mahadevan, flipped: 1/√3")
bx.set_xlabel("thickness / diameter for P(edge) = 1/3")
bx.invert_yaxis()
bx.set_xlim(0, 1.0)
bx.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
bx.set_title("the three-sided coin of each model")
plt.show()
