"""
A band on real-looking data
===========================

A maker measures a cam-like part with a rotary table: 240 readings of the distance from the axis to a
flat follower, taken at angles that are not quite evenly spaced and written to 5 decimals — real-looking
data.  The part is a rounded triangle (a triangle grown by a disc of radius 0.25 κ) with its centre of mass
off its centroid.  coinwall reads each reading as an interval (half its last digit, and the slope times the
angle's half digit) and returns, besides the body:

* ``outline_tolerance``: a certified bound on how far *every* convex body whose wall lies in the readings'
  intervals — the true part among them — can be from the outline returned (the band drawn below);
* the interval of ``b_c`` and the regime it decides;
* the corners the data force (here none: the part is rounded).

Every consistent body lies inside the *outer body* (every reading's upper end a support line of it) and
its support function is at least an inner envelope; the outline tolerance is the largest gap between the two.

Between two readings the data are silent: over a flat side the reading lines form a roof, and the band is
widest where a side's normal falls between two readings (about the side's length times the gap over 4).
The figure shows the outer body around the outline at true scale (magnified where the band is widest: the
roof of two readings over a flat side), then the whole band against the wall angle — both envelopes as
distances from the returned wall, on a scale linear near 0 and logarithmic beyond — with the readings'
intervals and the true part (known here in closed form) inside it.
"""

import os
import tempfile

import matplotlib.pyplot as plt
import numpy as np

from coinwall import solve_body
from coinwall.forward.formats import load_wall
from coinwall.forward.formats.style import legend_below

rng = np.random.default_rng(12)
corners = np.array([[1.0, 0.1], [-0.45, 0.85], [-0.55, -0.75]])
radius = 0.25


def truth(theta):
    """The true part's support function: the triangle's, plus the disc's radius (a Minkowski sum)."""
    return np.max(corners @ np.stack([np.cos(theta), np.sin(theta)]), axis=0) + radius


theta = np.sort(np.mod(np.linspace(0, 2 * np.pi, 240, endpoint=False) + rng.normal(0, 0.004, 240), 2 * np.pi))
folder = tempfile.mkdtemp()
path = os.path.join(folder, "readings.csv")
with open(path, "w") as stream:
    stream.write("theta,b\n")
    stream.writelines(f"{t:.5f},{v:.5f}\n" for t, v in zip(theta, truth(theta)))

body = solve_body(load_wall(path), b0=0.0)
print(body)
print(f"b_c certified in [{body.b_c_lower:.4f}, {body.b_c_upper:.4f}] (truth {-radius}), regime {body.regime}")
print(f"outline tolerance {body.outline_tolerance:.4f} κ; corners {len(body.corners)}")

fine = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
true_distance = float(np.max(np.abs(body.outline.support(fine) - truth(fine))))
print(f"distance from the outline to the true part {true_distance:.4f} κ (at most the tolerance)")

band = body.band
grid = np.sort(np.concatenate([fine, band.theta]))
own = body.outline.support(grid)
inner, outer = band.inner_support(grid) - own, band.outer_support(grid) - own

fig, (ax_shape, ax_band) = plt.subplots(1, 2, figsize=(12, 4.6), width_ratios=[1, 1.6])
outer_body = np.vstack([band.outer, band.outer[:1]])
points = body.outline.polygon(8)
closed = np.vstack([points, points[:1]])
# the true part, drawn from its definition: the triangle's corners, each grown by the disc
phi = np.linspace(0, 2 * np.pi, 2000)
grown = (corners[:, None, :] + radius * np.stack([np.cos(phi), np.sin(phi)], axis=1)[None]).reshape(-1, 2)
true_outline = grown[np.unique(np.argmax(np.column_stack([np.cos(phi), np.sin(phi)]) @ grown.T, axis=1))]
true_outline = true_outline[np.argsort(np.arctan2(true_outline[:, 1] - 0.1, true_outline[:, 0] + 0.0))]


def draw(ax):
    ax.fill(outer_body[:, 0], outer_body[:, 1], color="tab:cyan", lw=0, label="outer body: every consistent body "
                                                                             "is inside")
    ax.fill(closed[:, 0], closed[:, 1], color="white", lw=0)
    ax.plot(closed[:, 0], closed[:, 1], "k-", lw=0.9, label="outline returned")
    ax.plot(*np.vstack([true_outline, true_outline[:1]]).T, "--", color="tab:green", lw=0.9, label="true part")


draw(ax_shape)
ax_shape.plot([0], [0], "+", color="tab:red", ms=10)
ax_shape.set_aspect("equal")
ax_shape.set(xlabel="x (κ)", ylabel="y (κ)", title="the body and its band, true scale")
# where the band is widest: over a flat side, the roof of the two readings either side of its normal
widest = int(np.argmax(outer - inner))
centre = band.outer[np.argmax(band.outer @ np.array([np.cos(grid[widest]), np.sin(grid[widest])]))]
zoom = ax_shape.inset_axes([0.52, 0.52, 0.45, 0.45])
draw(zoom)
span = 0.03
zoom.set(xlim=(centre[0] - span, centre[0] + span), ylim=(centre[1] - span, centre[1] + span), xticks=[], yticks=[])
zoom.set_aspect("equal")
ax_shape.indicate_inset_zoom(zoom, edgecolor="0.4")
legend_below(ax_shape, fontsize=8, ncol=2)

ax_band.fill_between(grid, inner, outer, color="tab:cyan", alpha=0.5, lw=0, label="band of every consistent body")
ax_band.plot(grid, truth(grid) - own, "-", color="tab:green", lw=0.9, label="the true part")
at = body.outline.support(band.theta)
ax_band.vlines(band.theta, band.lower - at, band.upper - at, color="0.3", lw=0.7, label="readings' intervals")
ax_band.axhline(0, color="k", lw=0.8)
ax_band.set_yscale("symlog", linthresh=1e-4)
ax_band.set_xticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
ax_band.set(xlabel="wall angle θ (rad)", ylabel="distance from the returned wall (κ)",
            title=f"outline tolerance {body.outline_tolerance:.3g} κ; true part {true_distance:.2g} κ away")
legend_below(ax_band, fontsize=8, ncol=3)
fig.tight_layout()
plt.show()
