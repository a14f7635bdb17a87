"""The toss that lands: flights in a field, restitution, settling, Keller's hyperbolas and ``coinwall toss``.

Every check has a reference that does not share the code under test: the field-free billiard kernel,
the plain-numpy twin, the rigid body's impulse formula in lab units, Keller's closed form, energy.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard.table import Billiard, random_states, simulate
from coinwall.forward.dynamics.floor.field import FieldTable, field_run, field_run_many
from coinwall.forward.dynamics.floor.landscape import landscape

COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"


@pytest.fixture(scope="module")
def coin():
    return Wall.from_expression(COIN, {"eps": 99.0})


# --------------------------------------------------------------------------- 1. the kernel and its twin

@pytest.mark.parametrize("g, e, H, start", [
    (1.0, 1.0, 3.0, [0.3, 1.5, 0.7, 0.2]),        # floor and ceiling, elastic
    (2.0, 0.8, 3.0, [2.0, 2.0, -1.9, 1.0]),       # ceiling hit under gravity, inelastic
    (1.0, 0.6, None, [0.3, 1.5, 3.7, 0.2]),       # floor only, settles
    (1.0, 0.9, None, [1.0, 1.7, 0.0, 0.5]),       # no rotation: the quadratic in closed form
])
def test_kernel_matches_reference(coin, g, e, H, start):
    table = FieldTable(coin, g=g, e=e, H=H)
    kernel = field_run(table, start, 12)
    ref = field_run(table, start, 12, method="reference")
    assert len(kernel) == len(ref) > 0 and kernel.status == ref.status and kernel.valley == ref.valley
    assert np.array_equal(kernel.side, ref.side)
    for name in ("time", "theta", "eta", "v_theta", "v_eta"):
        a, b = getattr(kernel, name), getattr(ref, name)
        # chaotic growth of the contact tolerance (1e-13) over 12 impacts stays far below 1e-8
        assert np.allclose(a, b, rtol=0, atol=1e-8), (name, np.max(np.abs(a - b)))


def test_kernel_matches_reference_on_a_wall_with_corners():
    wall = Wall.from_expression("1.5*abs(cos(t)) + 0.3*abs(sin(t))")
    table = FieldTable(wall, g=1.0, e=0.7, H=5.0)
    start = [0.2, 3.0, 2.3, 0.4]
    kernel = field_run(table, start, 10)
    ref = field_run(table, start, 10, method="reference")
    assert len(kernel) == len(ref) > 0 and kernel.status == ref.status
    assert np.allclose(kernel.theta, ref.theta, atol=1e-8) and np.allclose(kernel.v_eta, ref.v_eta, atol=1e-8)


# --------------------------------------------------------------------------- 2. independent references

def test_no_field_elastic_is_the_billiard_collision_by_collision(coin):
    """g = 0, e = 1: from every state of a billiard orbit (3000 collisions), the field kernel's next impact is
    the billiard kernel's next collision to rounding; and a whole orbit agrees for its first collisions."""
    table = Billiard(coin, 3.0)
    state = random_states(table, 1, seed=4)[0]
    traj = simulate(table, state, 3000)
    field = FieldTable(coin, g=0.0, e=1.0, H=3.0)
    worst = 0.0
    for i in range(len(traj) - 1):
        s = [traj.theta[i] % (2 * math.pi), traj.eta[i], traj.v_theta[i], traj.v_eta[i]]
        one = field_run(field, s, 1)
        dt = traj.time[i + 1] - traj.time[i]
        dth = (traj.theta[i + 1] - traj.theta[i]) - (one.theta[0] - s[0])
        worst = max(worst, abs(one.time[0] - dt) / (1 + dt), abs(dth), abs(one.eta[0] - traj.eta[i + 1]),
                    abs(one.v_theta[0] - traj.v_theta[i + 1]), abs(one.v_eta[0] - traj.v_eta[i + 1]))
        assert one.side[0] == traj.side[i + 1]
    assert worst < 1e-11, worst
    # a whole orbit: the coin (ε = 99) is strongly chaotic, rounding differences (the billiard renormalises its
    # speed to 1 after each collision, the field kernel does not) grow about fourfold per collision
    whole = field_run(field, state, 8)
    assert np.array_equal(whole.side, traj.side[:8])
    assert np.allclose(whole.theta, traj.theta[:8], atol=1e-10) and np.allclose(whole.time, traj.time[:8])


@pytest.mark.parametrize("e", [0.25, 0.7, 1.0])
def test_one_impact_is_the_rigid_body_impulse(coin, e):
    """The post-impact velocities are those of the lab impulse J = −(1+e) u/(1/M + r²/I) at the contact point,
    for a body of mass M and radius of gyration κ (lever arm r = κ b'(θ), I = M κ², θ̇ = −ω)."""
    M, kappa = 0.37, 0.021
    table = FieldTable(coin, g=3.0, e=e)
    for start in ([0.4, 1.6, 2.5, 0.3], [2.0, 1.3, -1.7, -0.4], [5.0, 2.2, 0.9, 1.1]):
        flight = field_run(table, start, 1, catch=True)
        assert flight.status == "caught" and flight.side[0] == 0
        t = flight.time[0]
        th_dot, eta_dot = start[2], start[3] - table.g * t          # just before the impact
        _, d1, _ = coin.derivatives(np.array([flight.theta[0]]))
        r = kappa * float(d1[0])
        ydot, omega = kappa * eta_dot, -th_dot                        # lab velocities
        u = ydot + r * omega                                         # the contact point's vertical velocity
        J = -(1 + e) * u / (1 / M + r * r / (M * kappa ** 2))
        ydot_after, omega_after = ydot + J / M, omega + r * J / (M * kappa ** 2)
        assert flight.v_eta[0] == pytest.approx(ydot_after / kappa, rel=1e-12, abs=1e-12)
        assert flight.v_theta[0] == pytest.approx(-omega_after, rel=1e-12, abs=1e-12)
        # and the contact point leaves with −e times its approach speed
        u_after = kappa * (flight.v_eta[0] - float(d1[0]) * flight.v_theta[0])
        assert u_after == pytest.approx(-e * u, rel=1e-11)


def test_energy_is_conserved_over_1e5_bounces(coin):
    """e = 1 with gravity, floor and ceiling: E = ½(θ̇² + η̇²) + g η to 1e-12 relative over 10⁵ impacts."""
    table = FieldTable(coin, g=1.0, e=1.0, H=3.0)
    start = [0.3, 1.5, 2.0, 1.5]
    flight = field_run(table, start, 100_000)
    assert len(flight) == 100_000 and flight.status == "bounces"
    assert (flight.side == 1).sum() > 1000 and (flight.side == 0).sum() > 1000   # both walls are met
    E0 = table.energy(start[1], start[2], start[3])
    assert np.max(np.abs(flight.energy - E0)) / E0 < 1e-12


def test_keller_hyperbolas():
    """A coin caught at the floor (no bounce), thin enough that the angle at landing decides: heads exactly
    between the hyperbolas ω·v/g = π(n ± ¼) (Keller 1986), on a grid of (v, ω)."""
    L = 1e-4
    wall = Wall.from_expression(f"{L}*abs(cos(t))")
    g = 1.0
    table = FieldTable(wall, g=g, e=1.0)
    assert table.landscape.names == ["tails", "heads"]
    v, w = np.meshgrid(np.linspace(0.5, 6.0, 45), np.linspace(0.2, 12.0, 45))
    v, w = v.ravel(), w.ravel()
    states = np.column_stack([np.full(v.size, 1.5 * math.pi), np.full(v.size, 1e-9), w, v])
    out = field_run_many(table, states, 1, catch=True)
    assert np.all(out["status"] == 2)
    heads = np.array([table.landscape.names[k] == "heads" for k in out["valley"]])
    x = w * v / g / math.pi
    keller = np.abs(x - np.round(x)) < 0.25
    far = np.abs(np.abs(x - np.round(x)) - 0.25) > 0.01     # the coin's size moves the boundary by ≤ 2e-3
    assert far.sum() > 1500 and heads.sum() > 300 and (~heads).sum() > 300
    assert np.array_equal(heads[far], keller[far])


# --------------------------------------------------------------------------- 3. outcomes

def test_landscape_of_the_coin(coin):
    land = landscape(coin)
    assert land.names == ["tails", "heads"]
    assert np.allclose(land.minima, [math.pi / 2, 3 * math.pi / 2], atol=1e-7)
    assert np.allclose(land.barriers, 1.0, atol=1e-14)
    assert list(land.valley([0.1, 1.0, 3.0, 3.2, 6.2])) == [0, 0, 0, 1, 1]


def test_inelastic_toss_settles_and_twin_agrees(coin):
    """e = 0.5: every toss ends settled (energy below its valley's barrier) or sliding on the floor with its
    normal velocity gone (the chattering limit) and its level above the barrier; the twin agrees on the valley
    and the number of floor impacts.  Sliding orbits that lift off again (over the coin's edge) are followed
    back into the air by ``settle_many``."""
    from coinwall.forward.dynamics.floor.slide import settle_many

    table = FieldTable(coin, g=1.0, e=0.5)
    rng = np.random.default_rng(1)
    n = 200
    states = np.column_stack([rng.uniform(0, 2 * math.pi, n), rng.uniform(1.5, 3.0, n), rng.uniform(-8, 8, n),
                              rng.uniform(0, 3, n)])
    many = field_run_many(table, states, 10_000)
    assert set(np.unique(many["status"])) <= {1, 4} and (many["status"] == 1).sum() > 150
    th, eta, w, v = many["final"].T
    level = eta + 0.5 * (w ** 2 + v ** 2) / table.g
    barrier = table.landscape.barriers[many["valley"]]
    assert np.all((level < barrier) == (many["status"] == 1))
    slid = many["status"] == 4
    _, d1, _ = coin.derivatives(th[slid])
    assert np.allclose(v[slid] - d1 * w[slid], 0.0, atol=1e-12)       # no normal velocity left
    for k in np.flatnonzero(many["status"] == 1)[:5]:
        ref = field_run(table, states[k], 200, method="reference")
        assert ref.status == "settled" and ref.valley == many["valley"][k]
        assert ref.floor_impacts == many["floor_impacts"][k]
    more = settle_many(table, states, 10_000)
    assert np.all(more["status"][many["status"] == 1] == 1)
    assert ((more["slides"] > 0) & (more["status"] == 1)).sum() >= 1     # lifted off the edge, then settled


def test_chattering_on_the_edge_stops_in_finite_time(coin):
    """Balanced on its edge (θ = 0, no rotation) the coin bounces ever lower: infinitely many impacts in the
    finite time 2v/(g(1 − e)); the kernel stops at the chattering criterion with a note, never looping."""
    table = FieldTable(coin, g=1.0, e=0.5)
    flight = field_run(table, [0.0, 1.5, 0.0, 0.0], 10_000)
    assert flight.status == "slides" and flight.note and len(flight) < 100
    # the first impact comes at t0 = 1, with speed 1; then flights of 2·e^k
    assert flight.time[-1] == pytest.approx(1.0 + 2 * 0.5 / (1 - 0.5), rel=1e-3)
    # lying flat it settles at once
    assert field_run(table, [math.pi / 2, 0.5, 0.0, 0.0], 100).status == "settled"


def test_elastic_floor_without_outcome_stops_at_the_budget(coin):
    table = FieldTable(coin, g=1.0, e=1.0)
    flight = field_run(table, [0.3, 2.5, 3.0, 1.0], 500)
    assert flight.status == "bounces" and len(flight) == 500 and flight.outcome is None and flight.note


@pytest.mark.parametrize("kwargs, match", [
    ({"g": -1.0}, "`g`"), ({"e": 0.0}, "`e`"), ({"e": 1.5}, "`e`"), ({"g": 0.0}, "floor without a field"),
    ({"g": float("nan")}, "`g`"), ({"g": 1.0, "H": 0.15}, "`H`"),
])
def test_bad_tables_are_refused(coin, kwargs, match):
    from coinwall.forward.errors import CoinwallError

    with pytest.raises(CoinwallError, match=match):
        FieldTable(coin, **kwargs)
