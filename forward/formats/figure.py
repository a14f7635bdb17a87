"""Figures as files: the format follows the output's extension (PNG for screens, SVG or PDF for papers).

Every figure is made and written in the house style (:mod:`.style`): :func:`new_figure` and :func:`axes_or_new`
create it, :func:`figure_bytes` writes it.  A PNG is written at publication size: at least
:data:`PNG_MIN_WIDTH` pixels wide whatever the figure's size in inches (:func:`png_dpi`), so a small
one-panel figure and a wide three-panel one are both sharp on a page or a slide.
"""

from __future__ import annotations

import io
import os

from ..errors import OutputError

__all__ = ["FIGURE_FORMATS", "PNG_MIN_WIDTH", "axes_or_new", "figure_bytes", "new_figure", "png_dpi"]

FIGURE_FORMATS = (".png", ".svg", ".pdf")
#: the least width of a PNG written by :func:`figure_bytes` (and of the gallery's pictures), in pixels
PNG_MIN_WIDTH = 1600


def new_figure(*args, **kwargs):
    """``matplotlib.pyplot.subplots`` on the non-interactive Agg backend (no display needed), in the house style."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .style import house_style

    with house_style():
        return plt.subplots(*args, **kwargs)


def axes_or_new(ax, figsize):
    """``(ax, created)``: the caller's axes, or the axes of a new figure of ``figsize`` (the ``.plot(ax=None)``
    methods; ``created`` says whether the layout of the figure is theirs to finish)."""
    if ax is not None:
        return ax, False
    _, ax = new_figure(figsize=figsize)
    return ax, True


def png_dpi(fig, width: int = PNG_MIN_WIDTH) -> float:
    """The resolution (dots per inch) at which ``fig``, cropped to its drawn content as the house style saves
    it (``bbox_inches="tight"``), is at least ``width`` pixels wide; never below the house style's 150 dpi.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure whose content is drawn (its layout engine, if any, runs here).
    width : int
        The least width in pixels.

    Returns
    -------
    float
        Dots per inch, a whole number.

    Examples
    --------
    >>> from coinwall.forward.formats.figure import new_figure, png_dpi
    >>> fig, ax = new_figure(figsize=(4, 3))
    >>> _ = ax.plot([0, 1], [0, 1])
    >>> png_dpi(fig) >= 1600 / 4
    True
    """
    import math

    from .style import HOUSE_STYLE, house_style

    with house_style():
        fig.draw_without_rendering()
        box = fig.get_tightbbox()  # inches; the text is sized in points, so this does not depend on the dpi
    inches = box.width + 2 * HOUSE_STYLE["savefig.pad_inches"]
    return float(max(HOUSE_STYLE["savefig.dpi"], math.ceil(width / inches) + 1))


def figure_bytes(fig, path: str, *, close: bool = True) -> bytes:
    """The content of ``fig`` in the format named by the extension of ``path`` (.png, .svg or .pdf).

    Written in the house style (text as TrueType in PDF); a PNG at least :data:`PNG_MIN_WIDTH` pixels wide
    (:func:`png_dpi`).  SVG and PDF output carry no creation date, so the same figure gives the same bytes.
    """
    ext = os.path.splitext(path)[1].lower()
    if ext not in FIGURE_FORMATS:
        raise OutputError(f"figure {path!r}: unknown extension {ext or '(none)'!r}; known: {', '.join(FIGURE_FORMATS)}")
    import matplotlib.pyplot as plt

    from .style import house_style

    buffer = io.BytesIO()
    metadata = {"svg": {"Date": None}, "pdf": {"CreationDate": None, "ModDate": None}}.get(ext[1:])
    size = {"dpi": png_dpi(fig)} if ext == ".png" else {}
    with house_style():
        fig.savefig(buffer, format=ext[1:], metadata=metadata, **size)
    if close:
        plt.close(fig)
    return buffer.getvalue()
