"""The direct rigid-body simulation (forward/dynamics/billiard/rigidbody.py) and its cross-check against the billiard.

Part A tests the rigid-body simulator on its own (invariants, the paper's
closed-form impulse, units, input checks).  Part B holds it to the billiard of
forward/dynamics/billiard/table.py: the paper's theorem (sections II A–B, eq. 2–8 and 13),
derived for this project's conventions in docs/equivalence.md.
"""

import importlib
import math

import numpy as np
import pytest

from coinwall.forward.dynamics.billiard.rigidbody import (
    EllipseShape,
    PolygonShape,
    RigidBody,
    billiard_to_body,
    body_to_billiard,
    simulate_rigid_body,
)
from coinwall.forward.errors import CoinwallError, InvalidArgument, InvalidOutline

# Bodies in units of κ (κ = 1).  The triangle and the off-centre ellipse have no symmetry axis
# through the centre of mass, so they pin the sign convention θ ↔ −θ.
TRIANGLE = [[0.9, 0.1], [-0.5, 0.7], [-0.4, -0.8]]
EPS = 0.3
STICK = PolygonShape.stick(1.0)
ELLIPSE = EllipseShape(1.0, 1.0 / math.sqrt(1.0 + EPS))           # x² + (1+ε)y² = 1 (paper eq. 15)
EGG = EllipseShape(1.0, 0.9, centre=(0.05, -0.03))                # off-centre: no symmetry axis
SHAPES = {"stick": STICK, "ellipse": ELLIPSE, "triangle": PolygonShape(TRIANGLE), "egg": EGG}

# Billiard walls written from the closed-form support functions of the same bodies
# (not from forward/dynamics/billiard/rigidbody.py): b(θ) = max_i p_i·(cos θ, sin θ) for a vertex list (the stick:
# |cos θ|, paper eq. 5), the paper's eq. 18 for the ellipse, and for an ellipse with centre c:
# sqrt(a² cos²θ + b² sin²θ) + c·(cos θ, sin θ).
WALLS = {
    "stick": ("abs(cos(t))", {}),
    "ellipse": ("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": EPS}),
    "triangle": ("max(max(0.9*cos(t)+0.1*sin(t), -0.5*cos(t)+0.7*sin(t)), -0.4*cos(t)-0.8*sin(t))", {}),
    "egg": ("sqrt(cos(t)**2 + 0.81*sin(t)**2) + 0.05*cos(t) - 0.03*sin(t)", {}),
}


def _unit_state(y, psi, direction):
    """Rigid-body state with unit billiard speed: ẏ = sin φ, ω = cos φ (κ = 1)."""
    return np.array([y, psi, math.sin(direction), math.cos(direction)])


# ====================================================================== Part A: the rigid body alone
@pytest.mark.parametrize("name", sorted(SHAPES))
def test_invariants(name):
    """Energy ½mẏ² + ½mκ²ω² is conserved by every impulse, the contact point is on the wall.

    Also: every contact is the body's extreme point towards that wall (the whole body's
    smallest gap is the contact gap, ≈ 0), and the contact point lies on the outline.
    """
    body = RigidBody(SHAPES[name], H=3.0, kappa=1.0, mass=2.0)
    start = _unit_state(1.5, 0.3, 0.9)
    traj = simulate_rigid_body(body, start, 400)
    assert len(traj) == 400 and traj.message == ""
    e0 = body.energy(start[2], start[3])
    assert np.max(np.abs(traj.energy - e0)) < 1e-13 * e0
    assert np.max(np.abs(traj.gap)) < 1e-12
    assert set(np.unique(traj.side)) == {0, 1}
    # contact point height in the lab: 0 on the floor, H·κ on the ceiling
    q = traj.contact
    height = traj.y + np.sin(traj.psi) * q[:, 0] + np.cos(traj.psi) * q[:, 1]
    assert np.max(np.abs(height - np.where(traj.side == 0, 0.0, body.ceiling))) < 1e-12
    shape = SHAPES[name]
    if isinstance(shape, EllipseShape):
        u = (q - np.array(shape.centre)) / [shape.a, shape.b]
        assert np.max(np.abs(np.hypot(u[:, 0], u[:, 1]) - 1)) < 1e-14
    else:
        assert all(any(np.array_equal(p, v) for v in shape.vertices) for p in q)
    # the lever arm is the lab x of the contact point
    lever = np.cos(traj.psi) * q[:, 0] - np.sin(traj.psi) * q[:, 1]
    assert np.max(np.abs(lever - traj.lever)) < 1e-15


def _dense_outline(shape, n=4096):
    if isinstance(shape, EllipseShape):
        s = np.linspace(0, 2 * np.pi, n, endpoint=False)
        return np.stack([shape.centre[0] + shape.a * np.cos(s), shape.centre[1] + shape.b * np.sin(s)], axis=1)
    return shape.vertices


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_no_missed_collision(name):
    """Brute force: along every free flight (64 samples) every outline point stays between the walls.

    Independent of the collision finder: the outline is sampled densely (4096 points for an
    ellipse, the vertices for a polygon) and moved by the free-flight formulas.  A skipped
    collision would put part of the body through a wall.  The sampled ellipse lies inside the
    true one, so this sees penetrations deeper than ~(2π/4096)²/2·a ≈ 1e-6.
    """
    shape = SHAPES[name]
    body = RigidBody(shape, H=3.0)
    start = _unit_state(1.5, 0.3, 0.9)
    traj = simulate_rigid_body(body, start, 300)
    states = np.vstack([start, traj.states])
    times = np.concatenate([[0.0], traj.time])
    pts = _dense_outline(shape)
    frac = np.linspace(0, 1, 64)
    worst = np.inf
    for (y, psi, ydot, omega), t0, t1 in zip(states[:-1], times[:-1], times[1:]):
        dt = (t1 - t0) * frac
        yy = y + ydot * dt
        pp = psi + omega * dt
        heights = yy[:, None] + np.outer(np.sin(pp), pts[:, 0]) + np.outer(np.cos(pp), pts[:, 1])
        worst = min(worst, heights.min(), (body.ceiling - heights).min())
    assert worst > -1e-12


@pytest.mark.parametrize("name,collisions", [("ellipse", 300), ("egg", 300), ("stick", 10), ("triangle", 4)])
def test_time_reversal(name, collisions):
    """Reversing the velocities mid-flight retraces the collisions backwards.

    Reversed collision j happens at forward collision N+1−j, with the velocities after it equal
    to minus the forward velocities before that collision.  The ellipse and the egg orbits are
    regular (rounding grows slowly), the stick and triangle orbits are chaotic: there N is
    kept below the Lyapunov horizon of that orbit (measured: the reversal error of this
    triangle orbit is 8e-15 for N = 4 but 2e-8 for N = 6; the stick's is 4e-12 for N = 10).
    """
    body = RigidBody(SHAPES[name], H=3.0)
    start = _unit_state(1.5, math.pi + 0.1, 1.2) if name == "ellipse" else _unit_state(1.5, 3.243, 0.728)
    forward = simulate_rigid_body(body, start, collisions)
    last = forward.states[-1]
    half = 0.5 * simulate_rigid_body(body, last, 1).time[0]
    turned = np.array([last[0] + last[2] * half, last[1] + last[3] * half, -last[2], -last[3]])
    back = simulate_rigid_body(body, turned, collisions)
    before = -np.vstack([start, forward.states[:-1]])[:, 2:]  # velocities before collision i, reversed
    n = collisions
    np.testing.assert_array_equal(back.side, forward.side[::-1])
    np.testing.assert_allclose(back.y, forward.y[::-1], atol=1e-9, rtol=0)
    np.testing.assert_allclose(back.psi, forward.psi[::-1], atol=1e-9, rtol=0)
    np.testing.assert_allclose(back.states[:, 2:], before[::-1], atol=1e-9, rtol=0)
    np.testing.assert_allclose(back.time, half + forward.time[-1] - forward.time[::-1], atol=1e-9, rtol=0)
    assert n == len(back)


def test_stick_impulse_is_paper_eq_3_and_4():
    """A physical stick (L = 2, uniform rod κ = L/√3, m = 3): one floor collision against eq. 3–4.

    Paper eq. 4: δη̇ = −2(η̇ + (L/κ)θ̇ sin θ)/(1 + (L/κ)² sin²θ); eq. 3 (with the paper's
    misprinted L/R read as L/κ): δθ̇ = (L/κ) sin θ δη̇.  θ, η are the billiard coordinates of the
    rigid-body state (docs/equivalence.md); at the contact the vertex (L, 0) touches, cos θ > 0.
    """
    L = 2.0
    shape = PolygonShape.stick(L)
    kappa = shape.uniform_kappa
    assert kappa == pytest.approx(L / math.sqrt(3), rel=1e-15)
    body = RigidBody(shape, H=5.0, kappa=kappa, mass=3.0)
    start = np.array([2.5, -math.pi / 2 - 0.4, -1.0, 0.3])  # θ = 0.4: vertex (L, 0) is the lowest point
    traj = simulate_rigid_body(body, start, 1)
    assert traj.side[0] == 0 and np.array_equal(traj.contact[0], [L, 0.0])
    theta, eta, v_theta, v_eta = body_to_billiard(traj.states[0], kappa)
    _, _, w_theta, w_eta = body_to_billiard(start, kappa)  # velocities before the collision
    r = L / kappa
    d_eta = -2 * (w_eta + r * w_theta * math.sin(theta)) / (1 + r * r * math.sin(theta) ** 2)
    assert v_eta - w_eta == pytest.approx(d_eta, rel=1e-13)
    assert v_theta - w_theta == pytest.approx(r * math.sin(theta) * d_eta, rel=1e-13)
    assert eta == pytest.approx(r * abs(math.cos(theta)), rel=1e-13)  # on the wall b = (L/κ)|cos θ|, eq. 5


def test_units_scale_out():
    """A body scaled by κ = 2.5 (and any mass) has the same billiard trajectory as the κ = 1 body.

    The billiard coordinates η = y/κ, θ and time are dimensionless up to the common time unit;
    with ẏ = κ·η̇ the times agree as well.
    """
    kappa = 2.5
    unit = RigidBody(PolygonShape(TRIANGLE), H=3.0)
    big = RigidBody(PolygonShape(np.array(TRIANGLE) * kappa), H=3.0, kappa=kappa, mass=7.0)
    start = np.array([1.5, 0.3, 0.6, 0.8])
    a = simulate_rigid_body(unit, start, 8)
    b = simulate_rigid_body(big, billiard_to_body(body_to_billiard(start), kappa), 8)
    np.testing.assert_array_equal(a.side, b.side)
    np.testing.assert_allclose(b.billiard, a.billiard, atol=1e-11, rtol=0)
    np.testing.assert_allclose(b.time, a.time, atol=1e-11, rtol=0)


def test_coordinate_maps_are_inverse():
    rng = np.random.default_rng(3)
    states = rng.normal(size=(20, 4))
    np.testing.assert_allclose(billiard_to_body(body_to_billiard(states, 1.7), 1.7), states, atol=1e-15)


def test_uniform_kappa():
    """Closed forms: square of side 2 about its centre κ² = 2/3; uniform ellipse κ² = (a²+b²)/4."""
    square = PolygonShape([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    assert square.uniform_kappa ** 2 == pytest.approx(2 / 3, rel=1e-14)
    assert EllipseShape(2.0, 1.0).uniform_kappa ** 2 == pytest.approx(5 / 4, rel=1e-14)


@pytest.mark.parametrize("make", [
    lambda: RigidBody(STICK, H=-1.0),
    lambda: RigidBody(STICK, H=3.0, kappa=0.0),
    lambda: RigidBody(STICK, H=3.0, mass=float("nan")),
    lambda: RigidBody("stick", H=3.0),
    lambda: PolygonShape.stick(0.0),
    lambda: EllipseShape(1.0, -0.5),
    lambda: PolygonShape([[0.0, float("inf")]]),
    lambda: simulate_rigid_body(RigidBody(STICK, H=3.0), [1.5, 0.0, 1.0, 0.0], 0),
    lambda: simulate_rigid_body(RigidBody(STICK, H=3.0), [0.5, -math.pi / 2, 1.0, 0.0], 5),  # through the floor
    lambda: simulate_rigid_body(RigidBody(STICK, H=3.0), [1.5, 0.0, 0.0, 0.0], 5),
    lambda: simulate_rigid_body(RigidBody(STICK, H=3.0), [1.5, 0.0, 1.0], 5),
])
def test_bad_input_raises(make):
    with pytest.raises(CoinwallError) as info:
        make()
    assert isinstance(info.value, (InvalidArgument, InvalidOutline))
    assert "\n" not in str(info.value)


# ====================================================================== Part B: against the billiard
def _billiard_module():
    """coinwall.forward.dynamics.billiard.table if it exposes the contract's Billiard and simulate, else None."""
    try:
        module = importlib.import_module("coinwall.forward.dynamics.billiard.table")
    except ImportError:
        return None
    if not (hasattr(module, "Billiard") and hasattr(module, "simulate")):
        return None
    return module


billiard = _billiard_module()
needs_billiard = pytest.mark.skipif(
    billiard is None, reason="forward/dynamics/billiard/table.py does not (yet) expose Billiard and simulate")


def _compare(name, H, start, collisions, restart, method):
    """Billiard run of `collisions` from `start`; rigid body restarted from the billiard every `restart`.

    Returns the largest differences (state, time) and checks the wall sequence on the way.
    """
    from coinwall.forward import Wall

    text, params = WALLS[name]
    table = billiard.Billiard(Wall.from_expression(text, params), H)
    body = RigidBody(SHAPES[name], H=H)
    traj = billiard.simulate(table, start, collisions, method=method)
    bill = np.stack([traj.theta, traj.eta, traj.v_theta, traj.v_eta], axis=1)
    assert bill.shape == (collisions, 4)
    state_err = time_err = 0.0
    for first in range(0, collisions, restart):
        origin = start if first == 0 else bill[first - 1]
        t0 = 0.0 if first == 0 else traj.time[first - 1]
        count = min(restart, collisions - first)
        rigid = simulate_rigid_body(body, billiard_to_body(origin), count)
        assert len(rigid) == count, rigid.message
        np.testing.assert_array_equal(rigid.side, np.asarray(traj.side[first:first + count]),
                                      err_msg=f"wall sequence differs after collision {first}")
        state_err = max(state_err, float(np.max(np.abs(rigid.billiard - bill[first:first + count]))))
        time_err = max(time_err, float(np.max(np.abs(rigid.time + t0 - traj.time[first:first + count]))))
    return state_err, time_err


# Regular orbits (on invariant curves; rounding grows roughly linearly, measured: a 1e-10
# perturbation grows < 100× over 500 collisions): one uninterrupted run of 500 collisions.
# Chaotic orbits (the stick and the triangle are chaotic for every start tried): a 1e-10
# perturbation grows ≈ 3× per collision on average but up to ~1e3 in a single near-grazing
# collision, so 1e-16 rounding can reach 1e-9 after 5–20 collisions.  There the rigid body is
# restarted from the billiard's state after every collision (the one-step maps must agree to
# rounding, 1e-12) and, separately, every 3 collisions (measured worst 2e-11 over 300 collisions).
CROSS = [
    ("stick", 3.0, _unit_state(1.5, 0.3, 0.9), 300, 3),
    ("triangle", 3.0, _unit_state(1.5, 0.3, 0.9), 300, 3),
    ("ellipse", 3.0, _unit_state(1.5, math.pi + 0.1, 1.2), 500, 500),
    ("egg", 3.0, _unit_state(1.5, 3.243, 0.728), 500, 500),
]


@needs_billiard
@pytest.mark.parametrize("method", ["kernel", "reference"])
@pytest.mark.parametrize("name,H,start,collisions,restart", CROSS, ids=[c[0] for c in CROSS])
def test_rigid_body_equals_billiard(name, H, start, collisions, restart, method):
    """The paper's theorem, demonstrated: the rigid body and the billiard are the same dynamics.

    What this proves: starting from corresponding states (θ = −ψ − π/2, η = y/κ, θ̇ = −ω,
    η̇ = ẏ/κ), the rigid body — collisions found from its rotated outline, impulses from the
    lever arm of the contact point — hits the same wall at the same time in the same state as the
    point particle reflecting specularly in the (θ, η) strip between b(θ) and H − b(θ+π), for a
    symmetric smooth body (ellipse), a body with corners (stick), and two bodies with no symmetry
    axis (triangle, off-centre ellipse), which would fail if the sign of θ or the π shift of the
    upper wall were wrong.  For the regular orbits (ellipse, egg) it holds over 500 collisions
    in one run.  For the chaotic ones it proves that the collision maps agree to rounding at
    each of 300 collisions, and that 3-collision stretches agree to 1e-9; the restarts remove
    only the exponential growth of rounding errors, which is a property of the dynamics (its
    Lyapunov exponent), not a discrepancy between the two simulations.
    """
    state_err, time_err = _compare(name, H, body_to_billiard(start), collisions, restart, method)
    assert state_err < 1e-9
    assert time_err < 1e-9
    if restart > 1:
        state_err, time_err = _compare(name, H, body_to_billiard(start), collisions, 1, method)
        assert state_err < 1e-12
        assert time_err < 1e-12


# b(−θ) of WALLS' triangle and egg, written in the same structure as WALLS' (each sin term's coefficient negated as a
# number), so that they share its compiled kernel (a kernel is compiled per expression structure; the numbers are its
# constants)
MIRRORED = {
    "triangle": ("max(max(0.9*cos(t)+(-0.1)*sin(t), -0.5*cos(t)+(-0.7)*sin(t)), -0.4*cos(t)-(-0.8)*sin(t))", {}),
    "egg": ("sqrt(cos(t)**2 + 0.81*sin(t)**2) + 0.05*cos(t) - (-0.03)*sin(t)", {}),
}


@needs_billiard
@pytest.mark.parametrize("name", sorted(MIRRORED))
def test_mirror_image_wall_disagrees(name):
    """The sign convention is pinned: the mirror image's wall b(−θ) gives a different trajectory.

    Had the rigid body ↔ billiard map used θ = ψ + π/2 (θ counter-clockwise), the mirrored
    wall would be the one that matches; for a body with no symmetry axis it is a different
    billiard, and within 20 collisions the two runs differ macroscopically.
    """
    from coinwall.forward import Wall

    start = _unit_state(1.5, 0.3, 0.9) if name == "triangle" else _unit_state(1.5, 3.243, 0.728)
    text, params = MIRRORED[name]
    table = billiard.Billiard(Wall.from_expression(text, params), 3.0)
    traj = billiard.simulate(table, body_to_billiard(start), 20)
    rigid = simulate_rigid_body(RigidBody(SHAPES[name], H=3.0), start, 20)
    bill = np.stack([traj.theta, traj.eta, traj.v_theta, traj.v_eta], axis=1)
    assert np.max(np.abs(rigid.billiard - bill)) > 1e-3
