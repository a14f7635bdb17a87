"""One strict grammar of numbers and lists for flags, list items and sample files (ASCII decimal numbers;
no `1_0`, no other scripts' digits, no empty list item), and the same degrees check for every sample format.
Each refusal is one line and exit status 2, with nothing written."""

from __future__ import annotations

import json

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.validation import parse_number, parse_number_list


@pytest.mark.parametrize("text", ["1_0", "１", "١", "0x10", "1,5", "", " ", "1e", "--1", "½"])
def test_not_a_decimal_number(text):
    with pytest.raises(ValueError):
        parse_number(text)


@pytest.mark.parametrize("text, value", [("1", 1.0), (" -2.5e-3 ", -2.5e-3), (".5", 0.5), ("3.", 3.0)])
def test_decimal_numbers(text, value):
    assert parse_number(text) == value


@pytest.mark.parametrize("text, needle", [("3,,4", "item 2"), ("3,", "item 2"), (",3", "item 1"),
                                          ("3,1_0", "'1_0'"), ("3,inf", "finite"), ("3,nan", "finite")])
def test_lists_refuse_empty_and_foreign_items(text, needle):
    with pytest.raises(InvalidArgument, match=needle):
        parse_number_list("H", text)
    assert parse_number_list("H", "2, 3,4") == [2.0, 3.0, 4.0]


@pytest.mark.parametrize("argv", [["kam", "--H", "3,,4"], ["kam", "--H", "3,1_0"], ["quantum", "1", "--H", "2,,3",
                                                                                       "--levels", "4"]])
def test_cli_lists(argv, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--H" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("cell", ["1_0", "１", "٣"])
def test_sample_files_take_only_decimal_numbers(cell, tmp_path, capsys):
    theta = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    rows = [f"{float(t)!r},{float(1 + 0.1 * np.cos(2 * t))!r}" for t in theta]
    rows[5] = f"{cell},1.0"
    path = tmp_path / "w.csv"
    path.write_text("theta,b\n" + "\n".join(rows) + "\n")
    assert main(["critical", str(path)]) == 2
    err = capsys.readouterr().err
    assert "line 7" in err and len(err.strip().splitlines()) == 1


def test_json_samples_in_degrees_are_caught_like_csv(tmp_path, capsys):
    """A JSON ``{theta, b}`` in degrees was read as radians (the CSV reader caught the same data)."""
    degrees = np.arange(0, 360, 2.0)
    values = (1 + 0.1 * np.cos(np.radians(degrees))).tolist()
    path = tmp_path / "w.json"
    path.write_text(json.dumps({"theta": degrees.tolist(), "b": values}))
    assert main(["critical", str(path)]) == 2
    assert "degrees" in capsys.readouterr().err
    path.write_text(json.dumps({"theta": degrees.tolist(), "b": values, "degrees": True}))
    assert main(["critical", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["b_c_lower"] <= -1.0 <= doc["b_c_upper"]  # 1 + 0.1 cos θ (a disc off centre): b + b'' = 1
