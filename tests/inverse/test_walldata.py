"""The reference generators of ``tests/walldata.py`` checked against closed forms and independent constructions.

Nothing here imports coinwall: these tests make sure the truth the walls-from-data tests compare with is
itself right (support functions at vertex normals, constant width, cam laws, curvature radii, areas).
"""

import io

import numpy as np
import pytest
from walldata import (
    IRREGULAR_9GON,
    MT_PEAK,
    area_from_support,
    cam,
    cam_law,
    discrete_rho,
    noisy,
    polygon,
    random_angles,
    random_polygon,
    reuleaux,
    reuleaux_outline,
    smooth,
    true_b_c_dense,
    with_duplicates,
    write_rounded,
)

RNG_THETA = random_angles(400, seed=3)


def fd2(fun, x, step=1e-4):
    return (fun(x - step) - 2 * fun(x) + fun(x + step)) / step**2


def fd1(fun, x, step=1e-6):
    return (fun(x + step) - fun(x - step)) / (2 * step)


def away_from(theta, breaks, margin):
    d = np.abs(np.angle(np.exp(1j * (theta[:, None] - np.asarray(breaks)[None, :]))))
    return theta[d.min(axis=1) > margin]


# ---------------------------------------------------------------------------------------------------- polygons
def test_polygon_support_is_the_vertex_projection_on_its_window():
    """On each vertex's window (between the normals of its two edges) h = v_k·n and every other vertex is
    strictly lower; at an edge normal both ends of the edge project to h. The default 9-gon has its
    centroid off the origin and the origin well inside."""
    ref = polygon(None, 720)
    v = ref.vertices
    m = len(v)
    edges = np.roll(v, -1, axis=0) - v
    normals = np.arctan2(-edges[:, 0], edges[:, 1])  # outward normal of edge k (from v_k to v_{k+1})
    for k in range(m):
        lo, hi = normals[k - 1], normals[k]
        span = np.mod(hi - lo, 2 * np.pi)
        assert 0 < span < np.pi
        inside = lo + span * np.linspace(0.01, 0.99, 25)
        n = np.stack([np.cos(inside), np.sin(inside)])
        np.testing.assert_allclose(ref.b_of(inside), v[k] @ n, rtol=0, atol=1e-15)
        others = np.delete(v, k, axis=0) @ n
        assert np.all(others < v[k] @ n - 1e-6)
    n = np.stack([np.cos(normals), np.sin(normals)])
    np.testing.assert_allclose(np.sum(v * n.T, axis=1), np.sum(np.roll(v, -1, axis=0) * n.T, axis=1), atol=1e-14)
    np.testing.assert_allclose(ref.b_of(normals), np.sum(v * n.T, axis=1), atol=1e-15)
    np.testing.assert_allclose(np.sort(np.mod(normals, 2 * np.pi)), ref.breaks, atol=1e-15)
    assert ref.b_c == 0.0 and ref.corners == m == 9
    assert ref.b.min() > 0.5 and np.hypot(*ref.centroid) > 0.2
    np.testing.assert_array_equal(ref.vertices, IRREGULAR_9GON)


def test_polygon_curvature_and_area():
    """ρ = h + h'' vanishes on the windows (finite differences of h alone: b_c = 0), h' matches a central
    difference, and ½∮(h² − h'²) equals the shoelace area (and n sin(2π/n)/2 for the regular n-gon)."""
    for ref in (polygon(None, 720), polygon(random_polygon(7, seed=5), 360), polygon(5, 360, phase=0.3)):
        assert abs(true_b_c_dense(ref.b_of, ref.breaks)[0]) < 1e-6
        theta = away_from(RNG_THETA, ref.breaks, 1e-4)
        np.testing.assert_allclose(fd1(ref.b_of, theta), ref.d1b_of(theta), atol=1e-8)
        np.testing.assert_allclose(ref.rho(theta), 0.0, atol=1e-14)
        assert area_from_support(ref.b_of, ref.d1b_of, ref.breaks) == pytest.approx(ref.area, rel=1e-13)
    assert polygon(5, 10).area == pytest.approx(5 * np.sin(2 * np.pi / 5) / 2, rel=1e-14)
    # without the breaks the quadrature would straddle the kinks: it must not agree as well
    ref = polygon(None, 10)
    assert abs(area_from_support(ref.b_of, ref.d1b_of, (), pieces=3, nodes=8) - ref.area) > 1e-8


def test_random_angles_polygon_samples():
    ref = polygon(None, 200, random_angles=True, seed=4)
    assert np.all(np.diff(ref.theta) > 0) and 0 <= ref.theta[0] and ref.theta[-1] < 2 * np.pi
    np.testing.assert_array_equal(ref.b, ref.b_of(ref.theta))
    assert not np.allclose(np.diff(ref.theta), np.diff(ref.theta).mean())


# ---------------------------------------------------------------------------------------------------- Reuleaux
@pytest.mark.parametrize("n", [3, 5, 7])
def test_reuleaux_constant_width_and_construction(n):
    """h(θ) + h(θ+π) = w everywhere; h is the support function of the boundary built from its arcs (each
    centred at a vertex, radius w, joining the two opposite vertices); opposite vertices are w apart;
    ρ is 0 on the vertex windows and w on the arcs; the area matches ½∮(h² − h'²) and, for n = 3,
    (π − √3)w²/2."""
    width = 1.7
    ref = reuleaux(n, 360, width=width, phase=0.2)
    np.testing.assert_allclose(ref.b_of(RNG_THETA) + ref.b_of(RNG_THETA + np.pi), width, rtol=0, atol=1e-14)
    outline = reuleaux_outline(n, width, phase=0.2)
    n_dir = np.stack([np.cos(RNG_THETA), np.sin(RNG_THETA)])
    support = (outline @ n_dir).max(axis=0)
    np.testing.assert_allclose(ref.b_of(RNG_THETA), support, rtol=0, atol=2e-6)
    assert np.all(support <= ref.b_of(RNG_THETA) + 1e-14)
    v = ref.vertices
    m = (n - 1) // 2
    np.testing.assert_allclose(np.hypot(*(v - np.roll(v, -m, axis=0)).T), width, rtol=1e-14)
    theta = away_from(RNG_THETA, ref.breaks, 1e-3)
    rho = fd2(ref.b_of, theta, 1e-4) + ref.b_of(theta)
    assert np.all((np.abs(rho) < 1e-5) | (np.abs(rho - width) < 1e-5))
    assert np.sum(np.abs(rho) < 1e-5) > 50 and np.sum(np.abs(rho - width) < 1e-5) > 50
    np.testing.assert_allclose(ref.rho(theta), np.where(rho > width / 2, width, 0.0), atol=1e-13)
    np.testing.assert_allclose(fd1(ref.b_of, theta), ref.d1b_of(theta), atol=1e-8)
    assert area_from_support(ref.b_of, ref.d1b_of, ref.breaks) == pytest.approx(ref.area, rel=1e-13)
    if n == 3:
        assert ref.area == pytest.approx((np.pi - np.sqrt(3)) * width**2 / 2, rel=1e-14)
    assert ref.b_c == 0 and ref.corners == n and abs(true_b_c_dense(ref.b_of, ref.breaks)[0]) < 1e-6


def test_reuleaux_h_is_c1():
    """At the ends of the vertex windows the vertex and the arc give the same h and h'."""
    ref = reuleaux(5, 100, width=2.0)
    e = 1e-9
    for t in ref.breaks:
        assert ref.b_of(np.array([t - e]))[0] == pytest.approx(ref.b_of(np.array([t + e]))[0], abs=1e-8)
        assert ref.d1b_of(np.array([t - e]))[0] == pytest.approx(ref.d1b_of(np.array([t + e]))[0], abs=1e-8)


# ---------------------------------------------------------------------------------------------------- cams
@pytest.mark.parametrize("law", ["cycloidal", "345", "modified-trapezoid", "shm"])
def test_cam_law_boundary_values_and_continuity(law):
    """f(0) = 0, f(1) = 1, f'(0) = f'(1) = 0, f and f' continuous everywhere (f'' too, except the SHM ends);
    the closed-form f' and f'' match differences of f with errors falling as Δ² (ratio 4 per halving)."""
    f0, f1_0, f2_0 = cam_law(law, np.array([0.0, 1.0]))
    np.testing.assert_allclose(f0, [0.0, 1.0], atol=1e-15)
    np.testing.assert_allclose(f1_0, [0.0, 0.0], atol=1e-14)
    # the dwells have f'' = 0: continuous for all laws but SHM, whose f'' jumps to ±π²/2
    np.testing.assert_allclose(f2_0, [np.pi**2 / 2, -np.pi**2 / 2] if law == "shm" else [0.0, 0.0], atol=1e-12)
    e = 1e-11
    for x in (0.125, 0.375, 0.5, 0.625, 0.875):
        lo, hi = cam_law(law, np.array([x - e])), cam_law(law, np.array([x + e]))
        for order in range(3):
            assert lo[order][0] == pytest.approx(hi[order][0], abs=1e-8)
    x = np.linspace(0.02, 0.98, 97)
    x = x[np.min(np.abs(x[:, None] - np.array([0.125, 0.375, 0.625, 0.875])), axis=1) > 0.011]

    def f(t):
        return cam_law(law, t)[0]

    _, d1, d2 = cam_law(law, x)
    errors = [np.max(np.abs((f(x - h) - 2 * f(x) + f(x + h)) / h**2 - d2)) for h in (0.01, 0.005)]
    assert errors[1] < 1e-3 * np.max(np.abs(d2)) and 3.5 < errors[0] / errors[1] < 4.5
    np.testing.assert_allclose((f(x + 1e-6) - f(x - 1e-6)) / 2e-6, d1, atol=1e-8)


def test_cam_wall_layout_and_second_difference():
    """The wall b = base + s: s(0) = 0, s(β) = L, dwell at L, return over [π, π + β], 0 after; sampled at 1°
    its second difference matches the closed-form s'' to O(Δ²) away from the breaks."""
    L, beta, base = 2.5, np.radians(60), 0.25
    ref = cam("modified-trapezoid", 360, rise=L, beta=beta, base=base)
    b = ref.b_of
    np.testing.assert_allclose(b(np.array([0.0, beta, 2.0, np.pi, np.pi + beta, 5.0, 2 * np.pi])),
                               base + np.array([0, L, L, L, 0, 0, 0]), atol=1e-14)
    np.testing.assert_allclose(ref.d1b_of(np.array([0.0, beta, np.pi, np.pi + beta])), 0.0, atol=1e-13)
    assert np.max(ref.d2b_of(np.linspace(0, beta, 10001))) == pytest.approx(MT_PEAK * L / beta**2, rel=1e-12)
    assert MT_PEAK == pytest.approx(4.888, abs=5e-4)
    delta = np.radians(1.0)
    inner = away_from(ref.theta, ref.breaks, 1.5 * delta)
    second = (b(inner - delta) - 2 * b(inner) + b(inner + delta)) / delta**2
    err = np.max(np.abs(second - ref.d2b_of(inner)))
    assert 1e-6 < err < 0.1 * delta**2 * MT_PEAK * (4 * np.pi) ** 2 * L / beta**4
    # and the discrete b'' genuinely follows the law (not trivially zero)
    assert np.ptp(second) > 2 * MT_PEAK * L / beta**2 * 0.99


@pytest.mark.parametrize("law", ["cycloidal", "345", "modified-trapezoid", "shm"])
def test_cam_b_c_closed_form_against_finite_differences(law):
    """b_c from the closed-form s'' agrees with finite differences of b alone; it scales with L and shifts
    with the base circle."""
    ref = cam(law, 360)
    dense, _ = true_b_c_dense(ref.b_of, ref.breaks)
    assert ref.b_c == pytest.approx(dense, abs=2e-6)
    assert ref.b_c > 3
    np.testing.assert_allclose(ref.rho(ref.params["argmin_theta"]), -ref.b_c, atol=1e-9)
    scaled = cam(law, 36, rise=2.0, base=0.5)
    assert scaled.b_c == pytest.approx(2 * ref.b_c - 0.5, abs=1e-9)
    convex = cam(law, 36, base=ref.b_c + 0.1)
    assert convex.b_c == pytest.approx(-0.1, abs=1e-9) and convex.corners == 0 and convex.area > 0


def test_cam_known_values():
    """SHM: b + b'' is monotone in cos πx on the rise, so b_c = L(π²/(2β²) − 1) = 3.5 at β = 60° (taken at the
    jump of s'' at θ = β, one-sided). Modified trapezoid, L = 1, β = 60°: b_c = 3.726960 (the issue's value),
    inside the sine piece just before x = 5/8; the support lines of the 1° samples give a smaller value."""
    shm = cam("shm", 360)
    assert shm.b_c == pytest.approx(3.5, abs=1e-12)
    beta = np.radians(45)
    assert cam("shm", 10, beta=beta).b_c == pytest.approx(np.pi**2 / (2 * beta**2) - 1, abs=1e-12)
    mt = cam("modified-trapezoid", 360)
    assert round(mt.b_c, 6) == 3.726960
    x = np.mod(mt.params["argmin_theta"], np.pi) / mt.params["beta"]
    assert min(abs(x - 0.6227), abs(x - 0.3773)) < 1e-3  # rise, or its mirror on the return
    sampled = -discrete_rho(mt.theta, mt.b).min()
    assert 3.70 < sampled < mt.b_c


# ---------------------------------------------------------------------------------------------------- smooth walls
def test_ellipse_curvature_closed_form():
    """ρ = a²b²/h³ agrees with h + (second difference of h); b_c = −b²/a; area πab."""
    for a, b in ((1.0, 0.6), (0.7, 1.3)):
        ref = smooth("ellipse", 360, semi_axes=(a, b))
        rho_fd = ref.b_of(RNG_THETA) + fd2(ref.b_of, RNG_THETA)
        np.testing.assert_allclose(ref.rho(RNG_THETA), rho_fd, atol=1e-6)
        np.testing.assert_allclose(fd1(ref.b_of, RNG_THETA), ref.d1b_of(RNG_THETA), atol=1e-8)
        assert ref.b_c == pytest.approx(-min(a, b) ** 2 / max(a, b), abs=1e-15)
        assert true_b_c_dense(ref.b_of)[0] == pytest.approx(ref.b_c, abs=1e-6)
        assert area_from_support(ref.b_of, ref.d1b_of) == pytest.approx(np.pi * a * b, rel=1e-13)


def test_paper_wall_critical_offset():
    """The paper's wall: b_c = −1/2 at ε = 1 and −1/(1 + ε) in general (at θ = 0), confirmed by finite
    differences of b alone; the closed-form b'' matches a difference of b."""
    ref = smooth("paper", 720, eps=1.0)
    assert ref.b_c == pytest.approx(-0.5, abs=1e-12)
    assert true_b_c_dense(ref.b_of)[0] == pytest.approx(-0.5, abs=1e-6)
    np.testing.assert_allclose(ref.d2b_of(RNG_THETA), fd2(ref.b_of, RNG_THETA), atol=1e-6)
    for eps in (0.2, 3.0):
        assert smooth("paper", 10, eps=eps).b_c == pytest.approx(-1 / (1 + eps), abs=1e-12)
    # b² = cos² + sin²/(1 + ε): the ellipse with semi-axes 1 and 1/√(1 + ε), area π/√(1 + ε)
    for eps in (1.0, 0.3):
        paper, ellipse = smooth("paper", 50, eps=eps), smooth("ellipse", 50, semi_axes=(1.0, (1 + eps) ** -0.5))
        np.testing.assert_allclose(paper.b, ellipse.b, rtol=1e-15)
        np.testing.assert_allclose(paper.rho(RNG_THETA), ellipse.rho(RNG_THETA), rtol=1e-13)
        assert paper.area == pytest.approx(np.pi / np.sqrt(1 + eps), rel=1e-13)
    # the area formula against the shoelace of the envelope points h n + h' n⊥
    t = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    h, d = ref.b_of(t), ref.d1b_of(t)
    x, y = h * np.cos(t) - d * np.sin(t), h * np.sin(t) + d * np.cos(t)
    assert ref.area == pytest.approx(0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y), rel=1e-6)


def test_stadium():
    """|cos θ| + r: ρ = r off θ = ±π/2 (where the segment's Dirac masses sit), b_c = −r, area πr² + 4ℓr."""
    ref = smooth("stadium", 360, half_length=1.0, radius=0.5)
    theta = away_from(RNG_THETA, ref.breaks, 1e-3)
    np.testing.assert_allclose(ref.b_of(theta) + fd2(ref.b_of, theta), 0.5, atol=1e-6)
    np.testing.assert_allclose(ref.rho(theta), 0.5, atol=1e-14)
    assert ref.b_c == -0.5 and true_b_c_dense(ref.b_of, ref.breaks)[0] == pytest.approx(-0.5, abs=1e-6)
    assert area_from_support(ref.b_of, ref.d1b_of, ref.breaks) == pytest.approx(np.pi / 4 + 2, rel=1e-13)
    # h' jumps by 2ℓ at π/2: the Dirac mass of ρ
    jump = ref.d1b_of(np.array([np.pi / 2 + 1e-12])) - ref.d1b_of(np.array([np.pi / 2 - 1e-12]))
    assert jump[0] == pytest.approx(2.0, abs=1e-9)


# ---------------------------------------------------------------------------------------------------- data as written
def test_write_rounded_significant_and_decimals():
    """The CSV parses to the returned arrays; values carry the requested significant digits (or decimals)
    and are within half a unit of the last digit of the truth."""
    ref = smooth("ellipse", 90)
    out = write_rounded(ref, 4)
    assert out.text.splitlines()[0] == "theta,b" and len(out.text.splitlines()) == 91
    data = np.loadtxt(io.StringIO(out.text), delimiter=",", skiprows=1)
    np.testing.assert_array_equal(data[:, 0], ref.theta)  # full-precision angles read back exactly
    np.testing.assert_array_equal(data[:, 1], out.b)
    for line in out.text.splitlines()[1:]:
        digits = line.split(",")[1].replace(".", "").lstrip("0")
        assert len(digits) <= 4
    assert np.all(np.abs(out.b - ref.b) <= 0.5e-4 * 10 ** np.floor(np.log10(np.abs(ref.b))) * 10 + 1e-16)
    assert np.max(np.abs(out.b - ref.b)) > 1e-6
    dec = write_rounded(ref, 3, theta_digits=2, degrees=True, mode="decimals")
    assert dec.header == "theta_deg,b" and dec.text.startswith("theta_deg,b\n0.00,1.000\n4.00,")
    np.testing.assert_allclose(dec.radians, np.radians(dec.theta))
    np.testing.assert_array_equal(dec.theta, 4.0 * np.arange(90))
    assert np.max(np.abs(dec.b - ref.b)) <= 0.5e-3 + 1e-15


def test_duplicates_noise_and_discrete_rho():
    ref = polygon(None, 100)
    theta, b, copies = with_duplicates(ref.theta, ref.b, seed=1, fraction=0.1, return_indices=True)
    assert theta.size == 110 and copies.size == 10
    np.testing.assert_array_equal(theta[copies], theta[copies - 1])
    np.testing.assert_array_equal(b[copies], b[copies - 1])
    np.testing.assert_array_equal(np.delete(theta, copies), ref.theta)
    _, bj, cj = with_duplicates(ref.theta, ref.b, seed=1, fraction=0.1, jitter=1e-3, return_indices=True)
    assert np.all(bj[cj] != bj[cj - 1])
    assert len(with_duplicates(ref.theta, ref.b, seed=1)) == 2
    noise = noisy(ref, 1e-3, seed=2) - ref.b
    assert 0.8e-3 < noise.std() < 1.2e-3 and abs(noise.mean()) < 5e-4
    # ρ_i of the support lines: r for a circle on any grid; 0 for a polygon sample with both neighbours in
    # its window; ρ(θ_i) + O(Δ²) for the ellipse
    assert np.allclose(discrete_rho(RNG_THETA, np.full(RNG_THETA.size, 1.3)), 1.3, atol=1e-10)
    poly = polygon(None, 720)
    rho = discrete_rho(poly.theta, poly.b)
    assert np.sum(np.abs(rho) < 1e-9) > 600 and rho.min() > -1e-9 and rho.max() > 10
    errors = []
    for count in (360, 720):
        ell = smooth("ellipse", count)
        errors.append(np.max(np.abs(discrete_rho(ell.theta, ell.b) - ell.rho(ell.theta))))
    assert 3.5 < errors[0] / errors[1] < 4.5
