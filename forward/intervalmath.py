"""Ranges of the elementary functions, and of their second derivatives, on arrays of intervals.

The building blocks of :mod:`coinwall.forward.affine`: for an interval ``[lo, hi]`` (numpy arrays, one
interval per entry) each function returns ``(lo, hi)`` of an interval that contains every value of the
function on it, rounded outward.  Basic operations (``+ − × /``, ``sqrt``) are correctly rounded in IEEE
arithmetic, so one ulp outward covers them; the elementary functions of numpy's C library are trusted to
:data:`ULPS` units in the last place, and ``sin``/``cos`` to :data:`TRIG_ABSOLUTE` in absolute terms.
A range that is not finite (a pole or the end of a domain inside the interval) is ``(−inf, inf)``.

Hand-written on purpose: interval libraries for Python (``mpmath.iv``, ``pyinterval``) work one scalar
at a time, and the cell search of :mod:`coinwall.inverse.criticalcells` needs whole arrays of intervals.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["TRIG_ABSOLUTE", "ULPS", "UNARY", "down", "power_range", "up"]

EPS = float(np.finfo(float).eps)
#: Units in the last place trusted for numpy's exp, log, sinh, ... (glibc and numpy's SIMD loops: ≤ 4).
ULPS = 4.0
#: Absolute error trusted for numpy's sin and cos (|value| ≤ 1: 4 ulps of 1).
TRIG_ABSOLUTE = 4.0 * EPS
_TINY = 1e-300


def down(x, ulps: float = 1.0):
    """``x`` moved ``ulps`` units in the last place towards −inf (and below ``x − 1e-300``)."""
    x = np.asarray(x, dtype=float)
    return x - ulps * np.spacing(np.abs(x)) - _TINY


def up(x, ulps: float = 1.0):
    """``x`` moved ``ulps`` units in the last place towards +inf (and above ``x + 1e-300``)."""
    x = np.asarray(x, dtype=float)
    return x + ulps * np.spacing(np.abs(x)) + _TINY


def _clean(lo, hi):
    """``(lo, hi)`` with every entry that is nan (an undefined value) made the whole line."""
    bad = np.isnan(lo) | np.isnan(hi)
    if bad.any():
        lo = np.where(bad, -np.inf, lo)
        hi = np.where(bad, np.inf, hi)
    return lo, hi


def _increasing(func, ulps=ULPS):
    def image(lo, hi):
        with np.errstate(all="ignore"):
            return _clean(down(func(lo), ulps), up(func(hi), ulps))
    return image


def _decreasing(func, ulps=ULPS):
    def image(lo, hi):
        with np.errstate(all="ignore"):
            return _clean(down(func(hi), ulps), up(func(lo), ulps))
    return image


def _constant(bound):
    def image(lo, hi):
        shape = np.broadcast(lo, hi).shape
        return np.full(shape, -bound), np.full(shape, bound)
    return image


def _contains_point(lo, hi, offset, period):
    """Whether ``[lo, hi]`` may contain ``offset + k·period`` for an integer k (generous by the rounding of
    ``x / period``: a doubtful case counts as contained)."""
    margin = 1e-12 + 4.0 * EPS * np.maximum(np.abs(lo), np.abs(hi)) / period
    with np.errstate(all="ignore"):
        first = np.ceil((lo - offset) / period - margin)
        last = np.floor((hi - offset) / period + margin)
    return ~(first > last)  # nan (an infinite end) counts as contained


def _cos_range(lo, hi):
    with np.errstate(all="ignore"):
        a, b = np.cos(lo), np.cos(hi)
        low = np.minimum(a, b) - TRIG_ABSOLUTE
        high = np.maximum(a, b) + TRIG_ABSOLUTE
    wide = ~(hi - lo < 2.0 * math.pi)  # also an infinite or nan end
    high = np.where(wide | _contains_point(lo, hi, 0.0, 2.0 * math.pi), 1.0, np.minimum(high, 1.0))
    low = np.where(wide | _contains_point(lo, hi, math.pi, 2.0 * math.pi), -1.0, np.maximum(low, -1.0))
    return low, high


def _sin_range(lo, hi):
    with np.errstate(all="ignore"):
        a, b = np.sin(lo), np.sin(hi)
        low = np.minimum(a, b) - TRIG_ABSOLUTE
        high = np.maximum(a, b) + TRIG_ABSOLUTE
    wide = ~(hi - lo < 2.0 * math.pi)
    high = np.where(wide | _contains_point(lo, hi, 0.5 * math.pi, 2.0 * math.pi), 1.0, np.minimum(high, 1.0))
    low = np.where(wide | _contains_point(lo, hi, -0.5 * math.pi, 2.0 * math.pi), -1.0, np.maximum(low, -1.0))
    return low, high


def _negated(image):
    def negative(lo, hi):
        a, b = image(lo, hi)
        return -b, -a
    return negative


def _tan_range(lo, hi):
    pole = _contains_point(lo, hi, 0.5 * math.pi, math.pi) | ~(hi - lo < math.pi)
    with np.errstate(all="ignore"):
        low, high = down(np.tan(lo), ULPS), up(np.tan(hi), ULPS)
    return _clean(np.where(pole, -np.inf, low), np.where(pole, np.inf, high))


def _tan2_range(lo, hi):
    # (tan)'' = 2 tan (1 + tan²): increasing between poles
    def g(x):
        t = np.tan(x)
        return 2.0 * t * (1.0 + t * t)
    pole = _contains_point(lo, hi, 0.5 * math.pi, math.pi) | ~(hi - lo < math.pi)
    with np.errstate(all="ignore"):
        low, high = down(g(lo), 4 * ULPS), up(g(hi), 4 * ULPS)
    return _clean(np.where(pole, -np.inf, low), np.where(pole, np.inf, high))


def _even_range(func, ulps=ULPS):
    """Range of an even function increasing in |x| (cosh, x²)."""
    def image(lo, hi):
        with np.errstate(all="ignore"):
            inner = np.where((lo <= 0) & (hi >= 0), 0.0, np.minimum(np.abs(lo), np.abs(hi)))
            outer = np.maximum(np.abs(lo), np.abs(hi))
            return _clean(down(func(inner), ulps), up(func(outer), ulps))
    return image


def _within(lo, hi, low_end, high_end, image):
    """``image`` on ``[lo, hi]`` clipped to the domain ``[low_end, high_end]``; empty → the whole line."""
    def clipped(lo, hi):
        a, b = np.maximum(lo, low_end), np.minimum(hi, high_end)
        out_lo, out_hi = image(a, b)
        empty = a > b
        return np.where(empty, -np.inf, out_lo), np.where(empty, np.inf, out_hi)
    return clipped(lo, hi)


def _sqrt_range(lo, hi):
    return _within(lo, hi, 0.0, np.inf, _increasing(np.sqrt, 1.0))


def _log_range(lo, hi):
    return _within(lo, hi, 0.0, np.inf, _increasing(np.log))


def _inverse_range(lo, hi):
    zero = (lo <= 0) & (hi >= 0)
    with np.errstate(all="ignore"):
        low, high = down(1.0 / hi), up(1.0 / lo)
    return _clean(np.where(zero, -np.inf, low), np.where(zero, np.inf, high))


def _monotone_where(domain_lo, domain_hi, func, increasing=True, ulps=ULPS):
    image = (_increasing if increasing else _decreasing)(func, ulps)

    def ranged(lo, hi):
        return _within(lo, hi, domain_lo, domain_hi, image)
    return ranged


def _open_domain(domain_lo, domain_hi, image):
    """``image`` where the interval lies strictly inside the open domain, the whole line elsewhere."""
    def ranged(lo, hi):
        inside = (lo > domain_lo) & (hi < domain_hi)
        with np.errstate(all="ignore"):
            a, b = image(lo, hi)
        return np.where(inside, a, -np.inf), np.where(inside, b, np.inf)
    return ranged


def power_range(lo, hi, p: float):
    """The range of ``x**p`` on ``[lo, hi]`` for a constant exponent ``p`` (numpy's power: a negative base
    only with an integer exponent)."""
    lo, hi = np.broadcast_arrays(np.asarray(lo, float), np.asarray(hi, float))
    if p == 0:
        return np.ones_like(lo), np.ones_like(lo)
    integer = float(p).is_integer()
    with np.errstate(all="ignore"):
        if not integer:  # defined for x ≥ 0 (x > 0 when p < 0)
            a = np.maximum(lo, 0.0)
            empty = a > hi
            if p > 0:
                low, high = down(np.power(a, p), ULPS), up(np.power(hi, p), ULPS)
            else:
                low, high = down(np.power(hi, p), ULPS), up(np.power(a, p), ULPS)
                empty |= a <= 0
            return _clean(np.where(empty, -np.inf, low), np.where(empty, np.inf, high))
        zero = (lo <= 0) & (hi >= 0)
        ends_lo, ends_hi = np.power(lo, p), np.power(hi, p)
        low = np.minimum(ends_lo, ends_hi)
        high = np.maximum(ends_lo, ends_hi)
        if p > 0 and int(p) % 2 == 0:
            low = np.where(zero, 0.0, low)
        low, high = down(low, ULPS), up(high, ULPS)
        if p < 0:
            low, high = np.where(zero, -np.inf, low), np.where(zero, np.inf, high)
        return _clean(low, high)


def _asin2(x):  # (arcsin)'' = x (1 − x²)^(−3/2), increasing on (−1, 1)
    return x * (1.0 - x * x) ** -1.5


def _acosh2(x):  # (arccosh)'' = −x (x² − 1)^(−3/2), increasing on (1, ∞)
    return -x * (x * x - 1.0) ** -1.5


def _atanh2(x):  # (arctanh)'' = 2x / (1 − x²)², increasing on (−1, 1)
    return 2.0 * x / (1.0 - x * x) ** 2


def _inverse2_range(lo, hi):  # (1/x)'' = 2/x³, decreasing on each side of 0
    zero = (lo <= 0) & (hi >= 0)
    with np.errstate(all="ignore"):
        low, high = down(2.0 / hi**3, 2 * ULPS), up(2.0 / lo**3, 2 * ULPS)
    return _clean(np.where(zero, -np.inf, low), np.where(zero, np.inf, high))


def _log2_range(lo, hi):  # (log)'' = −1/x², increasing on (0, ∞)
    return _open_domain(0.0, np.inf, _increasing(lambda x: -1.0 / (x * x), 2 * ULPS))(lo, hi)


def _sqrt2_range(lo, hi):  # (sqrt)'' = −x^(−3/2)/4, increasing on (0, ∞)
    return _open_domain(0.0, np.inf, _increasing(lambda x: -0.25 * x**-1.5, 2 * ULPS))(lo, hi)


def _log1p2_range(lo, hi):  # (log1p)'' = −1/(1 + x)²
    return _open_domain(-1.0, np.inf, _increasing(lambda x: -1.0 / ((1.0 + x) * (1.0 + x)), 2 * ULPS))(lo, hi)


# name: (value, first derivative, range of the value, range of the second derivative), all on arrays.
# The bounds of bounded second derivatives are their maxima: |atan''| ≤ 3√3/8, |tanh''| ≤ 4/(3√3),
# |asinh''| ≤ 2/(3√3) (each rounded up).
UNARY = {
    "exp": (np.exp, np.exp, _increasing(np.exp), _increasing(np.exp)),
    "log": (np.log, lambda x: 1.0 / x, _log_range, _log2_range),
    "sqrt": (np.sqrt, lambda x: 0.5 / np.sqrt(x), _sqrt_range, _sqrt2_range),
    "sin": (np.sin, np.cos, _sin_range, _negated(_sin_range)),
    "cos": (np.cos, lambda x: -np.sin(x), _cos_range, _negated(_cos_range)),
    "tan": (np.tan, lambda x: 1.0 + np.tan(x) ** 2, _tan_range, _tan2_range),
    "asin": (np.arcsin, lambda x: 1.0 / np.sqrt(1.0 - x * x), _monotone_where(-1.0, 1.0, np.arcsin),
             _open_domain(-1.0, 1.0, _increasing(_asin2, 4 * ULPS))),
    "acos": (np.arccos, lambda x: -1.0 / np.sqrt(1.0 - x * x), _monotone_where(-1.0, 1.0, np.arccos, False),
             _negated(_open_domain(-1.0, 1.0, _increasing(_asin2, 4 * ULPS)))),
    "atan": (np.arctan, lambda x: 1.0 / (1.0 + x * x), _increasing(np.arctan), _constant(0.6496)),
    "sinh": (np.sinh, np.cosh, _increasing(np.sinh), _increasing(np.sinh)),
    "cosh": (np.cosh, np.sinh, _even_range(np.cosh), _even_range(np.cosh)),
    "tanh": (np.tanh, lambda x: 1.0 / np.cosh(x) ** 2, _increasing(np.tanh), _constant(0.7699)),
    "asinh": (np.arcsinh, lambda x: 1.0 / np.sqrt(1.0 + x * x), _increasing(np.arcsinh), _constant(0.3850)),
    "acosh": (np.arccosh, lambda x: 1.0 / np.sqrt(x * x - 1.0), _monotone_where(1.0, np.inf, np.arccosh),
              _open_domain(1.0, np.inf, _increasing(_acosh2, 4 * ULPS))),
    "atanh": (np.arctanh, lambda x: 1.0 / (1.0 - x * x), _open_domain(-1.0, 1.0, _increasing(np.arctanh)),
              _open_domain(-1.0, 1.0, _increasing(_atanh2, 4 * ULPS))),
    "inv": (lambda x: 1.0 / x, lambda x: -1.0 / (x * x), _inverse_range, _inverse2_range),
    "log1p": (np.log1p, lambda x: 1.0 / (1.0 + x), _monotone_where(-1.0, np.inf, np.log1p), _log1p2_range),
    "expm1": (np.expm1, np.exp, _increasing(np.expm1), _increasing(np.exp)),
}
