"""A wall with fewer than four extrema (paper section IV: "b(θ) must have at least four extrema to
represent a physical wall shape … the four-extremum requirement can always be met by mapping
θ → θ/2").

``b(θ) = 1 + 0.3 cos θ`` has one maximum and one minimum.  It is nevertheless
the support function of a convex body: ``h + h'' = 1 > 0``, and the body is the
unit disc whose centre is 0.3 away from the centre of mass (a disc with a
non-uniform density).  The four-vertex theorem concerns extrema of the
*curvature* of a closed convex curve, not of its support function, so the
paper's requirement does not apply to walls (see ``coinwall verify``).  Its
remedy is problematic too: ``b(θ/2)`` of a 2π-periodic b is 4π-periodic, not a
wall; ``b(2θ)`` (π-periodic, twice the extrema) is presumably what is meant.
"""

from coinwall.forward import Wall

from .catalog import Case, Reference

__all__ = ["FEW_EXTREMA_WALL", "few_extrema_wall", "CASES"]

FEW_EXTREMA_WALL = "1 + c*cos(t)"


def few_extrema_wall(c: float = 0.3) -> Wall:
    return Wall.from_expression(FEW_EXTREMA_WALL, {"c": c})


CASES = (
    Case("two-extrema", "wall 1 + 0.3 cos θ: two extrema, yet a disc (off-centre centre of mass)",
         "paper section IV (four-extremum remark)", lambda: few_extrema_wall(0.3), 0.0, None, None,
         (Reference("extrema", 2, "cos θ has one maximum and one minimum"),
          Reference("body", "unit disc centred at (0.3, 0)", "h = 1 + c cos θ is the support function of that disc"),
          Reference("b_c", -1.0, "h + h'' = 1")),
         FEW_EXTREMA_WALL, {"c": 0.3}),
)
