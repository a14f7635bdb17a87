"""`coinwall fit` reports the corners the noise supports, not every kink of the least-squares projection.

The truth is built here with plain numpy geometry (never coinwall's): a convex 9-gon (9 corners), a
Reuleaux pentagon (5 corners joined by circular arcs) and an ellipse (no corner), sampled at 360–1000
angles with Gaussian noise of 0.1 % and 1 % of their size.  Each fit must find the true number of corners,
say the right regime, stay convex, and put its wall within a fraction of σ (rms) of the true wall.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.inverse.discrete import discrete_curvature
from coinwall.inverse.fit import fit_convex

TWO_PI = 2 * np.pi


def _normals(theta):
    return np.stack([np.cos(theta), np.sin(theta)])


# ------------------------------------------------------------------------------------------------ the truth
def nonagon():
    """A convex 9-gon from its edges: outward normals φ_k (irregular; the vertex windows φ_{k+1} − φ_k lie
    between 0.61 and 0.79 rad: at σ = 1 % of the size a window much below 0.5 rad is at the resolution of
    1,000 samples) at distances d_k; vertex k is where edges k and k+1 meet."""
    phi = TWO_PI * np.arange(9) / 9 + np.array([0.0, 0.04, -0.03, 0.05, -0.04, 0.02, 0.05, -0.03, 0.01])
    d = np.array([1.0, 0.93, 1.06, 0.97, 1.03, 0.95, 1.05, 0.98, 1.01])
    vertices = []
    for k in range(9):
        a, b = phi[k], phi[(k + 1) % 9]
        vertices.append(np.linalg.solve([[np.cos(a), np.sin(a)], [np.cos(b), np.sin(b)]], [d[k], d[(k + 1) % 9]]))
    return np.array(vertices), np.diff(np.append(phi, phi[0] + TWO_PI))


def polygon_wall(vertices, theta):
    """h(θ) = max_k v_k · n(θ)."""
    return np.max(vertices @ _normals(theta), axis=0)


def reuleaux_pentagon(theta, radius=1.0, phase=0.3):
    """The Reuleaux pentagon: the intersection of the discs of radius w (the width: the pentagon's diagonal)
    centred at the vertices v_k of a regular pentagon.  Its boundary is the five vertices and five arcs; the
    arc centred at v_k joins v_{k+2} and v_{k+3} and carries the normals between the directions of
    v_{k+2} − v_k and v_{k+3} − v_k (a window of π/5), where h(θ) = v_k · n(θ) + w.  Every other normal
    belongs to a vertex, where h(θ) = v_j · n(θ), the largest over the vertices.  So h = max(max_j v_j·n,
    v_k·n + w inside arc k's window)."""
    k = np.arange(5)
    v = radius * np.column_stack([np.cos(phase + TWO_PI * k / 5), np.sin(phase + TWO_PI * k / 5)])
    width = float(np.hypot(*(v[0] - v[2])))
    h = polygon_wall(v, theta)
    for j in range(5):
        start = np.arctan2(*(v[(j + 2) % 5] - v[j])[::-1])
        span = np.mod(np.arctan2(*(v[(j + 3) % 5] - v[j])[::-1]) - start, TWO_PI)
        inside = np.mod(theta - start, TWO_PI) <= span
        h = np.where(inside, np.maximum(h, v[j] @ _normals(theta) + width), h)
    return h, v, width


def ellipse_wall(theta, a=1.0, b=0.6):
    return np.sqrt(a**2 * np.cos(theta) ** 2 + b**2 * np.sin(theta) ** 2)


def truth(name, theta):
    if name == "nonagon":
        return polygon_wall(nonagon()[0], theta)
    if name == "reuleaux":
        return reuleaux_pentagon(theta)[0]
    return ellipse_wall(theta)


CORNERS = {"nonagon": 9, "reuleaux": 5, "ellipse": 0}
REGIME = {"nonagon": "critical", "reuleaux": "critical", "ellipse": "convex"}
SIZE = {"nonagon": 1.0, "reuleaux": 1.0, "ellipse": 0.8}  # the mean of the true wall, rounded


def test_the_truth_is_right():
    """The 9-gon is convex with the stated windows; the Reuleaux wall is that of the intersection of the
    discs (dense points of its boundary) and has constant width; the ellipse wall is its points' maximum."""
    theta = np.linspace(0, TWO_PI, 720, endpoint=False)
    vertices, windows = nonagon()
    assert windows.min() > 0.6 and np.isclose(windows.sum(), TWO_PI)
    u, w = np.roll(vertices, -1, axis=0) - vertices, np.roll(vertices, -2, axis=0) - vertices
    assert np.all(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0] > 0)
    h, v, width = reuleaux_pentagon(theta)
    assert np.max(np.abs(h + np.roll(h, 360) - width)) < 1e-12
    points = np.concatenate([v] + [v[j] + width * _normals(np.linspace(0, TWO_PI, 20000, endpoint=False)).T
                                   for j in range(5)])
    inside = np.all(np.hypot(*(points[:, None, :] - v[None]).transpose(2, 0, 1)) <= width * (1 + 1e-12), axis=1)
    assert np.max(np.abs(np.max(points[inside] @ _normals(theta), axis=0) - h)) < 1e-7
    t = np.linspace(0, TWO_PI, 20000, endpoint=False)
    assert np.max(np.abs(np.max(np.column_stack([np.cos(t), 0.6 * np.sin(t)]) @ _normals(theta), axis=0)
                         - ellipse_wall(theta))) < 1e-7


# ------------------------------------------------------------------------------------------------ the fits
CASES = [(name, n, rel, seed) for name in CORNERS for (n, rel) in ((360, 1e-3), (1000, 1e-2)) for seed in (1, 2)]


@pytest.mark.parametrize("name,n,rel,seed", CASES)
def test_fit_reports_the_true_corners(name, n, rel, seed):
    theta = np.linspace(0, TWO_PI, n, endpoint=False)
    sigma = rel * SIZE[name]
    wall = truth(name, theta)
    fit = fit_convex(theta, wall + sigma * np.random.default_rng(seed).standard_normal(n))
    assert len(fit.body.corners) == fit.corners == CORNERS[name]
    assert fit.regime == REGIME[name] and fit.body.regime == REGIME[name]
    # the least-squares projection alone has many more vertex windows: the tests removed them
    assert len(fit.tests) >= CORNERS[name]
    # the noise is estimated to 10 %, the fit stays within the noise and near the truth
    assert fit.sigma == pytest.approx(sigma, rel=0.1)
    assert fit.chi2 <= fit.chi2_bound
    assert np.sqrt(np.mean((fit.fitted - wall) ** 2)) < sigma
    # a convex body: ρ ≥ 0 to rounding, > 0 away from the corners when there are none
    rho, tol = discrete_curvature(fit.theta, fit.fitted)
    assert np.all(rho >= -tol - 1e-9 / (TWO_PI / n) ** 2)
    if not CORNERS[name]:
        assert rho.min() > 0
    assert fit.body.convex and fit.body.valid and not fit.body.warnings


def test_corner_windows_match_the_polygon():
    """The 9-gon's corners sit at its vertices, each with about the normal window of its vertex (its ends
    sit where the fit put the edges: noise splits an edge across a few nearby directions)."""
    theta = np.linspace(0, TWO_PI, 1000, endpoint=False)
    vertices, windows = nonagon()
    fit = fit_convex(theta, polygon_wall(vertices, theta) + 1e-3 * np.random.default_rng(3).standard_normal(1000))
    points = np.array([[c.distance * np.cos(c.direction), c.distance * np.sin(c.direction)] for c in fit.body.corners])
    assert np.max(np.min(np.hypot(*(points[:, None] - vertices[None]).transpose(2, 0, 1)), axis=1)) < 0.01
    found = sorted(2 * c.half_width for c in fit.body.corners)
    assert np.allclose(found, sorted(windows), atol=0.06)


def test_given_noise_and_exact_data():
    """A noise given (--b-sd) is used as is; exact polygon data keep every vertex as a corner."""
    theta = np.linspace(0, TWO_PI, 360, endpoint=False)
    wall = ellipse_wall(theta)
    fit = fit_convex(theta, wall + 0.008 * np.random.default_rng(4).standard_normal(360), sigma=0.008)
    assert fit.sigma == 0.008 and fit.sigma_given and fit.corners == 0 and fit.regime == "convex"
    exact = fit_convex(theta, polygon_wall(nonagon()[0], theta))
    assert exact.corners == 9 and exact.regime == "critical" and exact.rms_residual < 1e-12
    with pytest.raises(ValueError, match="sigma"):
        fit_convex(theta, wall, sigma=-1.0)


def test_fit_cli_json(tmp_path, capsys):
    """`coinwall fit scan.csv --json` on a noisy Reuleaux pentagon: 5 corners, critical; on an ellipse with
    the noise given: no corner, convex; a bad --b-sd, and the ambiguous --sigma-b, are one line and status 2."""
    theta = np.linspace(0, TWO_PI, 720, endpoint=False)
    rng = np.random.default_rng(7)
    for name, extra in (("reuleaux", []), ("ellipse", ["--b-sd", "0.005"])):
        values = truth(name, theta) + 0.005 * rng.standard_normal(theta.size)
        path = tmp_path / f"{name}.csv"
        path.write_text("theta,b\n" + "".join(f"{t!r},{v!r}\n" for t, v in zip(theta.tolist(), values.tolist())))
        assert main(["fit", str(path), "--json", *extra]) == 0
        doc = json.loads(capsys.readouterr().out)
        assert len(doc["corners"]) == CORNERS[name] and doc["regime"] == REGIME[name] == doc["body_regime"]
        assert sum(c["verdict"] == "corner" for c in doc["candidates"]) == CORNERS[name]
        assert doc["chi2"] <= doc["chi2_bound"] and doc["rms_residual"] == pytest.approx(0.005, rel=0.15)
        assert doc["sigma_source"] == ("given" if extra else "estimated")
    assert main(["fit", str(tmp_path / "ellipse.csv"), "--b-sd", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--b-sd" in err
    for tiny in ("1e-300", "5e-324"):  # below what the values' own precision can tell from 0: one line
        assert main(["fit", str(tmp_path / "ellipse.csv"), "--b-sd", tiny]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--b-sd" in err
    assert main(["fit", str(tmp_path / "ellipse.csv"), "--sigma-b", "0.005"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--b-sd" in err
    assert main(["fit", str(tmp_path / "reuleaux.csv")]) == 0
    out = capsys.readouterr().out
    assert "regime     critical" in out and "corners    5 supported" in out
