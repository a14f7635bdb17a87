"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .dynamics.billiard.table import Billiard, ensemble, random_states, simulate
from .dynamics.billiard.trajectory import Trajectory
from .dynamics.analysis.correlation import Correlation, TauLaw, correlation, fit_tau_law, heads
from .dynamics.analysis.islands import paper_boundary
from .dynamics.analysis.kam import KamBoundary, kam_boundary
from .dynamics.analysis.lyapunov import ChaoticFraction, LyapunovResult, chaotic_fraction, lyapunov, lyapunov_many
from .dynamics.analysis.poincare import PoincareSection, incidence_angle, poincare_section
from .dynamics.billiard.rigidbody import (
    EllipseShape,
    PolygonShape,
    RigidBody,
    RigidBodyTrajectory,
    billiard_to_body,
    body_to_billiard,
    simulate_rigid_body,
)
from .errors import (
    CoinwallError,
    InvalidArgument,
    InvalidExpression,
    InvalidOutline,
    InvalidParameter,
    InvalidWall,
    OutputError,
)
from .formats.load import load_outline, outline_from_polar
from .massprops import MassProperties, mass_properties, outline_moments, parse_density
from .outline import Outline, support_function
from .revolution import Revolution
from .support import wall_functions
from .wall import Kink, Wall

__all__ = ["Billiard", "ChaoticFraction", "CoinwallError", "Correlation", "EllipseShape", "InvalidArgument",
           "InvalidExpression", "InvalidOutline", "InvalidParameter", "InvalidWall", "KamBoundary", "Kink",
           "LyapunovResult", "MassProperties", "Outline", "OutputError", "PoincareSection", "PolygonShape",
           "Revolution", "RigidBody", "RigidBodyTrajectory", "TauLaw", "Trajectory", "Wall", "billiard_to_body", "body_to_billiard",
           "chaotic_fraction", "correlation", "ensemble", "fit_tau_law", "heads", "incidence_angle", "kam_boundary",
           "load_outline", "lyapunov", "lyapunov_many", "mass_properties", "outline_from_polar", "outline_moments",
           "paper_boundary", "parse_density", "poincare_section", "random_states", "simulate", "simulate_rigid_body",
           "support_function", "wall_functions"]
