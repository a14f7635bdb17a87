"""Bodies of constant width (paper, Conclusions: "shapes of constant width may warrant investigation").

A body has constant width w iff ``h(θ) + h(θ + π) = w``: the support function is
``w/2`` plus odd harmonics only.  Its perimeter is ``π w`` (Barbier; from
Cauchy's ``L = ∫h dθ``).  In the billiard the two walls are then parallel
translates of each other: ``H − b(θ + π) = b(θ) + (H − w)``.

* Smooth: ``h = w/2 + a cos 3θ`` is convex iff ``ρ = w/2 − 8a cos 3θ ≥ 0``,
  i.e. ``|a| ≤ w/16``; at ``a = w/16`` the radius of curvature touches 0 (critical).
* Reuleaux polygon with n (odd) vertices on the circle of radius
  ``r = w / (2 cos(π/(2n)))``: arcs of radius w centred on the opposite
  vertices.  Its support function is C¹ but ``h + h''`` jumps between 0 (at a
  vertex) and w (on an arc), so no finite Fourier series represents it: the
  wall is exact piece by piece (``Wall.from_arcs``); the case also provides the
  exact *body* (arcs as cubic Béziers, error < 2e-12).
  Area of the Reuleaux triangle: ``(π − √3) w²/2``.
"""

import math

import numpy as np

from coinwall.forward import Outline, Wall

from .catalog import Case, Reference

__all__ = ["SMOOTH_WIDTH_WALL", "smooth_constant_width_wall", "reuleaux_outline", "reuleaux_wall",
           "sampled_reuleaux_wall", "CASES"]

SMOOTH_WIDTH_WALL = "w/2 + a*cos(3*t)"


def smooth_constant_width_wall(width: float = 2.0, a: float = 0.1) -> Wall:
    """``h = w/2 + a cos 3θ`` (convex for ``|a| ≤ w/16``)."""
    return Wall.from_expression(SMOOTH_WIDTH_WALL, {"w": width, "a": a})


def reuleaux_outline(n: int = 3, width: float = 2.0, pieces: int = 16) -> Outline:
    """The Reuleaux n-gon of width ``width`` (n odd), centred at the origin, one vertex on +x.

    Each arc (radius w, centred on the opposite vertex, spanning π/n) is cut into
    ``pieces`` cubic Béziers with handles ``(4/3) tan(Δ/4) w`` (radial error
    below 2e-12 for Δ = π/48, measured).  Vertices are true corners.
    """
    if n < 3 or n % 2 == 0:
        raise ValueError(f"`n` must be an odd integer ≥ 3, got {n}")
    r = width / (2 * math.cos(math.pi / (2 * n)))
    vertex_angle = 2 * math.pi * np.arange(n) / n
    vertices = r * np.stack([np.cos(vertex_angle), np.sin(vertex_angle)], axis=1)
    nodes, controls = [], []
    delta = math.pi / n / pieces
    k = 4.0 / 3.0 * math.tan(delta / 4) * width
    for i in range(n):
        # the arc from vertex i to vertex i+1 is centred on the opposite vertex i + (n+1)/2
        centre = vertices[(i + (n + 1) // 2) % n]
        start = math.atan2(*(vertices[i] - centre)[::-1])
        for j in range(pieces):
            a0, a1 = start + j * delta, start + (j + 1) * delta
            p0 = centre + width * np.array([math.cos(a0), math.sin(a0)])
            p3 = centre + width * np.array([math.cos(a1), math.sin(a1)])
            t0 = np.array([-math.sin(a0), math.cos(a0)])
            t1 = np.array([-math.sin(a1), math.cos(a1)])
            nodes.append(p0)
            controls.append([p0 + k * t0, p3 - k * t1])
    return Outline(np.array(nodes), np.array(controls))


def reuleaux_wall(n: int = 3, width: float = 2.0) -> Wall:
    """The Reuleaux n-gon's wall, exact: ``Wall.from_arcs`` with 2n pieces.

    Vertex k (at angle 2πk/n on the circle of radius ``r = w / (2 cos(π/(2n)))``) governs the wall
    angles within π/(2n) of its direction, where ``h = v_k·n(θ)``; between two vertex windows the arc
    of radius w centred on the opposite vertex, ``h = v_opp·n(θ) + w``.  The pieces meet with equal
    slopes (h is C¹) and ``h + h''`` jumps between 0 and w at the 2n breaks.  Constant width:
    ``h(θ) + h(θ + π) = w`` holds exactly (the vertex window at θ faces the arc centred on that vertex).
    """
    if n < 3 or n % 2 == 0:
        raise ValueError(f"`n` must be an odd integer ≥ 3, got {n}")
    r = width / (2 * math.cos(math.pi / (2 * n)))
    vertex_angle = 2 * math.pi * np.arange(n) / n
    vertices = r * np.stack([np.cos(vertex_angle), np.sin(vertex_angle)], axis=1)
    angles, centres, radii = [], [], []
    for k in range(n):
        angles += [vertex_angle[k] - math.pi / (2 * n), vertex_angle[k] + math.pi / (2 * n)]
        centres += [vertices[k], vertices[(k + (n + 1) // 2) % n]]
        radii += [0.0, width]
    return Wall.from_arcs(angles, centres, radii, description=f"Reuleaux {n}-gon of width {width:g} (exact arcs)")


def sampled_reuleaux_wall(n: int = 3, width: float = 2.0, samples: int = 4096) -> Wall:
    """The Reuleaux body's wall as data: uniform samples of the exact support function.

    Solved as data (vertex windows, half-plane intersection): exact at the samples; between them the
    arcs are the polygon of their sampled tangent lines (support error ≤ w(1/cos(Δ/2) − 1)).
    """
    theta = np.linspace(0, 2 * math.pi, samples, endpoint=False)
    return Wall.from_samples(theta, reuleaux_wall(n, width)(theta))


CASES = (
    Case("constant-width-smooth", "smooth constant width 2: h = 1 + 0.1 cos 3θ",
         "paper, Conclusions; odd harmonics", lambda: smooth_constant_width_wall(2.0, 0.1), 0.0, None, None,
         (Reference("width", 2.0, "h(θ) + h(θ+π) = w"),
          Reference("perimeter", 2 * math.pi, "Barbier: π w"),
          Reference("b_c", -(1.0 - 8 * 0.1), "−min(h + h'') = −(w/2 − 8a)")),
         SMOOTH_WIDTH_WALL, {"w": 2.0, "a": 0.1}),
    Case("reuleaux-3", "Reuleaux triangle of width 2", "paper, Conclusions; Reuleaux",
         lambda: reuleaux_wall(3, 2.0), 0.0, lambda: reuleaux_outline(3, 2.0), None,
         (Reference("width", 2.0, "construction"),
          Reference("perimeter", 2 * math.pi, "Barbier: π w"),
          Reference("area", (math.pi - math.sqrt(3)) * 4.0 / 2, "(π − √3) w²/2")),
         None, {}),
    Case("reuleaux-5", "Reuleaux pentagon of width 2", "paper, Conclusions; Reuleaux",
         lambda: reuleaux_wall(5, 2.0), 0.0, lambda: reuleaux_outline(5, 2.0), None,
         (Reference("width", 2.0, "construction"),
          Reference("perimeter", 2 * math.pi, "Barbier: π w")),
         None, {}),
)
