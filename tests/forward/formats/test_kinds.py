"""A wall file is never read as an outline, and an outline never as a wall (forward/formats/kinds.py).

Before, ``coinwall wall w.csv`` on a ``theta,b`` file gave the wall of the polygon with vertices (θ, b), exit
status 0, and ``coinwall solve pts.csv`` on the headerless points of an outline gave a wall b(θ = x) = y.
"""

from __future__ import annotations

import doctest
import json
import math
import os

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward.formats import kinds


def _wall_rows(n=90, degrees=False):
    theta = np.arange(n) * (360.0 / n if degrees else 2 * math.pi / n)
    b = 1 + 0.1 * np.cos(2 * np.radians(theta) if degrees else 2 * theta)
    return theta, b


def _write(path, header, rows):
    with open(path, "w") as fh:
        if header:
            fh.write(header + "\n")
        for row in rows:
            fh.write(",".join(f"{v:.6g}" for v in row) + "\n")


def _refused(capsys, argv, *needles):
    folder = os.listdir(".")
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:"), err
    for needle in needles:
        assert needle in err, err
    assert os.listdir(".") == folder  # nothing written
    return err


@pytest.mark.parametrize("header,degrees", [("theta,b", False), ("theta_deg,b", True), ("θ;b", False), (None, False),
                                            (None, True)])
@pytest.mark.parametrize("command", [["wall", "-o", "out.csv"], ["mass"]])
def test_a_wall_file_is_not_an_outline(tmp_path, monkeypatch, capsys, header, degrees, command):
    monkeypatch.chdir(tmp_path)
    theta, b = _wall_rows(degrees=degrees)
    if header and ";" in header:
        with open("w.csv", "w") as fh:
            fh.write(header + "\n" + "".join(f"{t:.6g};{v:.6g}\n" for t, v in zip(theta, b)))
    else:
        _write("w.csv", header, zip(theta, b))
    _refused(capsys, [command[0], "w.csv"] + command[1:], "looks like a wall file", "coinwall solve")


def test_a_wall_json_is_not_an_outline(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    theta, b = _wall_rows()
    with open("w.json", "w") as fh:
        json.dump({"theta": theta.tolist(), "b": b.tolist()}, fh)
    with open("f.json", "w") as fh:
        json.dump({"a0": 1.0, "cos": [0.0, 0.1]}, fh)
    for name in ("w.json", "f.json"):
        for command in (["mass"], ["wall", "-o", "out.csv"], ["export", "-o", "out.svg"]):
            err = _refused(capsys, [command[0], name] + command[1:], "looks like a wall file", "coinwall solve")
            assert "header row" not in err  # a JSON file's keys are never ambiguous


@pytest.mark.parametrize("command", [["solve"], ["critical"], ["fit", "-o", "out.json"],
                                     ["simulate", "--H", "3", "--collisions", "10"]])
def test_an_outline_is_not_a_wall(tmp_path, monkeypatch, capsys, command):
    monkeypatch.chdir(tmp_path)
    assert main(["solve", "1+0.1*cos(2*t)", "--points", "256", "-o", "body.json", "-o", "body.csv"]) == 0
    capsys.readouterr()
    phi = np.linspace(0, 2 * math.pi, 40, endpoint=False)
    _write("points.csv", None, zip(np.cos(phi), 0.7 * np.sin(phi)))  # no header: told by its first column
    _write("xy.csv", "x,y", zip(np.cos(phi), 0.7 * np.sin(phi)))
    for name in ("body.json", "body.csv", "points.csv", "xy.csv"):
        _refused(capsys, [command[0], name] + command[1:], "looks like a body file", "coinwall wall")


def test_a_header_row_makes_any_file_unambiguous(tmp_path, monkeypatch, capsys):
    """A headerless file is told by its first column; a header row overrides: ``x,y`` points whose x rises row by
    row are an outline (of the hull), ``theta,b`` samples in any order are a wall."""
    monkeypatch.chdir(tmp_path)
    x = np.linspace(-1, 1, 21)
    _write("sorted.csv", None, zip(x, 1 - x ** 2))  # looks like angles: refused, with the way out
    _refused(capsys, ["wall", "sorted.csv", "-o", "out.csv"], "name its columns x,y in a header row")
    _write("sorted.csv", "x,y", zip(x, 1 - x ** 2))
    assert main(["wall", "sorted.csv", "-o", "out.csv", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # the hull of the parabola's arc: reaches the chord y = 0 from its centroid, 1 - 2/5·... (checked loosely:
    # a wall of this body is positive everywhere and the file was read as points, not as (θ, b))
    assert out["b_min"] > 0 and "CSV points" in out["note"]
    theta, b = _wall_rows(60)
    order = np.random.default_rng(1).permutation(theta.size)
    _write("shuffled.csv", None, zip(theta[order], b[order]))
    _refused(capsys, ["solve", "shuffled.csv"], "looks like a body file", "theta,b")
    _write("shuffled.csv", "theta,b", zip(theta[order], b[order]))
    assert main(["critical", "shuffled.csv", "--json"]) == 0
    # b = 1 + 0.1 cos 2θ: b + b'' = 1 − 0.3 cos 2θ, so b_c = −0.7 (closed form); 6 digits and 6° spacing
    assert json.loads(capsys.readouterr().out)["b_c"] == pytest.approx(-0.7, abs=0.02)


def test_the_signs():
    assert kinds.csv_kind("# coinwall body: wall '1'\nx,y,alpha,R,K\n1,0,0,1,1\n")[0] == kinds.BODY
    assert kinds.csv_kind("angle [°]\tb\n0\t1\n")[0] == kinds.WALL
    assert kinds.csv_kind("1,2\n3,4\n") == (None, "")  # too few rows to tell
    wrap = "\n".join(f"{(k * 10 + 180) % 360},1" for k in range(36))  # 180°..350°, 0°..170°: one wrap
    assert kinds.csv_kind(wrap)[0] == kinds.WALL
    assert kinds.json_kind([1, 2]) == (None, "")


def test_doctests():
    assert doctest.testmod(kinds, optionflags=doctest.ELLIPSIS).failed == 0
