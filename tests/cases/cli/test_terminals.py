"""Terminals that cannot show every character: ``LANG=C`` (no UTF-8 mode), ``PYTHONIOENCODING=ascii``, latin-1.

Every subcommand runs in a worker process started under the terminal's settings (``tests/cli_fuzz.py``: the
arguments reach it as bytes, as from a shell), so the streams, the file-system encoding and the file names are
what such a user has.  The contract: the command ends as it would on a UTF-8 terminal (exit status 0, no
"internal error"), what it prints is in the terminal's encoding, and a file name with non-ASCII characters is
written under its own name and shown unambiguously.
"""

from __future__ import annotations

import io
import os

import pytest
from cli_fuzz import BASE_COMMANDS, Worker, make_folder, valid_files
from cli_fuzz_classes import ENCODINGS as TERMINALS
#: every subcommand: the fuzz's valid base commands (scan in this process: no cluster to start) and the rest
COMMANDS = [[name] + (argv if name != "scan" else [a for a in argv if a not in ("--workers", "1")]
                      + ["--scheduler", "synchronous"]) for name, argv in sorted(BASE_COMMANDS.items())] + [
    ["coin3d", "bounce", "--samples", "200", "--bounces", "2", "--seed", "1"], ["coin3d", "fit"], ["cases"],
    ["kam", "--help"], ["verify", "--help"], ["explore", "--help"], ["--help"],
    ["wall", "--polar", "1+0.1*cos(3*t)", "-o", "w\u00e4nde.csv"],
    ["solve", "1+0.1*cos(2*t)", "--points", "256", "-o", "k\u00f6rper \u03b8.svg", "--json"],
]


def _run_all(terminal, tmp_path, commands):
    worker = Worker(timeout=120, env=TERMINALS[terminal])
    try:
        base = tmp_path / "base"
        base.mkdir()
        valid_files(base, worker)
        failures = []
        for argv in commands:
            folder = make_folder(base, tmp_path)
            result = worker.run(argv, folder)
            text = result["stdout"] + result["stderr"]
            if result["rc"] != 0 or "internal error" in text:
                failures.append(f"{terminal}: coinwall {' '.join(argv)}: exit {result['rc']}: {text[-400:]!r}")
            elif terminal != "latin-1" and any(ord(c) > 127 for c in text):
                failures.append(f"{terminal}: coinwall {' '.join(argv)} printed non-ASCII: {text[-200:]!r}")
            for name in argv:  # a file name with non-ASCII characters is written under that very name
                if name.endswith((".csv", ".svg")) and any(ord(c) > 127 for c in name):
                    assert os.path.getsize(os.path.join(folder, name)) > 0
                    # shown as escapes: \xe4, or the bytes \xc3\xa4 where the locale could not decode them
                    shown = {name.encode("ascii", "backslashreplace").decode(),
                             name.encode().decode("ascii", "backslashreplace")}
                    if terminal != "latin-1" and "--json" not in argv:
                        assert any(f"wrote      {s}" in text for s in shown), text
        assert not failures, "\n".join(failures)
    finally:
        worker.close()


def test_every_command_on_an_ascii_terminal(tmp_path):
    """PYTHONIOENCODING=ascii: every subcommand, and files named with ä, ö and θ."""
    _run_all("ascii", tmp_path, COMMANDS)


@pytest.mark.parametrize("terminal", ["C", pytest.param("latin-1", marks=pytest.mark.slow)])
def test_file_names_and_symbols_on_c_and_latin1_terminals(tmp_path, terminal):
    """LANG=C (the file-system encoding is ASCII too: the name reaches coinwall as undecodable bytes) and latin-1
    (in the slow run, with every command on every terminal)."""
    quick = [argv for argv in COMMANDS if argv[0] in ("solve", "wall", "coin3d", "toss", "critical")]
    _run_all(terminal, tmp_path, quick)


@pytest.mark.slow
@pytest.mark.parametrize("terminal", sorted(TERMINALS))
def test_every_command_on_every_terminal(tmp_path, terminal):
    _run_all(terminal, tmp_path, COMMANDS)


def test_the_ascii_names():
    """The handler's table: symbols by name, other characters as escapes, undecoded bytes as their value."""
    from coinwall.cases.cli.main import ascii_fallback, restore_streams

    raw = io.BytesIO()
    stream = io.TextIOWrapper(raw, encoding="ascii", errors="strict")
    changed = ascii_fallback([stream])
    stream.write("θ₀ = 0.5 ± 0.1, κ ≥ 1, ε → 0, 2×10⁻³ m², x\u00e4 \udcc3\udca4")
    stream.flush()
    assert raw.getvalue().decode("ascii") == "theta0 = 0.5 +/- 0.1, kappa >= 1, eps -> 0, 2x10^-^3 m^2, x\\xe4 \\xc3\\xa4"
    restore_streams(changed)
    assert stream.errors == "strict"
    latin = io.TextIOWrapper(io.BytesIO(), encoding="latin-1")
    ascii_fallback([latin])
    latin.write("± θ")  # latin-1 has ±: written as it is
    latin.flush()
    assert latin.buffer.getvalue() == "± theta".encode("latin-1")


def test_doctests():
    import doctest
    import importlib

    assert doctest.testmod(importlib.import_module("coinwall.cases.cli.main")).failed == 0
