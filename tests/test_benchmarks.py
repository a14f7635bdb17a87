"""Every benchmark script runs at HEAD: each ``tests/benchmarks/bench_*.py`` with ``--smoke``, in a subprocess.

The smoke runs check that a script still runs against the library as it is (a renamed function, an old
call signature), not its numbers: those are measured by running the scripts in full (docs/performance.md).
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = sorted((ROOT / "tests" / "benchmarks").glob("bench_*.py"))


def test_there_are_benchmarks():
    assert len(SCRIPTS) >= 8


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_benchmark_smoke_run(script, tmp_path):
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, str(script), "--smoke"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, f"{script.name} --smoke exited {done.returncode}:\n{done.stderr[-3000:]}"
    assert done.stdout.strip(), f"{script.name} --smoke printed nothing"


def test_the_full_run_covers_every_benchmark():
    # run_all.py is the run behind docs/performance.md: a benchmark it leaves out would go stale unnoticed
    done = subprocess.run([sys.executable, str(ROOT / "tests" / "benchmarks" / "run_all.py"), "--list"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    listed = {line.split("tests/benchmarks/")[1].split()[0] for line in done.stdout.splitlines()}
    assert listed == {s.name for s in SCRIPTS}
