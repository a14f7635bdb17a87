"""Bad input at the library level: each raises a specific CoinwallError whose one-line message
names the argument and the offending value (the CLI turns the same errors into exit status 2)."""

import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.errors import InvalidArgument, InvalidExpression, InvalidParameter, InvalidWall
from coinwall.inverse import solve_body

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def _one_line(exc_info):
    message = str(exc_info.value)
    assert "\n" not in message
    return message


def test_nan_wall_is_refused_and_located():
    with pytest.raises(InvalidWall) as err:
        Wall.from_expression("sqrt(cos(t))", {})  # NaN where cos < 0
    message = _one_line(err)
    assert "finite" in message or "nan" in message.lower()


def test_infinite_wall_is_refused():
    """1/(1 + cos t) is infinite at θ = π.  (A pole strictly between the validation grid's 4096
    angles evaluates to a large finite number and is not caught: a documented limitation.)"""
    with pytest.raises(InvalidWall) as err:
        Wall.from_expression("1/(1+cos(t))", {})
    assert "3.14159" in _one_line(err)


def test_non_periodic_expression_is_refused():
    with pytest.raises(InvalidWall) as err:
        Wall.from_expression("1 + 0.1*t", {})
    assert "periodic" in _one_line(err)


def test_samples_not_covering_a_period_are_refused():
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    with pytest.raises(InvalidWall) as err:
        Wall.from_samples(theta / 2, 1 + 0.1 * np.cos(theta))  # covers only half a period
    assert "full period" in _one_line(err)


def test_too_few_samples_are_refused():
    with pytest.raises(InvalidWall) as err:
        Wall.from_samples([0.0, 1.0, 2.0], [1.0, 1.0, 1.0])
    assert "3" in _one_line(err)


def test_non_finite_samples_are_refused():
    theta = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    b = np.ones_like(theta)
    b[5] = math.nan
    with pytest.raises(InvalidWall) as err:
        Wall.from_samples(theta, b)
    _one_line(err)


def test_unknown_parameter_is_refused():
    with pytest.raises(InvalidParameter) as err:
        Wall.from_expression(ELLIPSE, {"eps": 1.0, "epsilon": 2.0})
    assert "epsilon" in _one_line(err)


def test_missing_parameter_is_refused():
    with pytest.raises(InvalidExpression) as err:
        Wall.from_expression(ELLIPSE, {})
    assert "eps" in _one_line(err)


def test_centre_of_mass_outside_is_refused_with_the_bound():
    """b0 + b < 0 somewhere: the message gives the angle and the smallest admissible b0 (−min b)."""
    wall = Wall.from_expression(ELLIPSE, {"eps": 1.0})  # min b = 1/sqrt(2) at θ = π/2
    with pytest.raises(InvalidWall) as err:
        solve_body(wall, -0.8)
    message = _one_line(err)
    assert "-0.707107" in message and "1.5708" in message


@pytest.mark.parametrize("kwargs,needle", [
    ({"method": "newton"}, "method"),
    ({"points": 3}, "points"),
    ({"points": 10**9}, "points"),
])
def test_bad_solver_arguments(kwargs, needle):
    """Arguments outside their range: InvalidArgument naming the argument."""
    wall = Wall.from_expression(ELLIPSE, {"eps": 1.0})
    with pytest.raises(InvalidArgument) as err:
        solve_body(wall, **kwargs)
    assert needle in _one_line(err)


@pytest.mark.parametrize("b0", [math.nan, math.inf, -math.inf])
def test_non_finite_offset(b0):
    wall = Wall.from_expression(ELLIPSE, {"eps": 1.0})
    with pytest.raises(InvalidParameter) as err:
        solve_body(wall, b0)
    assert "b0" in _one_line(err)
