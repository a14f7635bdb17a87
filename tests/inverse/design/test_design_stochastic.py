"""The Monte Carlo solvers: coverage of their intervals over seeds, designs re-simulated independently, a fair
three-parameter die of the bounce toss, and friction refused in one line.

Coverage needs a truth: a toy toss whose probability is known in closed form (P(x) = x², a uniform draw below
x²), run through the same Ensemble and solver as the physical tosses, over many seeds; the physical toss is
then checked the way a user would, by tossing the designed body again with independent launches.
"""

import math

import numpy as np
import pytest

from coinwall.inverse.design import Bounce, Family, Launch, design, resimulate
from coinwall.inverse.design.solvers import Ensemble, stochastic_least_squares, stochastic_root, z_value

RECT = "abs(cos(t)) + h*abs(sin(t))"
Z = z_value(0.95)


class ToyFamily:
    """x -> the body x (one or two free parameters)."""

    kind, b0 = "planar", 0.0

    def __init__(self, k=1):
        self.names = tuple("xyz"[:k])

    def body(self, x):
        return np.asarray(x, dtype=float)


class ToyModel:
    """'hit' when a uniform draw is below x[0]² (P = x²); with two parameters, 'other' when another draw is
    below (x[0] + x[1])/2."""

    name, exact, dimensions = "toy", False, 2

    def draw(self, rng, n):
        return rng.random((n, 2))

    def simulate(self, kind, body, draws, names, b0=0.0):
        hits = {"hit": draws[:, 0] < body[0] ** 2}
        if len(body) > 1:
            hits["other"] = draws[:, 1] < 0.5 * (body[0] + body[1])
        return {k: hits[k] for k in names}, np.zeros(draws.shape[0], dtype=bool)


def test_stochastic_root_covers_the_truth_over_seeds():
    """200 seeds: the parameter's interval holds the true root √t, and the probability interval at the design
    point holds the true P(x̂) = x̂², in at least 180 (95% nominal: 190 expected, P(fewer than 180) ≈ 6e-4)."""
    t, tol = 0.3, 0.02
    root_in = p_in = 0
    for seed in range(200):
        ens = Ensemble(ToyModel(), ToyFamily(), ["hit"], seed=seed)
        found = stochastic_root(ens, "hit", t, 0.1, 0.9, tol=tol, z=Z, max_tosses=10 ** 6)
        assert found.reached
        x, half = found.x[0], found.half_widths[0]
        root_in += abs(x - math.sqrt(t)) <= half
        p, h = found.estimate.p("hit"), Z * found.estimate.se("hit")
        p_in += abs(x * x - p) <= h
        assert h <= tol
    assert root_in >= 180 and p_in >= 180, (root_in, p_in)


def test_stochastic_least_squares_covers_the_truth():
    """Two parameters, two targets (x0² = 0.4, (x0 + x1)/2 = 0.6): the truth in each interval in >= 36 of 40."""
    inside = np.zeros(2)
    truth = np.array([math.sqrt(0.4), 1.2 - math.sqrt(0.4)])
    for seed in range(40):
        ens = Ensemble(ToyModel(), ToyFamily(2), ["hit", "other"], seed=seed)
        found = stochastic_least_squares(ens, {"hit": 0.4, "other": 0.6}, [[0.1, 0.95], [0.1, 0.95]], tol=0.02, z=Z,
                                         max_tosses=10 ** 6)
        inside += np.abs(found.x - truth) <= found.half_widths
    assert np.all(inside >= 36), inside


def test_bounce_design_resimulated_independently():
    """The three-sided coin of the bounce toss to ±0.02: tossed again with 60000 independent launches, every
    outcome agrees with the design within their combined intervals, and the target with the re-simulation."""
    fam = Family("planar", RECT, {"h": (0.2, 2.0)})
    d = design(fam, {"edge": 1 / 3}, Bounce(e=0.5), tolerance=0.02, seed=1)
    assert d.probabilities["edge"][1] <= 0.02 and d.undecided is not None
    check = resimulate(d, 60_000, seed=2)
    assert check.agrees(0.99), check
    p, se = check.probabilities["edge"]
    assert abs(p - 1 / 3) <= math.hypot(d.probabilities["edge"][1], Z * se) * 1.3


@pytest.mark.slow
def test_bounce_design_coverage_over_seeds():
    """30 designs (seeds 0–29) of the bounce three-sided coin to ±0.01, each re-simulated with 200000 independent
    launches: P̃(edge) within the reported interval combined with the re-simulation's own in >= 26 of 30
    (95% nominal: P(fewer than 26) ≈ 0.06 for a binomial of 30 at 0.95)."""
    fam = Family("planar", RECT, {"h": (0.2, 2.0)})
    covered = 0
    for seed in range(30):
        d = design(fam, {"edge": 1 / 3}, Bounce(e=0.5), tolerance=0.01, seed=seed)
        check = resimulate(d, 200_000, seed=1000 + seed)
        covered += abs(check.z["edge"]) <= Z
    assert covered >= 26, covered


@pytest.mark.slow
def test_fair_bounce_die_three_parameters():
    """A quadrilateral with fixed vertex radii and free directions, fair for the bounce toss (faces at 30°, 120°,
    210° each 1/4, the fourth follows) by weighted least squares to ±0.01; re-simulated with 100000 independent
    launches, each face agrees within the combined intervals."""
    text = "max(max(1.0*cos(t), 1.3*cos(t-a)), max(0.8*cos(t-a-b), 1.1*cos(t-a-b-c)))"
    fam = Family("planar", text, {"a": (1.0, 2.2), "b": (1.0, 2.2), "c": (1.0, 2.2)})
    targets = {"face@30": 0.25, "face@120": 0.25, "face@210": 0.25}
    d = design(fam, targets, Bounce(e=0.5), tolerance=0.01, seed=0)
    assert all(d.probabilities[k][1] <= 0.01 for k in targets)
    check = resimulate(d, 100_000, seed=5)
    assert all(abs(check.z[k]) <= Z for k in targets), check


def test_bounce_launch_is_common_to_the_family():
    """The same draws give the same hands for every member: launch angles and speeds do not depend on the body."""
    launch = Launch(v0=(1.0, 0.5), omega=(0.0, 4.0))
    draws = launch.draw(np.random.default_rng(0), 5)
    a = launch.states(lambda th: 1.0 + 0 * th, draws)
    b = launch.states(lambda th: 2.0 + 0 * th, draws)
    assert np.array_equal(a[:, [0, 2, 3]], b[:, [0, 2, 3]]) and np.allclose(b[:, 1] - a[:, 1], 1.0)
