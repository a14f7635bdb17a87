"""Answers from data only, one work bound, options checked in one place (forward/estimates.py,
cases/cli/budget.py, cases/cli/options.py).

* A statistic states its sample size; from fewer than 30 samples it is "not enough data" (or the command's
  one-line refusal), never a number, and no NaN is printed as an answer.
* Every long command estimates its work and refuses past one hour without --allow-long.
* Options that mean nothing or conflict are refused in one line before any work.
"""

from __future__ import annotations

import doctest
import json
import math
import os
import time

import pytest

from coinwall.cases.cli import budget, options
from coinwall.cases.cli.main import main
from coinwall.forward import estimates


def _one_line(capsys, *needles):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:"), err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


def test_doctests():
    for module in (estimates, budget, options):
        assert doctest.testmod(module, optionflags=doctest.ELLIPSIS).failed == 0, module.__name__


def test_a_share_against_the_binomial_formula():
    """The value and error of 1013 of 2000 (p(1 − p)/n, computed here), the 95 % bound 3/n of 0 of n (the rule of
    three: (1 − p)^n = 0.05 gives p = −ln 0.05/n ≈ 3.0/n), and no number below 30 samples."""
    one = estimates.share(1013, 2000)
    assert one.p == 1013 / 2000 and one.stderr == pytest.approx(math.sqrt(0.5065 * 0.4935 / 2000), rel=1e-12)
    assert -math.log(0.05) / 500 == pytest.approx(3 / 500, rel=0.002)
    assert "below 0.0060 at 95 %" in estimates.share(0, 500).text()
    assert "above 0.9940" in estimates.share(500, 500).text()
    for hits, n in ((0, 0), (3, 29)):
        assert estimates.share(hits, n).text().startswith("not enough data")
        assert estimates.share(hits, n).to_dict()["value"] is None
    with pytest.raises(ValueError):
        estimates.share(3, 2)
    assert "nan" not in estimates.finite_text(math.nan) and estimates.finite_text(math.inf) == "∞"


def test_coin3d_bounce_from_no_data(capsys):
    """ψ = 0: every toss lands flat at its first bounce and none reaches the second; bounces 2 … are "not enough
    data", the verdict rests on bounce 1 only, and --json has null where there is no share."""
    args = ["coin3d", "bounce", "--psi", "0", "--samples", "300", "--seed", "1", "--bounces", "3"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "       1  1.0000 (300 of 300 tosses" in out
    assert out.count("not enough data (0 tosses; at least 30 needed)") == 2
    assert "0.0000 ± 0.0000" not in out and "bounces after 1 were reached by fewer than 30 tosses" in out
    assert main(args + ["--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["same"][1:] == [None, None] and doc["enough"] == [True, False, False] and doc["reached"][1:] == [0, 0]


@pytest.mark.parametrize("flags,needle", [(["--height", "1e300"], "meets the floor at 4.43e+150 m/s"),
                                          (["--g", "1e-6"], "beyond 1e+06 rad its phase keeps too few digits"),
                                          (["--samples", "10"], "not enough data for P(same side) at any bounce"),
                                          (["--samples", "10000000", "--bounces", "1000"], "--allow-long")])
def test_coin3d_bounce_refusals_are_one_line_and_quick(capsys, flags, needle):
    start = time.perf_counter()
    assert main(["coin3d", "bounce", "--seed", "1", "--bounces", "2"] + flags) == 2
    _one_line(capsys, needle)
    assert time.perf_counter() - start < 30  # (--g 1e-6 used to run for 5 minutes)


def test_coin3d_caught_needs_samples(capsys):
    assert main(["coin3d", "caught", "--psi", "70", "--samples", "5", "--seed", "1"]) == 2
    _one_line(capsys, "not enough data for P(same side): 5 samples")
    assert main(["coin3d", "caught", "--psi", "10", "--samples", "200", "--seed", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["z"] is None  # p = 1 exactly: no number of standard errors


def test_toss_statistics_need_decided_tosses(capsys):
    assert main(["toss", "case:coin", "--e", "1", "--impacts", "10", "--spread", "2,5,0.05,0.2", "--samples", "100",
                 "--seed", "1"]) == 2
    _one_line(capsys, "not enough data for the outcome fractions: 0 decided tosses", "raise --samples or --impacts")
    assert main(["toss", "case:coin", "--v0", "0:3", "--omega", "0:8", "--uncertainty", "1e-6:1e-2:3", "--samples",
                 "5", "--seed", "1"]) == 2
    _one_line(capsys, "not enough data for the uncertainty exponent")


def test_simulate_and_correlation_print_counts_and_no_nan(capsys):
    assert main(["simulate", "case:coin", "--H", "3", "--collisions", "1", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert "not enough data (1 free flights; at least 30 needed)" in out
    assert main(["simulate", "case:coin", "--H", "3", "--collisions", "1000", "--seed", "1"]) == 0
    assert "(over 1000 free flights)" in capsys.readouterr().out
    # H below the coin's diameter: P(n) = 1, τ = ∞, no fit crossing -- said in words, never "nan"
    assert main(["correlation", "case:coin", "--H", "1.5", "--bounces", "500", "--orbits", "2", "--max-lag", "3",
                 "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert "nan" not in out.lower() and "fit: not determined" in out and "τ" not in out.split("tau")[0]
    assert "from the spread between the 2 orbits (fewer than 10: rough)" in out


@pytest.mark.parametrize("argv,needle", [
    (["toss", "case:coin", "--e", "1", "--impacts", "1000000000"], "167 days"),
    (["simulate", "case:coin", "--H", "3", "--collisions", "1e13"], "116 days"),
    (["correlation", "case:coin", "--H", "3", "--bounces", "1e10", "--max-lag", "1"], "5.56 hours"),
    (["scan", "chaotic-fraction", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=0.5:30:100log", "--H", "2:8:100",
      "--orbits", "1000", "--collisions", "100000", "--workers", "2", "-o", "big.zarr"], "13.9 days"),
])
def test_long_runs_are_refused_with_their_estimate(tmp_path, monkeypatch, capsys, argv, needle):
    monkeypatch.chdir(tmp_path)
    start = time.perf_counter()
    assert main(argv) == 2
    _one_line(capsys, needle, "more than the one hour allowed without --allow-long")
    assert time.perf_counter() - start < 20 and os.listdir(tmp_path) == []


@pytest.mark.parametrize("argv", [["section", "case:coin", "--H", "3", "--orbits", "2", "--collisions", "1000000",
                                   "-o", "s.csv"],
                                  ["coin3d", "bounce", "--samples", "100", "--bounces", "2"],
                                  ["correlation", "case:coin", "--H", "3", "--bounces", "100000"]])
def test_every_long_command_keeps_the_one_bound(tmp_path, monkeypatch, capsys, argv):
    """The bound is one number (budget.MAX_SECONDS): lowered to a millisecond, each command refuses before any work
    (on this machine memory bounds `section` first; on one with more memory its time does)."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(budget, "MAX_SECONDS", 1e-3)
    assert main(argv) == 2
    _one_line(capsys, "allowed without --allow-long")
    assert os.listdir(tmp_path) == []


def test_the_toss_estimate_runs_what_fits(capsys, monkeypatch):
    """Elastic tosses (nothing settles) within the bound run; --allow-long lifts the bound (the estimate is
    checked, the run itself is not started here: the check is called with the flag)."""
    assert main(["toss", "case:coin", "--e", "1", "--impacts", "20000", "--v0", "0:1:2", "--omega", "0:1:2",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["status"]
    import argparse

    assert budget.check_time(argparse.Namespace(allow_long=True), 1e9, "a long run") == 1e9


@pytest.mark.parametrize("argv,needle", [
    (["export", "body.json", "-o", "c.svg", "--cut", "--dimension"], "--cut and --dimension"),
    (["quantum", "1", "--H", "3", "--levels", "4", "--method", "spectral", "--order", "2"],
     "--method spectral and --order"),
    (["toss", "case:coin", "--theta0", "1e300"], "--theta0 must be an angle in radians"),
    (["toss", "case:coin", "--theta0", "nan"], "--theta0"),
    (["wall", "--polar", "1", "--H", "5e-324", "-o", "w.csv"], "below the body's narrowest width 2"),
])
def test_options_that_mean_nothing_are_refused(tmp_path, monkeypatch, capsys, argv, needle):
    monkeypatch.chdir(tmp_path)
    assert main(["solve", "1+0.1*cos(2*t)", "--points", "256", "-o", "body.json"]) == 0
    capsys.readouterr()
    before = sorted(os.listdir(tmp_path))
    assert main(argv) == 2
    _one_line(capsys, needle)
    assert sorted(os.listdir(tmp_path)) == before


def test_options_that_mean_something_pass(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["wall", "--polar", "1", "--H", "2.5", "-o", "w.csv"]) == 0  # the unit disc fits a strip of 2.5
    assert main(["quantum", "1", "--H", "3", "--levels", "2", "--method", "fem", "--order", "2", "--cells", "4"]) == 0
    assert main(["toss", "case:coin", "--theta0", "7.5", "--v0", "0:1:2", "--omega", "0:1:2"]) == 0
