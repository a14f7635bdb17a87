"""The billiard: the table between the walls, the cell bounds of a wall, its compiled kernel with the certified
search for the next contact, the generated wall code and the cache of every compiled kernel, the plain-Python
reference stepper, and the rigid body itself with its shapes (the lab-frame cross-check of the equivalence)."""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
