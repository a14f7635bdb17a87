"""The README's command lines paste: every `coinwall …` line of its command-line block is a valid command
(the default run parses each with the real parser); ``python -m pytest -m slow tests/test_readme.py`` runs
them all, in order, in a scratch folder with the input files they name."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from coinwall.cases.cli.main import main
from coinwall.cases.cli.parser import build_parser

ROOT = Path(__file__).resolve().parents[1]


def _commands():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = re.search(r"## The command line\n\n```\n(.*?)```", text, re.S).group(1)
    commands = []
    for line in block.splitlines():
        line = line.split("  #", 1)[0].strip()  # a comment after two spaces
        line = re.sub(r"\s*\[[^\]]*\]", "", line)  # [--json]: an optional flag shown as such
        if line.startswith("coinwall"):
            commands.append(shlex.split(line)[1:])
    return commands


COMMANDS = _commands()


def test_the_block_is_found():
    assert len(COMMANDS) >= 15


@pytest.mark.parametrize("argv", COMMANDS, ids=[" ".join(a)[:60] for a in COMMANDS])
def test_each_command_line_parses(argv):
    """Every subcommand and flag the README shows exists (argparse exits 2 on anything unknown)."""
    build_parser().parse_args(argv)


@pytest.mark.slow
def test_the_command_lines_run(tmp_path, monkeypatch, capsys):
    """Each line runs with exit 0 in order (the files it names made by the lines before it, or here: a sampled
    wall, a drawing); `verify --out report` writes into the scratch folder."""
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    import walldata as W

    monkeypatch.chdir(tmp_path)
    (tmp_path / "scan.csv").write_text(W.write_rounded(W.polygon(None, 360), 6, theta_digits=6).text)
    (tmp_path / "drawing.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
                                          '<polygon points="10,10 60,20 25,55"/></svg>')
    for argv in COMMANDS:
        code = main(argv)
        captured = capsys.readouterr()
        assert code == 0, f"coinwall {shlex.join(argv)}: exit {code}\n{captured.err}"
