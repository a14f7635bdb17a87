"""Validators of arguments, in one place, each named after what it checks (like scipy's ``_ivp/common.py``).

Each returns the value in its canonical type or raises :class:`~coinwall.forward.errors.InvalidArgument`
(or the error class passed as ``error``) with a message that names the argument, the value given and
what would be valid.  Library messages name *arguments* (``kappa``); the command line maps them to its
flags.
"""

from __future__ import annotations

import math
import numbers

from .errors import InvalidArgument

__all__ = ["check_count", "check_finite", "check_positive", "check_choice", "is_integer"]


def is_integer(value) -> bool:
    """True for Python and NumPy integers, False for ``bool`` (an integer to Python, never a count to us)."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def check_count(name: str, value, *, minimum: int = 1, maximum: int | None = None, error=InvalidArgument) -> int:
    """``value`` as an ``int`` in ``[minimum, maximum]``; ``bool`` and non-integers are refused."""
    if not is_integer(value):
        raise error(f"`{name}` must be an integer, got {value!r}")
    value = int(value)
    if value < minimum or (maximum is not None and value > maximum):
        valid = f">= {minimum}" if maximum is None else f"from {minimum} to {maximum}"
        raise error(f"`{name}` must be an integer {valid}, got {value}")
    return value


def check_finite(name: str, value, *, error=InvalidArgument) -> float:
    """``value`` as a finite ``float``; ``bool``, strings and non-finite numbers are refused."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise error(f"`{name}` must be a finite number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise error(f"`{name}` must be finite, got {value}")
    return value


def check_positive(name: str, value, *, error=InvalidArgument) -> float:
    """``value`` as a finite ``float`` > 0."""
    value = check_finite(name, value, error=error)
    if value <= 0:
        raise error(f"`{name}` must be positive, got {value:g}")
    return value


def check_choice(name: str, value, choices, *, error=InvalidArgument):
    """``value`` if it is one of ``choices``."""
    if value not in choices:
        raise error(f"`{name}` must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value
