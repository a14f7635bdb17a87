"""Body → wall: the two walls of the billiard are support functions of the body (the forward problem).

With the body at rest the distance from the centre of mass to the tangent wall with normal angle θ is
the support function ``h(θ)`` of its outline (paper, section II), so the lower wall is ``b(θ) = h(θ)``
and, with the walls a distance H apart, the upper wall is ``t(θ) = H − h(θ + π)``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["wall_functions"]


def wall_functions(outline, theta, H: float | None = None):
    """Lower wall ``b(θ) = h(θ)`` and, given the wall distance H, upper wall ``t(θ) = H − h(θ + π)``.

    Parameters
    ----------
    outline : Outline
        The body, in units of κ with the centre of mass at the origin.
    theta : array_like
        Wall normal angles (rad).
    H : float, optional
        Distance between the walls (units of κ).

    Returns
    -------
    lower : ndarray
    upper : ndarray or None
        None without ``H``.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall import Outline, wall_functions
    >>> square = Outline.from_polygon([[1, 1], [-1, 1], [-1, -1], [1, -1]])
    >>> lower, upper = wall_functions(square, np.array([0.0, np.pi / 4]), H=5.0)
    >>> lower.round(6).tolist(), upper.round(6).tolist()        # upper = H − h(θ + π)
    ([1.0, 1.414214], [4.0, 3.585786])
    """
    theta = np.asarray(theta, float)
    lower = outline.support(theta)
    upper = None if H is None else H - outline.support(theta + math.pi)
    return lower, upper
