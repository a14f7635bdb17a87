"""The elliptic disc (paper eq. 15–18), its limits, and the built-in example.

Ellipse with semi-axes 1 (along the body axis) and ``1/sqrt(1 + ε)``, centre of
mass at its centre: ``x² + (1 + ε) y² = 1``, in polar form
``R(α) = (1 + ε sin²α)^(−1/2)`` (eq. 15).  Its support function is
``h(θ) = sqrt(cos²θ + sin²θ/(1 + ε)) = sqrt((1 + ε cos²θ)/(1 + ε))``,
which is the paper's eq. 18 with κ = 1 (lengths in units of κ).

* ε → 0: ``b → 1``, the unit circle (paper, after eq. 18); ``b ≈ 1 − (ε/2) sin²θ``
  to first order (eq. 19), error O(ε²).
* ε → ∞: ``b → |cos θ|``, the stick (eq. 5); at θ = π/2 the difference is
  ``1/sqrt(1 + ε)``, so the convergence is like ε^(−1/2).
* The radius of curvature at the ends of the major axis is ``1/(1 + ε)``,
  the smallest anywhere, so ``b_c = −1/(1 + ε)`` (Appendix, and exact: it is
  ``−min(b + b'')``).
* Uniform density: ``κ² = (a² + b²)/4 = (1 + 1/(1 + ε))/4`` — *not* 1, so the
  ellipse of eq. 15 with lengths in units of κ is self-consistent only for a
  non-uniform mass distribution (DESIGN.md: make κ explicit).
* The coin of section III is ε = 99: diameter D = 2 (in units of κ).
"""

import math

import numpy as np

from coinwall.forward import Outline, Wall
from coinwall.forward.dynamics.analysis.islands import ELLIPSE_WALL

from .catalog import Case, Reference

__all__ = ["ELLIPSE_WALL", "ellipse_wall", "ellipse_critical_offset", "ellipse_outline", "EXAMPLE", "CASES"]

def ellipse_wall(eps: float) -> Wall:
    """The paper's eq. 18 wall (κ = 1) for eccentricity parameter ``eps``.

    Parameters
    ----------
    eps : float
        The paper's ε: the ellipse ``x² + (1 + ε)y² = 1``.

    Returns
    -------
    Wall
        ``sqrt((1 + ε cos² θ)/(1 + ε))``.

    Examples
    --------
    >>> from coinwall.cases import ellipse_wall
    >>> wall = ellipse_wall(1.0)
    >>> wall, float(wall(0.0))
    (Wall('sqrt((1+eps*cos(t)**2)/(1+eps))' [eps=1]), 1.0)
    """
    return Wall.from_expression(ELLIPSE_WALL, {"eps": eps})


def ellipse_critical_offset(eps: float) -> float:
    """Appendix: ``b_c = −1/(1 + ε)``.

    Parameters
    ----------
    eps : float
        The paper's ε > −1.

    Returns
    -------
    float

    Examples
    --------
    >>> from coinwall import critical_offset
    >>> from coinwall.cases import ellipse_critical_offset, ellipse_wall
    >>> ellipse_critical_offset(1.0), round(critical_offset(ellipse_wall(1.0)).b_c, 12)
    (-0.5, -0.5)
    """
    return -1.0 / (1.0 + eps)


def ellipse_outline(eps: float, segments: int = 256) -> Outline:
    """The ellipse ``x² + (1 + ε)y² = 1`` as a closed cubic Hermite outline (exact tangents).

    Each segment spans ``Δ = 2π/segments`` of the parameter ``u`` of
    ``(cos u, sin u/sqrt(1+ε))``; the handles ``(4/3) tan(Δ/4)`` times the tangent
    are the standard circle-arc approximation, mapped affinely (error ~1e-15
    relative for 256 segments).

    Parameters
    ----------
    eps : float
        The paper's ε.
    segments : int
        Bézier segments.

    Returns
    -------
    Outline

    Examples
    --------
    The area is π a b = π/√2 for ε = 1:

    >>> import math
    >>> from coinwall.cases import ellipse_outline
    >>> round(ellipse_outline(1.0).area - math.pi / math.sqrt(2), 9)
    0.0
    """
    a, b = 1.0, 1.0 / math.sqrt(1.0 + eps)
    u = np.linspace(0.0, 2 * math.pi, segments, endpoint=False)
    k = 4.0 / 3.0 * math.tan(math.pi / segments / 2)
    pts = np.stack([a * np.cos(u), b * np.sin(u)], axis=1)
    tangent = np.stack([-a * np.sin(u), b * np.cos(u)], axis=1)
    nxt = np.roll(np.arange(segments), -1)
    controls = np.stack([pts + k * tangent, pts[nxt] - k * tangent[nxt]], axis=1)
    return Outline(pts, controls)


def _ellipse_case(name, eps, title, source, H=None):
    b = 1 / math.sqrt(1 + eps)
    return Case(name, title, source, lambda: ellipse_wall(eps), 0.0, lambda: ellipse_outline(eps), H,
                (Reference("b_c", -1 / (1 + eps), "Appendix: −1/(1+ε), the minimum of b + b'' at θ = 0, π"),
                 Reference("semi_axes", (1.0, b), "eq. 15"),
                 Reference("area", math.pi * b, "π a b"),
                 Reference("kappa_uniform", math.sqrt((1 + b * b) / 4), "uniform ellipse κ² = (a² + b²)/4"),
                 Reference("diameter", 2.0, "2a")),
                ELLIPSE_WALL, {"eps": eps})


CASES = (
    _ellipse_case("ellipse", 1.0, "ellipse x² + 2y² = 1 (ε = 1)", "paper eq. 15–18"),
    _ellipse_case("ellipse-0.003", 0.003, "nearly circular ellipse ε = 0.003 (Poincaré section at H = 3)",
                  "paper section III text ('Fig. 2'; the figure captions say ε = 0.03)", H=3.0),
    _ellipse_case("ellipse-0.03", 0.03, "ellipse ε = 0.03 (Poincaré section at H = 3)",
                  "paper, caption of the first figure", H=3.0),
    _ellipse_case("ellipse-0.55", 0.55, "ellipse ε = 0.55 (mixed phase space at H = 1.9)",
                  "paper section III ('Fig. 3') and the second caption", H=1.9),
    _ellipse_case("coin", 99.0, "the coin: ellipse ε = 99 (heads/tails statistics)", "paper section III", H=2.4),
)

#: The built-in example of ``coinwall solve``: the paper's Fig. 4, the critical body for ε = 1.
EXAMPLE = {"wall": ELLIPSE_WALL, "params": {"eps": 1.0}, "b0": -0.5}
