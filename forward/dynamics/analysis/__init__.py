"""Analyses of the billiard's motion: Poincaré sections, Lyapunov exponents and chaotic fractions, the
heads/tails correlation P(n) and τ(H), the KAM boundary, the paper's ellipse islands, orbit statistics."""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
