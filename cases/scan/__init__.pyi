"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .driver import ScanResult, make_axes, scan
from .grid import Axis, cell_seed, parse_axis
from .quantities import QUANTITIES, Quantity, check_options, compute_cell
from .table import TableSpec

__all__ = ["Axis", "QUANTITIES", "Quantity", "ScanResult", "TableSpec", "cell_seed", "check_options", "compute_cell",
           "make_axes", "parse_axis", "scan"]
