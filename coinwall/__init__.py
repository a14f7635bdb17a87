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

import importlib

from ._version import __version__

# Public name -> the module that defines it.  Loaded lazily (PEP 562) so that ``import coinwall`` and
# ``coinwall --help`` do not pay for numpy/scipy/casadi before they are needed.
_API = {
    # the shared core
    "CoinwallError": "coinwall.forward.errors", "InvalidArgument": "coinwall.forward.errors",
    "InvalidExpression": "coinwall.forward.errors", "InvalidOutline": "coinwall.forward.errors",
    "InvalidParameter": "coinwall.forward.errors", "InvalidWall": "coinwall.forward.errors",
    "OutputError": "coinwall.forward.errors",
    "Wall": "coinwall.forward.wall", "Kink": "coinwall.forward.wall",
    "Outline": "coinwall.forward.outline", "support_function": "coinwall.forward.outline",
    "MassProperties": "coinwall.forward.massprops", "mass_properties": "coinwall.forward.massprops",
    # files
    "load_outline": "coinwall.forward.formats", "outline_from_polar": "coinwall.forward.formats",
    "wall_functions": "coinwall.forward.formats",
    # the inverse problem
    "Body": "coinwall.inverse", "Corner": "coinwall.inverse", "CriticalOffset": "coinwall.inverse",
    "critical_offset": "coinwall.inverse", "solve_body": "coinwall.inverse", "kappa_max": "coinwall.inverse",
    "realizability": "coinwall.inverse", "self_consistent_offset": "coinwall.inverse",
    "export_body": "coinwall.inverse.export",
    # the motion
    "Billiard": "coinwall.forward.dynamics", "Trajectory": "coinwall.forward.dynamics",
    "simulate": "coinwall.forward.dynamics", "ensemble": "coinwall.forward.dynamics",
    "random_states": "coinwall.forward.dynamics", "RigidBody": "coinwall.forward.dynamics",
    "simulate_rigid_body": "coinwall.forward.dynamics", "poincare_section": "coinwall.forward.dynamics",
    "lyapunov": "coinwall.forward.dynamics", "chaotic_fraction": "coinwall.forward.dynamics",
    "correlation": "coinwall.forward.dynamics", "kam_boundary": "coinwall.forward.dynamics",
    # the quantum body
    "quantum_spectrum": "coinwall.forward.quantum", "doublet_splitting": "coinwall.forward.quantum",
    "make_strip": "coinwall.forward.quantum",
    # the named cases
    "get_case": "coinwall.cases", "all_cases": "coinwall.cases",
}

__all__ = ["__version__", *_API]


def __getattr__(name):
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'coinwall' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__():
    return sorted(set(globals()) | set(_API))
