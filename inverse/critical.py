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

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import format_number, safe_repr

from .tolerances import ANGLE_TOLERANCE, OFFSET_TOLERANCE

__all__ = ["CriticalOffset", "critical_offset", "regime_of"]

_GRID = 8192
# The location of a smooth minimum is only known to ~sqrt(machine eps) (the function is flat to rounding
# there), whatever xatol the Brent polish below is given: each result measures its own (see
# _location_uncertainty); ANGLE_TOLERANCE is the fallback.


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
    angle_tolerance : float
        How well the angles are known (rad): the largest half-width over the minima within which
        ``b + b''`` changes less than its rounding error.  An angle within it of
        0 (or of 2π) *is* 0 for a reader; :meth:`format_angle` prints it so.
    b_c_tolerance : float
        The rounding level of ``b + b''`` (a b_c within it of 0 prints as 0); for data, the larger
        distance from :attr:`b_c` to an end of the certified interval.
    lower, upper : float or None
        For data: every wall consistent with the samples' intervals has ``b_c ≥ lower`` (certified by a
        linear programme); ``b_c ≤ upper`` under :attr:`assumption` (:mod:`coinwall.inverse.certify`).  For
        samples with standard deviations, a confidence interval (:mod:`coinwall.inverse.noise`; the
        assumption says so).  None for a formula wall (exact to :attr:`b_c_tolerance`).
    assumption : str
        What :attr:`upper` rests on (empty for a formula wall).
    samples_used : int
        For data: how many samples the geometry used (dense data are thinned); 0 otherwise.
    """

    b_c: float
    angles: tuple[float, ...]
    intervals: tuple[tuple[float, float], ...] = ()
    angle_tolerance: float = ANGLE_TOLERANCE
    b_c_tolerance: float = 0.0
    lower: float | None = None
    upper: float | None = None
    assumption: str = ""
    samples_used: int = 0

    def regimes(self, b0: float, scale: float = 1.0) -> tuple[str, ...]:
        """The regimes an offset ``b0`` may be in: one for a formula wall (:func:`regime_of`); for data,
        every regime some wall consistent with the samples allows (``("corner", "critical", "convex")``
        where the data cannot decide)."""
        if self.lower is None or self.upper is None or math.isinf(self.b_c):
            return (regime_of(b0, self.b_c, scale, self.b_c_tolerance),)
        tol = OFFSET_TOLERANCE * max(1.0, scale)
        if b0 < self.lower - tol:
            return ("corner",)
        if b0 > self.upper + tol:
            return ("convex",)
        return tuple(r for r, keep in (("corner", b0 > self.lower + tol), ("critical", True),
                                       ("convex", b0 < self.upper - tol)) if keep)

    def format_angle(self, angle: float, digits: int = 6) -> str:
        """``angle`` as a reader should see it: 0 when it is 0 or 2π within :attr:`angle_tolerance`."""
        if abs(angle - TWO_PI) <= self.angle_tolerance:
            angle = 0.0
        return format_number(angle, self.angle_tolerance, digits)

    @safe_repr
    def __repr__(self) -> str:
        angles = ", ".join(self.format_angle(a) for a in self.angles)
        within = "" if self.lower is None else f" in [{self.lower:.6g}, {self.upper:.6g}]"
        return f"CriticalOffset(b_c={format_number(self.b_c, self.b_c_tolerance, 12)}{within}, angles=[{angles}])"


def _smooth_curvature(wall, theta):
    b, _, d2 = wall.derivatives(theta)
    return b + d2


def _unresolved_minima(wall, theta, depth: int = 3, points: int = 257, most: int = 64):
    """Values of ``b + b''`` inside grid intervals the grid does not resolve, as ``(angles, values)``.

    On an interval of width ``w`` where ``b''`` varies on scales above ``w``, the trapezoid rule holds for
    ``(b', b'')``: ``r = b'(a + w) − b'(a) − w (b''(a) + b''(a + w)) / 2`` is small against the size of its
    terms (``|r| / s = O(w²)``; the same test as :mod:`coinwall.forward.singularities`).  A step narrower
    than the grid (``tanh(1e5 sin t)``) breaks it: there ``b + b''`` can dip far below every grid value
    and the grid minimum would be silently wrong.  Each such interval (the ``most`` with the largest terms,
    intervals holding a kink or a break left out: there ``b''`` has a point mass the kinks handle) is
    sampled at ``points`` angles, and the sub-intervals that still fail are sampled again, ``depth``
    levels down (to ~1e-11 rad on the default grid).
    """
    found_theta, found_rho, found_step = [], [], []
    skip = np.array([k.angle for k in wall.kinks] + list(getattr(wall, "breaks", ())), dtype=float)
    with np.errstate(all="ignore"):
        _, d1, d2 = wall.derivatives(theta)
        a, b = theta, np.append(theta[1:], theta[0] + TWO_PI)
        lo1, hi1, lo2, hi2 = d1, np.roll(d1, -1), d2, np.roll(d2, -1)
        for _ in range(depth):
            w = b - a
            r = hi1 - lo1 - 0.5 * w * (lo2 + hi2)
            size = np.abs(hi1 - lo1) + 0.5 * w * (np.abs(lo2) + np.abs(hi2))
            floor = 1e-12 * max(1.0, float(np.median(np.abs(d2))))
            suspect = (np.abs(r) > 0.1 * size) & (np.abs(r) > floor)
            if skip.size:
                inside = (np.mod(skip[None, :] - a[:, None], TWO_PI) <= w[:, None] + 1e-12)
                suspect &= ~inside.any(axis=1)
            idx = np.flatnonzero(suspect)
            if not idx.size:
                break
            idx = idx[np.argsort(-size[idx])][:most]
            fine = a[idx, None] + (b - a)[idx, None] * np.linspace(0.0, 1.0, points)[None, :]
            bb, f1, f2 = (np.asarray(v, dtype=float).reshape(fine.shape) for v in wall.derivatives(fine.ravel()))
            found_theta.append(fine.ravel())
            found_rho.append((bb + f2).ravel())
            found_step.append(np.repeat((b - a)[idx] / (points - 1), points))
            a, b = fine[:, :-1].ravel(), fine[:, 1:].ravel()
            lo1, hi1, lo2, hi2 = f1[:, :-1].ravel(), f1[:, 1:].ravel(), f2[:, :-1].ravel(), f2[:, 1:].ravel()
    if not found_theta:
        return np.empty(0), np.empty(0)
    # one candidate per dip: the lowest sample of each cluster, polished by Brent between its neighbours
    from .scalarmin import bounded_minimum

    t = np.concatenate(found_theta)
    rho = np.concatenate(found_rho)
    step = np.concatenate(found_step)
    order = np.argsort(t, kind="stable")
    t, rho, step = t[order], rho[order], step[order]
    ok = np.isfinite(rho)
    t, rho, step = t[ok], rho[ok], step[ok]
    gap = 2.0 * float(np.max(np.diff(theta))) if theta.size > 1 else TWO_PI
    starts = np.flatnonzero(np.concatenate([[True], np.diff(t) > gap]))
    out_t, out_rho = [], []
    for first, last in zip(starts, np.append(starts[1:], t.size)):
        i = first + int(np.argmin(rho[first:last]))
        # the lowest sample's neighbours at its own level (samples of several levels are interleaved here)
        centre, half = float(t[i]), float(step[i])
        where, value = centre, float(rho[i])
        if half > 0:
            # in the offset y from the sample: Brent's tolerance is relative to |x| (~1.5e-8 rad at θ ~ 1), far
            # coarser than a dip 1e-5 rad wide; relative to |y| it resolves the dip
            x, fx = bounded_minimum(lambda y: float(_smooth_curvature(wall, np.array([centre + y]))[0]),
                                    -half, half, xatol=1e-15)
            if np.isfinite(fx) and float(fx) < value:
                where, value = centre + float(x), float(fx)
        out_t.append(where)
        out_rho.append(value)
    return np.mod(np.array(out_t), TWO_PI), np.array(out_rho)


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
    from .scalarmin import bounded_minimum  # scipy's bounded Brent without importing scipy.optimize

    if wall.samples is not None:  # data: the certified interval of their lines, never the interpolant
        from .certify import data_critical_offset

        return data_critical_offset(wall)
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
    if samples is None or samples.phi.size < grid // 2:
        # a dip of b + b'' narrower than the grid (a steep step) is looked for where the grid fails to resolve
        # b''; its samples join the grid only where they go below it, so resolved walls are not touched
        extra_theta, extra_rho = _unresolved_minima(wall, theta)
        finite = np.isfinite(rho)
        deeper = extra_rho < (np.min(rho[finite]) if finite.any() else np.inf) - 1e-9 * max(1.0, wall.scale)
        if deeper.any():
            theta = np.concatenate([theta, extra_theta[deeper]])
            rho = np.concatenate([rho, extra_rho[deeper]])
            order = np.argsort(theta, kind="stable")
            theta, rho = theta[order], rho[order]
    bad = np.flatnonzero(~np.isfinite(rho))
    if bad.size:  # a wall passed its checks but not here: say where, never report b_c = nan
        from coinwall.forward.errors import InvalidWall

        where = float(np.mod(theta[bad[0]], TWO_PI))
        raise InvalidWall(f"wall {wall.description!r}: b + b'' is not finite at θ = {where:.6g}; "
                          "the critical offset needs a finite wall with finite slopes")
    low = float(np.min(rho))
    spread = float(np.max(rho) - low)
    tol = 1e-9 * max(wall.scale, spread)
    near = rho <= low + tol
    n = theta.size
    angles, intervals = [], []
    best = low
    uncertainty = 1e-12
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
            res = bounded_minimum(lambda x: float(_smooth_curvature(wall, np.array([x]))[0]),
                                  left, right, xatol=1e-10)
        if res is not None and float(res[1]) <= float(rho[i % n]):
            value, where = float(res[1]), float(res[0])
        else:
            value, where = float(rho[i % n]), float(theta[i % n])
        best = min(best, value)
        angles.append(float(np.mod(where, TWO_PI)))
        uncertainty = max(uncertainty, _location_uncertainty(wall, where, value))
    order = np.argsort(angles)
    rounding = 64.0 * np.finfo(float).eps * max(wall.scale, spread)
    # + 0.0: a minimum of exactly 0 is b_c = 0, not -0
    return CriticalOffset(-best + 0.0, tuple(angles[i] for i in order), tuple(intervals), uncertainty, rounding)


def _location_uncertainty(wall, where: float, value: float) -> float:
    """How far from ``where`` the minimum of ``b + b''`` may be: the half-width of the dip in which
    ``b + b''`` rises less than its own rounding.  Near a smooth minimum f ≈ f0 + c·δ²/2, so the
    minimiser cannot tell apart points within δ = sqrt(2·noise/c) (≈ 5e-8 rad for c ~ 1)."""
    step = 1e-3
    f = _smooth_curvature(wall, np.array([where - step, where + step]))
    curvature = (f[0] + f[1] - 2.0 * value) / step**2
    noise = 16.0 * np.finfo(float).eps * max(1.0, wall.scale, abs(value))
    if not curvature > 0:  # flat to the eye of this check (a quartic minimum): keep the default
        return ANGLE_TOLERANCE
    return float(math.sqrt(2.0 * noise / curvature))


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


def regime_of(b0: float, b_c: float, scale: float = 1.0, tolerance: float = 0.0) -> str:
    """``"convex"`` (Case I, b0 > b_c), ``"critical"`` (Case II) or ``"corner"`` (Case III, b0 < b_c).

    ``b0`` counts as critical within ``max(OFFSET_TOLERANCE·max(1, scale), tolerance)`` of ``b_c``
    (``tolerance``: how well b_c is known, e.g. what sampled data allow).
    """
    tol = max(OFFSET_TOLERANCE * max(1.0, scale), tolerance)
    if math.isinf(b_c) or b0 < b_c - tol:
        return "corner"
    if abs(b0 - b_c) <= tol:
        return "critical"
    return "convex"
