"""Figures as files: the format follows the output's extension (PNG for screens, SVG or PDF for papers).

Every figure is made and written in the house style (:mod:`.style`): :func:`new_figure` and :func:`axes_or_new`
create it, :func:`figure_bytes` writes it.
"""

from __future__ import annotations

import io
import os

from ..errors import OutputError

__all__ = ["FIGURE_FORMATS", "axes_or_new", "figure_bytes", "new_figure"]

FIGURE_FORMATS = (".png", ".svg", ".pdf")


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


def figure_bytes(fig, path: str, *, close: bool = True) -> bytes:
    """The content of ``fig`` in the format named by the extension of ``path`` (.png, .svg or .pdf).

    Written in the house style (150 dpi for PNG; text as TrueType in PDF).  SVG and PDF output carry no
    creation date, so the same figure gives the same bytes.
    """
    ext = os.path.splitext(path)[1].lower()
    if ext not in FIGURE_FORMATS:
        raise OutputError(f"figure {path!r}: unknown extension {ext or '(none)'!r}; known: {', '.join(FIGURE_FORMATS)}")
    import matplotlib.pyplot as plt

    from .style import house_style

    buffer = io.BytesIO()
    metadata = {"svg": {"Date": None}, "pdf": {"CreationDate": None, "ModDate": None}}.get(ext[1:])
    with house_style():
        fig.savefig(buffer, format=ext[1:], metadata=metadata)
    if close:
        plt.close(fig)
    return buffer.getvalue()
