"""Case III: the largest convex body whose wall never exceeds the prescribed one.

Below the critical offset the envelope ``x(φ)`` of the support lines has
swallowtails and no convex body has the prescribed wall.  The physically
meaningful body is then the intersection of the half-planes
``{x : x·n(φ) ≤ h(φ)}``.  Its boundary follows the envelope except over
windows ``[φ1, φ2]`` of normal angles, each collapsed into a corner ``P``
where the envelope crosses itself: ``x(φ1) = x(φ2) = P``.  Inside a window the
body's wall is ``P·n(φ) = R_c cos(φ − φ_k)`` with ``R_c = |P|``, ``φ_k = arg P``.

Which support lines are active is found on the sampled lines by polar
duality: for ``h > 0`` the half-plane intersection is the polar of the convex
hull of the points ``n(φ_j)/h(φ_j)`` (scipy's Qhull); lines whose dual point
is not a hull vertex are inactive.  Each window is then polished by Newton's
method on ``x(φ1) − x(φ2) = 0`` with the exact Jacobian
``[ρ(φ1) n'(φ1), −ρ(φ2) n'(φ2)]``, so corners are exact to rounding, not to
the sampling.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI

from .support import envelope_point, interior_point

__all__ = ["Corner", "Window", "find_windows", "corner_deficit"]



@dataclass(frozen=True)
class Corner:
    """A corner of the body.

    Attributes
    ----------
    direction : float
        Polar angle of the corner point (radians, body frame); the body's wall
        over the window is ``distance · cos(θ − direction)``.
    half_width : float
        Half the width of the window of wall angles the corner governs.
    distance : float
        Distance ``R_c`` of the corner from the centre of mass.
    max_deficit : float
        Largest ``(b0 + b(θ)) − R_c cos(θ − direction)`` over the window (0
        for corners the prescribed wall itself has, like the stick's ends).
    window : (float, float)
        The window ``[θ_start, θ_end]`` of wall angles (``θ_end ≥ θ_start``).
    deficit_angle : float
        Where the deficit is largest.
    exact : bool
        True when the corner was polished to rounding by Newton's method.
    length : float or None
        For a corner that data force: every body consistent with the samples turns through the whole
        window along a piece of boundary at most this long (certified); None for a formula wall's corner.

    Examples
    --------
    The ellipse's body at ``b0 = −0.6`` has a corner on each end of its long axis, at distance
    ``√0.14`` from the centre of mass; over the window the body's wall is ``distance·cos(θ − direction)``.

    >>> from coinwall import Wall, solve_body
    >>> wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> corner = solve_body(wall, -0.6, points=256).corners[0]
    >>> round(corner.direction, 12), round(corner.distance ** 2, 12), corner.exact
    (3.14159265359, 0.14, True)
    >>> [round(angle, 6) for angle in corner.window]
    [2.244148, 4.039037]
    """

    direction: float
    half_width: float
    distance: float
    max_deficit: float
    window: tuple[float, float]
    deficit_angle: float
    exact: bool = True
    length: float | None = None

    def to_dict(self) -> dict:
        out = {"direction": self.direction, "half_width": self.half_width, "distance": self.distance,
               "max_deficit": self.max_deficit, "window": list(self.window),
               "deficit_angle": self.deficit_angle, "exact": self.exact}
        if self.length is not None:
            out["length"] = self.length
        return out


@dataclass(frozen=True)
class Window:
    """A window ``[phi1, phi2]`` of inactive support lines and its corner ``point``."""

    phi1: float
    phi2: float
    point: np.ndarray
    rho1: float
    rho2: float
    exact: bool


def _envelope(wall, b0, phi):
    b, d1, d2 = wall.derivatives(np.atleast_1d(np.asarray(phi, float)))
    return envelope_point(np.atleast_1d(phi), b0 + b, d1), b0 + b + d2


def find_windows(samples, wall, b0: float) -> list[Window]:
    """Windows of inactive support lines that contain a swallowtail (ρ < 0 or a concave kink)."""
    from scipy.spatial import ConvexHull

    phi, h, rho = samples.phi, samples.h, samples.rho
    n = phi.size
    normals = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    # the active lines are the vertices of the hull of the polar dual points n/h, which needs the origin
    # strictly inside the body; with b0 at its lowest the centre of mass is on the boundary (h = 0 at some
    # angle), so take the dual about an interior point instead (which lines are active does not depend on it)
    shifted = h - normals @ interior_point(normals, h)
    dual = normals / shifted[:, None]
    active = np.zeros(n, bool)
    active[ConvexHull(dual).vertices] = True
    # a concave kink: the two sides of the kink are an inverted edge
    concave_edge = samples.edge_after & (np.roll(samples.h1, -1) < samples.h1)
    negative = (rho < -1e-12 * max(1.0, float(np.max(np.abs(h))))) | concave_edge | np.roll(concave_edge, 1)
    idx = np.flatnonzero(active)
    if idx.size < 2:
        return []
    windows = []
    scale = float(np.max(np.abs(h)))
    following = np.append(idx[1:], idx[0] + n)
    gaps = following - idx >= 2  # most consecutive hull vertices are neighbours: skip them at once
    for a, b in zip(idx[gaps], following[gaps]):
        inside = np.arange(a + 1, b) % n
        i, j = a % n, b % n
        if not negative[inside].any() and not _clearly_inactive(phi, h, i, j, inside, scale):
            continue  # lines off the hull by rounding only, on a convex stretch: harmless
        phi1, phi2 = phi[i], phi[j] + (TWO_PI if b >= n else 0.0)
        windows.append(_polish(wall, b0, phi1, phi2, phi[(i - 1) % n], phi[(i + 1) % n],
                               phi[(j - 1) % n] + (TWO_PI if b >= n else 0.0),
                               phi[(j + 1) % n] + (TWO_PI if b >= n else 0.0), scale,
                               kinked=bool(samples.edge_after[i] or samples.edge_after[(i - 1) % n]
                                           or samples.edge_after[j] or samples.edge_after[(j - 1) % n])))
    return windows


def _clearly_inactive(phi, h, i, j, inside, scale):
    """Whether the sampled lines strictly between active lines i and j miss the body by more than
    rounding: a swallowtail narrower than the sample spacing has no sample with ρ < 0, but its
    lines still stand off the corner where lines i and j meet."""
    normals = np.array([[np.cos(phi[i]), np.sin(phi[i])], [np.cos(phi[j]), np.sin(phi[j])]])
    try:
        corner = np.linalg.solve(normals, [h[i], h[j]])
    except np.linalg.LinAlgError:
        return False
    standoff = h[inside] - (corner[0] * np.cos(phi[inside]) + corner[1] * np.sin(phi[inside]))
    return bool(np.max(standoff) > 1e-10 * scale)


def _polish(wall, b0, phi1, phi2, lo1, hi1, lo2, hi2, scale, kinked):
    """Newton on x(φ1) = x(φ2) from the sampled window; falls back to the sampled corner."""
    if lo1 > phi1:
        lo1 -= TWO_PI
    if hi2 < phi2:
        hi2 += TWO_PI
    guess = (phi1, phi2)
    if not kinked:
        previous = np.inf
        for _ in range(30):
            pts, rho = _envelope(wall, b0, np.array([phi1, phi2]))
            residual = pts[0] - pts[1]
            size = float(np.hypot(*residual))
            # converged, or stalled at the rounding floor (Newton no longer halves the residual)
            if size <= 4e-16 * scale or (size <= 1e-13 * scale and size > 0.5 * previous):
                break
            previous = size
            jac = np.column_stack([rho[0] * np.array([-np.sin(phi1), np.cos(phi1)]),
                                   -rho[1] * np.array([-np.sin(phi2), np.cos(phi2)])])
            try:
                step = np.linalg.solve(jac, -residual)
            except np.linalg.LinAlgError:
                break
            phi1 = float(np.clip(phi1 + step[0], lo1, hi1))
            phi2 = float(np.clip(phi2 + step[1], lo2, hi2))
        pts, rho = _envelope(wall, b0, np.array([phi1, phi2]))
        if np.hypot(*(pts[0] - pts[1])) <= 1e-12 * scale and rho[0] >= 0 and rho[1] >= 0:
            point = 0.5 * (pts[0] + pts[1])
            return Window(phi1, phi2, point, float(rho[0]), float(rho[1]), True)
    # fallback: the corner where the two last active sampled lines meet
    phi1, phi2 = guess
    b = b0 + wall(np.array([phi1, phi2]))
    normals = np.array([[np.cos(phi1), np.sin(phi1)], [np.cos(phi2), np.sin(phi2)]])
    point = np.linalg.solve(normals, b)
    return Window(phi1, phi2, point, 0.0, 0.0, False)


def corner_deficit(wall, b0: float, point, phi1: float, phi2: float, samples: int = 256):
    """Largest ``h(φ) − P·n(φ)`` over ``[phi1, phi2]`` and where it is attained."""
    from scipy.optimize import minimize_scalar

    grid = np.linspace(phi1, phi2, samples)

    def deficit(phi):
        phi = np.atleast_1d(phi)
        return b0 + wall(np.mod(phi, TWO_PI)) - (point[0] * np.cos(phi) + point[1] * np.sin(phi))

    values = deficit(grid)
    k = int(np.argmax(values))
    if 0 < k < samples - 1:
        res = minimize_scalar(lambda x: -float(deficit(x)[0]), bounds=(grid[k - 1], grid[k + 1]),
                              method="bounded", options={"xatol": 1e-12})
        if -res.fun >= values[k]:
            return float(-res.fun), float(np.mod(res.x, TWO_PI))
    return float(values[k]), float(np.mod(grid[k], TWO_PI))
