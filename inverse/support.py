"""The body's support function ``h = b0 + b`` sampled on normal angles, kinks kept.

Both solvers start here.  Between kinks of the wall the normal angles are a
uniform grid; at a kink the grid carries the angle twice, once with the
left-hand and once with the right-hand slope, so that the straight edge the
kink stands for appears as two outline points at the same normal angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.errors import InvalidParameter, InvalidWall
from coinwall.forward.validation import check_count

__all__ = ["SupportSamples", "sample_support", "check_offset", "envelope_point"]



def check_offset(b0) -> float:
    """Validate an offset ``b0`` (a finite real number) and return it as float."""
    try:
        value = float(b0)
    except (TypeError, ValueError):
        raise InvalidParameter(f"`b0` must be a real number, got {b0!r}") from None
    if not math.isfinite(value):
        raise InvalidParameter(f"`b0` must be finite, got {value}")
    return value


def check_points(points) -> int:
    """Validate an outline resolution."""
    return check_count("points", points, minimum=16, maximum=5_000_000)


@dataclass(frozen=True, repr=False)
class SupportSamples:
    """``h, h', h''`` of ``b0 + b`` on sorted normal angles in [φ_start, φ_start + 2π).

    ``edge_after[i]`` is True where node i and i+1 are the two sides of a kink
    (same angle, a straight edge between them); ``break_after[i]`` where they are the two sides of
    a break (same angle, same point, only the curvature differs).
    """

    phi: np.ndarray
    h: np.ndarray
    h1: np.ndarray
    h2: np.ndarray
    edge_after: np.ndarray
    b0: float = 0.0
    break_after: np.ndarray | None = None

    @property
    def rho(self) -> np.ndarray:
        """Radius of curvature ``h + h''`` of the envelope at every sample."""
        return self.h + self.h2

    def points(self) -> np.ndarray:
        """Envelope points ``h n + h' n'`` (the Legendre form)."""
        return envelope_point(self.phi, self.h, self.h1)


def envelope_point(phi, h, h1):
    """``x(φ) = h(φ) n(φ) + h'(φ) n'(φ)`` with ``n = (cos φ, sin φ)``."""
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([h * c - h1 * s, h * s + h1 * c], axis=-1)


def sample_support(wall, b0: float, points: int) -> SupportSamples:
    """Sample ``h = b0 + b`` on ``points`` normal angles (plus one extra per kink and per break).

    Kinks and breaks (where only b'' jumps) get a node on each side, with one-sided values; the two
    nodes of a kink are joined by a straight edge, those of a break coincide.

    Raises
    ------
    InvalidWall
        If ``b0 + b(θ) < 0`` somewhere: the centre of mass would lie outside the body.
    """
    kinks = wall.kinks
    breaks = getattr(wall, "breaks", ())
    if not kinks and not breaks:
        phi = np.linspace(0.0, TWO_PI, points, endpoint=False)
        b, d1, d2 = wall.derivatives(phi)
        edge_after = np.zeros(points, bool)
        break_after = edge_after
    else:
        angles = np.array([k.angle for k in kinks] + list(breaks))
        is_kink = np.array([True] * len(kinks) + [False] * len(breaks))
        order = np.argsort(angles)
        angles, is_kink = angles[order], is_kink[order]
        ends = np.append(angles[1:], angles[0] + TWO_PI)
        kink_at_end = np.roll(is_kink, -1)
        phis, sides = [], []
        for start, stop in zip(angles, ends):
            m = max(2, int(round(points * (stop - start) / TWO_PI)) + 1)
            grid = np.linspace(start, stop, m)
            phis.append(grid)
            side = np.zeros(m, int)
            side[0], side[-1] = +1, -1
            sides.append(side)
        phi = np.concatenate(phis)
        side = np.concatenate(sides)
        b, d1, d2 = (np.array(v) for v in wall.derivatives(phi))
        for i in np.flatnonzero(side):
            b[i], d1[i], d2[i] = wall.one_sided(float(phi[i]), int(side[i]))
        # the last node of a piece and the first of the next are an edge when a kink separates them
        at_end = np.repeat(kink_at_end, [len(g) for g in phis])
        edge_after = (side == -1) & at_end
        break_after = (side == -1) & ~at_end
    h = b0 + b
    worst = int(np.argmin(h))
    if h[worst] < -1e-12 * wall.scale:
        raise InvalidWall(
            f"b0 + b(θ) = {h[worst]:.6g} < 0 at θ = {np.mod(phi[worst], TWO_PI):.6g}: the centre of mass would lie "
            f"outside the body; choose b0 ≥ {-(h[worst] - b0):.6g}")
    return SupportSamples(phi, h, d1, d2, edge_after, float(b0), break_after)
