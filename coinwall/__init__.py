"""coinwall: rigid bodies bouncing between parallel walls as point-particle billiards.

Balazs, Chatterjee & Jackson, "Coin Tossing as a Billiard Problem" (chao-dyn/9502011): the walls of
the billiard are the body's support function b(θ).  coinwall solves the inverse problem (wall → body),
the forward one (body → wall), and simulates and analyses the billiard.

The everyday API is importable from here; it is loaded on first use, so ``import coinwall`` stays fast::

    from coinwall import Wall, solve_body, critical_offset

    wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    body = solve_body(wall, b0=-0.6)

The three parts are subpackages: ``coinwall.forward`` (walls, outlines, file formats, dynamics),
``coinwall.inverse`` (wall → body, exports) and ``coinwall.cases`` (the named cases, the paper's claims,
the command line).
"""

from ._lazy import attach_stub
from ._version import __version__

# Public name -> the module that defines it: __init__.pyi, read by attach_stub.  Loaded lazily (PEP 562)
# so that ``import coinwall`` and ``coinwall --help`` do not pay for numpy/scipy/casadi before they are
# needed.
__getattr__, __dir__, _names = attach_stub(__name__, __file__)
__all__ = ["__version__", *_names]
