"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .body import Body
from .corners import Corner
from .critical import CriticalOffset, critical_offset, regime_of
from .polar import Fold
from .realizability import Realizability, SelfConsistency, kappa_max, realizability, self_consistent_offset
from .smooth import METHODS
from .solve import solve_body
from .tolerances import DEFAULT_POINTS

__all__ = ["Body", "Corner", "CriticalOffset", "DEFAULT_POINTS", "Fold", "METHODS", "Realizability",
           "SelfConsistency", "critical_offset", "kappa_max", "realizability", "regime_of", "self_consistent_offset",
           "solve_body"]
