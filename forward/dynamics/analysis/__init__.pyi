"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1)."""

from .correlation import Correlation, TauLaw, correlation, fit_tau_law, heads
from .islands import paper_boundary
from .kam import KamBoundary, kam_boundary
from .lyapunov import ChaoticFraction, LyapunovResult, chaotic_fraction, lyapunov, lyapunov_many
from .orbitstats import EnsembleStatistics, OrbitStatistics, ensemble_statistics, orbit_statistics
from .poincare import PoincareSection, incidence_angle, poincare_section

__all__ = [
    "ChaoticFraction",
    "Correlation",
    "EnsembleStatistics",
    "KamBoundary",
    "LyapunovResult",
    "OrbitStatistics",
    "PoincareSection",
    "TauLaw",
    "chaotic_fraction",
    "correlation",
    "ensemble_statistics",
    "fit_tau_law",
    "heads",
    "incidence_angle",
    "kam_boundary",
    "lyapunov",
    "lyapunov_many",
    "orbit_statistics",
    "paper_boundary",
    "poincare_section",
]
