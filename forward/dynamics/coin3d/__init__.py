"""The coin in three dimensions: the body of revolution as a top (the reduced billiard with its potential) and
its compiled kernel, the lab-frame rigid body, the caught flip (DHM), the bounced coin, and the side-up
correlation P(n) between two walls."""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
