"""
A sampled wall to a cut-ready DXF drawing
=========================================

Walls measured on a real body come as samples. Here 360 samples of a rounded triangle's support
function (a triangle grown by a disc of radius 0.15 κ, rounded to 6 decimals) are written to a CSV file
``theta,b``, read back with :func:`coinwall.forward.formats.load_wall` and solved as support lines
(no derivative of the data is taken). :func:`coinwall.export_body` then writes a *cut-ready* DXF at real
size — one closed LWPOLYLINE on layer ``CUT`` — for a body whose radius of gyration is κ = 10 mm. The
drawing is read back with ezdxf and drawn in millimetres.
"""

import os
import tempfile

import ezdxf
import matplotlib.pyplot as plt
import numpy as np

from coinwall import export_body, solve_body
from coinwall.forward.formats import load_wall

folder = tempfile.mkdtemp()
theta = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
vertices = np.array([[1.0, 0.0], [-0.5, 0.8], [-0.5, -0.8]])
b = np.max(vertices @ np.stack([np.cos(theta), np.sin(theta)]), axis=0) + 0.15
csv_path = os.path.join(folder, "wall.csv")
with open(csv_path, "w") as fh:
    fh.write("theta,b\n")
    fh.writelines(f"{t:.6f},{v:.6f}\n" for t, v in zip(theta, b))

wall = load_wall(csv_path)
body = solve_body(wall, b0=0.0)
print(body)

dxf_path = os.path.join(folder, "part.dxf")
result = export_body(body, [dxf_path], kappa=10.0, units="mm", cut=True)
print(result)

doc = ezdxf.readfile(dxf_path)
entities = list(doc.modelspace())
print("entities:", [(e.dxftype(), e.dxf.layer) for e in entities])
(polyline,) = entities
xy = np.array([p[:2] for p in polyline.get_points()])
xy = np.vstack([xy, xy[:1]])

fig, (ax_wall, ax_dxf) = plt.subplots(1, 2, figsize=(11, 4.2), width_ratios=[1, 1])
ax_wall.plot(theta, b, ".", ms=2.5, color="tab:blue", label="360 samples (CSV)")
fine = np.linspace(0.0, 2 * np.pi, 2000)
ax_wall.plot(fine, body.wall_of_body(fine), "k-", lw=0.8, label="wall of the solved body")
ax_wall.set_xticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
ax_wall.set(xlabel="θ (rad)", ylabel="b(θ) (κ)", title="sampled wall, b0 = 0")
ax_wall.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=2, frameon=False
)

ax_dxf.plot(xy[:, 0], xy[:, 1], "-", color="tab:red", lw=1.2)
ax_dxf.plot([0], [0], "k+", ms=10)
ax_dxf.set_aspect("equal")
deviation = result.deviations()[dxf_path]
ax_dxf.set(
    xlabel="x (mm)",
    ylabel="y (mm)",
    title=f"part.dxf: {len(xy) - 1}-vertex LWPOLYLINE on layer CUT\n"
    f"(κ = 10 mm, deviation ≤ {deviation:.1e} mm)",
)
fig.suptitle("Rounded triangle (disc radius 0.15 κ) from 360 samples → cut-ready DXF")
fig.tight_layout()
