"""coinwall inverse side: wall function + offset → body outline (Balazs, Chatterjee, Jackson, section IV)."""

from .body import Body
from .corners import Corner
from .critical import CriticalOffset, critical_offset, regime_of
from .polar import Fold
from .realizability import Realizability, SelfConsistency, kappa_max, realizability, self_consistent_offset
from .solve import DEFAULT_POINTS, METHODS, solve_body

__all__ = ["Body", "Corner", "CriticalOffset", "critical_offset", "regime_of", "Fold", "DEFAULT_POINTS",
           "METHODS", "solve_body", "Realizability", "SelfConsistency", "kappa_max", "realizability",
           "self_consistent_offset"]
