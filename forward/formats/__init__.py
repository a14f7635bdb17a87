"""File formats: one module per format, holding its reader and the constants its writer uses."""

from .bodyfile import load_outline, outline_from_polar, wall_functions
from .output import check_paths, write_all

__all__ = ["load_outline", "outline_from_polar", "wall_functions", "check_paths", "write_all"]
