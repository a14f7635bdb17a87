"""The coin in three dimensions: bodies of revolution, the spinning top's billiard, the direct 3-D simulation.

Reference values: the closed forms of the cylinder and the ellipsoid (derived in forward/revolution.py) are
held to independent quadratures written here; the reduced billiard (forward/dynamics/coin3d/top.py) is held to
its plain-numpy twin, to the direct 3-D simulation (forward/dynamics/coin3d/rigid3d.py, which never uses the
reduction) and, in the planar limit ℓz = ℓ3 = 0, to the planar field billiard (forward/dynamics/floor/field.py).
"""

import math

import numpy as np
import pytest

from coinwall.forward.dynamics.coin3d.rigid3d import Rigid3D, from_reduced, simulate_3d, to_reduced
from coinwall.forward.dynamics.coin3d.top import TopTable, energy, potential, state_after, top_run
from coinwall.forward.dynamics.floor.field import FieldTable, field_run
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.revolution import coin, ellipsoid, from_meridian
from coinwall.forward.wall import Wall

BODIES = [coin(1.0, 0.3), ellipsoid(1.0, 0.4), coin(1.0, 0.3, 0.1)]
START = [1.0, 3.0, 0.7, 0.3]


# ---------------------------------------------------------------------------------------------------- bodies
def _slices(radius_at, half, n=20001):
    """M, I3, I1 by Simpson's rule over disc slices (independent of the library's integrals)."""
    from scipy.integrate import simpson

    z = np.linspace(-half, half, n)
    R = radius_at(z)
    return (simpson(math.pi * R ** 2, x=z), simpson(math.pi * R ** 4 / 2, x=z),
            simpson(math.pi * (R ** 4 / 4 + R ** 2 * z ** 2), x=z))


def test_cylinder_closed_form_against_green_and_slices():
    c = coin(1.3, 0.4)
    m = from_meridian([[0, -0.2], [1.3, -0.2], [1.3, 0.2], [0, 0.2]])
    for got in (m.mass, m.I1, m.I3):
        assert np.isfinite(got)
    np.testing.assert_allclose([m.mass, m.I1, m.I3], [c.mass, c.I1, c.I3], rtol=1e-13)
    M, I3, I1 = _slices(lambda z: np.full_like(z, 1.3), 0.2)
    np.testing.assert_allclose([c.mass, c.I3, c.I1], [M, I3, I1], rtol=1e-10)


def test_ellipsoid_closed_form_against_slices():
    a, cc = 1.0, 0.4
    e = ellipsoid(a, cc)
    M, I3, I1 = _slices(lambda z: a * np.sqrt(np.clip(1 - (z / cc) ** 2, 0, None)), cc, 400001)
    np.testing.assert_allclose([e.mass, e.I3, e.I1], [M, I3, I1], rtol=2e-6)  # Simpson's error at the √ ends


def test_rounded_coin_against_a_fine_polygon_meridian():
    r, t, eps = 1.0, 0.3, 0.1
    rounded = coin(r, t, eps)
    d = t / 2
    for n, tol in ((200, 2e-5), (800, 2e-6)):  # an inscribed polygon: error O(n^-2)
        phi = np.linspace(0, math.pi / 2, n)
        lower = np.column_stack([r - eps + eps * np.cos(phi), -(d - eps) - eps * np.sin(phi)])[::-1]
        upper = np.column_stack([r - eps + eps * np.cos(phi), (d - eps) + eps * np.sin(phi)])
        pts = np.vstack([[[0, -d]], lower, upper, [[0, d]]])
        poly = from_meridian(pts)
        np.testing.assert_allclose([poly.mass, poly.I1, poly.I3], [rounded.mass, rounded.I1, rounded.I3], rtol=tol)
    assert rounded.mass < coin(r, t).mass


@pytest.mark.parametrize("body", BODIES, ids=lambda b: b.name)
def test_support_is_the_lowest_point_of_the_rotated_3d_body(body):
    """h(θ) against the lowest point of points sampled on the 3-D body, rotated by the tilt (own numpy)."""
    rng = np.random.default_rng(3)
    if body.kind == "ellipsoid":
        A, C = body.semi_axes
        u = rng.normal(size=(200000, 3))
        u /= np.linalg.norm(u, axis=1)[:, None]
        pts = u * [A, A, C]
        tol = 2e-3
    else:
        # the rim circles of the hull vertices, thickened by the rounding ball
        phi = rng.uniform(0, 2 * math.pi, 200000)
        k = rng.integers(0, body.vertices.shape[0], phi.size)
        rho, zeta = body.vertices[k, 0], body.vertices[k, 1]
        pts = np.column_stack([rho * np.cos(phi), rho * np.sin(phi), zeta])
        ball = rng.normal(size=pts.shape)
        ball /= np.linalg.norm(ball, axis=1)[:, None]
        pts = pts + body.rounding * ball
        tol = 2e-3
    for theta in np.linspace(0, math.pi, 9):
        # tilt the axis e3 by θ towards x: rotation about y
        s, c = math.sin(theta), math.cos(theta)
        z = -s * pts[:, 0] + c * pts[:, 2]
        h, _ = body.support(theta)
        assert -z.min() <= h + 1e-12
        assert -z.min() == pytest.approx(float(h), abs=tol)


def test_support_derivative_is_the_lever_arm():
    """h'(θ) against a central difference, away from the kinks."""
    for body in BODIES:
        theta = np.array([0.3, 0.9, 1.3, 2.0, 2.7])
        h1, d = body.support(theta)
        step = 1e-6
        fd = (body.support(theta + step)[0] - body.support(theta - step)[0]) / (2 * step)
        np.testing.assert_allclose(d, fd, atol=1e-7)


def test_bodies_refuse_bad_input():
    with pytest.raises(InvalidArgument, match="rounding"):
        coin(1.0, 0.2, 0.5)
    with pytest.raises(InvalidArgument, match="radius"):
        coin(-1.0, 0.2)
    with pytest.raises(InvalidArgument, match="convex"):
        from_meridian([[0, -1], [1, -1], [0.2, 0], [1, 1], [0, 1]])
    with pytest.raises(InvalidArgument):
        from_meridian([[0, 0], [1, float("nan")]])


# ---------------------------------------------------------------------------------------------------- reduced
CASES = [(6.0, 1.0, 0.4, 0.9, 1.0), (6.0, 0.0, 0.4, 0.9, 0.8), (None, 1.0, 0.9, 0.9, 0.7), (6.0, 0.0, 0.0, 0.0, 1.0),
         (None, 1.0, -0.5, 0.5, 0.9)]


@pytest.mark.parametrize("body", BODIES, ids=lambda b: b.name)
def test_kernel_matches_its_numpy_twin(body):
    for H, g, lz, l3, e in CASES:
        table = TopTable(body, g=g, e=e, H=H)
        fk = top_run(table, START, lz, l3, 8)
        fr = top_run(table, START, lz, l3, 8, method="reference")
        assert fk.impacts == fr.impacts == 8
        np.testing.assert_array_equal(fk.wall, fr.wall)
        # the twin reads θ through arccos, which loses ~1e-8 at a pole (the planar case passes through it)
        np.testing.assert_allclose(fk.states(), fr.states(), atol=1e-6 if lz == l3 == 0 else 1e-9)
        assert np.all(np.isfinite(fk.states()))


@pytest.mark.parametrize("body", BODIES, ids=lambda b: b.name)
def test_reduction_state_by_state_against_the_3d_body(body):
    """From every impact of the reduced orbit, the 3-D body (turned about its axis and the vertical at random,
    drifting sideways) reaches the next impact in the same state: the reduction, impact by impact."""
    rng = np.random.default_rng(7)
    k1 = body.kappa1
    for H, g, lz, l3, e in CASES:
        table = TopTable(body, g=g, e=e, H=H)
        system = Rigid3D(body, g=g * k1, e=e, H=None if H is None else H * k1)
        flight = top_run(table, START, lz, l3, 12)
        states = np.vstack([START, flight.states()])
        for i in range(flight.impacts):
            start = from_reduced(system, states[i], lz, l3, spin_angle=rng.uniform(0, 6), azimuth=rng.uniform(0, 6),
                                 drift=rng.normal(size=2))
            # the 3-D body starts in the air (i = 0) or on the wall it has just left; a step back in time on the
            # wall is not needed: simulate_3d leaves a wall it touches when moving away
            traj = simulate_3d(system, start, 1)
            got = traj.reduced()[0]
            assert traj.wall[0] == flight.wall[i]
            np.testing.assert_allclose(got[:4], states[i + 1], atol=1e-10)
            np.testing.assert_allclose(got[4:], [lz, l3], atol=1e-12)


def test_reduced_and_3d_orbits_agree_over_many_impacts():
    """The whole orbit, not restarted: floor with gravity (rounding differences grow slowly there)."""
    body = coin(1.0, 0.3)
    k1 = body.kappa1
    table = TopTable(body, g=1.0, e=0.9, H=None)
    system = Rigid3D(body, g=k1, e=0.9)
    flight = top_run(table, START, 0.9, 0.9, 40)
    traj = simulate_3d(system, from_reduced(system, START, 0.9, 0.9, spin_angle=0.4, azimuth=2.0, drift=(0.3, 0)), 40)
    red = traj.reduced()
    np.testing.assert_array_equal(traj.wall, flight.wall)
    np.testing.assert_allclose(red[:, :4], flight.states(), atol=1e-9)
    np.testing.assert_allclose(traj.time, flight.time, rtol=1e-10)
    np.testing.assert_allclose(red[:, 4:], 0.9, atol=1e-12)


def test_3d_conserves_energy_and_the_two_momenta():
    body = ellipsoid(1.0, 0.4)
    k1 = body.kappa1
    system = Rigid3D(body, g=0.0, e=1.0, H=6.0 * k1)
    traj = simulate_3d(system, from_reduced(system, START, 0.4, 0.9, spin_angle=1.0), 80)
    E = traj.energy()
    red = traj.reduced()
    assert traj.time.size == 80
    np.testing.assert_allclose(E, E[0], rtol=1e-12)
    np.testing.assert_allclose(red[:, 4], 0.4, atol=1e-12)
    np.testing.assert_allclose(red[:, 5], 0.9, atol=1e-12)


@pytest.mark.parametrize("H,g,e", [(6.0, 0.0, 1.0), (None, 1.0, 0.8), (6.0, 1.0, 0.9)])
def test_planar_limit_is_the_planar_billiard(H, g, e):
    """ℓz = ℓ3 = 0: the planar field billiard with the coin's section wall (r|sin θ| + d|cos θ|)/κ1, θ folded."""
    body = coin(1.0, 0.3)
    wall = Wall.from_expression("(r*abs(sin(t)) + d*abs(cos(t)))/k", {"r": 1.0, "d": 0.15, "k": body.kappa1})
    planar = field_run(FieldTable(wall, g=g, e=e, H=H), START, 6)
    flight = top_run(TopTable(body, g=g, e=e, H=H), START, 0.0, 0.0, 6)
    n = planar.time.size
    assert n >= 3 and flight.impacts >= n
    folded = np.arccos(np.cos(planar.theta))
    np.testing.assert_allclose(flight.theta[:n], folded, atol=1e-10)
    np.testing.assert_allclose(flight.eta[:n], planar.eta, atol=1e-10)
    np.testing.assert_allclose(flight.v_theta[:n], np.sign(np.sin(planar.theta)) * planar.v_theta, atol=1e-10)
    np.testing.assert_allclose(flight.time[:n], planar.time, atol=1e-10)


def test_energy_conserved_through_ten_thousand_impacts():
    body = coin(1.0, 0.3)
    for H, g, lz, l3 in ((6.0, 1.0, 0.4, 0.9), (6.0, 0.0, 0.9, 0.9)):
        table = TopTable(body, g=g, e=1.0, H=H)
        f = top_run(table, START, lz, l3, 10_000)
        assert f.impacts == 10_000
        E = energy(table, f.theta, f.eta, f.v_theta, f.v_eta, lz, l3)
        E0 = energy(table, *START, lz, l3)
        np.testing.assert_allclose(E, E0, rtol=1e-11)
        assert np.all(np.isfinite(f.states()))


@pytest.mark.slow
def test_energy_conserved_through_a_million_impacts():
    body = coin(1.0, 0.3)
    for H, g, lz, l3 in ((6.0, 1.0, 0.4, 0.9), (6.0, 0.0, 0.9, 0.9), (6.0, 0.0, 0.0, 0.0)):
        table = TopTable(body, g=g, e=1.0, H=H)
        f = top_run(table, START, lz, l3, 1_000_000)
        assert f.impacts == 1_000_000
        E = energy(table, f.theta, f.eta, f.v_theta, f.v_eta, lz, l3)
        np.testing.assert_allclose(E, energy(table, *START, lz, l3), rtol=1e-9)


def test_flight_through_the_pole_is_the_precessing_normal():
    """ℓz = ℓ3 (the axis reaches the vertical): starting flat, cos θ(t) = cos²ψ + sin²ψ cos Ωt (the normal
    precessing on a cone of half-angle ψ about L, which makes the angle ψ with the vertical start)."""
    table = TopTable(coin(1.0, 0.3), g=9.0)
    omega, psi = 7.0, 1.2
    t = np.linspace(0, 3, 301)
    states = np.tile([0.0, 5.0, omega * math.sin(psi), 0.0], (t.size, 1))
    lz = l3 = omega * math.cos(psi)
    out = state_after(table, states, lz, l3, t)
    assert np.all(np.isfinite(out))
    np.testing.assert_allclose(np.cos(out[:, 0]), math.cos(psi) ** 2 + math.sin(psi) ** 2 * np.cos(omega * t),
                               atol=1e-13)
    np.testing.assert_allclose(out[:, 1], 5.0 - 4.5 * t ** 2, atol=1e-12)
    # the energy ½θ̇² + V(θ) is conserved through the pole
    E = 0.5 * out[:, 2] ** 2 + potential(out[:, 0], lz, l3)
    np.testing.assert_allclose(E, 0.5 * (omega * math.sin(psi)) ** 2, rtol=1e-9)


def test_barrier_keeps_the_axis_off_the_vertical():
    """ℓz ≠ ±ℓ3: θ stays between the turning points, the roots of 2ε(1 − u²) = (ℓz − ℓ3 u)² (u = cos θ)."""
    table = TopTable(coin(1.0, 0.3))
    lz, l3, th0, w0 = 0.3, 1.1, 1.0, 0.8
    t = np.linspace(0, 20, 4001)
    out = state_after(table, np.tile([th0, 5.0, w0, 0.0], (t.size, 1)), lz, l3, t)
    eps = 0.5 * w0 ** 2 + float(potential(th0, lz, l3))
    roots = np.sort(np.roots([-(2 * eps + l3 ** 2), 2 * lz * l3, 2 * eps - lz ** 2]).real)
    u = np.cos(out[:, 0])
    assert u.min() >= roots[0] - 1e-12 and u.max() <= roots[1] + 1e-12
    assert u.min() < roots[0] + 1e-4 and u.max() > roots[1] - 1e-4
    assert 0 < out[:, 0].min() and out[:, 0].max() < math.pi


def test_top_refuses_bad_input():
    table = TopTable(coin(1.0, 0.3), g=1.0)
    with pytest.raises(InvalidArgument, match="pole"):
        top_run(table, [0.0, 3.0, 1.0, 0.0], 0.2, 0.9, 3)
    with pytest.raises(InvalidArgument, match="floor"):
        top_run(table, [1.0, 0.1, 1.0, 0.0], 0.2, 0.9, 3)
    with pytest.raises(InvalidArgument, match="θ"):
        top_run(table, [4.0, 3.0, 1.0, 0.0], 0.2, 0.9, 3)
    with pytest.raises(InvalidArgument, match="`e`"):
        TopTable(coin(1.0, 0.3), e=0.0)
    with pytest.raises(InvalidArgument, match="`H`"):
        TopTable(coin(1.0, 0.3), H=1.0)
    with pytest.raises(InvalidArgument, match="method"):
        top_run(table, START, 0.1, 0.2, 3, method="fast")


def test_to_reduced_round_trip():
    body = coin(1.0, 0.3)
    system = Rigid3D(body, g=1.0)
    for state, lz, l3 in (([0.7, 3.0, -0.4, 0.2], 0.3, -0.8), ([0.0, 3.0, 0.5, 0.0], 0.6, 0.6),
                          ([math.pi, 3.0, -0.5, 0.0], -0.6, 0.6)):
        got = to_reduced(system, *from_reduced(system, state, lz, l3, spin_angle=2.0, azimuth=-1.0))
        np.testing.assert_allclose(got, [*state, lz, l3], atol=1e-14)


def test_bounce_sides_match_single_orbits_and_settled_coins_keep_their_side():
    """The parallel bounce statistics against single orbits of the same tosses, and the equator's barrier:
    a toss marked settled, followed 300 impacts further, never shows the other side."""
    from coinwall.forward.dynamics.coin3d.top import sides_at_bounces

    body = coin(1.0, 0.15)
    table = TopTable(body, g=50.0, e=0.5)
    rng = np.random.default_rng(2)
    n = 40
    psi = math.radians(84.0)
    om = rng.uniform(20, 30, n)
    states = np.column_stack([np.zeros(n), np.full(n, 20.0), om * math.sin(psi), rng.uniform(5, 10, n)])
    ell = om * math.cos(psi)
    sides, status = sides_at_bounces(table, states, ell, ell, 8)
    assert np.any(status == 1) and np.all(np.isin(status, (0, 1)))
    for j in range(n):
        f = top_run(table, states[j], ell[j], ell[j], 300)
        floor = np.cos(f.theta[f.wall == 0])
        got = np.sign(floor[:8]).astype(int)
        if status[j] == 0:
            np.testing.assert_array_equal(sides[j], got)
        else:
            change = np.flatnonzero(sides[j] != sides[j][-1])
            k = int(change[-1]) + 1 if change.size else 0  # the settled side fills the run at the end
            np.testing.assert_array_equal(sides[j][: k + 1], got[: k + 1])
            assert np.all(np.sign(floor[k:]) == sides[j][-1]), "a settled toss changed side"


def _section_starts(H, n, seed):
    """Liouville-random starts of the planar ε = 99 ellipse section, as 3-D states of the ellipsoid (a = 1,
    c = 0.1): the planar angle θp (from the downward normal to the long axis) gives the normal's tilt
    cos θ = −sin θp (the normal is the long axis turned by 90°)."""
    from coinwall.forward.dynamics.billiard.table import Billiard, random_states

    body = ellipsoid(1.0, 0.1)
    wall = Wall.from_expression("sqrt(a**2*cos(t)**2 + c**2*sin(t)**2)/k", {"a": 1.0, "c": 0.1, "k": body.kappa1})
    bil = Billiard(wall, H)
    starts = random_states(bil, n, seed=seed)
    th = np.arccos(np.clip(-np.sin(starts[:, 0]), -1, 1))
    w = starts[:, 2] * np.cos(starts[:, 0]) / np.maximum(np.sin(th), 1e-300)
    return body, bil, np.column_stack([th, starts[:, 1], w, starts[:, 3]])


def test_side_correlation_plateau_and_bias():
    from coinwall.forward.dynamics.coin3d.correlation3d import side_correlation

    body, _, states = _section_starts(1.5 * 2 / ellipsoid(1.0, 0.1).kappa1, 6, 3)
    table = TopTable(body, g=0.0, e=1.0, H=1.5 * 2 / body.kappa1)
    flat = side_correlation(table, states, 0.0, 0.0, 3000, max_lag=5)
    spun = side_correlation(table, states, 0.5, 0.5, 3000, max_lag=5)
    assert abs(flat["heads"] - 0.5) < 4 * flat["heads_stderr"] + 0.02
    assert spun["heads"] > 0.6  # the potential (ℓz = ℓ3) favours heads
    assert spun["P_inf"] > 0.5 and np.all(spun["P"] >= spun["P_inf"] - 4 * spun["P_stderr"] - 0.01)
    assert 0.5 < flat["P"][0] < 1.0 and flat["orbits"] == 6
    with pytest.raises(InvalidArgument, match="ceiling"):
        side_correlation(TopTable(body, g=1.0), states, 0.0, 0.0, 100)


@pytest.mark.slow
def test_side_correlation_planar_limit_is_the_papers_correlation():
    """ℓz = ℓ3 = 0: the 3-D ellipsoid's side-up P(n) is the planar P(n) of its section (the paper's heads)."""
    from coinwall.forward.dynamics.analysis.correlation import correlation
    from coinwall.forward.dynamics.coin3d.correlation3d import side_correlation

    H = 1.5 * 2 / ellipsoid(1.0, 0.1).kappa1
    body, bil, states = _section_starts(H, 30, 1)
    planar = correlation(bil, bounces=300_000, max_lag=6, orbits=30, seed=1)
    three = side_correlation(TopTable(body, g=0.0, e=1.0, H=H), states, 0.0, 0.0, 20_000, max_lag=6)
    err = np.hypot(planar.P_stderr[1:7], three["P_stderr"])
    assert np.all(np.abs(planar.P[1:7] - three["P"]) < 4 * err)
