"""PNG export: the outline beside the wall function and ρ = b0 + b + b''."""

import math

import numpy as np

__all__ = ["EXTENSION", "write", "figure"]

EXTENSION = ".png"


def figure(body):
    """A matplotlib figure: outline | prescribed vs achieved wall | radius of curvature."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax0, ax1, ax2) = plt.subplots(1, 3, figsize=(14, 4.4))
    body.plot(ax0)
    theta = np.linspace(0, 2 * math.pi, 1200)
    wall = body.b0 + body.wall(theta)
    ax1.plot(theta, wall, "k-", label="prescribed b0 + b(θ)")
    ax1.plot(theta, body.outline.support(theta), "--", color="tab:orange", label="wall of the body")
    for c in body.corners:
        lo, hi = c.window
        ax1.axvspan(lo % (2 * math.pi), (lo % (2 * math.pi)) + (hi - lo), color="tab:orange", alpha=0.15)
    ax1.set_xlabel("θ (rad)")
    ax1.set_ylabel("distance to wall / κ")
    ax1.legend(loc="best", fontsize=8)
    ax1.set_title(f"max |wall error| = {body.max_wall_error:.1e}")
    b, _, d2 = body.wall.derivatives(theta)
    ax2.plot(theta, body.b0 + b + d2, "k-", label="ρ = b0 + b + b''")
    ax2.axhline(0, color="tab:red", lw=0.8)
    ax2.set_xlabel("θ (rad)")
    ax2.set_ylabel("radius of curvature / κ")
    ax2.set_title(f"b_c = {body.b_c:.6g}")
    ax2.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig


def write(body, stream):
    import matplotlib.pyplot as plt

    fig = figure(body)
    fig.savefig(stream, format="png", dpi=110)
    plt.close(fig)
