"""The stick of half-length L (paper eq. 5): wall ``(L/κ)|cos θ|``, a segment body."""

from forward import Wall

__all__ = ["STICK_WALL", "stick_wall"]

STICK_WALL = "L*abs(cos(t))"


def stick_wall(length_over_kappa: float = 1.0) -> Wall:
    """Wall of a stick whose half-length is ``length_over_kappa`` radii of gyration."""
    return Wall.from_expression(STICK_WALL, {"L": length_over_kappa})
