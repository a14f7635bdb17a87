"""coinwall cases: named walls and bodies of the paper, with reference values."""

from .ellipse import ELLIPSE_WALL, EXAMPLE, ellipse_critical_offset, ellipse_wall
from .stick import STICK_WALL, stick_wall

__all__ = ["ELLIPSE_WALL", "EXAMPLE", "ellipse_critical_offset", "ellipse_wall", "STICK_WALL", "stick_wall"]
