"""The billiard kernel: generated wall code, kernel vs reference, invariants, bad input, CLI.

Reference values and where they come from:

* generated wall code vs :meth:`Wall.derivatives` (casadi / Fourier backend): independent evaluation;
* kernel vs the plain-numpy reference stepper (``method="reference"``): independent implementation;
* Santaló: mean free path = π·Area/Perimeter of the domain (Santaló's formula for the
  boundary-map invariant measure; exact for an ergodic table), Area and Perimeter by
  :func:`scipy.integrate.quad` here, not by the library;
* time reversal and speed conservation: exact properties of specular billiards.
"""

import json
import math

import numpy as np
import pytest
from scipy.integrate import quad

from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard.table import Billiard, ensemble, random_states, simulate
from coinwall.forward.dynamics.billiard.wallcode import python_wall
from coinwall.forward.errors import CoinwallError, InvalidArgument, InvalidWall

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
ASYMMETRIC = "max(cos(t), max(cos(t-2.2)*0.8, cos(t+2.0)*0.9))"
FIELDS = ("time", "theta", "eta", "v_theta", "v_eta")


def _walls():
    return {
        "coin": (Wall.from_expression(ELLIPSE, {"eps": 99}), 3.0),
        "stick": (Wall.from_expression("abs(cos(t))"), 2.4),
        "asymmetric": (Wall.from_expression(ASYMMETRIC), 2.6),
        "fourier": (Wall.from_fourier(1.0, [0.1, 0.02, 0.003], [0.05, 0.0, 0.01]), 3.0),
    }


WALLS = _walls()


@pytest.mark.parametrize("name", ["coin", "stick", "asymmetric", "fourier", "samples"])
def test_generated_wall_code_matches_wall_derivatives(name):
    if name == "samples":
        theta = np.linspace(0, 2 * math.pi, 64, endpoint=False)
        wall = Wall.from_samples(theta, 1 + 0.2 * np.cos(theta) + 0.05 * np.sin(3 * theta))
    else:
        wall = WALLS[name][0]
    theta = np.linspace(-3.0, 10.0, 777) + 1e-3
    b, d1, d2 = wall.derivatives(theta)
    # each python_wall call generates the wall's code (casadi derivatives): once per order, not once per angle
    b1 = python_wall(wall)
    got = np.array([b1(x) for x in theta])
    np.testing.assert_allclose(got[:, 0], b, rtol=0, atol=1e-14)
    np.testing.assert_allclose(got[:, 1], d1, rtol=0, atol=1e-13)
    # wall_b2 (the kernel's last evaluation before a contact) also gives b''
    b2 = python_wall(wall, order=2)
    got2 = np.array([b2(x) for x in theta])
    np.testing.assert_allclose(got2[:, 0], b, rtol=0, atol=1e-14)
    np.testing.assert_allclose(got2[:, 1], d1, rtol=0, atol=1e-13)
    np.testing.assert_allclose(got2[:, 2], d2, rtol=1e-13, atol=1e-12)
    # wall_b3 (the contact phases' rates) against the fourth-order central difference of the wall's own b''
    h = 1e-4
    d3 = (8 * (wall.derivatives(theta + h)[2] - wall.derivatives(theta - h)[2])
          - (wall.derivatives(theta + 2 * h)[2] - wall.derivatives(theta - 2 * h)[2])) / (12 * h)
    b3 = python_wall(wall, order=3)
    got3 = np.array([b3(x) for x in theta])
    np.testing.assert_allclose(got3, d3, rtol=0, atol=1e-6 * np.max(np.abs(d3)))


def test_a_third_derivative_without_translation_is_nan_and_leaves_the_rest(monkeypatch):
    """Where casadi's b''' of an expression holds an operation with no numba translation, ``wall_b3`` is NaN (the
    contact phases then take first-order steps) and ``wall_b1``/``wall_b2`` are those of the wall as before."""
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.dynamics.billiard import wallcode

    wall = WALLS["coin"][0]
    before = wallcode.wall_source(wall)
    translate = wallcode._translate

    def refuse_third(func, name, *args):
        if name == "wall_b3":
            raise InvalidWall("no translation")
        return translate(func, name, *args)

    monkeypatch.setattr(wallcode, "_translate", refuse_third)
    source, constants = wallcode.wall_source(wall)
    assert source.startswith(before[0].split("def wall_b3")[0])
    assert math.isnan(python_wall(wall, order=3)(0.7))
    np.testing.assert_allclose(python_wall(wall, order=2)(0.7), [float(v) for v in wall.derivatives(0.7)], rtol=1e-13)


def _max_diff(a, b, n=None):
    return max(float(np.max(np.abs(getattr(a, f)[:n] - getattr(b, f)[:n]))) for f in FIELDS)


@pytest.mark.parametrize("name,H,collisions", [("ellipse", 3.0, 40), ("fourier", 3.0, 40)])
def test_kernel_matches_reference_whole_orbit(name, H, collisions):
    """Near-integrable tables (ε = 0.003, small Fourier ripple): rounding is hardly amplified,
    so whole orbits agree.  Chaotic tables are compared step by step below."""
    wall = Wall.from_expression(ELLIPSE, {"eps": 0.003}) if name == "ellipse" else WALLS["fourier"][0]
    table = Billiard(wall, H)
    start = random_states(table, 1, seed=7)[0]
    kern = simulate(table, start, collisions)
    ref = simulate(table, start, collisions, method="reference")
    assert len(kern) == len(ref) == collisions
    assert np.array_equal(kern.side, ref.side)
    assert _max_diff(kern, ref) < 1e-9


@pytest.mark.parametrize("name", ["coin", "stick", "asymmetric"])
def test_kernel_matches_reference_step_by_step(name):
    """Chaotic tables amplify rounding by a factor ~3–6 per collision (measured: 1e-9 after
    ~10 collisions), so whole orbits can only agree briefly.  Instead the reference
    restarts from every kernel collision and must find the same next collision: this
    checks every step of a 30-collision orbit without chaos in the way.  The whole orbit
    is also required to agree over its first 6 collisions."""
    wall, H = WALLS[name]
    table = Billiard(wall, H)
    start = random_states(table, 1, seed=3)[0]
    kern = simulate(table, start, 30)
    ref = simulate(table, start, 6, method="reference")
    assert np.array_equal(kern.side[:6], ref.side) and _max_diff(kern, ref, 6) < 1e-9
    for k in range(29):
        state = [kern.theta[k], kern.eta[k], kern.v_theta[k], kern.v_eta[k]]
        step = simulate(table, state, 1, method="reference")
        assert step.side[0] == kern.side[k + 1]
        assert abs(step.time[0] - (kern.time[k + 1] - kern.time[k])) < 1e-9
        for f in FIELDS[1:]:
            assert abs(getattr(step, f)[0] - getattr(kern, f)[k + 1]) < 1e-9, (k, f)


@pytest.mark.parametrize("name", ["coin", "stick", "asymmetric", "fourier"])
def test_contact_on_wall_and_speed_conserved(name):
    wall, H = WALLS[name]
    table = Billiard(wall, H)
    traj = simulate(table, random_states(table, 1, seed=11)[0], 20000)
    assert len(traj) == 20000 and traj.note == ""
    bottom = traj.side == 0
    residual = np.where(bottom, traj.eta - table.lower(traj.theta), table.upper(traj.theta) - traj.eta)
    # θ is reported unwrapped: after a long drift its last bit is worth |θ|·2.2e-16, which moves
    # the wall value by up to |b'| times that; the kernel itself works with θ mod 2π
    slope = np.abs(wall.derivatives(traj.theta + np.where(bottom, 0.0, math.pi))[1])
    allowed = 1e-12 + 4 * np.spacing(np.abs(traj.theta)) * (1 + slope)
    assert np.all(np.abs(residual) < allowed)
    assert np.max(np.abs(np.hypot(traj.v_theta, traj.v_eta) - 1.0)) < 1e-14
    assert np.all(np.diff(traj.time) > 0)
    # every collision lies inside the strip: the contact is on one wall and below/above the other
    assert np.all(traj.eta >= table.lower(traj.theta) - allowed)
    assert np.all(traj.eta <= table.upper(traj.theta) + allowed)


@pytest.mark.parametrize("name", ["coin", "stick", "asymmetric", "fourier"])
def test_reflection_uses_the_exact_slope_at_the_contact(name):
    """Specular reflection about the wall's normal at the reported contact point: with s the slope
    of the wall hit (b'(θ) below, −b'(θ+π) above, from Wall.derivatives, not the kernel's code),
    v_out = v_in − 2 (v_in·n) n, n ∝ (−s, 1).  The kernel takes the slope from a second-order
    Taylor step of its last wall evaluation (no evaluation at the contact itself), so this checks
    that step on every collision.  Kinks are excluded (the slope there is one-sided)."""
    wall, H = WALLS[name]
    table = Billiard(wall, H)
    # many short orbits: the reported θ is unwrapped, and its rounding (|θ|·2^-52) moves the slope
    # by |b''| times that, so long drifts would blur the check
    starts = random_states(table, 60, seed=23)
    checked = 0
    for start, traj in zip(starts, ensemble(table, starts, 50)):
        vin = np.column_stack([np.r_[start[2], traj.v_theta[:-1]], np.r_[start[3], traj.v_eta[:-1]]])
        top = traj.side == 1
        phi = np.mod(traj.theta, 2 * math.pi) + np.where(top, math.pi, 0.0)
        _, d1, d2 = wall.derivatives(phi)
        s = np.where(top, -d1, d1)
        f = 2.0 * (vin[:, 1] - s * vin[:, 0]) / (1.0 + s * s)
        expect_vt, expect_ve = vin[:, 0] + f * s, vin[:, 1] - f
        smooth = np.ones(len(traj), dtype=bool)
        for k in wall.kinks:
            smooth &= np.abs((phi - k.angle + math.pi) % (2 * math.pi) - math.pi) > 1e-9
        # a few roundings of θ (unwrapping, θ + π, mod 2π) times |b''|, and of the reflection itself
        allowed = 4e-15 + 8 * np.spacing(np.abs(traj.theta) + 2 * math.pi) * (1 + np.abs(d2))
        assert np.all(np.abs(traj.v_theta - expect_vt)[smooth] < allowed[smooth])
        assert np.all(np.abs(traj.v_eta - expect_ve)[smooth] < allowed[smooth])
        checked += int(smooth.sum())
    assert checked > 2500


@pytest.mark.parametrize("name,collisions", [("coin", 8), ("stick", 8), ("asymmetric", 8), ("fourier", 30)])
def test_time_reversal(name, collisions):
    """Run n collisions, reverse the incoming velocity at the last contact, run back n − 1:
    the contacts are revisited in reverse order and the final velocity is the reversed start
    velocity.  Chaotic tables amplify rounding (see above), so those runs are short."""
    wall, H = WALLS[name]
    table = Billiard(wall, H)
    start = random_states(table, 1, seed=5)[0]
    fwd = simulate(table, start, collisions)
    incoming = np.array([fwd.v_theta[-2], fwd.v_eta[-2]])
    back = simulate(table, [fwd.theta[-1], fwd.eta[-1], *(-incoming)], collisions - 1)
    np.testing.assert_allclose(back.theta, fwd.theta[-2::-1], atol=1e-9, rtol=0)
    np.testing.assert_allclose(back.eta, fwd.eta[-2::-1], atol=1e-9, rtol=0)
    np.testing.assert_array_equal(back.side, fwd.side[-2::-1])
    np.testing.assert_allclose([back.v_theta[-1], back.v_eta[-1]], -start[2:], atol=1e-9, rtol=0)
    np.testing.assert_allclose(back.time[-1], fwd.time[-1] - fwd.time[0], atol=1e-9, rtol=0)


def _quad_area_perimeter(wall, H):
    """Area and perimeter per period, by adaptive quadrature with the kinks as break points."""
    points = sorted({k.angle % (2 * math.pi) for k in wall.kinks} | {(k.angle + math.pi) % (2 * math.pi)
                                                                        for k in wall.kinks})

    def gap(t):
        return max(0.0, H - float(wall(t)) - float(wall(t + math.pi)))

    def arc(t):
        if gap(t) <= 0:
            return 0.0
        d = wall.derivatives(np.array([t, t + math.pi]))[1]
        return math.sqrt(1 + d[0] ** 2) + math.sqrt(1 + d[1] ** 2)

    opts = dict(points=points or None, limit=200, epsabs=1e-10)
    return quad(gap, 0, 2 * math.pi, **opts)[0], quad(arc, 0, 2 * math.pi, **opts)[0]


@pytest.mark.parametrize("name,H", [("coin", 1.9), ("stick", 1.5), ("asymmetric", 1.9)])
def test_mean_free_time_is_santalo(name, H):
    """⟨free time⟩ = π·Area/Perimeter, per ergodic component.

    The tables are chosen with a *finite horizon* (H below twice the largest wall value, so
    no straight channel runs along θ): with an open channel (e.g. the coin at H = 3) nearly
    horizontal flights are arbitrarily long, the free-time distribution has a ~1/t³ tail,
    its variance diverges and the spread of orbit means underestimates the error (we saw
    one orbit of 16 at +12 % there).  The coin and the stick here live in two mirror-image
    pockets (the coin cannot turn over), each with the same A/P by symmetry; the paper
    states the stick is chaotic for any H, and the orbits of all three show no regular
    islands.  Statistical error: the 16 orbits are independent, so the spread of their means
    gives the standard error; agreement within 4 standard errors, standard error < 0.5 %.  Each orbit runs
    10⁵ collisions (2·10⁴ before): a change of the kernel's rounding makes every orbit a new sample after
    ~30 collisions, and with 2·10⁴ one such sample of the coin came out 4.3 standard errors high (nine
    neighbouring samples within 2.9, twelve other seeds within 2.2, runs of 2·10⁵ within 1.4): the longer
    orbits make the test sharper (standard error ~2× smaller) and less at the mercy of one draw."""
    wall = WALLS[name][0]
    table = Billiard(wall, H)
    area, perimeter = _quad_area_perimeter(wall, H)
    expected = math.pi * area / perimeter
    lib_area, lib_perimeter = table.area_perimeter()
    assert abs(lib_area - area) < 1e-6 * area and abs(lib_perimeter - perimeter) < 1e-4 * perimeter
    trajs = ensemble(table, random_states(table, 16, seed=2), 100_000)
    means = np.array([t.time[-1] / len(t) for t in trajs])
    stderr = means.std(ddof=1) / math.sqrt(means.size)
    assert stderr < 0.005 * expected
    assert abs(means.mean() - expected) < 4 * stderr, (means.mean(), expected, stderr)


def test_ensemble_independent_of_workers_and_equal_to_simulate():
    wall, H = WALLS["coin"]
    table = Billiard(wall, H)
    states = random_states(table, 5, seed=42)
    one = ensemble(table, states, 500, workers=1)
    two = ensemble(table, states, 500, workers=2)
    for a, b, s in zip(one, two, states):
        single = simulate(table, s, 500)
        for f in FIELDS + ("side",):
            assert np.array_equal(getattr(a, f), getattr(b, f))
            assert np.array_equal(getattr(a, f), getattr(single, f))


def test_random_states_reproducible_and_inside():
    wall, H = WALLS["asymmetric"]
    table = Billiard(wall, H)
    a, b = random_states(table, 200, seed=9), random_states(table, 200, seed=9)
    assert np.array_equal(a, b) and not np.array_equal(a, random_states(table, 200, seed=10))
    assert np.all(a[:, 1] > table.lower(a[:, 0])) and np.all(a[:, 1] < table.upper(a[:, 0]))
    np.testing.assert_allclose(np.hypot(a[:, 2], a[:, 3]), 1.0, rtol=0, atol=1e-15)


def test_continuation_from_final_state():
    wall, H = WALLS["fourier"]
    table = Billiard(wall, H)
    start = random_states(table, 1, seed=1)[0]
    whole = simulate(table, start, 40)
    first = simulate(table, start, 20)
    rest = simulate(table, first.final_state, 20)
    np.testing.assert_allclose(rest.theta, whole.theta[20:], atol=1e-9, rtol=0)
    np.testing.assert_allclose(rest.time + first.time[-1], whole.time[20:], atol=1e-9, rtol=0)


def test_pinched_strip_keeps_particle_in_its_pocket():
    """The stick with H < its length (2): the coin cannot turn over (gap < 0 near θ = 0, π)."""
    table = Billiard(Wall.from_expression("abs(cos(t))"), 1.5)
    assert table.gap_min < 0 < table.gap_max
    traj = simulate(table, random_states(table, 1, seed=4)[0], 5000)
    assert len(traj) == 5000
    span = traj.theta.max() - traj.theta.min()
    assert span < math.pi  # a pocket around π/2 (or 3π/2) is narrower than π


@pytest.mark.parametrize("H,b0,match", [
    (1.9, 0.0, "no room"),      # circle of radius 1: needs H > 2
    (2.5, 0.3, "no room"),      # the offset adds 2·b0 = 0.6
    (float("nan"), 0.0, "finite"),
    ("x", 0.0, "real number"),
    (3.0, float("inf"), "finite"),
])
def test_bad_table(H, b0, match):
    with pytest.raises(InvalidArgument, match=match) as info:
        Billiard(Wall.from_expression("1+0*t"), H, b0)
    assert isinstance(info.value, CoinwallError) and "\n" not in str(info.value)


@pytest.mark.parametrize("state,collisions,match", [
    ([1.0, 1.0, 1.0, 0.0], 0, "positive integer"),
    ([1.0, 1.0, 1.0, 0.0], -3, "positive integer"),
    ([1.0, 1.0, 1.0, 0.0], 2.5, "positive integer"),
    ([1.0, 5.0, 1.0, 0.0], 10, "outside the strip"),
    ([1.0, float("nan"), 1.0, 0.0], 10, "finite"),
    ([1.0, 1.0, 0.0, 0.0], 10, "zero velocity"),
    ([1.0, 1.0, 1.0], 10, "shape"),
])
def test_bad_simulate_input(state, collisions, match):
    table = Billiard(Wall.from_expression(ELLIPSE, {"eps": 1}), 3.0)
    with pytest.raises(InvalidArgument, match=match) as info:
        simulate(table, state, collisions)
    assert "\n" not in str(info.value)


def test_wall_that_is_nan_between_checked_angles_is_refused_or_reported():
    """sqrt(sin²(θ − 1) − w²) is nan for |θ − 1| < w (and θ − 1 − π): too narrow for the wall's own
    check (4096 angles), so it must not be silently read as "no contact".  Width 1e-4: the kernel's
    denser cell sampling finds it and refuses the wall.  Width 1e-7: no sample lands in it; a
    vertical ray at θ = 1 meets the wall exactly there and the orbit stops with a note."""
    wide = Wall.from_expression("1 + 0.1*cos(t) + 1e-9*sqrt(sin(t-1)**2 - 1e-8)")
    with pytest.raises(InvalidWall, match="not finite at θ = 0.99") as info:
        simulate(Billiard(wide, 3.0), [2.0, 1.5, 0.6, 0.8], 10)
    assert "\n" not in str(info.value)
    narrow = Billiard(Wall.from_expression("1 + 0.1*cos(t) + 1e-9*sqrt(sin(t-1)**2 - 1e-14)"), 3.0)
    # from θ = 1 − 1.5e-7 (finite) nearly straight down: the contact is at θ ≈ 1 − 6e-8, inside
    traj = simulate(narrow, [1.0 - 1.5e-7, 1.5, 2e-7, -1.0], 10)
    assert len(traj) == 0 and "nan or infinity" in traj.note
    with pytest.raises(InvalidWall, match="not finite at θ = 1"):
        simulate(narrow, [1.0, 1.5, 0.0, -1.0], 10)  # a start right on the nan


def test_free_flight_is_reported_not_looped():
    """A horizontal ray in an open channel never collides: a finding in ``note``, no hang."""
    table = Billiard(Wall.from_fourier(0.5, [0.1]), 3.0)
    traj = simulate(table, [0.3, 1.5, 1.0, 0.0], 10)
    assert len(traj) == 0 and "free flight" in traj.note


def test_cli_simulate_json(capsys):
    from coinwall.cases.cli.main import main

    args = ["simulate", ELLIPSE, "--param", "eps=99", "--H", "3", "--collisions", "20000", "--seed", "1", "--json"]
    assert main(args) == 0
    first = json.loads(capsys.readouterr().out)
    for key in ("collisions", "seconds", "collisions_per_second", "compile_seconds", "mean_free_time",
                "bottom_fraction"):
        assert key in first
    assert first["collisions"] == 20000 and first["collisions_per_second"] > 0
    assert abs(first["mean_free_time"] - first["santalo_mean_free_time"]) < 0.05 * first["santalo_mean_free_time"]
    assert main(args) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["final_state"] == first["final_state"]  # same seed, same orbit


def test_cli_kappa_means_physical_lengths(capsys):
    """``--kappa K``: the wall, H and b0 are lengths in K's unit.  The coin drawn at twice the size
    (wall 2·b, H = 2·2.4, b0 = 2·0.01) with κ = 2 is the same billiard as the dimensionless one, so
    the orbit from the same seed is the same up to the rounding of (2·b)·(1/2) against b, which a
    chaotic orbit amplifies slowly over 30 collisions."""
    from coinwall.cases.cli.main import main

    common = ["--collisions", "30", "--seed", "4", "--json"]
    assert main(["simulate", ELLIPSE, "--param", "eps=99", "--H", "2.4", "--b0", "0.01", *common]) == 0
    plain = json.loads(capsys.readouterr().out)
    assert main(["simulate", "2*" + ELLIPSE, "--param", "eps=99", "--H", "4.8", "--b0", "0.02", "--kappa", "2",
                 *common]) == 0
    scaled = json.loads(capsys.readouterr().out)
    assert scaled["kappa"] == 2 and plain["kappa"] is None
    assert scaled["H"] == pytest.approx(2.4, abs=1e-15) and scaled["b0"] == pytest.approx(0.01, abs=1e-15)
    np.testing.assert_allclose(scaled["start"], plain["start"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(scaled["final_state"], plain["final_state"], rtol=0, atol=1e-8)


def test_wall_scaled_is_exact_and_keeps_kinks():
    stick = Wall.from_expression("L*abs(cos(t))", {"L": 3})
    half = stick.scaled(0.5)
    theta = np.linspace(0.1, 6.0, 50)
    for got, want in zip(half.derivatives(theta), stick.derivatives(theta)):
        np.testing.assert_allclose(got, 0.5 * want, rtol=1e-15, atol=0)
    assert [k.angle for k in half.kinks] == pytest.approx([k.angle for k in stick.kinks], abs=1e-12)
    assert half.kinks[0].jump == pytest.approx(0.5 * stick.kinks[0].jump, rel=1e-12)
    fourier = WALLS["fourier"][0]
    np.testing.assert_allclose(fourier.scaled(3.0)(theta), 3.0 * fourier(theta), rtol=1e-15, atol=0)
    for bad in (0.0, -1.0, float("nan"), float("inf"), True, "2"):
        with pytest.raises(CoinwallError, match="scale factor"):
            stick.scaled(bad)


@pytest.mark.parametrize("argv,match", [
    (["simulate", "abs(cos(t))", "--H", "1", "--collisions", "0"], "--collisions"),
    (["simulate", "abs(cos(t))", "--H", "1", "--collisions", "-5"], "--collisions"),
    (["simulate", "1+0*t", "--H", "1.5"], "no room"),
    (["simulate", "abs(cos(t))", "--H", "nan"], "--H must be a finite number"),
    (["simulate", "abs(cos(t))", "--H", "3", "--kappa", "0"], "--kappa must be a positive length"),
    (["simulate", "abs(cos(t))", "--H", "3", "--kappa", "-2"], "--kappa must be a positive length"),
    (["simulate", "1+0*t", "--H", "1.5", "--kappa", "2"], "no room"),  # b = 0.5 κ, H = 0.75 κ < 2 b
])
def test_cli_simulate_errors(capsys, argv, match):
    from coinwall.cases.cli.main import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1



# ------------------------------------------------------------------------------------------------ kernel internals
@pytest.mark.parametrize("name", ["coin", "stick", "asymmetric", "fourier"])
def test_cell_proxy_bounds_hold_on_an_independent_grid(name):
    """The kernel skips time intervals using b ≤ p_j + e_j (quintic proxy per cell) and b ≤ bmax_j.
    Check both on a grid the bounds were not built from (random points, 200 per cell), with the
    wall evaluated by Wall.__call__ (casadi / Fourier backend), not by the kernel's code."""
    from coinwall.forward.dynamics.billiard.cellbounds import cell_bounds as _cell_bounds

    wall = WALLS[name][0]
    bd = _cell_bounds(wall)
    edges, proxy = bd["edges"], bd["proxy"]
    rng = np.random.default_rng(17)
    u = rng.uniform(0.0, 1.0, (edges.size - 1, 200))
    s = np.diff(edges)[:, None] * u
    b = wall((edges[:-1, None] + s).ravel()).reshape(s.shape)
    p = sum(proxy[:, k, None] * s**k for k in range(6))
    assert np.all(np.abs(b - p) <= bd["perr"][:, None])
    assert np.all(b <= bd["bmax"][:, None])
    # |b'''| <= d3max: each difference quotient of b'' inside a cell is a mean value of b'''
    s_sorted = np.sort(s, axis=1)
    d2 = wall.derivatives((edges[:-1, None] + s_sorted).ravel())[2].reshape(s.shape)
    quotient = np.abs(np.diff(d2, axis=1) / np.diff(s_sorted, axis=1))
    assert np.all(quotient <= bd["d3max"][:, None])
    # |b''''| <= d4max likewise, from the generated code's exact b''' (not from the sampled b'' it was built on)
    d3 = np.vectorize(python_wall(wall, order=3))(edges[:-1, None] + s_sorted)
    assert np.all(np.abs(np.diff(d3, axis=1) / np.diff(s_sorted, axis=1)) <= bd["d4max"][:, None])
    # the proxy is useful: its error is far below the wall's variation over a cell
    assert np.median(bd["perr"]) < 1e-9


def test_shallow_ray_long_flight_agrees_with_reference():
    """A nearly horizontal ray (v_η = −4e-7) close to the upper wall: the lower wall is ~1e6 time
    units ahead in η while the upper wall is hit at once.  The search must not get lost far ahead
    (it once stalled where t + τ == t at t ≈ 4e6); the reference finds the same collisions."""
    table = Billiard(WALLS["coin"][0], 3.0)
    state = [648.5441680425411 % (2 * math.pi), 2.783060397966679, 0.9999999999999206, -3.9885691227592446e-07]
    kern = simulate(table, state, 3)
    ref = simulate(table, state, 3, method="reference")
    assert kern.note == "" and len(kern) == 3
    assert np.array_equal(kern.side, ref.side)
    assert _max_diff(kern, ref) < 1e-9


def test_near_tangent_pass_is_not_a_collision_and_does_not_stall():
    """Wall 1 + 0.1 cos θ (max 1.1 at θ = 0), a ray descending at slope 1e-4 that passes 1e-3 above
    the maximum: the gap has a minimum of ~1e-3 there (no contact), and again ~3.7e-4 one period
    later, then the ray hits near the third maximum.  Conservative steps must step past the near
    tangencies (they once stalled there) and agree with the reference stepper."""
    table = Billiard(Wall.from_fourier(1.0, [0.1]), 3.0)
    slope = -1e-4
    direction = np.array([1.0, slope]) / math.hypot(1.0, slope)
    start = [-0.5, 1.1 + 1e-3 - slope * 0.5, *direction]  # passes η = 1.101 at θ = 0
    kern = simulate(table, start, 2)
    ref = simulate(table, start, 2, method="reference")
    assert kern.note == "" and ref.note == ""
    assert np.array_equal(kern.side, ref.side) and kern.side[0] == 0
    assert kern.theta[0] > 2 * 2 * math.pi - 1.0  # not at the first or second maximum
    assert _max_diff(kern, ref) < 1e-9


def test_long_run_on_a_rippled_wall_completes():
    """20 harmonics (the benchmark's wall): many near-tangent passes; every collision is found."""
    rng = np.random.default_rng(0)
    rng.uniform(-1, 1, 10)  # the benchmark draws the 5-harmonic wall first
    k = np.arange(1, 21)
    amp = 0.3 / k**2
    wall = Wall.from_fourier(1.0, amp * rng.uniform(-1, 1, 20), amp * rng.uniform(-1, 1, 20))
    table = Billiard(wall, 3.0)
    traj = simulate(table, random_states(table, 1, seed=1)[0], 100_000)
    assert traj.note == "" and len(traj) == 100_000
