"""Mass properties of a lamina with a body outline: mass, centre of mass, radius of gyration κ.

Two routes, which the tests hold to each other and to closed forms:

* :func:`outline_moments` — the uniform lamina, exact for the piecewise cubic
  Bézier outline: by Green's theorem ``A = ½∮(x dy − y dx)``,
  ``∫x dA = ½∮x² dy``, ``∫y dA = −½∮y² dx``, ``∫(x² + y²) dA = ⅓∮(x³ dy − y³ dx)``;
  on a cubic segment the integrands are polynomials of degree ≤ 11 in the
  curve parameter, so 8-point Gauss–Legendre is exact.
* :func:`mass_properties` — any density ``ρ(x, y)`` given as an expression,
  integrated with scikit-fem over a triangulation of the outline (Delaunay
  of boundary points and an interior grid; the outline is convex so the
  Delaunay triangles tile it).  The domain is the inscribed polygon, so the
  error is O(N⁻²) in the number N of boundary points (measured in
  docs/artifacts.md); the density is integrated with a degree-``intorder``
  rule on every triangle.

Coordinates are body units (κ of the wall); nothing here assumes the
centre of mass is at the origin — that is what is computed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .display import safe_repr
from .errors import InvalidArgument, InvalidExpression, InvalidOutline, InvalidParameter

__all__ = ["DENSITY_VARIABLES", "MAX_DENSITY", "SINGULAR_EXPONENT", "MassProperties", "check_integrable", "mass_properties", "outline_moments",
           "parse_density"]

#: names a density expression may use: Cartesian body coordinates and the distance from the origin
DENSITY_VARIABLES = ("x", "y", "r")
_GL8 = np.polynomial.legendre.leggauss(8)
_BLOCK = 4096


@dataclass(frozen=True, repr=False)
class MassProperties:
    """Mass properties of a lamina.

    Attributes
    ----------
    mass : float
        ``∫ρ dA`` (area for the uniform lamina, ρ = 1).
    area : float
        Area of the integration domain.
    centre : tuple of float
        Centre of mass ``∫ρ x dA / mass``.
    kappa : float
        Radius of gyration about the centre of mass, ``sqrt(∫ρ|x − c|² dA / mass)``.
    kappa_origin : float
        Radius of gyration about the origin.
    polar_moment : float
        ``∫ρ|x − c|² dA`` about the centre of mass.
    density : str
        The density expression (``"1"`` for the uniform lamina).
    method : str
        ``"exact"`` (Green's theorem on the Bézier outline) or ``"fem"`` (scikit-fem).
    elements : int
        Number of triangles (0 for ``"exact"``).
    min_density : float
        Smallest density found at the quadrature points and mesh vertices.

    Examples
    --------
    >>> from coinwall import Outline, mass_properties
    >>> props = mass_properties(Outline.from_polygon([[1, 1], [-1, 1], [-1, -1], [1, -1]]))
    >>> props.density, props.method, round(props.polar_moment, 6)     # ∫|x|² dA = 8/3
    ('1', 'fem', 2.666667)
    """

    mass: float
    area: float
    centre: tuple
    kappa: float
    kappa_origin: float
    polar_moment: float
    density: str = "1"
    method: str = "exact"
    elements: int = 0
    min_density: float = 1.0

    @property
    def centre_offset(self) -> float:
        """Distance of the centre of mass from the origin."""
        return float(math.hypot(*self.centre))

    def to_dict(self) -> dict:
        return {"mass": self.mass, "area": self.area, "centre": list(self.centre), "kappa": self.kappa,
                "kappa_origin": self.kappa_origin, "polar_moment": self.polar_moment, "density": self.density,
                "method": self.method, "elements": self.elements, "min_density": self.min_density}

    @safe_repr
    def __repr__(self) -> str:
        return (f"MassProperties(mass={self.mass:.6g}, centre=({self.centre[0]:.3g}, {self.centre[1]:.3g}), "
                f"kappa={self.kappa:.6g}, density={self.density!r}, method={self.method!r})")


#: largest density value integrated (see :func:`mass_properties`)
MAX_DENSITY = 1e100
#: a density growing faster than d^-SINGULAR_EXPONENT near a point of the body is refused even when integrable
#: (see :func:`check_integrable`)
SINGULAR_EXPONENT = 0.25


def _from_moments(mass, area, first, second, density, method, elements=0, min_density=1.0):
    if not (mass > 0 and math.isfinite(mass)):
        raise InvalidOutline(f"the body has no mass (mass = {mass:.3g}): a lamina needs a positive area and density")
    centre = (float(first[0] / mass), float(first[1] / mass))
    about_origin = float(second)
    polar = about_origin - mass * (centre[0] ** 2 + centre[1] ** 2)
    return MassProperties(float(mass), float(area), centre, math.sqrt(max(polar, 0.0) / mass),
                          math.sqrt(max(about_origin, 0.0) / mass), float(polar), density, method,
                          int(elements), float(min_density))


def outline_moments(outline) -> MassProperties:
    """Uniform lamina (ρ = 1) bounded by ``outline``, exact for the Bézier curve (see module docstring).

    Parameters
    ----------
    outline : Outline

    Returns
    -------
    MassProperties
        ``method == "exact"`` (Green's theorem).

    Examples
    --------
    >>> from coinwall import Outline
    >>> from coinwall.forward import outline_moments
    >>> square = Outline.from_polygon([[1, 1], [-1, 1], [-1, -1], [1, -1]])
    >>> props = outline_moments(square)
    >>> round(props.mass, 12), round(props.kappa ** 2, 12)       # area 4, κ² = 2/3
    (4.0, 0.666666666667)
    """
    p0, p1, p2, p3 = outline._segments
    x, w = _GL8
    s, w = (x + 1) / 2, w / 2
    u = 1 - s
    pts = sum(b[None, :, None] * p[:, None, :] for b, p in zip((u**3, 3 * u * u * s, 3 * u * s * s, s**3),
                                                              (p0, p1, p2, p3)))
    der = sum(b[None, :, None] * p[:, None, :] for b, p in zip((3 * u * u, 6 * u * s, 3 * s * s),
                                                              (p1 - p0, p2 - p1, p3 - p2)))
    X, Y, dX, dY = pts[..., 0], pts[..., 1], der[..., 0], der[..., 1]
    area = 0.5 * np.sum((X * dY - Y * dX) * w)
    first = (0.5 * np.sum(X * X * dY * w), -0.5 * np.sum(Y * Y * dX * w))
    second = np.sum((X**3 * dY - Y**3 * dX) * w) / 3
    return _from_moments(area, area, first, second, "1", "exact")


def parse_density(text: str, params=None):
    """A density expression in ``x``, ``y`` (and ``r = sqrt(x² + y²)``) → vectorised function ρ(x, y).

    Parsed with the whitelist of :mod:`forward.expression` (never evaluated as
    Python); the same numbers, operators and functions as a wall expression.

    Parameters
    ----------
    text : str
        ρ(x, y) as an expression in ``x``, ``y`` and ``r``.
    params : mapping, optional
        Values of its named parameters.

    Returns
    -------
    callable
        ``rho(x, y)`` on arrays.

    Raises
    ------
    InvalidExpression, InvalidParameter
        For an expression that does not parse or a missing or bad parameter.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward import parse_density
    >>> rho = parse_density("1 + a*r**2", {"a": 1.0})
    >>> rho(np.array([0.0, 3.0]), np.array([0.0, 4.0])).tolist()
    [1.0, 26.0]
    """
    import casadi as ca

    from . import expression as ex

    if not isinstance(text, str) or not text.strip():
        raise InvalidExpression(f"density {text!r} is empty; give e.g. '1 + 4*r**8'")
    values = {ex._check_name(k): ex._check_value(k, v) for k, v in (params or {}).items()}
    clash = sorted(set(values) & set(DENSITY_VARIABLES))
    if clash:
        raise InvalidParameter(f"parameter {clash[0]!r} is a density variable; rename it")
    ex.check_ascii(text, "density")  # before strip(), which would drop a non-ASCII space (see check_ascii)
    source = text.strip()
    ex.check_one_line(source, "density")
    if len(source) > ex.MAX_LENGTH:
        raise InvalidExpression(f"density expression is too long ({len(source)} characters, at most {ex.MAX_LENGTH})")
    tree = ex._parse_tree(text, source)
    xs, ys = ca.SX.sym("x"), ca.SX.sym("y")
    symbols = {"x": xs, "y": ys, "r": ca.sqrt(xs * xs + ys * ys)}

    class _Plane(ex._Translator):
        # the wall translator knows one variable, t; a density has x, y and r instead
        def name(self, ident):
            if ident in symbols:
                return symbols[ident]
            if ident in ("t", "theta"):
                self.fail(f"{ident!r} is not a density variable; use x, y or r")
            return super().name(ident)

    walker = _Plane(ca, source, xs, values)
    try:
        expr = walker.visit(tree.body)
    except InvalidExpression as exc:
        raise InvalidExpression(str(exc).replace("expression ", "density ", 1)) from None
    unused = sorted(set(values) - walker.used)
    if unused:
        raise InvalidParameter(f"parameter {unused[0]!r} is not used in the density {source!r}")
    single = ca.Function("rho", [xs, ys], [expr])
    mapped = single.map(_BLOCK)

    def rho(x, y):
        x = np.ascontiguousarray(x, float)
        y = np.broadcast_to(np.asarray(y, float), x.shape)
        flat_x, flat_y = x.ravel(), np.ascontiguousarray(y).ravel()
        out = np.empty(flat_x.size)
        for start in range(0, flat_x.size, _BLOCK):
            cx, cy = flat_x[start:start + _BLOCK], flat_y[start:start + _BLOCK]
            m = cx.size
            if m < _BLOCK:
                cx = np.concatenate([cx, np.zeros(_BLOCK - m)])
                cy = np.concatenate([cy, np.zeros(_BLOCK - m)])
            out[start:start + m] = np.asarray(mapped(cx.reshape(1, -1), cy.reshape(1, -1))).ravel()[:m]
        return out.reshape(x.shape)

    rho.text = source
    return rho


def check_integrable(rho, density, polygon, start) -> None:
    """Refuse a density whose mass is infinite: one that grows too fast near some point of the body.

    What is checked: from ``start`` (where the sampled density is largest) the density is followed uphill,
    zooming in by a factor 3 at a time down to 1e-9 of the body's size, to the point ``c`` it grows towards.
    Then its growth ``ρ ~ d^(−p)`` with the distance ``d`` from ``c`` is measured on circles of radius
    1e-3 … 1e-7 of the body's size (64 directions, inside the body).  A density that grows like that around
    an isolated point has a finite mass only for ``p < 2`` (``∫ d^(−p) d dd``); across a singular curve (the
    largest value on a circle keeps growing as the directions close in on one, ``1/|x|``) only for ``p < 1``.
    A density bounded near ``c`` has ``p ≈ 0``.  Exponents within 0.02 of the limit count as not integrable.
    A density with ``p`` above :data:`SINGULAR_EXPONENT` that is integrable is refused too: its mass is
    finite, but quadrature at fixed points misses the spike (``r**-1.9`` gave half its mass).  A logarithmic
    growth (``-log(r)``) passes.  Singularities outside the body do not matter.

    Raises
    ------
    InvalidArgument
        Naming the point, the exponent and the limit.
    """
    polygon = np.asarray(polygon, float)
    size = float(np.max(np.ptp(polygon, axis=0)))
    a, b = polygon, np.roll(polygon, -1, axis=0)
    sign = np.sign(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))  # +1 for a counter-clockwise outline

    edge = b - a
    length = np.hypot(edge[:, 0], edge[:, 1])
    real = length > 0  # (a repeated node's edge has cross product 0: it never decides)

    def inside(p):
        # a point nearer to the points' mean c than c is to every edge's line is inside by the test below too (each
        # cross product is the edge's length times the point's distance from its line, at least that distance minus
        # |p − c| > 0): only the other points are tested edge by edge (a ring of 4001 points, 2048 edges: 0.4 s)
        c = p.mean(axis=0) if p.size else np.zeros(2)
        reach = np.min(sign * (edge[real, 0] * (c[1] - a[real, 1]) - edge[real, 1] * (c[0] - a[real, 0]))
                       / length[real], initial=np.inf)
        result = np.hypot(p[:, 0] - c[0], p[:, 1] - c[1]) < 0.5 * reach
        rest = ~result
        q = p[rest]
        cross = edge[None, :, 0] * (q[:, None, 1] - a[None, :, 1]) - edge[None, :, 1] * (q[:, None, 0] - a[None, :, 0])
        result[rest] = np.all(sign * cross >= -1e-12 * size * size, axis=1)
        return result

    def values(p):
        with np.errstate(all="ignore"):
            v = rho(p[:, 0], p[:, 1])
        return np.where(np.isnan(v), -np.inf, np.where(np.isinf(v), np.inf, v))

    centre, half = np.asarray(start, float), size / 10.0
    offsets = np.stack(np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 9)), axis=-1).reshape(-1, 2)
    while half > 1e-9 * size:
        trial = centre + half * offsets
        trial = trial[inside(trial)]
        v = values(trial)
        if trial.size and np.max(v) > -np.inf:
            centre = trial[int(np.argmax(v))]
        half /= 3.0
    angles = np.linspace(0.0, 2 * math.pi, 64, endpoint=False)
    ring = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    radii = size * 10.0 ** -np.arange(3, 8)
    typical, lowest, curve = [], [], False
    for d in radii:
        pts = centre + d * ring
        v = values(pts[inside(pts)])
        v = v[v > -np.inf]
        if not v.size:
            return
        typical.append(float(np.median(v)))
        lowest.append(float(np.min(v)))
        if d == radii[0]:  # across a curve the largest value keeps growing as the directions close in on it
            k = int(np.argmax(v))
            fine = np.linspace(angles[k] - 0.1, angles[k] + 0.1, 4001)
            near = centre + d * np.stack([np.cos(fine), np.sin(fine)], axis=1)
            w = values(near[inside(near)])
            curve = bool(w.size) and np.max(w) > 1e3 * max(np.median(v), 1e-300) and np.max(w) > 0
    with np.errstate(all="ignore"):
        span = math.log(radii[0] / radii[-1])
        grow = (np.log(typical[-1]) - np.log(typical[0])) / span if typical[0] > 0 else 0.0
        across = (np.log(lowest[-1]) - np.log(lowest[0])) / span if lowest[0] > 0 else 0.0
    p, limit, place, shape = (across, 1.0, "across a curve through", "across a curve") if curve else \
        (grow, 2.0, "around", "around a point")
    where = f"{place} (x, y) = ({centre[0]:.4g}, {centre[1]:.4g})"
    if not math.isfinite(typical[-1]) or not math.isfinite(lowest[-1]) or not math.isfinite(p) or p > limit - 0.02:
        shown = "without bound" if not (math.isfinite(p) and math.isfinite(typical[-1])) else f"like d^-{p:.3g}"
        raise InvalidArgument(f"density {density!r} has no finite mass: {where} it grows {shown} (d the distance "
                              f"from there), and a density growing like d^-p {shape} is integrable only for "
                              f"p < {limit:g}")
    if p > SINGULAR_EXPONENT:
        raise InvalidArgument(f"density {density!r} is singular (or nearly) {where}: it grows like d^-{p:.3g} (d the distance "
                              f"from there); its mass is finite, but the quadrature (points at fixed places) cannot "
                              "integrate a singular density to any stated accuracy: smooth it (e.g. r**2 + 1e-4 "
                              "for r**2 under a power)")


def _triangulation(outline, boundary, interior):
    """Points and triangles: ``boundary`` points along the curve, an interior grid, Delaunay."""
    from scipy.spatial import Delaunay

    per_segment = max(1, math.ceil(boundary / len(outline.nodes)))
    edge = outline.polygon(per_segment) if per_segment > 1 else outline.nodes.copy()
    keep = np.r_[True, np.hypot(*np.diff(edge, axis=0).T) > 0]
    edge = edge[keep]
    lo, hi = edge.min(axis=0), edge.max(axis=0)
    span = float(np.max(hi - lo))
    if span <= 0 or outline_moments(outline).area <= 1e-14 * span * span:
        raise InvalidOutline("the outline encloses no area (a segment or a point): a lamina needs an area")
    spacing = span / interior
    gx = np.arange(lo[0] + spacing / 2, hi[0], spacing)
    gy = np.arange(lo[1] + spacing / 2, hi[1], spacing)
    grid = np.stack(np.meshgrid(gx, gy), axis=-1).reshape(-1, 2)
    # inside the convex polygon, at least half a spacing from its edges (no slivers at the boundary)
    a, b = edge, np.roll(edge, -1, axis=0)
    tangent = b - a
    length = np.hypot(*tangent.T)
    ok = length > 0
    normal = np.stack([tangent[ok, 1], -tangent[ok, 0]], axis=1) / length[ok, None]  # outward (CCW outline)
    dist = np.einsum("pij,ij->pi", grid[:, None, :] - a[None, ok, :], normal)
    grid = grid[np.all(dist < -0.5 * spacing, axis=1)]
    points = np.vstack([edge, grid])
    tri = Delaunay(points)
    simplices = tri.simplices
    # drop the (rare) flat triangles that Qhull leaves along straight edges
    p = points[simplices]
    area = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    return points, simplices[area > 1e-15 * span * span]


def mass_properties(outline, density=None, params=None, *, boundary: int = 2048, interior: int = 48,
                    intorder: int = 8) -> MassProperties:
    """Mass, centre of mass and radius of gyration of the lamina inside ``outline`` (scikit-fem).

    Parameters
    ----------
    outline : forward.Outline
        A convex outline (body units).
    density : str or None
        ``ρ(x, y)`` as an expression in ``x``, ``y``, ``r`` (e.g. ``"1 + 4*r**8"``);
        ``None`` for the uniform lamina.
    params : mapping, optional
        Parameters of the density expression.
    boundary : int
        Number of points along the outline (the domain is their polygon).
    interior : int
        Interior grid points per diameter.
    intorder : int
        Degree of the quadrature rule on every triangle.

    Returns
    -------
    MassProperties
        ``method == "fem"``: computed on a triangle mesh of the outline's polygon.

    Examples
    --------
    The square of side 2: area 4 and κ² = (1 + 1)/3; a density ``1 + x²`` puts more mass at the sides.

    >>> from coinwall import Outline, mass_properties
    >>> square = Outline.from_polygon([[1, 1], [-1, 1], [-1, -1], [1, -1]])
    >>> uniform = mass_properties(square)
    >>> round(uniform.mass, 9), round(uniform.kappa, 6)
    (4.0, 0.816497)
    >>> heavy = mass_properties(square, "1 + x**2")
    >>> round(heavy.mass, 6), round(heavy.kappa, 6)               # mass 4 + 4/3
    (5.333333, 0.856349)

    Raises
    ------
    InvalidArgument
        A density that is negative or not finite somewhere in the body, or whose mass is infinite (it grows too
        fast near a point or a curve of the body: :func:`check_integrable`).
    InvalidOutline
        An outline without area.
    """
    from skfem import Basis, ElementTriP1, Functional, MeshTri

    for name, value, least in (("boundary", boundary, 8), ("interior", interior, 2), ("intorder", intorder, 1)):
        if not isinstance(value, int) or value < least:
            raise InvalidArgument(f"{name} must be an integer >= {least}, got {value!r}")
    rho = parse_density(density, params) if density is not None else None
    points, triangles = _triangulation(outline, boundary, interior)
    mesh = MeshTri(points.T.copy(), triangles.T.copy())
    basis = Basis(mesh, ElementTriP1(), intorder=intorder)
    qx, qy = basis.mapping.F(basis.quadrature[0])
    if rho is None:
        values = np.ones_like(qx)
        vertex_values = np.ones(len(points))
    else:
        values = rho(qx, qy)
        vertex_values = rho(points[:, 0], points[:, 1])
    both = np.concatenate([values.ravel(), vertex_values])
    if not np.all(np.isfinite(both)):
        k = int(np.flatnonzero(~np.isfinite(values.ravel()))[0]) if not np.all(np.isfinite(values)) else 0
        raise InvalidArgument(f"density {density!r} is not finite at (x, y) = "
                              f"({qx.ravel()[k]:.4g}, {qy.ravel()[k]:.4g}); it must be finite in the body")
    if np.max(both) > MAX_DENSITY:
        # the mass and the moments (density × coordinates², summed over many points) would overflow a double
        raise InvalidArgument(f"density {density!r} reaches {np.max(both):.3g} in the body; coinwall integrates "
                              f"densities up to {MAX_DENSITY:g} (only their ratios matter: scale it down)")
    if np.min(both) < 0:
        if np.min(values) <= np.min(vertex_values):
            k = int(np.argmin(values))
            where, val = (qx.ravel()[k], qy.ravel()[k]), values.ravel()[k]
        else:
            k = int(np.argmin(vertex_values))
            where, val = tuple(points[k]), vertex_values[k]
        raise InvalidArgument(f"density {density!r} is negative in the body: {val:.4g} at (x, y) = "
                              f"({where[0]:.4g}, {where[1]:.4g}); a mass density must be >= 0")

    if rho is not None:
        check_integrable(rho, density, outline.polygon(8), points[int(np.argmax(vertex_values))]
                         if np.max(vertex_values) >= np.max(values) else
                         np.array([qx.ravel()[int(np.argmax(values))], qy.ravel()[int(np.argmax(values))]]))

    @Functional
    def weighted(w):
        return w["rho"] * w["g"]

    def integral(g):
        return float(weighted.assemble(basis, rho=values, g=g))

    mass = integral(np.ones_like(qx))
    area = float(Functional(lambda w: 1.0 + 0 * w.x[0]).assemble(basis))
    first = (integral(qx), integral(qy))
    second = integral(qx * qx + qy * qy)
    return _from_moments(mass, area, first, second, density or "1", "fem", len(triangles), float(np.min(both)))
