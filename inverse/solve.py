"""``solve_body``: wall function + offset → body outline, verified through the forward wall.

This module only checks the request and dispatches: a wall given as data goes to :mod:`.sampled` (the
exact discrete path, or the smooth one where the data are shown to be smooth), any other wall to
:func:`.smooth.solve_smooth`.
"""

from __future__ import annotations

import time

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.errors import InvalidArgument, InvalidWall

from .body import Body
from .sampled import solve_samples
from .smooth import METHODS, solve_smooth
from .support import check_offset, check_points
from .tolerances import DEFAULT_POINTS

__all__ = ["MIN_BODY_SIZE", "solve_body"]


def solve_body(wall, b0: float = 0.0, *, method: str = "envelope", points: int = DEFAULT_POINTS,
               cross_check: bool = False) -> Body:
    """Solve the inverse problem: the body whose wall is ``b0 + b(θ)``.

    The body's support function is :math:`h(\\theta) = b_0 + b(\\theta)`; it is convex where
    :math:`b_0 + b + b'' \\ge 0` everywhere, that is for ``b0`` at or above the critical offset
    :math:`b_c = -\\min_\\theta (b + b'')` (:func:`critical_offset`).

    Parameters
    ----------
    wall : forward.Wall
        The prescribed wall function.
    b0 : float
        Offset added to the wall (the paper's ``b0``).
    method : {"envelope", "polar"}
        ``"envelope"`` (default: exact Legendre construction, fastest and most
        accurate) or ``"polar"`` (the paper's equation for R(α) with branch
        tracking).
    points : int
        Number of outline nodes (uniform in the normal angle for ``envelope``,
        in the polar angle for ``polar``); corners and kinks add nodes.
    cross_check : bool
        Also run the other method and report the largest difference of the two
        bodies' walls in :attr:`Body.cross_check`.

    Returns
    -------
    Body
        Below the critical offset (``regime == "corner"``) the largest convex
        body whose wall never exceeds the prescribed one, with its corners.

    Raises
    ------
    InvalidArgument, InvalidParameter, InvalidWall
        For an unknown method, a bad resolution, a non-finite offset, or an
        offset for which the centre of mass would lie outside the body.

    See Also
    --------
    critical_offset : the smallest offset with a convex body.
    export_body : write the body as SVG, DXF, JSON, CSV or PNG.

    Examples
    --------
    The paper's ellipse wall (eq. 18, ε = 1): at ``b0 = 0`` the body is the ellipse
    ``x² + 2y² = 1`` itself, of area π/√2; below ``b_c = -1/2`` it has two corners.

    >>> from coinwall import Wall, solve_body
    >>> ellipse = "sqrt((1+eps*cos(t)**2)/(1+eps))"
    >>> wall = Wall.from_expression(ellipse, {"eps": 1.0})
    >>> body = solve_body(wall, 0.0, points=256)
    >>> body.regime, round(body.area, 6), body.max_wall_error < 1e-8
    ('convex', 2.221441, True)
    >>> corner = solve_body(wall, -0.6, points=256)
    >>> corner.regime, len(corner.corners)
    ('corner', 2)
    """
    started = time.perf_counter()
    if method not in METHODS:
        raise InvalidArgument(f"`method` must be one of {sorted(METHODS)}, got {method!r}")
    b0 = check_offset(b0, wall.scale)
    points = check_points(points)
    _check_size(wall, b0)
    if wall.samples is not None:
        return solve_samples(wall, b0, method=method, points=points, cross_check=cross_check, started=started)
    return solve_smooth(wall, b0, method=method, points=points, cross_check=cross_check, started=started)


#: Smallest ``max(b0 + b)`` a body is solved for (units of κ).  Every body reaches at least κ from its
#: centre of mass (κ² = J/M ≤ R_max²), and the solvers' tolerances are absolute near 1e-9 κ: a body
#: below 1e-6 κ is unphysical and lost in them (1e-300·cos t gave NaN in the polar solver).
MIN_BODY_SIZE = 1e-6


def _check_size(wall, b0):
    values = wall.samples[1] if wall.samples is not None else wall(np.linspace(0.0, TWO_PI, 256, endpoint=False))
    top = b0 + float(np.max(values))
    if b0 + float(np.min(values)) >= 0 and top < MIN_BODY_SIZE:  # (below 0: the centre-of-mass check speaks)
        raise InvalidWall(f"b0 + b(θ) is at most {top:.3g}: the body would be smaller than {MIN_BODY_SIZE:g} κ, "
                          "but every body reaches at least κ from its centre of mass (κ² = J/M ≤ R_max²); "
                          "give the wall in units of κ")
