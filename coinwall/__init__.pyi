"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

__version__: str
from .cases.catalog import all_cases, get_case
from .forward.dynamics.billiard.table import Billiard, ensemble, random_states, simulate
from .forward.dynamics.billiard.trajectory import Trajectory
from .forward.dynamics.analysis.correlation import correlation
from .forward.dynamics.analysis.kam import kam_boundary
from .forward.dynamics.analysis.lyapunov import chaotic_fraction, lyapunov
from .forward.dynamics.analysis.poincare import poincare_section
from .forward.dynamics.billiard.rigidbody import RigidBody, simulate_rigid_body
from .forward.errors import (
    CoinwallError,
    InvalidArgument,
    InvalidExpression,
    InvalidOutline,
    InvalidParameter,
    InvalidWall,
    OutputError,
)
from .forward.formats.load import load_outline, outline_from_polar
from .forward.massprops import MassProperties, mass_properties
from .forward.outline import Outline, support_function
from .forward.quantum.spectrum import quantum_spectrum
from .forward.quantum.strip import make_strip
from .forward.quantum.tunnelling import doublet_splitting
from .forward.support import wall_functions
from .forward.wall import Kink, Wall
from .inverse.body import Body
from .inverse.corners import Corner
from .inverse.critical import CriticalOffset, critical_offset
from .inverse.export.core import export_body
from .inverse.realizability import kappa_max, realizability, self_consistent_offset
from .inverse.solve import solve_body

__all__ = ["__version__", "Billiard", "Body", "CoinwallError", "Corner", "CriticalOffset", "InvalidArgument",
           "InvalidExpression", "InvalidOutline", "InvalidParameter", "InvalidWall", "Kink", "MassProperties",
           "Outline", "OutputError", "RigidBody", "Trajectory", "Wall", "all_cases", "chaotic_fraction",
           "correlation", "critical_offset", "doublet_splitting", "ensemble", "export_body", "get_case",
           "kam_boundary", "kappa_max", "load_outline", "lyapunov", "make_strip", "mass_properties",
           "outline_from_polar", "poincare_section", "quantum_spectrum", "random_states", "realizability",
           "self_consistent_offset", "simulate", "simulate_rigid_body", "solve_body", "support_function",
           "wall_functions"]
