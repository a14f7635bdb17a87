"""The Examples sections of the data path's docstrings run (doctest), each a check of a fact the docstring
states: the band of a hexagon's samples, a pentagon's forced corners, the three critical angles of a wall with
three minima, the noisy ellipse's confidence interval, a designed grid's scatter."""

import doctest
import importlib

import pytest

MODULES = ["coinwall.forward.sampledata", "coinwall.inverse.band", "coinwall.inverse.certify",
           "coinwall.inverse.criticalbound", "coinwall.inverse.discrete", "coinwall.inverse.noise",
           "coinwall.inverse.fit"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    failed, attempted = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert attempted > 0 and failed == 0
