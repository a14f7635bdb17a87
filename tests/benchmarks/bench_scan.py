"""Benchmark of ``coinwall scan``: per-cell overhead against kernel time, and 1 → 2 local workers.

Run:  python tests/benchmarks/bench_scan.py [--quick | --smoke] [--json bench_scan.json]

Parts (each prints its numbers; nothing is asserted, this is a measurement):

1. Per-cell cost of one chaotic-fraction cell (ellipse wall, ε = 3, H = 3, 100 orbits): Benettin's method
   with a Python loop over orbits in every renormalisation round (tests/benettin_loop.py, the library's
   implementation until it moved into arrays) against
   :func:`coinwall.forward.dynamics.analysis.lyapunov.lyapunov_many` (arrays), and the time spent inside the compiled
   ensemble kernel (``_run_many``, timed by wrapping ``CompiledKernel.call``).  Overhead = cell − kernel.
2. GIL: the same cells on one worker process with 2 threads against 2 processes of 1 thread (the kernel is
   compiled without ``nogil``; if it held the GIL, 2 threads would take as long as 1).
3. Scaling: a grid of cells on a LocalCluster of 1 and of 2 single-threaded worker processes (warmed up
   first: the time is the scan's, not the cluster's start), efficiency T1 / (2 T2).
4. The plan: time of one cell at 100 orbits × 10⁴ collisions, times 10⁴ cells, over N workers.
"""

import argparse
import json
import os
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "tests"))  # the per-orbit loop, tests/benettin_loop.py

from _clock import KernelClock, log  # noqa: E402
from benettin_loop import lyapunov_loop  # noqa: E402

from coinwall.cases.scan import TableSpec, check_options, compute_cell, scan
from coinwall.forward.dynamics.analysis.islands import ELLIPSE_WALL
from coinwall.forward.dynamics.analysis.lyapunov import lyapunov_many
from coinwall.forward.dynamics.billiard.table import Billiard, random_states
from coinwall.forward.wall import Wall


def best(function, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def part_overhead(orbits, collisions, repeat):
    table = Billiard(Wall.from_expression(ELLIPSE_WALL, {"eps": 3.0}), 3.0)
    states = random_states(table, orbits, 0)
    lyapunov_many(table, states[:2], 20, workers=1)
    lyapunov_loop(table, states[:2], 20, workers=1)  # compile/load both paths first
    library = best(lambda: lyapunov_loop(table, random_states(table, orbits, 0), collisions, seed=0, workers=1),
                   repeat)
    batch = best(lambda: lyapunov_many(table, random_states(table, orbits, 0), collisions, seed=0, workers=1),
                 repeat)
    with KernelClock() as clock:
        lyapunov_many(table, states, collisions, seed=0, workers=1)
    row = {"orbits": orbits, "collisions": collisions, "library_s": library, "cell_s": batch,
           "kernel_s": clock.seconds, "overhead_s": batch - clock.seconds,
           "library_overhead_s": library - clock.seconds}
    log(f"cell {orbits} orbits x {collisions} collisions: per-orbit loop {library:.3f} s, lyapunov_many "
        f"{batch:.3f} s, kernel {clock.seconds:.3f} s -> overhead {batch - clock.seconds:.3f} s (loop "
        f"{library - clock.seconds:.3f} s)")
    return row


def _cells(count, orbits, collisions):
    options = check_options("chaotic-fraction", {"orbits": orbits, "collisions": collisions})
    table = TableSpec(ELLIPSE_WALL)
    return [(table, {"eps": 2.0 + 0.5 * k}, 3.0, k, options) for k in range(count)]


def _run_cells(client, cells):
    futures = [client.submit(compute_cell, "chaotic-fraction", *c, pure=False) for c in cells]
    client.gather(futures)


def part_gil(cells):
    from distributed import Client, LocalCluster

    rows = {}
    for label, kwargs in [("1 process x 2 threads", {"n_workers": 1, "threads_per_worker": 2}),
                          ("2 processes x 1 thread", {"n_workers": 2, "threads_per_worker": 1}),
                          ("1 process x 1 thread", {"n_workers": 1, "threads_per_worker": 1})]:
        with LocalCluster(processes=True, dashboard_address=":0", silence_logs=50, **kwargs) as cluster, \
                Client(cluster) as client:
            _run_cells(client, cells[:4])  # warm up every worker (imports, kernel load)
            start = time.perf_counter()
            _run_cells(client, cells)
            rows[label] = time.perf_counter() - start
        log(f"{label}: {rows[label]:.2f} s for {len(cells)} cells")
    return rows


def part_scaling(grid, options, workers=(1, 2)):
    from distributed import Client, LocalCluster

    rows = {}
    for n in workers:
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                          silence_logs=50) as cluster, Client(cluster) as client:
            _run_cells(client, _cells(2 * n, 5, 50))
            with tempfile.TemporaryDirectory() as folder:
                result = scan("chaotic-fraction", TableSpec(ELLIPSE_WALL), grid, output=os.path.join(folder, "s.zarr"),
                              options=options, seed=0, client=client)
            rows[n] = result.seconds
            log(f"{n} worker(s): {result.cells} cells in {result.seconds:.2f} s ({result.cells / result.seconds:.2f} "
                f"cells/s)")
    if 2 not in rows:
        return {"seconds": rows}
    efficiency = rows[1] / (2 * rows[2])
    log(f"efficiency 1 -> 2 workers: {efficiency:.2f}")
    return {"seconds": rows, "efficiency": efficiency}


def part_plan(collisions, repeat, points=((0.5, 2.5), (3.0, 3.0), (20.0, 6.0))):
    """One cell of 100 orbits × collisions at a few (ε, H); the mean is the plan's cell time."""
    times = []
    for eps, H in points:
        cell = check_options("chaotic-fraction", {"orbits": 100, "collisions": collisions})
        compute_cell("chaotic-fraction", TableSpec(ELLIPSE_WALL), {"eps": eps}, H, 0, check_options(
            "chaotic-fraction", {"orbits": 2, "collisions": 20}))
        t = best(lambda eps=eps, H=H, cell=cell: compute_cell("chaotic-fraction", TableSpec(ELLIPSE_WALL),
                                                              {"eps": eps}, H, 0, cell), repeat)
        times.append(t)
        log(f"cell eps={eps} H={H}, 100 orbits x {collisions} collisions: {t:.2f} s")
    per_cell = float(np.mean(times))
    core_hours = per_cell * 1e4 / 3600
    plan = {n: core_hours / n for n in (1, 2, 16, 64, 256)}
    log(f"100 x 100 grid: {core_hours:.2f} core-hours; on N workers (ideal): "
        + ", ".join(f"N={n}: {h * 60:.0f} min" for n, h in plan.items()))
    return {"cell_s": times, "mean_cell_s": per_cell, "core_hours": core_hours, "hours_on_N": plan}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes: checks that the script runs")
    parser.add_argument("--smoke", action="store_true",
                        help="tiny sizes, no cluster (the thread/process and scaling parts need one): checks it runs")
    parser.add_argument("--json", help="write the numbers here")
    args = parser.parse_args()
    quick = args.quick or args.smoke
    out = {"loadavg_before": os.getloadavg()}
    if args.smoke:  # tiny sizes; the store written with the synchronous scheduler (no cluster to start)
        out["overhead"] = [part_overhead(10, 100, 1)]
        with tempfile.TemporaryDirectory() as folder:
            result = scan("chaotic-fraction", TableSpec(ELLIPSE_WALL), {"eps": "2:4:2", "H": "3"},
                          output=os.path.join(folder, "s.zarr"), options={"orbits": 4, "collisions": 100}, seed=0,
                          scheduler="synchronous")
        log(f"synchronous: {result.cells} cells in {result.seconds:.2f} s")
        out["plan"] = part_plan(100, 1, points=((3.0, 3.0),))
        print(json.dumps(out, indent=1))
        return
    out["overhead"] = [part_overhead(100, c, 1 if quick else 2) for c in ((1000,) if quick else (1000, 10000))]
    cells = _cells(4 if quick else 8, 100, 1000 if quick else 2000)
    out["gil"] = part_gil(cells)
    grid = {"eps": "2:8:2", "H": "2,3"} if quick else {"eps": "1:20:4log", "H": "2,3,4"}
    out["scaling"] = part_scaling(grid, {"orbits": 100, "collisions": 1000 if quick else 2000})
    out["plan"] = part_plan(2000 if quick else 10000, 1)
    out["loadavg_after"] = os.getloadavg()  # the machine is shared: a load above its 2 cores skews the scaling
    print(json.dumps(out, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
