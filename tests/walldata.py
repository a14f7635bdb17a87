"""Independent reference walls for the tests of walls given as data.

Everything here is written with numpy and scipy only and never imports coinwall: a test that compares
coinwall's answer for sampled data with these values compares two independent computations.

Conventions (those of ``docs/theory.md``): the wall ``b(θ)`` plus the offset ``b0`` is the support
function ``h(θ) = b0 + b(θ)`` of the body in the direction ``n(θ) = (cos θ, sin θ)``; the radius of
curvature is ``ρ = h + h''`` (a measure: polygon edges are Dirac masses), and the critical offset is
``b_c = −min_θ (b + b'')``, the minimum taken over the absolutely continuous part of ``b + b''`` (Dirac
masses are positive and never decide it) and, where ``b''`` jumps, over both one-sided values.

Generators return a :class:`Reference` holding the samples and the truth:

* :func:`polygon` — a convex polygon's support function ``max_k v_k·n`` (b_c = 0, corners = vertices);
* :func:`reuleaux` — a Reuleaux polygon (constant width; b_c = 0, corners = n);
* :func:`cam` — a disc cam's follower displacement as a wall (cycloidal, 3-4-5, modified trapezoid, SHM);
* :func:`smooth` — the paper's ellipse wall, a true ellipse and a stadium.

Data as people write them: :func:`write_rounded` (a CSV with a given number of digits),
:func:`random_angles`, :func:`with_duplicates`, :func:`noisy`. Independent helpers:
:func:`true_b_c_dense` (finite differences of ``b`` alone), :func:`discrete_rho` (the support-line
radius of curvature of the samples, ``docs/theory.md`` "Walls as data"), :func:`area_from_support`.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
from collections.abc import Callable

import numpy as np
from scipy.optimize import minimize_scalar

__all__ = [
    "CAM_LAWS", "IRREGULAR_9GON", "MT_PEAK", "Reference", "Written", "area_from_support", "cam", "cam_law",
    "discrete_rho", "noisy", "polygon", "polygon_support", "random_angles", "random_polygon", "reuleaux",
    "reuleaux_outline", "smooth", "true_b_c_dense", "with_duplicates", "write_rounded",
]

TWO_PI = 2.0 * np.pi

#: A non-regular convex 9-gon, counter-clockwise: points of the ellipse ``(1.25 cos φ, 0.9 sin φ)`` at the
#: irregular angles φ = 10°, 52°, 85°, 131°, 170°, 204°, 238°, 283°, 321°, shifted by (0.23, −0.11) and
#: rounded to three decimals (still strictly convex). The origin is inside (distance ≥ 0.5 from every edge
#: line); the centroid is (0.22089, −0.10948), not the origin; area 3.23851; no edge normal lies on a
#: 0.5° grid.
IRREGULAR_9GON = np.array([
    [1.461, 0.046], [1.000, 0.599], [0.339, 0.787], [-0.590, 0.569], [-1.001, 0.046],
    [-0.912, -0.476], [-0.432, -0.873], [0.511, -0.987], [1.201, -0.676],
])


# ---------------------------------------------------------------------------------------------------- the record
@dataclasses.dataclass(frozen=True, eq=False)
class Reference:
    """A wall sampled at ``theta`` together with the truth about it.

    Attributes
    ----------
    name : str
        What the wall is, with its parameters.
    theta : ndarray
        Sample angles in radians (as generated: a uniform grid ``2πi/N`` or sorted random angles).
    b : ndarray
        The exact wall at ``theta`` (``b_of(theta)``), double precision.
    b_c : float
        The true critical offset ``−min(b + b'')`` of the continuous wall (not of the samples).
    corners : int or None
        Number of corners of the body at ``b0 = 0`` when ``b_c <= 0`` (vertices of a polygon or a
        Reuleaux polygon; 0 for a body whose support function has no vertex window). ``None`` when
        ``b_c > 0`` (at ``b0 = 0`` the body is cut, Case III, and its corners are not computed here).
    vertices : ndarray of shape (m, 2) or None
        The true corner points, counter-clockwise, when the body has any.
    b_of, d1b_of, d2b_of : callable
        The exact wall ``b(θ)``, its derivative and the absolutely continuous part of ``b''`` (Dirac masses
        at kinks left out; at a jump of ``b''`` the value of one side). 2π-periodic, vectorised.
    breaks : ndarray
        Angles in [0, 2π) where ``b`` is not C∞: kinks (edge normals), ends of vertex windows, break
        points of a cam law. Between consecutive breaks ``b`` is analytic.
    area : float or None
        Area of the true body at ``b0 = 0`` (when it is convex, i.e. ``b_c <= 0``).
    centroid : ndarray of shape (2,) or None
        Its centroid, where known.
    params : dict
        Generator parameters and extra facts (e.g. ``argmin_theta``, the angle where ``b + b''`` is least).
    """

    name: str
    theta: np.ndarray
    b: np.ndarray
    b_c: float
    corners: int | None
    vertices: np.ndarray | None
    b_of: Callable[[np.ndarray], np.ndarray]
    d1b_of: Callable[[np.ndarray], np.ndarray]
    d2b_of: Callable[[np.ndarray], np.ndarray]
    breaks: np.ndarray
    area: float | None = None
    centroid: np.ndarray | None = None
    params: dict = dataclasses.field(default_factory=dict)

    def rho(self, theta) -> np.ndarray:
        """The absolutely continuous part of ``b + b''`` at ``theta`` (``b_c = −min`` of it)."""
        theta = np.asarray(theta, dtype=float)
        return self.b_of(theta) + self.d2b_of(theta)

    def h(self, b0: float = 0.0) -> np.ndarray:
        """The samples of the support function ``b0 + b``."""
        return b0 + self.b

    def resampled(self, theta) -> Reference:
        """The same wall sampled at other angles (radians)."""
        theta = np.asarray(theta, dtype=float)
        return dataclasses.replace(self, theta=theta, b=self.b_of(theta))


def _angles(samples, random: bool, seed: int) -> np.ndarray:
    """``samples`` angles: an int gives the uniform grid ``2πi/N`` (or N sorted random angles), an array is
    taken as given (radians)."""
    if np.ndim(samples) == 0:
        count = int(samples)
        if count < 3:
            raise ValueError("need at least 3 samples")
        return random_angles(count, seed) if random else TWO_PI * np.arange(count) / count
    return np.asarray(samples, dtype=float).copy()


def _unit(theta):
    theta = np.asarray(theta, dtype=float)
    return np.cos(theta), np.sin(theta)


# ---------------------------------------------------------------------------------------------------- polygons
def polygon_support(vertices, theta) -> np.ndarray:
    """``h(θ) = max_k v_k·n(θ)``, the support function of the convex hull of ``vertices`` (definition)."""
    c, s = _unit(theta)
    v = np.asarray(vertices, dtype=float)
    return np.max(v[:, :1] * c.reshape(1, -1) + v[:, 1:] * s.reshape(1, -1), axis=0).reshape(np.shape(theta))


def _polygon_derivatives(vertices, theta, order):
    """``h'`` (order 1) or the a.e. ``h''`` (order 2) of the polygon's support function: on the window of
    vertex k, ``h = v_k·n`` so ``h' = v_k·n'`` and ``h'' = −v_k·n``."""
    c, s = _unit(np.ravel(theta))
    v = np.asarray(vertices, dtype=float)
    k = np.argmax(v[:, :1] * c + v[:, 1:] * s, axis=0)
    out = -v[k, 0] * s + v[k, 1] * c if order == 1 else -(v[k, 0] * c + v[k, 1] * s)
    return out.reshape(np.shape(theta))


def _check_convex(vertices: np.ndarray) -> None:
    edges = np.roll(vertices, -1, axis=0) - vertices
    turn = edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    inside = edges[:, 0] * (-vertices[:, 1]) - edges[:, 1] * (-vertices[:, 0])
    if np.any(turn <= 0):
        raise ValueError("vertices must be a strictly convex polygon in counter-clockwise order")
    if np.any(inside <= 0):
        raise ValueError("the origin must lie strictly inside the polygon")


def _shoelace(vertices: np.ndarray) -> tuple[float, np.ndarray]:
    x, y = vertices[:, 0], vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    return float(area), np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * area)


def _edge_normals(vertices: np.ndarray) -> np.ndarray:
    edges = np.roll(vertices, -1, axis=0) - vertices
    return np.sort(np.mod(np.arctan2(-edges[:, 0], edges[:, 1]), TWO_PI))


def random_polygon(count: int, seed: int = 0) -> np.ndarray:
    """Vertices (counter-clockwise) of a random convex polygon with ``count`` vertices around the origin.

    Sorted uniform angles and radii in [0.6, 1.2]; the convex hull of such points is taken until all
    ``count`` points are hull vertices and the origin is strictly inside (redrawn otherwise).
    """
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(seed)
    for _ in range(10000):
        angles = np.sort(rng.uniform(0, TWO_PI, count))
        radii = rng.uniform(0.6, 1.2, count)
        points = np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1)
        hull = ConvexHull(points)
        if len(hull.vertices) == count:
            vertices = points[hull.vertices]
            try:
                _check_convex(vertices)
            except ValueError:
                continue
            return vertices
    raise RuntimeError("no convex polygon found")  # pragma: no cover


def polygon(vertices_or_n=None, samples=720, *, phase: float = 0.0, random_angles: bool = False,
            seed: int = 0) -> Reference:
    """A convex polygon's wall: ``b(θ) = max_k v_k·n(θ)`` (the definition of the support function).

    Parameters
    ----------
    vertices_or_n : None, int or array of shape (m, 2)
        ``None``: :data:`IRREGULAR_9GON` (centroid off the origin, origin inside). An int ``n``: the
        regular n-gon of circumradius 1 with vertices at angles ``phase + 2πk/n``. An array: the vertices,
        counter-clockwise, strictly convex, origin strictly inside (checked).
    samples : int or array
        Number of uniform samples ``2πi/N`` or the angles themselves (radians).
    random_angles : bool
        With an int ``samples``: sorted uniform random angles (``seed``) instead of the grid.

    Notes
    -----
    Truth: on the window of vertex k (between the normals of its two edges) ``h = v_k·n``, so
    ``h + h'' = 0`` there; at each edge normal ``h'`` jumps by the edge length (a positive Dirac mass of
    ``ρ``). Hence ``b_c = 0`` exactly and the body at ``b0 = 0`` is the polygon: ``corners = m``.
    Area and centroid by the shoelace formula; ``breaks`` are the edge normals.
    """
    if vertices_or_n is None:
        vertices = IRREGULAR_9GON.copy()
        name = "irregular 9-gon"
    elif np.ndim(vertices_or_n) == 0:
        n = int(vertices_or_n)
        k = np.arange(n)
        vertices = np.stack([np.cos(phase + TWO_PI * k / n), np.sin(phase + TWO_PI * k / n)], axis=1)
        name = f"regular {n}-gon"
    else:
        vertices = np.array(vertices_or_n, dtype=float)
        name = f"{len(vertices)}-gon"
    _check_convex(vertices)
    theta = _angles(samples, random_angles, seed)
    b_of = functools.partial(polygon_support, vertices)
    area, centroid = _shoelace(vertices)
    return Reference(
        name=name, theta=theta, b=b_of(theta), b_c=0.0, corners=len(vertices), vertices=vertices, b_of=b_of,
        d1b_of=functools.partial(_polygon_derivatives, vertices, order=1),
        d2b_of=functools.partial(_polygon_derivatives, vertices, order=2),
        breaks=_edge_normals(vertices), area=area, centroid=centroid,
        params={"vertices_or_n": vertices_or_n, "phase": phase, "random_angles": random_angles, "seed": seed},
    )


# ---------------------------------------------------------------------------------------------------- Reuleaux
def _reuleaux_vertices(n: int, width: float, phase: float) -> np.ndarray:
    radius = width / (2 * np.cos(np.pi / (2 * n)))
    angles = phase + TWO_PI * np.arange(n) / n
    return radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)


def _reuleaux_parts(n, width, phase, theta):
    """For each θ: the vertex ``v`` that is either the support point (vertex window) or the centre of the
    supporting arc, and whether θ is on an arc. Windows and arcs alternate every π/n: vertex window k is
    centred on ``phase + 2πk/n``, the arc centred at vertex k on ``phase + 2πk/n + π`` (n odd ⇒ the odd
    multiples of π/n)."""
    theta = np.asarray(theta, dtype=float)
    vertices = _reuleaux_vertices(n, width, phase)
    j = np.rint(np.mod(theta - phase, TWO_PI) * n / np.pi).astype(int) % (2 * n)
    arc = (j % 2) == 1
    k = np.where(arc, ((j - n) // 2) % n, (j // 2) % n)
    return vertices[k], arc


def _reuleaux_b(n, width, phase, theta):
    v, arc = _reuleaux_parts(n, width, phase, theta)
    c, s = _unit(theta)
    return v[..., 0] * c + v[..., 1] * s + np.where(arc, width, 0.0)


def _reuleaux_d1b(n, width, phase, theta):
    v, _ = _reuleaux_parts(n, width, phase, theta)
    c, s = _unit(theta)
    return -v[..., 0] * s + v[..., 1] * c


def _reuleaux_d2b(n, width, phase, theta):
    v, _ = _reuleaux_parts(n, width, phase, theta)
    c, s = _unit(theta)
    return -(v[..., 0] * c + v[..., 1] * s)


def reuleaux_outline(n: int = 3, width: float = 2.0, *, phase: float = 0.0, points_per_arc: int = 2001):
    """Dense points on the boundary of the Reuleaux n-gon, built from its definition (for checks).

    The arc centred at vertex k joins the two vertices opposite to it, ``v_{k+m}`` and ``v_{k+m+1}``
    (``m = (n−1)/2``), with radius ``width``. Returns an array of shape (n·points_per_arc, 2).
    """
    vertices = _reuleaux_vertices(n, width, phase)
    m = (n - 1) // 2
    out = []
    for k in range(n):
        a, b = vertices[(k + m) % n] - vertices[k], vertices[(k + m + 1) % n] - vertices[k]
        start = np.arctan2(a[1], a[0])
        sweep = np.mod(np.arctan2(b[1], b[0]) - start, TWO_PI)
        phi = start + sweep * np.linspace(0, 1, points_per_arc)
        out.append(vertices[k] + width * np.stack([np.cos(phi), np.sin(phi)], axis=1))
    return np.concatenate(out)


def reuleaux(n_sides: int = 3, samples=720, *, width: float = 2.0, phase: float = 0.0,
             random_angles: bool = False, seed: int = 0) -> Reference:
    """The wall of the Reuleaux polygon with ``n_sides`` (odd) vertices and constant width ``width``.

    Notes
    -----
    Construction: the vertices of the regular n-gon on the circle of radius ``R = w/(2 cos(π/2n))``
    (vertex 0 at angle ``phase``), so each vertex is at distance ``w`` from the two opposite ones; the body
    is the intersection of the discs of radius ``w`` centred at the vertices. Its boundary is n arcs;
    the arc centred at ``v_k`` spans the normal directions within ``π/2n`` of ``phase + 2πk/n + π`` (the
    inscribed angle of the opposite side is π/n), and the remaining directions, within ``π/2n`` of
    ``phase + 2πk/n``, are the vertex window of ``v_k``. Hence exactly

    * vertex window of k: ``h(θ) = v_k·n(θ)``, ``ρ = 0``;
    * arc centred at k: ``h(θ) = w + v_k·n(θ)``, ``ρ = w``;

    ``h`` is C1 (the windows meet where both formulas give the same point) and ``h(θ) + h(θ+π) = w``.
    ``b_c = 0`` (ρ = 0 on the windows), ``corners = n``. Area: the regular n-gon plus n circular segments
    of radius w and angle π/n, ``A = n R² sin(2π/n)/2 + n w² (π/n − sin(π/n))/2``
    (``(π − √3) w²/2`` for n = 3); the centroid is the origin by symmetry.
    """
    n = int(n_sides)
    if n < 3 or n % 2 == 0:
        raise ValueError("a Reuleaux polygon needs an odd number of sides >= 3")
    theta = _angles(samples, random_angles, seed)
    b_of = functools.partial(_reuleaux_b, n, width, phase)
    radius = width / (2 * np.cos(np.pi / (2 * n)))
    area = n * radius**2 * np.sin(TWO_PI / n) / 2 + n * width**2 * (np.pi / n - np.sin(np.pi / n)) / 2
    breaks = np.sort(np.mod(phase + (np.arange(2 * n) + 0.5) * np.pi / n, TWO_PI))
    return Reference(
        name=f"Reuleaux {n}-gon of width {width:g}", theta=theta, b=b_of(theta), b_c=0.0, corners=n,
        vertices=_reuleaux_vertices(n, width, phase), b_of=b_of,
        d1b_of=functools.partial(_reuleaux_d1b, n, width, phase),
        d2b_of=functools.partial(_reuleaux_d2b, n, width, phase), breaks=breaks, area=float(area),
        centroid=np.zeros(2),
        params={"n_sides": n, "width": width, "phase": phase, "random_angles": random_angles, "seed": seed},
    )


# ---------------------------------------------------------------------------------------------------- cams
# Each law is the normalised rise f(x), x ∈ [0, 1], f(0) = 0, f(1) = 1, f'(0) = f'(1) = 0, returned as
# (f, f', f'') in x, with the interior points where a derivative of f is discontinuous.

def _law_cycloidal(x):
    """Cycloidal: ``f = x − sin(2πx)/2π``, ``f' = 1 − cos 2πx``, ``f'' = 2π sin 2πx`` (C2 at both ends)."""
    w = TWO_PI
    return x - np.sin(w * x) / w, 1 - np.cos(w * x), w * np.sin(w * x)


def _law_345(x):
    """3-4-5 polynomial: ``f = 10x³ − 15x⁴ + 6x⁵``, ``f' = 30x²(1−x)²``, ``f'' = 60x(1−x)(1−2x)``."""
    return x**3 * (10 - 15 * x + 6 * x**2), 30 * x**2 * (1 - x) ** 2, 60 * x * (1 - x) * (1 - 2 * x)


def _law_shm(x):
    """Simple harmonic: ``f = (1 − cos πx)/2``, ``f' = (π/2) sin πx``, ``f'' = (π²/2) cos πx``; ``f''`` jumps
    from 0 to π²/2 at x = 0 and from −π²/2 to 0 at x = 1."""
    return (1 - np.cos(np.pi * x)) / 2, np.pi * np.sin(np.pi * x) / 2, np.pi**2 * np.cos(np.pi * x) / 2


#: Peak acceleration of the modified trapezoid, ``A = 8π/(π + 2) = 4.888124`` (in units of L/β²).
MT_PEAK = 8 * np.pi / (np.pi + 2)


def _law_modified_trapezoid(x):
    """Modified trapezoid (standard, symmetric), acceleration in units L/β² with ``k = 4π``:

    =================  ==========================
    0 ≤ x ≤ 1/8        ``A sin(k x)``
    1/8 ≤ x ≤ 3/8      ``A``
    3/8 ≤ x ≤ 5/8      ``A cos(k (x − 3/8))``
    5/8 ≤ x ≤ 7/8      ``−A``
    7/8 ≤ x ≤ 1        ``−A cos(k (x − 7/8))``
    =================  ==========================

    Integrating twice from f(0) = f'(0) = 0 piece by piece (with ``u`` the distance from the piece's start):
    ``f'`` = ``A(1 − cos kx)/k``, ``v1 + A u``, ``v2 + A sin(ku)/k``, ``v2 − A u``, ``v1 − A sin(ku)/k`` with
    ``v1 = A/k``, ``v2 = A/k + A/4``; ``f`` = ``A(x/k − sin(kx)/k²)``, ``f1 + v1 u + A u²/2``,
    ``f2 + v2 u + A(1 − cos ku)/k²``, ``f3 + v2 u − A u²/2``, ``f4 + v1 u − A(1 − cos ku)/k²`` with
    ``f1 = A(1/8k − 1/k²)``, ``f2 = f1 + v1/4 + A/32``, ``f3 = f2 + v2/4 + 2A/k²``, ``f4 = f3 + v2/4 − A/32``.
    Then ``f(1) = A(1/k + 1/8)``, so ``f(1) = 1`` gives ``A = 8π/(π + 2) = 4.888124``; ``f'(1) = 0`` by the
    antisymmetry of the acceleration about x = 1/2. ``f''`` is continuous, ``f'''`` jumps at the quarters and
    eighths.
    """
    a, k = MT_PEAK, 4 * np.pi
    v1, v2 = a / k, a / k + a / 4
    f1 = a * (1 / (8 * k) - 1 / k**2)
    f2 = f1 + v1 / 4 + a / 32
    f3 = f2 + v2 / 4 + 2 * a / k**2
    f4 = f3 + v2 / 4 - a / 32
    x = np.asarray(x, dtype=float)
    piece = np.clip(np.searchsorted(np.array([1 / 8, 3 / 8, 5 / 8, 7 / 8]), x, side="right"), 0, 4)
    u = x - np.array([0.0, 1 / 8, 3 / 8, 5 / 8, 7 / 8])[piece]
    sk, ck = np.sin(k * u), np.cos(k * u)
    f = np.choose(piece, [a * (u / k - sk / k**2), f1 + v1 * u + a * u**2 / 2, f2 + v2 * u + a * (1 - ck) / k**2,
                          f3 + v2 * u - a * u**2 / 2, f4 + v1 * u - a * (1 - ck) / k**2])
    f_1 = np.choose(piece, [a * (1 - ck) / k, v1 + a * u, v2 + a * sk / k, v2 - a * u, v1 - a * sk / k])
    f_2 = np.choose(piece, [a * sk, np.full_like(u, a), a * ck, np.full_like(u, -a), -a * ck])
    return f, f_1, f_2


#: name -> (law, interior break points of the law in x)
CAM_LAWS = {
    "cycloidal": (_law_cycloidal, ()),
    "345": (_law_345, ()),
    "modified-trapezoid": (_law_modified_trapezoid, (1 / 8, 3 / 8, 5 / 8, 7 / 8)),
    "shm": (_law_shm, ()),
}


def cam_law(law: str, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The normalised rise ``(f, f', f'')`` of ``law`` at ``x ∈ [0, 1]`` (see :data:`CAM_LAWS`)."""
    if law not in CAM_LAWS:
        raise ValueError(f"unknown cam law {law!r}; choose from {sorted(CAM_LAWS)}")
    return CAM_LAWS[law][0](np.asarray(x, dtype=float))


def _cam_eval(law, rise, beta, return_start, base, order, theta):
    """``b = base + s`` (order 0), ``s'`` (1) or ``s''`` (2) of the rise–dwell–return–dwell cam."""
    theta = np.asarray(theta, dtype=float)
    phi = np.mod(theta, TWO_PI)
    on_rise = phi <= beta
    on_return = (phi >= return_start) & (phi <= return_start + beta)
    x = np.clip(np.where(on_rise, phi / beta, (phi - return_start) / beta), 0.0, 1.0)
    f = cam_law(law, x)[order] * rise / beta**order
    if order == 0:
        high = (phi > beta) & (phi < return_start)
        return base + np.where(on_rise, f, np.where(on_return, rise - f, np.where(high, rise, 0.0)))
    return np.where(on_rise, f, np.where(on_return, -f, 0.0))


def _min_on_interval(fun, lo, hi, points=2001):
    """Minimum of a smooth ``fun`` on the closed [lo, hi]: dense evaluation (endpoints included), then a
    bounded Brent minimisation on the bracket of the best sample. Returns (value, argument)."""
    x = np.linspace(lo, hi, points)
    y = fun(x)
    i = int(np.argmin(y))
    best, at = float(y[i]), float(x[i])
    if 0 < i < points - 1:
        res = minimize_scalar(lambda t: float(fun(np.array([t]))[0]), bounds=(x[i - 1], x[i + 1]),
                              method="bounded", options={"xatol": 1e-14})
        if res.fun < best:
            best, at = float(res.fun), float(res.x)
    return best, at


def cam(law: str = "modified-trapezoid", samples=360, *, rise: float = 1.0, beta: float = np.pi / 3,
        base: float = 0.0, return_start: float = np.pi, random_angles: bool = False, seed: int = 0) -> Reference:
    """A disc cam's follower displacement as a wall, ``b(θ) = base + s(θ)``.

    Layout (rise–dwell–return–dwell, one revolution): rise of height ``L = rise`` over ``[0, β]`` by the
    law, dwell at ``L`` until ``return_start`` (default π), return over ``[return_start, return_start + β]``
    by the mirrored law ``s = L(1 − f(x))``, dwell at 0 until 2π. With the defaults: rise 0°–60°, high dwell
    60°–180°, return 180°–240°, low dwell 240°–360°.

    Parameters
    ----------
    law : {"cycloidal", "345", "modified-trapezoid", "shm"}
        The normalised rise ``f(x)`` (closed forms in the ``_law_*`` docstrings).
    samples : int or array
        Number of uniform samples (default 360: one per degree) or the angles (radians).

    Notes
    -----
    Truth: ``b + b'' = base + s + s''`` with ``s'' = L f''(x)/β²`` on the rise and ``−L f''(x)/β²`` on the
    return, 0 on the dwells (``x`` = angle into the rise or return over β). ``b_c = −min`` of it, taken
    piece by piece on the closed rise and return (each split at the law's interior break points) with the
    law's own formula, so that at the ends both one-sided values count (the SHM law's ``s''`` jumps there),
    and on the dwells (``base + L`` and ``base``); on each piece a dense evaluation plus a bounded scalar
    minimisation (:func:`_min_on_interval`). Closed forms this reproduces: SHM ``b_c = L(π²/(2β²) − 1) − base``
    (``b + b''`` is monotone in ``cos πx`` on the rise; 3.5 L at β = 60°). For the modified trapezoid with
    L = 1, β = 60° the minimum is inside the sine piece just before x = 5/8 (θ ≈ 37.36°) and
    ``b_c = 3.7269596``. ``corners = 0`` when ``b_c <= 0`` (``s`` is C1 and ρ has no vertex window), else
    ``None``; ``area`` (``½∫(h² − h'²)``, piecewise Gauss–Legendre) only when ``b_c <= 0``.
    """
    if law not in CAM_LAWS:
        raise ValueError(f"unknown cam law {law!r}; choose from {sorted(CAM_LAWS)}")
    if not (0 < beta <= return_start and return_start + beta <= TWO_PI):
        raise ValueError("need 0 < beta <= return_start and return_start + beta <= 2π")
    law_fun, interior = CAM_LAWS[law]
    knots = np.concatenate([[0.0], interior, [1.0]])

    def g_rise(x):
        f, _, f2 = law_fun(x)
        return base + rise * f + rise * f2 / beta**2

    def g_return(x):
        f, _, f2 = law_fun(x)
        return base + rise * (1 - f) - rise * f2 / beta**2

    candidates = []
    for g, start in ((g_rise, 0.0), (g_return, return_start)):
        for lo, hi in itertools.pairwise(knots):
            value, x = _min_on_interval(g, lo, hi)
            candidates.append((value, start + beta * x))
    if return_start > beta:
        candidates.append((base + rise, 0.5 * (beta + return_start)))
    if return_start + beta < TWO_PI:
        candidates.append((base + 0.0, 0.5 * (return_start + beta + TWO_PI)))
    least, argmin = min(candidates)
    b_c = -least

    b_of, d1b_of, d2b_of = (functools.partial(_cam_eval, law, rise, beta, return_start, base, order)
                            for order in (0, 1, 2))
    breaks = np.unique(np.mod(np.concatenate([beta * knots, return_start + beta * knots]), TWO_PI))
    area = area_from_support(b_of, d1b_of, breaks) if b_c <= 0 else None
    theta = _angles(samples, random_angles, seed)
    return Reference(
        name=f"{law} cam, rise {rise:g} over {np.degrees(beta):g} deg, base {base:g}", theta=theta, b=b_of(theta),
        b_c=float(b_c), corners=0 if b_c <= 0 else None, vertices=None, b_of=b_of, d1b_of=d1b_of, d2b_of=d2b_of,
        breaks=breaks, area=area, centroid=None,
        params={"law": law, "rise": rise, "beta": beta, "base": base, "return_start": return_start,
                "argmin_theta": float(argmin), "random_angles": random_angles, "seed": seed},
    )


# ---------------------------------------------------------------------------------------------------- smooth walls
def _paper(eps, order, theta):
    """The paper's wall ``b = c√g``, ``g = 1 + ε cos²θ``, ``c = 1/√(1+ε)``, and its derivatives:
    ``g' = −ε sin 2θ``, ``g'' = −2ε cos 2θ``, ``b' = c g'/(2√g)``, ``b'' = c(g''/(2√g) − g'²/(4 g^{3/2}))``."""
    theta = np.asarray(theta, dtype=float)
    c = 1 / np.sqrt(1 + eps)
    g = 1 + eps * np.cos(theta) ** 2
    g1, g2 = -eps * np.sin(2 * theta), -2 * eps * np.cos(2 * theta)
    if order == 0:
        return c * np.sqrt(g)
    if order == 1:
        return c * g1 / (2 * np.sqrt(g))
    return c * (g2 / (2 * np.sqrt(g)) - g1**2 / (4 * g**1.5))


def _ellipse(a, b, order, theta):
    """``h = √(a² cos² + b² sin²)``, ``h' = (b² − a²) sin θ cos θ / h``, ``h'' = a²b²/h³ − h`` (so
    ``ρ = a²b²/h³``: the support function of the ellipse x²/a² + y²/b² ≤ 1)."""
    theta = np.asarray(theta, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    h = np.sqrt(a**2 * c**2 + b**2 * s**2)
    if order == 0:
        return h
    if order == 1:
        return (b**2 - a**2) * s * c / h
    return a**2 * b**2 / h**3 - h


def _stadium(half_length, radius, order, theta):
    """``h = ℓ|cos θ| + r``, ``h' = −ℓ sign(cos θ) sin θ``, a.e. ``h'' = −ℓ|cos θ|``."""
    theta = np.asarray(theta, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    if order == 0:
        return half_length * np.abs(c) + radius
    if order == 1:
        return -half_length * np.sign(c) * s
    return -half_length * np.abs(c)


def smooth(name: str = "paper", samples=720, *, eps: float = 1.0, semi_axes=(1.0, 0.6), half_length: float = 1.0,
           radius: float = 0.5, random_angles: bool = False, seed: int = 0) -> Reference:
    """Walls of bodies without corners at ``b0 = 0``.

    ``name``:

    * ``"paper"`` — the paper's wall ``b = √((1 + ε cos²θ)/(1 + ε))``. ``b + b''`` in closed form
      (see :func:`_paper`): ``c(4g² + 2g g'' − g'²)/(4 g^{3/2})``; at θ = 0 it is ``1/(1 + ε)`` and at π/2
      ``√(1 + ε)``. ``b_c`` is the minimum found by dense evaluation plus bounded minimisation on [0, π]
      (the wall has period π); it is at θ = 0, ``b_c = −1/(1 + ε)`` (−1/2 at ε = 1, as the paper says).
      Closed form behind it: ``b² = cos²θ + sin²θ/(1 + ε)``, so this wall *is* the support function of the
      ellipse with semi-axes 1 and ``1/√(1 + ε)`` (``"ellipse"`` below): ``b_c = −b²/a = −1/(1 + ε)``,
      area ``π/√(1 + ε)`` (π/√2 at ε = 1). Area here by ``½∫(h² − h'²)``, Gauss–Legendre; centroid 0.
    * ``"ellipse"`` — ``h = √(a² cos²θ + b² sin²θ)`` with ``(a, b) = semi_axes``: ``ρ = a²b²/h³`` is least
      where h is largest, ``b_c = −min(a,b)²/max(a,b)`` (−0.36 for the default (1, 0.6)). Area ``πab``.
    * ``"stadium"`` — ``h = ℓ|cos θ| + r``: ``ℓ|cos θ|`` is the support function of the segment
      [(−ℓ, 0), (ℓ, 0)], whose ρ is 0 except Dirac masses 2ℓ at θ = ±π/2; adding r (a disc) gives the
      stadium (the segment thickened by r), ``b + b'' = r`` except those positive Dirac masses, so
      ``b_c = −r`` (−0.5 default). At ``b0 = 0`` the body is the stadium, C1, no corners (at ``b0 = b_c``
      it degenerates to the segment, two corners with windows of width π). Area ``πr² + 4ℓr``.
    """
    theta = _angles(samples, random_angles, seed)
    if name == "paper":
        b_of, d1, d2 = (functools.partial(_paper, eps, order) for order in (0, 1, 2))
        value, at = _min_on_interval(lambda t: b_of(t) + d2(t), 0.0, np.pi, points=20001)
        return Reference(
            name=f"paper wall eps={eps:g}", theta=theta, b=b_of(theta), b_c=-value, corners=0 if value >= 0 else None,
            vertices=None, b_of=b_of, d1b_of=d1, d2b_of=d2, breaks=np.array([]),
            area=area_from_support(b_of, d1, np.array([])) if value >= 0 else None, centroid=np.zeros(2),
            params={"eps": eps, "argmin_theta": at, "random_angles": random_angles, "seed": seed},
        )
    if name == "ellipse":
        a, b = map(float, semi_axes)
        fun = functools.partial(functools.partial, _ellipse, a, b)
        return Reference(
            name=f"ellipse a={a:g} b={b:g}", theta=theta, b=fun(0)(theta), b_c=-min(a, b) ** 2 / max(a, b),
            corners=0, vertices=None, b_of=fun(0), d1b_of=fun(1), d2b_of=fun(2), breaks=np.array([]),
            area=np.pi * a * b, centroid=np.zeros(2),
            params={"semi_axes": (a, b), "argmin_theta": 0.0 if a >= b else np.pi / 2, "random_angles": random_angles,
                    "seed": seed},
        )
    if name == "stadium":
        fun = functools.partial(functools.partial, _stadium, half_length, radius)
        return Reference(
            name=f"stadium l={half_length:g} r={radius:g}", theta=theta, b=fun(0)(theta), b_c=-radius, corners=0,
            vertices=None, b_of=fun(0), d1b_of=fun(1), d2b_of=fun(2), breaks=np.array([np.pi / 2, 3 * np.pi / 2]),
            area=np.pi * radius**2 + 4 * half_length * radius, centroid=np.zeros(2),
            params={"half_length": half_length, "radius": radius, "random_angles": random_angles, "seed": seed},
        )
    raise ValueError(f"unknown smooth wall {name!r}; choose paper, ellipse or stadium")


# ---------------------------------------------------------------------------------------------------- data as written
@dataclasses.dataclass(frozen=True, eq=False)
class Written:
    """A wall as a person writes it: ``text`` is the CSV, ``theta`` and ``b`` exactly what it parses to
    (``theta`` in the unit written: degrees when ``degrees``), ``radians`` the angles in radians."""

    text: str
    theta: np.ndarray
    b: np.ndarray
    radians: np.ndarray
    header: str


def _format(x: float, digits: int | None, mode: str) -> str:
    if digits is None:
        return repr(float(x))
    if mode == "significant":
        return f"{x:.{digits}g}"
    if mode == "decimals":
        return f"{x:.{digits}f}"
    raise ValueError("mode must be 'significant' or 'decimals'")


def write_rounded(ref, digits: int | None, *, theta_digits: int | None = None, degrees: bool = False,
                  mode: str = "significant") -> Written:
    """Write ``ref``'s samples as a CSV with ``digits`` significant digits (``f"{x:.{digits}g}"``) or decimals
    (``mode="decimals"``, ``f"{x:.{digits}f}"``).

    Parameters
    ----------
    ref : Reference or (theta, b)
        The samples (theta in radians).
    digits : int or None
        Digits of ``b``; ``None`` writes ``repr(float)`` (the shortest string that reads back exactly).
    theta_digits : int or None
        Digits of the angle, same ``mode``; ``None`` (default) writes it in full.
    degrees : bool
        Write the angle in degrees under the header ``theta_deg,b`` (else ``theta,b``, radians).

    Returns
    -------
    Written
        The text (header line, one ``theta,b`` line per sample, final newline) and the arrays it parses to.
    """
    theta, b = (ref.theta, ref.b) if isinstance(ref, Reference) else map(np.asarray, ref)
    angle = np.degrees(theta) if degrees else np.asarray(theta, dtype=float)
    header = "theta_deg,b" if degrees else "theta,b"
    ts = [_format(t, theta_digits, mode) for t in angle]
    bs = [_format(v, digits, mode) for v in b]
    text = header + "\n" + "".join(f"{t},{v}\n" for t, v in zip(ts, bs, strict=True))
    theta_out = np.array([float(t) for t in ts])
    return Written(text=text, theta=theta_out, b=np.array([float(v) for v in bs]),
                   radians=np.radians(theta_out) if degrees else theta_out, header=header)


def random_angles(n: int, seed: int = 0, *, sort: bool = True) -> np.ndarray:
    """``n`` independent uniform angles in [0, 2π) (``numpy.random.default_rng(seed)``), sorted by default."""
    theta = np.random.default_rng(seed).uniform(0.0, TWO_PI, int(n))
    return np.sort(theta) if sort else theta


def with_duplicates(theta, b, seed: int = 0, *, fraction: float = 0.1, jitter: float = 0.0,
                    return_indices: bool = False):
    """Repeat a random ``fraction`` of the rows (at least one), each copy right after its original.

    ``jitter`` > 0 adds Gaussian noise of that size to the repeated ``b`` (two readings that disagree).
    Returns ``(theta, b)``, and with ``return_indices`` also the indices (into the result) of the copies.
    """
    theta, b = np.asarray(theta, dtype=float), np.asarray(b, dtype=float)
    rng = np.random.default_rng(seed)
    count = max(1, round(fraction * theta.size))
    chosen = np.sort(rng.choice(theta.size, size=count, replace=False))
    order = np.sort(np.concatenate([np.arange(theta.size), chosen]), kind="stable")
    copies = np.flatnonzero(np.r_[False, order[1:] == order[:-1]])
    out_b = b[order].copy()
    out_b[copies] += jitter * rng.standard_normal(copies.size) if jitter > 0 else 0.0
    return (theta[order], out_b, copies) if return_indices else (theta[order], out_b)


def noisy(ref, sigma: float, seed: int = 0) -> np.ndarray:
    """``ref.b`` plus independent Gaussian noise of standard deviation ``sigma`` (the truth stays in ``ref``)."""
    b = ref.b if isinstance(ref, Reference) else np.asarray(ref, dtype=float)
    return b + sigma * np.random.default_rng(seed).standard_normal(b.shape)


# ------------------------------------------------------------------------------------------------- independent checks
def _fd_rho(b_of, x, lo, hi, step):
    """``b + b''`` at ``x`` by finite differences of ``b`` alone, never reaching outside [lo, hi]: the central
    stencil ``(b₋ − 2b + b₊)/δ²`` inside, the second-order one-sided ``(2b₀ − 5b₁ + 4b₂ − b₃)/δ²`` within δ
    of an end (so that the one-sided limit at a break is what is measured)."""
    x = np.asarray(x, dtype=float)
    central = (b_of(x - step) - 2 * b_of(x) + b_of(x + step)) / step**2
    forward = (2 * b_of(x) - 5 * b_of(x + step) + 4 * b_of(x + 2 * step) - b_of(x + 3 * step)) / step**2
    backward = (2 * b_of(x) - 5 * b_of(x - step) + 4 * b_of(x - 2 * step) - b_of(x - 3 * step)) / step**2
    d2 = np.where(x - step < lo, forward, np.where(x + step > hi, backward, central))
    return b_of(x) + d2


def true_b_c_dense(b_of, breaks=(), *, points: int = 20000, step: float = 1e-4) -> tuple[float, float]:
    """``b_c = −min(b + b'')`` from the wall function alone (no closed-form derivative).

    Between consecutive ``breaks`` (where ``b''`` may jump or carry a Dirac mass; none: the whole circle)
    ``b + b''`` is computed by finite differences with step ``step`` that never straddle a break (one-sided
    stencils at the ends, :func:`_fd_rho`), on about ``points`` nodes in all, and the best node is refined by
    a bounded scalar minimisation. Accuracy ≈ ``step²·|b''''|/12 + 16 ε |b|/step²`` (~1e-7 for O(1) walls).
    Returns ``(b_c, argmin_theta)``.
    """
    edges = np.sort(np.mod(np.asarray(breaks, dtype=float), TWO_PI))
    if edges.size == 0:
        intervals = [(0.0, TWO_PI)]
    else:
        intervals = list(itertools.pairwise(np.r_[edges, edges[0] + TWO_PI]))
    best, at = np.inf, 0.0
    for lo, hi in intervals:
        if hi - lo < 4 * step:
            continue
        count = max(16, int(points * (hi - lo) / TWO_PI))
        value, x = _min_on_interval(lambda t, lo=lo, hi=hi: _fd_rho(b_of, t, lo, hi, step), lo, hi, count)
        if value < best:
            best, at = value, x
    return -float(best), float(np.mod(at, TWO_PI))


def discrete_rho(theta, h) -> np.ndarray:
    """The support lines' radius of curvature ``ρ_i = ℓ_i/(tan(Δ₋/2) + tan(Δ₊/2))`` (``docs/theory.md``,
    "Walls as data"), written here independently: ``ℓ_i = (h₋ − h cos Δ₋)/sin Δ₋ + (h₊ − h cos Δ₊)/sin Δ₊``
    is the length of line i between its neighbours. ``theta`` must be sorted, distinct, with gaps < π; the
    data's own critical offset is ``−min ρ_i``. Exact ``ρ_i = r`` for ``h ≡ r`` on any grid.
    """
    theta, h = np.asarray(theta, dtype=float), np.asarray(h, dtype=float)
    dm = np.mod(theta - np.roll(theta, 1), TWO_PI)
    dp = np.mod(np.roll(theta, -1) - theta, TWO_PI)
    hm, hp = np.roll(h, 1), np.roll(h, -1)
    length = (hm - h * np.cos(dm)) / np.sin(dm) + (hp - h * np.cos(dp)) / np.sin(dp)
    return length / (np.tan(dm / 2) + np.tan(dp / 2))


def area_from_support(b_of, d1b_of, breaks=(), *, nodes: int = 64, pieces: int = 32) -> float:
    """Area ``½∮(h² − h'²) dθ`` of the convex body with support function ``h = b_of`` (``h' = d1b_of``).

    Integration by parts of ``½∮ h ρ dθ`` on each smooth piece: the jumps of ``h'`` at kinks give back the
    Dirac masses of ρ, so the formula holds for piecewise-smooth ``h`` too. Gauss–Legendre with ``nodes``
    nodes on each of ``pieces`` sub-intervals of every interval between ``breaks`` (analytic there:
    near machine precision).
    """
    edges = np.sort(np.mod(np.asarray(breaks, dtype=float), TWO_PI))
    edges = np.r_[0.0, TWO_PI] if edges.size == 0 else np.r_[edges, edges[0] + TWO_PI]
    x, w = np.polynomial.legendre.leggauss(nodes)
    total = 0.0
    for lo, hi in itertools.pairwise(edges):
        cuts = np.linspace(lo, hi, pieces + 1)
        mid, half = (cuts[1:] + cuts[:-1]) / 2, (cuts[1:] - cuts[:-1]) / 2
        t = (mid[:, None] + half[:, None] * x[None, :]).ravel()
        weight = (half[:, None] * w[None, :]).ravel()
        total += float(np.sum(weight * (b_of(t) ** 2 - d1b_of(t) ** 2)))
    return total / 2
