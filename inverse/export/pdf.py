"""PDF export: the body's figure as vector graphics for papers (see :mod:`.figure`)."""

from .figure import write_figure

__all__ = ["EXTENSION", "write"]

EXTENSION = ".pdf"


def write(body, stream, options=None):
    """Write the PDF to a binary ``stream`` (always in units of κ: ``options`` do not apply)."""
    write_figure(body, stream, EXTENSION)
