"""The motion, in four rooms: ``billiard`` (the table, its compiled kernel and the rigid body it is equivalent
to), ``floor`` (a body on a floor: flights in a field, tosses and their outcomes), ``coin3d`` (the coin in three
dimensions) and ``analysis`` (Poincaré sections, Lyapunov exponents, P(n), the KAM boundary).  The other rooms
import from ``billiard``, which imports from none of them (and the 3-D coin's P(n) uses the fit of
``analysis``)."""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
