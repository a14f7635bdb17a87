"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1).

Each name is imported from the module named here on first use; editors and type checkers read the
same lines (go-to-definition).
"""

from .bounce import Bounce, Launch, toss
from .bounce3d import Bounce3D, Launch3D
from .design import MODELS, Design, Resimulation, design, design_curves, odds, plot_design, resimulate
from .drop import Drop
from .family import Family, Valleys, outcome_sets, planar_valleys, revolution_valleys
from .flip import Flip

__all__ = ["Bounce", "Bounce3D", "Design", "Drop", "Family", "Flip", "Launch", "Launch3D", "MODELS", "Resimulation",
           "Valleys", "design", "design_curves", "odds", "outcome_sets", "planar_valleys", "plot_design",
           "resimulate", "revolution_valleys", "toss"]
