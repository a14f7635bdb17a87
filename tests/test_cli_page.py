"""docs/cli.md covers every command of ``coinwall --help``: one section each, with a synopsis whose options exist and
an example that runs (tests/test_docs.py runs every ``$ coinwall`` line of the page, in order, in a temporary
folder, and checks its exit status and output); the internals are on the developer page docs/cli-limits.md."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from coinwall.cases.cli.parser import build_parser

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
PARSER = build_parser()
_SECTION = re.compile(r"^## `coinwall (\w+)`\n(.*?)(?=^## |\Z)", re.S | re.M)
SECTIONS = dict(_SECTION.findall(PAGE))


def _blocks(text, language):
    return re.findall(rf"^```{language}\n(.*?)^```", text, re.S | re.M)


def test_the_sections_are_those_of_help():
    """One section per command, in the order of ``coinwall --help``."""
    assert list(SECTIONS) == list(PARSER.commands)


@pytest.mark.parametrize("name", list(PARSER.commands))
def test_each_command_has_purpose_synopsis_and_example(name):
    section = SECTIONS.get(name)
    assert section is not None, f"docs/cli.md has no section for `coinwall {name}`"
    purpose = section.strip().split("\n\n")[0]
    assert purpose and not purpose.startswith("```"), f"{name}: no one-line purpose before the synopsis"
    synopses = [block for block in _blocks(section, "text") if block.startswith(f"coinwall {name}")]
    assert synopses, f"{name}: no synopsis (a text block starting with `coinwall {name}`)"
    known = set(PARSER.commands[name]._option_string_actions)
    shown = set(re.findall(r"(?<![\w-])(--?[a-zA-Z][\w-]*)", "".join(synopses)))
    assert shown - known == set(), f"{name}: the synopsis shows options the command does not have"
    examples = [line for block in _blocks(section, "console") for line in block.splitlines()
                if line.startswith(f"$ coinwall {name}")]
    assert examples, f"{name}: no example (a console block with `$ coinwall {name} …`)"


def test_the_internals_are_on_the_developer_page():
    """Fuzz tables, temporary-file names and the kernel cache's rules are for contributors (docs/cli-limits.md)."""
    for internal in ("Fuzz tests", ".coinwall-XXXXXXXX.tmp", "kernels-numba", "handled cleanly"):
        assert internal not in PAGE
        assert internal in (ROOT / "docs" / "cli-limits.md").read_text(encoding="utf-8")
