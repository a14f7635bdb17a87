"""The gallery's figures at publication size, drawn as the site draws them (docs/gallery_house.py: matplotlib's
defaults, then the house style): every figure at least 1600 px wide as a PNG and no legend over a text
(tests/figurecheck.py), and the figure says what its text says.

The default run draws one quick example and checks that the quantum spectrum's text names the method its figure
shows (it said "finite elements" and drew "spectral method"); the correlation panel whose legend lay on its x
label is checked in tests/forward/formats/test_figures.py.  ``-m slow`` draws all but the scan (a dask cluster
does not start inside pytest's process; the site build runs it with the same checks, in the gallery's scraper).
"""

from __future__ import annotations

import contextlib
import io
import runpy
import sys
from pathlib import Path

import pytest

pytest.importorskip("PIL")
pytest.importorskip("sphinx_gallery", reason="the gallery's scraper is sphinx-gallery's: pip install -e \".[docs]\"")

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))
QUICK = {"plot_02_appendix_case2_critical"}
SKIPPED = {"plot_14_scan_phase_diagram"}  # dask.distributed workers: built by the site, checked by its scraper


def _draw(path, monkeypatch, tmp_path):
    """Run an example as sphinx-gallery does; returns its docstring and figures."""
    import ast

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import gallery_house
    finally:
        sys.path.remove(str(ROOT / "docs"))
    plt.close("all")
    monkeypatch.chdir(tmp_path)
    with matplotlib.rc_context():
        matplotlib.rcdefaults()
        gallery_house.reset({}, str(path))
        with contextlib.redirect_stdout(io.StringIO()):
            runpy.run_path(str(path), run_name="__main__")
        figures = [plt.figure(num) for num in plt.get_fignums()]
    return ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))), figures


def _params():
    for path in EXAMPLES:
        if path.stem in SKIPPED:
            continue
        marks = () if path.stem in QUICK else (pytest.mark.slow,)
        yield pytest.param(path, id=path.stem, marks=marks)


@pytest.mark.parametrize("path", list(_params()))
def test_gallery_figure_is_fit_to_publish(path, monkeypatch, tmp_path):
    from figurecheck import figure_problems

    docstring, figures = _draw(path, monkeypatch, tmp_path)
    assert figures, f"{path.name} draws no figure"
    for k, fig in enumerate(figures):
        assert figure_problems(fig) == [], f"{path.name}, figure {k + 1}"
    if path.stem == "plot_12_quantum_spectrum":
        # the right panel names the method the spectrum was computed with; the text must say the same
        title = figures[0].axes[1].get_title()
        method = "spectral" if "spectral" in title else "finite elements" if "elements" in title else None
        assert method and method in docstring, (title, docstring)
    import matplotlib.pyplot as plt

    plt.close("all")


def test_the_gallery_scraper_refuses_a_covered_label(monkeypatch):
    """The site's build stops on a legend over a text: the gallery's scraper raises, naming the example."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import gallery_house
    finally:
        sys.path.remove(str(ROOT / "docs"))
    plt.close("all")
    fig, ax = plt.subplots(figsize=(6, 3))
    ax.plot([0, 1], [0, 1], label="a line")
    ax.set_xlabel("x (m)")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.02))
    with pytest.raises(RuntimeError, match="plot_99_bad.py: legend 1 .* covers axes 0: x label"):
        gallery_house.scraper(None, {"src_file": "plot_99_bad.py"}, {})
    plt.close("all")


def test_the_quantum_example_names_the_method_its_figure_shows():
    """plot_12 computes 80 levels of the ε = 0.55 ellipse at H = 2.5 with the default solver; its text says which
    method that is (the figure's title names it, `test_gallery_figure_is_fit_to_publish` checks the drawn one)."""
    import ast

    from coinwall import Wall
    from coinwall.forward.quantum.choice import default_solver
    from coinwall.forward.quantum.strip import make_strip

    path = ROOT / "examples" / "plot_12_quantum_spectrum.py"
    source = path.read_text(encoding="utf-8")
    assert "eps, H = 0.55, 2.5" in source and "levels=80" in source and "method=" not in source.split('"""')[2]
    choice = default_solver(make_strip(Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 0.55}), 2.5),
                            80)
    text = " ".join(ast.get_docstring(ast.parse(source)).split())
    named = {"spectral": "as this one, a spectral method", "fem": "as this one, P4 finite elements"}[choice.method]
    assert named in text, (choice, text)
