"""File formats: one module per format, holding its reader and the constants its writer uses.

``svg``, ``dxf``, ``bodyjson`` (the body JSON of ``coinwall solve``) and ``points`` (CSV x,y) read body
outlines; ``load`` turns what they read into an :class:`Outline` (``load_outline``,
``outline_from_polar``); ``wallfile`` reads walls (``load_wall``, ``load_wall_file``); ``output``
writes files all or nothing and ``figure`` renders figures as PNG, SVG or PDF.
"""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
