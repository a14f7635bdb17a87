"""A body on a floor: flights in a field (gravity, restitution, Coulomb friction and the contact phases it
brings), the valleys of the floor and their rest states, the outcomes of a toss, fairness against bounces,
the basin-boundary exponent and the wedge limit."""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
