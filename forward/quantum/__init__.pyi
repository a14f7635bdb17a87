"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .spectrum import METHODS, Spectrum, default_cells, quantum_spectrum
from .statistics import SpacingStatistics, level_statistics
from .strip import Strip, make_strip
from .tunnelling import Splitting, doublet_splitting, splitting_of, tunnelling_time, wkb_action
from .weyl import WeylCheck, weyl_check, weyl_count

__all__ = ["METHODS", "SpacingStatistics", "Spectrum", "Splitting", "Strip", "WeylCheck", "default_cells",
           "doublet_splitting", "level_statistics", "make_strip", "quantum_spectrum", "splitting_of",
           "tunnelling_time", "weyl_check", "weyl_count", "wkb_action"]
