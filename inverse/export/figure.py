"""The body as a figure: the outline beside the wall function and ρ = b0 + b + b''.

Written as PNG (``png.py``) or PDF (``pdf.py``) through :func:`coinwall.forward.formats.figure.figure_bytes`.
A body's ``.svg`` is the exact drawing (``svg.py``), not this figure.
"""

from __future__ import annotations

import numpy as np

from coinwall.forward.angles import TWO_PI

__all__ = ["figure", "write_figure"]


def _legend_below(ax):
    """The legend under the axes, off the curves."""
    # anchored a fixed distance below the axes (in font sizes), clear of the tick and axis labels whatever
    # the panel's height (the outline panel is short: its aspect is equal)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=4.5, ncol=2, fontsize=8, frameon=False)


def figure(body):
    """A matplotlib figure: outline | prescribed vs achieved wall | radius of curvature."""
    from coinwall.forward.formats.figure import new_figure

    fig, (ax0, ax1, ax2) = new_figure(1, 3, figsize=(14, 4.8))
    body.plot(ax0)
    ax0.set_xlabel("x / κ")
    ax0.set_ylabel("y / κ")
    _legend_below(ax0)
    theta = np.linspace(0, TWO_PI, 1200)
    wall = body.b0 + body.wall(theta)
    ax1.plot(theta, wall, "k-", label="prescribed b0 + b(θ)")
    ax1.plot(theta, body.outline.support(theta), "--", color="tab:orange", label="wall of the body")
    for c in body.corners:
        lo, hi = c.window
        ax1.axvspan(lo % TWO_PI, (lo % TWO_PI) + (hi - lo), color="tab:orange", alpha=0.15)
    ax1.set_xlabel("θ (rad)")
    ax1.set_ylabel("distance to wall / κ")
    _legend_below(ax1)
    ax1.set_title(f"max |wall error| = {body.max_wall_error:.1e}")
    b, _, d2 = body.wall.derivatives(theta)
    ax2.plot(theta, body.b0 + b + d2, "k-", label="ρ = b0 + b + b''")
    ax2.axhline(0, color="tab:red", lw=0.8)
    ax2.set_xlabel("θ (rad)")
    ax2.set_ylabel("radius of curvature ρ / κ")
    ax2.set_title(f"b_c = {body.b_c:.6g}")
    _legend_below(ax2)
    fig.tight_layout()
    return fig


def write_figure(body, stream, extension: str):
    """Write the figure of ``body`` to a binary ``stream`` in the format of ``extension`` (".png", ".pdf")."""
    from coinwall.forward.formats.figure import figure_bytes

    stream.write(figure_bytes(figure(body), "body" + extension))
