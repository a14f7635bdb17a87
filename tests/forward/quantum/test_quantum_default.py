"""`coinwall quantum`'s default solver: which one it picks, and that its answer carries the digits it prints."""

import importlib
import json

import numpy as np
import pytest

from coinwall.forward.quantum import make_strip, quantum_spectrum
from coinwall.forward.quantum.choice import default_solver, earned_digits, spectral_error
from coinwall.forward.wall import Wall

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def ellipse(eps=0.55):
    return Wall.from_expression(ELLIPSE, {"eps": eps})


def test_smooth_open_strip_gets_the_spectral_method():
    choice = default_solver(make_strip(ellipse(), 2.5), 100)
    assert choice.method == "spectral" and choice.accuracy == 1e-8


@pytest.mark.parametrize("wall, H, levels, eigenvectors, why", [
    (Wall.from_expression("max(cos(t), 0.5) + 1"), 4.5, 20, False, "kinks"),
    (ellipse(), 2.5, 20, True, "eigenvectors"),
    (ellipse(), 2.2, 1000, False, "modes"),  # 12,069 modes
    (Wall.from_expression("1"), 2.0000001, 4, False, "modes"),  # the widest place is 1e-7
    (ellipse(99.0), 2.05, 10, False, "neck"),
    (ellipse(), 1.8, 4, False, "falls apart"),  # 2b(θ) runs from 1.61 to 2
])
def test_other_strips_get_p4_elements(wall, H, levels, eigenvectors, why):
    choice = default_solver(make_strip(wall, H), levels, eigenvectors=eigenvectors)
    assert (choice.method, choice.order, choice.accuracy) == ("fem", 4, 1e-4) and why in choice.why


def run_cli(monkeypatch, argv):
    parser = importlib.import_module("coinwall.cases.cli.parser")
    quantum = importlib.import_module("coinwall.cases.cli.quantum")
    main = importlib.import_module("coinwall.cases.cli.main")
    monkeypatch.setitem(parser.SUBCOMMANDS, "quantum", quantum)
    return main.main(argv)


def test_default_prints_the_digits_it_earns(monkeypatch, capsys):
    """Reference: P4 elements with 12 cells, an independent discretisation (~1e-9 on the lowest levels,
    tests/forward/quantum/test_quantum.py).  The printed levels carry the digits the error estimate allows,
    and agree."""
    status = run_cli(monkeypatch, ["quantum", ELLIPSE, "--param", "eps=0.55", "--H", "2.5", "--levels", "6"])
    out = capsys.readouterr().out
    assert status == 0 and "spectral" in out
    accuracy = next(line for line in out.splitlines() if line.startswith("accuracy"))
    estimate = float(accuracy.split()[1])
    digits = earned_digits(estimate)
    assert estimate < 1e-8 and f"{digits} digits printed" in accuracy
    printed = [line.split("λ = ")[1].split()[0] for line in out.splitlines() if line.startswith("level")]
    assert len(printed) == 6 and max(len(p.replace(".", "").lstrip("0")) for p in printed) <= digits
    reference = quantum_spectrum(ellipse(), 2.5, levels=6, cells=12, order=4).eigenvalues
    assert np.max(np.abs(np.array([float(p) for p in printed]) - reference) / reference) < 1e-8


def test_error_estimate_covers_the_true_error():
    """At a coarse resolution, where the error shows: the estimate (against 4 fewer modes) is at least the
    error against P4 elements with 12 cells (~1e-9, independent), and within four orders of it."""
    strip = make_strip(ellipse(), 2.5)
    coarse = quantum_spectrum(strip, levels=30, method="spectral", cells=8).eigenvalues  # measured: 3.5e-5
    reference = quantum_spectrum(strip, levels=30, cells=12, order=4).eigenvalues
    true = np.abs(coarse - reference) / reference
    estimate = spectral_error(strip, coarse, 8)  # against 4 modes across: conservative (measured 1.1e-2)
    assert np.max(true) > 1e-6  # the test sees an error at all
    assert np.max(estimate) >= np.max(true) and np.max(estimate) < 1e4 * np.max(true)


def test_eigenvectors_or_cells_keep_the_elements(monkeypatch, capsys):
    status = run_cli(monkeypatch, ["quantum", ELLIPSE, "--param", "eps=0.55", "--H", "2.5", "--levels", "2",
                                   "--cells", "6", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert status == 0 and (data["method"], data["order"], data["cells"]) == ("fem", 4, 6)


def test_the_library_default_is_the_command_lines():
    # quantum_spectrum() without a method picks what `coinwall quantum` picks; the reference is P4 elements at
    # 12 rows (an independent discretisation, ~1e-9 on these levels by its h^8 rate)
    reference = quantum_spectrum(ellipse(), 2.5, levels=6, method="fem", cells=12, order=4).eigenvalues
    smooth = quantum_spectrum(ellipse(), 2.5, levels=6)
    assert smooth.method == "spectral"
    np.testing.assert_allclose(smooth.eigenvalues, reference, rtol=1e-8)
    kinked = quantum_spectrum(Wall.from_expression("max(cos(t), 0.5) + 1"), 4.5, levels=4)
    assert (kinked.method, kinked.order) == ("fem", 4) and len(kinked.vectors) == 4
    for given in ({"cells": 6}, {"order": 3}):  # an element parameter given: the elements
        assert quantum_spectrum(ellipse(), 2.5, levels=2, **given).method == "fem"


def test_eigenvector_uses_of_a_spectral_spectrum_say_so():
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.quantum import splitting_of
    from coinwall.forward.quantum.figures import orientation_probability, plot_density

    spectrum = quantum_spectrum(ellipse(), 2.5, levels=2, method="spectral")
    for use in (lambda: plot_density(spectrum), lambda: orientation_probability(spectrum, 0),
                lambda: splitting_of(spectrum)):
        with pytest.raises(InvalidArgument, match='needs eigenvectors.*method="fem"'):
            use()


def test_eigenvectors_asked_for_get_the_elements(monkeypatch, capsys):
    # the library and the command line choose in one place: eigenvectors=True (what --splittings passes)
    # and --order given both mean the elements
    spectrum = quantum_spectrum(ellipse(), 2.5, levels=2, eigenvectors=True)
    assert spectrum.method == "fem" and len(spectrum.vectors) == 2
    status = run_cli(monkeypatch, ["quantum", ELLIPSE, "--param", "eps=0.55", "--H", "2.5", "--levels", "2",
                                   "--order", "3", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert status == 0 and (data["method"], data["order"]) == ("fem", 3)
