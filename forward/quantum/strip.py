"""The quantum billiard's domain: the (θ, η) strip between the two walls, and where it falls apart.

With ``η = y/κ`` the body between the walls is a particle in the strip

    lo(θ) = b0 + b(θ)  <  η  <  hi(θ) = H − b0 − b(θ + π),        θ periodic with period 2π

(the table of :class:`coinwall.forward.dynamics.billiard.table.Billiard`, which this module reuses: its
``lower``/``upper`` are ``lo``/``hi`` and its ``area_perimeter`` gives the area and the wall length).
The width ``w(θ) = hi − lo = H − 2 b0 − b(θ) − b(θ + π)`` is π-periodic, so the narrowest places
(the *necks*) come in pairs θ_n, θ_n + π.  ``D = H − min w`` is the body's diameter.

Where ``w ≤ 0`` on intervals (H below the diameter) the strip falls apart into *regions* (heads and
tails): each region is a domain of its own, reported in :attr:`Strip.regions` — a finding, not an error.
A strip whose walls overlap at every angle is refused by ``Billiard`` (bad input).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..angles import TWO_PI
from ..display import safe_repr
from ..dynamics.billiard import Billiard
from ..errors import InvalidArgument

__all__ = ["SYMMETRY_TOL", "Strip", "make_strip"]

_GRID = 4096
#: a symmetry of the wall holds when it is satisfied to this relative accuracy on a 4096-point grid
SYMMETRY_TOL = 1e-10
_AREA_POINTS = 1 << 16


@dataclass(frozen=True, repr=False)
class Strip:
    """The (θ, η) strip of a billiard table, with its necks, regions, breakpoints and symmetries.

    Attributes
    ----------
    table : Billiard
        The table (wall, H, b0); ``lo = table.lower``, ``hi = table.upper``.
    neck : float
        Angle in [0, π) where the width is smallest (the other neck is ``neck + π``).
    width_min, width_max : float
        Smallest and largest width ``w(θ)`` (refined by a bounded minimisation around the grid minimum).
    diameter : float
        ``D = H − width_min``: the body's extent along the direction of the narrowest place.
    regions : tuple of (float, float)
        Empty when the strip is open at every angle (one periodic domain); otherwise the θ-intervals
        ``(a, b)``, ``a < b``, ``b − a < 2π`` (``b`` may exceed 2π: the interval wraps), where ``w > 0``.
    breakpoints : tuple of float
        Angles in [0, 2π) where ``lo`` or ``hi`` has a kink or a jump of its curvature (mesh lines go
        there), closed under the symmetries.
    symmetries : tuple of str
        ``"swap"`` ((θ, η) → (θ + π, H − η), always), ``"mirror"`` (θ → −θ, when b(−θ) = b(θ)) and
        ``"half_turn"`` ((θ, η) → (θ + π, η), when b(θ + π) = b(θ)), each checked numerically.
    area, wall_length : float
        Area of the open strip and the total length of both walls there (Euclidean metric in (θ, η)).

    Examples
    --------
    >>> from coinwall import Wall, make_strip
    >>> strip = make_strip(Wall.from_expression("1"), 3.0)
    >>> strip.width_min, strip.width_max, round(strip.diameter, 12)
    (1.0, 1.0, 2.0)
    """

    table: Billiard
    neck: float = field(init=False)
    width_min: float = field(init=False)
    width_max: float = field(init=False)
    diameter: float = field(init=False)
    regions: tuple = field(init=False)
    breakpoints: tuple = field(init=False)
    symmetries: tuple = field(init=False)
    area: float = field(init=False)
    wall_length: float = field(init=False)

    def __post_init__(self):
        if not isinstance(self.table, Billiard):
            raise InvalidArgument("`table` must be a coinwall.forward.dynamics.Billiard, "
                                  f"got {type(self.table).__name__}")
        init = object.__setattr__
        theta = np.linspace(0.0, math.pi, _GRID, endpoint=False)
        width = self.width(theta)
        neck, width_min = _refine_minimum(self.width, theta, width)
        init(self, "neck", neck)
        init(self, "width_min", width_min)
        init(self, "width_max", float(width.max()))
        init(self, "diameter", self.table.H - width_min)
        init(self, "symmetries", _symmetries(self.table.wall))
        init(self, "breakpoints", _breakpoints(self.table.wall, self.symmetries))
        init(self, "regions", _regions(self, neck) if width_min <= 0.0 else ())
        area, length = self.table.area_perimeter(_AREA_POINTS)
        init(self, "area", area)
        init(self, "wall_length", length)

    # ------------------------------------------------------------------ the walls
    @property
    def H(self) -> float:
        """Distance between the walls (units of κ)."""
        return self.table.H

    @property
    def periodic(self) -> bool:
        """True when the strip is open at every angle (one domain, periodic in θ)."""
        return not self.regions

    def lo(self, theta):
        """Lower wall ``b0 + b(θ)``."""
        return self.table.lower(theta)

    def hi(self, theta):
        """Upper wall ``H − b0 − b(θ + π)``."""
        return self.table.upper(theta)

    def width(self, theta):
        """Width ``w(θ) = hi(θ) − lo(θ)`` (negative where the walls overlap)."""
        return self.hi(theta) - self.lo(theta)

    def walls(self, theta):
        """``(lo, lo', w, w')`` at ``theta`` (one-sided values away from kinks; exact derivatives)."""
        theta = np.asarray(theta, dtype=float)
        b, d1, _ = self.table.wall.derivatives(theta)
        bu, du, _ = self.table.wall.derivatives(theta + math.pi)
        lo = self.table.b0 + b
        return lo, d1, self.table.H - 2.0 * self.table.b0 - b - bu, -du - d1

    def to_dict(self) -> dict:
        """The strip's numbers as a JSON-ready dict."""
        return {"H": self.H, "b0": self.table.b0, "neck": self.neck, "width_min": self.width_min,
                "width_max": self.width_max, "diameter": self.diameter, "periodic": self.periodic,
                "regions": [list(r) for r in self.regions], "breakpoints": list(self.breakpoints),
                "symmetries": list(self.symmetries), "area": self.area, "wall_length": self.wall_length}

    @safe_repr
    def __repr__(self) -> str:
        shape = "periodic" if self.periodic else f"{len(self.regions)} regions"
        return (f"Strip(H={self.H:g}, width {self.width_min:.4g}..{self.width_max:.4g}, {shape}, "
                f"symmetries {'+'.join(self.symmetries)}, area {self.area:.6g})")


def make_strip(wall, H, b0=0.0) -> Strip:
    """The :class:`Strip` of ``wall`` between walls at distance ``H`` (units of κ), offset ``b0``.

    Parameters
    ----------
    wall : Wall
    H : float
        Distance between the walls (units of κ).
    b0 : float
        Offset added to the wall.

    Returns
    -------
    Strip

    Examples
    --------
    >>> from coinwall import Wall
    >>> ellipse = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> from coinwall import make_strip
    >>> strip = make_strip(ellipse, 2.3)          # necks of width H − 2 at θ = 0 and π
    >>> strip
    Strip(H=2.3, width 0.3..0.8858, periodic, symmetries swap+mirror+half_turn, area 3.64618)
    """
    return Strip(Billiard(wall, H, b0))


# ---------------------------------------------------------------------------------------------------- helpers
def _refine_minimum(func, theta, values):
    """The minimum of a π-periodic function from its grid values, refined by a bounded Brent search."""
    from scipy.optimize import minimize_scalar

    i = int(np.argmin(values))
    step = theta[1] - theta[0]
    best = minimize_scalar(lambda x: float(func(np.array([x]))[0]), bounds=(theta[i] - step, theta[i] + step),
                           method="bounded", options={"xatol": 1e-12})
    if best.success and best.fun < values[i]:
        return float(np.mod(best.x, math.pi)), float(best.fun)
    return float(theta[i]), float(values[i])


def _symmetries(wall) -> tuple:
    theta = np.linspace(0.0, TWO_PI, _GRID, endpoint=False) + 0.123456789e-3
    b = wall(theta)
    tol = SYMMETRY_TOL * wall.scale
    found = ["swap"]
    if np.max(np.abs(wall(-theta) - b)) <= tol:
        found.append("mirror")
    if np.max(np.abs(wall(theta + math.pi) - b)) <= tol:
        found.append("half_turn")
    return tuple(found)


def _breakpoints(wall, symmetries) -> tuple:
    """Kinks and breaks of b(θ) and of b(θ + π), closed under the symmetries, in [0, 2π)."""
    angles = [k.angle for k in wall.kinks] + list(wall.breaks)
    angles = angles + [a - math.pi for a in angles]
    angles = angles + [a + math.pi for a in angles]  # the swap maps θ to θ + π
    if "mirror" in symmetries:
        angles = angles + [-a for a in angles]
    reduced = sorted(float(np.mod(a, TWO_PI)) for a in angles)
    out = []
    for a in reduced:
        if (not out or a - out[-1] > 1e-11) and TWO_PI - a > 1e-11:
            out.append(a)
    return tuple(out)


def _regions(strip, neck) -> tuple:
    """θ-intervals where the width is positive, starting the sweep at the neck (where w ≤ 0)."""
    from scipy.optimize import brentq

    theta = neck + np.linspace(0.0, TWO_PI, 2 * _GRID + 1)
    width = strip.width(theta)
    positive = width > 0.0
    regions = []
    i = 0
    n = theta.size
    def scalar(x):
        return float(strip.width(np.array([x]))[0])

    while i < n:
        if not positive[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and positive[j + 1]:
            j += 1
        a = brentq(scalar, theta[i - 1], theta[i], xtol=1e-14) if width[i - 1] < 0 else theta[i - 1]
        b = brentq(scalar, theta[j], theta[j + 1], xtol=1e-14) if width[j + 1] < 0 else theta[j + 1]
        start = float(np.mod(a, TWO_PI))
        regions.append((start, start + float(b - a)))
        i = j + 1
    return tuple(sorted(regions))
