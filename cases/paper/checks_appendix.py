"""The computations behind the paper's Appendix claims: the ellipse wall plus an offset b0.

Pure functions ``check(resolution, **inputs) -> dict`` of measured numbers, as in :mod:`.checks`.

Eq. 27 from eq. 29: at α = 0, R' = 0 and the curvature is ``K = (R² − R R'')/R³`` (eq. 28), so
``R'' = R − K R²`` and ``R ≈ R0 − ½ R0(R0 K − 1) α²`` with ``R0 K − 1 = ε/(1 + b0(1 + ε))``.
"""

from __future__ import annotations

import math

import numpy as np

from coinwall.forward.angles import TWO_PI

from .checks import Measured, fit_exponent

__all__ = ["critical_offsets", "extremum_estimate", "curvature_at_zero", "coefficient_27", "exponents_near_zero",
           "case_three", "offset_positivity", "realizable_body"]

#: The angle of a smooth maximum found by a minimiser is known to about sqrt(rounding) ≈ 1e-8 rad only.
ARGMAX_TOLERANCE = 1e-7


def critical_offsets(resolution, *, eps_values) -> dict:
    """Eq. 29: largest |b_c − (−1/(1 + ε))| of the exact critical offset −min(b + b'') (``error``)."""
    from coinwall.inverse import critical_offset

    from ..ellipse import ellipse_wall

    return {"error": max(abs(critical_offset(ellipse_wall(e)).b_c + 1 / (1 + e)) for e in eps_values)}


def extremum_estimate(resolution, *, expression: str) -> dict:
    """Appendix, last paragraph: on a wall whose minimum of b + b'' is not at an extremum of b, the exact
    b_c (``b_c``, at ``angle`` where b' = ``slope``) against −min(b + b'') over the extrema of b
    (``estimate``; ``estimate_error`` = |estimate − b_c|)."""
    from coinwall.forward import Wall
    from coinwall.inverse import critical_offset

    wall = Wall.from_expression(expression, {})
    exact = critical_offset(wall)
    theta = np.linspace(0, TWO_PI, 20000, endpoint=False)
    b, d1, d2 = wall.derivatives(theta)
    extrema = np.flatnonzero(np.sign(d1) != np.sign(np.roll(d1, -1)))
    estimate = float(-np.min((b + d2)[extrema]))
    at = exact.angles[0]
    slope = float(wall.derivatives(np.array([at]))[1][0])
    return {"b_c": exact.b_c, "estimate": estimate, "angle": at, "slope": slope,
            "estimate_error": abs(estimate - exact.b_c)}


def curvature_at_zero(resolution, *, cases) -> dict:
    """Eq. 28–29: largest relative error of the solved body's curvature at α = 0 against the closed form
    K(0), over ``cases`` = [(ε, b0), …] (``error``, ``count``)."""
    from coinwall.inverse import solve_body

    from ..appendix import appendix_curvature_at_zero
    from ..ellipse import ellipse_wall

    worst = 0.0
    for eps, b0 in cases:
        body = solve_body(ellipse_wall(eps), b0, points=resolution.points)
        i = int(np.argmin(np.abs(np.angle(np.exp(1j * body.alpha)))))
        worst = max(worst, abs(body.K[i] / appendix_curvature_at_zero(eps, b0) - 1))
    return {"error": worst, "count": len(cases)}


def _near_zero(b0, eps, points):
    """The solved body, its α in (−π, π] and R'(α) at the nodes (R' = R tan(α − φ))."""
    from coinwall.inverse import solve_body

    from ..ellipse import ellipse_wall

    body = solve_body(ellipse_wall(eps), b0, points=points)
    alpha = np.angle(np.exp(1j * body.alpha))
    slope = body.R * np.tan(alpha - np.angle(np.exp(1j * body.phi_out)))
    return body, alpha, slope


def coefficient_27(resolution, *, b0: float, eps: float) -> dict:
    """Eq. 27: the α² coefficient of R(α) fitted on the solved body for 1e-3 < |α| < 5e-2 (``fitted``),
    the paper's closed form (``paper_coefficient``) and ``relative_error`` = fitted/paper − 1."""
    body, alpha, _ = _near_zero(b0, eps, resolution.points)
    sel = (np.abs(alpha) > 1e-3) & (np.abs(alpha) < 5e-2)
    fitted = float(np.polyfit(alpha[sel] ** 2, body.R[sel], 2)[1])  # R0 + c α² + c₄ α⁴: the α² coefficient
    paper = -0.5 * (1 + b0) * eps / (1 + b0 * (1 + eps))
    return {"fitted": fitted, "paper_coefficient": paper, "relative_error": fitted / paper - 1}


def exponents_near_zero(resolution, *, b0: float, eps: float, lo: float, hi: float) -> dict:
    """Appendix Cases I and II: fitted powers of α of (b0 + 1) − R (``radius_exponent``) and of R'
    (``slope_exponent``) on the solved body's nodes with lo < α < hi."""
    body, alpha, slope = _near_zero(b0, eps, resolution.points)
    sel = (alpha > lo) & (alpha < hi)
    return {"radius_exponent": fit_exponent(alpha[sel], b0 + 1 - body.R[sel]),
            "slope_exponent": fit_exponent(alpha[sel], slope[sel])}


def case_three(resolution, *, b0: float, eps: float) -> dict:
    """Appendix Case III and eq. 30: the corner of the largest convex body under the wall nearest α = 0.

    Returns
    -------
    dict
        ``corners`` (how many), ``corner_slope`` = |R'(0±)|, ``corner_distance`` R_c,
        ``paper_distance`` = b0 + 1 and ``distance_gap`` = (b0 + 1) − R_c; ``paper_theta_c`` (eq. 30 as
        printed), ``exact_theta_c`` = atan(|R'_0|/R_c), ``half_width`` of the corner's window and their
        differences ``paper_theta_c_error``, ``exact_theta_c_error``; ``max_deficit`` and
        ``deficit_angle`` of the wall in the window, ``max_wall_error`` outside the windows.
    """
    from coinwall.inverse import solve_body

    from ..ellipse import ellipse_wall

    body = solve_body(ellipse_wall(eps), b0, points=resolution.points)
    corner = min(body.corners, key=lambda c: abs(np.angle(np.exp(1j * c.direction))))
    half = corner.half_width
    r_c = corner.distance
    # R'(0⁺) on the side α > 0: the contact normal is the window edge φ = +half; R'/R = tan(α − φ)
    slope0 = r_c * math.tan(0.0 - half)
    theta_c_paper = math.atan(abs(slope0) / (b0 + 1))
    theta_c_exact = math.atan(abs(slope0) / r_c)
    return {"corners": len(body.corners), "corner_slope": abs(slope0), "corner_distance": r_c,
            "paper_distance": b0 + 1, "distance_gap": b0 + 1 - r_c,
            "paper_theta_c": theta_c_paper, "exact_theta_c": theta_c_exact, "half_width": half,
            "paper_theta_c_error": abs(theta_c_paper - half), "exact_theta_c_error": abs(theta_c_exact - half),
            "max_deficit": corner.max_deficit, "deficit_angle": Measured(corner.deficit_angle, ARGMAX_TOLERANCE),
            "max_wall_error": body.max_wall_error}


def offset_positivity(resolution, *, eps: float) -> dict:
    """End of Case III: the smallest wall value (``min_wall``; b0 + b > 0 for b0 > −min b), the
    exact critical offset as ``minus_b_c`` = −b_c, and ``margin`` = b_c − (−min b)."""
    from coinwall.inverse import critical_offset

    from ..ellipse import ellipse_wall

    wall = ellipse_wall(eps)
    theta = np.linspace(0, TWO_PI, 721)  # holds θ = π/2, where the ellipse wall is smallest
    min_wall = float(np.min(wall(theta)))
    b_c = critical_offset(wall).b_c
    return {"min_wall": min_wall, "minus_b_c": -b_c, "margin": b_c + min_wall}


def realizable_body(resolution, *, b0: float, eps: float) -> dict:
    """A body the paper calls physical, as a rigid body: the ellipse wall (ε) at offset b0 solved, then
    κ of the uniform lamina (``kappa_uniform``) and κ_max, the largest κ any mass distribution inside the
    outline with its centre of mass at the origin gives (``kappa_max``); ``realizable`` iff κ_max ≥ 1
    (the wall is in units of κ, so the body must be able to have κ = 1)."""
    from coinwall.inverse import realizability, solve_body

    from ..ellipse import ellipse_wall

    body = solve_body(ellipse_wall(eps), b0, points=resolution.points)
    found = realizability(body)
    return {"kappa_uniform": found.kappa_uniform, "kappa_max": found.kappa_max, "realizable": found.realizable,
            "regime": body.regime}
