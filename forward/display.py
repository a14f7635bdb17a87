"""How results show themselves: a ``__repr__`` that never raises, numbers printed as what they are, numbers
for JSON (no NaN or infinity, which JSON does not have) and messages on one line."""

from __future__ import annotations

import functools
import math

__all__ = ["format_number", "format_within", "json_number", "json_numbers", "one_line", "safe_repr"]


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


def format_within(value: float, tolerance: float) -> str:
    """The shortest decimal within ``tolerance`` of ``value``: a number known to ``tolerance`` as a reader should
    see it (``-0.2`` for ``-0.20000000000000018`` known to 1e-14; ``0`` within the tolerance of 0).

    >>> format_within(-0.20000000000000018, 1e-14), format_within(0.8755555555555562, 2e-14)
    ('-0.2', '0.87555555555556')
    """
    value = float(value)
    if not math.isfinite(value):
        return str(value)
    if abs(value) <= tolerance:
        return "0"
    for digits in range(1, 18):
        text = f"{value:.{digits}g}"
        if abs(float(text) - value) <= tolerance:
            return text
    return repr(value)


def json_number(value, digits: int | None = None):
    """``value`` as a JSON number: a float, or None for None, NaN and ±inf (JSON has no such numbers).

    Parameters
    ----------
    value : float, int, numpy scalar or None
    digits : int, optional
        Round to this many decimal places (a page that shows numbers needs no more).
    """
    if value is None:
        return None
    value = float(value)
    if not math.isfinite(value):
        return None
    return value if digits is None else round(value, digits)


def json_numbers(values, digits: int | None = None) -> list:
    """:func:`json_number` of each of ``values`` (a sequence or 1-d array), as a list."""
    return [json_number(v, digits) for v in values]


def one_line(text, limit: int = 400) -> str:
    """``text`` (or an exception's message) on one line, shortened to ``limit`` characters with "…"
    (an exception's message can be a page)."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[:limit - 1] + "…"
