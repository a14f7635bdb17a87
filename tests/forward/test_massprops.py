"""Mass properties (scikit-fem and exact Green's theorem) and realizability, against closed forms."""

import math

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward import Outline, Wall
from coinwall.forward.errors import InvalidArgument, InvalidExpression, InvalidOutline
from coinwall.forward.massprops import mass_properties, outline_moments
from coinwall.inverse import solve_body
from coinwall.inverse.realizability import kappa_max, realizability, self_consistent_offset

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def circle(radius=1.0, n=256):
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    pts = radius * np.column_stack([np.cos(a), np.sin(a)])
    tangent = radius * np.column_stack([-np.sin(a), np.cos(a)])
    return Outline.from_hermite(pts, tangent, tangent, np.full(n, 2 * np.pi / n))


@pytest.fixture(scope="module")
def ellipse_body():
    return solve_body(Wall.from_expression(ELLIPSE, {"eps": 1}), 0.0)  # semi-axes 1, 1/sqrt(2)


def h_closed_forms(wall, b0, n=4096):
    """Area and polar moment from the support function h = b0 + b (DESIGN.md), periodic trapezoid."""
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    b, d1, d2 = wall.derivatives(phi)
    h = b0 + b
    w = 2 * np.pi / n
    area = 0.5 * np.sum(h * h - d1 * d1) * w
    polar = 0.25 * np.sum((h * h + d1 * d1) * h * (h + d2)) * w
    return area, polar


def test_ellipse_uniform_against_closed_forms(ellipse_body):
    a, b = 1.0, 1 / math.sqrt(2)
    exact = outline_moments(ellipse_body.outline)
    fem = mass_properties(ellipse_body.outline, boundary=4096)
    area_h, polar_h = h_closed_forms(ellipse_body.wall, 0.0)
    from shapely.geometry import Polygon

    shapely_area = Polygon(ellipse_body.outline.polygon(8)).area
    assert area_h == pytest.approx(math.pi * a * b, rel=1e-12)
    assert polar_h == pytest.approx(math.pi * a * b * (a * a + b * b) / 4, rel=1e-12)
    assert exact.area == pytest.approx(math.pi * a * b, rel=1e-9)
    # uniform ellipse κ² = (a² + b²)/4 (DESIGN.md)
    assert exact.kappa ** 2 == pytest.approx((a * a + b * b) / 4, rel=1e-9)
    assert shapely_area == pytest.approx(exact.area, rel=1e-6)  # inscribed polygon: O(N⁻²) below
    # FEM over the inscribed polygon with 4096 boundary points: chord error ~ (π/4096)²/2 relative
    assert fem.area == pytest.approx(exact.area, rel=2e-6)
    assert fem.kappa ** 2 == pytest.approx((a * a + b * b) / 4, rel=2e-6)
    assert fem.centre_offset < 1e-12


def test_fem_converges_at_second_order(ellipse_body):
    errors = []
    for n in (1024, 2048, 4096):
        fem = mass_properties(ellipse_body.outline, boundary=n)
        errors.append(abs(fem.kappa ** 2 - 0.375))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 2) < 0.1)  # polygonal domain: error ∝ N⁻²


def test_disc_with_heavy_rim():
    """ρ = 1 + c r^n on the unit disc.

    M = 2π∫(1 + c r^n) r dr = π(1 + 2c/(n+2)),  I = 2π∫(1 + c r^n) r³ dr = 2π(1/4 + c/(n+4)),
    κ² = I/M = (1/4 + c/(n+4)) / (1/2 + c/(n+2)).
    """
    c, n = 4.0, 8
    props = mass_properties(circle(1.0, 512), "1 + c*r**8", {"c": c}, boundary=4096, interior=64)
    mass = math.pi * (1 + 2 * c / (n + 2))
    kappa2 = (0.25 + c / (n + 4)) / (0.5 + c / (n + 2))
    assert props.mass == pytest.approx(mass, rel=1e-5)
    assert props.kappa ** 2 == pytest.approx(kappa2, rel=1e-5)
    assert props.kappa ** 2 > 0.5  # heavier than the uniform disc's 1/2


def test_polygons_exact():
    """Polygons are meshed exactly and the density is polynomial: FEM = closed forms to rounding.

    Rectangle w × h: κ² = (w² + h²)/12.  Triangle with sides a, b, c: κ² about the centroid
    = (a² + b² + c²)/36.  Linear density ρ = x on [0, 1]²: mass 1/2, centre (2/3, 1/2).
    """
    rect = Outline.from_polygon([[0, 0], [3, 0], [3, 1], [0, 1]])
    props = mass_properties(rect)
    assert props.kappa ** 2 == pytest.approx((9 + 1) / 12, rel=1e-12)
    assert props.centre == pytest.approx((1.5, 0.5), rel=1e-12)
    assert outline_moments(rect).kappa ** 2 == pytest.approx(10 / 12, rel=1e-12)
    tri_pts = np.array([[0, 0], [4, 0], [1, 3]], float)
    tri = Outline.from_polygon(tri_pts)
    sides = np.hypot(*(tri_pts - np.roll(tri_pts, 1, axis=0)).T)
    assert mass_properties(tri).kappa ** 2 == pytest.approx(np.sum(sides ** 2) / 36, rel=1e-12)
    square = Outline.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    lin = mass_properties(square, "x")
    assert lin.mass == pytest.approx(0.5, rel=1e-12) and lin.centre == pytest.approx((2 / 3, 0.5), rel=1e-12)


def test_bad_density():
    disc = circle()
    with pytest.raises(InvalidArgument, match="negative"):
        mass_properties(disc, "1 - 2*r")
    with pytest.raises(InvalidExpression):
        mass_properties(disc, "__import__('os')")
    with pytest.raises(InvalidExpression, match="density variable"):
        mass_properties(disc, "1 + t")
    for spaced in ("2\u2009", "\u00a01 + r"):  # non-ASCII spaces are refused as in a wall, even at the ends
        with pytest.raises(InvalidExpression, match="not allowed; use plain ASCII"):
            mass_properties(disc, spaced)
    with pytest.raises(InvalidOutline):
        mass_properties(Outline.from_polygon([[-1, 0], [1, 0]]))


def test_kappa_max_closed_forms(ellipse_body):
    # ellipse with semi-axes a >= b centred: κ_max = a; equilateral triangle, circumradius R: κ_max = R
    km, support = kappa_max(ellipse_body.outline)
    assert km == pytest.approx(1.0, rel=1e-9)
    assert np.allclose(np.sort(np.abs(support[:, 0])), 1.0, atol=1e-6)
    angles = np.pi / 2 + 2 * np.pi / 3 * np.arange(3)
    km, support = kappa_max(Outline.from_polygon(2 * np.column_stack([np.cos(angles), np.sin(angles)])))
    assert km == pytest.approx(2.0, rel=1e-12) and len(support) == 3
    assert np.allclose(support[:, 2], 1 / 3)
    shifted = Outline.from_polygon([[1, 1], [2, 1], [2, 2], [1, 2]])  # origin outside
    assert math.isnan(kappa_max(shifted)[0])


def test_realizability_and_self_consistent_offset(ellipse_body):
    r = realizability(ellipse_body)
    assert r.kappa_uniform == pytest.approx(math.sqrt(0.375), rel=1e-9)
    assert r.centroid_offset < 1e-12 and r.realizable and not r.uniform_consistent
    wall = Wall.from_expression(ELLIPSE, {"eps": 1})
    sc = self_consistent_offset(wall)
    assert len(sc.offsets) == 1 and sc.b0 is not None
    at = realizability(solve_body(wall, sc.b0))
    assert at.kappa_uniform == pytest.approx(1.0, abs=1e-9) and at.uniform_consistent
    # a wall shifted by 0.1 sin θ is the same body translated by 0.1 along y: κ = 1 at the same b0,
    # but the centroid stays 0.1 from the origin, so no b0 makes the uniform body self-consistent
    shifted = self_consistent_offset(Wall.from_expression(ELLIPSE + "+0.1*sin(t)", {"eps": 1}))
    assert shifted.offsets[0] == pytest.approx(sc.b0, abs=1e-8)
    assert shifted.centroid_offsets[0] == pytest.approx(0.1, abs=1e-9) and shifted.b0 is None


def test_mass_cli(tmp_path, capsys):
    body = str(tmp_path / "b.json")
    assert main(["solve", ELLIPSE, "--param", "eps=1", "-o", body]) == 0
    capsys.readouterr()
    assert main(["mass", body, "--density", "1+c*r**2", "--param", "c=1", "--json"]) == 0
    import json

    doc = json.loads(capsys.readouterr().out)
    assert doc["uniform"]["kappa"] == pytest.approx(math.sqrt(0.375), rel=1e-9)
    assert doc["kappa_max"] == pytest.approx(1.0, rel=1e-9) and doc["realizable"]
    assert main(["mass", body, "--density", "x"]) == 2
    err = capsys.readouterr().err
    assert "negative" in err and err.count("\n") == 1
