"""Run every benchmark in full, one after the other, and keep what each printed: the run behind docs/performance.md.

Run:  python tests/benchmarks/run_all.py --out DIR [--base-python PATH] [--only NAME ...] [--skip NAME ...] [--list]

Each entry of :data:`RUNS` is one script of this folder with the arguments its section of docs/performance.md
names.  Every script runs in its own process (``OMP_NUM_THREADS=1`` where the section says one BLAS thread),
its standard output and error go to ``DIR/<name>.txt``, and ``DIR/index.txt`` records the date, the commit,
the machine's load before each script, each script's wall-clock time and exit status.  The scripts compare
against baselines *inside* their own runs (ratios in one process), so the shared machine's load moves their
absolute times, not their ratios.  ``--base-python`` is the Python of a checkout of the commit before the speed
work (see the first section of docs/performance.md) for ``bench_solve_cli.py``; without it that script is
skipped.  A script that fails does not stop the others; the exit status is 1 if any failed.
"""

from __future__ import annotations

import argparse
import datetime
import os
import pathlib
import subprocess
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]

#: (name, script, arguments, one BLAS thread): the full runs docs/performance.md quotes
RUNS = [
    ("solve_cli", "bench_solve_cli.py", ["--base-python", "{base}"], False),
    ("quantum_default", "bench_quantum_default.py", [], True),
    ("solve", "bench_solve.py", [], False),
    ("data", "bench_data.py", [], False),
    ("critical", "bench_critical.py", [], False),
    ("dense_data", "bench_dense_data.py", [], True),
    ("data_truth", "bench_data_truth.py", [], False),
    ("billiard", "bench_billiard.py", ["--collisions", "1000000", "--count"], False),
    ("toss", "bench_toss.py", [], False),
    ("correlation", "bench_correlation.py", [], False),
    ("quantum", "bench_quantum.py", [], True),
    ("scan", "bench_scan.py", [], False),
    ("coin3d", "bench_coin3d.py", [], False),
    ("house", "bench_house.py", [], False),
    ("gpu", "bench_gpu.py", [], False),  # exits 2 with one line where there is no GPU (docs/performance.md, GPU)
    ("design", "bench_design.py", [], False),
]


def _commit() -> str:
    done = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    return (done.stdout.strip() or "unknown") + (" (with uncommitted changes)" if dirty else "")


def _load() -> str:
    try:
        return " ".join(f"{v:.2f}" for v in os.getloadavg())
    except OSError:
        return "unknown"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, help="folder for the outputs (created; must not hold an index)")
    parser.add_argument("--base-python", default=None, help="Python of the baseline checkout, for bench_solve_cli")
    parser.add_argument("--only", nargs="+", default=None, metavar="NAME", help="run only these entries")
    parser.add_argument("--skip", nargs="+", default=[], metavar="NAME", help="leave these entries out")
    parser.add_argument("--list", action="store_true", help="print the entries and their commands, run nothing")
    args = parser.parse_args(argv)
    names = [name for name, *_ in RUNS]
    for name in (args.only or []) + args.skip:
        if name not in names:
            parser.error(f"no benchmark entry {name!r}; the entries: {', '.join(names)}")
    chosen = [r for r in RUNS if (args.only is None or r[0] in args.only) and r[0] not in args.skip]
    if args.list:
        for name, script, extra, one_thread in RUNS:
            prefix = "OMP_NUM_THREADS=1 " if one_thread else ""
            shown = " ".join("BASE/.venv/bin/python" if a == "{base}" else a for a in extra)
            print(f"{name}: {prefix}python tests/benchmarks/{script} {shown}".rstrip())
        return 0
    if args.out is None:
        parser.error("--out is required (a folder for the outputs)")
    if (args.out / "index.txt").exists():
        parser.error(f"{args.out} holds the outputs of an earlier run: name a new folder")
    args.out.mkdir(parents=True, exist_ok=True)
    index = args.out / "index.txt"
    started = datetime.datetime.now(datetime.timezone.utc)
    with index.open("w") as log:
        log.write(f"started {started:%Y-%m-%d %H:%M} UTC, commit {_commit()}, {os.cpu_count()} CPUs\n")
    failed = []
    for name, script, extra, one_thread in chosen:
        if "{base}" in extra:
            if args.base_python is None:
                with index.open("a") as log:
                    log.write(f"{name}: skipped (no --base-python)\n")
                continue
            extra = [args.base_python if a == "{base}" else a for a in extra]
        env = {**os.environ, "MPLBACKEND": "Agg"}  # coinwall as installed (a PYTHONPATH would reach the baseline too)
        if one_thread:
            env["OMP_NUM_THREADS"] = "1"
        command = [sys.executable, str(HERE / script), *extra]
        load = _load()
        print(f"{name}: {' '.join(command[1:])} (load {load})", file=sys.stderr, flush=True)
        start = time.perf_counter()
        with (args.out / f"{name}.txt").open("w") as out:
            status = subprocess.run(command, cwd=ROOT, env=env, stdout=out, stderr=subprocess.STDOUT).returncode
        seconds = time.perf_counter() - start
        if status != 0:
            failed.append(name)
        with index.open("a") as log:
            log.write(f"{name}: {' '.join(command[1:])}: exit {status}, {seconds:.0f} s, load before {load}\n")
    with index.open("a") as log:
        log.write(f"finished {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC"
                  f"{'; failed: ' + ', '.join(failed) if failed else ''}\n")
    print(index.read_text(), end="")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
