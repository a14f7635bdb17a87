"""Certified ranges on cells (forward/affine.py, forward/intervalmath.py, forward/wallbounds.py): every value of
the formula on a cell lies inside its range, and the ranges narrow as the cells do.

Reference: the same formulas evaluated by casadi itself (its own C evaluation, not the numpy replay under test)
at 41 points of each cell, and, for a Fourier series, numpy's sum of its terms.
"""

import doctest
import importlib
import math

import numpy as np
import pytest

from coinwall.forward import Wall

CORPUS = [
    "1+0.1*cos(3*t)", "sqrt((1+eps*cos(t)**2)/(1+eps))", "abs(cos(t))", "max(cos(t), 0.5*cos(t-2))",
    "2+tanh(1e3*sin(t-1))", "exp(0.3*sin(t))*(1+0.1*cos(2*t))", "log(2+cos(t))", "(2+cos(t))**1.5",
    "1/(1.5+sin(t))", "arctan(sin(t))+2", "sqrt(1+1e-6-cos(t))", "min(1+0.1*cos(t), 1.05+0.1*sin(2*t))",
    "(abs(cos(t))**3 + abs(sin(t))**3)**(1/3)", "cosh(sin(t))", "arcsin(0.5*sin(t))+2", "2**cos(t)",
    "tan(0.5*sin(t))+2", "2+sinh(0.5*cos(t))", "3+arccos(0.4*cos(2*t))", "2+abs(sin(t))**1.5",
]


def _program(text):
    import casadi as ca

    from coinwall.forward.affine import AffineProgram
    from coinwall.forward.expression import parse_expression

    parsed = parse_expression(text, {"eps": 99.0} if "eps" in text else {})
    t, b = parsed.symbol, parsed.expr
    rho = b + ca.jacobian(ca.jacobian(b, t), t)
    return AffineProgram(ca.Function("rho", [t], [rho], {"cse": True})), ca.Function("plain", [t], [rho])


@pytest.mark.parametrize("text", CORPUS)
def test_every_value_lies_in_its_cells_range(text):
    program, plain = _program(text)
    rng = np.random.default_rng(7)
    widths = []
    for width in (0.3, 1e-2, 1e-4, 1e-7):
        lo = rng.uniform(0, 2 * math.pi, 150)
        hi = lo + width
        (low, high), = program.enclose(lo, hi)
        points = lo[:, None] + width * np.linspace(0, 1, 41)[None, :]
        values = np.array(plain.map(points.size)(points.reshape(1, -1))).reshape(points.shape)
        finite = np.isfinite(values).all(axis=1)
        assert np.all((values >= low[:, None]) & (values <= high[:, None]) | ~finite[:, None]), text
        bounded = np.isfinite(low) & np.isfinite(high)
        widths.append(np.median((high - low)[bounded]))
    # narrower with the cells, down to the rounding of ρ (the stick: 0 at every width; tanh: saturated)
    assert widths[-1] <= max(1e-3 * widths[1], 1e-6)


def test_a_point_has_the_rounding_of_its_value():
    program, plain = _program("sqrt((1+eps*cos(t)**2)/(1+eps))")
    x = np.linspace(0, 2 * math.pi, 1000)
    (low, high), = program.enclose(x, x)
    exact = np.array(plain.map(x.size)(x.reshape(1, -1))).ravel()
    assert np.all((low <= exact) & (exact <= high)) and np.max(high - low) < 1e-12


def test_two_equal_branches_of_a_max_stay_tied():
    """max(−cos, sqrt(cos²)) is |cos| where cos < 0 (both branches equal): the weights of casadi's derivative of a
    max share one unknown, so b + b'' = 0 there comes out as 0 at a point, not as a range of both branches."""
    program, _ = _program("max(-cos(t), sqrt(cos(t)**2))")
    x = np.array([2.0, 3.0, 4.0])
    (low, high), = program.enclose(x, x)
    assert np.max(np.abs(low)) < 1e-13 and np.max(np.abs(high)) < 1e-13


def test_fourier_ranges_hold():
    """Taylor's bound with the global bound of ρ'' (wallbounds.py): numpy's own sum of the terms at 33 points
    of each cell lies inside."""
    from coinwall.forward.wallbounds import curvature_ranges

    rng = np.random.default_rng(3)
    cos, sin = rng.normal(size=12) / np.arange(1, 13) ** 2, rng.normal(size=12) / np.arange(1, 13) ** 2
    ranges = curvature_ranges(Wall.from_fourier(2.0, cos, sin))
    k = np.arange(1, 13)
    for width in (0.5, 1e-3, 1e-6):
        lo = rng.uniform(0, 2 * math.pi, 200)
        low, high = ranges(lo, lo + width)
        x = lo[:, None, None] + width * np.linspace(0, 1, 33)[None, :, None]
        rho = 2.0 + np.sum((1 - k * k) * (cos * np.cos(k * x) + sin * np.sin(k * x)), axis=2)
        assert np.all((rho >= low[:, None]) & (rho <= high[:, None]))


@pytest.mark.parametrize("module", ["coinwall.forward.affine", "coinwall.forward.wallbounds",
                                    "coinwall.inverse.criticalcells", "coinwall.inverse.critical",
                                    "coinwall.forward.display"])
def test_docstring_examples(module):
    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0
