"""coinwall forward side: wall functions, outlines and their support functions (body → wall)."""

from .errors import (CoinwallError, InvalidArgument, InvalidExpression, InvalidOutline, InvalidParameter,
                     InvalidWall, OutputError)
from .bodyfile import load_outline, wall_functions
from .outline import Outline, support_function
from .wall import Kink, Wall

__all__ = [
    "CoinwallError", "InvalidArgument", "InvalidExpression", "InvalidOutline", "InvalidParameter",
    "InvalidWall", "OutputError", "load_outline", "wall_functions", "Outline", "support_function", "Kink", "Wall",
]
