"""The motion: the billiard and its compiled kernel, the rigid body it is equivalent to, and the
analyses of the motion (Poincaré sections, Lyapunov exponents, P(n), the KAM boundary)."""

from .billiard import Billiard, Trajectory, compile_kernel, ensemble, random_states, simulate
from .rigidbody import (EllipseShape, PolygonShape, RigidBody, RigidBodyTrajectory, billiard_to_body,
                        body_to_billiard, simulate_rigid_body)
from .poincare import PoincareSection, incidence_angle, poincare_section
from .lyapunov import ChaoticFraction, LyapunovResult, chaotic_fraction, lyapunov, lyapunov_many
from .correlation import Correlation, TauLaw, correlation, fit_tau_law, heads
from .kam import KamBoundary, kam_boundary, paper_boundary
from .orbitstats import OrbitStatistics, orbit_statistics

__all__ = [
    "Billiard", "Trajectory", "compile_kernel", "ensemble", "random_states", "simulate",
    "EllipseShape", "PolygonShape", "RigidBody", "RigidBodyTrajectory", "billiard_to_body", "body_to_billiard",
    "simulate_rigid_body",
    "PoincareSection", "incidence_angle", "poincare_section",
    "ChaoticFraction", "LyapunovResult", "chaotic_fraction", "lyapunov", "lyapunov_many",
    "Correlation", "TauLaw", "correlation", "fit_tau_law", "heads",
    "KamBoundary", "kam_boundary", "paper_boundary",
    "OrbitStatistics", "orbit_statistics",
]
