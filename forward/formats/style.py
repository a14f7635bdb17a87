"""The house style of every coinwall figure, in one place.

:data:`HOUSE_STYLE` is a matplotlib style (a dictionary of rcParams, usable as ``matplotlib.style.use(HOUSE_STYLE)``
or ``matplotlib.rc_context(HOUSE_STYLE)``).  The figures apply it only while they draw
(:func:`house_style`, :func:`styled`), so a program that imports coinwall keeps its own settings.

The rules the figures follow with it:

* the title or caption says what is shown: the wall (:func:`wall_label`), its parameters, H, the counts;
* every axis names its quantity and its unit, ``quantity (unit)``; dimensionless quantities say so;
* colour that carries a value has a colour bar with its quantity;
* log axes print every tick label in one format (:func:`plain_log_axis`): 0.5, 2, 40 — not 5×10⁻¹ beside 1.0;
* the file format follows the extension: .png for screens, .svg and .pdf (vector) for papers.
"""

from __future__ import annotations

import functools
import math

__all__ = ["HOUSE_STYLE", "PALETTE", "house_style", "plain_log_axis", "shade_angle_window", "styled", "wall_label"]

#: Okabe & Ito's colour-blind-safe palette (blue, vermillion, green, reddish purple, orange, sky blue, yellow).
PALETTE = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442")

HOUSE_STYLE = {
    "figure.dpi": 100,
    "savefig.dpi": 150,
    "savefig.bbox": "tight",          # legends placed below the axes are kept, margins stay small
    "savefig.pad_inches": 0.06,
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "axes.prop_cycle": "cycler('color', [%s])" % ", ".join(repr(c) for c in PALETTE),
    "axes.grid": True,
    "grid.linewidth": 0.5,
    "grid.alpha": 0.35,
    "axes.axisbelow": True,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.formatter.limits": (-3, 4),
    "axes.unicode_minus": True,
    "lines.linewidth": 1.4,
    "lines.markersize": 4,
    "errorbar.capsize": 0,
    "image.cmap": "viridis",
    "pdf.fonttype": 42,               # TrueType in PDF: text stays text (searchable, editable)
    "svg.hashsalt": "coinwall",       # the same figure gives the same SVG bytes
}


def house_style():
    """A context in which matplotlib draws in :data:`HOUSE_STYLE` (``matplotlib.rc_context``)."""
    import matplotlib

    return matplotlib.rc_context(HOUSE_STYLE)


def styled(function):
    """Decorator: run a figure-drawing ``function`` in :func:`house_style` (labels and ticks made inside it
    take the house sizes; rcParams are read when an artist is made)."""
    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        with house_style():
            return function(*args, **kwargs)

    return wrapper


def wall_label(wall, name: str | None = None, width: int = 70) -> str:
    """How a figure names a wall: ``name`` (as the user wrote it, e.g. ``case:coin``) when given, else the wall's
    description, then its parameters (``eps = 0.55``); descriptions longer than ``width`` are shortened."""
    text = str(name) if name else str(getattr(wall, "description", wall))
    if len(text) > width:
        text = text[: width - 1] + "…"
    params = getattr(wall, "params", None) or {}
    if params and "=" not in text:
        names = {"eps": "ε", "epsilon": "ε"}
        text += ", " + ", ".join(f"{names.get(k, k)} = {v:g}" for k, v in sorted(params.items()))
    return text


def _plain(value, _position=None) -> str:
    """A tick label in plain numbers: %g with a real minus sign (0.5, 2, 40)."""
    if value == 0 or not math.isfinite(value):
        return "0"
    return f"{value:.6g}".replace("-", "\u2212")


def _powers(value, _position=None) -> str:
    """A tick label as a power of ten: 10⁻⁵, 2×10⁻⁵ (mathtext)."""
    if value <= 0 or not math.isfinite(value):
        return "0"
    exponent = math.floor(math.log10(value) + 1e-9)
    mantissa = round(value / 10.0**exponent, 6)
    if abs(mantissa - 1) < 1e-6:
        return f"$10^{{{exponent}}}$"
    return f"${mantissa:g}\\times10^{{{exponent}}}$"


def plain_log_axis(axis):
    """One number format on a log axis, major and minor ticks alike: plain numbers (0.5, 2, 40) when the view
    lies within [10⁻³, 10⁵], powers of ten (10⁻⁵, 2×10⁻⁵) for every label otherwise.

    Minor ticks (2 … 9 × a decade) are labelled only when fewer than two decades are in view (at 2 and 5 when
    more than one is); call after the data are drawn (the view decides)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    low, high = sorted(axis.get_view_interval())
    decades = math.log10(high / low) if low > 0 and high > 0 else math.inf
    label = _plain if (low >= 1e-3 and high <= 1e5) else _powers
    axis.set_major_locator(LogLocator(base=10.0))
    axis.set_major_formatter(FuncFormatter(label))
    subs = (2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0)
    if decades < 1.0:
        labelled = (2.0, 3.0, 5.0, 7.0) if decades > 0.5 else subs
    elif decades < 2.0:
        labelled = (2.0, 5.0)
    else:
        labelled = ()
    axis.set_minor_locator(LogLocator(base=10.0, subs=subs))
    if labelled:
        def minor(value, position=None):
            mantissa = value / 10 ** math.floor(math.log10(value) + 1e-9)
            return label(value) if any(abs(mantissa - s) < 1e-6 for s in labelled) else ""

        axis.set_minor_formatter(FuncFormatter(minor))
    else:
        axis.set_minor_formatter(NullFormatter())


def shade_angle_window(ax, low: float, high: float, **kwargs):
    """Shade the angles ``[low, high]`` (radians, any turn) on an axis drawn over [0, 2π]: a window that wraps
    past 2π (or below 0) is shaded as two spans, both inside [0, 2π].  Returns the spans."""
    two_pi = 2.0 * math.pi
    width = high - low
    if width >= two_pi:
        return [ax.axvspan(0.0, two_pi, **kwargs)]
    start = low % two_pi
    end = start + width
    if end <= two_pi:
        return [ax.axvspan(start, end, **kwargs)]
    first = ax.axvspan(start, two_pi, **kwargs)
    kwargs.pop("label", None)  # one legend entry for the window
    return [first, ax.axvspan(0.0, end - two_pi, **kwargs)]
