"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .analysis.correlation import Correlation, TauLaw, correlation, fit_tau_law, heads
from .analysis.islands import paper_boundary
from .analysis.kam import KamBoundary, kam_boundary
from .analysis.lyapunov import ChaoticFraction, LyapunovResult, chaotic_fraction, lyapunov, lyapunov_many
from .analysis.orbitstats import EnsembleStatistics, OrbitStatistics, ensemble_statistics, orbit_statistics
from .analysis.poincare import PoincareSection, incidence_angle, poincare_section
from .billiard.rigidbody import (
    EllipseShape,
    PolygonShape,
    RigidBody,
    RigidBodyTrajectory,
    billiard_to_body,
    body_to_billiard,
    simulate_rigid_body,
)
from .billiard.table import Billiard, compile_kernel, ensemble, random_states, simulate
from .billiard.trajectory import Trajectory
from .coin3d.bounced import BounceStudy, same_side_by_bounce
from .coin3d.caught import PsiFit, dhm_same_side, fit_psi, simulate_caught
from .coin3d.correlation3d import side_correlation
from .coin3d.rest import rest_outcomes
from .coin3d.rigid3d import Rigid3D, Trajectory3D, simulate_3d
from .coin3d.top import TopFlight, TopTable, top_run
from .floor.fairness import Fairness, fairness, fairness_curve
from .floor.field import FieldTable, Flight, field_run, field_run_many
from .floor.hand import Tosses, heads_fraction, launch_spread, toss_outcomes
from .floor.toss import BasinMap, basin_map
from .floor.uncertainty import Uncertainty, uncertainty_exponent
from .floor.wedge import WedgeLyapunov, wedge_lyapunov

__all__ = ["BasinMap", "Billiard", "BounceStudy", "ChaoticFraction", "Correlation", "EllipseShape",
           "EnsembleStatistics", "Fairness",
           "FieldTable", "Flight", "KamBoundary", "LyapunovResult", "OrbitStatistics", "PoincareSection",
           "PolygonShape", "PsiFit", "Rigid3D", "RigidBody", "RigidBodyTrajectory", "TauLaw", "TopFlight", "TopTable",
           "Tosses", "Trajectory", "Trajectory3D", "Uncertainty", "WedgeLyapunov", "basin_map", "billiard_to_body",
           "body_to_billiard", "chaotic_fraction", "compile_kernel", "correlation", "dhm_same_side", "ensemble",
           "ensemble_statistics",
           "fairness", "fairness_curve", "field_run", "field_run_many", "fit_psi", "fit_tau_law", "heads",
           "heads_fraction", "incidence_angle", "kam_boundary", "launch_spread", "lyapunov", "lyapunov_many",
           "orbit_statistics", "paper_boundary", "poincare_section", "random_states", "rest_outcomes",
           "same_side_by_bounce", "side_correlation", "simulate", "simulate_3d", "simulate_caught",
           "simulate_rigid_body", "top_run", "toss_outcomes", "uncertainty_exponent", "wedge_lyapunov"]
