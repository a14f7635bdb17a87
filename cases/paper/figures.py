"""The report's figures: the paper's Fig. 4 recomputed, and the Appendix family's three regimes.

Each figure function returns a matplotlib Figure (imported inside); :func:`figure_files` turns them
into ``{path: bytes}`` in PNG, SVG or PDF (:mod:`coinwall.forward.formats.figure`).
"""

from __future__ import annotations

import math
import os

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes, new_figure
from coinwall.forward.validation import check_choice, check_count

__all__ = ["FIGURES", "critical_body_figure", "appendix_gallery_figure", "figure_files"]

_OUTLINE, _FILL, _CENTRE, _CORNER, _WALL = "#123", "#dde6f0", "#c00", "#d60", "#888"


def _closed(values):
    return np.append(values, values[0])


def _legend_below(fig, ncols):
    """One legend for all panels, below them, where it covers no curve (each label once)."""
    entries = {}
    for ax in fig.axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(label, handle)
    fig.legend(list(entries.values()), list(entries), loc="outside lower center", ncols=ncols, fontsize=8,
               frameon=False)


def critical_body_figure(points: int):
    """Paper Fig. 4: the critical body of the ellipse wall, ε = 1, b0 = b_c = −1/2."""
    from coinwall.inverse import solve_body

    from ..ellipse import ellipse_wall

    body = solve_body(ellipse_wall(1.0), -0.5, points=points)
    # the body is flat (height/width ≈ 0.4): a wide figure leaves no empty bands around it
    fig, ax = new_figure(figsize=(6.0, 3.4), layout="constrained")
    ax.fill(body.x, body.y, color=_FILL)
    ax.plot(_closed(body.x), _closed(body.y), color=_OUTLINE, lw=1.6, label="outline")
    ax.plot([0], [0], "o", color=_CENTRE, ms=4, label="centre of mass")
    ax.set_aspect("equal")
    ax.set_xlabel("x (units of κ)")
    ax.set_ylabel("y (units of κ)")
    ax.set_title("Paper Fig. 4: critical body, ε = 1, b0 = b_c = −1/2")
    ax.grid(alpha=0.3)
    _legend_below(fig, ncols=2)
    return fig


def appendix_gallery_figure(points: int):
    """The Appendix family (ellipse wall ε = 1 plus b0) in Cases I, II and III: the bodies above, the
    prescribed wall and the body's wall below, with the corner windows (wall deficit) shaded."""
    from coinwall.inverse import solve_body

    from ..ellipse import ellipse_wall

    wall = ellipse_wall(1.0)
    fig, axes = new_figure(2, 3, figsize=(12, 7.4), gridspec_kw={"height_ratios": [1.3, 1]}, layout="constrained")
    theta = np.linspace(0, TWO_PI, 1441)
    cases = [(-0.3, "Case I: b0 = −0.3 > b_c"), (-0.5, "Case II: b0 = b_c = −0.5"), (-0.6, "Case III: b0 = −0.6 < b_c")]
    for col, (b0, label) in enumerate(cases):
        body = solve_body(wall, b0, points=points)
        ax = axes[0, col]
        ax.fill(body.x, body.y, color=_FILL)
        ax.plot(_closed(body.x), _closed(body.y), color=_OUTLINE, lw=1.4, label="body outline")
        ax.plot([0], [0], "o", color=_CENTRE, ms=3, label="centre of mass")
        for corner in body.corners:
            ax.plot(corner.distance * math.cos(corner.direction), corner.distance * math.sin(corner.direction), "s",
                    color=_CORNER, ms=6, label="corner")
        ax.set_aspect("equal")
        ax.set_xlim(-0.78, 0.78)
        ax.set_ylim(-0.5, 0.5)
        ax.set_title(f"{label}\n{body.regime}", fontsize=10)
        ax.set_xlabel("x (units of κ)")
        if col == 0:
            ax.set_ylabel("y (units of κ)")
        ax.grid(alpha=0.3)
        lower = axes[1, col]
        lower.plot(theta / math.pi, b0 + wall(theta), color=_WALL, lw=2.5,
                   label="prescribed wall b0 + b(θ)")
        lower.plot(theta / math.pi, body.wall_of_body(theta) + b0, color=_OUTLINE, lw=1.1,
                   label="wall of the body")
        for corner in body.corners:
            lo, hi = corner.window
            for turn in (-1, 0, 1):
                lower.axvspan((lo + turn * TWO_PI) / math.pi, (hi + turn * TWO_PI) / math.pi, color=_CORNER,
                              alpha=0.15, label="corner window (wall deficit)")
        lower.set_xlim(0, 2)
        lower.set_xlabel("wall angle θ / π")
        if col == 0:
            lower.set_ylabel("wall height (units of κ)")
        lower.grid(alpha=0.3)
    fig.suptitle("Appendix family: ellipse wall (ε = 1) plus b0")
    _legend_below(fig, ncols=6)
    return fig


#: The report's figures by file name (without extension), in the order the report shows them.
FIGURES = {"fig4_critical": critical_body_figure, "appendix_gallery": appendix_gallery_figure}


def figure_files(folder: str, points: int, figure_format: str = ".png") -> dict:
    """Every figure of :data:`FIGURES` drawn with ``points`` nodes per body, as ``{path: bytes}`` in
    ``folder`` with the extension ``figure_format`` (``.png``, ``.svg`` or ``.pdf``)."""
    check_choice("figure_format", figure_format, FIGURE_FORMATS)
    points = check_count("points", points, minimum=16)
    files = {}
    for name, draw in FIGURES.items():
        path = os.path.join(folder, name + figure_format)
        files[path] = figure_bytes(draw(points), path)
    return files
