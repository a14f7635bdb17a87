"""Walls as data as people write them: every sample an interval, b_c a certified interval.

Every reference value comes from ``tests/walldata.py`` (numpy/scipy only, never coinwall): a polygon's and a
Reuleaux polygon's support function and their vertices, the closed-form cam laws with their exact ``b_c``
(``−min(s + s'')`` over both one-sided values at the laws' breaks), the paper's wall (an ellipse: ``b_c =
−1/(1+ε)``), a true ellipse (``b_c = −b²/a``) and a stadium (``b_c = −r``).  The data are written as a CSV
with a given number of digits (angles too) and read back by ``coinwall``, as a user's file would be.

What is promised, and tested on every case: the certified interval ``[b_c_lower, b_c_upper]`` contains the
true ``b_c``; the regime is the true one or the data say they cannot decide (the true one among those they
allow); the corners reported are the true corners.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import walldata as W

from coinwall import Wall, critical_offset, solve_body
from coinwall.cases.cli.main import main
from coinwall.forward.errors import InvalidWall
from coinwall.forward.formats import load_wall
from coinwall.forward.sampledata import sample_intervals


def _solve_csv(tmp_path, capsys, written, *args):
    path = tmp_path / "wall.csv"
    path.write_text(written.text)
    code = main(["solve", str(path), "--json", *args])
    captured = capsys.readouterr()
    assert code in (0, 1), captured.err
    return code, json.loads(captured.out)


def _true_regime(b0, b_c):
    return "corner" if b0 < b_c - 1e-12 else ("critical" if abs(b0 - b_c) <= 1e-12 else "convex")


def _check(doc, ref, b0=0.0):
    """The promise: the interval holds the truth, the regime is right or honestly undecided."""
    assert doc["b_c_lower"] <= ref.b_c <= doc["b_c_upper"], (doc["b_c_lower"], ref.b_c, doc["b_c_upper"])
    assert _true_regime(b0, ref.b_c) in doc["regimes"]
    if doc["regime_decided"]:
        assert doc["regime"] == _true_regime(b0, ref.b_c)


# ---------------------------------------------------------------------------------------------- polygons, Reuleaux
@pytest.mark.parametrize("make, samples", [
    (lambda n: W.polygon(None, n), 200), (lambda n: W.polygon(None, n), 1000),
    pytest.param(lambda n: W.polygon(None, n), 5000, marks=pytest.mark.slow),
    (lambda n: W.reuleaux(5, n), 720), pytest.param(lambda n: W.reuleaux(5, n), 5000, marks=pytest.mark.slow),
    (lambda n: W.reuleaux(3, n), 200), pytest.param(lambda n: W.polygon(7, n, phase=0.3), 2000, marks=pytest.mark.slow),
])
def test_polygons_at_six_significant_digits(tmp_path, capsys, make, samples):
    """θ and b written with 6 significant digits: the regime at b0 = 0 (truly critical) is undecided or
    critical, never a silent "corner"; every vertex comes back once, where it is (to the data's resolution);
    the body's wall is within the samples' intervals at every sample (exit 0, no warning)."""
    ref = make(samples)
    code, doc = _solve_csv(tmp_path, capsys, W.write_rounded(ref, 6, theta_digits=6))
    _check(doc, ref)
    assert code == 0 and doc["warnings"] == []
    assert len(doc["corners"]) == ref.corners
    found = np.array([[c["distance"] * np.cos(c["direction"]), c["distance"] * np.sin(c["direction"])]
                      for c in doc["corners"]])
    vertices = ref.vertices
    distance = np.hypot(*(found[:, None, :] - vertices[None, :, :]).transpose(2, 0, 1))
    # each true vertex has its corner within 1e-3 of the size (6 digits: the lines' positions to ~5e-6, their
    # intersections to ~5e-6/sin(gap))
    assert distance.min(axis=0).max() < 1e-3 * np.abs(vertices).max()


def test_the_nine_gon_written_at_six_digits_is_one_outline(tmp_path, capsys):
    """The case that used to come back with a vertex twice and an edge sliver: the outline is within the
    data's resolution of the true polygon everywhere (Hausdorff distance computed by shapely from the true
    vertices), and its area to 1e-5."""
    from shapely.geometry import Polygon

    ref = W.polygon(None, 200)
    path = tmp_path / "nine.csv"
    path.write_text(W.write_rounded(ref, 6, theta_digits=6).text)
    body = solve_body(load_wall(str(path)), 0.0)
    truth = Polygon(ref.vertices)
    outline = Polygon(body.outline.polygon(4))
    assert outline.hausdorff_distance(truth) < 1e-4
    assert abs(outline.area - truth.area) < 1e-5 * truth.area * 10


# ---------------------------------------------------------------------------------------------------- cams
@pytest.mark.parametrize("law", ["cycloidal", "345", "modified-trapezoid", "shm"])
@pytest.mark.parametrize("samples, b_digits, theta_decimals", [
    (360, None, None),  # 1°, 17 digits
    (3600, None, None),  # 0.1°, 17 digits
    (360, 6, 0),  # a rounded table: whole degrees, 6 significant digits of the lift
])
def test_cams(tmp_path, capsys, law, samples, b_digits, theta_decimals):
    """Cams (rise over 60°): the certified interval holds the exact b_c (the modified trapezoid at 1° was
    3.71509 ± 0.0036 against the truth 3.726960); at a base radius 0.5 above the interval's top the body is
    convex with no corner; below the interval's bottom the data certainly need corners."""
    ref = W.cam(law, samples)
    written = W.write_rounded(ref, b_digits)
    if theta_decimals is not None:  # a table: whole degrees, the lift to b_digits significant digits
        text = "theta_deg,b\n" + "".join(f"{t:.0f},{v:.{b_digits}g}\n" for t, v in zip(np.degrees(ref.theta), ref.b))
        written = W.Written(text, None, None, None, "theta_deg,b")
    code, doc = _solve_csv(tmp_path, capsys, written, "--b0", "0")
    _check(doc, ref)
    base = doc["b_c_upper"] + 0.5
    code, doc = _solve_csv(tmp_path, capsys, written, "--b0", repr(base))
    _check(doc, ref, base)
    assert doc["regime"] == "convex" and doc["corners"] == [] and code == 0


@pytest.mark.parametrize("law", ["345", "modified-trapezoid"])
def test_cam_with_its_centre_on_the_boundary_stays_under_every_sample(tmp_path, capsys, law):
    """0.1° with 4-decimal values at b0 = 0, where the dwell puts the centre of mass on the outline (h = 0 over
    a third of the turn): the corner at the top of the rise governs a 1.5-rad window.  The least-squares point
    of the lines through it used to lie 0.0087 beyond the window's edge line (exit 1: "wall differs by 0.00875").
    The body's own support function, computed here from its outline nodes with numpy, must not exceed any
    sample by more than the samples' rounding plus the reported accuracy, and the run must be clean."""
    ref = W.cam(law, 3600)
    written = W.write_rounded(ref, 4, theta_digits=1, degrees=True, mode="decimals")
    path = tmp_path / "cam.csv"
    path.write_text(written.text)
    body = solve_body(load_wall(str(path)), 0.0)
    assert body.warnings == ()
    theta, b = written.radians, written.b
    nodes = np.column_stack([body.x, body.y])
    support = np.max(np.outer(np.cos(theta), nodes[:, 0]) + np.outer(np.sin(theta), nodes[:, 1]), axis=1)
    assert np.max(support - b) <= 0.5e-4 + body.accuracy
    _check({"b_c_lower": body.b_c_lower, "b_c_upper": body.b_c_upper, "regimes": body.regimes,
            "regime_decided": body.regime_decided, "regime": body.regime}, ref)


def test_modified_trapezoid_truth_is_in_the_interval_from_the_issue():
    """The modified-trapezoid cam at 1°: truth 3.7269596 (walldata's closed form; the discrete curvature of
    the 360 lines gives 3.711452, below it: the minimum falls between samples, near a jump of ρ'')."""
    ref = W.cam("modified-trapezoid", 360)
    assert ref.b_c == pytest.approx(3.726960, abs=5e-7)
    result = critical_offset(Wall.from_samples(ref.theta, ref.b))
    assert result.lower <= ref.b_c <= result.upper
    assert result.upper - result.lower < 0.1


# ------------------------------------------------------------------------------------------- smooth walls, dense data
@pytest.mark.parametrize("samples, digits", [pytest.param(5000, 6, marks=pytest.mark.slow), (200, 6), (720, 4)])
def test_stadium_and_paper_wall_rounded(tmp_path, capsys, samples, digits):
    """A stadium (b_c = −0.5; was 19.99 ± 17 at 5,000 samples, 6 digits) and the paper's wall at ε = 1: where
    the data decide (convex at b0 = 0), no corner; 4 digits at 0.5° leave b_c between about −0.5 and above 0,
    and the answer says so."""
    for ref in (W.smooth("stadium", samples, half_length=1.0, radius=0.5), W.smooth("paper", samples, eps=1.0)):
        code, doc = _solve_csv(tmp_path, capsys, W.write_rounded(ref, digits, theta_digits=digits))
        _check(doc, ref)
        assert code == 0
        if doc["regime_decided"]:
            assert doc["regime"] == "convex" and doc["corners"] == []
        else:
            assert digits == 4 and doc["b_c_upper"] > 0  # 4 digits at 0.5°: the data cannot decide


@pytest.mark.parametrize("count, decimals", [(10_000, 4), (10_000, 8), (10_000, None),
                                             pytest.param(100_000, 4, marks=pytest.mark.slow),
                                             pytest.param(100_000, 8, marks=pytest.mark.slow), (1_000_000, 8),
                                             pytest.param(1_000_000, None, marks=pytest.mark.slow),
                                             pytest.param(1_000_000, 4, marks=pytest.mark.slow)])
def test_random_angles_as_written(count, decimals):
    """Random angles (and values) written with 4, 8 or 17 digits; at 4 decimals up to a sixth of 10⁵ angles
    round to the same value and are merged as intervals.  The ellipse (1.25, 0.8): b_c = −0.8²/1.25."""
    ref = W.smooth("ellipse", W.random_angles(count, seed=count), semi_axes=(1.25, 0.8))
    theta, b = ref.theta, ref.b
    if decimals is not None:
        theta, b = np.round(theta, decimals), np.round(b, decimals)
        half = 0.5 * 10.0**-decimals
        wall = Wall.from_samples(theta, b, rounding=half, theta_rounding=half)
    else:
        wall = Wall.from_samples(theta, b)
    body = solve_body(wall, 0.0)
    assert body.b_c_lower <= ref.b_c <= body.b_c_upper
    assert body.regime == "convex" and body.corners == () and not body.warnings


def test_duplicates_are_merged_and_a_contradiction_is_named(tmp_path, capsys):
    """Repeated rows are merged (their intervals intersected); two readings at one angle that cannot both hold
    are named by their line numbers."""
    ref = W.polygon(None, 360)
    theta, b = W.with_duplicates(ref.theta, ref.b, seed=1, fraction=0.2)
    data = sample_intervals(theta, b, 5e-7, 0.0)
    assert data.merged == theta.size - 360 and data.theta.size == 360
    theta, b, copies = W.with_duplicates(ref.theta, np.round(ref.b, 6), seed=2, fraction=0.05, return_indices=True)
    b = b.copy()
    b[copies[3]] += 1e-3
    text = "theta,b\n" + "".join(f"{float(t)!r},{v:.6f}\n" for t, v in zip(theta, b))
    path = tmp_path / "dup.csv"
    path.write_text(text)
    assert main(["critical", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"line {copies[3] + 2}" in err and f"line {copies[3] + 1}" in err and "disagree" in err
    assert len(err.strip().splitlines()) == 1


def test_interval_widths_are_honest_about_the_digits():
    """The same polygon at 17 digits, 8 and 5: the certified interval holds 0 every time and widens with
    fewer digits (a check that could not pass by an interval that ignores the data)."""
    ref = W.polygon(None, 720)
    widths = []
    for digits in (None, 8, 5):
        written = W.write_rounded(ref, digits, theta_digits=digits)
        rounding = None if digits is None else 0.5 * 10.0 ** (np.floor(np.log10(np.abs(written.b))) + 1 - digits)
        theta_rounding = None if digits is None else 0.5 * 10.0 ** (
            np.floor(np.log10(np.maximum(np.abs(written.theta), 1e-300))) + 1 - digits)
        result = critical_offset(Wall.from_samples(written.theta, written.b, rounding=rounding,
                                                   theta_rounding=theta_rounding))
        assert result.lower <= 0.0 <= result.upper
        widths.append(result.upper - result.lower)
    assert widths[0] < 1e-9 < widths[1] < widths[2]


def test_angle_rounding_is_in_the_error_model():
    """Angles written with 4 decimals move each support line by up to |h'|·5e-5: with the angles' rounding
    the interval holds the truth; taking the same angles as exact would not be honest (and here it is not:
    the face-value interval misses the truth), which is what the angles' half-width is for."""
    ref = W.polygon(None, 3000)
    theta = np.round(ref.theta, 4)
    b = np.round(ref.b, 8)
    honest = critical_offset(Wall.from_samples(theta, b, rounding=5e-9, theta_rounding=5e-5))
    assert honest.lower <= 0.0 <= honest.upper
    blind = critical_offset(Wall.from_samples(theta, b, rounding=5e-9))
    assert not blind.lower <= 0.0 <= blind.upper


def test_bad_half_widths_are_refused():
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    with pytest.raises(InvalidWall, match="b_halfwidth"):
        Wall.from_samples(theta, 1 + 0 * theta, rounding=-1.0)
    with pytest.raises(InvalidWall, match="theta_halfwidth"):
        Wall.from_samples(theta, 1 + 0 * theta, theta_rounding=np.nan)


def test_half_width_flags_and_columns(tmp_path, capsys):
    """--b-halfwidth widens the interval; a b_halfwidth column does the same per sample; a designed grid of
    whole degrees is exact (no angle rounding); the ambiguous --sigma-b and sigma_b column are refused with a
    line that names both meanings."""
    ref = W.smooth("paper", 360, eps=1.0)
    degrees = np.degrees(ref.theta)
    path = tmp_path / "w.csv"
    path.write_text("theta_deg,b\n" + "".join(f"{t:.0f},{float(v)!r}\n" for t, v in zip(degrees, ref.b)))
    assert main(["critical", str(path), "--json"]) == 0
    tight = json.loads(capsys.readouterr().out)
    assert main(["critical", str(path), "--json", "--b-halfwidth", "1e-4"]) == 0
    wide = json.loads(capsys.readouterr().out)
    assert tight["b_c_upper"] - tight["b_c_lower"] < 0.01 < wide["b_c_upper"] - wide["b_c_lower"]
    for doc in (tight, wide):
        assert doc["b_c_lower"] <= ref.b_c <= doc["b_c_upper"]
    column = tmp_path / "c.csv"
    column.write_text("theta_deg,b,b_halfwidth\n" + "".join(
        f"{t:.0f},{float(v)!r},1e-4\n" for t, v in zip(degrees, ref.b)))
    assert main(["critical", str(column), "--json"]) == 0
    from_column = json.loads(capsys.readouterr().out)
    assert from_column["b_c_lower"] == pytest.approx(wide["b_c_lower"], rel=1e-9)
    assert main(["critical", "1 + 0.1*cos(2*t)", "--b-halfwidth", "0.1"]) == 2
    assert "sample files" in capsys.readouterr().err
    assert main(["critical", str(path), "--sigma-b", "1e-4"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--b-halfwidth" in err and "--b-sd" in err
    ambiguous = tmp_path / "a.csv"
    ambiguous.write_text(column.read_text().replace("b_halfwidth", "sigma_b", 1))
    assert main(["critical", str(ambiguous)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "b_halfwidth" in err and "b_sd" in err


def test_the_interval_is_a_promise_over_many_walls():
    """A seeded sweep over walls and ways of writing them (polygons of 3–8 vertices, Reuleaux 3/5/7, the four
    cams, ellipses; 90–3,000 uniform or random angles; 4–17 digits, angles rounded too): the certified
    interval holds the true b_c every time, and wherever the data decide the regime at b0 = 0 it is the true
    one.  60 cases, each truth from walldata's closed forms."""
    rng = np.random.default_rng(2026)
    misses = []
    for case in range(60):
        kind = rng.choice(["polygon", "reuleaux", "cam", "ellipse"])
        samples = int(rng.integers(90, 3000))
        random = bool(rng.random() < 0.3)
        seed = int(rng.integers(1 << 30))
        if kind == "polygon":
            ref = W.polygon(W.random_polygon(int(rng.integers(3, 9)), seed=seed), samples, random_angles=random,
                            seed=seed)
        elif kind == "reuleaux":
            ref = W.reuleaux(int(rng.choice([3, 5, 7])), samples, phase=float(rng.uniform(0, 1)),
                             random_angles=random, seed=seed)
        elif kind == "cam":
            ref = W.cam(str(rng.choice(list(W.CAM_LAWS))), samples, random_angles=random, seed=seed)
        else:
            a = float(rng.uniform(1.0, 2.0))
            ref = W.smooth("ellipse", samples, semi_axes=(a, float(rng.uniform(0.4, 1.0)) * a))
        digits = int(rng.choice([4, 5, 6, 8, 17]))
        written = W.write_rounded(ref, None if digits == 17 else digits,
                                  theta_digits=None if digits == 17 else digits)
        if digits == 17:
            make = (written.theta, written.b), {}
        else:
            def half(values):
                exponent = np.floor(np.log10(np.maximum(np.abs(values), 1e-300)))
                return np.where(values == 0, 0.5 * 10.0 ** (-digits), 0.5 * 10.0 ** (exponent + 1 - digits))
            make = (written.theta, written.b), {"rounding": half(written.b), "theta_rounding": half(written.theta)}
        try:
            wall = Wall.from_samples(*make[0], **make[1])
            result = critical_offset(wall)
        except InvalidWall as exc:  # a few random angles may leave a gap the reader refuses, with its reason
            assert "does not cover a full period" in str(exc)
            continue
        regimes = result.regimes(0.0, wall.scale)
        if not (result.lower <= ref.b_c <= result.upper) or _true_regime(0.0, ref.b_c) not in regimes:
            misses.append((case, ref.name, samples, random, digits, result.lower, ref.b_c, result.upper))
    assert misses == []


def test_a_drawn_circle_carries_its_flattening(tmp_path, capsys):
    """A circle of radius 20 drawn in SVG, its wall written at 20,000 angles: the reader flattens the circle to
    a chord error of 1e-8 of its size, and the wall file says so (a b_halfwidth column), so the certified interval
    holds the circle's own b_c = −20 exactly (it said −19.8012 ± 4.6e-07 when the file pretended to be exact)."""
    svg = tmp_path / "circle.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
                   '<circle cx="50" cy="50" r="20"/></svg>')
    wall = tmp_path / "circle.csv"
    assert main(["wall", str(svg), "--samples", "20000", "-o", str(wall)]) == 0
    capsys.readouterr()
    assert wall.read_text().splitlines()[0] == "theta,b,b_halfwidth"
    assert main(["critical", str(wall), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["b_c_lower"] <= -20.0 <= doc["b_c_upper"] and doc["b_c_upper"] - doc["b_c_lower"] < 1e-2


def test_an_angle_rounded_past_two_pi_is_not_taken_for_degrees(tmp_path, capsys):
    """An angle just below 2π written to 4 decimals is 6.2832 > 2π: within its rounding, so the file is read
    (it was refused as "more than 2π radians: are they degrees?")."""
    ref = W.smooth("ellipse", 400, semi_axes=(1.25, 0.8))
    path = tmp_path / "w.csv"
    path.write_text("theta,b\n" + "".join(f"{t:.4f},{v:.4f}\n" for t, v in zip(ref.theta, ref.b)) + "6.2832,1.2500\n")
    assert main(["critical", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["b_c_lower"] <= ref.b_c <= doc["b_c_upper"]


# ---------------------------------------------------------------------------------------------- the body's wall
def _outside_intervals(body, theta, h, w):
    """How far the body's wall leaves ``h ± w``, computed here from its outline's points (numpy: the support
    function of a polygon is the largest projection of its vertices; a Case III cut window may lie below)."""
    points = body.outline.polygon(8)
    wall = np.max(np.cos(theta)[:, None] * points[:, 0] + np.sin(theta)[:, None] * points[:, 1], axis=1)
    inside = np.zeros(theta.size, bool)
    for corner in body.corners:
        if corner.max_deficit > 0:
            lo, hi = corner.window
            inside |= np.mod(theta - lo, 2 * np.pi) <= hi - lo
    return float(np.max(np.where(inside, wall - h, np.abs(wall - h)) - w))


@pytest.mark.parametrize("eps, digits, noise", [
    (0.5, 3, 0.0), (1.0, 4, 0.0), (3.0, 4, 0.0), (1.0, 6, 0.0), (0.5, None, 1e-3), (3.0, None, 1e-2),
])
@pytest.mark.parametrize("b0", [0.0, -0.3])
def test_the_body_stays_inside_the_samples_intervals(eps, digits, noise, b0):
    """The ellipse wall at 1°, rounded to 3, 4 or 6 decimals (half-width: half the last digit) or with Gaussian
    noise σ declared as ±3σ: the body's wall lies within every sample's interval (to 1e-9 of the size, the
    half-plane geometry's rounding), outside the windows of corners that cut the data.  Measured before this
    was checked: 3.8 half-widths from the samples at 4 decimals, 3.6 with noise (the vertices were fitted to their lines
    within 4 half-widths); now the check is part of the solve, and a body that leaves the intervals warns."""
    theta = np.radians(np.arange(360.0))
    b = np.sqrt((1 + eps * np.cos(theta) ** 2) / (1 + eps))
    if noise:
        b = b + np.random.default_rng(7).normal(0.0, noise, theta.size)
        w = np.full(theta.size, 3.0 * noise)
    else:
        b = np.round(b, digits)
        w = np.full(theta.size, 0.5 * 10.0**-digits)
    body = solve_body(Wall.from_samples(theta, b, rounding=w), b0)
    assert body.warnings == ()
    assert _outside_intervals(body, theta, b0 + b, w) <= 1e-9


def test_a_body_outside_the_intervals_is_named():
    from coinwall.forward.outline import Outline
    from coinwall.inverse.sampled import interval_excess

    # the unit square's wall against samples 0.01 too low at θ = 0 (half-width 0.001): 0.009 outside there
    square = Outline.from_polygon(np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]]))
    theta = np.array([0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi])
    excess, where = interval_excess(square, theta, np.array([0.99, 1.0, 1.0, 1.0]), np.full(4, 1e-3), [], True)
    assert excess == pytest.approx(0.009) and where == 0.0
    # inside a cut window only a wall above the interval counts
    excess, _ = interval_excess(square, theta, np.array([1.5, 1.0, 1.0, 1.0]), np.full(4, 1e-3), [(-0.1, 0.1)], True)
    assert excess < 0


def test_the_region_of_a_long_merge_stays_small_and_inside_every_strip():
    """1,000 lines turning slowly through a common point (a vertex window of rounded data): the region of
    points within every line's interval is kept to a few vertices (clipping it again and again was quadratic:
    50,000 rounded samples took 15.7 s), and its centroid is within every interval."""
    from coinwall.inverse.discrete import MAX_REGION_VERTICES, _clip_strip, _parallelogram

    rng = np.random.default_rng(3)
    theta = np.linspace(0.2, 1.4, 1000)
    point = np.array([0.7, -0.3])
    tol = np.full(theta.size, 1e-4)
    h = np.cos(theta) * point[0] + np.sin(theta) * point[1] + rng.uniform(-0.9, 0.9, theta.size) * tol
    region = _parallelogram(theta[0], h[0], tol[0], theta[-1], h[-1], tol[-1])
    for k in range(1, theta.size - 1):
        region = _clip_strip(region, theta[k], h[k], tol[k])
        assert 3 <= len(region) <= MAX_REGION_VERTICES
    centre = np.mean(region, axis=0)
    assert np.all(np.abs(h - np.cos(theta) * centre[0] - np.sin(theta) * centre[1]) <= tol)


def test_dense_rounded_data_give_a_body_inside_every_interval():
    """150,000 samples of an off-centre ellipse at 4 decimals: the body stays inside every sample's interval
    (an independent look at every 50th sample with numpy), and the true outline (the closed-form support of the
    shifted ellipse) is within the reported outline tolerance (this came back as a body 1 half-width outside
    the intervals with a note while the body was built from thinned samples)."""
    n = 150_000
    theta = np.arange(n) * 2 * np.pi / n
    exact = np.sqrt((2 * np.cos(theta)) ** 2 + np.sin(theta) ** 2) + 0.05 * np.cos(theta)
    b = np.round(exact, 4)
    body = solve_body(Wall.from_samples(theta, b, rounding=np.full(n, 5e-5)), 0.0)
    assert body.warnings == ()
    assert _outside_intervals(body, theta[::50], b[::50], np.full(theta[::50].size, 5e-5)) <= 1e-9
    assert np.max(np.abs(body.outline.support(theta[::7]) - exact[::7])) <= body.outline_tolerance
