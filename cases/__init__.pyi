"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .bartos import BartosFits, bartos_counts, bartos_fits
from .catalog import Case, Reference, all_cases, get_case
from .ellipse import ELLIPSE_WALL, EXAMPLE, ellipse_critical_offset, ellipse_outline, ellipse_wall
from .stick import STICK_WALL, stick_outline, stick_wall

__all__ = ["BartosFits", "Case", "ELLIPSE_WALL", "EXAMPLE", "Reference", "STICK_WALL", "all_cases", "bartos_counts", "bartos_fits", "ellipse_critical_offset",
           "ellipse_outline", "ellipse_wall", "get_case", "stick_outline", "stick_wall"]
