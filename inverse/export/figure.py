"""The body as a figure: the outline beside the wall function and its radius of curvature ρ.

Written as PNG (``png.py``) or PDF (``pdf.py``) through :func:`coinwall.forward.formats.figure.figure_bytes`, in
the house style (:mod:`coinwall.forward.formats.style`).  A body's ``.svg`` is the exact drawing (``svg.py``),
not this figure.

For a wall given as data the outline panel shades the certified band (every body whose wall lies in the
samples' intervals lies in it) and the middle panel shows that band, and the samples' intervals, as distances
from the body's own wall (the outline tolerance is its widest point).

The ρ panel shows what decided the regime: for a formula wall ``ρ = b0 + b + b''`` from the exact derivatives;
for a sampled wall the discrete radius of curvature of the samples themselves
(:func:`coinwall.inverse.discrete.discrete_support`, ``ρ_i + b0``) with the band their rounding allows — never the
second derivative of an interpolant, which is the interpolant's noise, not the data's.
"""

from __future__ import annotations

import math

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.formats.style import PALETTE, shade_angle_window, styled, wall_label

__all__ = ["band_curves", "figure", "sampled_curvature", "write_figure"]

_WINDOW = dict(color=PALETTE[4], alpha=0.18, lw=0)


def _legend_below(ax, ncol=2):
    """The legend under the axes, off the curves."""
    # anchored a fixed distance below the axes (in font sizes), clear of the tick and axis labels whatever
    # the panel's height (the outline panel is short: its aspect is equal)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=4.5, ncol=ncol)


def _angle_axis(ax):
    ax.set_xlim(0.0, TWO_PI)
    ax.set_xticks([k * 0.5 * math.pi for k in range(5)], ["0", "π/2", "π", "3π/2", "2π"])
    ax.set_xlabel("wall angle θ (rad)")


def _shade_windows(ax, body, label=True):
    for k, c in enumerate(body.corners):
        lo, hi = c.window
        shade_angle_window(ax, lo, hi, label="corner window" if (label and k == 0) else None, **_WINDOW)


def sampled_curvature(body):
    """``(theta, rho, tolerance)`` of a sampled wall's body: the discrete radius of curvature of the samples plus
    b0 (:func:`~coinwall.inverse.discrete.discrete_support`) and its rounding tolerance; None for a formula wall."""
    from coinwall.inverse.discrete import discrete_support, machine_rounding

    if body.wall.samples is None:
        return None
    theta, b = body.wall.samples
    rounding = body.wall.sample_rounding if body.wall.sample_rounding is not None else machine_rounding(b)
    support = discrete_support(theta, b, rounding)
    return theta, support.rho + body.b0, support.rho_tolerance


def _mark_minima(ax, body):
    """Every critical angle, at the height of the minimum of ρ + b0 (the list `coinwall critical` prints)."""
    angles = np.mod(np.asarray(body.critical_angles, dtype=float), TWO_PI)
    if angles.size and math.isfinite(body.b_c):
        ax.plot(angles, np.full(angles.size, body.b0 - body.b_c), "^", color=PALETTE[1], ms=6, zorder=4,
                label=f"min ρ: {angles.size} critical angle{'s' if angles.size > 1 else ''}")


def band_curves(body, count: int = 4000):
    """``(theta, inner, outer)``: the envelopes of every body consistent with a sampled wall's intervals, as
    differences from the body's own wall at ``count`` angles (``L − h`` ≤ 0 ≤ ``U − h``, up to the body's own
    excess); None for a body with no band (a formula wall, Case III, samples with standard deviations)."""
    band = body.band
    if band is None:
        return None
    theta = np.sort(np.concatenate([np.linspace(0.0, TWO_PI, count, endpoint=False), band.theta]))
    own = body.outline.support(theta)
    return theta, band.inner_support(theta) - own, band.outer_support(theta) - own


def _band_outline(ax, body):
    """Shade, at true scale, the band around the outline: each support point moved along its normal out to the
    outer envelope and in to the inner one."""
    curves = band_curves(body, 2000)
    if curves is None:
        return
    theta, inner, outer = curves
    normal = np.column_stack([np.cos(theta), np.sin(theta)])
    points = body.outline.polygon(8)
    touch = points[np.argmax(normal @ points.T, axis=1)]
    ring = np.vstack([touch + outer[:, None] * normal, (touch + inner[:, None] * normal)[::-1]])
    ax.fill(ring[:, 0], ring[:, 1], color=PALETTE[5], alpha=0.45, lw=0,
            label=f"band: every body within the samples (±{body.outline_tolerance:.2g})")


def _band_panel(ax, body):
    """The band and the samples' intervals as distances from the body's wall, against θ."""
    theta, inner, outer = band_curves(body)
    ax.fill_between(theta, inner, outer, color=PALETTE[5], alpha=0.45, lw=0, label="band of every consistent body")
    ts, lo, hi = body.band.theta, body.band.lower, body.band.upper
    own = body.outline.support(ts)
    step = max(1, ts.size // 2000)
    ax.vlines(ts[::step], (lo - own)[::step], (hi - own)[::step], color="0.3", lw=0.6,
              label=f"samples' intervals ({ts.size})")
    ax.axhline(0.0, color="k", lw=0.8, label="wall of the body")
    ax.set_ylabel("distance from the body's wall (κ)")
    ax.set_title(f"the outline is within {body.outline_tolerance:.2g} κ of every body the samples allow")


def _rho_panel(ax, body):
    data = sampled_curvature(body)
    ax.axhline(0, color="0.3", lw=0.8)
    _mark_minima(ax, body)
    _shade_windows(ax, body, label=False)
    for k, angle in enumerate(body.critical_angles):  # the one set solve, critical and the JSON list
        ax.axvline(angle, color=PALETTE[1], lw=0.7, ls=":", label="critical angles" if k == 0 else None)
    if data is None:
        theta = np.linspace(0, TWO_PI, 1200)
        b, _, d2 = body.wall.derivatives(theta)
        ax.plot(theta, body.b0 + b + d2, "k-", label="ρ = b0 + b + b″")
        ax.set_title(f"radius of curvature; b_c = {body.b_c:.6g}")
        return
    theta, rho, tol = data
    closed = np.append(theta, theta[0] + TWO_PI)
    ax.fill_between(closed, np.append(rho - tol, rho[0] - tol[0]), np.append(rho + tol, rho[0] + tol[0]),
                    color=PALETTE[5], alpha=0.35, lw=0, label="± rounding of the samples")
    ax.plot(theta, rho, "k.-", lw=0.6, ms=2.5 if theta.size <= 2000 else 0,
            label=f"discrete ρ + b0 ({theta.size} samples)")
    lower, upper = body.b_c_lower, body.b_c_upper
    if lower is not None and upper is not None and math.isfinite(lower) and math.isfinite(upper):
        ax.axhspan(body.b0 - upper, body.b0 - lower, facecolor="none", edgecolor=PALETTE[1], lw=1.0, ls="--",
                   zorder=3, label="b0 − b_c: certified interval of min ρ + b0")
        ax.set_title(f"radius of curvature of the data; b_c ∈ [{lower:.4g}, {upper:.4g}]")
    else:
        ax.set_title(f"radius of curvature of the data; b_c = {body.b_c:.6g}")
    # vertex windows have ρ + b0 ≈ b0 and the edges between them spikes of the edge length over the spacing:
    # show the part that decides the regime (around 0 and the bulk of the samples), say what is off scale
    lo, hi = np.percentile(rho, [2, 90])
    pad = max(0.15 * (hi - lo), 2 * float(np.median(tol)), 0.05 * max(abs(body.b0), 1e-3))
    bottom, top = min(lo, 0.0, body.b0 - (upper or body.b_c)) - pad, max(hi, 0.0) + pad
    if rho.max() > top or rho.min() < bottom:
        ax.set_ylim(bottom, top)
        off = int(np.count_nonzero((rho > top) | (rho < bottom)))
        ax.text(0.99, 0.98, f"{off} samples off scale (up to {rho.max():.3g})", transform=ax.transAxes,
                ha="right", va="top", fontsize=7.5, color="0.2",
                bbox=dict(facecolor="white", edgecolor="none", alpha=0.85, pad=1.5))


@styled
def figure(body, name=None):
    """A matplotlib figure: outline | prescribed vs achieved wall | radius of curvature, titled with the wall
    (``name`` as the user wrote it, default the wall's description), b0, the regime and the outline's nodes."""
    from coinwall.forward.formats.figure import new_figure

    fig, (ax0, ax1, ax2) = new_figure(1, 3, figsize=(14, 4.8), layout="constrained")
    _band_outline(ax0, body)
    body.plot(ax0)
    ax0.set_title(f"outline: area {body.area:.4g} κ², {len(body.corners)} corners")
    _legend_below(ax0)
    theta = np.linspace(0, TWO_PI, 1200)
    if body.band is not None:
        _band_panel(ax1, body)
    else:
        ax1.plot(theta, body.b0 + body.wall(theta), "k-", label="prescribed b0 + b(θ)")
        ax1.plot(theta, body.outline.support(theta), "--", color=PALETTE[1], label="wall of the body")
        if body.wall.samples is not None:
            ts, bs = body.wall.samples
            ax1.plot(ts, body.b0 + bs, ".", color="0.35", ms=2, label=f"{ts.size} samples")
        ax1.set_ylabel("distance from centre of mass to wall (κ)")
        ax1.set_title(f"wall; max |wall error| = {body.max_wall_error:.1e} κ")
    _shade_windows(ax1, body)
    _angle_axis(ax1)
    _legend_below(ax1, ncol=2)
    _rho_panel(ax2, body)
    _angle_axis(ax2)
    ax2.set_ylabel("radius of curvature ρ (κ)")
    _legend_below(ax2)
    regime = body.regime if body.regime_decided else f"undecided ({' or '.join(body.regimes)})"
    fig.suptitle(f"Body of the wall {wall_label(body.wall, name)}: b0 = {body.b0:g} κ, {regime}, "
                 f"b_c = {body.b_c:.6g}")
    return fig


def write_figure(body, stream, extension: str):
    """Write the figure of ``body`` to a binary ``stream`` in the format of ``extension`` (".png", ".pdf")."""
    from coinwall.forward.formats.figure import figure_bytes

    stream.write(figure_bytes(figure(body), "body" + extension))
