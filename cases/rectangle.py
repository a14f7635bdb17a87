"""A rectangle with half-sides a (along the body axis) and c (paper, Conclusions: "rectangles … may
warrant investigation").

Its support function about the centre is ``h(θ) = a|cos θ| + c|sin θ|``: the
maximum of ``(±a, ±c)·(cos θ, sin θ)``.  It has four kinks (θ = 0, π/2, π,
3π/2) with jumps ``2c, 2a, 2c, 2a`` — the four edges — and ``b + b'' = 0``
between them, so ``b_c = 0``: at ``b0 = 0`` the body is the rectangle itself,
for ``b0 > 0`` a rounded rectangle.  Uniform density: ``κ² = (a² + c²)/3``.
"""

import math

from coinwall.forward import Outline, Wall

from .catalog import Case, Reference

__all__ = ["RECTANGLE_WALL", "rectangle_wall", "rectangle_outline", "CASES"]

RECTANGLE_WALL = "a*abs(cos(t)) + c*abs(sin(t))"


def rectangle_wall(a: float = 1.0, c: float = 0.5) -> Wall:
    """Support function of the rectangle [−a, a] × [−c, c]."""
    return Wall.from_expression(RECTANGLE_WALL, {"a": a, "c": c})


def rectangle_outline(a: float = 1.0, c: float = 0.5) -> Outline:
    return Outline.from_polygon([[a, -c], [a, c], [-a, c], [-a, -c]])


CASES = (
    Case("rectangle", "rectangle 2 × 1 (half-sides a = 1, c = 1/2)", "paper, Conclusions; h = a|cos θ| + c|sin θ|",
         lambda: rectangle_wall(1.0, 0.5), 0.0, lambda: rectangle_outline(1.0, 0.5), None,
         (Reference("b_c", 0.0, "b + b'' = 0 between the four kinks"),
          Reference("area", 2.0, "4 a c"),
          Reference("perimeter", 6.0, "4(a + c)"),
          Reference("kappa_uniform", math.sqrt((1.0 + 0.25) / 3), "κ² = (a² + c²)/3")),
         RECTANGLE_WALL, {"a": 1.0, "c": 0.5}),
)
