"""
A parameter scan: the chaotic fraction over (ε, H)
==================================================

:func:`coinwall.cases.scan.scan` computes one quantity on every cell of a grid of wall parameters × H,
one seeded task per cell on a local dask.distributed cluster, written cell by cell into a resumable
xarray/Zarr store (here in a temporary folder). This is a small 4 × 4 grid with 20 orbits × 300 collisions
per cell, computed when the page is built; :func:`coinwall.cases.scan.figures.plot_scan` draws the phase
diagram with the paper's KAM curve :math:`\\varepsilon = 1/H + 17/H^2` and the closed-form ε*(H), ε**(H)
(:doc:`/scan` shows the 16 × 13 map). Needs the ``scan`` extra (``pip install -e ".[scan]"``).
"""

import os
import tempfile

import matplotlib.pyplot as plt

from coinwall.cases.scan import TableSpec, scan
from coinwall.cases.scan.figures import plot_scan

store = os.path.join(tempfile.mkdtemp(), "phase.zarr")
result = scan(
    "chaotic-fraction",
    TableSpec("sqrt((1+eps*cos(t)**2)/(1+eps))"),
    {"eps": "0.5:20:4log", "H": "2:8:4"},
    output=store,
    options={"orbits": 20, "collisions": 300},
    seed=0,
    workers=2,
)
print(result)
dataset = result.dataset()
print(dataset.chaotic_fraction.values)

ax = plot_scan(dataset)
ax.set_title(
    "chaotic fraction of the ellipse wall sqrt((1+ε cos²θ)/(1+ε))\n"
    "4 × 4 cells, 20 orbits × 300 collisions each"
)
ax.set_ylabel("ellipse parameter ε (dimensionless)")
ax.set_xlabel("wall distance H (κ)")
plt.gcf().tight_layout()
