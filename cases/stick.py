"""The stick of half-length L (paper section II.A, eq. 5).

A uniform rod of half-length L pivoting about its midpoint has the lower
wall ``b(θ) = (L/κ)|cos θ|`` and the upper wall ``H − (L/κ)|cos θ|``
(eq. 5).  In units of κ the wall is ``L |cos θ|``.  As a support function it
is that of the segment from (−L, 0) to (L, 0): ``b + b'' = 0`` away from the
kinks at θ = π/2 and 3π/2, where ``b'`` jumps by ``2L`` (the segment's length,
a straight "edge" of the body).  Hence ``b_c = 0``: at ``b0 = 0`` the body is
the segment itself (critical), for ``b0 > 0`` a stadium (the segment thickened
by ``b0``), for ``b0 < 0`` the centre of mass would be outside.

For a uniform rod ``κ² = L²/3``, so the physical wall is ``√3 |cos θ|`` in units
of κ; the paper keeps ``L/κ`` general.
"""

import math

from coinwall.forward import Outline, Wall

from .catalog import Case, Reference

__all__ = ["STICK_WALL", "stick_wall", "stick_outline", "CASES"]

STICK_WALL = "L*abs(cos(t))"


def stick_wall(length_over_kappa: float = 1.0) -> Wall:
    """Wall of a stick whose half-length is ``length_over_kappa`` radii of gyration (eq. 5).

    Parameters
    ----------
    length_over_kappa : float
        The half-length L in units of κ (a uniform rod has L = √3 κ).

    Returns
    -------
    Wall
        ``L |cos θ|``, with its two kinks.

    Examples
    --------
    >>> from coinwall.cases import stick_wall
    >>> stick_wall()
    Wall('L*abs(cos(t))' [L=1], 2 kinks)
    """
    return Wall.from_expression(STICK_WALL, {"L": length_over_kappa})


def stick_outline(length_over_kappa: float = 1.0) -> Outline:
    """The segment body, from (−L, 0) to (L, 0).

    Parameters
    ----------
    length_over_kappa : float
        The half-length L in units of κ.

    Returns
    -------
    Outline
        Two straight segments, there and back (area 0).

    Examples
    --------
    >>> from coinwall.cases import stick_outline
    >>> stick_outline(2.0).perimeter
    8.0
    """
    L = length_over_kappa
    return Outline.from_polygon([[-L, 0.0], [L, 0.0]])


CASES = (
    Case("stick", "stick of half-length L = κ: wall |cos θ|", "paper eq. 5", lambda: stick_wall(1.0), 0.0,
         lambda: stick_outline(1.0), None,
         (Reference("b_c", 0.0, "b + b'' = 0 between the kinks (eq. 5 is the segment's support function)"),
          Reference("kinks", (math.pi / 2, 3 * math.pi / 2), "|cos θ| has corners where cos θ = 0"),
          Reference("kink_jump", 2.0, "b' jumps from −L to +L: the edge length 2L"),
          Reference("area", 0.0, "a segment"),
          Reference("perimeter", 4.0, "Cauchy: ∫|cos θ| dθ = 4L, twice the segment length")),
         STICK_WALL, {"L": 1.0}),
    Case("stick-uniform", "uniform rod: L/κ = √3, wall √3 |cos θ|", "paper eq. 5 with κ² = L²/3",
         lambda: stick_wall(math.sqrt(3.0)), 0.0, lambda: stick_outline(math.sqrt(3.0)), None,
         (Reference("b_c", 0.0, "as for the stick"),
          Reference("kappa_over_L", 1 / math.sqrt(3.0), "uniform rod: I = M L²/3")),
         STICK_WALL, {"L": math.sqrt(3.0)}),
)
