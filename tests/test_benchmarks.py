"""Every benchmark script runs at HEAD: each ``tests/benchmarks/bench_*.py`` with ``--smoke``, as a script.

The smoke runs check that a script still runs against the library as it is (a renamed function, an old
call signature), not its numbers: those are measured by running the scripts in full (docs/performance.md).

Each script runs as ``python bench_x.py --smoke`` would run it (``__main__``, its folder first on ``sys.path``, its
own ``sys.argv``, exit status and output of its own), in a process of its own: a child forked from one process
started for this file that has already imported numpy, scipy, numba, casadi and matplotlib.  Starting a fresh
interpreter and importing those for each script cost about a second of CPU per script; a forked child starts with
them loaded, and nothing a script does (its imports, ``sys.path``, globals, environment) reaches the next one.
"""

import os
import select
import signal
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = sorted((ROOT / "tests" / "benchmarks").glob("bench_*.py"))

# the process the scripts are forked from: it reads "script<TAB>folder<TAB>capture folder" lines, runs each script in
# a forked child in the folder, its stdout and stderr to files in the capture folder, and answers with its exit status
_FORKER = r"""
import atexit, os, runpy, sys, traceback
import numpy, scipy.integrate, scipy.optimize, scipy.sparse, numba, casadi, shapely, matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot
for line in sys.stdin:
    script, folder, capture = line.rstrip("\n").split("\t")
    pid = os.fork()
    if pid == 0:
        code = 1
        try:
            os.chdir(folder)
            for fd, name in ((1, "stdout"), (2, "stderr")):
                os.dup2(os.open(os.path.join(capture, name), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), fd)
            sys.argv = [script, "--smoke"]
            sys.path[0] = os.path.dirname(script)
            try:
                runpy.run_path(script, run_name="__main__")
                code = 0
            except SystemExit as exc:
                if isinstance(exc.code, int) or exc.code is None:
                    code = exc.code or 0
                else:
                    print(exc.code, file=sys.stderr)
            except BaseException:
                traceback.print_exc()
            atexit._run_exitfuncs()
        finally:
            sys.stdout.flush(), sys.stderr.flush()
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    print(os.waitstatus_to_exitcode(status), flush=True)
"""


@pytest.fixture(scope="module")
def forker():
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    process = subprocess.Popen([sys.executable, "-c", _FORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               env=env, text=True, start_new_session=True)
    yield process
    process.stdin.close()
    try:
        process.wait(60)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def test_there_are_benchmarks():
    assert len(SCRIPTS) >= 8


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_benchmark_smoke_run(script, tmp_path, forker):
    assert forker.poll() is None, "the process the scripts are forked from has stopped"
    (tmp_path / "run").mkdir()
    forker.stdin.write(f"{script}\t{tmp_path / 'run'}\t{tmp_path}\n")
    forker.stdin.flush()
    if not select.select([forker.stdout], [], [], 300)[0]:
        os.killpg(forker.pid, signal.SIGKILL)
        pytest.fail(f"{script.name} --smoke ran for more than 300 s")
    answer = forker.stdout.readline()
    assert answer, "the process the scripts are forked from has stopped"
    status = int(answer)
    stdout, stderr = ((tmp_path / name).read_text(errors="replace") for name in ("stdout", "stderr"))
    assert status == 0, f"{script.name} --smoke exited {status}:\n{stderr[-3000:]}"
    assert stdout.strip(), f"{script.name} --smoke printed nothing"


def test_the_full_run_covers_every_benchmark():
    # run_all.py is the run behind docs/performance.md: a benchmark it leaves out would go stale unnoticed
    done = subprocess.run([sys.executable, str(ROOT / "tests" / "benchmarks" / "run_all.py"), "--list"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    listed = {line.split("tests/benchmarks/")[1].split()[0] for line in done.stdout.splitlines()}
    assert listed == {s.name for s in SCRIPTS}


def test_the_kernel_count_reads_callgrind_as_written(tmp_path):
    # count_kernel.py runs for ~12 minutes under valgrind, outside the default run; its reading of callgrind's
    # output is checked here on a file written by hand in callgrind's format (name and position compression,
    # a call's inclusive cost on the line after calls=), the counts known by construction
    sys.path.insert(0, str(ROOT / "tests" / "benchmarks"))
    try:
        from count_kernel import tally
    finally:
        sys.path.pop(0)
    profile = tmp_path / "callgrind.out"
    profile.write_text(
        "positions: instr line\nevents: Ir Bc Bcm Bi Bim\n"
        "ob=(1) ???\nfl=(1) ???\nfn=(1) 0x1000\n"
        "0x1000 0 5 1 1\n+4 0 3\n*  0 2 1\n"             # own code of the kernel at 0x1000: Ir 10, Bc 2, Bcm 1
        "cfn=(2) __sincos_fma\ncalls=7 0x9000 0\n+2 0 140\n"  # 7 calls, 140 instructions inside them
        "fn=(3) elsewhere\n0x90000 0 1000 50 5\n"         # another function's code: not the kernel's
        "cfn=(2)\ncalls=1 0x9000 0\n+1 0 20\n",           # a call from outside: not the kernel's either
        encoding="utf-8")
    own, calls = tally(str(profile), {0x1000: "kernel"})
    assert own["kernel"] == [10, 2, 1, 0, 0]
    assert dict(calls["kernel"]) == {"__sincos_fma": [7, 140]}


@pytest.mark.skipif(not (ROOT / ".git").exists(), reason="kernel_ab.py compares git revisions: needs a git checkout")
def test_kernel_ab_runs(tmp_path):
    # the A/B tool of kernel work: the last commit against the working tree, a short run of each kernel (its
    # numbers are not checked here)
    for kernel in ("billiard", "field"):
        done = subprocess.run([sys.executable, str(ROOT / "tests" / "benchmarks" / "kernel_ab.py"), "HEAD", ".",
                               "--kernel", kernel, "--collisions", "2000", "--rounds", "1"], cwd=tmp_path,
                              capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr[-3000:]
        assert f"{kernel} kernel" in done.stdout and "ratio B/A" in done.stdout
    refused = subprocess.run([sys.executable, str(ROOT / "tests" / "benchmarks" / "kernel_ab.py"), "HEAD",
                              "no-such-revision"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert refused.returncode != 0 and "names no commit" in refused.stderr
