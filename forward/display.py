"""How results show themselves: a ``__repr__`` that never raises, and numbers printed as what they are."""

from __future__ import annotations

import functools
import math

__all__ = ["safe_repr", "format_number"]


def safe_repr(method):
    """Decorate a ``__repr__`` so that it never raises: a result that cannot summarise itself (a field
    still missing, a NaN where a format expects a number …) shows as ``ClassName(<unprintable>)``."""

    @functools.wraps(method)
    def wrapper(self):
        try:
            return method(self)
        except Exception:  # a repr must never raise, whatever went wrong
            return f"{type(self).__name__}(<unprintable>)"

    return wrapper


def format_number(value, tolerance: float = 0.0, digits: int = 6) -> str:
    """``value`` with ``digits`` significant digits, as the reader should see it.

    A value within ``tolerance`` of zero (a minimiser's answer 1e-10 for an exact 0, an area of -5e-45)
    prints as ``0``; ``-0`` never appears.  Non-finite values print as ``nan``, ``inf``, ``-inf``.
    """
    value = float(value)
    if not math.isfinite(value):
        return str(value)
    if abs(value) <= tolerance or value == 0.0:
        return "0"
    text = f"{value:.{digits}g}"
    return "0" if text in ("-0", "0") else text
