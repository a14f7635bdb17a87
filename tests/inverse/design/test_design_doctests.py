"""The Examples sections of the design modules' docstrings run (doctest)."""

import doctest
import importlib

import pytest

MODULES = ["coinwall.inverse.design.family", "coinwall.inverse.design.drop", "coinwall.inverse.design.flip",
           "coinwall.inverse.design.bounce", "coinwall.inverse.design.bounce3d", "coinwall.inverse.design.solvers",
           "coinwall.inverse.design.design", "coinwall.forward.dynamics.coin3d.rest"]


@pytest.mark.parametrize("name", MODULES)
def test_examples_run(name):
    module = importlib.import_module(name)
    failed, tried = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
    assert tried > 0, f"{name} has no example"
    assert failed == 0
