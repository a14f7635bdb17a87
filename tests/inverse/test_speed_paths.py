"""The fast paths of the solve: numpy replay of a wall's casadi algorithm, the linear-time convexity test."""

import math

import numpy as np
import pytest
from shapely.geometry import Polygon

from coinwall.forward import Wall
from coinwall.forward.wallvector import ArrayProgram
from coinwall.inverse.convexity import simple_convex
from coinwall.inverse.smooth import shape_check
from coinwall.inverse.solve import solve_body

# every function of the expression grammar, min/max (kinks), powers, quotients
EXPRESSIONS = [
    "sqrt((1+eps*cos(t)**2)/(1+eps))",
    "2 + 0.1*sin(3*t) - 0.05*cos(5*t)**3 + exp(0.1*sin(t)) + log(2 + cos(t))",
    "3 + tan(0.2*sin(t)) + arcsin(0.3*cos(t)) + arccos(0.2*sin(2*t)) + arctan(cos(t))",
    "4 + sinh(0.3*cos(t)) + cosh(0.2*sin(t)) + tanh(cos(2*t)) + abs(sin(t))*0.1",
    "max(cos(t), 0.5) + min(sin(t), 0.2, 0.1*cos(3*t)) + 2",
    "1/(2 + cos(t)) + (2 + sin(t))**1.5 + 2**cos(t)",
    "1",
    "t*0 + 2",
]


@pytest.mark.parametrize("text", EXPRESSIONS)
def test_array_replay_matches_casadi(text):
    """Reference: casadi's own evaluation of the same functions, one angle at a time."""
    params = {"eps": 0.55} if "eps" in text else {}
    wall = Wall.from_expression(text, params)
    backend = wall._backend
    theta = np.linspace(-1.0, 8.0, 997)
    single = backend._f012[0]
    want = np.array([[float(v) for v in single(x)] for x in theta]).T
    got = np.array(wall.derivatives(theta))
    scale = np.maximum(1.0, np.abs(want))
    assert np.all(np.abs(got - want) <= 8 * np.finfo(float).eps * scale), np.max(np.abs(got - want) / scale)
    assert isinstance(backend._f012[2], ArrayProgram)  # the replay is what ran


def test_constant_wall_has_zero_derivatives():
    b, d1, d2 = Wall.from_expression("1.5").derivatives(np.linspace(0, 6, 50))
    assert np.all(b == 1.5) and np.all(d1 == 0.0) and np.all(d2 == 0.0)


def _circle(n, radius=1.0, direction=1):
    phi = direction * np.linspace(0, 2 * math.pi, n, endpoint=False)
    return radius * np.column_stack([np.cos(phi), np.sin(phi)])


def _shapely(points):
    polygon = Polygon(points)
    valid = bool(polygon.is_valid)
    return valid, bool(valid and polygon.area >= polygon.convex_hull.area * (1 - 1e-9))


def test_convex_polygons_are_decided():
    for pts in (_circle(5), _circle(400000), _circle(64, direction=-1)):
        assert simple_convex(pts)
    square = np.array([[0, 0], [0.5, 0], [1, 0], [1, 1], [1, 1], [0, 1], [0, 0.5]], float)  # collinear, repeated
    assert simple_convex(square)
    assert simple_convex(np.vstack([_circle(9), _circle(9)[:1]]))  # closed by repeating the first point


def test_doubtful_polygons_are_left_to_shapely():
    barely = _circle(1000)
    barely[500] *= math.cos(2 * math.pi / 1000) * (1 - 1e-12)  # just inside its neighbours' chord: turns back
    twice = _circle(101)[(2 * np.arange(101)) % 101]  # every second vertex: winds twice, crosses itself
    bowtie = np.array([[0, 0], [1, 1], [1, 0], [0, 1]], float)
    reversal = np.array([[0, 0], [2, 0], [1, 0], [1, 1]], float)  # a spike back along an edge
    dent = np.array([[0, 0], [2, 0], [2, 2], [1, 0.1], [0, 2]], float)
    star = _circle(5)[[0, 2, 4, 1, 3]]  # the pentagram: turns one way, by 4π
    for pts in (barely, twice, bowtie, reversal, dent, star):
        assert not simple_convex(pts)
        assert shape_check(pts) == _shapely(pts)
    assert _shapely(twice)[0] is False and _shapely(bowtie)[0] is False and _shapely(star)[0] is False
    assert _shapely(dent) == (True, False)
    assert _shapely(barely) == (True, True)  # shapely's area tolerance: convex to 1e-9


def test_never_convex_when_shapely_says_otherwise():
    """Random polygons, many of them non-simple or dented: every one the pre-check accepts, shapely does too."""
    rng = np.random.default_rng(7)
    accepted = 0
    for trial in range(400):
        n = int(rng.integers(3, 40))
        if trial % 3 == 0:  # random points in random order: mostly self-intersecting
            pts = rng.normal(size=(n, 2))
        else:  # a convex polygon, perturbed or with a vertex reordered
            noise = rng.normal(scale=10.0 ** -rng.integers(1, 8), size=(n, 1))
            pts = _circle(n, direction=1 if trial % 2 else -1) * (1 + noise)
            if trial % 5 == 0:
                i, j = rng.integers(0, n, 2)
                pts[[i, j]] = pts[[j, i]]
        if simple_convex(pts):
            accepted += 1
            assert _shapely(pts) == (True, True)
    assert accepted > 50  # the fast path is taken, not only the fallback


def test_kappa_max_of_an_ellipse_is_its_semi_major_axis():
    """Closed form (inverse/realizability.py docstring): a centred ellipse with semi-axes a ≥ b has κ_max = a."""
    from coinwall.inverse.realizability import kappa_max

    a, b = 1.3, 0.7
    wall = Wall.from_expression("sqrt(a**2*cos(t)**2 + b**2*sin(t)**2)", {"a": a, "b": b})
    value, support = kappa_max(solve_body(wall, 0.0).outline)
    assert value == pytest.approx(a, rel=1e-9) and len(support) == 2
    assert np.allclose(np.sort(np.abs(support[:, 0])), [a, a], rtol=1e-6) and np.allclose(support[:, 2], 0.5)


def test_solving_a_formula_wall_does_not_import_scipy_optimize():
    """Importing scipy.optimize costs 0.3-0.7 s, a third of the built-in example's whole run."""
    import subprocess
    import sys

    code = ("import sys, io, contextlib\nfrom coinwall.cases.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()): status = main(['solve', '--json'])\n"
            "print(status, 'scipy.optimize' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.stdout.split() == ["0", "False"], done.stderr[-2000:]
