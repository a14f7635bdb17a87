"""Issues 12 and 16, numerics: poles and non-finite intervals between grid angles, no non-finite body,
ranges with memory estimates, large sampled walls, the expression grammar, no NumPy warnings.

Reference values: the poles and NaN intervals are placed by construction (``tan t`` at π/2,
``sqrt(1 − 1e-9 − cos(t − c))`` is NaN for |t − c| < acos(1 − 1e-9) ≈ 4.47e-5, i.e. on a 8.9e-5 rad interval
about c); the bounds are the module constants, whose derivations are in their docstrings.
"""

import math
import re
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest

from coinwall import Wall, critical_offset, solve_body
from coinwall.forward import validation
from coinwall.forward.errors import CoinwallError, InvalidExpression, InvalidParameter, InvalidWall
from coinwall.forward.expression import parse_expression, parse_param, parse_params
from coinwall.forward.wall import MAX_MAGNITUDE, MAX_SAMPLES
from coinwall.forward.wallbackends import MAX_LSQ_SAMPLES
from coinwall.inverse.support import MAX_OFFSET_RATIO, check_offset, check_points

NAN_WALL = "1+0.1*sqrt(1-1e-9-cos(t-1.2358771881065316))"
NAN_CENTRE = 1.2358771881065316
NAN_HALF_WIDTH = math.acos(1 - 1e-9)  # 4.47e-5: where the argument of sqrt is negative


# ---------------------------------------------------------------- 1. poles between grid angles
@pytest.mark.parametrize("text, angle", [("2+tan(t)", math.pi / 2), ("1/(cos(t))", math.pi / 2),
                                         ("3+1/(sin(t-1))**2", 1.0), ("2+sqrt(abs(sin(t-2)))", 2.0),
                                         ("3+log(abs(sin(t-0.5))+1e-300)", 0.5)])
def test_pole_or_infinite_slope_is_refused_with_its_angle(text, angle):
    with pytest.raises(InvalidWall) as info:
        Wall.from_expression(text)
    message = str(info.value)
    assert "pole" in message or "infinite slope" in message
    shown = float(message.split("near θ = ")[1].split()[0])
    assert shown == pytest.approx(angle, abs=1e-6)


def test_nan_interval_between_grid_angles_is_refused_with_its_extent():
    with pytest.raises(InvalidWall, match="is not finite on θ in") as info:
        Wall.from_expression(NAN_WALL)
    lo, hi = (float(v) for v in str(info.value).split("θ in [")[1].split("]")[0].split(","))
    # the message prints 6 digits: the interval is NAN_CENTRE ± NAN_HALF_WIDTH to that precision
    assert lo == pytest.approx(NAN_CENTRE - NAN_HALF_WIDTH, abs=1e-5)
    assert hi == pytest.approx(NAN_CENTRE + NAN_HALF_WIDTH, abs=1e-5)


@pytest.mark.parametrize("text", [
    "(abs(cos(t))**(4/3) + abs(sin(t))**(4/3))**(3/4)",  # superellipse: b'' → +∞ at its flat points
    "sqrt(1+1e-6-cos(t))",                               # steep near 0, finite
    "2+tanh(1e3*sin(t-1))",                              # a step 1e-3 wide
    "2+abs(sin(t))",                                     # kinks
    "2+abs(sin(t))**1.5",                                # b'' unbounded, b' finite
    "1/(cos(t)+1.0000001)",                              # |b| up to 1e7, finite
    "1+0.1*cos(30*t)",
])
def test_steep_but_finite_walls_pass(text):
    wall = Wall.from_expression(text)
    assert math.isfinite(wall.scale)


def test_every_path_benefits_critical_solve_and_the_billiard():
    """The check lives in Wall construction, which critical, solve, fit (samples), wall --polar and the
    billiard's wall all go through."""
    from coinwall.forward.dynamics.billiard.table import Billiard

    for build in (lambda: critical_offset(Wall.from_expression("2+tan(t)")),
                  lambda: solve_body(Wall.from_expression(NAN_WALL), 0.0, points=2000),
                  lambda: Billiard(Wall.from_expression("2+tan(t)"), 10.0, 0.0)):
        with pytest.raises(InvalidWall):
            build()


def test_non_periodic_overflow_is_a_periodicity_error_not_a_pole():
    with pytest.raises(InvalidWall, match="not 2π-periodic"):
        Wall.from_expression("exp(5*t)")


# ---------------------------------------------------------------- 2. no non-finite body
def test_body_refuses_non_finite_numbers_naming_the_angle():
    import dataclasses

    body = solve_body(Wall.from_expression("1+0.1*cos(2*t)"), 0.0, points=64)
    x = body.x.copy()
    x[5] = np.nan
    with pytest.raises(InvalidWall, match="not finite near the normal angle θ = "):
        dataclasses.replace(body, x=x)
    with pytest.raises(InvalidWall, match="`b_c` is not finite"):
        dataclasses.replace(body, b_c=math.nan)
    assert dataclasses.replace(body, b_c=math.inf).b_c == math.inf  # a concave kink: a finding, allowed


def test_export_refuses_a_non_finite_outline_and_writes_nothing(tmp_path):
    from coinwall.forward.errors import InvalidOutline
    from coinwall.forward.outline import Outline
    from coinwall.inverse.export import export_body

    class Stored:  # a body read back from a file is not a checked Body
        outline = Outline(np.array([[1.0, 0.0], [np.nan, 1.0], [-1.0, 0.0]]), np.zeros((3, 2, 2)))
        b0, regime = 0.0, "convex"

    target = tmp_path / "x.csv"
    with pytest.raises(InvalidOutline, match="not finite at node 1"):
        export_body(Stored(), [str(target)])
    assert not target.exists()


# ---------------------------------------------------------------- 3. ranges with memory estimates
def test_b0_range_follows_the_walls_scale():
    assert check_offset(-1e-3) == -1e-3
    assert check_offset(0.9e8, scale=1.0) == 0.9e8
    for bad in (1e308, -1e308, 2 * MAX_OFFSET_RATIO):
        with pytest.raises(InvalidParameter, match="`b0` must be between"):
            check_offset(bad)
    assert check_offset(1e9, scale=100.0) == 1e9  # the bound scales with the wall
    for bad in (math.nan, math.inf, "1", True):
        with pytest.raises(InvalidParameter):
            check_offset(bad)


def test_points_are_counted_and_checked_against_memory(monkeypatch):
    with pytest.raises(CoinwallError, match="`points` must be an integer from 16 to"):
        check_points(10 ** 9)
    monkeypatch.setattr(validation, "available_memory", lambda: 100 * 2 ** 20)
    with pytest.raises(CoinwallError, match=r"`points` = 1000000 \(2560 bytes per point\) needs about 2.38 GiB"):
        check_points(1_000_000)
    assert check_points(1024) == 1024


def test_sample_count_bound_and_wall_magnitude():
    theta = np.linspace(0, 2 * np.pi, MAX_SAMPLES + 1, endpoint=False)
    with pytest.raises(InvalidWall, match=f"at most {MAX_SAMPLES}"):
        Wall.from_samples(theta, np.ones_like(theta))
    with pytest.raises(InvalidWall, match="would overflow"):
        Wall.from_expression("1e300*cos(t)**2+1e300")
    with pytest.raises(InvalidWall, match="would overflow"):
        Wall.from_samples(np.linspace(0, 6, 16), np.full(16, 10 * MAX_MAGNITUDE))


def test_a_body_far_below_kappa_is_refused_not_solved_into_nan():
    """Every body reaches at least κ from its centre of mass (κ² = J/M ≤ R_max²); 1e-300 gave NaN."""
    with pytest.raises(InvalidWall, match="smaller than 1e-06"):
        solve_body(Wall.from_expression("1e-300*(1+0.1*cos(2*t))"), 0.0)
    with pytest.raises(InvalidWall, match="centre of mass would lie outside"):  # that message still comes first
        solve_body(Wall.from_expression("-1+0.1*cos(t)"), 0.0)


# ---------------------------------------------------------------- 4. large sampled walls
def test_critical_of_many_non_uniform_samples_makes_no_interpolant():
    """10⁴ random angles of a smooth wall: the critical offset is the data's own geometry; the least-squares
    interpolant (n·k², minutes before) is never made.  b_c of 1 + 0.1 cos 2t + 0.05 sin 3t is
    −min(1 − 0.3 cos 2t − 0.4 sin 3t) (b + b'' in closed form), found here on a fine grid."""
    rng = np.random.default_rng(4)
    theta = np.sort(rng.uniform(0, 2 * np.pi, 10_000))
    b = 1 + 0.1 * np.cos(2 * theta) + 0.05 * np.sin(3 * theta)
    started = time.perf_counter()
    wall = Wall.from_samples(theta, b)
    result = critical_offset(wall)
    assert time.perf_counter() - started < 10
    assert wall._backend._fourier is None  # not made
    grid = np.linspace(0, 2 * np.pi, 200_001)
    exact = -np.min(1 - 0.3 * np.cos(2 * grid) - 0.4 * np.sin(3 * grid))
    assert result.b_c == pytest.approx(exact, abs=max(result.b_c_tolerance, 1e-5))


def test_too_many_non_uniform_samples_solve_from_the_lines_and_refuse_an_interpolant():
    rng = np.random.default_rng(5)
    theta = np.sort(rng.uniform(0, 2 * np.pi, MAX_LSQ_SAMPLES + 10))
    wall = Wall.from_samples(theta, 2 + 0.1 * np.cos(2 * theta))
    with pytest.raises(InvalidWall, match=f"takes at most {MAX_LSQ_SAMPLES}"):
        wall(0.3)


def test_lazy_interpolant_gives_the_same_numbers_and_scales():
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False) + 0.01 * np.sin(np.arange(64))
    wall = Wall.from_samples(theta, 1 + 0.1 * np.cos(2 * theta))
    scaled = wall.scaled(2.0)
    x = np.linspace(0, 6, 7)
    np.testing.assert_array_equal(scaled(x), 2.0 * np.asarray(Wall.from_samples(theta, 1 + 0.1 * np.cos(2 * theta))(x)))


# ---------------------------------------------------------------- 5. expressions
@pytest.mark.parametrize("text, code", [("ｓｉｎ(t)+2", "U+FF53"), ("2+𝐭", "U+1D42D"), ("2−cos(t)", "U+2212")])
def test_lookalike_unicode_is_refused_with_its_code_point(text, code):
    with pytest.raises(InvalidExpression, match=re.escape(code)) as info:
        parse_expression(text)
    assert "column" in str(info.value)


@pytest.mark.parametrize("literal", ["0x10", "1_0", "0o7", "0b1", "1j", "１"])
def test_expressions_and_params_share_the_decimal_grammar(literal):
    with pytest.raises((InvalidExpression, InvalidParameter)):
        parse_expression(f"2+{literal}*cos(t)")
    with pytest.raises(InvalidParameter):
        parse_param(f"eps={literal}")


@pytest.mark.parametrize("literal", ["16", "0.5", ".5", "5.", "1e-3", "2E+2"])
def test_decimal_literals_are_accepted_both_ways(literal):
    parsed = parse_expression(f"2+eps*cos(t)+{literal}*0", {"eps": parse_param(f"eps={literal}")[1]})
    assert dict(parsed.params)["eps"] == float(literal)


def test_params_are_finite_named_once_and_used():
    for bad in ("eps=inf", "eps=nan", "eps=1e999", "eps=-Infinity"):
        with pytest.raises(InvalidParameter, match="finite"):
            parse_param(bad)
    with pytest.raises(InvalidParameter, match="given twice"):
        parse_params(["eps=1", "eps=2"])
    with pytest.raises(InvalidParameter, match="not used"):
        parse_expression("2+cos(t)", parse_params(["eps=1"]))


# ---------------------------------------------------------------- 6. no NumPy warnings
@pytest.mark.parametrize("text", ["2+tan(t)", NAN_WALL, "1/(cos(t))", "log(cos(t)+1)", "sqrt(cos(t))", "exp(100*t)"])
def test_bad_walls_raise_without_warnings(text):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InvalidWall):
            critical_offset(Wall.from_expression(text))


@pytest.mark.parametrize("argv", [["critical", "2+tan(t)"], ["solve", NAN_WALL, "--points", "2000"],
                                  ["solve", "1+0.1*cos(2*t)", "--b0", "1e308"], ["critical", "ｓｉｎ(t)+2"],
                                  ["wall", "--polar", "1/(cos(t))"]])
def test_cli_exit_2_with_one_line(argv, tmp_path):
    out = tmp_path / "x.csv"
    done = subprocess.run([sys.executable, "-m", "coinwall", *argv, "-o", str(out)] if argv[0] == "solve"
                          else [sys.executable, "-m", "coinwall", *argv], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path, check=False)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("coinwall: error: ")
    assert not out.exists()


# --------------------------------------------------------------------- found by the large fuzz run (docs/cli-limits.md)

def _square_support(theta, corners):
    """Support function of the convex polygon ``corners`` about the origin: max over its vertices of x·n(θ)."""
    return np.max(np.cos(theta)[:, None] * corners[:, 0] + np.sin(theta)[:, None] * corners[:, 1], axis=1)


def test_samples_with_the_centre_of_mass_on_the_boundary_give_the_body():
    """Support lines through the centre of mass (h = 0 at some angles) used to divide by zero in the polar dual
    and in Qhull's half-plane intersection.  The unit square with its centre of mass at a corner: the body is
    that square (reference: the square's vertices, computed here by hand)."""
    theta = np.linspace(0.0, 2 * np.pi, 90, endpoint=False)
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    wall = Wall.from_samples(theta, _square_support(theta, square))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no divide-by-zero warning on the way
        body = solve_body(wall, 0.0)
    nodes = np.asarray(body.outline.nodes)
    # every node lies on the square's boundary, and every corner of the square is a node
    on_edge = np.min(np.stack([np.abs(nodes[:, 0]), np.abs(nodes[:, 0] - 1), np.abs(nodes[:, 1]),
                               np.abs(nodes[:, 1] - 1)]), axis=0)
    assert np.max(on_edge) < 1e-9 and np.all((nodes > -1e-9) & (nodes < 1 + 1e-9))
    for corner in square:
        assert np.min(np.hypot(*(nodes - corner).T)) < 1e-9


def test_an_offset_that_leaves_a_segment_is_refused_in_one_line():
    """b = 1 + 0.1 cos 2θ at b0 = −0.9: h = 0.2 cos²θ, the lines enclose the segment |x| ≤ 0.2 (no area)."""
    from coinwall.forward.errors import InvalidWall

    with pytest.raises(InvalidWall, match="enclose no area"):
        solve_body(Wall.from_expression("1+0.1*cos(2*t)"), -0.9)


def test_export_tolerance_must_be_below_a_tenth_of_the_body(tmp_path):
    from coinwall.forward.errors import InvalidArgument
    from coinwall.inverse.export import export_body

    body = solve_body(Wall.from_expression("1+0.1*cos(2*t)"), 0.0)
    for name in ("b.csv", "b.svg"):  # also for CSV, which does not approximate
        with pytest.raises(InvalidArgument, match="tenth of the body's diameter"):
            export_body(body, [str(tmp_path / name)], tolerance=1e308)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("density,message", [("", "is empty"), ("1e308", "up to 1e\\+100")])
def test_density_empty_or_huge_is_refused(density, message):
    from coinwall import mass_properties
    from coinwall.forward.errors import CoinwallError

    body = solve_body(Wall.from_expression("1+0.1*cos(2*t)"), 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(CoinwallError, match=message):
            mass_properties(body.outline, density)


def test_a_dip_narrower_than_the_grid_is_found_by_critical():
    """b = 2 + tanh(k sin(θ − 1)), k = 1e5: b + b'' dips to about −4k²/(3√3) within 1e-5 rad of θ = 1 and
    θ = 1 + π, far narrower than the 8192-point grid (7.7e-4 rad); the grid alone reported b_c = −1.
    Reference: the same b + b'' written out by hand, b'' = −k sech²(u) sin(θ−1) − 2k² tanh(u) sech²(u) cos²(θ−1)
    with u = k sin(θ−1), minimised on 2·10⁶ points across the dip with numpy (independent of casadi)."""
    k = 1e5
    c = critical_offset(Wall.from_expression("2+tanh(1e5*sin(t-1))"))
    delta = np.linspace(-5e-5, 5e-5, 2_000_001)
    s, co = np.sin(delta), np.cos(delta)
    u = k * s
    sech2 = 1.0 / np.cosh(u) ** 2
    reference = -np.min(2 + np.tanh(u) - k * sech2 * s - 2 * k * k * np.tanh(u) * sech2 * co * co)
    assert reference == pytest.approx(4 * k * k / (3 * math.sqrt(3)), rel=1e-5)  # the closed-form leading term
    assert c.b_c == pytest.approx(reference, rel=1e-9)
    assert min(abs(a - 1.0) for a in c.angles) < 1e-5 and min(abs(a - 1.0 - math.pi) for a in c.angles) < 1e-5
