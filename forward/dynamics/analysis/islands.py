"""Closed-form stability limits of the two period-2 orbits of the paper's ellipse wall (docs/dynamics.md,
"The islands come from two period-2 orbits"): the curves drawn on a chaotic-fraction phase diagram.

Wall ``b(θ) = sqrt((1 + ε cos²θ)/(1 + ε))`` (:data:`ELLIPSE_WALL`), units of κ.
With s = b², ``b' = s'/(2b)`` and ``b'' = (s''/2 − b'²)/b``, ``s' = −ε sin 2θ/(1+ε)``, ``s'' = −2ε cos 2θ/(1+ε)``.

* ε*(H): the vertical orbit θ = π/2 bounces between two focusing mirrors of radius R = √(1+ε)/ε a distance
  L = H − 2/√(1+ε) apart; it turns unstable at L = 2R.
* ε**(H): the tilted pair born there runs through (π/2, H/2), meeting the lower wall at θ₁ = π/2 − δ with
  δ = −b'(θ₁)(H/2 − b(θ₁)); it turns unstable where g = 1 − L/R reaches 1 (its contact point reaches the
  wall's inflection point), with L = 2·hypot(δ, H/2 − b) and 1/R = b''/(1 + b'²)^{3/2}.

The same construction as tests/benchmarks/kam_sensitivity.py (which evaluates the wall through
:class:`~coinwall.forward.wall.Wall`); here the derivatives are written out so a figure needs no casadi.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["ELLIPSE_WALL", "eps_star", "eps_star_star", "paper_boundary"]

#: the paper's ellipse wall (eq. 18, κ = 1): the support function of the ellipse with semi-axes 1 and 1/sqrt(1 + ε)
ELLIPSE_WALL = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def paper_boundary(H):
    """The paper's eq. (20): ``ε ≈ 1/H + 17/H²``.

    Parameters
    ----------
    H : float or array_like
        Wall distances (units of κ).

    Returns
    -------
    float or ndarray
        The paper's ε_c(H).

    Examples
    --------
    >>> from coinwall.forward import paper_boundary
    >>> round(float(paper_boundary(10.0)), 6)
    0.27
    """
    H = np.asarray(H, dtype=float)
    return 1.0 / H + 17.0 / H**2


def _wall(theta, eps):
    """b, b', b'' of the ellipse wall at ``theta`` (arrays)."""
    b = np.sqrt((1.0 + eps * np.cos(theta) ** 2) / (1.0 + eps))
    s1 = -eps * np.sin(2 * theta) / (1.0 + eps)
    s2 = -2.0 * eps * np.cos(2 * theta) / (1.0 + eps)
    b1 = s1 / (2 * b)
    return b, b1, (s2 / 2 - b1**2) / b


def _vertical_g(eps, H):
    return 1.0 - (H - 2.0 / math.sqrt(1.0 + eps)) * eps / math.sqrt(1.0 + eps)


def eps_star(H: float) -> float:
    """ε at which the vertical period-2 orbit of the ellipse wall turns unstable at wall distance ``H`` (κ)."""
    from scipy.optimize import brentq

    return float(brentq(lambda e: _vertical_g(e, H) + 1.0, 1e-6, 1e6, xtol=1e-13))


def _tilted_g(eps, H):
    """g of the tilted orbit with δ closest to 0 (nan if there is none)."""
    from scipy.optimize import brentq

    def F(delta):
        b, b1, _ = _wall(math.pi / 2 - delta, eps)
        return delta + b1 * (H / 2 - b)

    grid = np.linspace(1e-7, math.pi / 2 - 1e-7, 4000)
    values = F(grid)
    cross = np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))
    if cross.size == 0:
        return math.nan
    delta = brentq(F, grid[cross[0]], grid[cross[0] + 1], xtol=1e-15)
    b, b1, b2 = (float(v) for v in _wall(math.pi / 2 - delta, eps))
    return 1.0 - 2.0 * math.hypot(delta, H / 2 - b) * b2 / (1.0 + b1 * b1) ** 1.5


def eps_star_star(H: float) -> float:
    """ε at which the tilted period-2 orbit turns unstable (g = 1); the islands' closed-form upper limit."""
    from scipy.optimize import brentq

    low = eps_star(H) * 1.001
    high = low
    while _tilted_g(high, H) < 1.0:
        high *= 1.5
    return float(brentq(lambda e: _tilted_g(e, H) - 1.0, high / 1.5 if high > low else low, high, xtol=1e-6))
