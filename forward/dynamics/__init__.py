"""The motion: the billiard and its compiled kernel, the rigid body it is equivalent to, and the
analyses of the motion (Poincaré sections, Lyapunov exponents, P(n), the KAM boundary)."""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
