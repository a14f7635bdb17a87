"""Figures worth publishing: one house style, a title that says what is shown, quantities and units on every axis,
colour bars where colour carries a value, one number format on log axes, legends clear of every text, PNGs at
least 1600 px wide, and the figure-specific facts (corner windows inside [0, 2π], a sampled wall's ρ from its
samples, a P(n) error that covers the data, |ψ|² from the solution rather than the mesh)."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from coinwall.forward import Wall  # noqa: E402
from coinwall.forward.dynamics import Billiard, KamBoundary, correlation, paper_boundary, poincare_section  # noqa: E402
from coinwall.forward.formats.figure import figure_bytes  # noqa: E402
from coinwall.forward.formats.style import HOUSE_STYLE, plain_log_axis, shade_angle_window  # noqa: E402
from figurecheck import figure_problems, png_size  # noqa: E402  (tests/figurecheck.py)

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
TWO_PI = 2 * math.pi


def ellipse(eps):
    return Wall.from_expression(ELLIPSE, {"eps": eps})


def _data_axes(fig):
    """The axes that plot data (not colour bars)."""
    return [ax for ax in fig.axes if not hasattr(ax, "_colorbar")]


def _texts(fig):
    """Every title of the figure (suptitle and axes titles) as one string."""
    parts = [fig._suptitle.get_text()] if fig._suptitle is not None else []
    for ax in fig.axes:
        parts += [ax.get_title(loc) for loc in ("left", "center", "right")]
    return "\n".join(parts)


def _assert_publishable(fig, *names, formats=(".png",)):
    """Every data axes names its quantity and unit; the titles name ``names``; colour has a colour bar; no legend
    covers a text and the PNG is at least 1600 px wide (tests/figurecheck.py); the figure is written in
    ``formats`` (the vector formats are checked on the body figure: they are slow)."""
    assert figure_problems(fig) == []
    for ax in _data_axes(fig):
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            assert label and "(" in label and label.rstrip().endswith(")"), f"axis label without a unit: {label!r}"
    text = _texts(fig)
    for name in names:
        assert name in text, f"{name!r} not in the titles {text!r}"
    valued = any(ax.images or any(type(c).__name__ in ("QuadMesh", "TriMesh", "PolyQuadMesh") for c in ax.collections)
                 for ax in _data_axes(fig))
    if valued:
        bars = [ax for ax in fig.axes if hasattr(ax, "_colorbar")]
        assert bars and all(ax._colorbar.ax.get_ylabel() or ax._colorbar.ax.get_xlabel() for ax in bars)
    magic = {".png": b"\x89PNG", ".svg": b"<?xml", ".pdf": b"%PDF"}
    for k, ext in enumerate(formats):
        assert figure_bytes(fig, "figure" + ext, close=k == len(formats) - 1).startswith(magic[ext])


def _log_labels_one_format(ax, axis="y"):
    ax.figure.canvas.draw()
    which = ax.yaxis if axis == "y" else ax.xaxis
    labels = [t.get_text() for t in which.get_ticklabels(which="both") if t.get_text()]
    assert labels
    powers = ["$" in t for t in labels]
    assert all(powers) or not any(powers), labels
    return labels


# ------------------------------------------------------------------------------------------------ the house style
def test_house_style_is_applied_and_left_behind():
    from coinwall.forward.formats.figure import new_figure

    before = matplotlib.rcParams["axes.spines.top"]
    fig, ax = new_figure()
    assert ax.spines["top"].get_visible() is HOUSE_STYLE["axes.spines.top"]
    assert matplotlib.rcParams["axes.spines.top"] == before  # the caller's settings are untouched
    figure_bytes(fig, "x.png")


def test_log_axis_has_one_number_format():
    from coinwall.forward.formats.figure import new_figure

    for low, high in ((0.55, 7.0), (0.3, 30.0), (1e-5, 0.2), (2.0, 3.0)):
        fig, ax = new_figure()
        ax.plot([0, 1], [low, high])
        ax.set_yscale("log")
        plain_log_axis(ax.yaxis)
        labels = _log_labels_one_format(ax)
        assert "1.0" not in labels and not any("mathdefault" in t for t in labels), labels
        figure_bytes(fig, "x.png")


def test_wrapped_windows_are_two_spans_inside_the_period():
    from coinwall.forward.formats.figure import new_figure

    fig, ax = new_figure()
    spans = shade_angle_window(ax, 5.385740597631452, 7.18063001672772)
    assert len(spans) == 2
    extents = sorted((float(s.get_x()), float(s.get_x() + s.get_width())) for s in spans)
    assert extents[0] == pytest.approx((0.0, 7.18063001672772 - TWO_PI))
    assert extents[1] == pytest.approx((5.385740597631452, TWO_PI))
    spans = shade_angle_window(ax, -0.5, 0.5)
    assert sorted(round(s.get_x(), 9) for s in spans) == [0.0, round(TWO_PI - 0.5, 9)]
    figure_bytes(fig, "x.png")


def test_png_is_at_least_1600_pixels_wide_whatever_the_figure_size():
    from coinwall.forward.formats.figure import PNG_MIN_WIDTH, new_figure, png_dpi

    for size in ((3.0, 2.0), (6.4, 4.8), (14.0, 4.8)):
        fig, ax = new_figure(figsize=size)
        ax.plot([0, 1], [0, 1])
        dpi = png_dpi(fig)
        width, height = png_size(figure_bytes(fig, "x.png"))
        assert PNG_MIN_WIDTH <= width <= PNG_MIN_WIDTH + 2 * dpi / 100 + 4 or dpi == HOUSE_STYLE["savefig.dpi"]
        assert height > 0.5 * width * size[1] / size[0]  # the drawing is scaled, not cropped


def test_legend_checks_find_a_legend_over_a_label_and_legend_below_clears_it():
    """The check fails on the kind of figure it guards against (a legend anchored a fraction of the axes below a
    short panel lands on its x label) and passes once the legend hangs below the label (any panel height)."""
    from coinwall.forward.formats.figure import new_figure
    from coinwall.forward.formats.style import legend_below, legend_overlaps

    for height in (2.2, 3.0, 6.0):
        fig, ax = new_figure(figsize=(6.4, height))
        ax.plot([0, 1], [0, 1], label="a line")
        ax.set_xlabel("lag n (bottom-wall collisions)\nsecond line")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12))
        fig.tight_layout()
        covered = legend_overlaps(fig)
        if height < 4:  # a tall panel puts 12 % of its height below the labels: the fraction works there only
            assert any("x label" in p or "tick label" in p for p in covered), (height, covered)
        legend_below(ax)
        fig.tight_layout()
        assert legend_overlaps(fig) == [], height


def test_docstring_examples_of_the_figure_modules_run():
    import doctest

    import coinwall.forward.formats.figure as figure_module
    import coinwall.forward.formats.style as style_module
    import coinwall.forward.quantum.figures as quantum_figures

    for module in (figure_module, style_module, quantum_figures):
        result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
        assert result.attempted > 0 and result.failed == 0, module.__name__


# ------------------------------------------------------------------------------------------------ bodies
def _spans(ax):
    return [p for p in ax.patches if type(p).__name__ == "Rectangle" and p.get_width() > 0]


def test_body_figure_of_a_corner_body_shades_its_windows_inside_the_period():
    from coinwall import solve_body
    from coinwall.inverse.export.figure import figure

    body = solve_body(ellipse(1.0), b0=-0.6)
    assert body.regime == "corner" and any(c.window[1] > TWO_PI for c in body.corners)
    fig = figure(body)
    wall_axes, rho_axes = fig.axes[1], fig.axes[2]
    for ax in (wall_axes, rho_axes):
        spans = _spans(ax)
        assert len(spans) == 3  # [2.24, 4.04] and the wrapped window as [5.39, 2π] + [0, 0.90]
        for span in spans:
            x0, x1 = span.get_x(), span.get_x() + span.get_width()
            assert -1e-12 <= x0 < x1 <= TWO_PI + 1e-12
        assert any(s.get_x() == pytest.approx(0.0) for s in spans)
        assert ax.get_xlim() == pytest.approx((0.0, TWO_PI))
    _assert_publishable(fig, ELLIPSE, "ε = 1", "b0 = -0.6", "corner", formats=(".png", ".svg", ".pdf"))


@pytest.fixture(scope="module")
def polygon_csv(tmp_path_factory):
    """The support function of a pentagon at 360 angles, written with 6 digits (as a scanner would)."""
    angles, radii = np.array([0.3, 1.5, 2.6, 3.9, 5.1]), np.array([1.0, 0.8, 1.1, 0.9, 1.0])
    vertices = np.c_[radii * np.cos(angles), radii * np.sin(angles)]
    theta = np.linspace(0, TWO_PI, 360, endpoint=False)
    b = (vertices @ np.vstack([np.cos(theta), np.sin(theta)])).max(axis=0)
    path = tmp_path_factory.mktemp("walls") / "pentagon.csv"
    path.write_text("theta,b\n" + "".join(f"{t:.6f},{v:.6f}\n" for t, v in zip(theta, b)))
    return str(path)


def test_body_figure_of_a_sampled_wall_draws_the_samples_discrete_curvature(polygon_csv):
    from coinwall import solve_body
    from coinwall.forward.formats import load_wall
    from coinwall.inverse.discrete import discrete_support
    from coinwall.inverse.export.figure import figure

    wall = load_wall(polygon_csv, {})
    body = solve_body(wall, b0=0.1)
    assert body.regime == "convex"
    fig = figure(body)
    rho_axes = fig.axes[2]
    theta, b = wall.samples
    expected = discrete_support(theta, b, wall.sample_rounding)
    lines = [line for line in rho_axes.get_lines() if np.size(line.get_ydata()) == theta.size]
    assert len(lines) == 1
    assert np.asarray(lines[0].get_xdata()) == pytest.approx(theta)
    assert np.asarray(lines[0].get_ydata()) == pytest.approx(expected.rho + 0.1, abs=1e-12)
    # the rounding band is drawn, and the panel shows the decisive range: ρ + b0 ≈ b0 on the vertex windows,
    # with zero in view — not the interpolant's ±50 of noise
    assert rho_axes.collections, "no tolerance band"
    low, high = rho_axes.get_ylim()
    assert low <= 0.0 < 0.1 < high < 1.0
    assert "samples" in rho_axes.get_ylabel() or "ρ" in rho_axes.get_ylabel()
    _assert_publishable(fig, "b0 = 0.1", "convex", "b_c ∈")


# ------------------------------------------------------------------------------------------------ the motion
def test_poincare_section_title_names_the_wall_and_counts():
    result = poincare_section(Billiard(ellipse(0.55), 1.9), orbits=2, collisions=200, seed=1)
    ax = result.plot(name="case:ellipse-0.55")
    title = ax.get_title()
    assert "case:ellipse-0.55, ε = 0.55" in title and "H = 1.9 κ" in title and "2 orbits × 200 collisions" in title
    assert " , " not in title
    _assert_publishable(ax.figure)
    assert ELLIPSE in result.plot().get_title()  # without a name: the expression


def test_correlation_fit_states_an_error_that_covers_the_data():
    result = correlation(Billiard(ellipse(99.0), 2.2), bounces=60000, max_lag=30, orbits=20, seed=1)
    ax = result.plot(name="case:coin")
    assert "case:coin, ε = 99" in ax.get_title() and "H = 2.2 κ" in ax.get_title()
    low, high, lags, _ = result.decay_band()
    assert low <= result.tau <= high and lags.size >= 3
    y, s = np.abs(result.P - 0.5), result.P_stderr
    amplitude = abs(result.amplitude)
    for n in lags:  # every lag out of the noise lies within one error of the stated band of τ
        lo_curve, hi_curve = amplitude * math.exp(-n / low), amplitude * math.exp(-n / high)
        assert lo_curve - s[n] - 1e-12 <= y[n] <= hi_curve + s[n] + 1e-12, n
    legend = " ".join(t.get_text() for t in ax.get_legend().get_texts())
    assert f"{low:.3g}" in legend and f"{high:.3g}" in legend and "statistical" in legend
    _log_labels_one_format(ax)
    _assert_publishable(ax.figure)


def test_kam_log_axis_has_one_number_format_and_counts():
    H = np.array([2.0, 3.0, 4.0, 6.0, 8.0])
    eps = paper_boundary(H)
    result = KamBoundary(H=H, eps_low=0.9 * eps, eps_high=1.1 * eps, eps=eps, paper=eps, orbits=100,
                         collisions=1000, regular_max=0.01, history=((),) * 5)
    ax = result.plot()
    labels = _log_labels_one_format(ax)
    assert not any("times" in t for t in labels) and "1" in labels
    assert "100 orbits × 1000 collisions" in ax.get_title()
    _assert_publishable(ax.figure, "ε")


# ------------------------------------------------------------------------------------------------ quantum
@pytest.fixture(scope="module")
def spectrum():
    from coinwall.forward.quantum import quantum_spectrum

    return quantum_spectrum(ellipse(0.55), 2.2, levels=2, cells=10)


def test_quantum_figures_name_the_wall_and_colour_has_a_bar(spectrum):
    from coinwall.forward.quantum.figures import plot_counting, plot_density, plot_orientation

    fig = plot_density(spectrum, 0, name="case:ellipse-0.55")
    assert any(hasattr(ax, "_colorbar") for ax in fig.axes), "|ψ|² without a colour bar"
    _assert_publishable(fig, "case:ellipse-0.55", "H = 2.2 κ")
    for fig in (plot_counting(spectrum), plot_orientation(spectrum), spectrum.weyl().plot()):
        _assert_publishable(fig)
    _assert_publishable(plot_counting(spectrum), ELLIPSE, "ε = 0.55")


def test_quantum_cli_figure_and_splittings_name_the_wall(spectrum):
    from coinwall.cases.cli.quantum import _figure
    from coinwall.forward.quantum.figures import plot_splittings
    from coinwall.forward.quantum.tunnelling import Splitting

    fig = _figure([(spectrum, None)], spectrum.strip.table.wall, "case:ellipse-0.55")
    _assert_publishable(fig, "case:ellipse-0.55", "H = 2.2 κ")
    splittings = [Splitting(H=h, gap=h - 2.0, lower=1.0, upper=1.0 + d, classes=("a", "b"), direct=d, flux=d,
                            direct_trusted=True, flux_trusted=True, neck_amplitude=1.0, action=-math.log(d), dofs=1,
                            cells=1) for h, d in ((2.3, 2e-5), (2.5, 5e-3), (2.8, 0.1))]
    fig = plot_splittings(splittings, wall=ellipse(0.55), name="case:ellipse-0.55")
    _log_labels_one_format(fig.axes[0])
    _assert_publishable(fig, "case:ellipse-0.55", "H = 2.3, 2.5, 2.8 κ")


# ------------------------------------------------------------------------------------------------ scans
def _store(eps_values, H_values):
    xr = pytest.importorskip("xarray")
    from coinwall.forward.dynamics.analysis.islands import ELLIPSE_WALL

    shape = (len(eps_values), len(H_values))
    values = np.linspace(0.1, 0.9, shape[0] * shape[1]).reshape(shape)
    return xr.Dataset(
        {"chaotic_fraction": (("eps", "H"), values, {"units": "1"}),
         "chaotic_fraction_stderr": (("eps", "H"), 0.05 * np.ones(shape), {"units": "1"}),
         "cell_status": (("eps", "H"), np.ones(shape, dtype=np.int8)),
         "cell_seed": (("eps", "H"), np.zeros(shape, dtype=np.int64))},
        coords={"eps": ("eps", np.asarray(eps_values, float), {"units": "1"}),
                "H": ("H", np.asarray(H_values, float), {"units": "kappa"})},
        attrs={"quantity": "chaotic-fraction", "wall": ELLIPSE_WALL, "params": "{}", "kappa": "none"})


def test_scan_figures_name_the_wall_and_cells():
    from coinwall.cases.scan.figures import plot_scan

    ax = plot_scan(_store([0.5, 1.0, 2.0, 4.0, 8.0], [2.0, 3.0, 4.0]))
    fig = ax.figure
    assert any(hasattr(a, "_colorbar") for a in fig.axes)
    assert "κ" in ax.get_xlabel() and "dimensionless" in ax.get_ylabel()
    _log_labels_one_format(ax)
    _assert_publishable(fig, "sqrt((1+eps", "5 eps × 3 H cells")
    ax = plot_scan(_store([2.0], [2.0, 3.0, 4.0]))
    _assert_publishable(ax.figure, "sqrt((1+eps", "3 heights")


def test_density_panel_shows_the_solution_not_the_mesh(spectrum):
    """|ψ|² is drawn from the finite-element solution on a fine grid (no streaks along the triangles' edges): at
    random points between the grid's nodes the picture (bilinear between nodes) is within 0.5 % of the peak of
    the solution there, evaluated by scikit-fem's own probes (measured: 0.03 %).  Colouring the mesh's vertices,
    as the panel did, errs 20 times more on this mesh (2.3 %; 11 % on the gallery's coarser P4 mesh)."""
    from matplotlib.collections import QuadMesh
    from matplotlib.tri import LinearTriInterpolator, Triangulation
    from scipy.interpolate import RegularGridInterpolator

    from coinwall.forward.quantum.figures import level_density, level_grid, plot_density

    fig = plot_density(spectrum, 0)
    meshes = [c for c in fig.axes[0].collections if isinstance(c, QuadMesh)]
    assert len(meshes) == 1 and not any(type(c).__name__ == "TriMesh" for c in fig.axes[0].collections)
    theta, eta, density = level_density(spectrum, 0)
    assert density.shape == (721, 97)
    assert np.asarray(meshes[0].get_array()).ravel() == pytest.approx(density.ravel())

    mesh = spectrum.meshes[int(spectrum.domain[0])]
    values = mesh.reduce @ spectrum.vectors[0]
    rng = np.random.default_rng(3)
    points = np.array([rng.uniform(mesh.theta[0], mesh.theta[-1], 400), rng.uniform(0.0, 1.0, 400)])
    exact = (mesh.basis.probes(points) @ values) ** 2  # skfem's own element finder and basis
    peak = float(np.max(density))
    drawn = RegularGridInterpolator((theta[:, 0], np.linspace(0.0, 1.0, 97)), density)(points.T)
    error = np.max(np.abs(drawn - exact))
    assert error < 0.005 * peak
    vertex_theta, vertex_eta, vertex_density, triangles = level_grid(spectrum, 0)
    s_of = Triangulation(mesh.mesh.p[0], mesh.mesh.p[1], triangles)
    old = LinearTriInterpolator(s_of, vertex_density)(*points)
    assert np.max(np.abs(old - exact)) > 20 * error  # what the vertex picture got wrong (the streaks)
