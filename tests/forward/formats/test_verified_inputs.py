"""Inputs that used to be accepted and must not be: damaged body files, walls that jump.

A body JSON holds redundant data (nodes, Bézier controls, the area and perimeter it was solved with), so a
damaged one can be told from a real one; a wall expression's value must be continuous (a support function
is), while its slope may jump (a kink).
"""

from __future__ import annotations

import copy
import json
import os

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward.errors import InvalidOutline, InvalidWall
from coinwall.forward.formats import bodyjson
from coinwall.forward.formats.load import read_outline
from coinwall.forward.wall import Wall


@pytest.fixture(scope="module")
def solved(tmp_path_factory):
    """Real body files from ``coinwall solve``: a smooth body, one with corners, a polygon."""
    folder = tmp_path_factory.mktemp("solved")
    files = {}
    for name, args in {"ellipse": [], "corner": ["case:appendix-corner"], "rectangle": ["case:rectangle"]}.items():
        path = str(folder / f"{name}.json")
        assert main(["solve", *args, "-o", path]) == 0
        with open(path) as handle:
            files[name] = json.load(handle)
    return files


def _clockwise(doc):
    """The same curve traced clockwise: nodes reversed, every segment's controls reversed."""
    nodes, controls = np.array(doc["outline"]), np.array(doc["controls"])
    doc["outline"] = np.roll(nodes[::-1], 1, axis=0).tolist()
    doc["controls"] = controls[::-1, ::-1].tolist()


def _swap(doc, i, j):
    nodes = np.array(doc["outline"])
    nodes[[i, j]] = nodes[[j, i]]
    doc["outline"] = nodes.tolist()


def _controls(doc, change):
    doc["controls"] = change(np.array(doc["controls"])).tolist()


def _longer_arm(doc):
    """One Bézier arm 1.5 times longer along its own tangent: still convex, but not the solved outline."""
    nodes, controls = np.array(doc["outline"]), np.array(doc["controls"])
    k = len(nodes) // 4
    controls[k, 0] = nodes[k] + 1.5 * (controls[k, 0] - nodes[k])
    doc["controls"] = controls.tolist()


DAMAGE = {
    "shift controls by 0.1": (lambda d: _controls(d, lambda c: c + 0.1), "controls do not fit"),
    "shift controls by 0.1 in x": (lambda d: _controls(d, lambda c: c + [0.1, 0.0]), "controls do not fit"),
    "zero controls": (lambda d: _controls(d, lambda c: 0 * c), "controls do not fit"),
    "scale controls by 5": (lambda d: _controls(d, lambda c: 5 * c), "controls do not fit"),
    "reverse the controls": (lambda d: _controls(d, lambda c: c[::-1]), "controls do not fit"),
    "reverse the nodes": (lambda d: d.update(outline=d["outline"][::-1]), "controls do not fit"),
    "clockwise": (_clockwise, "clockwise"),
    "swap two nodes": (lambda d: _swap(d, 1, 3), "controls do not fit"),
    # near a critical angle neighbours are ~1e-7 apart: the recorded perimeter tells
    "swap two neighbours": (lambda d: _swap(d, 1, 2), ("controls do not fit", "not the one that was solved")),
    "one arm longer": (_longer_arm, "not the one that was solved"),
}


@pytest.mark.parametrize("damage", list(DAMAGE))
@pytest.mark.parametrize("command", ["wall", "mass", "export"])
def test_damaged_body_file_is_refused(damage, command, solved, tmp_path, capsys, monkeypatch):
    name = "rectangle" if damage == "swap two nodes" else "ellipse"  # a 4-node body's 1 and 3 are not neighbours
    doc = copy.deepcopy(solved[name])
    change, needle = DAMAGE[damage]
    change(doc)
    monkeypatch.chdir(tmp_path)
    with open("body.json", "w") as handle:
        json.dump(doc, handle)
    capsys.readouterr()
    args = {"wall": ["wall", "body.json", "-o", "wall.csv"], "mass": ["mass", "body.json", "--json"],
            "export": ["export", "body.json", "-o", "body.svg"]}[command]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error: body file 'body.json'"), err
    assert any(text in err for text in ((needle,) if isinstance(needle, str) else needle)), err
    assert sorted(os.listdir(tmp_path)) == ["body.json"]  # no output file
    with pytest.raises(InvalidOutline):
        read_outline("body.json")


def test_damage_on_a_body_with_corners_is_refused(solved, tmp_path):
    for damage in ("shift controls by 0.1", "zero controls", "scale controls by 5", "clockwise", "swap two nodes"):
        doc = copy.deepcopy(solved["corner"])
        DAMAGE[damage][0](doc)
        path = tmp_path / "body.json"
        path.write_text(json.dumps(doc))
        with pytest.raises(InvalidOutline, match=DAMAGE[damage][1]):
            read_outline(str(path))


@pytest.mark.parametrize("name", ["ellipse", "corner", "rectangle"])
def test_undamaged_body_file_works_byte_for_byte(name, solved, tmp_path, capsys, monkeypatch):
    """The verification refuses, never changes: the outputs are those made without it."""
    monkeypatch.chdir(tmp_path)
    with open("body.json", "w") as handle:
        json.dump(solved[name], handle, indent=1)
    outputs = {}
    for verified in (True, False):
        with monkeypatch.context() as patch:
            if not verified:
                patch.setattr(bodyjson, "verify_controls", lambda *args: None)
            assert main(["wall", "body.json", "-o", f"wall{verified}.csv"]) == 0
            capsys.readouterr()
            assert main(["mass", "body.json", "--json"]) == 0
            mass = capsys.readouterr().out
            assert main(["export", "body.json", "-o", f"body{verified}.svg"]) == 0
            with open(f"wall{verified}.csv", "rb") as wall, open(f"body{verified}.svg", "rb") as drawing:
                outputs[verified] = (wall.read(), mass, drawing.read().replace(str(verified).encode(), b""))
    assert outputs[True] == outputs[False]


def test_every_solved_case_passes_the_verification(tmp_path):
    for case in ("stick", "triangle", "reuleaux-3", "appendix-critical", "egg", "coin"):
        path = str(tmp_path / f"{case}.json")
        assert main(["solve", f"case:{case}", "-o", path]) == 0
        read_outline(path)


def test_points_files_are_not_held_to_controls(tmp_path):
    """A plain list of points (any orientation) is still read as points: its convex hull."""
    path = tmp_path / "points.json"
    path.write_text(json.dumps({"points": [[0, 0], [0, 1], [1, 1], [1, 0]]}))  # clockwise
    assert read_outline(str(path)).outline.area > 0


# ------------------------------------------------------------------ walls that jump

JUMPS = [
    ("1+0.1*cos(t)/abs(cos(t))", 1.5707963),                  # a sign written with abs: jumps at ±π/2
    ("1+0.1*sin(t+0.3)/abs(sin(t+0.3))", np.pi - 0.3),
    ("1+0.1*max(0, cos(t))/cos(t)", 1.5707963),               # a step: max of a division
    ("1+0.1*min(1,max(-1,cos(t)/abs(cos(t))))", 1.5707963),
    ("1+1e-6*cos(t)/abs(cos(t))", 1.5707963),                 # a small jump is still a jump
]


@pytest.mark.parametrize("wall,angle", JUMPS)
def test_wall_that_jumps_is_refused(wall, angle, capsys):
    assert main(["critical", wall]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "jumps at θ = " in err and "continuous" in err, err
    assert abs(float(err.split("jumps at θ = ")[1].split(":")[0]) - angle) < 1e-6
    with pytest.raises(InvalidWall, match="jumps"):
        Wall.from_expression(wall)


def test_solve_of_a_wall_that_jumps_writes_nothing(tmp_path, capsys):
    assert main(["solve", JUMPS[0][0], "--b0", "0", "-o", str(tmp_path / "body.json")]) == 2
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("wall,b_c", [
    ("1+0.1*tanh(50*sin(t))", 191.40289019335),     # steep but continuous
    ("1+0.1*tanh(1000*sin(t))", None),             # steeper still
    ("abs(cos(t))+1", -1.0),                        # kinked: the slope jumps, the value does not
    ("abs(sin(t))", 0.0),
    ("1+0.01*cos(50*t)", 23.99),
    ("sqrt((1+cos(t)**2)/2)", -0.5),
])
def test_steep_and_kinked_walls_are_accepted(wall, b_c, capsys):
    assert main(["critical", wall, "--json"]) == 0
    found = json.loads(capsys.readouterr().out)["b_c"]
    if b_c is not None:
        assert abs(found - b_c) < 1e-6 * max(1.0, abs(b_c))
