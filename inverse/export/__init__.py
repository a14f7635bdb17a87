"""Exporters of solved bodies, chosen by file extension.

``EXPORTERS`` maps each extension to its module.  Every exporter module defines ``EXTENSION`` and
``write(body, stream, options=None)``: it writes the bytes of the file to the binary ``stream``,
following the :class:`ExportOptions` (physical scale, tolerance) where they apply, and may return a
report ``{name: achieved deviation, ..., "tolerance": t}``.  Adding a format is adding one module
and one line to ``EXPORTERS``.  Files are written atomically: all outputs go to temporary files
first and are renamed only when every one of them succeeded, so a failure leaves nothing behind.
The same body and options always give the same bytes (no dates or timings inside).
"""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
