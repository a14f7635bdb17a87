"""Formula walls with kinks, breaks and unbounded curvature: polygons, a half-disc, a lens, a Reuleaux
triangle, a cam with simple-harmonic rises and the superellipse |x|⁴ + |y|⁴ = 1.

Every wall is written as an expression (max/min/abs), the way a user types it, and solved with the
cross-check (both solvers).  The references are independent of coinwall's solvers; each says where it
comes from:

* polygons: the vertices the expression is built from (``h = max_k v_k·n``); the area by the shoelace
  formula, the outline by shapely's Hausdorff distance to ``Polygon(vertices)``; lowered by ``b0 < 0`` the
  largest body under the wall is the inner parallel polygon, shapely's ``buffer(b0, join_style="mitre")``;
  raised, its support function is ``max_k v_k·n + b0`` exactly;
* half-disc, lens, Reuleaux triangle, superellipse: their boundary written down in closed form here
  (arcs, segments, ``(|cos s|^½ sgn cos s, |sin s|^½ sgn sin s)``), their areas from elementary formulas
  (π/2, ``2(r² acos(d/r) − d√(r² − d²))``, ``(π − √3)w²/2``, ``4Γ(5/4)²/Γ(3/2)``);
* the cam: a flat-faced follower's cam has the follower lift as its support function, so the wall is
  the lift law, evaluated here with numpy from its definition (not from the expression).

For curved bodies the distance to the truth is measured as ``max_θ |h_body(θ) − h_true(θ)|``, which for
convex sets *is* their Hausdorff distance: ``h_true`` is written piecewise in numpy from the geometry,
``h_body`` is the exact support function of the solved Bézier outline (the forward map), on 20 000
directions.  (shapely's Hausdorff distance is O(n·m) in the vertex counts: kept for the polygons.)
The outline is checked as a whole for simplicity (shapely, at 16 points per Bézier piece): no
self-crossing at any scale.
"""

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Polygon

from coinwall import Wall, solve_body
from coinwall.cases.cli.main import main

DENSE = np.linspace(0.0, 2 * math.pi, 20000, endpoint=False) + 1e-4


def nested_max(terms):
    text = terms[0]
    for term in terms[1:]:
        text = f"max({text}, {term})"
    return text


def polygon_expression(vertices):
    """``max_k r_k cos(t − a_k)``: the support function of the polygon with these vertices."""
    return nested_max([f"{math.hypot(x, y)!r}*cos(t - {math.atan2(y, x)!r})" for x, y in vertices])


def polygon_support(vertices, theta):
    return np.max(np.asarray(vertices) @ np.stack([np.cos(theta), np.sin(theta)]), axis=0)


def shoelace(vertices):
    x, y = np.asarray(vertices).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def outline_polygon(body, per_piece=16):
    return Polygon(body.outline.polygon(per_piece))


def assert_clean(body, tol=1e-9):
    """No warning, the two solvers agree, the whole outline is simple and convex."""
    assert body.warnings == ()
    assert body.cross_check is not None and body.cross_check < tol
    assert body.valid and body.convex
    polygon = outline_polygon(body)
    assert polygon.is_valid and LineString(body.outline.polygon(16)).is_simple


EQUILATERAL = [(math.cos(a), math.sin(a)) for a in (0.0, 2 * math.pi / 3, -2 * math.pi / 3)]
SCALENE = [(1.3, 0.1), (-0.6, 0.9), (-0.5, -0.8)]
_angles = np.arange(9) * 2 * math.pi / 9 + np.array([0.05, -0.12, 0.17, 0.0, -0.08, 0.13, -0.15, 0.09, 0.02])
_radii = np.array([1.0, 1.12, 0.91, 1.05, 0.87, 1.14, 0.95, 1.08, 0.9])
NONAGON = [(r * math.cos(a), r * math.sin(a)) for r, a in zip(_radii, _angles)]
# a triangle whose windows cross the 2π seam away from a vertex, vertices at different distances
SKEWED = [(0.78257747, -0.24598004), (-1.04049484, 0.75370209), (0.25791737, -0.50772205)]


@pytest.mark.parametrize("vertices", [EQUILATERAL, SCALENE, NONAGON, SKEWED],
                         ids=["equilateral", "scalene", "nonagon", "skewed"])
def test_polygon_is_its_vertices(vertices):
    """b0 = 0: the polygon itself (critical: ρ = 0 on every vertex window), its vertices the corners."""
    text = polygon_expression(vertices) if vertices is not EQUILATERAL else \
        "max(cos(t), max(cos(t-2.0943951023931953), cos(t+2.0943951023931953)))"
    body = solve_body(Wall.from_expression(text), 0.0, cross_check=True)
    assert_clean(body)
    assert body.regime == "critical" and len(body.corners) == len(vertices)
    corners = np.array([[c.distance * math.cos(c.direction), c.distance * math.sin(c.direction)]
                        for c in body.corners])
    for v in vertices:
        assert np.min(np.hypot(*(corners - v).T)) < 1e-12
    truth = Polygon(vertices)
    assert body.area == pytest.approx(shoelace(vertices), abs=1e-12)
    assert outline_polygon(body).hausdorff_distance(truth) < 1e-12


@pytest.mark.parametrize("vertices", [SCALENE, NONAGON, SKEWED], ids=["scalene", "nonagon", "skewed"])
def test_polygon_lowered_is_the_inner_parallel_polygon(vertices):
    """b0 = −0.05 < b_c = 0: every vertex window is a swallowtail; the largest body under the wall is the
    polygon shrunk by 0.05 (shapely's mitred inner buffer), whose vertices carry a deficit."""
    body = solve_body(Wall.from_expression(polygon_expression(vertices)), -0.05, cross_check=True)
    assert_clean(body)
    truth = Polygon(vertices).buffer(-0.05, join_style="mitre")
    assert body.regime == "corner" and len(body.corners) == len(truth.exterior.coords) - 1
    assert all(c.max_deficit > 0 for c in body.corners)
    assert body.area == pytest.approx(truth.area, abs=1e-12)
    assert outline_polygon(body).hausdorff_distance(truth) < 1e-12


@pytest.mark.parametrize("vertices", [EQUILATERAL, NONAGON, SKEWED], ids=["equilateral", "nonagon", "skewed"])
def test_polygon_raised_is_rounded(vertices):
    """b0 = 0.3 > b_c: the polygon's outer parallel body (edges and arcs of radius 0.3), support function
    max_k v_k·n + 0.3 exactly; the area is the Steiner formula A + P·r + πr²."""
    body = solve_body(Wall.from_expression(polygon_expression(vertices)), 0.3, cross_check=True)
    assert_clean(body, tol=1e-7)
    assert body.regime == "convex" and not body.corners
    assert np.max(np.abs(body.outline.support(DENSE) - (polygon_support(vertices, DENSE) + 0.3))) < 1e-9
    perimeter = Polygon(vertices).length
    assert body.area == pytest.approx(shoelace(vertices) + 0.3 * perimeter + math.pi * 0.09, abs=1e-9)


def distance_to(body, true_support):
    """Hausdorff distance of two convex bodies: the largest difference of their support functions."""
    return float(np.max(np.abs(body.outline.support(DENSE) - true_support(DENSE))))


def half_disc_support(centre):
    """The half-disc x² + y² ≤ 1, y ≥ 0 seen from ``centre``: the arc's support 1 for normals in the upper
    half plane, the diameter's ends (±1, 0) for the lower, minus c·n."""
    def h(theta):
        upper = np.mod(theta, 2 * math.pi) <= math.pi
        return np.where(upper, 1.0, np.abs(np.cos(theta))) - centre[0] * np.cos(theta) - centre[1] * np.sin(theta)
    return h


@pytest.mark.parametrize("text", ["max(abs(cos(t)), 1 - 2*max(0, -sin(t)))",
                                  "max(cos(t), max(-cos(t), sqrt(cos(t)**2 + max(sin(t), 0)**2)))"])
@pytest.mark.parametrize("centre", [(0.1, 0.3), (0.0, 4 / (3 * math.pi)), (0.0, 0.0)])
def test_half_disc(text, centre):
    """Support function 1 on the upper half, |cos θ| on the lower (the diameter's ends), moved to ``centre``
    (h − c·n).  Corners at (±1, 0) − c, each governing a quarter turn; area π/2.  The centre (0, 0) puts
    the centre of mass on the flat side, where b0 + b = 0 along it."""
    wall = Wall.from_expression(f"{text} - {centre[0]!r}*cos(t) - {centre[1]!r}*sin(t)")
    body = solve_body(wall, 0.0, cross_check=True)
    assert_clean(body)
    assert body.area == pytest.approx(math.pi / 2, abs=1e-10)
    corners = sorted((c.distance * math.cos(c.direction), c.distance * math.sin(c.direction)) for c in body.corners)
    expected = [(-1 - centre[0], -centre[1]), (1 - centre[0], -centre[1])]
    assert np.max(np.abs(np.array(corners) - np.array(expected))) < 1e-12
    assert distance_to(body, half_disc_support(centre)) < 1e-9
    raised = solve_body(wall, 0.2, cross_check=True)  # breaks at 0 and π, an edge at 3π/2, arcs of radius 0.2
    assert_clean(raised, tol=1e-7)
    assert raised.area == pytest.approx(math.pi / 2 + 0.2 * (math.pi + 2) + math.pi * 0.04, abs=1e-9)


LENS_R, LENS_D = 1.0, 0.6
LENS_S = math.sqrt(LENS_R**2 - LENS_D**2)
LENS = (f"min({LENS_R} - {LENS_D}*abs(cos(t)), {LENS_S!r}*abs(sin(t)) + 5*max(0, abs(cos(t)) - {LENS_D / LENS_R!r}))")
REULEAUX_R = 2 / math.sqrt(3)


def reuleaux_expression():
    """Width 2: h = T(θ) on the vertex windows (cos 3θ ≥ 0), 2 − T(θ + π) on the arcs, with T the support
    function of the triangle of vertices; the min picks the vertex where the added term vanishes."""
    def triangle(shift):
        return nested_max([f"{REULEAUX_R!r}*cos(t{shift} - {a!r})" for a in (0.0, 2 * math.pi / 3, 4 * math.pi / 3)])
    return f"min(2 - {triangle(' + pi')}, {triangle('')} + 4*max(0, -cos(3*t)))"


def lens_support(theta):
    """The lens: for normals within atan2(s, d) of the x axis, the arc of the disc centred on the other
    side, r − d|cos θ|; otherwise the corner (0, ±s), s|sin θ|."""
    on_arc = np.abs(np.cos(theta)) >= LENS_D / LENS_R
    return np.where(on_arc, LENS_R - LENS_D * np.abs(np.cos(theta)), LENS_S * np.abs(np.sin(theta)))


def test_lens_corners_do_not_cross():
    """Two discs of radius 1 centred at (±0.6, 0) intersected: corners (0, ±0.8), C¹ wall with breaks.
    Area 2(r² acos(d/r) − d√(r² − d²)); the outline against the two arcs written down here."""
    body = solve_body(Wall.from_expression(LENS), 0.0, cross_check=True)
    assert_clean(body)
    assert body.regime == "critical" and len(body.corners) == 2
    assert sorted(round(c.distance * math.sin(c.direction), 12) for c in body.corners) == [-LENS_S, LENS_S]
    area = 2 * (LENS_R**2 * math.acos(LENS_D / LENS_R) - LENS_D * LENS_S)
    assert body.area == pytest.approx(area, abs=1e-10)
    assert distance_to(body, lens_support) < 1e-9


def test_reuleaux_triangle_expression():
    """Reuleaux triangle of width 2 as min/max: three corners at 2/√3 with windows of π/3, area (π − √3)·2,
    width 2 in every direction (h(θ) + h(θ + π) of the solved body)."""
    body = solve_body(Wall.from_expression(reuleaux_expression()), 0.0, cross_check=True)
    assert_clean(body)
    assert body.regime == "critical" and len(body.corners) == 3
    assert all(c.distance == pytest.approx(REULEAUX_R, abs=1e-12) for c in body.corners)
    assert all(c.half_width == pytest.approx(math.pi / 6, abs=1e-9) for c in body.corners)
    assert body.area == pytest.approx((math.pi - math.sqrt(3)) * 2, abs=1e-10)
    width = body.outline.support(DENSE) + body.outline.support(DENSE + math.pi)
    assert np.max(np.abs(width - 2)) < 1e-10


CAM_A, CAM_BETA, CAM_LIFT, CAM_BASE = 0.5, 1.5, 0.5, 1.5
CAM = (f"{CAM_BASE} + {CAM_LIFT / 2}*(1 - cos(pi*(arccos(min(max(cos(t), {math.cos(CAM_A + CAM_BETA)!r}), "
       f"{math.cos(CAM_A)!r})) - {CAM_A})/{CAM_BETA}))")


def cam_lift(theta):
    """Flat-faced follower: dwell at the base circle for |θ| < a, a simple-harmonic rise of 0.5 over β,
    dwell at the top up to π; symmetric about the body axis (the law as a designer writes it)."""
    u = np.abs(np.angle(np.exp(1j * theta)))
    s = np.clip((u - CAM_A) / CAM_BETA, 0.0, 1.0)
    return CAM_BASE + CAM_LIFT / 2 * (1 - np.cos(math.pi * s))


@pytest.mark.parametrize("b0", [0.0, -0.45])
def test_shm_cam(b0):
    """The cam's support function is the lift law: breaks (the acceleration jumps) where the rise starts
    and ends; the body's wall is the law to 1e-9, both solvers agree."""
    body = solve_body(Wall.from_expression(CAM), b0, cross_check=True)
    assert_clean(body, tol=1e-7)
    assert body.regime == "convex" and not body.corners
    assert np.max(np.abs(body.outline.support(DENSE) - (b0 + cam_lift(DENSE)))) < 1e-9


def test_superellipse_with_flat_points():
    """|x|⁴ + |y|⁴ ≤ 1 has support function (|cos θ|^{4/3} + |sin θ|^{4/3})^{3/4}; ρ = h + h'' → ∞ at its
    four flat points.  Area 4Γ(5/4)²/Γ(3/2); the support values from the curve's own normal (the gradient
    (x³, y³) of |x|⁴ + |y|⁴ is parallel to n(θ) where x³ ∝ cos θ)."""
    body = solve_body(Wall.from_expression("(abs(cos(t))**(4/3) + abs(sin(t))**(4/3))**(3/4)"), 0.0,
                      cross_check=True)
    assert_clean(body, tol=1e-6)
    assert body.regime == "convex" and not body.corners and body.max_wall_error < 1e-6
    assert body.area == pytest.approx(4 * math.gamma(1.25) ** 2 / math.gamma(1.5), abs=1e-6)
    # the boundary point of normal θ, from the curve itself: x ∝ sgn(cos θ)|cos θ|^{1/3}, y alike, scaled
    # onto |x|⁴ + |y|⁴ = 1; its projection on n(θ) is the true support value
    c, s = np.cos(DENSE), np.sin(DENSE)
    x, y = np.sign(c) * np.abs(c) ** (1 / 3), np.sign(s) * np.abs(s) ** (1 / 3)
    scale = (x**4 + y**4) ** -0.25
    assert distance_to(body, lambda theta: scale * (x * c + y * s)) < 1e-6


@pytest.mark.parametrize("text", [polygon_expression(NONAGON), LENS, CAM,
                                  "(abs(cos(t))**(4/3) + abs(sin(t))**(4/3))**(3/4)"])
def test_command_line_exit_zero_without_warning(text, capsys):
    assert main(["solve", text]) == 0
    captured = capsys.readouterr()
    assert "warning" not in captured.out + captured.err
