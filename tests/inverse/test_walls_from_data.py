"""Walls from data: sampled, drawn, polygonal and noisy walls give right answers, or say why not.

Reference values come from independent computations written here with numpy: a convex polygon's
support function ``h(θ) = max_k v_k·n(θ)``, the superellipse's support function in closed form
(the dual norm), the rounded rectangle's ``max_k c_k·n(θ) + r``, scipy's ``HalfspaceIntersection``
for the largest body under sampled lines, and the paper's ellipse wall (eq. 18, b_c = −1/2 at ε = 1).
"""

import json

import numpy as np
import pytest

from coinwall import Wall, critical_offset, solve_body
from coinwall.cases.cli.main import main
from coinwall.forward.formats.wallfile import rounding_of
from coinwall.inverse.discrete import discrete_curvature, halfspace_polygon
from coinwall.inverse.fit import fit_convex

THETA720 = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
DENSE = np.linspace(0.0, 2 * np.pi, 20011, endpoint=False)


def polygon_support(vertices, theta):
    return np.max(np.asarray(vertices) @ np.stack([np.cos(theta), np.sin(theta)]), axis=0)


def random_convex_polygon(rng, count):
    """Vertices of a random convex polygon around the origin (sorted angles, radii in [0.6, 1.2]), the
    convex hull taken so that every vertex is a true corner."""
    from scipy.spatial import ConvexHull

    angles = np.sort(rng.uniform(0, 2 * np.pi, count))
    radii = rng.uniform(0.6, 1.2, count)
    points = np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1)
    return points[ConvexHull(points).vertices]


def match_vertices(found, vertices):
    """Largest distance from a true vertex to the nearest found corner, and from a corner to a vertex."""
    d = np.hypot(*(found[:, None, :] - vertices[None, :, :]).transpose(2, 0, 1))
    return max(d.min(axis=0).max(), d.min(axis=1).max())


def corner_points(body):
    return np.array([[c.distance * np.cos(c.direction), c.distance * np.sin(c.direction)] for c in body.corners])


# ---------------------------------------------------------------------------------------------------- discrete geometry
def test_discrete_curvature_closed_forms():
    """ρ_i is exact for a circle (circumscribed polygon: ℓ = r(tan Δ₋/2 + tan Δ₊/2)) on any grid, adding
    b0 to every h adds b0 to every ρ, and it is 0 on the samples of a polygon inside vertex windows."""
    rng = np.random.default_rng(0)
    theta = np.sort(rng.uniform(0, 2 * np.pi, 300))
    rho, tol = discrete_curvature(theta, np.full(theta.size, 1.7))
    np.testing.assert_allclose(rho, 1.7, rtol=0, atol=1e-9)
    rho_shifted, _ = discrete_curvature(theta, np.full(theta.size, 1.7) + 0.25)
    np.testing.assert_allclose(rho_shifted - rho, 0.25, rtol=0, atol=1e-9)
    triangle = np.array([[1.0, 0.0], [-0.4, 0.9], [-0.6, -0.7]])
    rho, tol = discrete_curvature(THETA720, polygon_support(triangle, THETA720))
    assert np.sum(np.abs(rho) <= tol) >= 720 - 6  # two samples flank each of the three edge normals
    assert np.all(rho >= -tol)


def test_rounding_is_read_from_the_digits():
    values = np.round(np.linspace(0.1, 0.9, 50) + 1e-3 * np.sin(np.arange(50)), 6)
    assert np.all(rounding_of(values) == pytest.approx(5e-7))
    exact = np.sqrt(np.linspace(0.1, 0.9, 50))
    assert np.all(rounding_of(exact) < 1e-15)


@pytest.mark.parametrize("seed,count", [(1, 3), (2, 6), (3, 11), (4, 25), (5, 40)])
def test_sampled_random_polygons_come_back_exactly(seed, count):
    """A convex polygon sampled at 720 angles: its vertices to ~1e-9 of its size, regime critical
    (b_c = 0 within tolerance), every vertex whose window holds two samples or more a corner with zero
    deficit, and nothing else; the outline within its outline tolerance of the polygon everywhere."""
    rng = np.random.default_rng(seed)
    vertices = random_convex_polygon(rng, count)
    wall = Wall.from_samples(THETA720, polygon_support(vertices, THETA720))
    body = solve_body(wall, 0.0, cross_check=True)
    assert body.regime == "critical" and abs(body.b_c) <= max(body.b_c_tolerance, 1e-9)
    edges = np.roll(vertices, -1, axis=0) - vertices
    normals = np.mod(np.arctan2(-edges[:, 0], edges[:, 1]), 2 * np.pi)
    # the sample lines through each vertex: those whose angle lies in its normal cone; every body within the
    # samples turns through the window of the lines strictly inside, so a forced corner needs four (two inside):
    # with fewer the vertex may be a vertex of the body but not a corner the data can vouch for
    start = np.roll(normals, 1)
    width = np.mod(normals - start, 2 * np.pi)
    through = np.array([np.sum(np.mod(THETA720 - s, 2 * np.pi) <= w) for s, w in zip(start, width)])
    seen = through >= 4
    dense = body.wall_of_body(DENSE) - polygon_support(vertices, DENSE)
    assert np.max(np.abs(dense)) <= body.outline_tolerance  # the band holds the truth
    if seen.all():  # every vertex forced: the body is the polygon
        assert np.max(np.abs(dense)) < 1e-9
    found = corner_points(body)
    assert len(found) == seen.sum()
    assert match_vertices(found, vertices[seen]) < 1e-9
    assert all(c.max_deficit == 0.0 for c in body.corners)
    assert body.convex and body.valid and not body.warnings
    assert body.max_wall_error < 1e-12 and body.cross_check < 1e-12


def test_sampled_polygon_body_is_inside_the_largest_body_and_exact_at_samples():
    """Against scipy's HalfspaceIntersection (an independent construction of the largest body under the
    sampled lines): equal at every sample, never outside it, and every vertex of ours is a vertex of the
    polygon (the edges between vertex windows replace its slivers)."""
    rng = np.random.default_rng(7)
    vertices = random_convex_polygon(rng, 9)
    h = polygon_support(vertices, THETA720)
    body = solve_body(Wall.from_samples(THETA720, h), 0.0)
    largest = halfspace_polygon(THETA720, h)
    ours_dense = body.wall_of_body(DENSE)
    largest_dense = polygon_support(largest, DENSE)
    assert np.all(ours_dense <= largest_dense + 1e-12)
    np.testing.assert_allclose(body.wall_of_body(THETA720), h, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ours_dense, polygon_support(vertices, DENSE), rtol=0, atol=1e-9)


def test_rounded_data_of_a_polygon_are_critical_within_their_accuracy():
    """The same triangle written with 6 decimals (a file: the rounding is read off its digits): critical
    within the rounding's tolerance, three corners within ~1e-6 of the vertices."""
    triangle = np.array([[1.0, 0.0], [-0.4, 0.9], [-0.6, -0.7]])
    h = np.round(polygon_support(triangle, THETA720), 6)
    body = solve_body(Wall.from_samples(THETA720, h, rounding=rounding_of(h)), 0.0, cross_check=True)
    assert body.regime == "critical" and abs(body.b_c) <= body.b_c_tolerance
    assert 1e-3 < body.b_c_tolerance < 0.1  # 6 decimals at 0.5° spacing: ~4·5e-7/Δ²
    assert match_vertices(corner_points(body), triangle) < 1e-6
    assert not body.warnings


def test_ellipse_samples_keep_the_formula_accuracy():
    """Paper eq. 18 at ε = 1 sampled at 720 angles (uniform, and shifted off θ = 0): b_c = −1/2 to 1e-6."""
    for shift in (0.0, 0.003):
        theta = THETA720 + shift
        wall = Wall.from_samples(theta, np.sqrt((1 + np.cos(theta) ** 2) / 2))
        assert critical_offset(wall).b_c == pytest.approx(-0.5, abs=1e-6)
        body = solve_body(wall, 0.0, cross_check=True)
        assert body.regime == "convex" and body.method == "envelope" and not body.corners
        assert body.max_wall_error < 1e-9 and not body.warnings


def test_superellipse_is_convex_with_no_corners():
    """|x|⁴ + |y|⁴ = 1 has support function (|cos θ|^{4/3} + |sin θ|^{4/3})^{3/4} (the dual norm): a smooth
    convex body, b_c < 0 (its smallest radius of curvature is positive), no corners.  The reference b_c
    is the formula wall's, from casadi's exact derivatives."""
    expression = "(abs(cos(t))**(4/3) + abs(sin(t))**(4/3))**(3/4)"
    reference = critical_offset(Wall.from_expression(expression)).b_c
    h = (np.abs(np.cos(THETA720)) ** (4 / 3) + np.abs(np.sin(THETA720)) ** (4 / 3)) ** 0.75
    wall = Wall.from_samples(THETA720, h)
    body = solve_body(wall, 0.0, cross_check=True)
    assert body.regime == "convex" and not body.corners
    assert body.b_c < 0 and body.b_c == pytest.approx(reference, abs=max(body.b_c_tolerance, 1e-6))
    assert body.convex and body.valid and not body.warnings
    assert np.max(np.abs(body.wall_of_body(THETA720) - h)) < 1e-9


def test_rounded_rectangle_has_no_spike():
    """A 2×1 rectangle with corners rounded (r = 0.2): convex, valid, exact at the samples, no corners
    (its wall has kinks at the flat sides' normals: edges, not corners), b_c = −r from the arcs."""
    r = 0.2
    centres = np.array([[0.8, 0.3], [-0.8, 0.3], [-0.8, -0.3], [0.8, -0.3]])
    h = polygon_support(centres, THETA720) + r
    body = solve_body(Wall.from_samples(THETA720, h), 0.0, cross_check=True)
    assert body.regime == "convex" and body.b_c == pytest.approx(-r, abs=body.b_c_tolerance + 1e-9)
    assert body.convex and body.valid and not body.warnings and not body.corners
    np.testing.assert_allclose(body.wall_of_body(THETA720), h, rtol=0, atol=1e-12)
    # between samples: a polygon inside the samples' band, within the outline tolerance of the truth (the
    # roof over the flat sides' kinks: up to E·Δ/4 ≈ 2e-3 for a side of length E = 1.6 at Δ = 0.5°)
    excess = body.wall_of_body(DENSE) - (polygon_support(centres, DENSE) + r)
    assert np.max(np.abs(excess)) <= body.outline_tolerance < 2.5e-3


def test_case_three_from_samples():
    """Ellipse samples below b_c: corners with positive deficits at 0 and π, the body under every line."""
    h = np.sqrt((1 + np.cos(THETA720) ** 2) / 2)
    body = solve_body(Wall.from_samples(THETA720, h), -0.6)
    assert body.regime == "corner" and len(body.corners) == 2
    assert all(c.max_deficit > 0 for c in body.corners)
    # up to the outline's own interpolation error (the smooth path's Bézier outline)
    assert np.all(body.wall_of_body(THETA720) <= h + 2 * body.max_wall_error)


# ---------------------------------------------------------------------------------------------------- least squares
def test_fit_recovers_an_exact_polygon_and_follows_noise():
    triangle = np.array([[1.0, 0.0], [-0.4, 0.9], [-0.6, -0.7]])
    fit = fit_convex(THETA720, polygon_support(triangle, THETA720))
    assert fit.rms_residual < 1e-12 and len(fit.body.corners) == 3
    assert match_vertices(corner_points(fit.body), triangle) < 1e-9


@pytest.mark.parametrize("sigma", [0.003, 0.01, 0.03])
def test_fit_error_against_noise(sigma):
    """1,000 noisy samples of the ellipse wall: the residual is the noise (rms within 10 % of σ, as a
    least-squares fit with far fewer effective parameters than samples must give), the fitted wall is
    convex (ρ ≥ 0 to rounding) and nearer the truth than the data (max error below 3σ)."""
    rng = np.random.default_rng(11)
    truth = np.sqrt((1 + np.cos(THETA720) ** 2) / 2)
    fit = fit_convex(THETA720, truth + sigma * rng.standard_normal(THETA720.size))
    assert fit.rms_residual == pytest.approx(sigma, rel=0.1)
    rho, tol = discrete_curvature(fit.theta, fit.fitted)
    assert np.all(rho >= -tol - 1e-9 / (2 * np.pi / 720) ** 2)
    assert np.max(np.abs(fit.fitted - truth)) < 3 * sigma
    assert fit.body.convex and fit.body.valid


def test_fit_refuses_what_it_cannot_do():
    with pytest.raises(ValueError, match="at least 8"):
        fit_convex([0, 1, 2], [1, 1, 1])
    with pytest.raises(ValueError, match="at most"):
        fit_convex(np.linspace(0, 6.28, 2500), np.ones(2500))


# ---------------------------------------------------------------------------------------------------- reading data
def _write(path, text):
    path.write_text(text)
    return str(path)


def test_a_file_carries_its_rounding(tmp_path, capsys):
    """Values written with 6 decimals are rounded at the 6th: the certified interval of b_c says so (it
    holds the truth, 0 for a polygon, and is far wider than the face-value rounding allows: a half-width of
    5e-7 moves the discrete curvature by ~4·5e-7/Δ² at the spacing Δ the interval is computed on); the same
    values given as an array are taken at face value."""
    triangle = np.array([[1.0, 0.0], [-0.4, 0.9], [-0.6, -0.7]])
    h = polygon_support(triangle, THETA720)
    path = _write(tmp_path / "tri6.csv", "theta,b\n" + "".join(f"{float(a)!r},{v:.6f}\n" for a, v in zip(THETA720, h)))
    assert main(["critical", path, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    tolerance = doc["b_c_tolerance"]
    assert doc["b_c_lower"] <= 0.0 <= doc["b_c_upper"]
    assert 4 * 5e-7 / 0.5**2 < tolerance < 0.1
    # the same numbers as an array: no rounding is assumed, only the spacing term remains
    assert critical_offset(Wall.from_samples(THETA720, np.round(h, 6))).b_c_tolerance < tolerance / 2


def test_csv_variants(tmp_path, capsys):
    degrees = np.arange(0, 360, 2.0)
    b = np.sqrt((1 + np.cos(np.radians(degrees)) ** 2) / 2)
    files = {
        "deg.csv": "Theta (deg),b\n" + "".join(f"{a},{v}\n" for a, v in zip(degrees, b)),
        "deg_name.csv": "theta_deg,b\n" + "".join(f"{a},{v}\n" for a, v in zip(degrees, b)),
        "three.csv": "i,theta,b\n" + "".join(f"{i},{float(np.radians(a))!r},{float(v)!r}\n" for i, (a, v) in enumerate(zip(degrees, b))),
        "semicolon.csv": "theta;b\n" + "".join(f"{float(np.radians(a))!r};{float(v)!r}\n".replace(".", ",") for a, v in zip(degrees, b)),
    }
    for name, text in files.items():
        assert main(["critical", _write(tmp_path / name, text), "--json"]) == 0, name
        doc = json.loads(capsys.readouterr().out)
        assert doc["b_c"] == pytest.approx(-0.5, abs=max(doc["b_c_tolerance"], 1e-6)), name
    plain = _write(tmp_path / "plain.csv", "".join(f"{a},{v}\n" for a, v in zip(degrees, b)))
    assert main(["critical", plain]) == 2
    assert "degrees" in capsys.readouterr().err
    assert main(["critical", plain, "--degrees", "--json"]) == 0
    capsys.readouterr()


@pytest.mark.parametrize("text,needle", [
    ("theta,b\n0,1\n0.5,x\n", "line 3"),
    ("1\n2\n3\n", "columns"),
    ("x,y\n0,1\n1,1\n", "looks like a body file (columns x, y)"),
    ("", "no rows"),
])
def test_bad_csv_is_one_line(text, needle, tmp_path, capsys):
    assert main(["critical", _write(tmp_path / "w.csv", text)]) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1


def test_missing_file_and_drawing_are_named(tmp_path, capsys):
    assert main(["solve", str(tmp_path / "none.csv")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["solve", "body.svg"]) == 2
    assert "coinwall wall" in capsys.readouterr().err


def test_drawn_triangle_round_trip(tmp_path, capsys):
    """A triangle drawn in SVG → `coinwall wall` → `coinwall solve`: critical at b0 = 0, its three
    vertices (about the centroid, in units of its κ) as corners with zero deficit."""
    triangle = np.array([[10.0, 10.0], [60.0, 20.0], [25.0, 55.0]])
    svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
           f'<polygon points="{" ".join(f"{x},{y}" for x, y in triangle)}"/></svg>')
    drawing = _write(tmp_path / "tri.svg", svg)
    wall_csv = str(tmp_path / "tri.csv")
    assert main(["wall", drawing, "-o", wall_csv]) == 0
    capsys.readouterr()
    assert main(["solve", wall_csv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["regime"] == "critical" and len(doc["corners"]) == 3
    assert all(c["max_deficit"] == 0.0 for c in doc["corners"])
    assert doc["convex"] and doc["valid"] and not doc["warnings"]


def test_fit_cli_writes_a_reusable_wall(tmp_path, capsys):
    rng = np.random.default_rng(5)
    theta = np.sort(rng.uniform(0, 2 * np.pi, 400))
    b = np.sqrt((1 + np.cos(theta) ** 2) / 2) + 0.01 * rng.standard_normal(theta.size)
    samples = _write(tmp_path / "scan.csv", "theta,b\n" + "".join(f"{float(t)!r},{float(v)!r}\n" for t, v in zip(theta, b)))
    fitted = str(tmp_path / "fitted-wall.csv")
    body = str(tmp_path / "body.json")
    assert main(["fit", samples, "-o", fitted, "-o", body, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["rms_residual"] == pytest.approx(0.01, rel=0.15)
    assert {"rms_residual", "max_residual", "regime", "corners"} <= set(doc)
    assert json.loads(open(body).read())["outline"]
    assert main(["solve", fitted, "--json"]) in (0, 1)
    assert json.loads(capsys.readouterr().out)["convex"]


# ---------------------------------------------------------------------------------------------------- what bodies are made of
def test_real_size_drawing_of_an_unrealizable_body_is_refused(tmp_path, capsys):
    """κ_max of the Appendix Case III body is 0.374 κ (coinwall mass): no part of that size has that
    wall; the drawing is refused unless asked for, and nothing is written."""
    out = tmp_path / "body.dxf"
    assert main(["solve", "case:appendix-corner", "-o", str(out), "--kappa", "20", "--units", "mm"]) == 2
    err = capsys.readouterr().err
    assert "κ_max" in err and "self-consistent" in err and not out.exists()
    assert main(["solve", "case:appendix-corner", "-o", str(out), "--kappa", "20", "--units", "mm",
                 "--allow-unrealizable"]) == 0
    assert out.exists()
    capsys.readouterr()
    assert main(["solve", "case:appendix-corner", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["realizable"] is False and doc["kappa_max"] == pytest.approx(0.374, abs=1e-3)


def test_warnings_exit_1(capsys):
    """A body whose check fails (too few nodes for the accuracy) is a warning on stderr and exit 1."""
    assert main(["solve", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=99", "--points", "16"]) == 1
    captured = capsys.readouterr()
    assert "warning:" in captured.err
    assert main(["solve", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=99", "--points", "16", "--json"]) == 1
    assert json.loads(capsys.readouterr().out)["warnings"]


def test_nearest_least_squares_below_b_c(capsys):
    assert main(["solve", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=1", "--b0", "-0.6",
                 "--nearest", "least-squares", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["nearest"] == "least-squares" and doc["rms_residual"] > 0 and doc["convex"]


def test_export_reports_and_guards_realizability(tmp_path, capsys):
    """`export` of a stored body: κ of the uniform body and κ_max in its report (Fig. 4 body: κ_max = 0.5 κ,
    the distance of its farthest point, b0 + 1), and a real-size drawing of it is refused."""
    stored = str(tmp_path / "fig4.json")
    assert main(["solve", "-o", stored]) == 0
    capsys.readouterr()
    assert main(["export", stored, "-o", str(tmp_path / "f.svg"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["kappa_max"] == pytest.approx(0.5, abs=1e-6) and doc["realizable"] is False
    assert main(["export", stored, "-o", str(tmp_path / "f.dxf"), "--kappa", "10", "--units", "mm"]) == 2
    assert "κ_max" in capsys.readouterr().err and not (tmp_path / "f.dxf").exists()
