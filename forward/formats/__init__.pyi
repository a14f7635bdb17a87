"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .load import OUTLINE_FORMATS, load_outline, outline_from_polar
from .output import check_paths, write_all
from .wallfile import WALL_FORMATS, load_wall, load_wall_file

__all__ = ["OUTLINE_FORMATS", "WALL_FORMATS", "check_paths", "load_outline", "load_wall", "load_wall_file",
           "outline_from_polar", "write_all"]
