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

from .criticalcells import CELLS
from .tolerances import ANGLE_TOLERANCE, OFFSET_TOLERANCE

__all__ = ["CriticalOffset", "critical_offset", "format_critical_angles", "regime_of"]


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
        minimum attained on a whole interval, its midpoint).  For a formula wall, every global
        minimiser lies within :attr:`angle_errors` of one of them.
    intervals : tuple of (float, float)
        Intervals on which ``b + b''`` stays at its minimum (e.g. the stick,
        where ``b + b'' = 0`` away from the kinks); empty for isolated minima.
    angle_tolerance : float
        How well the angles are known (rad): for a formula wall, the largest of
        :attr:`angle_errors` over the isolated angles (ANGLE_TOLERANCE when there are none).  An angle
        within it of 0 (or of 2π) *is* 0 for a reader; :meth:`format_angle` prints it so.
    b_c_tolerance : float
        For a formula wall, certified: ``|b_c − exact| ≤ b_c_tolerance`` (the ranges of ``b + b''`` on
        cells, rounding included: :mod:`coinwall.inverse.criticalcells`); for data, the larger distance
        from :attr:`b_c` to an end of the certified interval.
    lower, upper : float or None
        For data: every wall consistent with the samples' intervals has ``b_c ≥ lower`` (certified by a
        linear programme); ``b_c ≤ upper`` under :attr:`assumption` (:mod:`coinwall.inverse.certify`).  For
        samples with standard deviations, a confidence interval (:mod:`coinwall.inverse.noise`; the
        assumption says so).  None for a formula wall (exact to :attr:`b_c_tolerance`).
    assumption : str
        What :attr:`upper` rests on (empty for a formula wall).
    samples_used : int
        For data: how many samples the geometry used (dense data are thinned); 0 otherwise.
    angle_errors : tuple of float
        For a formula wall, one per angle: the certified half-width of the window around it that holds
        its minimisers (the half-length of an interval).  Empty for data.
    spread : float
        For a formula wall: on every window, ``b + b''`` is within ``spread`` of its certified lower bound
        (``−b_c − b_c_tolerance``): an angle is reported only that close to the minimum.  0 for data.
    uncertified : tuple of (float, float)
        For a formula wall, angle ranges the certificate leaves out (usually none): where ``b''`` grows
        without bound (the flat points of a superellipse, ~1e-11 rad around them) or where its ranges did
        not narrow within the search's budget; there ``b + b''`` counts by sampled values, and
        :attr:`b_c_tolerance` holds everywhere else (:mod:`coinwall.inverse.criticalcells`).

    Examples
    --------
    >>> from coinwall import Wall, critical_offset
    >>> result = critical_offset(Wall.from_expression("1 + 0.1*cos(3*t)"))   # b + b'' = 1 − 0.8 cos 3θ
    >>> round(result.b_c, 12), len(result.angles), result.b_c_tolerance < 1e-12
    (-0.2, 3, True)
    >>> [round(angle, 6) for angle in result.angles]                       # 0, 2π/3, 4π/3
    [0.0, 2.094395, 4.18879]
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
    angle_errors: tuple[float, ...] = ()
    spread: float = 0.0
    uncertified: tuple[tuple[float, float], ...] = ()

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


def format_critical_angles(angles, errors=(), digits: int = 6) -> tuple[str, str]:
    """The critical angles as a reader sees them, and their uncertainty: ``("0, 2.0944, 4.18879", "±6e-08 rad")``.

    One text for every front end (``coinwall critical``, ``coinwall solve``, the explorer).  An angle
    within its uncertainty (:attr:`CriticalOffset.angle_errors`; :data:`ANGLE_TOLERANCE` without one) of 0 or
    2π prints as 0.  The second part gives the largest uncertainty of the isolated angles (the middles of
    intervals are left out: the intervals say where those minima are); it is empty without errors.

    Examples
    --------
    >>> format_critical_angles([6.283185307179, 3.14159265], [6e-8, 5e-8])
    ('0, 3.14159', '±6e-08 rad')
    """
    from .criticalcells import INTERVAL_WIDTH

    given = len(errors) > 0
    errors = tuple(errors) if given else (ANGLE_TOLERANCE,) * len(angles)
    shown, isolated = [], []
    for angle, error in zip(angles, errors):
        point = 2.0 * error < INTERVAL_WIDTH
        tolerance = max(error, 1e-15) if point else ANGLE_TOLERANCE
        angle = 0.0 if abs(angle - TWO_PI) <= tolerance else angle
        shown.append(format_number(angle, tolerance, digits))
        if point:
            isolated.append(error)
    spread = f"±{max(isolated):.1g} rad" if given and isolated else ""
    return ", ".join(shown) or "—", spread


def critical_offset(wall, *, cells: int = CELLS) -> CriticalOffset:
    """Exact critical offset of ``wall``, ``b_c = −min_θ (b + b'')``, with every angle where it is attained.

    For a formula wall (an expression, a Fourier series, circle arcs) the minimum is sought over the whole
    period from certified ranges of ``b + b''`` on cells (:mod:`.criticalcells`): cells that cannot hold
    a minimiser are dropped, the others halved until the rounding of ``b + b''`` decides.  So ``b_c`` is
    certified to :attr:`~CriticalOffset.b_c_tolerance`, and **every** global minimiser lies within its
    :attr:`~CriticalOffset.angle_errors` entry of one of the reported angles (or in one of the intervals,
    where ``b + b''`` is minimal on a whole arc: the stick); an angle is reported only where ``b + b''``
    comes within that tolerance of its minimum, so a second dip above it is left out.  Intervals are split
    at the kinks, where ``b''`` has a point mass.  A concave kink (``b'`` jumps down) gives ``b_c = inf``.
    A wall of samples gets the data's certified interval (:func:`coinwall.inverse.certify.data_critical_offset`).

    Parameters
    ----------
    wall : forward.Wall
    cells : int
        Uniform cells of the search's first grid (kinks and breaks add more).

    Returns
    -------
    CriticalOffset

    Raises
    ------
    InvalidWall
        Where ``b + b''`` has no finite bound near some angle (a wall that is not finite with finite
        slopes), naming the angle.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> found = critical_offset(Wall.from_expression("1 + 0.1*cos(3*t)"))   # b + b'' = 1 − 0.8 cos 3θ
    >>> round(found.b_c, 12), [found.format_angle(a) for a in found.angles]
    (-0.2, ['0', '2.0944', '4.18879'])
    >>> bool(found.b_c_tolerance < 1e-13 and max(found.angle_errors) < 1e-6)
    True
    """
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.wallbounds import curvature_ranges

    from .criticalcells import INTERVAL_WIDTH, certified_minimum

    if wall.samples is not None:  # data: the certified interval of their lines, never the interpolant
        from .certify import data_critical_offset

        return data_critical_offset(wall)
    concave = [k for k in wall.kinks if k.jump < 0]
    if concave:
        return CriticalOffset(math.inf, tuple(k.angle for k in concave))
    cached = wall.__dict__.get("_critical_offset")  # a wall is immutable: its b_c is computed once
    if cached is not None and cached[0] == cells:
        return cached[1]
    ranges = curvature_ranges(wall)
    found = certified_minimum(ranges, ranges.cuts, ranges.kinks, cells=cells)
    if not (math.isfinite(found.lower) and math.isfinite(found.upper)):
        where = ", ".join(f"{np.mod(0.5 * (lo + hi), TWO_PI):.6g}" for lo, hi in found.windows[:3])
        raise InvalidWall(f"wall {wall.description!r}: b + b'' has no finite bound near θ = {where}; the critical "
                          "offset needs a finite wall with finite slopes")
    angles, errors, intervals = [], [], []
    for lo, hi in found.windows:
        if hi - lo >= TWO_PI - 1e-12:  # the whole circle (a circle): it starts and ends at a kink if any
            lo = wall.kinks[0].angle if wall.kinks else 0.0
            hi = lo + TWO_PI
        if hi - lo >= INTERVAL_WIDTH:
            intervals.append((float(np.mod(lo, TWO_PI)), float(np.mod(lo, TWO_PI) + (hi - lo))))
        angle, error = float(np.mod(0.5 * lo + 0.5 * hi, TWO_PI)), float(0.5 * (hi - lo))
        angles.append(0.0 if TWO_PI - angle <= min(error, 0.5 * INTERVAL_WIDTH) else angle)  # at 0, not 2π
        errors.append(error)
    order = np.argsort(angles)
    point_errors = [e for e in errors if 2.0 * e < INTERVAL_WIDTH]
    tolerance = max(found.upper - found.value, found.value - found.lower)
    # + 0.0: a minimum of exactly 0 is b_c = 0, not -0
    result = CriticalOffset(-found.value + 0.0, tuple(angles[i] for i in order), tuple(sorted(intervals)),
                            max(point_errors) if point_errors else ANGLE_TOLERANCE, float(tolerance),
                            angle_errors=tuple(errors[i] for i in order), spread=float(found.spread),
                            uncertified=tuple((float(lo), float(hi)) for lo, hi in found.uncertified))
    object.__setattr__(wall, "_critical_offset", (cells, result))
    return result


def regime_of(b0: float, b_c: float, scale: float = 1.0, tolerance: float = 0.0) -> str:
    """``"convex"`` (Case I, b0 > b_c), ``"critical"`` (Case II) or ``"corner"`` (Case III, b0 < b_c).

    ``b0`` counts as critical within ``max(OFFSET_TOLERANCE·max(1, scale), tolerance)`` of ``b_c``
    (``tolerance``: how well b_c is known, e.g. what sampled data allow).

    Parameters
    ----------
    b0 : float
        The offset.
    b_c : float
        The critical offset (:attr:`CriticalOffset.b_c`).
    scale : float
        The wall's scale (``max |b|``): the tolerance is relative to it.
    tolerance : float
        How well ``b_c`` is known (0 for a formula).

    Returns
    -------
    str
        ``"convex"``, ``"critical"`` or ``"corner"``.

    Examples
    --------
    >>> from coinwall.inverse import regime_of
    >>> regime_of(0.0, -0.5), regime_of(-0.5, -0.5), regime_of(-0.6, -0.5)
    ('convex', 'critical', 'corner')
    >>> regime_of(-0.501, -0.5, tolerance=0.01)          # within what the data decide
    'critical'
    """
    tol = max(OFFSET_TOLERANCE * max(1.0, scale), tolerance)
    if math.isinf(b_c) or b0 < b_c - tol:
        return "corner"
    if abs(b0 - b_c) <= tol:
        return "critical"
    return "convex"
