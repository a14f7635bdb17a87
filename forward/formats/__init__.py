"""File formats: one module per format, holding its reader and the constants its writer uses.

``svg``, ``dxf``, ``bodyjson`` (the body JSON of ``coinwall solve``) and ``points`` (CSV x,y) read body
outlines; ``load`` turns what they read into an :class:`Outline` (``load_outline``,
``outline_from_polar``); ``wallfile`` reads walls (``load_wall``, ``load_wall_file``); ``output``
writes files all or nothing and ``figure`` renders figures as PNG, SVG or PDF.
"""

from ..support import wall_functions
from .load import OUTLINE_FORMATS, load_outline, outline_from_polar
from .output import check_paths, write_all
from .wallfile import WALL_FORMATS, load_wall, load_wall_file

__all__ = [
           "OUTLINE_FORMATS",
           "WALL_FORMATS",
           "check_paths",
           "load_outline",
           "load_wall",
           "load_wall_file",
           "outline_from_polar",
           "wall_functions",
           "write_all",
]
