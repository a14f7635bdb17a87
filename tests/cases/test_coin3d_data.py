"""Caught tosses: DHM's closed form reproduced by simulating the precessing coin, and the fit to the flips
of Bartoš et al. (2023).  Reference values: DHM, SIAM Rev. 49 (2007) 211, P = ½ + arcsin(cot²ψ)/π; the
totals 178,078 of 350,757 from the paper (cases/data/README.md)."""

import math

import numpy as np
import pytest

from coinwall.cases.bartos import bartos_counts, bartos_fits
from coinwall.forward.dynamics.coin3d.caught import (
    dhm_same_side,
    fit_psi,
    psi_from_same_side,
    simulate_caught,
    spread_same_side,
)
from coinwall.forward.errors import InvalidArgument


@pytest.mark.parametrize("degrees", [50, 55, 62, 70, 78, 85])
def test_simulated_caught_coin_reproduces_dhm(degrees):
    """Six angles ψ > 45°, 40,000 tosses each: within 3.5 binomial standard errors (a false alarm rate of
    ~5e-4 per angle); the simulation knows nothing of the formula (it integrates the top's flight)."""
    psi = math.radians(degrees)
    p, se = simulate_caught(psi, 40_000, seed=degrees)
    assert abs(p - float(dhm_same_side(psi))) < 3.5 * se
    assert se > 0


def test_below_45_degrees_the_coin_never_turns_over():
    p, se = simulate_caught(math.radians(40), 5_000, seed=1)
    assert p == 1.0 and float(dhm_same_side(math.radians(40))) == 1.0


def test_psi_inverts_the_model():
    psi = np.radians(np.linspace(46, 90, 23))
    np.testing.assert_allclose(psi_from_same_side(dhm_same_side(psi)), psi, atol=1e-12)
    assert psi_from_same_side(0.49) == pytest.approx(math.pi / 2)


def test_spread_model_limits():
    assert spread_same_side(0.0) == pytest.approx(0.5)
    # a small spread: E[½ + arcsin(cot²ψ)/π] ≈ ½ + E[δ²]/π = ½ + σ²/π (cot ψ ≈ δ near 90°)
    assert spread_same_side(0.01) == pytest.approx(0.5 + 0.01 ** 2 / math.pi, rel=1e-3)


def test_bartos_totals_and_fit():
    data = bartos_counts()
    assert len(data["tosser"]) == 48
    assert int(data["same"].sum()) == 178_078 and int(data["flips"].sum()) == 350_757
    np.testing.assert_array_equal(data["same"], data["heads_same"] + data["tails_same"])
    fits = bartos_fits()
    o = fits.overall
    assert o.p == pytest.approx(178_078 / 350_757)
    # the paper's 95 % interval [0.506, 0.509] (its rounding)
    assert o.p_low == pytest.approx(0.506, abs=6e-4) and o.p_high == pytest.approx(0.509, abs=6e-4)
    assert float(dhm_same_side(math.radians(o.psi))) == pytest.approx(o.p, abs=1e-12)
    assert o.psi_low < o.psi < o.psi_high < 90
    assert spread_same_side(math.radians(o.sigma)) == pytest.approx(o.p, abs=1e-9)
    # the tossers differ far beyond binomial noise
    assert fits.dof == 47 and fits.p_value < 1e-10


def test_fit_refuses_bad_counts():
    with pytest.raises(InvalidArgument, match="same"):
        fit_psi(11, 10)
    with pytest.raises(InvalidArgument, match="flips"):
        fit_psi(1, 0)
    with pytest.raises(InvalidArgument, match="psi"):
        simulate_caught(4.0, 10)


def _cli(capsys):
    from coinwall.cases.cli.main import main

    def run(*argv):
        code = main(["coin3d", *argv])
        out, err = capsys.readouterr()
        return code, out, err

    return run


def test_cli_coin3d_refuses_bad_input_in_one_line(tmp_path, capsys):
    run = _cli(capsys)
    for argv, word in ((("caught", "--psi", "270"), "--psi"), (("fit", "--tosser", "T99"), "--tosser"),
                       (("bounce", "--e", "2"), "--e"), (("caught",), "--psi"), (("caught", "--psi", "nan"), "--psi"),
                       (("bounce", "-o", str(tmp_path / "x.png")), "-o"), (("bounce", "--g", "0"), "--g"),
                       (("fit", "-o", str(tmp_path / "x.txt")), ""),
                       (("fit", "--tosser", "T48", "-o", str(tmp_path / "x.png")), "--tosser"),
                       (("caught", "--psi", "70", "--ceiling", "0.001"), "--ceiling does nothing"),
                       (("fit", "--psi", "70"), "--psi does nothing"), (("fit", "--e", "0.3"), "--e does nothing")):
        code, out, err = run(*argv)
        assert code == 2 and out == ""
        assert len(err.strip().splitlines()) == 1 and word in err
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "x.txt").exists()


def test_cli_one_tossers_fit_reads_like_the_table(capsys):
    """`coin3d fit --tosser` prints the counts, the share and its interval as the table does; a share below ½
    (T07: 7458 of 15012) lies below the interval, which the model bounds to [½, 1], and the line says so."""
    run = _cli(capsys)
    counts = bartos_counts()
    for name in ("T07", "T40"):
        row = counts["tosser"].index(name)
        same, flips = int(counts["same"][row]), int(counts["flips"][row])
        code, out, err = run("fit", "--tosser", name)
        assert code == 0 and err == ""
        first = out.splitlines()[0]
        assert first.startswith(f"{name}  {same:,} same side of {flips:,}: {same / flips:.5f} [")
        assert ("lies below its interval" in first) == (same / flips < 0.5)
        assert "PsiFit(" not in out and "ψ = " in out


@pytest.mark.slow
def test_cli_coin3d_runs(tmp_path, capsys):
    import json

    run = _cli(capsys)
    code, out, err = run("caught", "--psi", "70", "--samples", "4000", "--seed", "1", "--json")
    assert code == 0, err
    out = json.loads(out)
    assert abs(out["same_side"] - out["dhm"]) < 4 * out["stderr"]
    fig = tmp_path / "b.png"
    code, out, err = run("fit", "-o", str(fig))
    assert code == 0 and fig.stat().st_size > 10_000 and "81.16°" in out
    code, out, err = run("bounce", "--psi", "81", "--e", "0.9", "--bounces", "3", "--samples", "500", "--json")
    assert code == 0 and len(json.loads(out)["same"]) == 3


def test_cli_bounce_says_not_resolved_when_the_errors_are_wider_than_the_tolerance(capsys):
    """Without precession (ψ = 90°) the share stays near ½; 300 tosses give two standard errors of ~0.06, so
    "within 0.001" can be neither shown nor refuted: the verdict says so (it said "never within")."""
    run = _cli(capsys)
    code, out, err = run("bounce", "--psi", "90", "--e", "0.9", "--bounces", "2", "--samples", "300", "--seed", "2")
    assert code == 0, err
    assert "not resolved" in out and "never" not in out


def test_interval_with_the_spread_between_tossers():
    """The 48 tossers differ (Pearson χ² 265 on 47 dof): the ψ interval of all flips allows for it. Its width
    against the binomial one is the square root of the dispersion, nearly (2.5 in ψ, through the curved model);
    a bootstrap over the tossers, which assumes nothing about the shape of the spread, gives nearly the same
    interval (an independent computation: resampled tossers, pooled proportion, DHM inverted)."""
    data = bartos_counts()
    k, n = data["same"], data["flips"]
    fits = bartos_fits()
    p = k.sum() / n.sum()
    pearson = sum((ki - ni * p) ** 2 / (ni * p * (1 - p)) for ki, ni in zip(k.tolist(), n.tolist()))
    assert fits.pearson_statistic == pytest.approx(pearson) and fits.dispersion == pytest.approx(pearson / 47)
    assert 265 < pearson < 266 and 266 < fits.lr_statistic < 267
    o, w = fits.overall, fits.overall_overdispersed
    assert w.p == o.p and w.psi == o.psi and w.dispersion == fits.dispersion and o.dispersion == 1.0
    assert w.p_low < o.p_low and w.p_high > o.p_high
    ratio_p = (w.p_high - w.p_low) / (o.p_high - o.p_low)
    assert ratio_p == pytest.approx(math.sqrt(fits.dispersion * 4.0471 / 3.8415), rel=2e-3)  # φ F(1,47) / χ²(1)
    assert (w.psi_high - w.psi_low) / (o.psi_high - o.psi_low) == pytest.approx(2.5, abs=0.1)
    assert w.psi_low == pytest.approx(79.13, abs=0.01) and w.psi_high == pytest.approx(83.88, abs=0.01)
    rng = np.random.default_rng(7)
    picks = rng.integers(0, k.size, (20_000, k.size))
    pooled = k[picks].sum(axis=1) / n[picks].sum(axis=1)
    low, high = np.degrees(psi_from_same_side(np.percentile(pooled, [97.5, 2.5])))
    assert low == pytest.approx(w.psi_low, abs=0.3) and high == pytest.approx(w.psi_high, abs=0.6)
    assert high - low > 2 * (o.psi_high - o.psi_low)


def test_quasi_binomial_interval_covers_heterogeneous_tossers():
    """Coverage, simulated: 48 tossers with the real flip counts, each with his own proportion drawn about 0.508
    with the spread that gives the data's dispersion; over 300 such experiments the 95 % interval with the spread
    covers 0.508, the proportion of a toss by a tosser drawn at random from such people, in more than 90 % of them
    (measured 91 %: φ is estimated from 48 tossers), the binomial one in fewer than 65 % (measured 51 %: it is the
    interval of these 48 people's own average, not of people like them)."""
    from coinwall.forward.dynamics.coin3d.caught import likelihood_interval, overdispersion

    n = bartos_counts()["flips"]
    rng = np.random.default_rng(11)
    # Var(k_i) = n p(1-p) + n² τ²: τ chosen so that the mean φ is near the data's 5.6 with these n (5.5)
    tau = 0.0125
    covered = {"binomial": 0, "spread": 0}
    phis = []
    trials = 300
    for _ in range(trials):
        p_i = np.clip(0.508 + tau * rng.standard_normal(n.size), 0.0, 1.0)
        k = rng.binomial(n, p_i)
        truth = 0.508
        lo, hi = likelihood_interval(int(k.sum()), int(n.sum()))
        covered["binomial"] += lo <= truth <= hi
        phi, _, dof = overdispersion(k, n)
        phis.append(phi)
        wide = fit_psi(int(k.sum()), int(n.sum()), dispersion=phi, dof=dof)
        # the fit clips at ½ (the model's edge); compare on the proportion's interval
        lo, hi = likelihood_interval(int(k.sum()), int(n.sum()), phi * 4.0471)
        covered["spread"] += lo <= truth <= hi
        assert wide.p_low == pytest.approx(max(lo, 0.5)) and wide.p_high == pytest.approx(max(hi, 0.5))
    assert 4.0 < np.mean(phis) < 7.5
    assert covered["spread"] / trials > 0.90 and covered["binomial"] / trials < 0.65, covered


def test_overdispersion_refuses_what_it_cannot_scale():
    from coinwall.forward.dynamics.coin3d.caught import overdispersion

    assert overdispersion([50, 50], [100, 100])[0] == 1.0  # no spread: no widening
    for same, flips in (([1], [2]), ([1.5, 2], [3, 3]), ([0, 0], [3, 3]), ([4, 1], [3, 3])):
        with pytest.raises(InvalidArgument):
            overdispersion(same, flips)
    with pytest.raises(InvalidArgument, match="dof"):
        fit_psi(60, 100, dispersion=2.0)
    with pytest.raises(InvalidArgument, match="dispersion"):
        fit_psi(60, 100, dispersion=0.5, dof=3)


def test_docstring_examples_of_the_caught_coin_run():
    import doctest

    import coinwall.cases.bartos as bartos
    import coinwall.forward.dynamics.coin3d.caught as caught

    for module in (caught, bartos):
        result = doctest.testmod(module)
        assert result.attempted > 0 and result.failed == 0, module.__name__


def test_cli_fit_prints_both_intervals(capsys):
    import json

    run = _cli(capsys)
    code, out, err = run("fit")
    assert code == 0, err
    assert "81.16° [80.28, 82.16] binomial; [79.13, 83.88] with the spread between tossers" in out
    assert "φ = Pearson χ² 265.3 / 47 = 5.64" in out
    code, out, err = run("fit", "--json")
    doc = json.loads(out)
    assert doc["overall"]["psi_low"] == pytest.approx(80.275, abs=1e-3)
    assert doc["overall_overdispersed"]["psi_low"] == pytest.approx(79.134, abs=1e-3)
    assert doc["homogeneity"]["dispersion"] == pytest.approx(5.644, abs=1e-3)
