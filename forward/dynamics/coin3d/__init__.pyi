"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1)."""

from .bounced import BounceStudy, same_side_by_bounce
from .caught import PsiFit, dhm_same_side, fit_psi, simulate_caught
from .correlation3d import side_correlation
from .rest import rest_outcomes
from .rigid3d import Rigid3D, Trajectory3D, simulate_3d
from .top import TopFlight, TopTable, top_run

__all__ = [
    "BounceStudy",
    "PsiFit",
    "Rigid3D",
    "TopFlight",
    "TopTable",
    "Trajectory3D",
    "dhm_same_side",
    "rest_outcomes",
    "fit_psi",
    "same_side_by_bounce",
    "side_correlation",
    "simulate_3d",
    "simulate_caught",
    "top_run",
]
