"""Bodies without a symmetry axis (paper, section II.B and Conclusions: "strongly asymmetric rigid
bodies strike us as being of particular interest").

For these the upper wall is ``H − b(θ + π)``, not a mirror image of the lower
one — they exercise the convention (θ counter-clockwise in the body frame from
the body axis, i.e. clockwise from the downward wall normal to the axis).

* ``triangle``: a scalene obtuse triangle with its centroid at the origin;
  ``b(θ) = max_i p_i·(cos θ, sin θ)`` (three kinks; b_c = 0; the body at b0 = 0 is
  the triangle itself).
* ``egg``: a smooth wall ``1 + 0.06 cos 2θ + 0.04 sin 3θ + 0.05 cos θ`` with no
  symmetry axis (the cos 2θ and sin 3θ terms have incompatible axes).
"""

import numpy as np

from coinwall.forward import Outline, Wall

from .catalog import Case, Reference

__all__ = ["TRIANGLE_VERTICES", "triangle_wall", "triangle_outline", "EGG_WALL", "egg_wall", "CASES"]

_RAW = np.array([[1.3, 0.2], [-0.7, 0.9], [-0.4, -0.8]])
#: Vertices of the asymmetric triangle, centroid at the origin.
TRIANGLE_VERTICES = _RAW - _RAW.mean(axis=0)

EGG_WALL = "1 + 0.06*cos(2*t) + 0.04*sin(3*t) + 0.05*cos(t)"


def _triangle_expression(points=TRIANGLE_VERTICES):
    terms = [f"({float(x)!r})*cos(t) + ({float(y)!r})*sin(t)" for x, y in points]
    return f"max({terms[0]}, max({terms[1]}, {terms[2]}))"


def triangle_wall(points=TRIANGLE_VERTICES) -> Wall:
    """b(θ) = max_i p_i·(cos θ, sin θ)."""
    return Wall.from_expression(_triangle_expression(points), {})


def triangle_outline(points=TRIANGLE_VERTICES) -> Outline:
    return Outline.from_polygon(points)


def egg_wall() -> Wall:
    return Wall.from_expression(EGG_WALL, {})


def _triangle_area(p):
    (ax, ay), (bx, by) = p[1] - p[0], p[2] - p[0]
    return 0.5 * abs(ax * by - ay * bx)


CASES = (
    Case("triangle", "scalene triangle, centroid at the origin (no symmetry axis)", "coinwall; paper section II.B",
         triangle_wall, 0.0, triangle_outline, None,
         (Reference("b_c", 0.0, "polygon: b + b'' = 0 between the kinks"),
          Reference("vertices", TRIANGLE_VERTICES.tolist(), "construction"),
          Reference("area", _triangle_area(TRIANGLE_VERTICES), "½|cross product|")),
         _triangle_expression(), {}),
    Case("egg", "smooth egg without symmetry axis", "coinwall; paper section II.B", egg_wall, 0.0, None, None,
         (Reference("perimeter", 2 * np.pi, "Cauchy: 2π × mean of b"),),
         EGG_WALL, {}),
)
