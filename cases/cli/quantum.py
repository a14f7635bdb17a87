"""``coinwall quantum``: the spectrum of the quantum coin (the Dirichlet Laplacian on the billiard strip)."""

from __future__ import annotations

import json
import math
import os

from .common import (
    LibraryChoices,
    add_command,
    count,
    number,
    progress_bar,
    wall_arguments,
    written_lines,
)

__all__ = ["MAX_SECONDS", "register"]

#: The longest solve started without --allow-long, by the library's estimate (one idle core; measured figures in
#: coinwall.forward.quantum.spectrum.estimated_seconds).
MAX_SECONDS = 120.0

DESCRIPTION = """\
The lowest levels of the quantum body between the walls (docs/quantum.md).

With η = y/κ the Hamiltonian is −(ħ²/2Mκ²)(∂²_θ + ∂²_η): the levels are the eigenvalues λ of −Δ on the
billiard's strip b0 + b(θ) < η < H − b0 − b(θ + π), periodic in θ, zero on both walls (units 1/κ²;
E = ħ²λ/(2Mκ²)).  The method is chosen for the wall (--method auto, the default): a spectral basis for a
smooth wall on an open strip (printed to the digits a coarser second solve confirms), else finite elements
of degree --order (default 4) on a mesh that follows the walls exactly; either is solved
class by class: each level is labelled by its symmetry class (swap: (θ, η) → (θ + π, H − η), always;
mirror: θ → −θ and half_turn: θ → θ + π when the wall has them).  Weyl's law N ≈ Aλ/4π − L√λ/4π + C is
checked.  Where H is below the body's diameter the strip falls apart: each region is solved on its own
(a finding, reported).  Just above it the levels pair into heads–tails doublets: --splittings (and any
list of several H) reports the splitting λ₂ − λ₁ of each low pair, directly and by Herring's flux
formula (which reaches splittings far below rounding), with the WKB action through the neck; --body
gives a physical body's energies and the tunnelling time ħ/ΔE."""

EXAMPLE = """\
coinwall quantum "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=0.55 --H 2.5 --levels 100 -o spectrum.png
coinwall quantum "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=0.55 --H 2.1,2.2,2.3 --levels 2 --json"""


def register(subparsers):
    """Add the ``quantum`` subcommand."""
    parser = add_command(subparsers, "quantum", help="levels of the quantum body: spectrum, classes, tunnelling",
                         description=DESCRIPTION, example=EXAMPLE)
    wall_arguments(parser, intervals=False)
    parser.add_argument("--H", required=True, metavar="H1,H2,...",
                        help="distance between the walls (units of κ); several, comma-separated, make a doublet scan")
    parser.add_argument("--b0", type=number, default=0.0, help="offset added to the wall (default 0)")
    parser.add_argument("--levels", type=count, required=True, help="number of levels (the lowest)")
    parser.add_argument("--method", choices=LibraryChoices("coinwall.forward.quantum.spectrum", "METHODS", ("auto",)),
                        metavar="METHOD", default="auto",
                        help="solver: auto (default: spectral for a smooth wall on an open strip, up to 12,000 "
                             "modes, else fem of degree 4), fem (Lagrange elements on a mesh that follows the walls) "
                             "or spectral (Fourier × Legendre modes, smooth walls only, exponentially convergent; no "
                             "eigenvectors, so no --splittings or |ψ|² figure)")
    parser.add_argument("--order", type=int, default=None, choices=(2, 3, 4),
                        help="element degree (default 4; given, --method auto uses the elements)")
    parser.add_argument("--cells", type=count, default=None,
                        help="fem: rows of cells across the strip (default: from --levels, ~1e-4 relative at the top); "
                             "spectral: polynomial modes across (default ~1e-8)")
    parser.add_argument("--body", default=None, metavar="MASS,KAPPA",
                        help="mass (kg) and radius of gyration κ (m) of a physical body: adds the energies "
                             "E = ħ²λ/(2Mκ²) (J) and the tunnelling time ħ/ΔE (s) of each pair")
    parser.add_argument("--splittings", action="store_true",
                        help="report the splitting of each low pair of levels (always on for several H)")
    parser.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                        help="figure (.png, .svg, .pdf: counting function and |ψ|², or Δλ(H) for a scan) or .json")
    parser.add_argument("--json", action="store_true", help="print the result as JSON (no progress bar)")
    # dest max_seconds: the library's bound, so that its messages name this flag
    parser.add_argument("--allow-long", dest="max_seconds", action="store_const", const=None, default=MAX_SECONDS,
                        help="solve even when the estimated time exceeds two minutes (the estimate is printed)")
    parser.set_defaults(run=_cmd_quantum)


def _heights(text):
    from coinwall.forward.validation import parse_number_list

    return parse_number_list("H", text)


def _body(text):
    from coinwall.forward.errors import InvalidArgument

    if text is None:
        return None
    try:
        values = [number(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 2 or not all(math.isfinite(v) and v > 0 for v in values):
        raise InvalidArgument(f"--body must be two positive numbers MASS,KAPPA (kg, m), got {text!r}")
    from coinwall.forward.quantum.tunnelling import HBAR

    mass, kappa = values
    # the energy unit ħ²/(2Mκ²) in logarithms (M κ² may overflow or vanish in floating point): energies λ × unit
    # and times ħ/ΔE must be numbers, with room for the spectrum's range of λ (1e-150 to 1e150)
    log_unit = 2 * math.log10(HBAR) - math.log10(2.0) - math.log10(mass) - 2 * math.log10(kappa)
    if not -150 <= log_unit <= 150:
        raise InvalidArgument(f"--body {text}: the energy unit ħ²/(2Mκ²) would be 1e{log_unit:.0f} J, outside what "
                              "the energies and tunnelling times can be given in (1e-150 to 1e150 J); give M in kg "
                              "and κ in m")
    return tuple(values)


def _solve(args, wall, H, bar):
    import numpy as np

    from coinwall.forward.quantum import make_strip, quantum_spectrum, splitting_of

    strip = make_strip(wall, H, args.b0)
    # --method auto picks the solver as the library does: the elements when --cells or --order is given or
    # --splittings needs eigenvectors, else the fastest accurate one for the strip
    spectrum = quantum_spectrum(strip, levels=args.levels, method=args.method, cells=args.cells, order=args.order,
                                eigenvectors=args.splittings, max_seconds=args.max_seconds,
                                progress=(lambda n: bar.update(n)) if bar is not None else None)
    splittings = None
    if args.splittings and strip.periodic and spectrum.symmetry_names:
        splittings = [splitting_of(spectrum, k) for k in range(len(spectrum) // 2)]
    error = None
    if spectrum.method == "spectral":  # with --cells too: a resolution given is no accuracy earned
        from coinwall.forward.quantum.choice import spectral_error

        # the digits the default modes have earned: a second, coarser solve says (its docstring)
        error = float(np.max(spectral_error(strip, spectrum.eigenvalues, spectrum.cells)))
    return spectrum, splittings, error


def _finite(value):
    """A number for JSON and the text: None where it is not finite (a splitting of 0 is no time)."""
    value = float(value)
    return value if math.isfinite(value) else None


def _summary(spectrum, splittings, error, body):
    from coinwall.forward.quantum.tunnelling import HBAR, tunnelling_time

    strip = spectrum.strip
    weyl = spectrum.weyl()
    physical = None
    if body is not None:
        mass, kappa = body
        # in logarithms: M κ² may overflow or vanish where the unit itself is a fine number (--body checks it)
        unit = math.exp(2 * math.log(HBAR) - math.log(2.0) - math.log(mass) - 2 * math.log(kappa))
        physical = {"mass": mass, "kappa": kappa, "energy_unit": unit,
                    "energies": [float(v) * unit for v in spectrum.eigenvalues],
                    "tunnelling_times": None if splittings is None else
                    [_finite(tunnelling_time(s.flux, mass, kappa)) if s.flux_trusted else None for s in splittings]}
    return {
        "H": strip.H, "b0": strip.table.b0,
        "eigenvalues": [float(v) for v in spectrum.eigenvalues], "classes": list(spectrum.classes),
        "symmetries": list(spectrum.symmetry_names),
        "splittings": None if splittings is None else [s.to_dict() for s in splittings],
        "weyl": {"area": weyl.area, "wall_length": weyl.wall_length, "constant": weyl.constant,
                 "residual": [float(r) for r in weyl.residual], "rms_residual": weyl.rms_residual},
        "strip": strip.to_dict(), "method": spectrum.method, "order": spectrum.order, "cells": spectrum.cells,
        "dofs": spectrum.dofs, "seconds": spectrum.seconds, "body": physical,
        # the spectral method's largest relative difference from a coarser solve (None: not estimated)
        "error_estimate": error if error is not None and math.isfinite(error) else None,
    }


def _figure(results, wall=None, name=None):
    from coinwall.forward.formats.style import house_style

    with house_style():
        return _draw_figure(results, wall, name)


def _draw_figure(results, wall, name):
    from coinwall.forward.formats.figure import new_figure
    from coinwall.forward.formats.style import wall_label
    from coinwall.forward.quantum.figures import plot_counting, plot_density, plot_splittings

    if len(results) > 1:
        splittings = [s[0] for _, s in results if s]
        fig, ax = new_figure(figsize=(6.4, 4.2))
        plot_splittings(splittings, ax=ax, wall=wall, name=name)
        fig.tight_layout()
        return fig
    spectrum = results[0][0]
    if not spectrum.meshes:  # the spectral method has no eigenvectors: the counting function alone
        fig, ax = new_figure(figsize=(6, 4))
        plot_counting(spectrum, ax=ax, name=name)
        fig.tight_layout()
        return fig
    fig, (left, right) = new_figure(1, 2, figsize=(12, 4.2), gridspec_kw={"width_ratios": [1, 1.7]},
                                    layout="constrained")
    plot_counting(spectrum, ax=left, name=name)
    plot_density(spectrum, 0, ax=right, name=name)
    left.set_title(f"{len(spectrum.eigenvalues)} levels ({spectrum.method}) and Weyl's law")
    right.set_title(f"|ψ|² of level 1 ({spectrum.classes[0]}), λ = {spectrum.eigenvalues[0]:.6g} /κ²")
    fig.suptitle(f"Quantum body of {wall_label(spectrum.strip.table.wall, name)}, H = {spectrum.strip.H:g} κ")
    return fig


def _cmd_quantum(args):
    from coinwall.forward.errors import InvalidArgument
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, write_all

    from .common import load_wall, wall_options

    heights = _heights(args.H)
    body = _body(args.body)
    check_paths(args.output, FIGURE_FORMATS + (".json",))
    args.splittings = args.splittings or len(heights) > 1
    if args.splittings and args.method == "spectral":
        raise InvalidArgument("--splittings (and a scan of several --H) need --method fem: Herring's flux formula "
                              "uses the eigenvectors")
    wall = load_wall(args.wall, args.param, **wall_options(args))
    with progress_bar(args, None, "class") as bar:
        solved = [_solve(args, wall, H, bar) for H in heights]
    results = [(spectrum, splittings) for spectrum, splittings, _ in solved]
    summaries = [_summary(*r, body) for r in solved]
    document = summaries[0] if len(summaries) == 1 else {"scan": summaries}
    document = {"wall": args.wall, "params": dict(wall.params), **document}
    files = {}
    for path in args.output:
        if os.path.splitext(path)[1].lower() in FIGURE_FORMATS:
            files[path] = figure_bytes(_figure(results, wall, args.wall), path)
        else:
            files[path] = json.dumps(document, allow_nan=False).encode()
    written = write_all(files)
    if args.json:
        print(json.dumps(document, indent=1, allow_nan=False))
        return 0
    for (spectrum, splittings, error), summary in zip(solved, summaries):
        _print(spectrum, splittings, summary["body"], default_mesh=args.cells is None, error=error)
    for line in written_lines(written, written.replaced):
        print(line)
    return 0


def _print(spectrum, splittings, body, default_mesh=True, error=None):
    strip = spectrum.strip
    print(f"strip      {strip!r}")
    if not strip.periodic:
        parts = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in strip.regions)
        print(f"finding    H < diameter {strip.diameter:.10g}: the strip falls apart into {len(strip.regions)} "
              f"regions θ ∈ {parts}, each solved on its own")
    if spectrum.method == "fem":
        solver = f"fem P{spectrum.order}, {spectrum.cells} cells across, {spectrum.dofs} dofs"
    else:
        solver = f"{spectrum.method}, {spectrum.cells} modes across, {spectrum.dofs} modes"
    print(f"solver     {solver}, {spectrum.seconds:.3g} s")
    if spectrum.method == "fem" and default_mesh:
        # default_cells aims at ~1e-4 relative at the top level: print the digits that carry, and say so
        print("accuracy   about 1e-4 relative at the highest level (the default mesh; --cells for "
              "more; --json has every digit)")
        digits = 6
    elif error is not None:
        from coinwall.forward.quantum.choice import earned_digits

        digits = earned_digits(error)
        if math.isfinite(error):
            print(f"accuracy   {error:.1g} relative at most (the difference from a solve with 4 fewer modes "
                  f"across); {digits} digits printed, --json has every digit")
        else:  # the coarser solve has fewer modes than levels asked for
            print(f"accuracy   not estimated (too few modes for a coarser check); {digits} digits printed, "
                  "--json has every digit")
    else:
        digits = 10
        print("accuracy   not estimated (--cells sets the mesh); 10 digits printed: compare with a finer --cells")
    width = len(str(len(spectrum)))
    for k, (value, name) in enumerate(zip(spectrum.eigenvalues, spectrum.classes)):
        print(f"level {k + 1:>{width}}  λ = {value:.{digits}g}  {name}")
    weyl = spectrum.weyl()
    print(f"weyl       A = {weyl.area:.8g}, L = {weyl.wall_length:.8g}, C = {weyl.constant:.4g}; "
          f"N − N̄ over the upper half: mean {weyl.mean_residual:.3g}, rms {weyl.rms_residual:.3g}")
    for k, s in enumerate(splittings or ()):
        direct = f"{s.direct:.6g}" + ("" if s.direct_trusted else " (below rounding)")
        flux = f"{s.flux:.6g}" + ("" if s.flux_trusted else " (below rounding)")
        print(f"pair {k + 1}     Δλ direct {direct}, flux {flux}, WKB action S = {s.action:.6g} "
              f"(exp(−S) = {math.exp(-s.action):.3g})")
    if body is not None:
        print(f"body       M = {body['mass']:g} kg, κ = {body['kappa']:g} m: E = ħ²λ/(2Mκ²) = λ × "
              f"{body['energy_unit']:.6g} J; E₁ = {body['energies'][0]:.6g} J")
        for k, t in enumerate(body["tunnelling_times"] or ()):
            if t is not None:
                print(f"pair {k + 1}     tunnelling time ħ/ΔE = 2Mκ²/(ħΔλ) = {t:.4g} s")
