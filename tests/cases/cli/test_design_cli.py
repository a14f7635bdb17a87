"""``coinwall design``: the issue's command as written, outputs all or nothing, and bad input in one line."""

import json
import math
import os

import pytest

from coinwall.cases.cli.main import main

RECT = "abs(cos(t)) + h*abs(sin(t))"


def test_the_three_sided_coin_command_as_written(capsys):
    status = main(["design", RECT, "--param", "h=0.05:3", "--target", "edge=1/3", "--model", "drop", "--json"])
    assert status == 0
    doc = json.loads(capsys.readouterr().out)
    h = doc["parameters"]["h"]
    assert abs(h["value"] - 1 / math.sqrt(3)) < 1e-9
    assert h["interval"][0] <= 1 / math.sqrt(3) <= h["interval"][1]
    assert h["interval"][1] - h["interval"][0] <= 2.1e-10
    for name in ("edge", "heads", "tails"):
        row = doc["outcomes"][name]
        assert abs(row["p"] - 1 / 3) < 1e-9 and row["interval"][0] <= row["p"] <= row["interval"][1]
    assert doc["outcomes"]["edge"]["target"] == pytest.approx(1 / 3)
    assert doc["body"]["regime"] == "critical" and doc["body"]["max_wall_error"] < 1e-9
    assert doc["warnings"] == []


def test_the_designed_body_is_the_rectangle(tmp_path, capsys):
    """The wall |cos t| + h|sin t| at b0 = 0 is the support function of the 2 × 2h rectangle about its centre:
    the body written is that rectangle, its vertices (±1, ±1/√3)."""
    body = str(tmp_path / "rect.json")
    assert main(["design", RECT, "--param", "h=0.05:3", "--target", "edge=1/3", "-o", body]) == 0
    capsys.readouterr()
    vertices = sorted(tuple(round(c, 12) for c in p) for p in json.load(open(body))["outline"])
    h = round(1 / math.sqrt(3), 12)
    assert vertices == [(-1.0, -h), (-1.0, h), (1.0, -h), (1.0, h)]


def test_cylinder_writes_body_and_figure(tmp_path, capsys):
    svg, dxf, fig = (str(tmp_path / name) for name in ("coin.svg", "coin.dxf", "odds.png"))
    status = main(["design", "cylinder", "--param", "thickness=1:30", "--param", "radius=12", "--target",
                   "edge=1/3", "--model", "flip", "-o", svg, "-o", dxf, "--figure", fig, "--units", "mm"])
    out = capsys.readouterr().out
    assert status == 0, out
    assert "thickness = 13.856406460" in out  # 2r/√3 at r = 12
    assert open(fig, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    text = open(svg).read()
    assert text.startswith("<svg") and "mm" in text
    assert os.path.getsize(dxf) > 0


def test_odds_of_one_body(capsys):
    assert main(["design", "cylinder", "--param", "thickness=1", "--model", "drop", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["outcomes"]["edge"]["p"] == pytest.approx(0.5 / math.sqrt(1.25), abs=1e-12)


def test_bounce_design_json(capsys):
    status = main(["design", RECT, "--param", "h=0.2:2", "--target", "edge=1/3", "--model", "bounce", "--e", "0.5",
                   "--tolerance", "0.03", "--resimulate", "20000", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert status in (0, 1)  # 1: the undecided share carries a warning
    edge = doc["outcomes"]["edge"]
    assert edge["interval"][1] - edge["interval"][0] <= 0.06 + 1e-12
    h = doc["parameters"]["h"]
    assert h["interval"][0] < h["value"] < h["interval"][1]
    assert doc["undecided"]["p"] > 0 and doc["resimulation"]["tosses"] == 20000
    assert not any(w.startswith("the independent") for w in doc["warnings"])  # the re-simulation agrees


def test_bounce_design_with_friction(capsys):
    """--mu reaches the toss: the model in the JSON, and no toss left undecided (the same hands slide for ever on a
    frictionless floor, test_bounce_design_json)."""
    status = main(["design", RECT, "--param", "h=0.5:1.2", "--target", "edge=1/3", "--model", "bounce", "--e", "0.5",
                   "--mu", "0.3", "--rolling", "0.001", "--tolerance", "0.03", "--max-tosses", "1024", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert status == 0 and doc["warnings"] == []
    assert doc["model"]["mu"] == 0.3 and doc["model"]["rolling"] == 0.001
    assert doc["undecided"]["p"] == 0 and abs(doc["outcomes"]["edge"]["p"] - 1 / 3) <= 0.03


@pytest.mark.parametrize("args,message", [
    (["--model", "bounce", "--mu", "-0.3"], "--mu must be a coefficient of friction between 0 and 1e6, got -0.3"),
    (["--model", "bounce", "--rolling", "0.01"], "--rolling must be a rolling resistance in [0, 1]"),
    (["--model", "bounce", "--vx", "1,0"], "a horizontal launch velocity --vx does nothing on a frictionless floor"),
    (["--mu", "0.3"], "--mu does nothing in the drop toss"),
    (["--model", "bounce3d", "--mu", "0.3"], "--mu: the bounce3d toss has a frictionless floor"),
    (["--e", "0.5"], "--e does nothing in the drop toss"),
    (["--target", "side=0.2"], "unknown outcome 'side'"),
    (["--target", "edge=1/0"], "must be a number or a fraction"),
    (["--target", "edge=0.9"], "is not reached"),
    (["--model", "bounce3d"], "does not apply to a planar family"),
    (["--param", "q=1"], "'q' is not used"),
])
def test_bad_input_is_one_line(args, message, capsys, tmp_path):
    out = str(tmp_path / "body.svg")
    base = ["design", RECT, "--param", "h=0.05:3", "-o", out]
    if not any(a.startswith("edge") or a.startswith("side") for a in args):
        base += ["--target", "edge=1/3"]
    assert main(base + args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err
    assert not os.path.exists(out)


def test_files_and_cases_are_refused(capsys):
    assert main(["design", "wall.csv", "--target", "edge=1/3"]) == 2
    assert "has no parameter to design" in capsys.readouterr().err
    assert main(["design", RECT, "--param", "h=0.05:3"]) == 2
    assert "give a --target" in capsys.readouterr().err
