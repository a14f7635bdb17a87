"""The exact critical offset ``b_c = −min_θ (b + b'')`` and the regime of an offset.

The radius of curvature of the body with support function ``h = b0 + b`` is
``ρ = h + h'' = b0 + (b + b'')``; a convex body exists iff ρ ≥ 0 as a measure.
Hence ``b_c = −min (b + b'')`` over *all* θ, not only at the extrema of b
where the paper's Appendix estimated it.  At a kink of the wall, b'' carries
a point mass ``jump``; a positive one is harmless (an edge of the body), a
negative one makes ``b_c = +∞`` (no offset yields a convex body).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CriticalOffset", "critical_offset", "regime_of"]

TWO_PI = 2.0 * math.pi
_GRID = 8192


@dataclass(frozen=True)
class CriticalOffset:
    """Result of :func:`critical_offset`.

    Attributes
    ----------
    b_c : float
        The critical offset; ``math.inf`` if a concave kink of the wall makes
        every offset non-convex.
    angles : tuple of float
        Angles in [0, 2π) where the minimum of ``b + b''`` is attained (for a
        minimum attained on a whole interval, its midpoint).
    intervals : tuple of (float, float)
        Intervals on which ``b + b''`` stays at its minimum (e.g. the stick,
        where ``b + b'' = 0`` away from the kinks); empty for isolated minima.
    """

    b_c: float
    angles: tuple[float, ...]
    intervals: tuple[tuple[float, float], ...] = ()

    def __repr__(self) -> str:
        try:
            angles = ", ".join(f"{a:.6g}" for a in self.angles)
            return f"CriticalOffset(b_c={self.b_c:.12g}, angles=[{angles}])"
        except Exception:
            return "CriticalOffset(<unprintable>)"


def _smooth_curvature(wall, theta):
    b, _, d2 = wall.derivatives(theta)
    return b + d2


def critical_offset(wall, *, grid: int = _GRID, samples=None) -> CriticalOffset:
    """Exact critical offset of ``wall``: ``b_c = −min_θ (b + b'')``.

    The minimum is bracketed on a grid of angles, then every grid minimum
    within reach of the global one is polished with a bounded Brent search on
    the exact ``b + b''`` (casadi derivatives), so the value is exact to
    rounding and the angle to ~1e-8 rad.  A minimum attained on a whole
    interval (the stick: ``b + b'' = 0`` between its kinks) is reported as an
    interval; intervals are split at the kinks, where ``b''`` has a point mass.

    Parameters
    ----------
    wall : forward.Wall
    grid : int
        Resolution of the uniform bracketing grid (used when no samples are given).
    samples : inverse.support.SupportSamples, optional
        Samples the solver already holds (angles in increasing order, kinks as
        one-sided pairs); with at least ``grid // 2`` of them they serve as the
        bracketing grid and the wall is not evaluated again.
    """
    from scipy.optimize import minimize_scalar

    concave = [k for k in wall.kinks if k.jump < 0]
    if concave:
        return CriticalOffset(math.inf, tuple(k.angle for k in concave))
    if samples is not None and samples.phi.size >= grid // 2:
        theta = np.asarray(samples.phi, float)
        rho = samples.h + samples.h2 - samples.b0
    else:
        theta = np.linspace(0.0, TWO_PI, grid, endpoint=False)
        rho = _smooth_curvature(wall, theta)
        for k in wall.kinks:  # the smooth part is meaningless exactly at a kink: use both one-sided values
            i = int(np.argmin(np.abs(np.angle(np.exp(1j * (theta - k.angle))))))
            if abs(theta[i] - k.angle) < 1e-12 or abs(abs(theta[i] - k.angle) - TWO_PI) < 1e-12:
                b, _, _ = wall.one_sided(k.angle, -1)
                rho[i] = b + min(k.curvature_left, k.curvature_right)
    low = float(np.min(rho))
    spread = float(np.max(rho) - low)
    tol = 1e-9 * max(wall.scale, spread)
    near = rho <= low + tol
    n = theta.size
    angles, intervals = [], []
    best = low
    for start, length in _cyclic_runs(near):
        if length > 3:
            lo = theta[start]
            hi = lo + np.mod(theta[(start + length - 1) % n] - lo, TWO_PI)
            if length == n:  # the whole circle: it starts and ends at a kink, if there is one
                lo = wall.kinks[0].angle if wall.kinks else 0.0
                hi = lo + TWO_PI
            for a, b in _split_at_kinks(lo, hi, [k.angle for k in wall.kinks]):
                intervals.append((float(np.mod(a, TWO_PI)), float(np.mod(a, TWO_PI) + (b - a))))
                angles.append(float(np.mod(0.5 * (a + b), TWO_PI)))
            continue
        left = theta[(start - 1) % n]
        right = theta[(start + length) % n]
        left = theta[start] - np.mod(theta[start] - left, TWO_PI)
        right = theta[start] + np.mod(right - theta[start], TWO_PI)
        i = start + int(np.argmin(rho[[(start + j) % n for j in range(length)]]))
        res = None
        if right - left > 1e-12:
            res = minimize_scalar(lambda x: float(_smooth_curvature(wall, np.array([x]))[0]),
                                  bounds=(left, right), method="bounded", options={"xatol": 1e-10})
        if res is not None and float(res.fun) <= float(rho[i % n]):
            value, where = float(res.fun), float(res.x)
        else:
            value, where = float(rho[i % n]), float(theta[i % n])
        best = min(best, value)
        angles.append(float(np.mod(where, TWO_PI)))
    order = np.argsort(angles)
    return CriticalOffset(-best, tuple(angles[i] for i in order), tuple(intervals))


def _split_at_kinks(lo, hi, kinks):
    """Pieces of the angular interval [lo, hi] between the kinks strictly inside it."""
    cuts = sorted(lo + np.mod(k - lo, TWO_PI) for k in kinks)
    cuts = [c for c in cuts if lo + 1e-12 < c < hi - 1e-12]
    edges = [lo] + cuts + [hi]
    return [(a, b) for a, b in zip(edges[:-1], edges[1:]) if b - a > 1e-12]


def _cyclic_runs(mask):
    """(start, length) of runs of True in a cyclic boolean array."""
    n = mask.size
    if mask.all():
        return [(0, n)]
    shift = int(np.argmin(mask))  # a False entry: no run wraps past it
    rolled = np.roll(mask, -shift).astype(np.int8)
    edges = np.diff(np.concatenate([[0], rolled, [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(int((i + shift) % n), int(j - i)) for i, j in zip(starts, stops)]


def regime_of(b0: float, b_c: float, scale: float = 1.0) -> str:
    """``"convex"`` (Case I, b0 > b_c), ``"critical"`` (Case II) or ``"corner"`` (Case III, b0 < b_c).

    ``b0`` counts as critical within ``1e-9·scale`` of ``b_c``.
    """
    tol = 1e-9 * max(1.0, scale)
    if math.isinf(b_c) or b0 < b_c - tol:
        return "corner"
    if abs(b0 - b_c) <= tol:
        return "critical"
    return "convex"
