"""Tests of the whitelisted wall-expression parser (forward/expression.py)."""

import math
import re

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from coinwall.forward.errors import CoinwallError, InvalidExpression, InvalidParameter
from coinwall.forward.expression import ParsedExpression, parse_expression, parse_param

THETAS = np.array([0.0, 0.3, 1.0, math.pi / 2, 2.0, math.pi, 4.5, 6.0])


def evaluate(expr, thetas=THETAS, symbol=None):
    """Evaluate an SX expression (of the parsed symbol) at several angles."""
    f = ca.Function("f", [symbol], [expr])
    return np.array([float(f(x)) for x in thetas])


def values(parsed, thetas=THETAS):
    return evaluate(parsed.expr, thetas, parsed.symbol)


# ---------------------------------------------------------------- accepted input
def test_ellipse_wall_matches_closed_form():
    parsed = parse_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1})
    expected = np.sqrt((1 + np.cos(THETAS) ** 2) / 2)
    np.testing.assert_allclose(values(parsed), expected, rtol=1e-14)
    assert parsed.params == (("eps", 1.0),)
    assert parsed.switching == ()
    assert isinstance(parsed, ParsedExpression)
    assert parsed.text == "sqrt((1+eps*cos(t)**2)/(1+eps))"


def test_params_are_sorted_and_substituted():
    parsed = parse_expression("b*cos(t) + a", {"b": 2.0, "a": 0.5})
    assert parsed.params == (("a", 0.5), ("b", 2.0))
    np.testing.assert_allclose(values(parsed), 2 * np.cos(THETAS) + 0.5, rtol=1e-14)
    # only t is left free: parameters are numbers in the expression
    free = ca.symvar(parsed.expr)
    assert len(free) == 1 and ca.is_equal(free[0], parsed.symbol)


def test_theta_alias_and_constants():
    parsed = parse_expression("theta + t*pi - e")
    np.testing.assert_allclose(values(parsed), THETAS + THETAS * math.pi - math.e, rtol=1e-14)


def test_power_and_unary_operators():
    parsed = parse_expression("-t**2 + +t - -1 + 2**-1")
    np.testing.assert_allclose(values(parsed), -THETAS**2 + THETAS + 1 + 0.5, rtol=1e-14)


@pytest.mark.parametrize("name, func", [
    ("sin", np.sin), ("cos", np.cos), ("tan", np.tan), ("exp", np.exp), ("log", np.log),
    ("sqrt", np.sqrt), ("abs", np.abs), ("sinh", np.sinh), ("cosh", np.cosh), ("tanh", np.tanh),
    ("arctan", np.arctan),
])
def test_functions(name, func):
    parsed = parse_expression(f"{name}(t + 0.5)")
    np.testing.assert_allclose(values(parsed), func(THETAS + 0.5), rtol=1e-13)


def test_inverse_trig_functions():
    x = np.linspace(-0.9, 0.9, 7)
    for name, func in (("arcsin", np.arcsin), ("arccos", np.arccos)):
        parsed = parse_expression(f"{name}(t)")
        np.testing.assert_allclose(values(parsed, x), func(x), rtol=1e-13)


def test_constant_wall_allowed():
    parsed = parse_expression("1.5")
    np.testing.assert_allclose(values(parsed), 1.5)
    assert parsed.switching == ()


def test_abs_records_switching_function():
    parsed = parse_expression("abs(cos(t))")
    assert len(parsed.switching) == 1
    np.testing.assert_allclose(evaluate(parsed.switching[0], THETAS, parsed.symbol), np.cos(THETAS), atol=1e-15)
    np.testing.assert_allclose(values(parsed), np.abs(np.cos(THETAS)), rtol=1e-14)


def test_min_max_two_args():
    parsed = parse_expression("max(cos(t), sin(t)) + min(t, 1)")
    assert len(parsed.switching) == 2
    expected = np.maximum(np.cos(THETAS), np.sin(THETAS)) + np.minimum(THETAS, 1)
    np.testing.assert_allclose(values(parsed), expected, rtol=1e-14)
    # zeros where the arguments cross: cos = sin at π/4 and 5π/4, t = 1
    zeros = np.array([math.pi / 4, 5 * math.pi / 4])
    np.testing.assert_allclose(evaluate(parsed.switching[0], zeros, parsed.symbol), 0, atol=1e-15)
    np.testing.assert_allclose(evaluate(parsed.switching[1], [1.0], parsed.symbol), 0, atol=1e-15)


def test_min_max_three_args_fold_pairwise():
    parsed = parse_expression("min(cos(t), sin(t), 0.5)")
    assert len(parsed.switching) == 2
    expected = np.minimum(np.minimum(np.cos(THETAS), np.sin(THETAS)), 0.5)
    np.testing.assert_allclose(values(parsed), expected, rtol=1e-14)
    # second switch is min(cos, sin) - 0.5: zero where cos t = 0.5 while cos t < sin t
    np.testing.assert_allclose(evaluate(parsed.switching[1], [math.pi / 3], parsed.symbol), 0, atol=1e-15)
    parsed = parse_expression("max(t, 1, 2, 3)")
    assert len(parsed.switching) == 3


def test_constant_switching_functions_are_dropped():
    # cannot kink in t, so they are no kink candidates
    assert parse_expression("abs(-2) + max(1, pi) + t").switching == ()


def test_repr_is_short_and_safe():
    text = repr(parse_expression("1 + eps*cos(t)", {"eps": 0.25}))
    assert text.startswith("ParsedExpression(") and "eps=0.25" in text and "\n" not in text
    assert "..." in repr(parse_expression("+".join(["t"] * 100)))


def test_surrounding_blanks_are_allowed_but_an_expression_is_one_line():
    parsed = parse_expression("  (1 +\t  t)  \n")
    np.testing.assert_allclose(values(parsed), 1 + THETAS)
    # one grammar: no line breaks (not even the continuation Python allows inside parentheses), no comment, no
    # backslash continuation, no empty argument -- each would be read by Python's parser
    for text, needle in [("(1 +\n  t)", "line break at column 5"), ("1 + t # + 2*t", "'#' at column 7"),
                         ("1 + \\\n t", "'\\' at column 5"), ("max(t, 1,)", "empty argument after ',' at column 9"),
                         ("1 +\x0bt", "control character"), ("max(t, 1, )", "column 9")]:
        with pytest.raises(InvalidExpression, match=re.escape(needle)):
            parse_expression(text)


# ---------------------------------------------------------------- rejected input
@pytest.mark.parametrize("text, token", [
    ("__import__('os')", "__import__"),
    ("t.__class__", ".__class__"),
    ("sin(t).real", ".real"),
    ("open('x')", "open"),
    ("eval('1')", "eval"),
    ("lambda: 1", "lambda"),
    ("t[0]", "t[0]"),
    ("'abc'", "abc"),
    ("t if t else 1", "t if t else 1"),
    ("t < 1", "<"),
    ("t and 1", "and"),
    ("not t", "not"),
    ("t // 2", "//"),
    ("t % 2", "%"),
    ("sin(t, 1)", "sin"),
    ("sin()", "sin"),
    ("min(t)", "min"),
    ("foo(t)", "foo"),
    ("x + t", "x"),
    ("sin(t=1)", "t=1"),
    ("sin(*t)", "*t"),
    ("sin(t)(1)", "sin(t)"),
    ("1j", "1j"),
    ("True", "True"),
    ("None", "None"),
    ("f'{t}'", "f-string"),
    ("(y := t)", "y := t"),
    ("[t]", "[t]"),
    ("t, 1", "tuple"),
    ("__builtins__", "__builtins__"),
    ("sin", "sin"),
    ("1e999", "1e999"),
])
def test_rejected_constructs_name_the_token(text, token):
    with pytest.raises(InvalidExpression) as info:
        parse_expression(text)
    message = str(info.value)
    assert token in message
    assert "\n" not in message


def test_unknown_name_suggests_param_flag():
    with pytest.raises(InvalidExpression, match=r"unknown name 'esp'.*did you mean 'eps'.*--param esp=VALUE"):
        parse_expression("1 + esp*cos(t)", {"eps": 0.5})


def test_arity_messages():
    with pytest.raises(InvalidExpression, match=r"'sin' takes 1 argument, got 2"):
        parse_expression("sin(t, 1)")
    with pytest.raises(InvalidExpression, match=r"'max' takes 2 or more arguments, got 1"):
        parse_expression("max(t)")


@pytest.mark.parametrize("text, where", [("1 +", "column 4"), ("sin(t", "column 4"), ("t)", "column 2")])
def test_syntax_error_names_column(text, where):
    with pytest.raises(InvalidExpression, match="syntax error") as info:
        parse_expression(text)
    assert where in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("text", ["", "   ", "\n\t"])
def test_empty_expression(text):
    with pytest.raises(InvalidExpression, match="empty"):
        parse_expression(text)


def test_pathological_sizes():
    with pytest.raises(InvalidExpression, match="too long"):
        parse_expression("t+" * 2499 + "t")
    with pytest.raises(InvalidExpression, match="too complex|nested"):
        parse_expression("-" * 1500 + "t")
    with pytest.raises(InvalidExpression, match="too complex|nested"):
        parse_expression("sin(" * 250 + "t" + ")" * 250)
    # nesting counts nesting, not length: a flat sum or product of as many terms as 2,000 characters hold passes
    parse_expression("+".join(["cos(t)"] * 150))
    assert str(parse_expression("1" + "+1" * 994).expr) == "995"
    parse_expression("t" + "-t" * 999)
    parse_expression("*".join(["(1+0.001*cos(t))"] * 110))
    # ... but 201 signs, calls or powers inside one another are refused as nesting
    with pytest.raises(InvalidExpression, match="levels of nesting"):
        parse_expression("-" * 120 + "sin(" * 90 + "t" + ")" * 90)


def test_a_long_flat_sum_is_a_wall():
    from coinwall.forward import Wall
    from coinwall.inverse import critical_offset

    wall = Wall.from_expression("1" + "+0.001*cos(2*t)" * 130)  # 1 + 0.13 cos 2θ, 1,951 characters
    assert critical_offset(wall).b_c == pytest.approx(-(1 - 3 * 0.13), abs=1e-12)


def test_non_string_expression():
    with pytest.raises(InvalidExpression, match="string"):
        parse_expression(3.0)


def test_null_byte():
    with pytest.raises(InvalidExpression):
        parse_expression("t\x00")


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet="tsinco()+-*/ .,[]_'ex0123456789=<lambd:", max_size=40))
def test_arbitrary_text_only_raises_coinwall_errors(text):
    try:
        parse_expression(text)
    except CoinwallError as exc:
        assert "\n" not in str(exc)


# ---------------------------------------------------------------- parameters
def test_unused_parameter():
    with pytest.raises(InvalidParameter, match=r"parameter 'x' is not used in the expression"):
        parse_expression("1 + cos(t)", {"x": 1.0})


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_non_finite_parameter(value):
    with pytest.raises(InvalidParameter, match=r"parameter 'eps' must be finite, got"):
        parse_expression("1 + eps*cos(t)", {"eps": value})


@pytest.mark.parametrize("value", ["0.5", True, None, [1.0]])
def test_non_numeric_parameter(value):
    with pytest.raises(InvalidParameter, match="'eps' must be a real number"):
        parse_expression("1 + eps*cos(t)", {"eps": value})


@pytest.mark.parametrize("name", ["1x", "a b", "", "x-y", "é", "__x", 3])
def test_bad_parameter_names(name):
    with pytest.raises(InvalidParameter) as info:
        parse_expression("t", {name: 1.0})
    assert f"'{name}'" in str(info.value)


@pytest.mark.parametrize("name", ["pi", "e", "t", "theta", "sin", "min", "abs"])
def test_reserved_parameter_names(name):
    with pytest.raises(InvalidParameter, match=f"'{name}' is reserved"):
        parse_expression("t", {name: 1.0})


def test_params_must_be_mapping():
    with pytest.raises(InvalidParameter, match="mapping"):
        parse_expression("a*t", [("a", 1.0)])


# ---------------------------------------------------------------- parse_param
@pytest.mark.parametrize("text, expected", [
    ("eps=0.5", ("eps", 0.5)),
    (" eps = 1e-3 ", ("eps", 1e-3)),
    ("a_1=-2", ("a_1", -2.0)),
    ("k=.5", ("k", 0.5)),
    ("k=+3.", ("k", 3.0)),
])
def test_parse_param_good(text, expected):
    assert parse_param(text) == expected


@pytest.mark.parametrize("text, token", [
    ("eps", "eps"),
    ("eps=", "eps"),
    ("=1", "=1"),
    ("eps=abc", "abc"),
    ("eps=nan", "nan"),
    ("eps=inf", "inf"),
    ("eps=1e999", "1e999"),
    ("1x=2", "1x"),
    ("pi=3", "pi"),
    ("eps=1_0", "1_0"),
    ("eps=1=2", "1=2"),
])
def test_parse_param_bad(text, token):
    with pytest.raises(InvalidParameter) as info:
        parse_param(text)
    assert token in str(info.value)


def test_parse_param_round_trip():
    name, value = parse_param("eps=0.25")
    parsed = parse_expression("1 + eps*cos(t)", {name: value})
    np.testing.assert_allclose(values(parsed), 1 + 0.25 * np.cos(THETAS))
