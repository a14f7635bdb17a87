"""The house style of every coinwall figure, in one place.

:data:`HOUSE_STYLE` is a matplotlib style (a dictionary of rcParams, usable as ``matplotlib.style.use(HOUSE_STYLE)``
or ``matplotlib.rc_context(HOUSE_STYLE)``).  The figures apply it only while they draw
(:func:`house_style`, :func:`styled`), so a program that imports coinwall keeps its own settings.

The rules the figures follow with it:

* the title or caption says what is shown: the wall (:func:`wall_label`), its parameters, H, the counts;
* every axis names its quantity and its unit, ``quantity (unit)``; dimensionless quantities say so;
* colour that carries a value has a colour bar with its quantity;
* a legend covers no text: inside the axes where the curves leave room, else below the x label
  (:func:`legend_below`); :func:`legend_overlaps` finds one that does;
* log axes print every tick label in one format (:func:`plain_log_axis`): 0.5, 2, 40 — not 5×10⁻¹ beside 1.0;
* the file format follows the extension: .png for screens, .svg and .pdf (vector) for papers.
"""

from __future__ import annotations

import functools
import math

__all__ = ["HOUSE_STYLE", "PALETTE", "house_style", "legend_below", "legend_overlaps", "plain_log_axis",
           "shade_angle_window", "styled", "wall_label"]

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


def legend_below(ax, **kwargs):
    """Put the legend of ``ax`` under its x label, centred, whatever the height of the panel.

    The legend hangs a fixed distance in points below the axes: the tick marks, the tick labels and the
    lines of the x label as they are when this is called (call it after ``set_xlabel``).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes whose legend it is.
    **kwargs
        Passed to ``ax.legend`` (``ncol``, ``fontsize``, ``handles``, ...).

    Returns
    -------
    matplotlib.legend.Legend

    Examples
    --------
    >>> from coinwall.forward.formats.figure import new_figure
    >>> fig, ax = new_figure()
    >>> _ = ax.plot([0, 1], [0, 1], label="a line")
    >>> _ = ax.set_xlabel("time t (s)")
    >>> legend = legend_below(ax)
    >>> legend_overlaps(fig)
    []
    """
    from matplotlib.transforms import offset_copy

    xaxis = ax.xaxis
    ticks = xaxis.get_major_ticks()
    tick = ticks[0] if ticks else None
    tick_size = tick.label1.get_fontsize() if tick is not None else 10.0
    drop = (tick.tick1line.get_markersize() + tick.get_pad() if tick is not None else 7.0) + 1.4 * tick_size
    text = xaxis.label.get_text()
    if text.strip():
        drop += xaxis.labelpad + 1.3 * xaxis.label.get_fontsize() * (text.count("\n") + 1)
    anchor = offset_copy(ax.transAxes, fig=ax.figure, y=-(drop + 2.0), units="points")
    kwargs.setdefault("loc", "upper center")
    return ax.legend(bbox_to_anchor=(0.5, 0.0), bbox_transform=anchor, **kwargs)


def _texts_of(fig):
    """(what, text artist) of every visible, non-empty text a legend must leave clear."""
    found = [("the figure title", fig._suptitle)] if fig._suptitle is not None else []
    for k, ax in enumerate(fig.axes):
        name = f"axes {k}"
        found += [(f"{name}: x label", ax.xaxis.label), (f"{name}: y label", ax.yaxis.label)]
        found += [(f"{name}: title", t) for t in (ax.title, ax._left_title, ax._right_title)]
        for axis, which in ((ax.xaxis, "x"), (ax.yaxis, "y")):
            low, high = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                # a tick outside the view is kept by matplotlib but not drawn, its label left where it was
                if tick.get_visible() and tick.get_loc() is not None and low <= tick.get_loc() <= high:
                    found += [(f"{name}: {which} tick label {t.get_text()!r}", t) for t in (tick.label1, tick.label2)]
    return [(what, t) for what, t in found if t.get_visible() and t.get_text().strip()]


def legend_overlaps(fig, slack: float = 1.0) -> list:
    """Every legend of ``fig`` that covers a text it does not own — an axis label, a tick label, a title, the
    figure's title — or another legend, as one sentence each (``[]``: none).

    Boxes are the drawn extents in display pixels after the layout has run; two boxes overlap when they
    share more than ``slack`` pixels in both directions.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, drawn here (its layout engine runs).
    slack : float
        Pixels two boxes may share without counting as overlapping.

    Returns
    -------
    list of str
        One sentence per overlap, naming the legend by its first entry and what it covers.

    Examples
    --------
    >>> from coinwall.forward.formats.figure import new_figure
    >>> fig, ax = new_figure()
    >>> _ = ax.plot([0, 1], [0, 1], label="a line")
    >>> _ = ax.set_xlabel("time t (s)")
    >>> _ = ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.02))  # on the labels of the x axis
    >>> legend_overlaps(fig)[0]
    "legend 1 ('a line') covers axes 0: x label"
    """
    with house_style():
        fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends)
    legends = [legend for legend in legends if legend.get_visible()]
    texts = [(what, t.get_window_extent(renderer)) for what, t in _texts_of(fig)]

    def overlap(a, b):
        return min(a.x1, b.x1) - max(a.x0, b.x0) > slack and min(a.y1, b.y1) - max(a.y0, b.y0) > slack

    problems = []
    boxes = [legend.get_window_extent(renderer) for legend in legends]
    for i, (legend, box) in enumerate(zip(legends, boxes), start=1):
        entries = legend.get_texts()
        name = f"legend {i} ({entries[0].get_text()[:30]!r})" if entries else f"legend {i}"
        problems += [f"{name} covers {what}" for what, extent in texts if overlap(box, extent)]
        problems += [f"{name} covers legend {j}" for j, other in enumerate(boxes[i:], start=i + 1)
                     if overlap(box, other)]
    return problems
