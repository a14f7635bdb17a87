"""The quantum coin: the Dirichlet Laplacian on the billiard strip, periodic in θ.

With η = y/κ the body's Hamiltonian is −(ħ²/2Mκ²)(∂²_θ + ∂²_η): the levels are the eigenvalues λ of −Δ on
the strip lo(θ) < η < hi(θ) of :class:`coinwall.forward.dynamics.billiard.Billiard` (units 1/κ²;
E = ħ²λ/(2Mκ²)).  One module per step: :mod:`.strip` (the domain), :mod:`.mesh`, :mod:`.fem`,
:mod:`.symmetry`, :mod:`.spectrum` (the result and :func:`quantum_spectrum`), :mod:`.weyl`,
:mod:`.statistics`, :mod:`.tunnelling`, :mod:`.figures`.  scikit-fem is imported only when a mesh is made.
"""

from .spectrum import METHODS, Spectrum, default_cells, quantum_spectrum
from .statistics import SpacingStatistics, level_statistics
from .strip import Strip, make_strip
from .tunnelling import Splitting, doublet_splitting, splitting_of, tunnelling_time, wkb_action
from .weyl import WeylCheck, weyl_check, weyl_count

__all__ = [
           "METHODS",
           "SpacingStatistics",
           "Spectrum",
           "Splitting",
           "Strip",
           "WeylCheck",
           "default_cells",
           "doublet_splitting",
           "level_statistics",
           "make_strip",
           "quantum_spectrum",
           "splitting_of",
           "tunnelling_time",
           "weyl_check",
           "weyl_count",
           "wkb_action",
]
