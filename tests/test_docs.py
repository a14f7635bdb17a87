"""Every example in the documentation runs.

* ```python blocks are executed with ``exec``.  The blocks of one file run **in order in one
  shared namespace** (the pages are written as a continuous session), in a temporary working
  folder (``monkeypatch.chdir``) that the blocks of that file share, so files written by one
  block can be read by a later one.
* ```console blocks: every line starting with ``$ coinwall`` is split with :mod:`shlex` and run
  through ``cases.cli.main(argv)``.  The lines after a command (up to the next ``$`` line) are
  its documented output: each must appear, in order, in the actual stdout + stderr; a line
  ``...`` stands for any number of lines, and a line ending in ``...`` matches any line that
  starts with the text before it.  The expected exit status is 0 unless the output
  contains a line ``[exit status N]``.
* Blocks in other languages (```text, plain ``` …) are not run.

One block is run by another test instead, which checks its documented output the same way and needs the same
run (:data:`ELSEWHERE`: the ``coinwall verify --fast`` example, run once by ``tests/cases/test_paper_check.py``,
whose checks read the report it writes); here it is skipped, naming that test.

Each block is its own test (``docs/api.md#3-python-line120``), so a failure names the block.
When a block is run on its own, the blocks before it in its file are replayed first; in a full
run each block runs once, continuing the session of the block before it.
"""

from __future__ import annotations

import linecache
import re
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ("README.md", "docs/api.md", "docs/cli.md", "docs/cli-limits.md", "docs/theory.md", "docs/quantum.md", "docs/explore.md",
        "docs/scan.md", "docs/design.md")
_FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```\s*$", re.S | re.M)
_STATUS = re.compile(r"^\[exit status (\d+)\]$")
#: (doc file, subcommand) of console blocks that another test runs, with the test that runs them
ELSEWHERE = {("docs/cli.md", "verify"):
             "tests/cases/test_paper_check.py::test_the_documented_command_prints_what_the_documentation_shows"}


def _blocks(relpath):
    """Runnable fenced blocks of a doc file: list of (language, text, line number)."""
    path = ROOT / relpath
    if not path.exists():
        return []
    text = path.read_text(encoding="utf-8")
    found = []
    for match in _FENCE.finditer(text):
        lang = match.group(1).lower()
        if lang in ("python", "console"):
            found.append((lang, match.group(2), text.count("\n", 0, match.start()) + 1))
    return found


def _cases():
    for relpath in DOCS:
        for index, (lang, _, line) in enumerate(_blocks(relpath)):
            yield pytest.param(relpath, index, id=f"{relpath}#{index}-{lang}-line{line}")


def _console_commands(text):
    """(argv, expected output lines, expected status) for each ``$ coinwall`` line of a console block."""
    commands = []
    for raw in text.splitlines():
        line = raw.rstrip()
        if line.startswith("$ "):
            words = shlex.split(line[2:])
            assert words and words[0] == "coinwall", f"console line does not run coinwall: {line!r}"
            commands.append([words[1:], [], 0])
        elif commands and line:
            status = _STATUS.match(line.strip())
            if status:
                commands[-1][2] = int(status.group(1))
            else:
                commands[-1][1].append(line)
    return commands


def _elsewhere(relpath, lang, text):
    """The test that runs this block instead (:data:`ELSEWHERE`), or None."""
    if lang != "console":
        return None
    commands = _console_commands(text)
    return ELSEWHERE.get((relpath, commands[0][0][0])) if len(commands) == 1 and commands[0][0] else None


def _match_output(expected, actual_text):
    """Each expected line appears in the actual output, in order; ``...`` skips any number of lines."""
    actual = [line.rstrip() for line in actual_text.splitlines()]
    position = 0
    gap_allowed = False
    for want in expected:
        if want.strip() == "...":
            gap_allowed = True
            continue

        def same(line, want=want):
            return line.startswith(want[:-3]) if want.endswith("...") else line == want

        if gap_allowed:
            hits = [i for i in range(position, len(actual)) if same(actual[i])]
            if not hits:
                return f"line not found after line {position}: {want!r}"
            position = hits[0] + 1
        else:
            if position >= len(actual) or not same(actual[position]):
                got = actual[position] if position < len(actual) else "<end of output>"
                return f"expected {want!r}, got {got!r}"
            position += 1
        gap_allowed = False
    return None


def _run_block(lang, text, namespace, capsys, name="<doc block>"):
    if lang == "python":
        # registered with linecache so that a failing line shows up in the traceback
        linecache.cache[name] = (len(text), None, text.splitlines(True), name)
        exec(compile(text, name, "exec"), namespace)
        return
    from coinwall.cases.cli.main import main

    for argv, expected, status in _console_commands(text):
        capsys.readouterr()
        try:
            code = main(argv)
        except SystemExit as exit_:  # argparse: --help, or a usage error
            code = exit_.code if isinstance(exit_.code, int) else (0 if exit_.code is None else 1)
        captured = capsys.readouterr()
        assert code == status, f"coinwall {shlex.join(argv)}: exit status {code}, documented {status}\n" \
                               f"stdout: {captured.out}\nstderr: {captured.err}"
        problem = _match_output(expected, captured.out + captured.err)
        assert problem is None, f"coinwall {shlex.join(argv)}: {problem}\nactual output:\n{captured.out}{captured.err}"


# per doc file: (working folder, namespace, index of the last block run there)
_STATE: dict[str, tuple[Path, dict, int]] = {}


@pytest.mark.parametrize("relpath,index", list(_cases()))
def test_doc_example(relpath, index, tmp_path_factory, monkeypatch, capsys):
    import matplotlib

    matplotlib.use("Agg")  # examples that draw must not need a display
    blocks = _blocks(relpath)
    state = _STATE.get(relpath)
    if state is None or state[2] != index - 1:
        # a fresh session: replay the blocks before this one
        folder = tmp_path_factory.mktemp(Path(relpath).stem)
        namespace = {"__name__": f"doc:{relpath}"}
        monkeypatch.chdir(folder)
        for k, (lang, text, line) in enumerate(blocks[:index]):
            if not _elsewhere(relpath, lang, text):
                _run_block(lang, text, namespace, capsys, f"<{relpath} block {k}, line {line}>")
    else:
        folder, namespace, _ = state
        monkeypatch.chdir(folder)
    lang, text, line = blocks[index]
    runner = _elsewhere(relpath, lang, text)
    if runner:
        _STATE[relpath] = (folder, namespace, index)
        pytest.skip(f"run, and its output checked, by {runner}")
    try:
        _run_block(lang, text, namespace, capsys, f"<{relpath} block {index}, line {line}>")
    finally:
        # even after a failure the next block continues this session, so one broken example
        # fails one test, not every later one
        _STATE[relpath] = (folder, namespace, index)


def test_docs_have_examples():
    """The parametrisation above is not silently empty: the API and CLI pages carry examples."""
    assert len(_blocks("docs/api.md")) >= 8
    assert sum(lang == "console" for lang, _, _ in _blocks("docs/cli.md")) >= 3


def test_console_parser():
    """The console-block reader itself: commands, output lines, status markers, '...' gaps."""
    commands = _console_commands("$ coinwall solve --b0 '-0.5'\nline one\n...\n[exit status 2]\n$ coinwall critical x\n")
    assert commands == [[["solve", "--b0", "-0.5"], ["line one", "..."], 2], [["critical", "x"], [], 0]]
    assert _match_output(["a", "...", "d"], "a\nb\nc\nd\n") is None
    assert _match_output(["a", "c"], "a\nb\nc\n") is not None
    assert _match_output(["b"], "a\nb\n") is not None
    assert _match_output(["a = ...", "b"], "a = 1.5e-11 (x)\nb\n") is None
    assert _match_output(["a = 2..."], "a = 1.5e-11\n") is not None


def test_blocks_run_elsewhere_exist_and_so_do_the_tests_that_run_them():
    for (relpath, command), runner in ELSEWHERE.items():
        assert sum(_elsewhere(relpath, lang, text) == runner for lang, text, _ in _blocks(relpath)) == 1, command
        path, name = runner.split("::")
        assert f"def {name}(" in (ROOT / path).read_text(encoding="utf-8"), runner


_LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


@pytest.mark.parametrize("relpath", DOCS)
def test_relative_links_resolve(relpath):
    """Links from the docs to source files and other pages point at files that exist.

    Figures under docs/figures/ are generated separately (the paper-check figures); a missing
    one is reported as a skip, not hidden.
    """
    path = ROOT / relpath
    if not path.exists():
        pytest.skip(f"{relpath} not written")
    missing, pending = [], []
    for target in _LINK.findall(path.read_text(encoding="utf-8")):
        if "://" in target:
            continue
        resolved = (path.parent / target).resolve()
        if resolved.exists():
            continue
        (pending if "figures" in Path(target).parts else missing).append(target)
    assert not missing, f"{relpath}: broken links {missing}"
    if pending:
        pytest.skip(f"{relpath}: figures not generated yet: {pending}")
