"""The angle convention, pinned with bodies that have no symmetry axis, and solver robustness.

Convention (forward/wall.py): ``b0 + b(θ)`` is the support function of the body at the
body-frame polar angle θ, counter-clockwise from the body axis; physically θ is measured
clockwise from the downward normal of the bottom wall to the body axis, and the upper wall
of the billiard is ``H − b(θ + π)``.  A symmetric body cannot tell θ from −θ; the triangle
below can.
"""

import math

import numpy as np
import pytest

from coinwall.forward import Outline, Wall
from coinwall.forward.outline import _GL3
from coinwall.inverse import critical_offset, solve_body

# an obtuse, scalene triangle with its centroid at the origin: no symmetry axis at all
_RAW = np.array([[1.3, 0.2], [-0.7, 0.9], [-0.4, -0.8]])
TRIANGLE = _RAW - _RAW.mean(axis=0)


def triangle_wall(points=TRIANGLE):
    """b(θ) = max_i p_i·(cos θ, sin θ): the support function of the triangle (a closed form)."""
    terms = [f"({float(x)!r})*cos(t) + ({float(y)!r})*sin(t)" for x, y in points]
    return Wall.from_expression(f"max({terms[0]}, max({terms[1]}, {terms[2]}))", {})


def test_triangle_is_not_mirror_symmetric():
    """The test below is only meaningful if b(θ) ≠ b(−θ) for this body."""
    theta = np.linspace(0, 2 * np.pi, 97)
    wall = triangle_wall()
    assert np.max(np.abs(wall(theta) - wall(-theta))) > 0.1


def test_solved_triangle_has_the_vertices_not_their_mirror_images():
    """Solving b(θ) at b0 = 0 gives back the triangle itself (corners at p_i, in body coordinates)."""
    body = solve_body(triangle_wall(), 0.0, points=512)
    corners = np.array([[c.distance * math.cos(c.direction), c.distance * math.sin(c.direction)]
                        for c in body.corners])
    assert len(corners) == 3
    for p in TRIANGLE:
        assert np.min(np.hypot(*(corners - p).T)) < 1e-9
        mirrored = p * [1, -1]
        assert np.min(np.hypot(*(corners - mirrored).T)) > 0.1
    (ax, ay), (bx, by) = TRIANGLE[1] - TRIANGLE[0], TRIANGLE[2] - TRIANGLE[0]
    assert body.area == pytest.approx(0.5 * abs(ax * by - ay * bx), rel=1e-12)


@pytest.mark.parametrize("psi", np.linspace(0.0, 2 * np.pi, 13)[:-1] + 0.1)
def test_physical_meaning_of_theta(psi):
    """Independent geometry in the lab frame: body axis at lab angle ψ (counter-clockwise).

    The bottom wall is tangent to the lowest point, at depth ``max_i −(R(ψ) p_i)_y`` below
    the centre of mass; the top wall to the highest point, at ``max_i (R(ψ) p_i)_y``.  The
    downward normal (0, −1) has body-frame angle θ = −π/2 − ψ, i.e. θ is measured clockwise
    from the downward normal to the body axis, so the depths must equal b(θ) and b(θ + π)
    (the upper billiard wall H − b(θ + π)).
    """
    rot = np.array([[math.cos(psi), -math.sin(psi)], [math.sin(psi), math.cos(psi)]])
    lab = TRIANGLE @ rot.T
    theta = np.mod(-math.pi / 2 - psi, 2 * math.pi)
    wall = triangle_wall()
    assert wall(np.array([theta]))[0] == pytest.approx(np.max(-lab[:, 1]), abs=1e-13)
    assert wall(np.array([theta + math.pi]))[0] == pytest.approx(np.max(lab[:, 1]), abs=1e-13)


def test_support_function_on_straight_edges():
    """An outline whose straight edges are cut into many segments (equal chord normals, with
    rounding deciding their order) still has the support function of its vertices."""
    square = np.array([[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]]) @ [[0.8, -0.6], [0.6, 0.8]]
    fine = np.concatenate([a + np.linspace(0, 1, 60, endpoint=False)[:, None] * (b - a)
                           for a, b in zip(square, np.roll(square, -1, axis=0))])
    outline = Outline.from_polygon(fine)
    theta = np.linspace(0, 2 * np.pi, 2001)
    exact = np.max(square @ np.stack([np.cos(theta), np.sin(theta)]), axis=0)
    assert np.max(np.abs(outline.support(theta) - exact)) < 1e-14


def test_bezier_area_closed_form():
    """The closed-form area of a cubic Bézier outline equals Green's integral by 3-point
    Gauss–Legendre, which is exact here (the integrand x y' − y x' has degree 5)."""
    rng = np.random.default_rng(7)
    outline = Outline(rng.normal(size=(9, 2)), rng.normal(size=(9, 2, 2)))
    x, w = _GL3
    s, w = (x + 1) / 2, w / 2
    pts, der = outline.point(s), outline._derivative(s)
    green = 0.5 * np.sum((pts[..., 0] * der[..., 1] - pts[..., 1] * der[..., 0]) * w)
    assert outline.area == pytest.approx(green, rel=1e-13, abs=1e-14)


@pytest.mark.parametrize("shift", [0.0, 0.37, math.pi / 2, 2.0])
@pytest.mark.parametrize("points", [1000, 2048, 10000])
def test_case_three_corners_anywhere(shift, points):
    """Case III with the corners rotated to arbitrary angles, including the α = 0 seam
    (shift 0 puts a corner exactly on it): both solvers find both corners and agree."""
    wall = Wall.from_expression("sqrt((1+cos(t-s)**2)/2)", {"s": shift})
    body = solve_body(wall, -0.6, points=points, cross_check=True)
    assert body.regime == "corner"
    assert len(body.corners) == 2
    # Appendix geometry: corners on the major axis (direction s and s + π), same distance
    directions = sorted(np.mod([c.direction - shift for c in body.corners], 2 * math.pi))
    assert min(directions[0], 2 * math.pi - directions[1]) < 1e-9 or abs(directions[0] - math.pi) < 1e-9
    assert body.cross_check < 1e-9
    assert body.max_wall_error < 1e-9


@pytest.mark.parametrize("expr,b0,tol", [
    ("abs(cos(t))", 0.3, 2e-9),                      # stadium: two arcs and two edges
    ("abs(cos(t))", 1.0, 1e-9),
    ("max(cos(t), 0.5*cos(t-2))", 1.0, 1e-9),        # an asymmetric kinked wall
    ("abs(cos(t)) + 0.2*cos(2*t)", 1.0, 1e-9),
])
def test_polar_solver_on_kinked_walls(expr, b0, tol):
    """Walls with kinks: the polar solver's straight-edge branches join the arcs correctly.

    Tolerances at 1024 nodes: the envelope's Hermite error next to an edge end, measured
    (1.2e-9 for the stadium at b0 = 0.3, below 3e-10 elsewhere; 6e-14 at 4096 nodes).
    """
    body = solve_body(Wall.from_expression(expr, {}), b0, points=1024, cross_check=True)
    assert body.cross_check < tol
    assert body.max_wall_error < 1e-10


def test_stick_critical_intervals_split_at_kinks():
    """For the stick b + b'' = 0 away from its kinks at π/2 and 3π/2, so b_c = 0 and the minimum
    is attained on the two open arcs between the kinks (not on isolated angles)."""
    result = critical_offset(Wall.from_expression("abs(cos(t))", {}))
    assert result.b_c == pytest.approx(0.0, abs=1e-12)
    assert len(result.intervals) == 2
    for lo, hi in result.intervals:
        assert hi - lo == pytest.approx(math.pi, abs=2e-3)
        assert min(abs(np.angle(np.exp(1j * (lo - k)))) for k in (math.pi / 2, 3 * math.pi / 2)) < 2e-3
