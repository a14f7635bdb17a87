"""Benchmark and figures of the quantum coin (docs/quantum.md, docs/performance.md).

Run:  OMP_NUM_THREADS=1 python tests/benchmarks/bench_quantum.py [--part NAME ...] [--quick] [--figures DIR]

Parts (all but ``figures`` by default):

accuracy    The lowest 100 eigenvalues of the ε = 0.55 ellipse at H = 2.5.  Reference: P4 with 44 cells across
            (its own error, from the P4 sequence's h^8 rate, is ~1e-10 relative).  Error (largest relative over
            the 100 levels) against free dofs for P2, P3, P4; the cheapest P4 mesh below 1e-6 is re-run in a
            fresh process for its wall-clock time and peak memory (VmHWM of /proc/self/status: ru_maxrss would
            carry over the parent's peak through fork and exec).
thousand    1000 levels of the same table (P4, default cells): time and peak memory in a fresh process.
transition  Poisson → GOE along the ellipse family at H = 2.5: Brody q and KS distances of 400 levels per ε,
            beside the classical chaotic fraction (coinwall.forward.dynamics.analysis.lyapunov.chaotic_fraction,
            100 orbits × 2000 collisions).
splitting   The lowest doublet's splitting Δλ(H) of the ε = 0.55 ellipse as H → D = 2: direct, flux, WKB.
figures     quantum-*.png into the folder given by ``--figures DIR`` (``--figures docs/figures`` redraws the
            docs' figures; without it the part is not run, so that a benchmark run changes no tracked file).

Results are printed and written to /tmp/bench_quantum.json (one key per part).

``--smoke``: each part's calls once at tiny sizes (a few seconds), the figures into a temporary folder and
no results file: checks the script, not the numbers.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
RESULTS = "/tmp/bench_quantum.json"


def ellipse(eps):
    from coinwall.forward.wall import Wall

    return Wall.from_expression(ELLIPSE, {"eps": eps})


def child(levels, cells, order):
    """Run one solve in a fresh process: seconds (solve only), total seconds and peak RSS (MB)."""
    code = ("import time,json;t=time.perf_counter();"
            "from coinwall.forward.wall import Wall;from coinwall.forward.quantum import quantum_spectrum;"
            f"w=Wall.from_expression({ELLIPSE!r},{{'eps':0.55}});"
            f"s=quantum_spectrum(w,2.5,levels={levels},cells={cells},order={order});"
            "print(json.dumps({'solve':s.seconds,'total':time.perf_counter()-t,'dofs':s.dofs,'cells':s.cells,"
            "'rss_mb':[int(l.split()[1]) for l in open('/proc/self/status') if l.startswith('VmHWM')][0]/1024,"
            "'last':float(s.eigenvalues[-1])}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "PYTHONPATH": "."})
    return json.loads(out.stdout.strip().splitlines()[-1])


def part_accuracy(quick):
    from coinwall.forward.quantum import quantum_spectrum

    wall = ellipse(0.55)
    reference = quantum_spectrum(wall, 2.5, levels=100, cells=28 if quick else 44, order=4)
    rows = []
    plan = {2: [16, 24, 36, 54], 3: [10, 14, 20, 28], 4: [8, 10, 12, 16, 20, 24]}
    for order, cells_list in plan.items():
        for cells in cells_list[: 3 if quick else None]:
            s = quantum_spectrum(wall, 2.5, levels=100, cells=cells, order=order)
            error = float(np.max(np.abs(s.eigenvalues - reference.eigenvalues) / reference.eigenvalues))
            rows.append({"order": order, "cells": s.cells, "dofs": s.dofs, "seconds": s.seconds, "error": error})
            print(f"P{order} cells {s.cells:3d} dofs {s.dofs:7d} {s.seconds:6.2f} s  max rel error {error:.2e}")
    p4 = [r for r in rows if r["order"] == 4 and r["error"] < 1e-6]
    answer = min(p4, key=lambda r: r["dofs"]) if p4 else None
    fresh = child(100, answer["cells"], 4) if answer else None
    print("answer", answer, "fresh process", fresh)
    return {"reference": {"cells": reference.cells, "dofs": reference.dofs, "seconds": reference.seconds,
                          "lambda_100": float(reference.eigenvalues[-1])}, "rows": rows, "answer": answer,
            "fresh": fresh}


def part_thousand(quick):
    result = child(300 if quick else 1000, "None", 4)
    print("1000 levels:", result)
    return result


def part_transition(quick):
    from coinwall.forward.dynamics.analysis.lyapunov import chaotic_fraction
    from coinwall.forward.dynamics.billiard.table import Billiard
    from coinwall.forward.quantum import quantum_spectrum

    rows = []
    for eps in ([0.03, 0.55, 3.0] if quick else [0.003, 0.03, 0.1, 0.3, 0.55, 1.0, 3.0, 10.0, 99.0]):
        wall = ellipse(eps)
        spectrum = quantum_spectrum(wall, 2.5, levels=150 if quick else 400, order=4)
        stats = spectrum.statistics()
        chaos = chaotic_fraction(Billiard(wall, 2.5), orbits=100, collisions=2000, seed=1)
        rows.append({"eps": eps, "levels": len(spectrum), "dofs": spectrum.dofs, "seconds": spectrum.seconds,
                     **stats.to_dict(), "chaotic_fraction": chaos.fraction, "chaotic_stderr": chaos.stderr})
        print(rows[-1])
    return rows


def part_splitting(quick):
    from coinwall.forward.quantum import doublet_splitting

    rows = []
    for H in ([2.4, 2.2, 2.05] if quick else [2.6, 2.5, 2.4, 2.3, 2.25, 2.2, 2.15, 2.1, 2.07, 2.05, 2.04, 2.03]):
        s = doublet_splitting(ellipse(0.55), H, cells=10)
        rows.append(s.to_dict())
        print(s)
    return rows


def part_figures(quick, results, folder):
    from coinwall.forward.formats.figure import new_figure
    from coinwall.forward.quantum import quantum_spectrum
    from coinwall.forward.quantum.figures import plot_density, plot_orientation, plot_splittings
    from coinwall.forward.quantum.tunnelling import Splitting

    os.makedirs(folder, exist_ok=True)

    def save(fig, name):
        fig.savefig(os.path.join(folder, name), dpi=110)
        print("wrote", name)

    spectrum = quantum_spectrum(ellipse(0.55), 2.5, levels=400, order=4)
    fig, axes = new_figure(2, 1, figsize=(8, 5.5))
    plot_density(spectrum, 0, ax=axes[0])
    plot_density(spectrum, 60, ax=axes[1])
    fig.tight_layout()
    save(fig, "quantum-density.png")
    near = quantum_spectrum(ellipse(0.55), 2.2, levels=2, cells=10)
    fig, axes = new_figure(1, 2, figsize=(11, 3.5))
    plot_orientation(near, (0, 1), ax=axes[0])
    axes[0].set_title("H = 2.2: the lowest doublet", fontsize=9)
    plot_orientation(spectrum, (0, 60), ax=axes[1])
    axes[1].set_title("H = 2.5", fontsize=9)
    fig.tight_layout()
    save(fig, "quantum-orientation.png")
    fig, axes = new_figure(1, 2, figsize=(11, 3.8))
    spectrum.plot(ax=axes[0])
    spectrum.weyl().plot(ax=axes[1])
    fig.tight_layout()
    save(fig, "quantum-counting.png")
    fig, _ = new_figure()
    fig = spectrum.statistics().plot()
    save(fig, "quantum-spacings.png")
    if "splitting" in results:
        splittings = [Splitting(**{**{k: v for k, v in r.items() if k != "wkb_action"}, "action": r["wkb_action"],
                                   "classes": tuple(r["classes"])}) for r in results["splitting"]]
        save(plot_splittings(splittings), "quantum-splitting.png")
    if "transition" in results:
        rows = results["transition"]
        fig, ax = new_figure(figsize=(6, 4))
        eps = [r["eps"] for r in rows]
        ax.semilogx(eps, [r["brody"] for r in rows], "o-", label="Brody q (quantum, 400 levels)")
        ax.semilogx(eps, [r["chaotic_fraction"] for r in rows], "s--", label="chaotic fraction (classical)")
        ax.set_xlabel("ε (ellipse wall, H = 2.5)")
        ax.set_ylim(-0.05, 1.05)
        ax.legend(fontsize=8)
        fig.tight_layout()
        save(fig, "quantum-transition.png")


def _smoke():
    """Each part's calls once, at tiny sizes; nothing written outside a temporary folder."""
    import tempfile

    from coinwall.forward.dynamics.analysis.lyapunov import chaotic_fraction
    from coinwall.forward.dynamics.billiard.table import Billiard
    from coinwall.forward.formats.figure import new_figure
    from coinwall.forward.quantum import doublet_splitting, quantum_spectrum
    from coinwall.forward.quantum.figures import plot_density, plot_orientation

    wall = ellipse(0.55)
    reference = quantum_spectrum(wall, 2.5, levels=8, cells=8, order=4)
    for order in (2, 3, 4):
        s = quantum_spectrum(wall, 2.5, levels=8, cells=4, order=order)
        error = float(np.max(np.abs(s.eigenvalues - reference.eigenvalues) / reference.eigenvalues))
        print(f"P{order} cells {s.cells} dofs {s.dofs} {s.seconds:.2f} s  max rel error {error:.2e}")
    print("fresh process", child(8, 4, 4))
    print(quantum_spectrum(wall, 2.5, levels=30, order=4).statistics().to_dict())
    print(chaotic_fraction(Billiard(wall, 2.5), orbits=4, collisions=100, seed=1).fraction)
    print(doublet_splitting(wall, 2.2, cells=6))
    with tempfile.TemporaryDirectory() as folder:
        fig, axes = new_figure(1, 2, figsize=(8, 3))
        plot_density(reference, 0, ax=axes[0])
        plot_orientation(reference, (0, 1), ax=axes[1])
        fig.savefig(os.path.join(folder, "smoke.png"), dpi=50)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", action="append", choices=["accuracy", "thousand", "transition", "splitting",
                                                            "figures"])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--figures", metavar="DIR", default=None, help="draw the figures into DIR (the figures part)")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes, no files: checks the script")
    args = parser.parse_args()
    if args.smoke:
        _smoke()
        return
    parts = args.part or ["accuracy", "thousand", "transition", "splitting"] + (["figures"] if args.figures else [])
    if "figures" in parts and not args.figures:
        parser.error("--part figures needs --figures DIR (docs/figures redraws the docs' figures)")
    results = {}
    if os.path.exists(RESULTS):
        with open(RESULTS) as handle:
            results = json.load(handle)
    for name in parts:
        start = time.perf_counter()
        if name == "figures":
            part_figures(args.quick, results, args.figures)
        else:
            results[name] = globals()[f"part_{name}"](args.quick)
        print(f"[{name}: {time.perf_counter() - start:.1f} s]")
        with open(RESULTS, "w") as handle:
            json.dump(results, handle, indent=1)


if __name__ == "__main__":
    main()
