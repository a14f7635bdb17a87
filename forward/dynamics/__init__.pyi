"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .billiard import Billiard, Trajectory, compile_kernel, ensemble, random_states, simulate
from .correlation import Correlation, TauLaw, correlation, fit_tau_law, heads
from .islands import paper_boundary
from .kam import KamBoundary, kam_boundary
from .lyapunov import ChaoticFraction, LyapunovResult, chaotic_fraction, lyapunov, lyapunov_many
from .orbitstats import OrbitStatistics, orbit_statistics
from .poincare import PoincareSection, incidence_angle, poincare_section
from .rigidbody import (
    EllipseShape,
    PolygonShape,
    RigidBody,
    RigidBodyTrajectory,
    billiard_to_body,
    body_to_billiard,
    simulate_rigid_body,
)

__all__ = ["Billiard", "ChaoticFraction", "Correlation", "EllipseShape", "KamBoundary", "LyapunovResult",
           "OrbitStatistics", "PoincareSection", "PolygonShape", "RigidBody", "RigidBodyTrajectory", "TauLaw",
           "Trajectory", "billiard_to_body", "body_to_billiard", "chaotic_fraction", "compile_kernel", "correlation",
           "ensemble", "fit_tau_law", "heads", "incidence_angle", "kam_boundary", "lyapunov", "lyapunov_many",
           "orbit_statistics", "paper_boundary", "poincare_section", "random_states", "simulate",
           "simulate_rigid_body"]
