"""What a figure at publication size must be, checked on the figure itself (shared by the figure, gallery and
command-line tests): its PNG, as the house writer saves it, at least ``PNG_MIN_WIDTH`` pixels wide, and no
legend over a text (:func:`coinwall.forward.formats.style.legend_overlaps`)."""

from __future__ import annotations

from coinwall.forward.formats.figure import PNG_MIN_WIDTH, figure_bytes
from coinwall.forward.formats.style import legend_overlaps


def png_size(data: bytes):
    """(width, height) in pixels of PNG bytes (read from the IHDR chunk: no image library needed)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def figure_problems(fig) -> list:
    """Sentences naming what keeps ``fig`` from publication (``[]``: nothing); the figure stays open."""
    problems = legend_overlaps(fig)
    width, _ = png_size(figure_bytes(fig, "figure.png", close=False))
    if width < PNG_MIN_WIDTH:
        problems.append(f"the PNG is {width} px wide, below {PNG_MIN_WIDTH}")
    return problems
