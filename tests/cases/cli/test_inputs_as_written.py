"""Inputs read as they are written and computed within what floating point and the machine can do: every
example a clear line and exit status 2 (or a right answer), nothing created, changed or deleted.

Classes: formulas floating point cannot follow; SVG transform lists (SVG 1.1 §7.6: applied whole or not at
all); DXF circles, arcs and ellipses outside the DXF reference's ranges; densities with no finite mass (or
singular); numbers that are not ASCII; quantum bodies whose energies leave floating point; nesting that is
not nesting; a KAM bracket without the boundary; quantum solves past the time bound.
"""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from coinwall.cases.cli.main import main


def _refused(argv, folder, capsys, *needles):
    """Run ``coinwall ARGV`` in ``folder``: exit 2, one line naming ``needles``, the folder untouched."""
    before = sorted(os.listdir(folder))
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        try:
            status = main(argv)
        except SystemExit as exc:  # argparse's own refusals (a flag's type)
            status = exc.code
        assert status == 2
    finally:
        os.chdir(cwd)
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and err.startswith("coinwall: error:"), err
    for needle in needles:
        assert needle in err, err
    assert sorted(os.listdir(folder)) == before
    return err


# ------------------------------------------------------------------------------ formulas floating point loses
@pytest.mark.parametrize("wall, blamed", [
    ("2+0.1*cos(2*t+1e20)", "cos is taken of an argument as large as 1e+20"),   # the argument no longer holds t
    ("2+0.1*sin(3*t+1e17)", "sin is taken of an argument as large as 1e+17"),
    ("1+1e-30*cos(1e15*t)", "cos is taken of an argument as large as 6.2"),  # b'' = −cos(1e15 t), lost
    ("2+0.1*cos(2*t+1e13)", "cos is taken"),                                   # ±0.02 rad of argument
])
def test_formulas_floating_point_cannot_follow_are_refused(wall, blamed, tmp_path, capsys):
    _refused(["solve", wall, "-o", "body.json"], tmp_path, capsys, "loses its precision", blamed)


def test_a_formula_that_loses_a_little_gets_an_honest_tolerance():
    """cos(2t + 1e8): the argument is rounded to 1.5e-8, so b and b'' carry ~1e-9 of rounding.  The exact
    b + b'' = 2 − 0.3 cos(2t + 1e8) has its minimum 1.7 whatever the phase: b_c = −1.7 must lie within the
    certified tolerance (which takes the rounding in), not only near the computed value."""
    from coinwall import Wall, critical_offset

    result = critical_offset(Wall.from_expression("2+0.1*cos(2*t+1e8)"))
    assert abs(result.b_c + 1.7) <= result.b_c_tolerance < 1e-6
    assert len(result.angles) == 2


@pytest.mark.parametrize("wall", ["1/(cos(t)+1.0000001)", "sqrt(1+1e-6-cos(t))", "2+tanh(1e5*sin(t-1))",
                                  "1+0.1*cos(30*t)", "(abs(cos(t))**(4/3) + abs(sin(t))**(4/3))**(3/4)",
                                  "1+1e8*cos(t)-1e8*cos(t)+0.1*cos(2*t)"])
def test_steep_but_precise_formulas_pass(wall):
    from coinwall import Wall

    Wall.from_expression(wall)


# ------------------------------------------------------------------------------ SVG transform lists
_SVG = '<svg xmlns="http://www.w3.org/2000/svg"><g transform="{}"><circle cx="0" cy="0" r="1"/></g></svg>'


@pytest.mark.parametrize("transform", ["scale(2) evil(1)", "rotate(30, 5)", "matrix(1 0 0 1 0)",
                                       "translate(1 2 3)", "scale(2),,translate(1)", "scale()", "SCALE(2)",
                                       "scale(2) translate", "skewX(10 20)", "scale(\u00a02)", "translate(1-2)"])
def test_an_invalid_transform_list_is_refused_whole(transform, tmp_path, capsys):
    (tmp_path / "d.svg").write_text(_SVG.format(transform), encoding="utf-8")
    _refused(["wall", "d.svg", "-o", "w.csv"], tmp_path, capsys, "not a valid transform list")


@pytest.mark.parametrize("transform, radius", [("scale(2)", 2.0), (" scale(2) ,translate(0.5 0) ", 2.0),
                                               ("scale(2)translate(1)", 2.0), ("rotate(30 5 5) scale(1.5)", 1.5),
                                               ("matrix(3 0 0 3 1 1)", 3.0), ("", 1.0)])
def test_a_valid_transform_list_is_applied_whole(transform, radius, tmp_path):
    """A circle of radius 1 under the list: the wall of a disc about its centre is its radius, at every angle
    (independent of the reader: the closed form)."""
    from coinwall.forward.formats import load_outline
    from coinwall.forward.support import wall_functions

    (tmp_path / "d.svg").write_text(_SVG.format(transform), encoding="utf-8")
    outline, _ = load_outline(str(tmp_path / "d.svg"))
    theta = np.linspace(0, 2 * math.pi, 90, endpoint=False)
    b, _ = wall_functions(outline, theta)
    assert np.allclose(b, radius, rtol=1e-4)


# ------------------------------------------------------------------------------ DXF ranges
_DXF = "0\nSECTION\n2\nENTITIES\n0\n{kind}\n8\n0\n10\n0.0\n20\n0.0\n30\n0.0\n40\n{radius}\n{extra}0\nENDSEC\n0\nEOF\n"


@pytest.mark.parametrize("kind, radius, extra, needle", [
    ("CIRCLE", "-2.0", "", "radius is -2"), ("CIRCLE", "0.0", "", "radius is 0"),
    ("ARC", "-1.0", "50\n0.0\n51\n180.0\n", "radius is -1"),
])
def test_dxf_shapes_outside_their_ranges_are_refused(kind, radius, extra, needle, tmp_path, capsys):
    (tmp_path / "d.dxf").write_text(_DXF.format(kind=kind, radius=radius, extra=extra), encoding="ascii")
    _refused(["wall", "d.dxf", "-o", "w.csv"], tmp_path, capsys, needle)


def test_the_explorer_refuses_a_negative_radius_too(tmp_path):
    pytest.importorskip("starlette")
    from coinwall.cases.explore.app import create_app  # noqa: F401  (the app reads uploads with load_outline)
    from coinwall.forward.errors import InvalidOutline
    from coinwall.forward.formats import load_outline

    path = tmp_path / "d.dxf"
    path.write_text(_DXF.format(kind="CIRCLE", radius="-2.0", extra=""), encoding="ascii")
    with pytest.raises(InvalidOutline, match="radius is -2"):
        load_outline(str(path))


# ------------------------------------------------------------------------------ densities
@pytest.fixture(scope="module")
def disc(tmp_path_factory):
    """The unit disc centred at its centre of mass (the wall b = 1), as a body file."""
    folder = tmp_path_factory.mktemp("disc")
    assert main(["solve", "1", "--b0", "0", "-o", str(folder / "disc.json")]) == 0
    return folder / "disc.json"


@pytest.mark.parametrize("density, needle", [
    ("r**-3", "no finite mass"), ("r**-2", "no finite mass"), ("1/abs(x)", "no finite mass"),
    ("1/x**2", "no finite mass"), ("1/((x-0.2)**2+(y-0.1)**2)", "no finite mass"),
    ("r**-1.5", "singular"), ("1/sqrt(abs(x-0.3))", "singular"),
])
def test_densities_without_a_finite_mass_are_refused(density, needle, disc, tmp_path, capsys):
    capsys.readouterr()
    _refused(["mass", str(disc), "--density", density], tmp_path, capsys, needle)


@pytest.mark.parametrize("density, mass", [
    ("r**0.5", 2 * math.pi / 2.5),                                  # 2π ∫ r^1.5 dr
    ("1+4*r**8", math.pi + 8 * math.pi / 10),                       # π + 2π·4/10
    ("-log(r/2)", 2 * math.pi * (0.5 * math.log(2) + 0.25)),        # 2π ∫ −log(r/2) r dr: a log is integrable
    ("1/(x-5)**2", None),                                           # its pole lies outside the body
])
def test_integrable_densities_keep_their_mass(density, mass, disc, capsys):
    capsys.readouterr()
    assert main(["mass", str(disc), "--density", density, "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["density"]["mass"]
    if mass is not None:
        assert got == pytest.approx(mass, rel=2e-3)


# ------------------------------------------------------------------------------ numbers are ASCII
@pytest.mark.parametrize("argv", [
    ["solve", "1+0.1*cos(2*t)", "--b0", "\u00a0-0.3", "-o", "b.json"],
    ["solve", "1+0.1*cos(2*t)", "--b0=-0.3\u00a0", "-o", "b.json"],
    ["critical", "1+eps*cos(2*t)", "--param", "eps=\u00a00.1"],
    ["critical", "\u00a01+0.1*cos(2*t)"],
    ["solve", "1+0.1*cos(2*t)", "--points", "\u2007256", "-o", "b.json"],
    ["kam", "--H", "3,\u00a04"],
    ["quantum", "1", "--H", "3", "--levels", "2", "--body", "1,\u00a00.01"],
])
def test_numbers_with_unicode_spaces_are_refused(argv, tmp_path, capsys):
    _refused(argv, tmp_path, capsys)


def test_files_with_unicode_spaces_are_refused(tmp_path, capsys):
    theta = np.linspace(0, 2 * math.pi, 40, endpoint=False)
    rows = [f"{float(t)!r},{1 + 0.1 * math.cos(2 * t)!r}" for t in theta]
    rows[3] = "\u00a0" + rows[3]
    (tmp_path / "w.csv").write_text("theta,b\n" + "\n".join(rows) + "\n", encoding="utf-8")
    _refused(["critical", "w.csv"], tmp_path, capsys, "line 5")
    points = "\n".join(f"{math.cos(t)!r},\u00a0{math.sin(t)!r}" for t in theta.tolist())
    (tmp_path / "p.csv").write_text(points + "\n", encoding="utf-8")
    _refused(["wall", "p.csv", "-o", "out.csv"], tmp_path, capsys)


# ------------------------------------------------------------------------------ quantum
@pytest.mark.parametrize("body", ["1e308,1e308", "1,1e-300", "1e-300,1e300"])
def test_a_body_whose_energies_leave_floating_point_is_refused(body, tmp_path, capsys):
    _refused(["quantum", "1", "--H", "3", "--levels", "2", "--body", body, "-o", "q.json"], tmp_path, capsys,
             "energy unit")


@pytest.mark.parametrize("argv", [["--H", "2.00403", "--levels", "2"], ["--H", "1e6", "--levels", "4"]])
def test_quantum_solves_past_the_time_bound_are_refused(argv, tmp_path, capsys):
    err = _refused(["quantum", "1", *argv, "-o", "q.json"], tmp_path, capsys, "--allow-long")
    if "fits" in err:  # the height it suggests is within the bounds it states
        from coinwall.cases.cli.quantum import MAX_SECONDS
        from coinwall.forward import Wall
        from coinwall.forward.quantum import make_strip
        from coinwall.forward.quantum.spectrum import MAX_DOFS, default_cells, estimated_seconds, fem_dofs

        H = float(err.split("H ≥ ")[1].split()[0])
        strip = make_strip(Wall.from_expression("1"), H, 0.0)
        cells = default_cells(strip, 2, 4)
        assert estimated_seconds(strip, 2, "fem", cells, 4) <= MAX_SECONDS and fem_dofs(strip, cells, 4) <= MAX_DOFS


def test_the_time_estimate_grows_with_the_problem():
    from coinwall.forward import Wall
    from coinwall.forward.quantum import make_strip
    from coinwall.forward.quantum.spectrum import estimated_seconds

    wall = Wall.from_expression("1")
    thin = [estimated_seconds(make_strip(wall, H, 0.0), 2, "fem", 4, 4) for H in (2.1, 2.01, 2.001)]
    assert thin[0] < thin[1] < thin[2]
    wide = [estimated_seconds(make_strip(wall, 1e4, 0.0), 4, "fem", c, 4) for c in (60, 140)]
    assert 5 < wide[1] / wide[0] < 50  # measured: 17 times longer (docstring)


# ------------------------------------------------------------------------------ KAM without a boundary
def test_a_kam_bracket_without_the_boundary_is_no_answer(monkeypatch, capsys):
    from coinwall.forward.dynamics.analysis import kam
    from coinwall.forward.dynamics.analysis.kam import KamBoundary

    result = KamBoundary(H=np.array([3.0, 4.0]), eps_low=np.array([1.0, 1.0]), eps_high=np.array([np.inf, 2.0]),
                         eps=np.array([np.nan, math.sqrt(2.0)]), paper=np.array([2.22, 1.31]), orbits=8,
                         collisions=400, regular_max=0.01, history=((), ()))
    monkeypatch.setattr(kam, "kam_boundary", lambda *a, **k: result)
    assert main(["kam", "--H", "3,4", "--bracket", "5e-324,1"]) == 1
    captured = capsys.readouterr()
    assert "nan" not in captured.out and "(not found)" in captured.out and "1.414" in captured.out
    assert "no ε_c found" in captured.err and "raise the bracket's top" in captured.err
    assert main(["kam", "--H", "3,4", "--bracket", "5e-324,1", "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["eps"] == [None, pytest.approx(math.sqrt(2.0))] and len(doc["not_found"]) == 1
