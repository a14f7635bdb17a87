"""The elliptic disc (paper eq. 15–18) and its wall; the built-in example.

Ellipse with semi-axes 1 (along the body axis) and ``1/sqrt(1 + ε)``, centre of
mass at its centre: ``x² + (1 + ε) y² = 1``.  Its support function is
``h(θ) = sqrt((1 + ε cos²θ)/(1 + ε))`` (paper eq. 18 with κ = 1), the radius
of curvature at the ends of the major axis is ``1/(1 + ε)``, hence the
critical offset of the Appendix ``b_c = −1/(1 + ε)`` (the minimum of
``b + b''`` is attained there, see ``tests/test_known_answers.py``).
"""

from forward import Wall

__all__ = ["ELLIPSE_WALL", "ellipse_wall", "ellipse_critical_offset", "EXAMPLE"]

ELLIPSE_WALL = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def ellipse_wall(eps: float) -> Wall:
    """The paper's eq. 18 wall (κ = 1) for eccentricity parameter ``eps``."""
    return Wall.from_expression(ELLIPSE_WALL, {"eps": eps})


def ellipse_critical_offset(eps: float) -> float:
    """Appendix: ``b_c = −1/(1 + ε)``."""
    return -1.0 / (1.0 + eps)


#: The built-in example of ``coinwall solve``: the paper's Fig. 4, the critical body for ε = 1.
EXAMPLE = {"wall": ELLIPSE_WALL, "params": {"eps": 1.0}, "b0": -0.5}
