"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1)."""

from .fairness import Fairness, fairness, fairness_curve
from .field import FieldTable, Flight, field_run, field_run_many
from .landscape import Landscape, landscape
from .hand import Tosses, heads_fraction, launch_spread, toss_outcomes
from .toss import BasinMap, basin_map
from .uncertainty import Uncertainty, uncertainty_exponent
from .wedge import WedgeLyapunov, wedge_lyapunov

__all__ = [
    "BasinMap",
    "Fairness",
    "FieldTable",
    "Flight",
    "Landscape",
    "Tosses",
    "Uncertainty",
    "WedgeLyapunov",
    "basin_map",
    "fairness",
    "fairness_curve",
    "field_run",
    "field_run_many",
    "heads_fraction",
    "landscape",
    "launch_spread",
    "toss_outcomes",
    "uncertainty_exponent",
    "wedge_lyapunov",
]
