"""Poles and non-finite intervals of a wall between the angles of a check grid.

A wall given as a formula is evaluated on a grid of angles; a pole (``tan t`` at π/2) or a short
interval where the formula is not defined (``sqrt`` of a negative number on 1e-4 rad) can sit between
two grid angles, where every value is finite.  casadi has no interval arithmetic, so the grid itself
is made to testify, with the exact derivatives it already carries.

**The detector.**  On an interval ``[a, a + w]`` a function ``f`` with a bounded derivative ``f'``
satisfies the trapezoid rule

    r = f(a + w) − f(a) − w (f'(a) + f'(a + w)) / 2 = −w³ f'''(ξ) / 12,

so ``|r|`` is small against ``s = |f(a + w) − f(a)| + w (|f'(a)| + |f'(a + w)|) / 2`` (the size of
the terms) once ``w`` is below the scale on which ``f`` varies: ``|r| / s = O(w²)``.  A pole inside
breaks this at every scale: for ``f = 1/(θ − c)`` the end slopes are both negative and large while
``f`` jumps up across the pole, and ``|r| / s`` stays O(1) however small the interval (the pole is
scale-invariant).  The test is applied to ``(b, b')`` and to ``(b', b'')``.

An interval is *suspect* when ``|r| > 0.1·s`` and ``|r|`` is above the rounding of the terms.  Every
suspect interval is bisected (the exact ``b, b', b''`` at its midpoint) and its suspect halves are
kept, down to a width of :data:`MIN_WIDTH` rad.  A finite feature stops being suspect on the way
(a steep step ``tanh(k(θ − c))`` once ``w`` is below ``1/k``), or stays suspect with bounded values
(a kink of ``abs``, where ``b'`` jumps by a finite amount; a flat point like ``θ⁴``, where the values
shrink).  A singularity is what stays suspect *and* grows: at width ``w`` one end of the interval is
within ``w/2`` of it, so a power law ``|b| ~ d^(−p)`` (a pole, p ≥ 1), or ``|b'| ~ d^(−p)`` (a
logarithm, p = 1; a square-root cusp ``sqrt|θ − c|``, p = 1/2), grows by ``(1e6)^p`` from width
:data:`REFERENCE_WIDTH` = 1e-4 to :data:`MIN_WIDTH` = 1e-10, while a bounded one does not grow.  The
wall is refused when ``|b|`` or ``|b'|`` grows by more than :data:`GROWTH` = 100 on a followed
interval (and is 1e3 times its typical size, the median on the grid, at least 1), or is :data:`HUGE`
times its typical size.  ``b''`` is not judged: ``b'' → +∞`` is a point of zero curvature of a
perfectly good body (the superellipse ``|x|⁴ + |y|⁴ = 1`` at its flat points).  A non-finite value at
any midpoint is refused at once, with the extent of the non-finite set found by bisection between
finite and non-finite angles.

Legitimate steep walls (a stick, ``sqrt(1 + 1e-6 - cos t)``, a high harmonic) are resolved at a
width well above :data:`MIN_WIDTH` and pass; tests/inverse/test_hardening_numerics.py holds the detector to
both kinds.
"""

from __future__ import annotations

import numpy as np

from .angles import TWO_PI
from .display import format_number
from .errors import InvalidWall

__all__ = ["GROWTH", "HUGE", "MIN_WIDTH", "REFERENCE_WIDTH", "SUSPECT_RATIO", "check_singularities"]

#: Intervals are bisected down to this width (rad); 2π·eps ≈ 1.4e-15, so five orders of rounding margin.
MIN_WIDTH = 1e-10
#: The width (rad) at which each followed interval's values are recorded, to be compared at :data:`MIN_WIDTH`.
REFERENCE_WIDTH = 1e-4
#: How much ``|b|`` or ``|b'|`` must grow from :data:`REFERENCE_WIDTH` to :data:`MIN_WIDTH` (a factor 1e6 in
#: width) to count as unbounded: 100 catches every power law ``d^(−p)`` with ``p > 1/3``.
GROWTH = 100.0
#: ``|b|`` or ``|b'|`` this many times its typical size counts as unbounded whatever its growth.
HUGE = 1e12
#: ``|r| / s`` above which an interval is suspect (a smooth function gives O(w²)).
SUSPECT_RATIO = 0.1
# at most this many suspect intervals are followed at once (nearest the largest values first): a pole
# leaves one chain on each side, a kink one; a wall with more suspects than this is pathological anyway
_MAX_LIVE = 256
_EPS = np.finfo(float).eps


def _suspect(lo, hi, width, floor):
    """Mask of suspect intervals; ``lo``/``hi`` are (b, b', b'') at the ends, arrays over intervals."""
    out = np.zeros(width.size, bool)
    for k in (0, 1):
        f0, f1, g0, g1 = lo[k], hi[k], lo[k + 1], hi[k + 1]
        residual = np.abs(f1 - f0 - 0.5 * width * (g0 + g1))
        size = np.abs(f1 - f0) + 0.5 * width * (np.abs(g0) + np.abs(g1))
        rounding = 1e3 * _EPS * (np.abs(f0) + np.abs(f1) + width * (np.abs(g0) + np.abs(g1))) + floor
        out |= (residual > SUSPECT_RATIO * size) & (residual > rounding)
    return out


def _extent(derivatives, finite_at, bad_at):
    """Bisect between a finite and a non-finite angle: the boundary of the non-finite set (to 1e-12)."""
    for _ in range(60):
        if abs(bad_at - finite_at) <= 1e-12:
            break
        mid = 0.5 * (finite_at + bad_at)
        if all(np.isfinite(v[0]) for v in derivatives(np.array([mid]))):
            finite_at = mid
        else:
            bad_at = mid
    return bad_at


def _refuse_non_finite(description, derivatives, left, bad, right):
    lo = _extent(derivatives, left, bad)
    hi = _extent(derivatives, right, bad)
    start = float(np.mod(lo, TWO_PI))
    where = f"θ = {format_number(start, 1e-11)}" if hi - lo < 1e-9 else \
        f"θ in [{format_number(start, 1e-11)}, {start + (hi - lo):.6g}]"
    raise InvalidWall(f"wall {description!r} is not finite on {where} (between the check angles); "
                      "the wall must be finite with finite slopes everywhere")


def check_singularities(description: str, derivatives, theta, values) -> None:
    """Refuse a wall with a pole or a non-finite interval between the angles ``theta``.

    Parameters
    ----------
    description : str
        The wall, for the message.
    derivatives : callable
        ``derivatives(angles) -> (b, b', b'')`` (exact).
    theta : ndarray
        Increasing check angles covering one period (the interval after the last wraps to the first).
    values : tuple of ndarray
        ``(b, b', b'')`` at ``theta``, all finite (the caller checked).

    Raises
    ------
    InvalidWall
        "has a pole near θ = …" or "is not finite on θ in [a, b]", with the angle.
    """
    values = [np.asarray(v, dtype=float) for v in values]
    typical = np.array([[max(1.0, float(np.median(np.abs(v))))] for v in values[:2]])
    floor = 1e-12 * float(typical[0, 0])
    with np.errstate(all="ignore"):  # non-finite values are looked for explicitly below
        starts = theta
        ends = np.append(theta[1:], theta[0] + TWO_PI)
        lo = np.stack(values)
        hi = np.roll(lo, -1, axis=1)
        mask = _suspect(lo, hi, ends - starts, floor)
        a, b, lo, hi = starts[mask], ends[mask], lo[:, mask], hi[:, mask]
        reference = np.maximum(np.abs(lo[:2]), np.abs(hi[:2]))
        while a.size:
            width = b - a
            if width[0] <= MIN_WIDTH:
                break
            if a.size > _MAX_LIVE:  # follow the intervals with the largest values
                keep = np.argsort(-np.max(np.abs(np.concatenate([lo, hi])), axis=0))[:_MAX_LIVE]
                a, b, lo, hi, reference = a[keep], b[keep], lo[:, keep], hi[:, keep], reference[:, keep]
            mid = 0.5 * (a + b)
            at_mid = np.stack([np.asarray(v, dtype=float).ravel() for v in derivatives(mid)])
            bad = np.flatnonzero(~np.all(np.isfinite(at_mid), axis=0))
            if bad.size:
                i = int(bad[0])
                _refuse_non_finite(description, derivatives, float(a[i]), float(mid[i]), float(b[i]))
            # the two halves of every interval
            a2 = np.concatenate([a, mid])
            b2 = np.concatenate([mid, b])
            lo2 = np.concatenate([lo, at_mid], axis=1)
            hi2 = np.concatenate([at_mid, hi], axis=1)
            reference = np.concatenate([reference, reference], axis=1)
            if 0.5 * width[0] > REFERENCE_WIDTH:  # not yet at the reference width: the values here
                reference = np.maximum(np.abs(lo2[:2]), np.abs(hi2[:2]))
            keep = _suspect(lo2, hi2, b2 - a2, floor)
            a, b, lo, hi, reference = a2[keep], b2[keep], lo2[:, keep], hi2[:, keep], reference[:, keep]
        if not a.size:
            return
        final = np.maximum(np.abs(lo[:2]), np.abs(hi[:2]))  # (2, intervals): |b| and |b'|
        unbounded = ((final > GROWTH * np.maximum(reference, typical)) & (final > 1e3 * typical)) \
            | (final > HUGE * typical)
    orders = np.flatnonzero(unbounded.any(axis=1))
    if not orders.size:
        return  # kinks, flat points, rounding: suspect to the end, but bounded
    order = int(orders[0])  # a pole of b before the slope it also makes unbounded
    i = int(np.argmin(np.where(unbounded[order], np.mod(a, TWO_PI), np.inf)))  # the first in angle
    angle = float(np.mod(0.5 * (a[i] + b[i]), TWO_PI))
    angle = 0.0 if angle > TWO_PI - 10 * MIN_WIDTH else angle  # known to MIN_WIDTH: 2π is 0
    what = "has a pole" if order == 0 else "has an infinite slope b'"
    name = ("b", "b'")[order]
    shown = format_number(angle, 10 * MIN_WIDTH, 10)
    raise InvalidWall(f"wall {description!r} {what} near θ = {shown} (|{name}| reaches {final[order, i]:.3g} "
                      f"within {MIN_WIDTH:g} rad of it); the wall must be finite with finite slopes everywhere")
