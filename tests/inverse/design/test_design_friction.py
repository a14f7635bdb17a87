"""The bounce toss of ``design`` on a floor with Coulomb friction: a design checked by the floor's own toss
(:func:`coinwall.forward.dynamics.floor.toss_outcomes`, fresh launches), friction that changes the toss, bad μ
refused, and μ = 0 the frictionless design exactly."""

from __future__ import annotations

import math

import numpy as np
import pytest

from coinwall.forward.dynamics.floor import FieldTable, launch_spread, toss_outcomes
from coinwall.forward.errors import InvalidArgument
from coinwall.inverse.design import Bounce, Family, Launch, design, odds
from coinwall.inverse.design.solvers import z_value

RECT = "abs(cos(t)) + h*abs(sin(t))"  # the planar three-sided coin: a 2 × 2h rectangle, edges at θ = 0, π
Z = z_value(0.95)


def _fresh_tosses(wall, *, e, mu, launch, n, seed):
    """``n`` tosses of ``wall`` by the floor's toss (``toss_outcomes``, one launch per call) with launches drawn
    here, independently of the design's: θ0 uniform, the lowest point ``launch.height`` above the floor (the
    centre at b(θ0) + height), v0 and ω0 from ``launch_spread``; the rest states by their names."""
    table = FieldTable(wall, g=launch.g, e=e, mu=mu)
    v0, omega0 = launch_spread((launch.v0[0], launch.omega[0]), (launch.v0[1], launch.omega[1]), n, seed=seed)
    theta0 = 2 * math.pi * np.random.default_rng(seed + 1).random(n)
    names = []
    for v, w, th in zip(v0, omega0, theta0):
        height = float(wall(np.array([th]))[0]) + launch.height
        names.append(toss_outcomes(table, v, w, height, float(th), workers=1).name[0])
    return np.array(names)


def test_friction_design_checked_by_the_floor_toss():
    """The three-sided coin designed with μ = 0.3, e = 0.5 (coarse: 1024 launches per evaluation, ±0.03); the
    designed rectangle tossed 1500 more times by ``toss_outcomes`` with other launches: P(edge) is the target,
    and every outcome the design's, within the design's interval and the check's standard error combined."""
    fam = Family("planar", RECT, {"h": (0.5, 1.2)})
    model = Bounce(e=0.5, mu=0.3)
    found = design(fam, {"edge": 1 / 3}, model, tolerance=0.03, seed=3, max_tosses=1024)
    assert not found.warnings and found.probabilities["edge"][1] <= 0.03
    assert found.undecided[0] == 0.0  # with friction every toss of this hand settles
    n = 1500
    names = _fresh_tosses(found.body(), e=0.5, mu=0.3, launch=model.launch, n=n, seed=11)
    assert set(names) <= {"heads", "tails", "edge"}
    for name, (p, half) in found.probabilities.items():
        q = float(np.mean(names == name))
        allowed = math.hypot(half, Z * math.sqrt(q * (1 - q) / n))
        assert abs(q - p) <= allowed, (name, q, p, allowed)
        if name == "edge":
            assert abs(q - 1 / 3) <= allowed, (q, allowed)


def test_friction_settles_what_slides_without_it():
    """The same hands (common random numbers) on the same rectangle: without friction some tosses slide for
    ever (undecided), with μ = 0.3 none; the horizontal launch velocity changes the odds only with friction."""
    fam = Family("planar", RECT, {}, {"h": 0.75})
    free = odds(fam, Bounce(e=0.5), names=["edge"], tosses=2000, seed=4)
    rough = odds(fam, Bounce(e=0.5, mu=0.3), names=["edge"], tosses=2000, seed=4)
    assert free["undecided"][0] > 0.03 and rough["undecided"][0] == 0.0
    pushed = odds(fam, Bounce(e=0.5, mu=0.3, launch=Launch(vx=(0.0, 3.0))), names=["edge"], tosses=2000, seed=4)
    assert pushed["edge"][0] != rough["edge"][0]


def test_rolling_resistance_reaches_the_toss():
    """A near-round body (the coin wall at ε = 0.5) with μ = 0.3: without rolling resistance most tosses roll for
    ever (undecided), with a resistance of 0.01 κ every one comes to rest."""
    fam = Family("planar", "sqrt((1+eps*cos(t)**2)/(1+eps))", {}, {"eps": 0.5})
    free = odds(fam, Bounce(e=0.5, mu=0.3), tosses=100, seed=4)
    held = odds(fam, Bounce(e=0.5, mu=0.3, rolling=0.01), tosses=100, seed=4)
    assert free["undecided"][0] > 0.5 and held["undecided"][0] == 0.0


@pytest.mark.parametrize("kwargs, message", [
    ({"mu": -0.1}, r"^`mu` must be a coefficient of friction between 0 and 1e6, got -0.1$"),
    ({"mu": float("nan")}, r"^`mu` must be a finite number"),
    ({"mu": "rough"}, r"^`mu` must be a real number"),
    ({"mu": 0.0, "rolling": 0.01}, r"^`rolling` must be a rolling resistance in \[0, 1\] .* got 0.01$"),
    ({"mu": 0.3, "rolling": 2.0}, r"^`rolling` must be a rolling resistance"),
    ({"mu": 0.0, "launch": Launch(vx=(1.0, 0.0))}, r"^a horizontal launch velocity `vx` does nothing on a "
                                                    r"frictionless floor"),
])
def test_bad_friction_is_refused_in_one_line(kwargs, message):
    with pytest.raises(InvalidArgument, match=message):
        Bounce(e=0.5, **kwargs)


def test_mu_zero_is_the_frictionless_design_exactly():
    """μ = 0 given explicitly (and a hand with vx = 0) is the design from before friction existed: h recorded
    from the code at the commit before friction was passed through (same seed, same coarse design)."""
    fam = Family("planar", RECT, {"h": (0.2, 2.0)})
    before = 0.7756992402012551  # design(..., Bounce(e=0.5), tolerance=0.03, seed=3) before friction, this machine
    found = design(fam, {"edge": 1 / 3}, Bounce(e=0.5, mu=0.0, launch=Launch(vx=(0.0, 0.0))), tolerance=0.03, seed=3)
    assert found.x[0] == before


@pytest.mark.slow
def test_friction_design_coverage_over_seeds():
    """20 coarse designs (seeds 0–19, ±0.03, 1024 launches per evaluation) of the three-sided coin with μ = 0.3,
    each re-simulated with 20000 independent launches: P̃(edge) within the reported interval combined with the
    re-simulation's own in >= 16 of 20 (95% nominal: P(fewer than 16) ≈ 0.003 for a binomial of 20 at 0.95)."""
    from coinwall.inverse.design import resimulate

    fam = Family("planar", RECT, {"h": (0.5, 1.2)})
    covered = 0
    for seed in range(20):
        found = design(fam, {"edge": 1 / 3}, Bounce(e=0.5, mu=0.3), tolerance=0.03, seed=seed, max_tosses=1024)
        covered += abs(resimulate(found, 20_000, seed=1000 + seed).z["edge"]) <= Z
    assert covered >= 16, covered
