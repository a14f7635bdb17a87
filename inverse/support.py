"""The body's support function ``h = b0 + b`` sampled on normal angles, kinks kept.

Both solvers start here.  Between kinks of the wall the normal angles are a
uniform grid; at a kink the grid carries the angle twice, once with the
left-hand and once with the right-hand slope, so that the straight edge the
kink stands for appears as two outline points at the same normal angle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.errors import InvalidParameter, InvalidWall
from coinwall.forward.validation import check_count, check_memory, check_range

__all__ = [
    "BYTES_PER_POINT",
    "MAX_OFFSET_RATIO",
    "MAX_POINTS",
    "SupportSamples",
    "check_offset",
    "check_points",
    "envelope_point",
    "interior_point",
    "sample_support",
]

#: Largest ``|b0|`` in units of the wall's scale ``max(1, max|b|)``.  Every value of ``h = b0 + b`` is
#: rounded by ``|b0|·eps/2`` (eps = 2.2e-16) and the construction and its check amplify that about
#: 16-fold; beyond ``1e8·scale`` that rounding alone (16·2.2e-16·1e8 ≈ 3.6e-7·scale) approaches the
#: accuracy ``1e-6·scale`` every body is checked to (inverse.smooth.WALL_ACCURACY), so the wall ``b``
#: would be drowned in the rounding of the offset and no body could be the answer.  (Far below it, at
#: 1024 points, the discretisation error ``1.3e-12·b0`` already earns a warning above b0 ≈ 1e6: more
#: points help there, nothing helps beyond the bound.)
MAX_OFFSET_RATIO = 1e8

#: Largest outline resolution, and the memory a solve needs per node, every stage of the command included
#: (envelope, polar cross-check, wall check, shape check, realizability/κ_max): peak RSS of
#: `coinwall solve --points N -o body.json` is about 2,200 bytes per point plus ~100 MB of interpreter (542 MB
#: at 2·10^5 points, 1,160 MB at 5·10^5, 2,306 MB at 10^6), counted as 2,560 bytes per point.
MAX_POINTS = 5_000_000
BYTES_PER_POINT = 2560


def check_offset(b0, scale: float = 1.0) -> float:
    """Validate an offset ``b0``: a finite real number with ``|b0| ≤ MAX_OFFSET_RATIO·max(1, scale)``
    (``scale``: the wall's, ``Wall.scale``; see :data:`MAX_OFFSET_RATIO` for why)."""
    if isinstance(b0, (bool, str, bytes)):
        raise InvalidParameter(f"`b0` must be a real number, got {b0!r}")
    try:
        value = float(b0)
    except (TypeError, ValueError, OverflowError):
        raise InvalidParameter(f"`b0` must be a real number, got {b0!r}") from None
    limit = MAX_OFFSET_RATIO * max(1.0, float(scale))
    return check_range("b0", value, -limit, limit, error=InvalidParameter,
                       why=f"{MAX_OFFSET_RATIO:g} times the wall's scale {max(1.0, float(scale)):.6g}: beyond it the "
                           "rounding of b0 + b exceeds the accuracy the body is checked to")


def check_points(points) -> int:
    """Validate an outline resolution: 16 to :data:`MAX_POINTS`, and within memory."""
    points = check_count("points", points, minimum=16, maximum=MAX_POINTS)
    check_memory(f"`points` = {points} ({BYTES_PER_POINT} bytes per point)", points * BYTES_PER_POINT)
    return points


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
    phi, b, d1, d2, edge_after, break_after = _refine(wall, b0, phi, b, d1, d2, edge_after, break_after, points)
    h = b0 + b
    worst = int(np.argmin(h))
    if h[worst] < -1e-12 * wall.scale:
        raise InvalidWall(
            f"b0 + b(θ) = {h[worst]:.6g} < 0 at θ = {np.mod(phi[worst], TWO_PI):.6g}: the centre of mass would lie "
            f"outside the body; choose b0 ≥ {-(h[worst] - b0):.6g}")
    return SupportSamples(phi, h, d1, d2, edge_after, float(b0), break_after)


def _refine(wall, b0, phi, b, d1, d2, edge_after, break_after, points):
    """Halve the grid steps over which the radius of curvature ρ = b0 + b + b'' is not resolved.

    Both solvers join their nodes by cubics in φ whose end derivatives are ``ρ n'``; that is O(Δφ⁴) only
    where ρ changes little over a step.  Where b'' is unbounded (ρ ~ |φ − φ_k|^(−2/3) at the flat points of
    |x|⁴ + |y|⁴ = 1) a uniform grid leaves an error of 1e-5; halving every step over which ρ changes by
    more than half of itself (and by more than half the wall's scale) grades the grid geometrically
    towards such a point and leaves resolved walls untouched.  At most ``points`` nodes are added.
    """
    scale = float(wall.scale)
    budget = points
    for _ in range(48):
        rho = b0 + b + d2
        nxt = np.arange(1, phi.size)
        change = np.abs(rho[nxt] - rho[:-1])
        low = np.minimum(np.abs(rho[nxt]), np.abs(rho[:-1]))
        joined = edge_after[:-1] | break_after[:-1]  # the two sides of a kink or break: one angle
        wide = (change > 0.5 * low) & (change > 0.5 * scale) & ~joined & (phi[nxt] - phi[:-1] > 1e-12)
        idx = np.flatnonzero(wide)[:budget]
        if not idx.size:
            break
        budget -= idx.size
        mid = 0.5 * (phi[idx] + phi[idx + 1])
        mb, m1, m2 = (np.asarray(v, dtype=float) for v in wall.derivatives(mid))
        at = idx + 1
        phi, b, d1, d2 = (np.insert(arr, at, new) for arr, new in ((phi, mid), (b, mb), (d1, m1), (d2, m2)))
        edge_after = np.insert(edge_after, at, False)
        break_after = np.insert(break_after, at, False)
        if budget <= 0:
            break
    return phi, b, d1, d2, edge_after, break_after


def interior_point(normals, h) -> np.ndarray:
    """The origin when it is well inside ``{x : n_i·x <= h_i}``, else the centre of the largest disc inside it
    (Chebyshev centre, a three-variable linear programme).

    The polar-dual constructions (active lines as hull vertices of ``n_i / h_i``) need a point strictly
    inside the body; with b0 at its lowest the centre of mass is on the boundary (``h = 0`` at some angle).

    Raises
    ------
    InvalidWall
        If the lines enclose no area (at most a segment).
    """
    from scipy.optimize import linprog

    scale = float(np.max(np.abs(h)))
    if np.min(h) > 1e-6 * scale:
        return np.zeros(2)
    # maximise r subject to n_i·p + r <= h_i
    res = linprog(c=[0.0, 0.0, -1.0], A_ub=np.column_stack([normals, np.ones(len(h))]), b_ub=h,
                  bounds=[(None, None), (None, None), (0.0, None)], method="highs")
    if not res.success or res.x[2] <= 1e-9 * scale:
        raise InvalidWall("at this b0 the support lines b0 + b(θ) enclose no area (at most a segment: the largest "
                          "disc inside has radius 0); choose a larger b0")
    return res.x[:2]
