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


def critical_offset(wall, *, grid: int = _GRID) -> CriticalOffset:
    """Exact critical offset of ``wall``: ``b_c = −min_θ (b + b'')``.

    The minimum is bracketed on a uniform grid of ``grid`` points, then every
    grid minimum within reach of the global one is polished with a bounded
    Brent search on the exact ``b + b''`` (casadi derivatives), so the value is
    exact to rounding and the angle to ~1e-8 rad.

    Parameters
    ----------
    wall : forward.Wall
    grid : int
        Resolution of the bracketing grid.
    """
    from scipy.optimize import minimize_scalar

    concave = [k for k in wall.kinks if k.jump < 0]
    if concave:
        return CriticalOffset(math.inf, tuple(k.angle for k in concave))
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
    # a minimum attained over many consecutive grid points is an interval, not a point
    runs = _cyclic_runs(near)
    angles, intervals = [], []
    best = low
    step = TWO_PI / grid
    for start, length in runs:
        if length > 3:
            lo, hi = theta[start], theta[start] + (length - 1) * step
            intervals.append((float(np.mod(lo, TWO_PI)), float(np.mod(hi, TWO_PI))))
            angles.append(float(np.mod(0.5 * (lo + hi), TWO_PI)))
            continue
        centre = theta[start] + (length - 1) * step / 2
        res = minimize_scalar(lambda x: float(_smooth_curvature(wall, np.array([x]))[0]),
                              bounds=(centre - 1.5 * step, centre + 1.5 * step), method="bounded",
                              options={"xatol": 1e-12})
        value = min(float(res.fun), float(rho[start]))
        best = min(best, value)
        angles.append(float(np.mod(res.x, TWO_PI)))
    order = np.argsort(angles)
    return CriticalOffset(-best, tuple(angles[i] for i in order), tuple(intervals))


def _cyclic_runs(mask):
    """(start, length) of runs of True in a cyclic boolean array."""
    n = mask.size
    if mask.all():
        return [(0, n)]
    first_false = int(np.argmin(mask))
    rolled = np.roll(mask, -first_false)
    runs = []
    i = 0
    while i < n:
        if rolled[i]:
            j = i
            while j < n and rolled[j]:
                j += 1
            runs.append(((i + first_false) % n, j - i))
            i = j
        else:
            i += 1
    return runs


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
