"""Every figure the command line writes is fit to publish: its PNG at least 1600 px wide (whatever the figure's
size in inches: ``figure_bytes`` picks the resolution) and no legend over a text (tests/figurecheck.py).

Each command runs in-process with the one writer of figures, ``coinwall.forward.formats.figure.figure_bytes``,
watched: every figure it is handed is checked, and the PNG file written is measured.  The default run takes
two quick commands; ``-m slow`` every command that draws.
"""

from __future__ import annotations

import pytest

from coinwall.cases.cli.main import main
from figurecheck import figure_problems, png_size

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
COMMANDS = {
    "solve": (["solve", "-o", "body.png"], False),
    "coin3d": (["coin3d", "fit", "-o", "flips.png"], False),
    "wall": (["wall", "--polar", "1 + 0.2*cos(3*t)", "-o", "wall.png"], True),
    "section": (["section", "case:ellipse-0.55", "--H", "1.9", "--orbits", "3", "--collisions", "300", "--seed", "1",
                 "-o", "section.png"], True),
    "correlation": (["correlation", "case:coin", "--H", "2.4", "--bounces", "20000", "--max-lag", "10", "--orbits",
                     "5", "--seed", "1", "-o", "correlation.png"], True),
    "kam": (["kam", "--H", "3", "--orbits", "4", "--collisions", "200", "--steps", "1", "-o", "kam.png"], True),
    "quantum": (["quantum", ELLIPSE, "--param", "eps=0.55", "--H", "2.5", "--levels", "6", "-o", "spectrum.png"],
                True),
    "toss": (["toss", "case:coin", "--g", "1", "--e", "0.6", "--height", "1.2", "--v0", "0:3:24", "--omega", "0:8:24",
              "-o", "basins.png"], True),
}


@pytest.mark.parametrize("name", [pytest.param(name, marks=(pytest.mark.slow,) if slow else ())
                                  for name, (_, slow) in COMMANDS.items()])
def test_cli_figure_is_fit_to_publish(name, tmp_path, monkeypatch, capsys):
    import coinwall.cases.paper.figures as paper_figures
    import coinwall.forward.formats.figure as writer

    original = writer.figure_bytes
    checked = []

    def watched(fig, path, *, close=True):
        checked.append((path, figure_problems(fig)))
        return original(fig, path, close=close)

    monkeypatch.setattr(writer, "figure_bytes", watched)
    monkeypatch.setattr(paper_figures, "figure_bytes", watched)
    monkeypatch.chdir(tmp_path)
    argv, _ = COMMANDS[name]
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 0, err
    path = argv[argv.index("-o") + 1]
    assert checked and all(problems == [] for _, problems in checked), checked
    width, _ = png_size((tmp_path / path).read_bytes())
    assert width >= 1600, width
