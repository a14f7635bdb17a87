"""One convention across the commands (docs/cli.md, "Conventions"), one test per rule:

* seeds: every command that draws at random takes ``--seed N`` with the same default (0), so that a command run
  twice without it prints the same numbers, and prints the seed it used, in its text and in its JSON (``"seed"``);
* parameters: every command that reads a WALL gives ``"wall"`` (as written) and ``"params"`` in its JSON, with one
  shape, ``{name: value}`` (the case's own for ``case:NAME``);
* units: the commands with a field (``toss``, ``coin3d bounce``) state the units of their numbers in one shape
  (``"units": {"length", "field"}``).

The runs are small (a second or two each, the kernels' compile aside)."""

from __future__ import annotations

import json

import pytest

from coinwall.cases.cli.common import DEFAULT_SEED
from coinwall.cases.cli.main import main
from coinwall.cases.cli.parser import build_parser

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"

#: the commands that draw at random, each with a small run (argv without --seed and --json)
RANDOM = {
    "simulate": ["simulate", ELLIPSE, "--param", "eps=0.5", "--H", "3", "--collisions", "2000"],
    "simulate --orbits": ["simulate", ELLIPSE, "--param", "eps=0.5", "--H", "3", "--collisions", "500",
                          "--orbits", "4"],
    "section": ["section", ELLIPSE, "--param", "eps=0.5", "--H", "3", "--orbits", "3", "--collisions", "200"],
    "correlation": ["correlation", ELLIPSE, "--param", "eps=0.5", "--H", "3", "--bounces", "20000", "--max-lag", "5",
                    "--orbits", "4"],
    "toss --spread": ["toss", ELLIPSE, "--param", "eps=99", "--spread", "2,5,0.05,0.2", "--samples", "200"],
    "toss --uncertainty": ["toss", ELLIPSE, "--param", "eps=99", "--v0", "0:3", "--omega", "0:8", "--uncertainty",
                           "1e-3:1e-2:2", "--samples", "300"],
    "coin3d caught": ["coin3d", "caught", "--psi", "70", "--samples", "1000"],
    "coin3d bounce": ["coin3d", "bounce", "--samples", "100", "--bounces", "2"],
    "kam": ["kam", "--H", "3", "--steps", "1", "--orbits", "2", "--collisions", "200"],
    "design": ["design", "abs(cos(t)) + h*abs(sin(t))", "--param", "h=1", "--model", "bounce", "--tolerance", "0.05"],
}
#: what varies from run to run by nature (timings), left out of the comparison
TIMINGS = ("seconds", "collisions_per_second", "compile_seconds", "estimated_seconds")


def _run(argv, capsys):
    capsys.readouterr()
    code = main(argv)
    out = capsys.readouterr().out
    assert code == 0, f"coinwall {' '.join(argv)}: exit {code}\n{out}"
    return out


def _json(argv, capsys):
    doc = json.loads(_run(argv + ["--json"], capsys))
    for key in TIMINGS:
        doc.pop(key, None)
    return doc


def test_one_seed_flag():
    """The same flag, type and default wherever a command draws at random (design resolves its model-specific
    flags' None to their defaults: 0)."""
    from coinwall.cases.cli import design

    parser = build_parser()
    commands = {argv[0] for argv in RANDOM.values()} | {"scan"}
    for name in sorted(commands):
        action = next(a for a in parser.commands[name]._actions if "--seed" in a.option_strings)
        default = design._FLAGS["seed"][0] if name == "design" else action.default
        assert default == DEFAULT_SEED == 0, name
        assert action.type(" 7 ") == 7, name
    others = set(parser.commands) - commands
    for name in others:  # a command that draws nothing takes no seed
        assert not any("--seed" in a.option_strings for a in parser.commands[name]._actions), name


@pytest.mark.parametrize("name", RANDOM)
def test_runs_repeat_and_print_their_seed(name, tmp_path, monkeypatch, capsys):
    """Twice without --seed: the same JSON (timings aside), with "seed": 0; --seed 0 is the same run; the text
    output prints the seed."""
    monkeypatch.chdir(tmp_path)
    argv = RANDOM[name]
    first, second = _json(argv, capsys), _json(argv, capsys)
    assert first == second
    assert first["seed"] == DEFAULT_SEED
    assert _json(argv + ["--seed", "0"], capsys) == first
    assert f"seed {DEFAULT_SEED}" in _run(argv, capsys).replace("seed       ", "seed ")


def test_another_seed_draws_again(capsys):
    """The seed is used: another one gives other draws (and says so)."""
    argv = RANDOM["coin3d caught"]
    other = _json(argv + ["--seed", "5"], capsys)
    assert other["seed"] == 5 and other["same_side"] != _json(argv, capsys)["same_side"]


#: the commands that read a WALL, with the wall given as ELLIPSE --param eps=VALUE (99, a coin, for the toss)
WALLS = {
    "solve": ["solve", ELLIPSE, "--param", "eps=0.5", "--points", "128", "--no-cross-check"],
    "critical": ["critical", ELLIPSE, "--param", "eps=0.5"],
    "quantum": ["quantum", ELLIPSE, "--param", "eps=0.5", "--H", "3", "--levels", "2"],
    **{name: argv for name, argv in RANDOM.items()
       if argv[0] in ("simulate", "section", "correlation", "toss")},
    "toss": ["toss", ELLIPSE, "--param", "eps=99", "--v0", "0:3:4", "--omega", "0:8:4"],
}


@pytest.mark.parametrize("name", WALLS)
def test_params_have_one_shape(name, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    doc = _json(WALLS[name], capsys)
    assert doc["wall"] == ELLIPSE
    value = float(WALLS[name][WALLS[name].index("--param") + 1].split("=")[1])
    assert doc["params"] == {"eps": value}


def test_params_of_a_case(capsys):
    """A case gives its own parameters, as a dict too (section gave the empty list of --param before)."""
    doc = _json(["section", "case:ellipse-0.55", "--H", "1.9", "--orbits", "2", "--collisions", "100"], capsys)
    assert doc["wall"] == "case:ellipse-0.55" and doc["params"] == {"eps": 0.55}


@pytest.mark.parametrize("name", ["toss --spread", "coin3d bounce", "toss"])
def test_units_have_one_shape(name, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    doc = _json(RANDOM.get(name) or WALLS[name], capsys)
    assert set(doc["units"]) == {"length", "field"}
    assert doc["units"]["field"] == doc["units"]["length"] + "/s^2"


class _CountingBar:
    """Stands in for the tqdm bar of :func:`coinwall.cases.cli.common.terminal_bar`: the total and every step
    must be whole numbers (a float shows as ``7.00/45.0``)."""

    made = []

    def __init__(self, total, unit):
        import numbers

        assert total is None or (isinstance(total, numbers.Integral) and not isinstance(total, bool)), total
        self.total, self.unit, self.n, self.steps = total, unit, 0, 0
        _CountingBar.made.append(self)

    def update(self, step=1):
        import numbers

        assert isinstance(step, numbers.Integral) and not isinstance(step, bool), f"{self.unit}: step {step!r}"
        self.n += step
        self.steps += 1

    def set_description(self, text):
        pass

    def close(self):
        assert self.total is None or self.n <= self.total, f"{self.unit}: {self.n} of {self.total}"


#: the long commands, each with a bar (the RANDOM runs above, and the basin map and the spectrum)
BARS = {**{name: argv for name, argv in RANDOM.items() if name not in ("coin3d caught", "simulate")},
        "simulate": RANDOM["simulate"][:-1] + ["400000"],  # one orbit has a bar above 200,000 collisions
        "toss": WALLS["toss"], "quantum": WALLS["quantum"]}


@pytest.mark.parametrize("name", BARS)
def test_progress_bars_count_whole_numbers(name, tmp_path, monkeypatch, capsys):
    """Every command's bar counts whole tosses, orbits, collisions, cells (without a terminal the commands draw
    none, so the bar is replaced by one that checks what it is given; tests/cases/cli/test_progress.py draws
    real ones on a pseudo-terminal)."""
    import importlib

    from coinwall.cases.cli.parser import SUBCOMMANDS

    monkeypatch.chdir(tmp_path)
    _CountingBar.made.clear()
    # progress_bar opens common.terminal_bar; scan opens its own lazily, by the name it imported
    for module in (importlib.import_module("coinwall.cases.cli.common"), *SUBCOMMANDS.values()):
        if hasattr(module, "terminal_bar"):
            monkeypatch.setattr(module, "terminal_bar", lambda args, total, unit: _CountingBar(total, unit))
    _run(BARS[name], capsys)
    assert _CountingBar.made and any(bar.steps for bar in _CountingBar.made), f"{name}: no bar was moved"


def test_kappa_reads_si_and_reports_in_kappa(capsys):
    """`toss --kappa METRES` reads the wall, --b0, --H, --height and the launch speeds in metres (m/s) and --g in
    m/s², like the billiard commands: a body of κ = 0.5 m given in SI tosses as the same body given in units of κ
    (g = 0.5 m/s² is 1 κ/s², v0 up to 1.5 m/s is 3 κ/s, a height of 1.1 m is 2.2 κ)."""
    in_kappa = ["toss", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=99", "--b0", "0.1", "--g", "1",
                "--height", "2.2", "--v0", "0:3:5", "--omega", "0:8:5"]
    in_si = ["toss", "0.5*sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=99", "--b0", "0.05", "--kappa", "0.5",
             "--g", "0.5", "--height", "1.1", "--v0", "0:1.5:5", "--omega", "0:8:5"]
    a, b = _json(in_kappa, capsys), _json(in_si, capsys)
    assert b["units"] == a["units"] == {"length": "kappa", "field": "kappa/s^2"}
    for key in ("g", "height", "fractions", "status", "mean_bounces", "grid"):
        assert b[key] == pytest.approx(a[key], rel=1e-12), key


def test_scan_gives_its_seed_and_params(tmp_path, monkeypatch, capsys):
    """scan (a store, so not run twice here: a second run resumes it) gives the seed and the fixed parameters in
    the same shape as the other commands; scan's own tests check that a rerun gives identical arrays."""
    pytest.importorskip("dask.distributed")
    monkeypatch.chdir(tmp_path)
    argv = ["scan", "chaotic-fraction", "sqrt((1+eps*cos(t)**2)/(1+eps)) + a*cos(3*t)", "--param", "eps=0.5,4",
            "--param", "a=0.01", "--H", "2,3", "--orbits", "4", "--collisions", "200", "--scheduler", "synchronous"]
    doc = _json(argv + ["-o", "one.zarr"], capsys)
    assert doc["seed"] == DEFAULT_SEED and doc["params"] == {"a": 0.01}
    assert f"seed {DEFAULT_SEED}" in _run(argv + ["-o", "two.zarr"], capsys)
