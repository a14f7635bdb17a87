"""The command line: outputs, JSON summaries, and bad input → one line on stderr, exit 2, no files."""

import json
import os

import numpy as np
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
    (["solve", "1", "-o", "/dev/null/body.svg"], "not a folder"),        # missing folders are created, files are not
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

    def broken(body, stream, options=None):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(svg, "write", broken)
    assert main(["solve", "1", "-o", str(tmp_path / "a.json"), "-o", str(tmp_path / "b.svg")]) == 2
    assert "No space left" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


def test_outputs_get_the_usual_file_mode(tmp_path, capsys):
    """Outputs are renamed from temporary files; they must still get 0666 minus the umask, like any file."""
    import os
    import stat

    out = tmp_path / "body.svg"
    assert main(["solve", "-o", str(out), "--no-cross-check"]) == 0
    mask = os.umask(0o022)
    os.umask(mask)
    assert stat.S_IMODE(os.stat(out).st_mode) == 0o666 & ~mask


# --------------------------------------------------------------------------- the house: parser and subcommands

def test_subcommand_table_is_explicit_and_complete():
    """One module per subcommand, listed in one table; each registers exactly its own subcommand."""
    import argparse
    import types

    from coinwall.cases.cli.parser import SUBCOMMANDS, CommandParser, build_parser

    assert list(SUBCOMMANDS) == ["solve", "critical", "fit", "wall", "export", "mass", "simulate", "section",
                                 "correlation", "toss", "design", "coin3d", "kam", "quantum", "scan", "cases",
                                 "verify", "explore"]
    for name, module in SUBCOMMANDS.items():
        assert isinstance(module, types.ModuleType) and module.__name__.endswith(f".cli.{name}")
        subparsers = argparse.ArgumentParser().add_subparsers(parser_class=CommandParser)
        module.register(subparsers)
        assert list(subparsers.choices) == [name]
    assert list(build_parser().commands) == list(SUBCOMMANDS)


def test_version(capsys):
    from coinwall import __version__

    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out == f"coinwall {__version__}\n"


def test_bare_coinwall_prints_the_help(capsys):
    """No subcommand is a request for help: the help on stdout, status 0."""
    assert main([]) == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: coinwall")
    for name in ("solve", "critical", "wall", "export", "mass", "simulate", "cases", "verify"):
        assert f"    {name} " in out


def test_python_dash_m_coinwall():
    import subprocess
    import sys

    from coinwall import __version__

    done = subprocess.run([sys.executable, "-m", "coinwall", "--version"], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0 and done.stdout == f"coinwall {__version__}\n"
    done = subprocess.run([sys.executable, "-m", "coinwall"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and done.stdout.startswith("usage: coinwall") and done.stderr == ""


@pytest.mark.parametrize("command", ["solve", "critical", "wall", "export", "mass", "cases", "verify"])
def test_help_explains_then_gives_an_example(command, capsys):
    """--help: usage, then a paragraph on what the command computes, the options, and an example last."""
    with pytest.raises(SystemExit) as exc:
        main([command, "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    paragraphs = out.split("\n\n")
    assert paragraphs[0].startswith(f"usage: coinwall {command}")
    description = paragraphs[1]
    assert len(description.split()) >= 30 and not description.lstrip().startswith(("-", "positional", "options"))
    example = paragraphs[-1].rstrip("\n").splitlines()
    assert example[0] == "example:" and all(line.startswith("  $ coinwall ") for line in example[1:])
    assert any(line.startswith(f"  $ coinwall {command}") for line in example[1:])


# --------------------------------------------------------------------------- library errors in the words of the CLI

@pytest.mark.parametrize("args,flag", [
    (["solve", "1", "--kappa", "-1", "--units", "mm"], "--kappa must be between 1e-06 and 1e+06"),
    (["solve", "1", "--tolerance", "0"], "--tolerance must be positive"),
    (["solve", "1", "--points", "2"], "--points"),
    (["wall", "--polar", "1", "--samples", "3"], "--samples must be an integer >= 8, got 3"),
    (["wall", "--polar", "1", "--H", "-1"], "--H must be positive, got -1"),
    (["wall", "--polar", "1", "--H", "nan"], "--H must be finite"),
])
def test_library_errors_name_the_flag(args, flag, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:")
    assert flag in err and "`" not in err.split(":", 2)[2].split(",")[0]


def test_flag_message_maps_only_flags_of_the_command():
    from coinwall.cases.cli.main import flag_message

    flags = {"max_lag": "--max-lag", "kappa": "--kappa"}
    assert flag_message("`max_lag` must be >= 1, got 0", flags) == "--max-lag must be >= 1, got 0"
    assert flag_message("`kappa` 2 needs `units`", flags) == "--kappa 2 needs `units`"
    assert flag_message("no names here", flags) == "no names here"


# --------------------------------------------------------------------------- cases NAME

def test_cases_name_shows_one_case(capsys):
    from coinwall.cases import get_case

    assert main(["cases", "ellipse-0.55"]) == 0
    out = capsys.readouterr().out.splitlines()
    case = get_case("ellipse-0.55")
    assert out[0] == f"case       ellipse-0.55: {case.title}"
    assert out[1] == f"source     {case.source}"
    assert out[2].startswith("wall       b(θ) = sqrt((1+eps*cos(t)**2)/(1+eps))") and "eps = 0.55" in out[2]
    assert "b0         0" in out and "H          1.9" in out
    refs = [line for line in out if line.startswith("reference  ")]
    assert len(refs) == len(case.references)
    assert refs[0] == f"reference  b_c = {case.reference('b_c'):.15g}  [{case.references[0].source}]"
    assert main(["cases", "case:ellipse-0.55", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["name"] == "ellipse-0.55" and doc["H"] == 1.9 and doc["params"] == {"eps": 0.55}
    assert doc["references"][0] == {"name": "b_c", "value": case.reference("b_c"), "source": case.references[0].source}


def test_cases_name_sampled_wall_and_unknown(capsys):
    from coinwall.cases import get_case

    assert main(["cases", "reuleaux-3"]) == 0  # a wall without an expression shows as the Wall itself
    wall = get_case("reuleaux-3").wall()
    assert f"wall       {wall!r} (no closed-form expression)" in capsys.readouterr().out.splitlines()
    assert main(["cases", "triangle", "--json"]) == 0  # NumPy reference values are plain JSON numbers
    assert json.loads(capsys.readouterr().out)["references"][2]["value"] == pytest.approx(1.595)
    assert main(["cases", "no-such-case"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "unknown case 'no-such-case'" in err


# --------------------------------------------------------------------------- outputs: folders, replaced files

def test_outputs_create_missing_folders_and_name_replaced_files(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = ["solve", "1 + 0.1*cos(2*t)", "--no-cross-check", "-o", "deep/er/body.svg", "-o", "body.json"]
    assert main(args) == 0
    wrote = [line for line in capsys.readouterr().out.splitlines() if line.startswith("wrote")]
    assert wrote[0].startswith("wrote      deep/er/body.svg: exact Bézier path") and wrote[1] == "wrote      body.json"
    assert (tmp_path / "deep" / "er" / "body.svg").is_file()
    assert main(args) == 0
    wrote = [line for line in capsys.readouterr().out.splitlines() if line.startswith("wrote")]
    assert wrote[0].startswith("wrote      deep/er/body.svg (replaced): exact") and wrote[1] == "wrote      body.json (replaced)"
    assert main(["wall", "body.json", "-o", "walls/b.csv", "-o", "figs/b.pdf"]) == 0
    assert capsys.readouterr().out.splitlines()[-2:] == ["wrote      walls/b.csv", "wrote      figs/b.pdf"]
    assert (tmp_path / "figs" / "b.pdf").read_bytes()[:5] == b"%PDF-"
    assert main(["wall", "body.json", "-o", "walls/b.csv"]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "wrote      walls/b.csv (replaced)"
    assert main(["export", "body.json", "-o", "drawings/mm/b.dxf", "--kappa", "5", "--units", "mm"]) == 0
    assert (tmp_path / "drawings" / "mm" / "b.dxf").is_file()


def test_bad_output_creates_no_folder(tmp_path, capsys, monkeypatch):
    """Every output name is checked before any folder is made: one bad name, nothing created."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken.svg").mkdir()
    assert main(["solve", "1", "-o", "new/body.json", "-o", "taken.svg"]) == 2
    assert "output 'taken.svg' is a folder" in capsys.readouterr().err
    assert main(["solve", "1", "-o", "new/body.json", "-o", "new/body.xyz"]) == 2
    assert main(["wall", "--polar", "1", "-o", "new/w.csv", "-o", "new/w.gif"]) == 2
    assert sorted(os.listdir(tmp_path)) == ["taken.svg"]


def test_check_paths_and_write_all(tmp_path):
    from coinwall.forward.errors import OutputError
    from coinwall.forward.formats.output import check_folder, check_paths, existing_files, write_all

    a, b = str(tmp_path / "x" / "y" / "a.json"), str(tmp_path / "b.json")
    (tmp_path / "file").write_text("")
    with pytest.raises(OutputError, match="is not a folder"):
        check_paths([a, str(tmp_path / "file" / "c.json")], (".json",))
    with pytest.raises(OutputError, match="is a folder"):
        check_paths([str(tmp_path)], (".json", ""))
    assert check_paths([a, b], (".json",)) is None and not (tmp_path / "x").exists()  # the folders come with files
    written = write_all({a: b"1", b: b"2"})
    assert written == [a, b] and isinstance(written, list) and written.replaced == ()
    written = write_all({a: b"3", str(tmp_path / "c.json"): b"4"})
    assert written.replaced == (a,) and existing_files([a, str(tmp_path / "d.json")]) == (a,)
    assert check_folder(str(tmp_path / "p" / "q")) == str(tmp_path / "p" / "q") and not (tmp_path / "p").exists()
    with pytest.raises(OutputError, match="not a folder"):
        check_folder(str(tmp_path / "file" / "q"))


def test_verify_out_creates_the_folder(tmp_path, capsys, monkeypatch):
    """`coinwall verify --out docs` from a folder where docs/ does not exist (outside the repository): the page
    and its PNG figures.  The claims' checks are the paper tests' (tests/cases/test_paper_check.py, which runs
    them once): here each row is its recorded verdict, so that this test pays for the files only."""
    from coinwall.cases.paper import REGISTRY, verify
    from coinwall.cases.paper.report import Row

    rows = tuple(Row(c.key, c.claim, c.source, c.paper, "-", c.expected, c.expected, "") for c in REGISTRY.values())
    monkeypatch.setattr(verify, "evaluate", lambda claims, resolution, progress=False: rows)
    monkeypatch.chdir(tmp_path)
    assert main(["verify", "--fast", "--out", "docs"]) == 0
    text = (tmp_path / "docs" / "paper-check.md").read_text()
    assert "| # | claim |" in text and "fig4_critical.png" in text
    for name in ("fig4_critical.png", "appendix_gallery.png"):
        assert (tmp_path / "docs" / "figures" / name).stat().st_size > 10000
    assert "every verdict as recorded" in capsys.readouterr().out


# --------------------------------------------------------------------------- numbers as a reader sees them

def test_numbers_at_their_tolerance_print_as_zero(capsys):
    """critical's minimiser finds θ = 0 only to ~1e-8 rad, the stick's area is -5.6e-45: they read 0."""
    from coinwall import Wall, critical_offset

    assert main(["critical", "1+0.1*cos(2*t)"]) == 0
    out = capsys.readouterr().out
    assert "angles     0, 3.14159 (rad, where b + b'' is smallest; every minimiser within ±" in out
    assert main(["critical", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=1"]) == 0
    assert "angles     0, 3.14159 (rad, where b + b'' is smallest; every minimiser within ±" in capsys.readouterr().out
    assert main(["critical", "cos(t)"]) == 0
    assert "b_c        0 (certified to ±" in capsys.readouterr().out  # -0 from the library
    assert main(["solve", "abs(cos(t))", "--no-cross-check"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert "critical   b_c = 0 at θ = 0, 3.14159" in out
    assert "body       2 nodes, area 0, perimeter 4, R from 0 to 1 (units of κ, along the whole outline)" in out
    corners = [line for line in out if line.startswith("corner")]
    assert corners[1] == "corner     at direction 0 rad, distance 1, window ±1.5708 rad, largest wall deficit 0"
    assert not any("-0 " in line or "-0," in line for line in out)
    # JSON keeps the full precision of the library's result
    assert main(["critical", "1+0.1*cos(2*t)", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["angles"] == list(critical_offset(Wall.from_expression("1+0.1*cos(2*t)")).angles)


def test_solve_summary_lines(capsys):
    """The text summary keeps its status lines, in order."""
    assert main(["solve", ELLIPSE, "--param", "eps=1", "--b0", "-0.6"]) == 0
    heads = [line[:11].strip() for line in capsys.readouterr().out.splitlines()]
    assert heads == ["wall", "offset", "critical", "regime", "body", "corner", "corner", "check", "outline",
                     "physical"]


def test_an_unknown_wall_file_extension_is_named(tmp_path, capsys, monkeypatch):
    """`coinwall solve wall.txt` names the extension (it said "attribute access '.txt' is not allowed"),
    whether or not the file exists; `t.real` is still an expression and gets the parser's message."""
    monkeypatch.chdir(tmp_path)
    for exists in (False, True):
        if exists:
            (tmp_path / "wall.txt").write_text("0,1\n")
        assert main(["solve", "wall.txt"]) == 2
        err = capsys.readouterr().err
        assert "extension '.txt'" in err and ".csv or .json" in err and len(err.strip().splitlines()) == 1
    assert main(["critical", "t.real"]) == 2
    assert "attribute access" in capsys.readouterr().err


@pytest.mark.parametrize("command", [["simulate", "case:coin", "--H", "3"], ["section", "case:coin", "--H", "3"],
                                     ["correlation", "case:coin", "--H", "3"], ["toss", "case:coin"],
                                     ["quantum", "1", "--H", "3", "--levels", "2"]])
@pytest.mark.parametrize("option", ["--sigma-b", "--sigma-theta"])
def test_options_only_where_they_act(command, option, capsys):
    """The dynamics and the quantum body read a sample file's values, not their half-widths: the options that
    set them are not offered there (they used to be accepted and change nothing)."""
    with pytest.raises(SystemExit) as exc:
        main([*command, option, "0.1"])
    assert exc.value.code == 2 and f"unrecognized arguments: {option}" in capsys.readouterr().err


@pytest.mark.parametrize("args", [["simulate", "case:coin", "--H", "3", "--collisions", "10", "--seed", "-1"],
                                  ["section", "case:coin", "--H", "3", "--orbits", "0"],
                                  ["correlation", "case:coin", "--H", "3", "--bounces", "-1"],
                                  ["kam", "--H", "3", "--bracket", "1,2,3"],
                                  ["fit", "missing.csv", "--sigma-b", "-1"]])
def test_the_library_checks_and_the_command_line_names_the_flag(args, capsys, tmp_path, monkeypatch):
    """The rules of counts, seeds and ranges are the library's; its message reaches the user with the flag's name."""
    monkeypatch.chdir(tmp_path)
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    np.savetxt("missing.csv", np.column_stack([theta, 1 + 0.05 * np.cos(2 * theta)]), delimiter=",",
               header="theta,b", comments="")
    assert main(args) == 2
    err = capsys.readouterr().err
    flag = args[-2]
    assert err.count("\n") == 1 and err.startswith(f"coinwall: error: {flag}") and "`" not in err, err
