"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .core import EXPORTERS, ExportResult, check_outputs, export_body, exporters, write_outputs
from .options import UNITS, ExportOptions

__all__ = ["EXPORTERS", "ExportOptions", "ExportResult", "UNITS", "check_outputs", "export_body", "exporters",
           "write_outputs"]
