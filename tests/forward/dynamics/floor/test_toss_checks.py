"""The toss that lands, checked against independent references: the direct rigid-body simulation in gravity,
the fairness of a bouncing toss, and the uncertainty exponent of the basin boundary.

References that do not share the code under test: forward/dynamics/billiard/rigidbody.py (the body's own outline, the
lab impulse at the contact point, its own certified collision search) for the field kernel; closed forms
derived in the docstrings for the fairness and the exponent.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard.rigidbody import (
    EllipseShape,
    PolygonShape,
    RigidBody,
    body_to_billiard,
    simulate_rigid_body,
)
from coinwall.forward.dynamics.floor.field import FieldTable, field_run

# The bodies, and their walls written from the closed-form support functions (b = h/κ), not from rigidbody.py:
# a vertex list has h(θ) = max_i p_i·(cos θ, sin θ); the ellipse x²/a² + y²/b² = 1 with a = κ, b = κ/sqrt(1+ε)
# has h/κ = sqrt((1 + ε cos²θ)/(1 + ε)) (paper eq. 18; the coin's expression, whose field kernel the suite
# compiles anyway).
TRIANGLE = [[0.9, 0.1], [-0.5, 0.7], [-0.4, -0.8]]
BODIES = {
    "triangle": (PolygonShape(TRIANGLE), 1.0,
                 "max(max(0.9*cos(t)+0.1*sin(t), -0.5*cos(t)+0.7*sin(t)), -0.4*cos(t)-0.8*sin(t))", {}),
    # κ = 0.5: the billiard's lengths are the body's over κ, its field g/κ
    "ellipse": (EllipseShape(0.5, 0.5 / math.sqrt(1.3)), 0.5, "sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 0.3}),
}


def _pair(name, H, g, e):
    shape, kappa, text, params = BODIES[name]
    body = RigidBody(shape, H=None if H is None else H, kappa=kappa, mass=0.37, g=g, e=e)
    table = FieldTable(Wall.from_expression(text, params), g=g / kappa, e=e, H=H)
    return body, table, kappa


@pytest.mark.parametrize("name, H, g, e, start, impacts", [
    ("triangle", 4.0, 2.0, 1.0, [0.9, 0.3, 0.5, 2.2], 200),     # floor and ceiling, elastic
    ("ellipse", 10.0, 1.0, 0.97, [0.9, 0.4, 0.75, -2.0], 150),  # floor and ceiling, inelastic, κ = 0.5
    ("triangle", None, 3.0, 0.8, [2.0, 0.3, 0.8, 8.0], 150),    # a floor only: the toss that lands
])
def test_rigid_body_in_gravity_is_the_field_billiard_impact_by_impact(name, H, g, e, start, impacts):
    """From every state of a rigid-body orbit, the field kernel's next impact is the rigid body's next collision
    (same wall, time, angle, height and velocities to 1e-10), over 90 and more impacts; and whole runs agree
    for their first impacts (the orbits are chaotic: rounding grows several-fold per impact).  The comparison
    ends where the kernel declares the chattering limit (``rest``/``slides``: it then takes the normal velocity
    away, by its stated criterion, while the rigid body goes on bouncing ever lower)."""
    body, table, kappa = _pair(name, H, g, e)
    rigid = simulate_rigid_body(body, start, impacts)
    bill = rigid.billiard
    n = len(rigid)
    assert n >= min(impacts, 100), rigid.message
    worst = 0.0
    compared = 0
    for i in range(n - 1):
        one = field_run(table, bill[i], 1)
        if one.status in ("rest", "slides"):
            break
        assert len(one) == 1 and one.side[0] == rigid.side[i + 1], i
        dt = rigid.time[i + 1] - rigid.time[i]
        worst = max(worst, abs(one.time[0] - dt) / (1 + dt),
                    float(np.max(np.abs(np.array([one.theta[0], one.eta[0], one.v_theta[0], one.v_eta[0]])
                                        - bill[i + 1]))))
        compared += 1
    assert compared >= 90 and worst < 1e-10, (compared, worst)
    # and the whole orbit from the start, for as long as the kernel runs (it stops when the toss is decided)
    whole = field_run(table, body_to_billiard(start, kappa), 6)
    m = len(whole)
    assert m >= 4 and np.array_equal(whole.side, rigid.side[:m])
    assert np.allclose(np.column_stack([whole.theta, whole.eta, whole.v_theta, whole.v_eta]), bill[:m],
                       rtol=0, atol=1e-8)


def test_rigid_body_restitution_and_energy():
    """e < 1: each floor impact leaves the contact point with −e times its normal velocity (checked in the lab);
    e = 1 in gravity conserves ½mẏ² + ½mκ²ω² + mgy."""
    shape, kappa, _, _ = BODIES["ellipse"]
    body = RigidBody(shape, H=None, kappa=kappa, mass=0.37, g=9.8, e=0.6)
    start = [1.5, 0.2, 0.0, 4.0]
    traj = simulate_rigid_body(body, start, 6)
    assert len(traj) == 6
    _y, _psi, ydot, omega = start
    for i in range(6):
        dt = traj.time[i] - (traj.time[i - 1] if i else 0.0)
        before_ydot = (traj.ydot[i - 1] if i else ydot) - 9.8 * dt
        before_omega = traj.omega[i - 1] if i else omega
        lever = traj.lever[i]
        approach = before_ydot + before_omega * lever
        after = traj.ydot[i] + traj.omega[i] * lever
        assert after == pytest.approx(-0.6 * approach, rel=1e-12)
    elastic = RigidBody(shape, H=6.0, kappa=kappa, mass=0.37, g=9.8, e=1.0)
    traj = simulate_rigid_body(elastic, start, 500)
    e0 = elastic.energy(start[2], start[3], start[0])
    assert len(traj) == 500 and np.max(np.abs(traj.energy - e0)) < 1e-12 * e0


@pytest.mark.parametrize("kwargs, match", [({"g": -1.0}, "`g`"), ({"e": 0.0}, "`e`"), ({"e": 1.2}, "`e`"),
                                           ({"g": 0.0}, "floor without a field"), ({"g": float("nan")}, "`g`")])
def test_bad_rigid_bodies_are_refused(kwargs, match):
    from coinwall.forward.errors import InvalidArgument

    with pytest.raises(InvalidArgument, match=match):
        RigidBody(BODIES["ellipse"][0], H=None, **kwargs)


# --------------------------------------------------------------------------- fairness versus bounces

COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def test_fairness_follows_the_uninterrupted_kernel_toss_by_toss():
    """The n-th-impact outcome of ``fairness`` (kernel run to each floor contact, then lifted off by the certified
    free time) is the valley of the n-th impact of one uninterrupted ``field_run`` of the same toss (or its
    settled outcome), for 300 tosses and n ≤ 10 (rounding differences grow ~4× per impact: 1e-16·4¹⁰ ≈ 1e-10,
    far from deciding a valley)."""
    from coinwall.forward.dynamics.floor.fairness import fairness
    from coinwall.forward.dynamics.floor.toss import launch_states

    coin = Wall.from_expression(COIN, {"eps": 99.0})
    table = FieldTable(coin, g=1.0, e=0.6)
    mean, sigma, n, samples = (2.0, 5.0), (0.3, 1.0), 10, 300
    result = fairness(table, mean, sigma, 1.2, bounces=n, samples=samples, seed=7)
    rng = np.random.default_rng(7)
    v, w = rng.normal(mean[0], sigma[0], samples), rng.normal(mean[1], sigma[1], samples)
    states = launch_states(table, v, w, 1.2)
    heads_k = table.landscape.names.index("heads")
    heads = np.zeros(n)
    decided = np.zeros(n)
    for state in states:
        flight = field_run(table, state, n)
        valleys = table.landscape.valley(flight.theta)
        for k in range(n):
            if k < len(flight):
                valley = valleys[k]
            elif flight.status in ("settled", "rest"):
                valley = flight.valley
            else:
                continue
            decided[k] += 1
            heads[k] += valley == heads_k
    assert np.array_equal(np.round((result.heads + result.tails) * samples), decided)
    assert np.array_equal(np.round(result.heads * samples), heads)
    assert result.settled[-1] > 0.3     # the comparison covers settled tosses, too


def test_fairness_of_the_caught_thin_coin_is_kellers():
    """n = 1 for a thin coin caught at the floor (the ε = 99 ellipse scaled to semi-axes 1e-4 and 1e-5,
    launched flat just above the floor): heads exactly when ω v/g is within π/4 of a multiple of π (Keller), for
    the same Gaussian draws, except for draws within 1% of a boundary (the coin's size moves it by ≤ 2e-3)."""
    from coinwall.forward.dynamics.floor.fairness import fairness

    wall = Wall.from_expression(COIN, {"eps": 99.0}).scaled(1e-4)
    table = FieldTable(wall, g=1.0, e=0.5)
    mean, sigma, samples = (3.0, 4.0), (1.0, 2.0), 20_000
    result = fairness(table, mean, sigma, 3e-5, bounces=1, samples=samples, seed=11)
    rng = np.random.default_rng(11)
    v, w = rng.normal(mean[0], sigma[0], samples), rng.normal(mean[1], sigma[1], samples)
    x = w * v / math.pi
    keller = np.abs(x - np.round(x)) < 0.25
    near = np.abs(np.abs(x - np.round(x)) - 0.25) < 0.01
    assert result.undecided[0] == 0.0
    assert abs(result.heads[0] * samples - keller.sum()) <= near.sum()
    assert near.sum() < 0.05 * samples


@pytest.mark.slow
def test_bounces_randomise_the_toss():
    """The caught toss (n = 1) is biased for this hand; with e = 0.9 the bias after 30 floor bounces is zero
    within its error and the toss is fair to 0.01 from some bounce on; ``fair_after`` refuses to claim 0.001
    with 20 000 tosses (its 2σ band is 0.007)."""
    from coinwall.forward.dynamics.floor.fairness import fairness

    coin = Wall.from_expression(COIN, {"eps": 99.0})
    result = fairness(FieldTable(coin, g=1.0, e=0.9), (2.0, 5.0), (0.05, 0.2), 1.2, bounces=30, samples=20_000)
    assert abs(result.bias[0]) > 4 * result.stderr[0]
    assert abs(result.bias[-1]) < 3 * result.stderr[-1]
    assert result.fair_after(0.01) is not None and result.fair_after(0.001) is None


# --------------------------------------------------------------------------- the uncertainty exponent

def _keller_length(v0, omega0, g=1.0):
    """Total length, in the box scaled to the unit square, of Keller's boundaries ω v/g = π(n ± ¼) (numpy)."""
    v = np.linspace(v0[0], v0[1], 20001)
    total = 0.0
    for n in range(200):
        for q in (0.25, 0.75):
            w = math.pi * (n + q) * g / v
            inside = (w >= omega0[0]) & (w <= omega0[1])
            if inside.sum() > 1:
                x = (v[inside] - v0[0]) / (v0[1] - v0[0])
                y = (w[inside] - omega0[0]) / (omega0[1] - omega0[0])
                total += float(np.sum(np.hypot(np.diff(x), np.diff(y))))
    return total


def test_uncertainty_exponent_of_the_smooth_keller_boundary_is_one():
    """The caught thin coin's basin boundaries are Keller's hyperbolas, smooth: α = 1 (within 3σ, σ < 0.08), and
    f(ε) = (4/π) L ε with L their length in the scaled box (the uncertainty module's docstring): each count
    within 3 of its Poisson standard deviations √(expected) of N·(4/π)Lε (ε ≤ 3e-3, a thirtieth of the
    curves' smallest spacing, where the O(ε²) terms are below 1%)."""
    from coinwall.forward.dynamics.floor.uncertainty import uncertainty_exponent

    wall = Wall.from_expression(COIN, {"eps": 99.0}).scaled(1e-4)
    table = FieldTable(wall, g=1.0, e=0.5)
    box_v, box_w = (0.5, 3.0), (0.5, 6.0)
    result = uncertainty_exponent(table, box_v, box_w, 3e-5, epsilons=(3e-3, 1e-3, 3e-4), samples=20_000,
                                  catch=True, seed=5)
    assert result.alpha_stderr < 0.08 and abs(result.alpha - 1.0) < 3 * result.alpha_stderr, result
    expected = 4 / math.pi * _keller_length(box_v, box_w) * result.epsilons * result.samples
    assert np.all(np.abs(result.counts - expected) < 3 * np.sqrt(expected)), (result.counts, expected)


def test_uncertainty_exponent_of_the_bouncing_toss_is_fractal():
    """With bounces (e = 0.6) the boundary is far from smooth on these scales: α well below 1."""
    from coinwall.forward.dynamics.floor.uncertainty import uncertainty_exponent

    coin = Wall.from_expression(COIN, {"eps": 99.0})
    result = uncertainty_exponent(FieldTable(coin, g=1.0, e=0.6), (0.0, 3.0), (0.0, 8.0), 1.2,
                                  epsilons=(1e-2, 1e-4, 1e-6), samples=3000, seed=2)
    assert result.alpha + 3 * result.alpha_stderr < 0.5, result


def test_toss_uncertainty_on_the_command_line(capsys):
    import json

    from coinwall.cases.cli.main import main

    code = main(["toss", "case:coin", "--g", "1", "--e", "0.6", "--height", "1.2", "--v0", "0:3:2", "--omega",
                 "0:8:2", "--uncertainty", "1e-5:1e-2:3", "--samples", "500", "--seed", "3", "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["epsilons"]) == 3 and 0 < out["alpha"] < 1 and out["samples"] == 500
    assert main(["toss", "case:coin", "--uncertainty", "1e-5:1e-2:3", "--v0", "1:1:3"]) == 2
    assert "needs a box" in capsys.readouterr().err


# --------------------------------------------------------------------------- scans over (e, toss energy)

def test_toss_scan_cells_are_heads_fraction(tmp_path):
    """A 2 × 2 scan over (restitution, launch height) on the scan engine: each cell's shares are those of
    ``toss.heads_fraction`` with the cell's seed (same draws: an independent entry point of the library)."""
    pytest.importorskip("distributed")
    xr = pytest.importorskip("xarray")
    pytest.importorskip("zarr")
    from coinwall.cases.scan import TableSpec, scan
    from coinwall.cases.scan.grid import cell_seed
    from coinwall.forward.dynamics.floor.hand import heads_fraction

    spec = TableSpec(COIN, (("eps", 99.0),))
    store = str(tmp_path / "toss.zarr")
    result = scan("toss", spec, {"restitution": "0.5,0.9", "H": "1.2,2.0"}, output=store,
                  options={"tosses": 300}, seed=3, scheduler="synchronous")
    assert result.computed == 4 and result.refused == 0
    data = xr.open_zarr(store)
    coin = Wall.from_expression(COIN, {"eps": 99.0})
    for i, e in enumerate((0.5, 0.9)):
        for j, height in enumerate((1.2, 2.0)):
            ref = heads_fraction(FieldTable(coin, g=1.0, e=e), (2.0, 5.0), (0.04, 0.1), height, samples=300,
                                 seed=cell_seed(3, (e, height)))
            assert float(data["heads"].values[i, j]) == pytest.approx(ref.fractions["heads"][0], abs=1e-12)
            assert float(data["undecided"].values[i, j]) == pytest.approx(
                ref.fractions.get("undecided", (0.0, 0.0))[0], abs=1e-12)
            assert float(data["level"].values[i, j]) == pytest.approx(height + (4 + 25) / 2)


def test_bad_toss_inputs_are_refused(tmp_path):
    from coinwall.forward.dynamics.floor.fairness import fairness
    from coinwall.forward.dynamics.floor.uncertainty import uncertainty_exponent
    from coinwall.forward.errors import InvalidArgument

    coin = FieldTable(Wall.from_expression(COIN, {"eps": 99.0}), g=1.0, e=0.6)
    corners = FieldTable(Wall.from_expression("abs(cos(t))"), g=1.0, e=0.6)
    for call, match in [
        (lambda: fairness(corners, (2, 5), (0.1, 0.1), 1.2), "smooth wall"),
        (lambda: fairness(coin, (2, 5), (-0.1, 0.1), 1.2), "standard deviations"),
        (lambda: uncertainty_exponent(coin, (1, 1), (0, 8), 1.2), "`v0`"),
        (lambda: uncertainty_exponent(coin, (0, 3), (0, 8), 1.2, epsilons=(0.5, 0.1)), "`epsilons`"),
        (lambda: uncertainty_exponent(coin, (0, 3), (0, 8), 1.2, epsilons=(1e-3,)), "`epsilons`"),
    ]:
        with pytest.raises(InvalidArgument, match=match):
            call()
    pytest.importorskip("distributed")
    from coinwall.cases.scan import TableSpec, scan

    with pytest.raises(InvalidArgument, match="toss quantity"):
        scan("chaotic-fraction", TableSpec(COIN, (("eps", 99.0),)), {"restitution": "0.5,0.7", "H": "3"},
             output=str(tmp_path / "x.zarr"), scheduler="synchronous")
    assert not (tmp_path / "x.zarr").exists()


def test_toss_scan_checks_its_grid_before_any_store_and_records_e(tmp_path, capsys):
    """A restitution outside (0, 1] or a launch height the body does not clear is one line, exit 2, no store
    (they used to be refused cell by cell, exit 1, with a half-NaN store left); a scan that gives no restitution
    uses coinwall toss's default e = 0.6 and says so in the store; a named case takes a restitution too."""
    pytest.importorskip("distributed")
    xr = pytest.importorskip("xarray")
    pytest.importorskip("zarr")
    import json as _json

    from coinwall.cases.cli.main import main
    from coinwall.cases.scan.table import DEFAULT_RESTITUTION
    from coinwall.forward.dynamics.floor.hand import heads_fraction

    base = ["scan", "toss", COIN, "--param", "eps=99", "--tosses", "50", "--scheduler", "synchronous"]
    for extra, needle in [(["--param", "restitution=0.5,1.5", "--H", "1.2"], "restitution must be in (0, 1]"),
                          (["--param", "restitution=0.5", "--H", "0.01,1.2"], "--H 0.01")]:
        store = tmp_path / "bad.zarr"
        assert main([*base, *extra, "-o", str(store)]) == 2
        err = capsys.readouterr().err
        assert needle in err and len(err.strip().splitlines()) == 1
        assert not store.exists()
    store = tmp_path / "default.zarr"
    assert main([*base, "--H", "1.2", "-o", str(store), "--seed", "4"]) == 0
    capsys.readouterr()
    data = xr.open_zarr(str(store))
    assert _json.loads(data.attrs["scan_identity"])["restitution"] == DEFAULT_RESTITUTION == 0.6
    from coinwall.cases.scan.grid import cell_seed

    ref = heads_fraction(FieldTable(Wall.from_expression(COIN, {"eps": 99.0}), g=1.0, e=0.6), (2.0, 5.0),
                         (0.04, 0.1), 1.2, samples=50, seed=cell_seed(4, (1.2,)))
    assert float(data["heads"].values[0]) == pytest.approx(ref.fractions["heads"][0], abs=1e-12)
    assert main(["scan", "toss", "case:coin", "--param", "restitution=0.4,0.8", "--H", "1.2", "--tosses", "20",
                 "--scheduler", "synchronous", "-o", str(tmp_path / "case.zarr")]) == 0


def test_basin_map_csv_holds_plain_numbers():
    from coinwall.forward.dynamics.floor.toss import basin_map

    table = FieldTable(Wall.from_expression(COIN, {"eps": 99.0}), g=1.0, e=1.0)
    text = basin_map(table, np.linspace(0.5, 1.0, 2), np.linspace(1.0, 2.0, 2), 1.2, catch=True).to_csv()
    rows = [line.split(",") for line in text.splitlines()[1:]]
    assert len(rows) == 4 and all(float(r[0]) in (0.5, 1.0) and float(r[1]) in (1.0, 2.0) for r in rows)


def test_a_caught_basin_map_has_no_bounce_panel():
    """Caught at the floor every launch is decided at its first contact: the bounce panel would be one colour,
    so the figure has the outcome only; a bouncing toss keeps both panels (and the bounces' colour bar)."""
    import matplotlib.pyplot as plt

    from coinwall.forward.dynamics.floor.toss import basin_map

    table = FieldTable(Wall.from_expression(COIN, {"eps": 99.0}), g=1.0, e=0.6)
    grid = (np.linspace(0.5, 1.0, 3), np.linspace(1.0, 2.0, 3), 1.2)
    caught = basin_map(table, *grid, catch=True).plot()
    assert len(caught.figure.axes) == 1 and "caught" in caught.get_title()
    bounced = basin_map(table, *grid).plot()
    assert len(bounced.figure.axes) == 3  # outcome, bounces, the bounces' colour bar
    plt.close("all")


def test_a_disc_has_no_outcome():
    """b constant: every angle is a rest state; the toss used to report 'rest θ=0' after one impact."""
    from coinwall.forward.dynamics.floor.toss import launch_states
    from coinwall.forward.errors import InvalidArgument

    with pytest.raises(InvalidArgument, match="no valleys"):
        launch_states(FieldTable(Wall.from_expression("1 + 0*t"), g=1.0, e=0.6), 1.0, 1.0, 2.0)


def test_toss_refuses_flags_its_mode_does_not_read(capsys):
    from coinwall.cases.cli.main import main

    for argv, needle in [(["--samples", "100"], "--samples and --seed"), (["--seed", "3"], "--samples and --seed"),
                         (["--catch", "--slide"], "--slide"), ]:
        assert main(["toss", "case:coin", *argv]) == 2
        err = capsys.readouterr().err
        assert needle in err and len(err.strip().splitlines()) == 1
    assert main(["toss", "case:reuleaux-3"]) == 2
    assert "built from exact arcs" in capsys.readouterr().err
