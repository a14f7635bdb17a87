"""``coinwall toss --mu``, the outcome function for many launches, the names of the rest states and Keller's lines.

The bodies are Fourier walls written to JSON files (the file format the command line reads), which share one
compiled kernel with the rest of the friction tests; the egg is case:egg's wall.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward import Wall
from coinwall.forward.dynamics.floor.field import STATUS, FieldTable
from coinwall.forward.dynamics.floor.hand import launch_spread, toss_outcomes
from coinwall.forward.dynamics.floor.toss import basin_map

EGG = {"a0": 1.0, "cos": [0.05, 0.06], "sin": [0.0, 0.0, 0.04]}
COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"


@pytest.fixture
def egg_file(tmp_path):
    path = tmp_path / "egg.json"
    path.write_text(json.dumps(EGG))
    return str(path)


def test_toss_with_friction_counts_each_undecided_reason_on_the_terminal(egg_file, capsys):
    """Without friction the egg's undecided tosses slide; with μ = 0.3 they roll away (no rolling resistance): the
    terminal has one line per reason, its count and what it means; the JSON summary has the same counts."""
    grid = ["--e", "0.8", "--v0", "0:3:5", "--omega", "0:8:5"]
    assert main(["toss", egg_file, *grid]) == 0
    out = capsys.readouterr().out
    assert "undecided  slides" in out and "frictionless floor" in out
    assert main(["toss", egg_file, *grid, "--mu", "0.3"]) == 0
    out = capsys.readouterr().out
    lines = [line for line in out.splitlines() if line.startswith("undecided")]
    assert lines and all(line.split()[1] != "slides" for line in lines)
    assert any(line.split()[1] == "rolls" and "rolling resistance" in line for line in lines)
    assert main(["toss", egg_file, *grid, "--mu", "0.3", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    counts = {line.split()[1]: int(line.split()[2]) for line in lines}
    assert summary["undecided"] == counts and summary["mu"] == 0.3
    assert summary["names"] == ["rest 94.8°", "rest 225°"]


def test_toss_with_rolling_resistance_settles_the_egg(egg_file, capsys):
    assert main(["toss", egg_file, "--e", "0.8", "--mu", "0.3", "--rolling", "0.01", "--v0", "0:3:5", "--omega",
                 "0:8:5", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["fractions"]["undecided"] == 0.0 and summary["undecided"] == {}


@pytest.mark.parametrize("argv, needle", [
    (["--mu", "-0.5"], "--mu"),
    (["--rolling", "0.1"], "--rolling"),                   # rolling resistance without friction
    (["--mu", "0.3", "--rolling", "2"], "--rolling"),
    (["--mu", "0.3", "--slide"], "--slide"),
    (["--e", "0", "--H", "6"], "--e"),                     # perfectly plastic needs a floor only
    (["--e", "1.5"], "--e"),
])
def test_bad_friction_options_are_one_line_and_status_2(egg_file, capsys, argv, needle):
    assert main(["toss", egg_file, "--v0", "0:1:2", "--omega", "0:1:2", *argv]) == 2
    err = capsys.readouterr().err
    assert needle in err and len(err.strip().splitlines()) == 1


def test_toss_outcomes_are_seeded_vectorised_and_named():
    """The library's function for many launches: the same seed gives the same launches and outcomes; each launch
    has its rest state by name, its rest angle (the valley's minimum), the time it was decided and its impacts;
    the outcomes are those of the basin map at the same launches (one kernel, two entry points)."""
    table = FieldTable(Wall.from_fourier(**EGG), g=1.0, e=0.8,
                       mu=0.3, rolling=0.01)
    v, w = launch_spread((2.0, 5.0), (0.3, 1.0), 40, seed=5)
    again = launch_spread((2.0, 5.0), (0.3, 1.0), 40, seed=5)
    assert np.array_equal(v, again[0]) and np.array_equal(w, again[1])
    result = toss_outcomes(table, v, w, height=2.3)
    assert len(result) == 40 and set(result.name) <= set(table.landscape.names) | {"undecided"}
    decided = result.outcome >= 0
    assert decided.mean() > 0.9
    settled = result.status == 1
    assert np.allclose(result.rest_angle[settled], table.landscape.minima[result.outcome[settled]])
    held = result.status == 3  # at rest where the rolling resistance holds it: |B'(θ)| ≤ δ, in its valley
    assert np.all(np.abs(table.wall.derivatives(result.rest_angle[held])[1]) <= table.rolling + 1e-9)
    assert np.array_equal(table.landscape.valley(result.rest_angle[decided]), result.outcome[decided])
    assert np.all(np.isnan(result.rest_angle[~decided]))
    assert np.all(result.time[decided] > 0) and np.all(result.impacts[decided] >= 1)
    assert all(r == "" for r in result.reason[decided])
    grid = basin_map(table, v[:5], w[:1], 2.3)
    one = toss_outcomes(table, v[:5], np.full(5, w[0]), 2.3)
    assert np.array_equal(grid.outcome[0], one.outcome)
    assert sum(result.undecided_counts().values()) == int((~decided).sum())
    json.dumps(result.to_dict(), allow_nan=False)


def test_names_heads_tails_edge_for_coins_and_faces_by_angle_otherwise():
    """A coin (centrally symmetric, its deepest pair of valleys opposite): heads/tails, and edge for its other
    faces (a rectangle seen edge-on); a body without that symmetry: its rest states by the normal's angle, ``face``
    where b has a kink there (a flat face), ``rest`` on a smooth part."""
    from coinwall.forward.dynamics.floor.landscape import landscape

    rectangle = landscape(Wall.from_expression("0.3*abs(cos(t)) + 1.2*abs(sin(t))"))  # thin along x
    assert sorted(rectangle.names) == ["edge", "edge", "heads", "tails"] and rectangle.coin
    # its faces rest at θ = 0 and π (sin θ = 0 there: heads is the one with cos θ < 0), its edges at ±π/2
    assert rectangle.names[int(np.argmin(np.abs(rectangle.minima - math.pi)))] == "heads"
    assert rectangle.names[int(np.argmin(np.abs(rectangle.minima - 1.5 * math.pi)))] == "edge"
    square = landscape(Wall.from_expression("abs(cos(t)) + abs(sin(t))"))
    assert not square.coin and sorted(square.names) == ["face 0°", "face 180°", "face 270°", "face 90°"]
    egg = landscape(Wall.from_fourier(**EGG))
    assert not egg.coin and egg.names == ["rest 94.8°", "rest 225°"] and not egg.faces.any()


def test_kellers_lines_are_drawn_for_a_coin_only():
    """The basin map's dashed hyperbolas ω0 v0/g = π(n ± ¼) belong to a coin; a body that is no coin has none."""
    import matplotlib.pyplot as plt

    def dashed(table):
        ax = basin_map(table, np.linspace(0.5, 1.5, 3), np.linspace(1.0, 3.0, 3), 2.5, catch=True).plot()
        lines = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
        plt.close("all")
        return len(lines)

    coin = FieldTable(Wall.from_expression(COIN, {"eps": 99.0}), g=1.0, e=0.6, mu=0.3)
    egg = FieldTable(Wall.from_fourier(**EGG), g=1.0, e=0.6, mu=0.3)
    assert dashed(coin) > 0 and dashed(egg) == 0


def test_status_words_cover_the_reasons():
    """Every undecided status has a note that says why (the terminal prints it)."""
    from coinwall.forward.dynamics.floor.field import FIELD_NOTES, UNDECIDED_STATUSES

    words = {word: code for code, word in STATUS.items()}
    assert set(UNDECIDED_STATUSES) == {w for w in words if words[w] not in (1, 2, 3)}
    assert all(FIELD_NOTES.get(words[w]) for w in UNDECIDED_STATUSES)
