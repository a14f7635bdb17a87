"""Bodies of revolution: a meridian, its support function in the tilt direction, and its moments of inertia.

A body of revolution about the unit axis ``a`` (its "heads" normal) is the set swept by its meridian section
``{(ρ, ζ)}`` (ρ ≥ 0: distance from the axis, ζ: coordinate along ``a``, both measured from the centre of
mass).  Tilted by θ ∈ [0, π] from the upward vertical, the body's lowest point is on the meridian in the
plane of ``a`` and the vertical, and the height of the centre of mass above it is the support function in
the downward direction,

    h(θ) = max over the meridian of (ρ sin θ − ζ cos θ),

(the downward unit vector has the component ``−cos θ`` along ``a`` and ``sin θ`` across it).  Its highest
point is ``h(π − θ)`` above the centre (the support in the upward direction).  The wall of the
reduced billiard (:mod:`.dynamics.top`) is ``b(θ) = h(θ)/κ₁`` with ``κ₁ = √(I₁/M)`` the transverse radius of
gyration.  For a polygonal meridian the maximum runs over its convex hull's vertices, exactly; a rounded
edge (the Minkowski sum with a ball of radius ε) adds ε to h; an ellipsoid of revolution (semi-axes ``a``
across the axis, ``c`` along it) has ``h = √(a² sin²θ + c² cos²θ)``.  By the envelope theorem
``h'(θ) = ρ* cos θ + ζ* sin θ`` at the maximising point (ρ*, ζ*): the horizontal lever arm of the contact.

Moments (uniform density, so the mass is the volume).  A ring of radius ρ and mass dm at height ζ has
moment ``ρ² dm`` about the axis and ``(ρ²/2 + ζ²) dm`` about a transverse axis through the origin; with
``dm = 2π ρ dA`` over the half-section:

    M = 2π ∬ ρ dA,   M ζ_c = 2π ∬ ρ ζ dA,   I₃ = 2π ∬ ρ³ dA,   I₁ = 2π ∬ ρ (ρ²/2 + ζ²) dA − M ζ_c².

For a polygon these are boundary integrals by Green's theorem (``∬ ∂F/∂ρ dA = ∮ F dζ``) of polynomials of
degree ≤ 5 along each edge: 3-point Gauss–Legendre is exact.  Closed forms (``tests/test_coin3d.py``
holds them to independent quadratures): the cylinder of radius r, half-thickness d, ``M = 2π r² d``,
``I₃ = M r²/2``, ``I₁ = M (r²/4 + d²/3)``; the ellipsoid ``M = 4π a² c/3``, ``I₃ = 2 M a²/5``,
``I₁ = M (a² + c²)/5``.  The rounded coin (edge radius ε) is integrated slice by slice
(``dM = π R(ζ)² dζ``, ``dI₃ = π R⁴/2 dζ``, ``dI₁ = π (R⁴/4 + R² ζ²) dζ`` with the profile R(ζ)) by
``scipy.integrate.quad`` on its three smooth pieces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .display import safe_repr
from .errors import InvalidArgument
from .validation import check_finite, check_positive

__all__ = ["Revolution", "coin", "ellipsoid", "from_meridian"]

_GL3 = np.polynomial.legendre.leggauss(3)


@dataclass(frozen=True, repr=False)
class Revolution:
    """A body of revolution, its support function and moments (uniform density 1; lengths in any unit).

    Attributes
    ----------
    name : str
        What it is (for reports).
    kind : str
        ``"polygon"`` (a convex polygonal meridian, possibly with rounded edges) or ``"ellipsoid"``.
    vertices : ndarray (k, 2)
        ``(ρ, ζ)`` of the convex hull of the meridian (ρ ≥ 0) about the centre of mass (polygon kind; for a
        rounded body, the inner polygon whose Minkowski sum with a ball of radius ``rounding`` is the body).
    rounding : float
        Radius of the rounded edges (0: sharp).
    semi_axes : tuple of float
        ``(a, c)`` of the ellipsoid (across, along the axis); ``(nan, nan)`` for a polygon.
    mass, I1, I3 : float
        Volume and the moments of inertia about the transverse and the symmetry axis through the centre of
        mass (uniform density 1).
    centre : float
        ζ of the centre of mass in the coordinates the body was given in (vertices are shifted by it).

    Examples
    --------
    A coin of radius 1 and thickness 0.1 (uniform density): I3 = M r²/2.

    >>> from coinwall.forward.revolution import coin
    >>> disc = coin(1.0, 0.1)
    >>> disc.kind, round(disc.I3 / (disc.mass / 2), 12)
    ('polygon', 1.0)
    >>> h, slope = disc.support([0.0, 1.5707963267948966])     # lying flat, standing on its edge
    >>> h.round(12).tolist()
    [0.05, 1.0]
    """

    name: str
    kind: str
    vertices: np.ndarray
    rounding: float
    semi_axes: tuple
    mass: float
    I1: float
    I3: float
    centre: float = 0.0

    @property
    def kappa1(self) -> float:
        """Transverse radius of gyration ``√(I₁/M)``: the length unit of the reduced billiard."""
        return math.sqrt(self.I1 / self.mass)

    @property
    def kappa3(self) -> float:
        """Axial radius of gyration ``√(I₃/M)``."""
        return math.sqrt(self.I3 / self.mass)

    @property
    def reach(self) -> float:
        """The largest distance of a point of the body from its centre of mass."""
        if self.kind == "ellipsoid":
            return max(self.semi_axes)
        return float(np.hypot(self.vertices[:, 0], self.vertices[:, 1]).max()) + self.rounding

    def support(self, theta):
        """``(h, h')``: height of the centre of mass above the lowest point, tilt θ ∈ [0, π], and dh/dθ."""
        th = np.asarray(theta, dtype=float)
        s, c = np.sin(th), np.cos(th)
        if self.kind == "ellipsoid":
            a, cc = self.semi_axes
            h = np.sqrt((a * s) ** 2 + (cc * c) ** 2)
            return h, (a * a - cc * cc) * s * c / h
        rho, zeta = self.vertices[:, 0], self.vertices[:, 1]
        values = rho[:, None] * s.ravel()[None, :] - zeta[:, None] * c.ravel()[None, :]
        k = np.argmax(values, axis=0)
        h = values[k, np.arange(k.size)].reshape(th.shape) + self.rounding
        dh = (rho[k] * c.ravel() + zeta[k] * s.ravel()).reshape(th.shape)
        return h, dh

    def wall(self, theta):
        """The reduced billiard's floor ``b(θ) = h(θ)/κ₁``."""
        return self.support(theta)[0] / self.kappa1

    def kernel_params(self):
        """``(kind code, vertices/κ₁, rounding/κ₁, a/κ₁, c/κ₁, reach/κ₁)``: the body as the kernels take it."""
        k1 = self.kappa1
        if self.kind == "ellipsoid":
            a, c = self.semi_axes
            return 1, np.zeros((1, 2)), 0.0, a / k1, c / k1, self.reach / k1
        return 0, np.ascontiguousarray(self.vertices / k1), self.rounding / k1, 0.0, 0.0, self.reach / k1

    def to_dict(self) -> dict:
        return {"name": self.name, "kind": self.kind, "vertices": self.vertices.tolist(), "rounding": self.rounding,
                "semi_axes": list(self.semi_axes), "mass": self.mass, "I1": self.I1, "I3": self.I3,
                "kappa1": self.kappa1, "kappa3": self.kappa3}

    @safe_repr
    def __repr__(self):
        return (f"Revolution({self.name}: M={self.mass:.6g}, I1={self.I1:.6g}, I3={self.I3:.6g}, "
                f"κ1={self.kappa1:.6g})")


def _hull(points: np.ndarray) -> np.ndarray:
    """Vertices (ρ ≥ 0) of the convex hull of the meridian points mirrored across the axis."""
    from scipy.spatial import ConvexHull

    both = np.vstack([points, points * [-1.0, 1.0]])
    try:
        hull = ConvexHull(both)
    except Exception as exc:  # scipy's QhullError: a degenerate (flat) meridian
        raise InvalidArgument(f"the meridian spans no area: {exc.__class__.__name__}") from None
    verts = both[hull.vertices]
    return verts[verts[:, 0] >= 0.0]


def _polygon_moments(points: np.ndarray):
    """``(M, ∬ρζ·2π, I₃, I₁ about ζ = 0)`` of the solid swept by the closed polygon ``points`` (ρ ≥ 0)."""
    x, w = _GL3
    s = 0.5 * (x + 1.0)
    w = 0.5 * w
    p0 = points
    p1 = np.roll(points, -1, axis=0)
    rho = p0[:, 0:1] + (p1[:, 0:1] - p0[:, 0:1]) * s[None, :]
    zeta = p0[:, 1:2] + (p1[:, 1:2] - p0[:, 1:2]) * s[None, :]
    dz = (p1[:, 1] - p0[:, 1])[:, None]

    def loop(F):  # ∮ F dζ (counter-clockwise in (ρ, ζ))
        return float(np.sum(F * dz * w[None, :]))

    sign = 1.0 if loop(rho) > 0 else -1.0  # ∮ ρ dζ is the area: orientation
    mass = sign * 2 * math.pi * loop(rho ** 2 / 2)
    first = sign * 2 * math.pi * loop(rho ** 2 * zeta / 2)
    i3 = sign * 2 * math.pi * loop(rho ** 4 / 4)
    i1 = sign * 2 * math.pi * loop(rho ** 4 / 8 + rho ** 2 * zeta ** 2 / 2)
    return mass, first, i3, i1


def from_meridian(points, name: str = "meridian") -> Revolution:
    """The solid swept by a meridian polygon: ``points`` (n, 2) of ``(ρ, ζ)`` with ρ ≥ 0, in order along the
    outline from the axis back to the axis (the axis segment closes it).  The body must be convex (its support
    function is that of the hull; a non-convex meridian is refused, because its mass would not be the hull's).
    """
    try:
        pts = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`points` must be (ρ, ζ) pairs of numbers, got {points!r}") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2 or not np.all(np.isfinite(pts)):
        raise InvalidArgument(f"`points` must be at least two finite (ρ, ζ) pairs, got shape {pts.shape}")
    if np.any(pts[:, 0] < 0):
        raise InvalidArgument("`points` must have ρ >= 0 (the distance from the axis)")
    closed = pts
    if pts[0, 0] != 0.0:
        closed = np.vstack([[0.0, pts[0, 1]], closed])
    if pts[-1, 0] != 0.0:
        closed = np.vstack([closed, [0.0, pts[-1, 1]]])
    mass, first, i3, i1_origin = _polygon_moments(closed)
    if not mass > 0:
        raise InvalidArgument("the meridian spans no area")
    hull = _hull(closed)
    hull_mass = _polygon_moments(_ordered_half(hull))[0]
    if not math.isclose(mass, hull_mass, rel_tol=1e-9):
        raise InvalidArgument("the meridian must be convex (with its mirror image across the axis): a body of "
                              "revolution meets a flat wall only on its convex hull")
    zc = first / mass
    i1 = i1_origin - mass * zc * zc
    verts = hull - [0.0, zc]
    return Revolution(name, "polygon", verts, 0.0, (math.nan, math.nan), mass, i1, i3, zc)


def _ordered_half(hull: np.ndarray) -> np.ndarray:
    """The ρ ≥ 0 hull vertices as a closed polygon with the axis (ordered by angle about their centroid)."""
    pts = np.vstack([hull, [[0.0, hull[:, 1].min()], [0.0, hull[:, 1].max()]]])
    pts = np.unique(pts, axis=0)
    c = pts.mean(axis=0)
    order = np.argsort(np.arctan2(pts[:, 1] - c[1], pts[:, 0] - c[0]))
    return pts[order]


def coin(radius: float, thickness: float, rounding: float = 0.0) -> Revolution:
    """A coin: a cylinder of ``radius`` and ``thickness`` (full), its edges rounded with radius ``rounding``
    (0 ≤ rounding ≤ min(radius, thickness/2)).  Closed forms for the sharp cylinder; slice integrals (quad)
    for the rounded one."""
    r = check_positive("radius", radius)
    d = check_positive("thickness", thickness) / 2
    eps = check_finite("rounding", rounding)
    if not 0.0 <= eps <= min(r, d):
        raise InvalidArgument(f"`rounding` must be between 0 and min(radius, thickness/2) = {min(r, d):g}, got {eps:g}")
    verts = np.array([[0.0, -(d - eps)], [r - eps, -(d - eps)], [r - eps, d - eps], [0.0, d - eps]])
    name = f"coin r={r:g} thickness={2 * d:g}" + (f" rounding={eps:g}" if eps else "")
    if eps == 0.0:
        mass = 2 * math.pi * r * r * d
        return Revolution(name, "polygon", verts, 0.0, (math.nan, math.nan), mass, mass * (r * r / 4 + d * d / 3),
                          mass * r * r / 2)
    from scipy.integrate import quad

    core = d - eps

    def radius_at(z):
        z = abs(z)
        return r if z <= core else r - eps + math.sqrt(max(0.0, eps * eps - (z - core) ** 2))

    def integral(f):  # over ζ ∈ [−d, d], split where the profile's pieces meet; even integrands: twice [0, d]
        pieces = [(0.0, core), (core, d)] if core > 0 else [(0.0, d)]
        return 2.0 * sum(quad(lambda z: f(radius_at(z), z), lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
                         for lo, hi in pieces)

    mass = integral(lambda R, z: math.pi * R * R)
    i3 = integral(lambda R, z: math.pi * R ** 4 / 2)
    i1 = integral(lambda R, z: math.pi * (R ** 4 / 4 + R * R * z * z))
    return Revolution(name, "polygon", verts, eps, (math.nan, math.nan), mass, i1, i3)


def ellipsoid(equatorial: float, polar: float) -> Revolution:
    """An ellipsoid of revolution with semi-axes ``equatorial`` (across the axis) and ``polar`` (along it)."""
    a = check_positive("equatorial", equatorial)
    c = check_positive("polar", polar)
    mass = 4 * math.pi * a * a * c / 3
    return Revolution(f"ellipsoid a={a:g} c={c:g}", "ellipsoid", np.zeros((0, 2)), 0.0, (a, c), mass,
                      mass * (a * a + c * c) / 5, 2 * mass * a * a / 5)
