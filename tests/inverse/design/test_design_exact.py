"""The exact toss models (drop, flip) and their solvers against closed forms and independent computations.

References: the planar drop of a d × h rectangle, P(edge) = (2/π) atan(h/d) (the angle the edge subtends at
the centre, docs/design.md); the dropped cylinder, P(edge) = (h/2)/√(r² + h²/4) (the solid angle of the rim
band, docs/design.md); a polygon's face subtends the angle between its vertices' directions (numpy atan2,
independent of the wall machinery); the flip's first-contact rule brute-forced on a grid of angles.
"""

import math

import numpy as np
import pytest

from coinwall.forward.errors import CoinwallError, InvalidArgument
from coinwall.forward.revolution import coin
from coinwall.forward.wall import Wall
from coinwall.inverse.design import Drop, Family, Flip, design, odds, planar_valleys, resimulate

RECT = "abs(cos(t)) + h*abs(sin(t))"  # a 2 × 2h rectangle: the three-sided coin


def rectangle_edge(d, h):
    return 2 / math.pi * math.atan(h / d)


def cylinder_edge(r, h):
    return (h / 2) / math.sqrt(r * r + h * h / 4)


@pytest.mark.parametrize("a,c", [(1.0, 0.5), (1.0, 1 / math.sqrt(3)), (2.5, 0.3), (0.7, 1.9), (1.2345, 0.0417)])
def test_drop_rectangle_closed_form(a, c):
    """A 2a × 2c rectangle (edges of length 2c at θ = 0, π): P(edge) = (2/π) atan(c/a) to 1e-12."""
    wall = Wall.from_expression("a*abs(cos(t)) + c*abs(sin(t))", {"a": a, "c": c})
    got = Drop().odds("planar", wall, ["edge", "heads", "tails"])
    assert abs(got["edge"] - rectangle_edge(a, c)) < 1e-12
    assert abs(got["heads"] - got["tails"]) < 1e-12
    assert abs(sum(got.values()) - 1) < 1e-12


@pytest.mark.parametrize("r,h", [(1.0, 0.1), (1.0, 2 / math.sqrt(8)), (0.012, 0.00175), (3.0, 7.5)])
def test_drop_cylinder_closed_form(r, h):
    got = Drop().odds("cylinder", coin(r, h), ["edge", "heads", "tails"])
    assert abs(got["edge"] - cylinder_edge(r, h)) < 1e-12
    assert abs(got["heads"] - got["tails"]) < 1e-12


def test_drop_rounded_cylinder():
    """Rounding ε: the rim band ends where the inner rectangle's corner is below the centre, tan a = (r−ε)/(d−ε)."""
    r, h, eps = 1.0, 0.6, 0.1
    a = math.atan((r - eps) / (h / 2 - eps))
    got = Drop().odds("cylinder", coin(r, h, eps), ["edge"])
    assert abs(got["edge"] - math.cos(a)) < 1e-12


def test_three_sided_coin_designs():
    """The issue's designs: h/d = 1/√3 (planar drop, and the flip), h/(2r) = 1/(2√2) (dropped cylinder),
    thickness/diameter = 1/√3 (the cylinder flipped about a diameter), each to 1e-9 with the interval around it."""
    planar = Family("planar", RECT, {"h": (0.05, 3.0)})
    for model in (Drop(), Flip()):
        d = design(planar, {"edge": 1 / 3}, model)
        assert abs(d.x[0] - 1 / math.sqrt(3)) < 1e-9
        lo, hi = d.interval[0]
        assert lo <= 1 / math.sqrt(3) <= hi and hi - lo <= 2.1e-10
        assert all(abs(p - 1 / 3) < 1e-9 for p, _ in d.probabilities.values())
    cylinder = Family("cylinder", None, {"thickness": (0.05, 3.0)}, {"radius": 1.0})
    d = design(cylinder, {"edge": 1 / 3}, Drop())
    assert abs(d.x[0] / 2 - 1 / (2 * math.sqrt(2))) < 1e-9
    d = design(cylinder, {"edge": 1 / 3}, Flip())
    assert abs(d.x[0] / 2 - 1 / math.sqrt(3)) < 1e-9


def test_design_at_other_targets_and_radius():
    """P(edge) = 0.1 for a cylinder of radius 2.5: h from the closed form, h = 2 r p/√(1 − p²)."""
    p, r = 0.1, 2.5
    d = design(Family("cylinder", None, {"thickness": (0.01, 10.0)}, {"radius": r}), {"edge": p}, Drop())
    assert abs(d.x[0] - 2 * r * p / math.sqrt(1 - p * p)) < 1e-9
    d = design(Family("planar", "a*abs(cos(t)) + c*abs(sin(t))", {"c": (0.01, 5.0)}, {"a": 1.7}), {"heads": 0.4},
               Drop())
    assert abs(d.x[0] - 1.7 * math.tan(math.pi * 0.1)) < 1e-9  # edge = 0.2: (2/π) atan(c/a) = 0.2


def _polygon(vertices, digits):
    """The support function of a polygon as a user writes it: max of r_i cos(t − φ_i), numbers rounded."""
    terms = [f"{round(r, digits)}*cos(t - {round(p, digits)})" for r, p in vertices]
    text = terms[0]
    for term in terms[1:]:
        text = f"max({text}, {term})"
    return text


def _random_polygon(rng, digits):
    """Vertices (r, φ) rounded to ``digits``, each the farthest point of the polygon in its own direction
    (r_j cos(φ_j − φ_i) < r_i: every vertex direction is a maximum of b, so every face holds a valley)."""
    while True:
        phis = np.round(np.sort(rng.uniform(0, 2 * np.pi, 5)), digits)
        radii = np.round(rng.uniform(0.8, 1.2, 5), digits)
        gaps = np.diff(np.r_[phis, phis[0] + 2 * np.pi])
        proj = radii[None, :] * np.cos(phis[None, :] - phis[:, None])
        np.fill_diagonal(proj, -np.inf)
        if gaps.max() < 0.9 * np.pi and np.all(proj.max(axis=1) < radii - 1e-3):
            return radii, phis


@pytest.mark.parametrize("digits", [4, 6, 8])
def test_drop_polygon_written_with_rounded_numbers(digits):
    """An irregular pentagon given by rounded vertices: each face's P is the angle between its vertices'
    directions (numpy, from the rounded numbers themselves), to 1e-12."""
    radii, phis = _random_polygon(np.random.default_rng(digits), digits)
    wall = Wall.from_expression(_polygon(zip(radii, phis), digits))
    valleys, p = Drop().valley_odds("planar", wall)
    expected = np.diff(np.r_[phis, phis[0] + 2 * np.pi]) / (2 * np.pi)
    assert len(valleys) == 5
    assert np.allclose(np.sort(p), np.sort(expected), atol=1e-12, rtol=0)


def test_drop_polygon_with_unstable_faces_against_a_dense_grid():
    """A polygon whose short faces cannot hold it (their foot is outside them): fewer valleys than faces; the
    widths against the maxima of b found by numpy on 2·10⁶ angles (to the grid step, 3e-6 rad)."""
    vertices = [(1.0, 0.0), (0.75, 0.5), (1.1, 1.6), (0.9, 3.0), (1.2, 4.2), (0.7, 4.9)]
    wall = Wall.from_expression(_polygon(vertices, 8))
    _, p = Drop().valley_odds("planar", wall)
    grid = np.linspace(0, 2 * np.pi, 2_000_000, endpoint=False)
    b = np.max([r * np.cos(grid - f) for r, f in vertices], axis=0)
    top = np.flatnonzero((b > np.roll(b, 1)) & (b >= np.roll(b, -1)))
    widths = np.diff(np.r_[grid[top], grid[top[0]] + 2 * np.pi]) / (2 * np.pi)
    assert len(widths) == len(p) < len(vertices)
    assert np.allclose(np.sort(p), np.sort(widths), atol=2e-6)


def test_valleys_of_a_smooth_coin_and_named_faces():
    wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 3.0})
    v = planar_valleys(wall)
    assert len(v) == 2
    got = Drop().odds("planar", wall, ["heads", "tails", "face@90", "face@270"])
    assert abs(got["heads"] - 0.5) < 1e-12 and got["face@270"] == got["heads"] and got["face@90"] == got["tails"]
    with pytest.raises(InvalidArgument, match="unknown outcome"):
        Drop().odds("planar", wall, ["side"])


def test_edge_is_empty_on_a_two_faced_coin_and_heads_needs_two_faces():
    wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 3.0})
    assert Drop().odds("planar", wall, ["edge"])["edge"] == 0.0
    tri = Wall.from_expression(_polygon([(1, 0.2), (1, 2.3), (1, 4.4)], 8))
    # a triangle whose vertex directions 0.2, 2.3, 4.4 put π/2 and 3π/2 in different valleys: named faces work
    assert abs(sum(Drop().odds("planar", tri, ["face@30", "face@180", "face@300"]).values()) - 1) < 1e-12


def test_disc_has_no_outcome():
    with pytest.raises(CoinwallError, match="constant"):
        Drop().odds("planar", Wall.from_expression("1 + 0*t"), ["heads"])


def test_flip_vigorous_limit_favours_the_farthest_corner():
    """k → 0: the two faces beside the farthest vertex (r = 1.3 at 1.4 rad) share everything (docs/design.md)."""
    wall = Wall.from_expression(_polygon([(1.0, 0.0), (1.3, 1.4), (0.8, 3.1), (1.1, 4.6)], 8))
    valleys, p = Flip().valley_odds("planar", wall)
    beside = {valleys.index(1.4 - 0.1), valleys.index(1.4 + 0.1)}
    assert np.allclose([p[i] for i in sorted(beside)], [0.5, 0.5], atol=1e-12)
    assert abs(sum(p) - 1) < 1e-12
    # no turn (k large): the drop's angle measure
    _, slow = Flip(1e6).valley_odds("planar", wall)
    _, drop = Drop().valley_odds("planar", wall)
    assert np.allclose(slow, drop, atol=2e-6)


def test_flip_against_a_brute_force_first_contact():
    """The first-contact rule simulated directly: a uniform phase, b(φ ± u) + k u first reaching the level of the
    highest point (a fine grid of angles), the valley there; against the exact odds within 4 standard errors."""
    wall = Wall.from_expression(_polygon([(1.0, 0.0), (1.3, 1.4), (0.8, 3.1), (1.1, 4.6)], 8))
    k = 0.1
    valleys, exact = Flip(k).valley_odds("planar", wall)
    m = 2 ** 13
    grid = np.arange(m) * (2 * np.pi / m)
    b = wall(grid)
    index = np.array([valleys.index(g) for g in grid])
    turns = int(np.ceil((b.max() - b.min()) / k / (2 * np.pi))) + 1
    steps = np.arange(turns * m)
    rng = np.random.default_rng(3)
    hits = np.zeros(len(valleys))
    for sense in (1, -1):
        for start in rng.integers(0, m, 1500):
            where = (start + sense * steps) % m
            j = np.argmax(b[where] + k * steps * (2 * np.pi / m) >= b.max() + 1e-12)
            hits[index[where[j]]] += 1
    n = hits.sum()
    se = np.sqrt(exact * (1 - exact) / n)
    assert np.all(np.abs(hits / n - exact) < 4 * se + 2e-3)  # 2e-3: the grid's angle step, 7.7e-4 rad


def test_fair_die_three_parameters_exact_and_resimulated():
    """A quadrilateral with fixed radii and free vertex directions: fair (each face 1/4) exactly when the faces
    subtend right angles; solved by least squares to 1e-9, then re-simulated (4·10⁵ random drops) within the
    intervals."""
    text = "max(max(1.0*cos(t), 1.3*cos(t-a)), max(0.8*cos(t-a-b), 1.1*cos(t-a-b-c)))"
    fam = Family("planar", text, {"a": (1.0, 2.2), "b": (1.0, 2.2), "c": (1.0, 2.2)})
    targets = {"face@30": 0.25, "face@120": 0.25, "face@210": 0.25, "face@300": 0.25}
    d = design(fam, targets, Drop())
    assert np.allclose(d.x, np.pi / 2, atol=1e-9)
    check = resimulate(d, 400_000, seed=11)
    assert check.agrees(0.999)
    assert all(abs(check.probabilities[k][0] - 0.25) < 5 * check.probabilities[k][1] for k in targets)


def test_target_out_of_range_and_jumps():
    fam = Family("planar", RECT, {"h": (0.05, 0.5)})
    with pytest.raises(InvalidArgument, match="not reached"):
        design(fam, {"edge": 0.5}, Drop())
    # the vigorous flip of an irregular body jumps where the farthest corner changes: no value gives 0.3
    fam = Family("planar", "max(max(1.0*cos(t), r*cos(t-1.4)), max(0.8*cos(t-3.1), 1.1*cos(t-4.6)))",
                 {"r": (1.0, 1.2)})
    with pytest.raises(InvalidArgument, match="jumps"):
        design(fam, {"face@40": 0.3}, Flip())


def test_odds_of_one_body_and_family_checks():
    assert abs(odds(Family("cylinder", None, {}, {"thickness": 1.0}), Drop())["edge"][0] - cylinder_edge(1, 1)) < 1e-12
    with pytest.raises(CoinwallError):
        Family("planar", RECT, {"q": (0, 1)})  # q is not in the expression, h is missing
    with pytest.raises(CoinwallError, match="thickness"):
        Family("cylinder", None, {})
    with pytest.raises(CoinwallError, match="LO < HI"):
        Family("planar", RECT, {"h": (2.0, 1.0)})
