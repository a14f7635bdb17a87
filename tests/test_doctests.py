"""Every Examples section of the package's docstrings runs (scipy and shapely style: short, doctested).

Each module whose source holds a ``>>>`` line is one test; its examples run with :mod:`doctest` (numbers
compared as printed, ``...`` in a traceback standing for its middle lines), in a temporary working folder.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil
from pathlib import Path

import pytest


def _modules():
    names = set()
    for top in ("coinwall", "coinwall.forward", "coinwall.inverse", "coinwall.cases"):  # (mapped folders)
        package = importlib.import_module(top)
        for info in pkgutil.walk_packages(package.__path__, top + "."):
            spec = importlib.util.find_spec(info.name)
            if spec is not None and spec.origin and spec.origin.endswith(".py"):
                if ">>> " in Path(spec.origin).read_text(encoding="utf-8"):
                    names.add(info.name)
    return sorted(names)


def test_there_are_examples():
    assert len(_modules()) >= 3


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = [t for t in finder.find(module, name) if t.examples and t.name.split(".")[-1] != "__init__"]
    assert tests, f"{name} has '>>> ' in its source but no docstring examples were found"
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed (output above)"
