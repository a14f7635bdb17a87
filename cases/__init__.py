"""coinwall cases: named walls and bodies of the paper and beyond, with reference values and provenance."""

from .catalog import Case, Reference, all_cases, get_case
from .ellipse import ELLIPSE_WALL, EXAMPLE, ellipse_critical_offset, ellipse_outline, ellipse_wall
from .stick import STICK_WALL, stick_outline, stick_wall

__all__ = ["Case", "Reference", "all_cases", "get_case", "ELLIPSE_WALL", "EXAMPLE", "ellipse_critical_offset",
           "ellipse_outline", "ellipse_wall", "STICK_WALL", "stick_outline", "stick_wall"]
