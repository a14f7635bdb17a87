"""The Examples sections of the floor's public functions run, and print what they say (doctest)."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = ["coinwall.forward.dynamics.floor.field", "coinwall.forward.dynamics.floor.landscape",
           "coinwall.forward.dynamics.floor.toss", "coinwall.forward.dynamics.floor.hand", "coinwall.forward.dynamics.billiard.rigidbody"]


@pytest.mark.parametrize("name", MODULES)
def test_examples_run(name):
    module = importlib.import_module(name)
    tests = [t for t in doctest.DocTestFinder().find(module, name, globs=dict(vars(module))) if t.examples]
    assert tests, f"{name} has no examples"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed (see above)"
