"""Every critical angle of a formula wall: all global minimisers of ρ = b + b'', each with its certified
uncertainty, and b_c with a certified tolerance (inverse/criticalcells.py).

References are closed forms, derived here, never the code under test:

* ``b = 1 + a cos(kθ + φ)`` has ``ρ = 1 + a(1 − k²) cos(kθ + φ)``: for k ≥ 2 and a > 0 its minimum
  ``1 − a(k² − 1)`` is attained exactly where ``kθ + φ ≡ 0 (mod 2π)``, at the k angles ``(2πn − φ)/k``.
* A Fourier series ``Σ c_k cos kθ + s_k sin kθ`` has ``ρ = a0 + Σ (1 − k²)(c_k cos kθ + s_k sin kθ)``, evaluated
  here with numpy on a dense grid and polished by golden sections (an independent minimiser).
* ``|sin kθ|`` and ``|cos θ|`` are arcs of circles of radius 0 between their kinks: ``|cos θ|'' = −|cos θ|``, so
  they add nothing to ρ away from the kinks (where they add point masses, positive: edges).
"""

import json
import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.inverse import critical_offset, solve_body

TWO_PI = 2 * math.pi


def _cyclic(a, b):
    return abs(math.remainder(a - b, TWO_PI))


def _check_certificate(result, truth_b_c, minimisers):
    """b_c within its certified tolerance of the truth; every true minimiser within its angle's certified
    half-width of a reported angle; every reported angle near a true minimiser."""
    assert abs(result.b_c - truth_b_c) <= result.b_c_tolerance, (result.b_c, truth_b_c, result.b_c_tolerance)
    assert len(result.angles) == len(minimisers), (result.angles, minimisers)
    for true in minimisers:
        k = min(range(len(result.angles)), key=lambda i: _cyclic(result.angles[i], true))
        assert _cyclic(result.angles[k], true) <= result.angle_errors[k], (true, result.angles[k],
                                                                           result.angle_errors[k])


@pytest.mark.parametrize("k", [2, 3, 4, 5, 6, 7])
@pytest.mark.parametrize("phase", [0.0, 0.7, -math.pi / 2, 2.9])
def test_every_minimiser_of_one_harmonic(k, phase):
    a = 0.5 / (k * k - 1)  # ρ = 1 − 0.5 cos(kθ + φ) (+ ...): keeps b positive and b_c = −0.5
    wall = Wall.from_expression(f"1 + {a!r}*cos({k}*t + {phase!r})")
    result = critical_offset(wall)
    minimisers = [np.mod((TWO_PI * n - phase) / k, TWO_PI) for n in range(k)]
    _check_certificate(result, -(1 - a * (k * k - 1)), minimisers)
    assert result.b_c_tolerance < 1e-12 and max(result.angle_errors) < 1e-6
    assert result.intervals == ()


@pytest.mark.parametrize("expression,count,b_c", [
    ("1+0.1*cos(3*t)", 3, -0.2),                       # 1 − 0.8 cos 3θ, the issue's examples
    ("1+0.1*sin(3*t)", 3, -0.2),
    ("1+0.05*cos(6*t)", 6, 0.75),                      # 1 − 1.75 cos 6θ
    ("1+0.02*cos(5*t)+0.02*cos(10*t)", 5, 1.46),       # 1 − 0.48 cos 5θ − 1.98 cos 10θ: both least at 5θ ≡ 0
])
def test_the_issues_walls_list_every_angle(expression, count, b_c):
    result = critical_offset(Wall.from_expression(expression))
    period = TWO_PI / count
    first = 0.0 if "cos" in expression else math.pi / 6  # sin 3θ = 1 at θ = π/6 (mod 2π/3)
    _check_certificate(result, b_c, [first + n * period for n in range(count)])


def test_a_fourier_file_and_the_command_line_list_the_same_angles(tmp_path, capsys):
    """The same wall as an expression, as a Fourier .json and through `critical --json` and `solve --json`:
    the same three angles (0, 2π/3, 4π/3), in JSON with their uncertainties."""
    from coinwall.cases.cli.main import main

    series = Wall.from_fourier(1.0, cos=[0.0, 0.0, 0.1])
    _check_certificate(critical_offset(series), -0.2, [0.0, TWO_PI / 3, 2 * TWO_PI / 3])
    path = tmp_path / "wall.json"
    path.write_text(json.dumps({"a0": 1, "cos": [0, 0, 0.1]}), encoding="utf-8")
    assert main(["critical", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert len(doc["angles"]) == len(doc["angle_errors"]) == 3
    assert main(["solve", str(path), "--b0", "-0.3", "--json"]) == 0
    solved = json.loads(capsys.readouterr().out)
    assert solved["critical_angles"] == doc["angles"] and solved["critical_angle_errors"] == doc["angle_errors"]
    assert len(solved["corners"]) == 3
    assert main(["critical", str(path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "angles     0, 2.0944, 4.18879 (rad, where b + b'' is smallest; every minimiser within ±" in lines[2]
    assert main(["solve", str(path), "--b0", "-0.3"]) == 0
    assert any(line.startswith("critical   b_c = -0.2 at θ = 0, 2.0944, 4.18879 (each ±")
               for line in capsys.readouterr().out.splitlines())


@pytest.mark.parametrize("eps", [1e-3, 1e-5, 5e-7, 1e-9, 1e-11, 1e-15])
def test_a_second_dip_is_listed_only_within_the_tolerance(eps):
    """b = 1 + a cos 2θ − (ε/8) cos 3θ: ρ = 1 − 3a cos 2θ + ε cos 3θ has its global minimum 1 − 3a − ε at π and a
    local one 1 − 3a + ε at 0 (both stationary exactly: sin 2θ = sin 3θ = 0 there), 2ε above.  The dip at 0
    may be listed only when 2ε is within what the result certifies (its spread)."""
    a = 0.1
    wall = Wall.from_expression(f"1 + {a!r}*cos(2*t) - {eps / 8!r}*cos(3*t)")
    result = critical_offset(wall)
    assert abs(result.b_c - (-(1 - 3 * a - eps))) <= result.b_c_tolerance
    listed_zero = any(_cyclic(x, 0.0) < 1e-3 for x in result.angles)
    assert any(_cyclic(x, math.pi) <= e for x, e in zip(result.angles, result.angle_errors))
    if listed_zero:
        assert 2 * eps <= result.spread + result.b_c_tolerance
    else:
        assert len(result.angles) == 1
    if eps >= 5e-7:
        assert not listed_zero and len(result.angles) == 1


def test_random_trigonometric_walls_against_an_independent_minimiser():
    """Random series of 2–5 harmonics with random phases (ρ kept positive or not, as it comes): b_c within its
    tolerance of numpy's dense minimum, every grid local minimum within 1e-9 of the global one lies within the
    certified half-width of a listed angle, and every listed angle is such a near-minimiser."""
    rng = np.random.default_rng(32)
    theta = np.linspace(0.0, TWO_PI, 2**18, endpoint=False)
    for _ in range(12):
        m = int(rng.integers(2, 6))
        k = np.sort(rng.choice(np.arange(2, 9), m, replace=False)).astype(float)
        c, s = rng.normal(size=m) * 0.05, rng.normal(size=m) * 0.05
        cos, sin = np.zeros(int(k.max())), np.zeros(int(k.max()))
        cos[k.astype(int) - 1], sin[k.astype(int) - 1] = c, s

        def rho(x, k=k, c=c, s=s):
            x = np.atleast_1d(x)[:, None]
            return 1.0 + np.sum((1 - k * k) * (c * np.cos(k * x) + s * np.sin(k * x)), axis=1)

        values = rho(theta)
        lows = np.flatnonzero((values <= np.roll(values, 1)) & (values <= np.roll(values, -1)))
        polished = []
        for i in lows:  # golden sections between the neighbours
            lo, hi = theta[i] - TWO_PI / theta.size, theta[i] + TWO_PI / theta.size
            for _ in range(80):
                a, b = lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo)
                lo, hi = (lo, b) if rho(a)[0] < rho(b)[0] else (a, hi)
            polished.append((float(rho(0.5 * (lo + hi))[0]), 0.5 * (lo + hi)))
        best = min(v for v, _ in polished)
        for wall in (Wall.from_fourier(1.0, cos, sin), _as_expression(k, c, s)):
            result = critical_offset(wall)
            assert abs(-result.b_c - best) <= result.b_c_tolerance + 1e-14
            for value, where in polished:
                if value <= best + 1e-9:
                    assert min(_cyclic(where, x) - e for x, e in zip(result.angles, result.angle_errors)) <= 1e-9
            for x in result.angles:
                assert rho(x)[0] <= best + result.spread + result.b_c_tolerance + 1e-12


def _as_expression(k, c, s):
    terms = " + ".join(f"{float(ci)!r}*cos({int(ki)}*t) + {float(si)!r}*sin({int(ki)}*t)"
                       for ki, ci, si in zip(k, c, s))
    return Wall.from_expression("1 + " + terms)


def test_kinked_walls():
    # |sin 2θ| adds −3|sin 2θ| to ρ between its kinks (at multiples of π/2, positive jumps: edges)
    result = critical_offset(Wall.from_expression("1 + 0.1*abs(sin(2*t))"))
    _check_certificate(result, -0.7, [math.pi / 4 + n * math.pi / 2 for n in range(4)])
    # |sin θ| adds nothing; 0.05 cos 2θ gives ρ = 1 − 0.15 cos 2θ, least at 0 and π: exactly at the kinks
    result = critical_offset(Wall.from_expression("1 + 0.2*abs(sin(t)) + 0.05*cos(2*t)"))
    _check_certificate(result, -0.85, [0.0, math.pi])
    # the stick: ρ = 0 on the two open arcs between the kinks at ±π/2, split there
    result = critical_offset(Wall.from_expression("abs(cos(t))"))
    assert abs(result.b_c) <= result.b_c_tolerance < 1e-12
    assert sorted((round(lo, 9), round(hi, 9)) for lo, hi in result.intervals) == \
        [(round(math.pi / 2, 9), round(1.5 * math.pi, 9)), (round(1.5 * math.pi, 9), round(2.5 * math.pi, 9))]
    # the rectangle a|cos| + c|sin|: four vertex windows, each a quarter turn between kinks
    result = critical_offset(Wall.from_expression("abs(cos(t)) + 0.5*abs(sin(t))"))
    assert len(result.intervals) == 4 and all(abs(hi - lo - math.pi / 2) < 1e-9 for lo, hi in result.intervals)


def test_arcs_list_their_least_radius():
    """A Reuleaux triangle of width 1: three vertices (radius 0, windows of π/3) and three arcs of radius 1:
    ρ is least (0) on exactly the three vertex windows."""
    from coinwall.cases.catalog import get_case

    wall = get_case("reuleaux-3").wall()
    result = critical_offset(wall)
    assert result.b_c == 0 and len(result.intervals) == 3
    assert all(abs(hi - lo - math.pi / 3) < 1e-12 for lo, hi in result.intervals)


def test_a_scaled_wall_keeps_its_angles():
    wall = Wall.from_expression("1 + 0.1*cos(3*t + 0.4)")
    small, big = critical_offset(wall), critical_offset(wall.scaled(25.4))
    assert big.b_c == pytest.approx(25.4 * small.b_c, abs=big.b_c_tolerance + 25.4 * small.b_c_tolerance)
    assert len(big.angles) == 3 and max(abs(x - y) for x, y in zip(big.angles, small.angles)) < 1e-6


def test_solve_lists_every_angle_and_draws_every_corner():
    # ρ + b0 = b0 + 1 − 0.48 cos 5θ − 1.98 cos 10θ, below 0 only near θ = 2πn/5 when 0.5 < b0 < 1.46
    body = solve_body(Wall.from_expression("1+0.02*cos(5*t)+0.02*cos(10*t)"), 1.0)
    assert len(body.critical_angles) == 5 == len(body.critical_angle_errors)
    assert body.regime == "corner" and len(body.corners) == 5


def test_the_explorer_and_the_figure_list_the_same_angles():
    """The explorer's wall panel prints the list `coinwall critical` prints; the figure's ρ panel marks each."""
    from coinwall.cases.explore.compute import wall_info
    from coinwall.forward.formats.figure import new_figure  # noqa: F401  (matplotlib, as the exporters use it)
    from coinwall.inverse.export.figure import figure

    info = wall_info({"expression": "1+0.1*cos(3*t)", "params": {}})
    assert info["critical_angles_text"].startswith("θ = 0, 2.0944, 4.18879 (each ±")
    assert len(info["critical_angles"]) == len(info["critical_angle_errors"]) == 3
    body = solve_body(Wall.from_expression("1+0.1*cos(3*t)"), -0.3)
    fig = figure(body)
    marks = [line for ax in fig.axes for line in ax.get_lines() if str(line.get_label()).startswith("min ρ")]
    assert len(marks) == 1 and len(marks[0].get_xdata()) == 3
    assert np.allclose(sorted(marks[0].get_xdata()), sorted(body.critical_angles))
