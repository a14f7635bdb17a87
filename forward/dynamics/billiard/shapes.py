"""The outlines the rigid-body simulation knows: a vertex list (:class:`PolygonShape`) or an ellipse
(:class:`EllipseShape`), in the body frame (centre of mass at the origin, body axis along +x).

A shape gives what :mod:`.rigidbody` needs to find a collision without ever forming a wall function:
the *pieces* of the outline that can touch a flat wall (a vertex, or the whole smooth ellipse), the
lab height of each piece's extreme point and its derivative in the orientation ψ, a bound ``A_k`` of
that height's second derivative, and the body-frame contact point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidOutline
from ...validation import check_positive

__all__ = ["EllipseShape", "PolygonShape"]


@dataclass(frozen=True, repr=False)
class PolygonShape:
    """A body given by its vertices (body frame, centre of mass at the origin, axis along +x).

    Only the vertices can touch a flat wall, so the convex hull is implicit: a
    non-convex vertex list behaves like its hull.  Two vertices make a stick.

    Attributes
    ----------
    vertices : ndarray, shape (n, 2)
        Vertex positions relative to the centre of mass (physical lengths).

    Examples
    --------
    >>> from coinwall.forward import PolygonShape
    >>> PolygonShape.stick(1.0)                                # two vertices: a stick of half-length 1
    PolygonShape(2 vertices, radius=1)
    """

    vertices: np.ndarray

    def __post_init__(self):
        pts = np.array(self.vertices, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 1:
            raise InvalidOutline(f"`vertices` must be (x, y) pairs, got an array of shape {pts.shape}")
        if not np.all(np.isfinite(pts)):
            raise InvalidOutline("`vertices` must be finite")
        pts.setflags(write=False)
        object.__setattr__(self, "vertices", pts)

    @classmethod
    def stick(cls, half_length: float = 1.0) -> PolygonShape:
        """The paper's stick: end points ``(±L, 0)``; its wall is ``(L/κ)|cos θ|`` (paper eq. 5)."""
        L = check_positive("half_length", half_length, error=InvalidOutline)
        return cls(np.array([[-L, 0.0], [L, 0.0]]))

    @property
    def curvature_bounds(self) -> np.ndarray:
        """``A_k ≥ |Y_k''(ψ)|`` for every piece of one wall: a vertex's lab height is ``|p| sin(ψ + β)``."""
        return np.hypot(self.vertices[:, 0], self.vertices[:, 1])

    @property
    def radius(self) -> float:
        """Largest distance of the outline from the centre of mass."""
        return float(np.max(self.curvature_bounds))

    def pieces(self, psi: float):
        """Lab heights ``Y_k`` (relative to the centre of mass) and ``dY_k/dψ`` of the vertices.

        The same pieces serve both walls (floor: the minimum, ceiling: the maximum).
        ``dY_k/dψ`` is the lab x of the vertex, i.e. the lever arm of a vertical impulse.
        """
        c, s = math.cos(psi), math.sin(psi)
        x, y = self.vertices[:, 0], self.vertices[:, 1]
        heights = s * x + c * y
        slopes = c * x - s * y
        return heights, slopes, heights, slopes

    def contact_point(self, piece: int, psi: float, side: int) -> np.ndarray:
        """Body-frame contact point of ``piece`` (a vertex) at orientation ``psi``."""
        return self.vertices[piece].copy()

    @property
    def uniform_kappa(self) -> float:
        """Radius of gyration if the body were uniform: a rod (2 vertices) or a lamina (≥ 3).

        Rod of half-length L: κ² = L²/3.  Lamina: polar moment about the origin
        (triangle fan, exact) over the area.  Meaningful only if the uniform
        body's centroid is the origin; it is not checked here.
        """
        pts = self.vertices
        if len(pts) == 2:
            return float(np.hypot(*(pts[1] - pts[0])) / 2 / math.sqrt(3.0))
        x, y = pts[:, 0], pts[:, 1]
        xn, yn = np.roll(x, -1), np.roll(y, -1)
        cross = x * yn - xn * y
        area = 0.5 * np.sum(cross)
        # polar moment of a polygon about the origin (shoelace form of ∫(x²+y²) dA)
        polar = np.sum(cross * (x * x + x * xn + xn * xn + y * y + y * yn + yn * yn)) / 12.0
        return float(math.sqrt(polar / area))

    @safe_repr
    def __repr__(self) -> str:
        return f"PolygonShape({len(self.vertices)} vertices, radius={self.radius:.6g})"


@dataclass(frozen=True, repr=False)
class EllipseShape:
    """An elliptical body: semi-axis ``a`` along the body axis, ``b`` across it.

    The ellipse's geometric centre sits at ``centre`` relative to the centre of
    mass (body frame); a non-zero centre off both axes (a non-uniform density)
    gives a smooth body with no symmetry axis.  The paper's ellipse
    ``x² + (1+ε)y² = 1`` is ``a = 1``, ``b = 1/sqrt(1+ε)``, centre 0.

    Attributes
    ----------
    a, b : float
        Semi-axes (physical lengths, positive).
    centre : tuple of float
        Geometric centre relative to the centre of mass.

    Examples
    --------
    >>> from coinwall.forward import EllipseShape
    >>> EllipseShape(1.0, 0.5)
    EllipseShape(a=1, b=0.5, centre=(0, 0))
    """

    a: float
    b: float
    centre: tuple = (0.0, 0.0)

    def __post_init__(self):
        for name in ("a", "b"):  # the semi-axes
            object.__setattr__(self, name, check_positive(name, getattr(self, name), error=InvalidOutline))
        try:
            cx, cy = (float(v) for v in self.centre)
        except (TypeError, ValueError):
            raise InvalidOutline(f"`centre` must be an (x, y) pair, got {self.centre!r}") from None
        if not (math.isfinite(cx) and math.isfinite(cy)):
            raise InvalidOutline(f"`centre` must be finite, got {(cx, cy)}")
        object.__setattr__(self, "centre", (cx, cy))

    @property
    def curvature_bounds(self) -> np.ndarray:
        """Bound on ``|Y''|``: ``|h_E''| = |ρ − h_E| ≤ max(a,b)²/min(a,b)`` plus ``|centre|`` for the shift.

        (ρ ∈ [min²/max, max²/min] is the ellipse's radius of curvature, h_E ∈ [min, max].)
        """
        big, small = max(self.a, self.b), min(self.a, self.b)
        bound = big * big / small + math.hypot(*self.centre)
        return np.array([bound])  # one smooth piece per wall

    @property
    def radius(self) -> float:
        """Largest distance of the outline from the centre of mass (an upper bound)."""
        return max(self.a, self.b) + math.hypot(*self.centre)

    def _extreme(self, psi: float, side: int):
        # The outline point c + (a cos s, b sin s) has lab height sinψ·x + cosψ·y; it is
        # extreme where (cos s, sin s) ∝ ∓(a sinψ, b cosψ): a closed form, no search.
        c, s = math.cos(psi), math.sin(psi)
        spread = math.hypot(self.a * s, self.b * c)
        sign = -1.0 if side == 0 else 1.0
        qx = self.centre[0] + sign * self.a * self.a * s / spread
        qy = self.centre[1] + sign * self.b * self.b * c / spread
        return qx, qy, s * qx + c * qy, c * qx - s * qy

    def pieces(self, psi: float):
        """Lab height and ``d/dψ`` of the lowest point (floor piece) and the highest point (ceiling piece)."""
        _, _, low, low_slope = self._extreme(psi, 0)
        _, _, high, high_slope = self._extreme(psi, 1)
        return np.array([low]), np.array([low_slope]), np.array([high]), np.array([high_slope])

    def contact_point(self, piece: int, psi: float, side: int) -> np.ndarray:
        """Body-frame contact point: the lowest (``side=0``) or highest (``side=1``) point of the outline."""
        qx, qy, _, _ = self._extreme(psi, side)
        return np.array([qx, qy])

    @property
    def uniform_kappa(self) -> float:
        """κ of a uniform elliptical lamina, ``sqrt((a² + b²)/4)`` (its centroid is the centre)."""
        return math.sqrt((self.a**2 + self.b**2) / 4.0)

    @safe_repr
    def __repr__(self) -> str:
        return f"EllipseShape(a={self.a:.6g}, b={self.b:.6g}, centre=({self.centre[0]:.6g}, {self.centre[1]:.6g}))"
