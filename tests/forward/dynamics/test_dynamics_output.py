"""What the dynamics show a reader: the ``.plot()`` figures of the analyses (labelled axes, legends),
figure files in every format, the orbit statistics, and the ``--help`` of the dynamics subcommands."""

import math

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward import Wall
from coinwall.forward.dynamics import (
    Billiard,
    KamBoundary,
    correlation,
    orbit_statistics,
    paper_boundary,
    poincare_section,
    random_states,
    simulate,
)

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def ellipse(eps, H):
    return Billiard(Wall.from_expression(ELLIPSE, {"eps": eps}), H)


def _assert_labelled(ax):
    assert ax.get_xlabel() and ax.get_ylabel()
    # a unit or a dimensionless quantity is named in parentheses on each axis
    assert "(" in ax.get_xlabel() and "(" in ax.get_ylabel()
    assert ax.figure is not None


def test_section_plot_has_labelled_axes():
    result = poincare_section(ellipse(0.55, 1.9), orbits=2, collisions=100, seed=1)
    ax = result.plot()
    _assert_labelled(ax)
    assert "θ_c (rad)" in ax.get_xlabel() and "φ_c (rad)" in ax.get_ylabel()
    assert ax.get_xlim() == pytest.approx((0.0, 2 * math.pi))


def test_correlation_plot_has_labelled_axes_and_a_legend():
    result = correlation(ellipse(99, 2.4), bounces=4000, max_lag=5, orbits=4, seed=1)
    ax = result.plot()
    _assert_labelled(ax)
    assert "P(n)" in ax.get_ylabel()
    assert ax.get_legend() is not None


def test_kam_plot_has_labelled_axes_and_a_legend():
    # a KamBoundary made by hand (the bisection itself is tested elsewhere): the figure only
    H = np.array([2.0, 3.0])
    eps = paper_boundary(H)
    result = KamBoundary(H=H, eps_low=0.9 * eps, eps_high=1.1 * eps, eps=eps, paper=eps, orbits=10, collisions=100,
                         regular_max=0.01, history=((), ()))
    ax = result.plot()
    _assert_labelled(ax)
    assert "H (κ)" in ax.get_xlabel() and "ε_c" in ax.get_ylabel()
    assert ax.get_legend() is not None


@pytest.mark.parametrize("ext,magic", [(".svg", b"<?xml"), (".pdf", b"%PDF-"), (".png", b"\x89PNG\r\n\x1a\n")])
def test_section_writes_every_figure_format(tmp_path, capsys, ext, magic):
    path = tmp_path / f"section{ext}"
    assert main(["section", ELLIPSE, "--param", "eps=0.55", "--H", "1.9", "--orbits", "2", "--collisions", "100",
                 "--seed", "1", "-o", str(path)]) == 0
    data = path.read_bytes()
    assert data.startswith(magic)
    if ext == ".svg":
        assert b"<svg" in data[:2000]
    if ext == ".pdf":
        assert data.rstrip().endswith(b"%%EOF")


def test_section_refuses_an_unknown_figure_extension(tmp_path, capsys):
    assert main(["section", ELLIPSE, "--param", "eps=0.55", "--H", "1.9", "--orbits", "2", "--collisions", "50",
                 "-o", str(tmp_path / "s.jpg")]) == 2
    assert not (tmp_path / "s.jpg").exists()


def test_orbit_statistics_match_one_simulation():
    """Pieces of CHUNK collisions continue each other exactly: the totals equal one simulate() call."""
    table = ellipse(99, 3.0)
    state = random_states(table, 1, seed=2)[0]
    stats = orbit_statistics(table, state, 5000)
    traj = simulate(table, state, 5000)
    assert stats.collisions == 5000 and stats.note == ""
    assert stats.mean_free_time == pytest.approx(traj.time[-1] / 5000, rel=1e-12)
    assert stats.bottom_fraction == float(np.mean(traj.side == 0))
    assert stats.to_dict()["collisions"] == 5000 and "OrbitStatistics(5000" in repr(stats)


@pytest.mark.parametrize("command,words", [
    ("simulate", ["unit speed", "Santaló"]),
    ("section", ["Poincaré section", "angle of incidence"]),
    ("correlation", ["P(n) is the", "probability", "bottom-wall collisions later"]),
    ("kam", ["sqrt((1+eps*cos(t)**2)/(1+eps))", "ellipse wall"]),
])
def test_help_says_what_it_computes_and_ends_with_an_example(command, words, capsys):
    with pytest.raises(SystemExit) as info:
        main([command, "--help"])
    assert info.value.code == 0
    text = capsys.readouterr().out
    paragraph = text[text.index("\n\n") + 2:text.index("options:")] if "options:" in text else text
    for word in words:
        assert word in paragraph
    lines = text.rstrip().splitlines()
    assert lines[-2].strip() == "example:"
    assert lines[-1].strip().removeprefix("$ ").startswith(f"coinwall {command} ")


def test_kernel_is_a_real_module_and_its_tail_is_what_is_compiled():
    """``_kernel.py`` imports on its own (stubs for the wall functions) and the compiled text is its tail."""
    from pathlib import Path

    import coinwall.forward.dynamics.billiard._kernel as source
    from coinwall.forward.dynamics.billiard.kernel import KERNEL_SOURCE

    assert callable(source._run) and callable(source.wall_b1)
    assert Path(source.__file__).read_text(encoding="utf-8").endswith(KERNEL_SOURCE)
    assert "def _run(" in KERNEL_SOURCE and "def wall_b1" not in KERNEL_SOURCE and "import" not in KERNEL_SOURCE
