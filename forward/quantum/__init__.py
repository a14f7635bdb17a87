"""The quantum coin: the Dirichlet Laplacian on the billiard strip, periodic in θ.

With η = y/κ the body's Hamiltonian is −(ħ²/2Mκ²)(∂²_θ + ∂²_η): the levels are the eigenvalues λ of −Δ on
the strip lo(θ) < η < hi(θ) of :class:`coinwall.forward.dynamics.billiard.table.Billiard` (units 1/κ²;
E = ħ²λ/(2Mκ²)).  One module per step: :mod:`.strip` (the domain), :mod:`.mesh`, :mod:`.fem`,
:mod:`.symmetry`, :mod:`.spectrum` (the result and :func:`quantum_spectrum`), :mod:`.weyl`,
:mod:`.statistics`, :mod:`.tunnelling`, :mod:`.figures`.  scikit-fem is imported only when a mesh is made.
"""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
