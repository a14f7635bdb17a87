"""Analyses of the billiard: Poincaré section, Lyapunov exponent, heads/tails correlation, CLI.

Reference values and where they come from are stated in each test.
"""

import json
import math

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward import Wall
from coinwall.forward.dynamics.analysis.correlation import correlation, fit_tau_law, heads
from coinwall.forward.dynamics.analysis.lyapunov import chaotic_fraction, default_threshold, lyapunov, lyapunov_many
from coinwall.forward.dynamics.analysis.poincare import incidence_angle, poincare_section
from coinwall.forward.dynamics.billiard.table import Billiard
from coinwall.forward.errors import InvalidArgument

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def ellipse(eps, H):
    return Billiard(Wall.from_expression(ELLIPSE, {"eps": eps}), H)


# ---------------------------------------------------------------------------------------------------- heads
def test_heads_convention_matches_rigid_body_axis():
    """heads ⇔ arrow x-component −sin θ > 0 (module docstring of coinwall.forward.dynamics.analysis.correlation; ψ = −θ − π/2 in rigidbody)."""
    from coinwall.forward.dynamics.billiard.rigidbody import billiard_to_body

    theta = np.array([0.3, 1.0, 2.0, 3.5, 4.5, 6.0])
    body = billiard_to_body(np.column_stack([theta, np.ones_like(theta), np.zeros_like(theta), np.ones_like(theta)]))
    psi = body[:, 1]  # lab angle of the body axis
    assert np.array_equal(heads(theta), np.cos(psi) > 0)


# ---------------------------------------------------------------------------------------------------- section
def test_incidence_angle_flat_wall_is_velocity_angle():
    """ε = 0: the wall is flat (b ≡ 1), so φ_c = atan2(v_θ, v_η) exactly (closed form)."""
    table = ellipse(0.0, 3.0)
    v = np.array([[0.6, 0.8], [-0.28, 0.96]])
    phi = incidence_angle(table, np.array([0.4, 2.0]), v[:, 0], v[:, 1])
    assert np.allclose(phi, np.arctan2(v[:, 0], v[:, 1]), atol=1e-15)


def test_section_whispering_gallery_orbit_stays_bounded():
    """ε = 0.003, H = 3: a fast-spinning (whispering-gallery) orbit lies on a KAM curve, so φ_c stays in a band
    that does not grow with time.

    Each bottom reflection kicks φ by up to 2 max|b'| = 2·(ε/2) = 0.003 rad (b' ≈ −(ε/2) sin 2θ); kicks that
    did not cancel (a random walk) would spread φ_c by ~0.003·√N: ≈ 0.1 rad after N = 2000 bottom hits and
    twice as much after 4× longer. We require the band after 4000 collisions to be the band after 1000
    (to 1 %) and far below the random-walk size.
    """
    table = ellipse(0.003, 3.0)
    phi0 = 0.4 * math.pi
    start = [[0.1, 1.5, math.sin(phi0), math.cos(phi0)]]
    short = poincare_section(table, states=start, collisions=1000)
    long = poincare_section(table, states=start, collisions=4000)
    assert long.theta.size > 1900
    assert np.all((long.theta >= 0) & (long.theta < 2 * math.pi))
    assert np.ptp(long.phi) == pytest.approx(np.ptp(short.phi), rel=0.01)
    assert np.ptp(long.phi) < 0.05
    assert abs(np.mean(long.phi) - phi0) < 0.01



@pytest.mark.parametrize("text", ["abs(cos(t))", "1 + 0.2*cos(t) + 0.1*sin(2*t) + 0.05*cos(3*t)"])
def test_incidence_angle_evaluates_only_the_wall_hit(text, monkeypatch):
    """One wall evaluation per point (the wall that was hit), same φ as evaluating both walls everywhere.

    Reference: the module docstring's formula with the lower slope b'(θ) and the upper slope −b'(θ+π)
    both computed at every point and the one of the wall hit selected afterwards (the implementation
    before it was changed to evaluate only the wall hit). An asymmetric wall makes the two slopes
    differ; the stick has kinks.
    """
    table = Billiard(Wall.from_expression(text, {}), 4.0)
    rng = np.random.default_rng(5)
    theta = rng.uniform(-10.0, 10.0, 3000)
    side = rng.integers(0, 2, theta.size)
    angle = rng.uniform(0.0, 2 * math.pi, theta.size)
    v_theta, v_eta = np.cos(angle), np.sin(angle)
    lower, upper = table.wall.derivatives(theta)[1], -table.wall.derivatives(theta + math.pi)[1]
    slope = np.where(side == 0, lower, upper)
    sign = np.where(side == 0, 1.0, -1.0)
    expected = np.arctan2(v_theta + slope * v_eta, sign * (v_eta - slope * v_theta))

    calls = []
    derivatives = type(table.wall).derivatives  # a Wall is immutable: spy on its class
    monkeypatch.setattr(type(table.wall), "derivatives", lambda self, t: calls.append(np.size(t)) or derivatives(self, t))
    phi = incidence_angle(table, theta, v_theta, v_eta, side)
    assert calls == [theta.size]
    np.testing.assert_allclose(phi, expected, rtol=0, atol=1e-15)
    # a scalar side applies to every point
    for wall_side in (0, 1):
        phi = incidence_angle(table, theta, v_theta, v_eta, wall_side)
        np.testing.assert_allclose(phi, np.where(side == wall_side, expected, phi), rtol=0, atol=1e-15)


def test_section_in_groups_equals_one_ensemble_and_reports_progress(monkeypatch):
    """Orbits followed in groups (memory bound) give the same section, bit for bit, as all at once.

    Reference: the same call with every orbit in one ``ensemble`` call (a chunk larger than the
    whole run). Each orbit is computed from its own start state, so grouping must not change a bit.
    """
    import coinwall.forward.dynamics.analysis.poincare as poincare

    table = Billiard(Wall.from_expression("1 + 0.2*cos(t) + 0.1*sin(2*t)", {}), 3.0)
    whole = poincare_section(table, 5, 400, seed=2)
    monkeypatch.setattr(poincare, "_CHUNK_COLLISIONS", 800)  # groups of 2 orbits: 2, 2, 1
    done = []
    grouped = poincare_section(table, 5, 400, seed=2, progress=done.append)
    assert done == [2, 4, 5]
    assert whole.theta.size > 900 and set(np.unique(whole.orbit)) == set(range(5))
    for name in ("theta", "phi", "orbit", "starts"):
        a, b = getattr(whole, name), getattr(grouped, name)
        assert a.dtype == b.dtype and np.array_equal(a, b), name
    # explicit states take the same path
    again = poincare_section(table, states=whole.starts, collisions=400, progress=done.append)
    assert np.array_equal(again.phi, whole.phi) and done[-3:] == [2, 4, 5]


@pytest.mark.parametrize("collisions", [0, -3, 2.5, True])
def test_section_rejects_bad_collisions(collisions):
    with pytest.raises(InvalidArgument, match="collisions"):
        poincare_section(ellipse(0.55, 1.9), 2, collisions)


# ---------------------------------------------------------------------------------------------------- lyapunov
def test_lyapunov_unstable_vertical_orbit_closed_form():
    """ε = 0.003, H = 3, vertical orbit at θ = 0 between two dispersing mirrors.

    b''(0) = −ε/(1+ε) (from b² = (1+ε cos²θ)/(1+ε)), so both walls are convex mirrors of radius
    R = (1+ε)/ε a distance L = H − 2 apart; the one-bounce matrix [[1, L], [2/R, 1 + 2L/R]] has trace
    2 + 2L/R, hence λ = arccosh(1 + L/R) per collision and λ/L per unit time. The orbit stays on the
    periodic orbit for ~ln(1e16)/λ ≈ 480 collisions, so we use 300.
    """
    eps, H = 0.003, 3.0
    L, R = H - 2.0, (1 + eps) / eps
    expected = math.acosh(1 + L / R)
    result = lyapunov(ellipse(eps, H), [0.0, 1.5, 0.0, 1.0], collisions=300)
    assert result.per_collision[0] == pytest.approx(expected, rel=2e-3)
    assert result.per_time[0] == pytest.approx(expected / L, rel=2e-3)


def test_lyapunov_regular_near_stable_orbit_vs_chaotic_stick():
    """Near the stable vertical orbit at θ = π/2 of the ε = 0.003 table (two focusing mirrors, b''(π/2) > 0,
    L/R ≪ 2: stable) the exponent is below the regular threshold 3 ln N/N; the stick |cos θ| at H = 2.2
    (H near D = 2; paper: a Bernoulli system, K-type motion) has exponents far above it."""
    N = 1000
    regular = lyapunov(ellipse(0.003, 3.0), [math.pi / 2, 1.5, 0.03, 1.0], collisions=N)
    assert regular.per_collision[0] < default_threshold(N)
    stick = Billiard(Wall.from_expression("abs(cos(t))", {}), 2.2)
    from coinwall.forward.dynamics.billiard.table import random_states

    chaotic = lyapunov_many(stick, random_states(stick, 4, seed=3), collisions=N)
    assert np.all(chaotic.per_collision > 10 * default_threshold(N))


def test_chaotic_fraction_counts_and_validates():
    """The stick at H = 2.2 is fully chaotic (paper, sec. III): every sampled orbit is chaotic."""
    stick = Billiard(Wall.from_expression("abs(cos(t))", {}), 2.2)
    frac = chaotic_fraction(stick, orbits=8, collisions=500, seed=2)
    assert frac.fraction == 1.0 and frac.regular == 0 and frac.orbits == 8
    with pytest.raises(InvalidArgument):
        chaotic_fraction(stick, orbits=0)


def test_regular_fraction_is_exact_at_the_threshold():
    """One regular orbit of 400 is exactly 1/400 = 0.0025, so ``regular_max = 0.0025`` must not count it
    as chaotic.  (It was ``1 − 399/400``, which rounds to 0.0024999999999999467 and moved ε_c at H = 3
    from 2.71 to 8.49 in the KAM sensitivity study.)"""
    from dataclasses import replace

    stick = Billiard(Wall.from_expression("abs(cos(t))", {}), 2.2)
    frac = chaotic_fraction(stick, orbits=4, collisions=100, seed=2)
    one_in_400 = replace(frac, fraction=399 / 400, regular=1, orbits=400)
    assert 1.0 - one_in_400.fraction < 0.0025  # the rounding the count-based value avoids
    assert one_in_400.regular_fraction == 0.0025
    assert not one_in_400.regular_fraction < 0.0025


# ---------------------------------------------------------------------------------------------------- correlation
@pytest.fixture(scope="module")
def coin_correlation():
    return correlation(ellipse(99.0, 2.4), bounces=200_000, max_lag=30, orbits=40, seed=5)


def test_correlation_symmetry_and_lag_zero(coin_correlation):
    """P(0) = 1 by definition; the ε = 99 ellipse is symmetric under θ → −θ, so P(heads) = ½
    (within 4 standard errors from the spread between orbits)."""
    r = coin_correlation
    assert r.P[0] == 1.0 and r.P_stderr[0] == 0.0
    assert abs(r.heads_fraction - 0.5) < 4 * r.heads_stderr
    assert 0 < r.heads_stderr < 0.02
    # decay towards ½: the fitted τ is finite and positive with an error, and P(n) − ½ falls below 0.01
    assert 0 < r.tau < 30 and 0 < r.tau_stderr < r.tau
    assert r.n_needed is not None and abs(r.P[r.n_needed] - 0.5) < 0.01
    assert np.all(np.abs(r.P[: r.n_needed] - 0.5) >= 0.01)


def test_correlation_no_flip_below_diameter():
    """H = 1.9 < D = 2: the coin cannot stand on its edge, so it never turns over: P(n) = 1, τ = ∞."""
    r = correlation(ellipse(99.0, 1.9), bounces=4000, max_lag=5, orbits=4, seed=1)
    assert np.all(r.P == 1.0) and r.tau == math.inf and r.n_needed is None


def test_correlation_bad_input():
    table = ellipse(99.0, 2.4)
    with pytest.raises(InvalidArgument):
        correlation(table, bounces=100, max_lag=40, orbits=10)
    with pytest.raises(InvalidArgument):
        correlation(table, bounces=0)
    with pytest.raises(InvalidArgument):
        correlation(table, bounces=1000, count="top")


def test_fit_tau_law_recovers_exact_law():
    """Synthetic τ = 3/(H − 2) exactly: c = 3, χ² = 0, power p = 1."""
    H = np.array([2.1, 2.2, 2.4, 2.8])
    law = fit_tau_law(H, 3 / (H - 2), 0.01 * np.ones(4), 2.0)
    assert law.c == pytest.approx(3.0, rel=1e-12)
    assert law.power == pytest.approx(1.0, rel=1e-9)


# ---------------------------------------------------------------------------------------------------- CLI
def test_cli_correlation_json(capsys):
    code = main(["correlation", ELLIPSE, "--param", "eps=99", "--H", "2.4", "--bounces", "20000", "--max-lag", "10",
                 "--orbits", "10", "--seed", "1", "--json"])
    assert code == 0
    out = capsys.readouterr()
    doc = json.loads(out.out)
    assert len(doc["P"]) == 11 and len(doc["P_stderr"]) == 11 and doc["P"][0] == 1.0
    assert {"tau", "tau_stderr", "n_needed"} <= set(doc)
    assert out.err == ""


@pytest.mark.parametrize("argv", [
    ["correlation", ELLIPSE, "--param", "eps=99", "--H", "0.1", "--bounces", "1000"],
    ["correlation", ELLIPSE, "--param", "eps=99", "--H", "2.4", "--bounces", "-5"],
    ["correlation", ELLIPSE, "--param", "eps=99", "--H", "2.4", "--bounces", "30", "--max-lag", "40"],
    ["section", ELLIPSE, "--param", "eps=0.55", "--H", "1.9", "--orbits", "0"],
    ["section", ELLIPSE, "--param", "eps=0.55", "--H", "1.9", "--collisions", "0"],
    ["kam", "--H", "2,x"],
    ["kam", "--H", "0.5"],
])
def test_cli_nonsense_is_one_line_exit_2(argv, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("coinwall: error:") and err.count("\n") == 1


def test_cli_section_writes_all_or_nothing(tmp_path, capsys):
    png, csv = tmp_path / "s.png", tmp_path / "s.csv"
    assert main(["section", ELLIPSE, "--param", "eps=0.55", "--H", "1.9", "--orbits", "3", "--collisions", "200",
                 "--seed", "1", "-o", str(png), "-o", str(csv)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert rows.shape[1] == 3 and set(np.unique(rows[:, 2])) <= {0, 1, 2}
    bad = tmp_path / "t.png"
    assert main(["section", ELLIPSE, "--param", "eps=0.55", "--H", "1.9", "--orbits", "2", "--collisions", "50",
                 "-o", str(bad), "-o", str(tmp_path / "t.xyz")]) == 2
    assert not bad.exists()
