"""PNG export: the body's figure (outline, wall, radius of curvature; see :mod:`.figure`)."""

from .figure import write_figure

__all__ = ["EXTENSION", "write"]

EXTENSION = ".png"


def write(body, stream, options=None):
    """Write the PNG to a binary ``stream`` (always in units of κ: ``options`` do not apply)."""
    write_figure(body, stream, EXTENSION)
