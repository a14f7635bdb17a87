"""Bodies designed for their odds: toss models (drop, flip, bounce, bounce3d) and the solvers that find the
parameters of a family of bodies for which the toss has prescribed outcome probabilities."""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
