"""The command line: outputs, JSON summaries, and bad input → one line on stderr, exit 2, no files."""

import json
import os

import pytest

from coinwall.cases.cli.main import main

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def test_solve_writes_all_formats(tmp_path, capsys):
    outs = [str(tmp_path / f"body.{ext}") for ext in ("svg", "json", "csv", "png")]
    args = ["solve", ELLIPSE, "--param", "eps=1", "--b0", "-0.5"]
    for o in outs:
        args += ["-o", o]
    assert main(args) == 0
    doc = json.loads(open(outs[1]).read())
    assert doc["regime"] == "critical"
    assert doc["b_c"] == pytest.approx(-0.5, abs=1e-12)
    assert doc["max_wall_error"] < 1e-9
    assert len(doc["outline"]) > 100 and doc["corners"] == []
    svg = open(outs[0]).read()
    assert svg.startswith("<svg") and "viewBox" in svg
    assert open(outs[3], "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    assert open(outs[2]).read().splitlines()[1] == "x,y,alpha,R,K"


def test_solve_json_and_builtin_example(capsys):
    assert main(["solve", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["regime"] == "critical" and "outline" not in doc
    assert main(["solve"]) == 0
    assert "critical" in capsys.readouterr().out


def test_corner_regime_reports_corners(capsys):
    assert main(["solve", ELLIPSE, "--param", "eps=1", "--b0", "-0.6", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["regime"] == "corner"
    assert {"direction", "half_width", "distance", "max_deficit"} <= set(doc["corners"][0])


def test_critical_json(capsys):
    assert main(["critical", ELLIPSE, "--param", "eps=1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["b_c"] == pytest.approx(-0.5, abs=1e-12)
    assert len(doc["angles"]) == 2


def test_wall_round_trip(tmp_path, capsys):
    body = str(tmp_path / "body.json")
    assert main(["solve", ELLIPSE, "--param", "eps=1", "-o", body, "--json"]) == 0
    wall_csv = str(tmp_path / "wall.csv")
    assert main(["wall", body, "-o", wall_csv, "--H", "3"]) == 0
    import numpy as np

    data = np.loadtxt(wall_csv, delimiter=",", skiprows=1)
    expected = np.sqrt((1 + np.cos(data[:, 0]) ** 2) / 2)  # paper eq. 18, eps = 1, b0 = 0
    assert np.max(np.abs(data[:, 1] - expected)) < 1e-9
    assert np.max(np.abs(data[:, 2] - (3 - expected))) < 1e-9  # symmetric body: t = H − b(θ+π) = H − b(θ)


@pytest.mark.parametrize("args,needle", [
    (["solve", "__import__('os').system('true')"], "__import__"),
    (["solve", "t.__class__"], "__class__"),
    (["solve", "sin(t) +"], "syntax"),
    (["solve", ELLIPSE], "eps"),                                     # undeclared parameter
    (["solve", "sin(t)", "--param", "eps=1"], "eps"),                # unknown (unused) parameter
    (["solve", "sin(t)", "--param", "eps=nan"], "nan"),
    (["solve", "1 + 0.1*cos(t)", "--b0", "nan"], "b0"),
    (["solve", "1 + 0.1*cos(t/2)"], "periodic"),
    (["solve", "sqrt(-1)"], "finite"),
    (["solve", "0.5 + cos(t)"], "centre of mass"),                   # negative wall
    (["solve", "1", "-o", "/nonexistent-dir/body.svg"], "does not exist"),
    (["solve", "1", "-o", "body.xyz"], "unknown extension"),
    (["critical", "log(0*t)"], "finite"),
])
def test_bad_input_one_line_exit_2(args, needle, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(args + ["-o", "keep.json"] if args[0] == "solve" and "-o" not in args else args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:")
    assert needle.lower() in err.lower()
    assert os.listdir(tmp_path) == []  # nothing written, no temporary left behind


def test_unwritable_output_leaves_nothing(tmp_path, capsys):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if os.access(locked, os.W_OK):
            pytest.skip("running as a user who can write anywhere (root)")
        assert main(["solve", "1", "-o", str(tmp_path / "ok.json"), "-o", str(locked / "b.svg")]) == 2
        assert not (tmp_path / "ok.json").exists()
    finally:
        locked.chmod(0o700)


def test_argparse_error_is_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["solve", "1", "--points", "many"])
    assert exc.value.code == 2


def test_failure_mid_write_leaves_nothing(tmp_path, capsys, monkeypatch):
    """All or nothing: when the second exporter fails, the first file is not left behind either."""
    from coinwall.inverse.export import svg

    def broken(body, stream):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(svg, "write", broken)
    assert main(["solve", "1", "-o", str(tmp_path / "a.json"), "-o", str(tmp_path / "b.svg")]) == 2
    assert "No space left" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


def test_outputs_get_the_usual_file_mode(tmp_path, capsys):
    """Outputs are renamed from temporary files; they must still get 0666 minus the umask, like any file."""
    import os
    import stat

    from coinwall.forward.formats.output import default_file_mode

    out = tmp_path / "body.svg"
    assert main(["solve", "-o", str(out), "--no-cross-check"]) == 0
    assert stat.S_IMODE(os.stat(out).st_mode) == default_file_mode()
