"""The README's shell blocks paste and run, in order, on a fresh clone, and leave its tree clean.

* In the default run: every ``coinwall …`` line of the README parses with the real parser (a placeholder such as
  ``[--json]`` or an option that does not exist is a usage error), and the set-up lines are the two a newcomer
  needs.
* ``python -m pytest -m slow tests/test_readme.py`` (several minutes on two shared cores): the repository is
  copied into a temporary folder (every file ``git ls-files --cached --others --exclude-standard`` lists, i.e. the
  working tree as a fresh clone of it would be, uncommitted edits included) and committed there; the README's shell
  blocks (fences without a language) run there in order in one ``bash``, each line checked for exit status 0;
  afterwards ``git status --porcelain`` must print nothing (the commands write into the git-ignored ``scratch/``).

Set-up steps are skipped where they are already done: in a line, the ``&&``-joined steps ``python3 -m venv .venv``,
``. .venv/bin/activate`` and ``pip install -e ".[EXTRAS]"`` are dropped when the ``coinwall`` distribution is
installed in the interpreter running the tests and every requirement of those extras is installed too
(:func:`_installed`, read from the distribution's metadata); otherwise the test is skipped, saying which
requirement is missing.  The commands then run the installed ``coinwall`` (an editable install of the repository
these tests belong to, the same source as the copy).  The test-suite step ``python -m pytest …`` is the one step
that is not run: it would run this test inside itself (``.ci/run`` runs it, word for word).
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from coinwall.cases.cli.parser import build_parser

ROOT = Path(__file__).resolve().parents[1]
#: a shell block: a fence without a language (``python`` blocks are run by tests/test_docs.py)
_SHELL = re.compile(r"^```(?:console|bash|sh|shell)?\n(.*?)^```\s*$", re.S | re.M)
_VENV = re.compile(r"python3? -m venv \S+")
_ACTIVATE = re.compile(r"(\.|source) \S+/bin/activate")
_PIP = re.compile(r"(python3? -m )?pip install (-e )?(\S+)")
_PYTEST = re.compile(r"python3? -m pytest\b.*")


def shell_lines(text: str) -> list[str]:
    """The command lines of the shell blocks of a Markdown text, in order (a comment after two spaces removed)."""
    lines = []
    for block in _SHELL.findall(text):
        for raw in block.splitlines():
            line = raw[2:] if raw.startswith("$ ") else raw
            line = line.split("  #", 1)[0].strip()
            if line and not line.startswith("#"):
                lines.append(line)
    return lines


LINES = shell_lines((ROOT / "README.md").read_text(encoding="utf-8"))
COMMANDS = [shlex.split(step)[1:] for line in LINES for step in line.split(" && ") if step.startswith("coinwall ")]


def _installed(spec: str) -> str | None:
    """None when ``pip install -e SPEC`` (``.`` or ``".[test]"``) is already satisfied here, else what is missing."""
    import importlib.metadata as metadata

    from packaging.requirements import Requirement

    extras = re.findall(r"[\w-]+", spec.partition("[")[2])
    try:
        requirements = metadata.distribution("coinwall").requires or []
    except metadata.PackageNotFoundError:
        return "coinwall"
    for text in requirements:
        requirement = Requirement(text)
        marker = requirement.marker
        if marker is not None and not any(marker.evaluate({"extra": extra}) for extra in extras or [""]):
            continue
        try:
            metadata.version(requirement.name)
        except metadata.PackageNotFoundError:
            return requirement.name
    return None


def runnable_steps(line: str) -> tuple[list[str], str | None]:
    """The steps of a README line to run here: set-up steps already done are dropped, so is the test suite.
    Returns (steps, what is missing for a set-up step, or None)."""
    steps = []
    for step in line.split(" && "):
        step = step.strip()
        pip = _PIP.fullmatch(step)
        if pip:
            missing = _installed(pip.group(3).strip("'\""))
            if missing:
                return [], missing
            continue
        if _VENV.fullmatch(step) or _ACTIVATE.fullmatch(step) or _PYTEST.fullmatch(step):
            continue
        steps.append(step)
    return steps, None


def test_the_blocks_are_found():
    assert len(COMMANDS) >= 20
    assert any(line.startswith("python3 -m venv") and "pip install -e ." in line for line in LINES)


@pytest.mark.parametrize("argv", COMMANDS, ids=[" ".join(a)[:60] for a in COMMANDS])
def test_each_command_line_parses(argv):
    """Every subcommand and flag the README shows exists (argparse exits 2 on anything unknown, a placeholder such
    as ``[--json]`` included)."""
    build_parser().parse_args(argv)


def test_setup_lines():
    """Two set-up lines, the second the test command .ci/run runs word for word; the installs are detected."""
    setup = [line for line in LINES if line.startswith("python3 -m venv")]
    assert len(setup) == 2
    assert setup[1].endswith('pip install -e ".[test]" && python -m pytest -q -n auto')
    assert 'pip install -e ".[test]" && python -m pytest -q -n auto' in (ROOT / ".ci" / "run").read_text()
    assert runnable_steps(setup[1]) == ([], None)  # the test run here has the test extra
    assert runnable_steps(setup[0])[0] == ["coinwall solve -o scratch/body.svg -o scratch/body.png"]


def _copy_of_the_repository(target: Path) -> None:
    """The working tree as a fresh clone would hold it, committed in a repository of its own."""
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                            check=True, capture_output=True).stdout.decode().split("\0")
    for name in filter(None, listed):
        source = ROOT / name
        if source.is_file():  # a file deleted but not yet committed is not in a clone
            (target / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target / name)
    git = ["git", "-c", "user.name=readme-test", "-c", "user.email=readme@test", "-c", "init.defaultBranch=main"]
    for args in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "the working tree"]):
        subprocess.run(git + args, cwd=target, check=True, capture_output=True)


@pytest.mark.slow
def test_the_blocks_run_on_a_fresh_clone(tmp_path):
    clone = tmp_path / "coinwall"
    clone.mkdir()
    _copy_of_the_repository(clone)
    script = ["set -u"]
    for number, line in enumerate(LINES, start=1):
        steps, missing = runnable_steps(line)
        if missing:
            pytest.skip(f"README line {number} installs {missing}, which is not installed here")
        for step in steps:
            script += [step, f"status=$?; if [ $status -ne 0 ]; then echo {shlex.quote(f'README line {number}: {step}')}"
                             ' "exited with status $status" >&2; exit 1; fi']
    env = dict(os.environ, PATH=os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", ""))
    log = tmp_path / "output.txt"
    with open(log, "w") as out:
        done = subprocess.run(["bash", "-c", "\n".join(script)], cwd=clone, env=env, stdout=out,
                              stderr=subprocess.STDOUT, timeout=3600)
    assert done.returncode == 0, log.read_text()[-3000:]
    status = subprocess.run(["git", "status", "--porcelain", "--untracked-files=all"], cwd=clone, check=True,
                            capture_output=True, text=True).stdout
    assert status == "", f"the README's commands left the tree changed:\n{status}"
    assert (clone / "scratch" / "body.png").is_file() and (clone / "scratch" / "report" / "paper-check.md").is_file()
