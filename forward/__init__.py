"""coinwall forward side: wall functions, outlines and their support functions (body → wall), the
billiard and the rigid body it is equivalent to, and the analyses of the motion."""

from .dynamics.billiard import Billiard, Trajectory, ensemble, random_states, simulate
from .dynamics.correlation import Correlation, TauLaw, correlation, fit_tau_law, heads
from .dynamics.kam import KamBoundary, kam_boundary, paper_boundary
from .dynamics.lyapunov import ChaoticFraction, LyapunovResult, chaotic_fraction, lyapunov, lyapunov_many
from .dynamics.poincare import PoincareSection, incidence_angle, poincare_section
from .dynamics.rigidbody import (
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
from .support import wall_functions
from .wall import Kink, Wall

__all__ = [
    "CoinwallError", "InvalidArgument", "InvalidExpression", "InvalidOutline", "InvalidParameter",
    "InvalidWall", "OutputError",
    "load_outline", "outline_from_polar", "wall_functions", "Outline", "support_function", "Kink", "Wall",
    "MassProperties", "mass_properties", "outline_moments", "parse_density",
    "Billiard", "Trajectory", "ensemble", "random_states", "simulate",
    "EllipseShape", "PolygonShape", "RigidBody", "RigidBodyTrajectory", "billiard_to_body", "body_to_billiard",
    "simulate_rigid_body",
    "PoincareSection", "incidence_angle", "poincare_section",
    "ChaoticFraction", "LyapunovResult", "chaotic_fraction", "lyapunov", "lyapunov_many",
    "Correlation", "TauLaw", "correlation", "fit_tau_law", "heads",
    "KamBoundary", "kam_boundary", "paper_boundary",
]
