"""The kernels on a GPU (device="gpu"): the same kernel text compiled for CUDA, checked against the CPU kernel.

The default run executes the GPU code path in numba's CUDA simulator (tests/conftest.py sets
NUMBA_ENABLE_CUDASIM=1): the kernel text runs as Python, one thread per orbit, and must give the CPU kernel's
collisions.  tests/benchmarks/gpu_check.sh runs this file on a real GPU (NUMBA_ENABLE_CUDASIM=0); there the
collisions agree to rounding (fused multiply-adds, CUDA's math library), which the one-step check measures
(coinwall.forward.dynamics.billiard.onestep): from every GPU state, the GPU's and the CPU's next collisions,
each within the bound of what the kernel guarantees.  Sizes are small (the simulator runs ~10^4 collisions a
second).
"""

from __future__ import annotations

import doctest

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard import gpu
from coinwall.forward.dynamics.billiard.onestep import next_collisions, one_step_check
from coinwall.forward.dynamics.billiard.table import Billiard, ensemble, random_states
from coinwall.forward.errors import InvalidArgument

numba = pytest.importorskip("numba")
pytest.importorskip("numba.cuda", reason="numba-cuda is not installed (pip install 'coinwall[gpu]')")
SIMULATOR = bool(numba.config.ENABLE_CUDASIM)

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def _tables():
    """The coin (ε = 99, H = 3), the paper's mixed ellipse (ε = 0.55, H = 1.9), a Fourier wall, and a wall as data:
    the ε = 0.55 ellipse sampled at 1° and rounded to 5 digits (the CSV a person would bring)."""
    deg = np.deg2rad(np.arange(360.0))
    samples = np.round(np.sqrt((1 + 0.55 * np.cos(deg) ** 2) / 1.55), 5)
    return {"coin": Billiard(Wall.from_expression(ELLIPSE, {"eps": 99.0}), 3.0),
            "ellipse": Billiard(Wall.from_expression(ELLIPSE, {"eps": 0.55}), 1.9),
            "fourier": Billiard(Wall.from_fourier(1.0, [0.15, 0.0, 0.04], [0.0, 0.03]), 3.5),
            "data": Billiard(Wall.from_samples(deg, samples, rounding=5e-6), 2.2)}


TABLES = _tables()


@pytest.mark.parametrize("name", sorted(TABLES))
def test_gpu_orbits_are_the_cpu_kernels(name):
    # the same launch on both devices: every collision of every orbit, the notes and the end angles
    table = TABLES[name]
    states = random_states(table, 4, seed=7)
    on_gpu = ensemble(table, states, 25, device="gpu")
    on_cpu = ensemble(table, states, 25, device="cpu")
    # the simulator runs the kernel text as Python: the CPU kernel's floats exactly.  A real GPU rounds differently
    # (fused multiply-adds, its math library) and chaos amplifies that (the coin's λ ≈ 1.2 per collision: 1e-16
    # becomes 1e-12 in ~8 collisions), so whole orbits are compared over their first 6 collisions only; the
    # one-step checks below hold every collision
    first = 25 if SIMULATOR else 6
    for g, c in zip(on_gpu, on_cpu):
        assert len(g) == len(c) == 25 and g.note == c.note == ""
        assert np.array_equal(g.side[:first], c.side[:first])
        for field in ("time", "theta", "eta", "v_theta", "v_eta"):
            got, want = getattr(g, field)[:first], getattr(c, field)[:first]
            if SIMULATOR:
                assert np.array_equal(got, want), field
            else:
                assert np.allclose(got, want, rtol=0, atol=1e-9), field
        assert (g.end_angle, g.end_turns) == (c.end_angle, c.end_turns) or not SIMULATOR
    # collision by collision: from each GPU state, the GPU's next collision against the CPU's (the same floats in,
    # so in the simulator the same floats out) and the orbit's own next one against the CPU's (the reported θ is
    # unwrapped and rounded: the simulator's differences are that rounding), each within the kernel's bound
    same, orbit = one_step_check(table, on_gpu, device="gpu"), one_step_check(table, on_gpu)
    assert same.collisions == orbit.collisions == 4 * 24 and same.ok and orbit.ok, (same.worst, orbit.worst)
    if SIMULATOR:
        assert same.max_difference == 0.0 and orbit.max_difference < 1e-13


def test_one_step_check_sees_a_wrong_collision():
    # the check must fail on a trajectory that is not the kernel's: one collision moved by 1e-9 in time, and one
    # orbit whose second collision is taken from another orbit (a flight through a wall, or a missed collision)
    table = TABLES["fourier"]
    orbits = ensemble(table, random_states(table, 3, seed=3), 8)
    assert one_step_check(table, orbits).ok
    from dataclasses import replace

    moved = orbits[0].time.copy()
    moved[4] += 1e-9
    check = one_step_check(table, [replace(orbits[0], time=moved)])
    assert not check.ok and check.max_ratio > 10 and check.worst[0]["collision"] in (4, 5)  # (flights into 4 and 5)
    other = orbits[0]
    spliced = replace(other, theta=np.r_[other.theta[:2], orbits[1].theta[2:]],
                      eta=np.r_[other.eta[:2], orbits[1].eta[2:]])
    assert not one_step_check(table, [spliced]).ok


def _contacts_at_gap(table, states, turns, leaving, gap):
    """The next collision of each state moved along its flight to where the gap to the wall is ``gap`` (Newton on
    the numpy wall from the CPU kernel's contact), and reflected with the wall's slope there (the kernel's law)."""
    nxt, side, found = next_collisions(table, states, turns, leaving)
    th0, eta0, vt, ve = states.T
    t = nxt[:, 0].copy()
    up = side == 1
    for _ in range(8):
        phi = th0 + vt * t + np.where(up, np.pi, 0.0)
        b, d1, _ = table.wall.derivatives(phi)
        g = np.where(up, table.H - table.b0 - eta0 - ve * t - b, eta0 + ve * t - table.b0 - b)
        rate = np.where(up, -ve, ve) - vt * d1
        t -= (g - gap) / rate
    s = np.where(up, -d1, d1)
    f = 2 * (ve - s * vt) / (1 + s * s)
    v = np.column_stack([vt + f * s, ve - f])
    v /= np.hypot(v[:, 0], v[:, 1])[:, None]
    moved = np.column_stack([t, th0 + vt * t + 2 * np.pi * turns, eta0 + ve * t, v])
    return moved, side, found


@pytest.mark.parametrize("name", ["coin", "fourier"])
def test_one_step_bound_is_what_the_kernel_promises(name):
    # the bound of a collision covers any contact the kernel could return (|gap| ≤ tol on the same flight):
    # contacts moved to gaps of ±0.99 tol pass it, and not by orders of magnitude (the time moves by tol/|g'|,
    # a quarter of the bound); a contact at 8 tol, which the kernel never returns, fails it
    table = TABLES[name]
    orbits = ensemble(table, random_states(table, 40, seed=9), 12)
    for gap, passes in ((0.99, True), (-0.99, True), (8.0, False)):
        check = one_step_check(table, orbits, device=lambda *a, g=gap: _contacts_at_gap(table, *a, g * table.tol))
        assert check.collisions == 40 * 11 and check.other_wall == 0 and check.grazes == 0
        assert check.ok == passes, (gap, check)
        assert 0.1 < check.max_ratio < 1.0 if passes else check.max_ratio > 1.0


@pytest.mark.filterwarnings("ignore:divide by zero:RuntimeWarning")  # the simulator runs 1/v_η = 1/0 as numpy
def test_free_flight_and_resumed_orbits_on_the_gpu():
    # an orbit that never collides again (horizontal, in the open channel) stops with the CPU's note; orbits that
    # continue from a collision (on a wall, with whole turns of θ) are followed exactly as on the CPU
    table = TABLES["fourier"]
    channel = [0.3, 0.5 * (table.H), 1.0, 0.0]
    start = random_states(table, 2, seed=11)
    first = ensemble(table, start, 7)
    resumed = [t.resume_state() for t in first]
    states = np.array([channel] + [s for s, _ in resumed])
    turns = [0] + [k for _, k in resumed]
    on_gpu = ensemble(table, states, 9, turns=turns, device="gpu")
    on_cpu = ensemble(table, states, 9, turns=turns)
    assert len(on_gpu[0]) == 0 and on_gpu[0].note == on_cpu[0].note and "free flight" in on_gpu[0].note
    first = 9 if SIMULATOR else 5  # (chaos: see the test above)
    for g, c in zip(on_gpu[1:], on_cpu[1:]):
        assert len(g) == 9 and np.allclose(g.theta[:first], c.theta[:first], rtol=0, atol=1e-9)
        assert np.array_equal(g.side[:first], c.side[:first])
    assert one_step_check(table, on_gpu[1:]).ok and one_step_check(table, on_gpu[1:], device="gpu").ok


def test_analyses_take_the_device():
    # P(n), the section and the Lyapunov exponents give the CPU's numbers on the GPU (in the simulator to the bit;
    # on a real GPU the orbits part after a few collisions, so these small samples agree only roughly)
    from coinwall.forward.dynamics.analysis.correlation import correlation
    from coinwall.forward.dynamics.analysis.lyapunov import chaotic_fraction
    from coinwall.forward.dynamics.analysis.poincare import poincare_section

    table = TABLES["coin"]
    a = correlation(table, 90, 2, orbits=2, seed=2, burn=0)
    b = correlation(table, 90, 2, orbits=2, seed=2, burn=0, device="gpu")
    assert b.P[0] == 1.0 and np.allclose(a.P, b.P, rtol=0, atol=0 if SIMULATOR else 0.5)
    s1 = poincare_section(table, 2, 20, seed=4)
    s2 = poincare_section(table, 2, 20, seed=4, device="gpu")
    if SIMULATOR:
        assert s1.theta.size == s2.theta.size and np.array_equal(s1.theta, s2.theta)
    else:
        assert abs(s1.theta.size - s2.theta.size) <= 10 and np.allclose(s1.theta[:3], s2.theta[:3], atol=1e-9)
    f1 = chaotic_fraction(TABLES["ellipse"], orbits=2, collisions=20, seed=5)
    f2 = chaotic_fraction(TABLES["ellipse"], orbits=2, collisions=20, seed=5, device="gpu")
    lam1, lam2 = f1.exponents.per_collision, f2.exponents.per_collision
    assert np.all(np.isfinite(lam2)) and np.allclose(lam1, lam2, rtol=0, atol=1e-12 if SIMULATOR else 0.5)


def test_device_refused_in_one_line(monkeypatch, capsys):
    # an unknown device, and "gpu" where numba-cuda is missing: InvalidArgument from the library, one line and
    # exit status 2 from the command line, before any work
    table = TABLES["fourier"]
    with pytest.raises(InvalidArgument, match="`device` must be one of 'cpu', 'gpu'"):
        ensemble(table, random_states(table, 1, seed=0), 3, device="cuda")

    def missing():
        raise ImportError("No module named 'numba.cuda'")

    monkeypatch.setattr(gpu, "cuda_module", missing)
    with pytest.raises(InvalidArgument, match="numba-cuda is not installed"):
        gpu.check_device("gpu")
    from coinwall.cases.cli.main import main

    for argv in (["section", "case:ellipse-0.55", "--H", "1.9", "--orbits", "2", "--collisions", "5"],
                 ["correlation", "case:coin", "--H", "3", "--bounces", "100", "--orbits", "2", "--max-lag", "2"],
                 ["kam", "--H", "3", "--orbits", "2", "--collisions", "20", "--steps", "0"],
                 ["simulate", "case:coin", "--H", "3", "--collisions", "10", "--orbits", "3"]):
        assert main(argv + ["--device", "gpu"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--device" in err[0] and "numba-cuda is not installed" in err[0], err


def test_reference_method_stays_on_the_cpu():
    table = TABLES["fourier"]
    with pytest.raises(InvalidArgument, match="reference"):
        ensemble(table, random_states(table, 1, seed=0), 3, method="reference", device="gpu")


def test_docstring_examples():
    # the Examples sections of the GPU module, the one-step check, ensemble and ensemble_statistics run (those that
    # need a GPU are skipped in the text)
    from coinwall.forward.dynamics.analysis import orbitstats
    from coinwall.forward.dynamics.billiard import onestep
    from coinwall.forward.dynamics.billiard import table as table_module

    for module in (gpu, onestep):
        result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
        assert result.failed == 0 and result.attempted > 0, module.__name__
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for func in (table_module.ensemble, orbitstats.ensemble_statistics):
        for test in doctest.DocTestFinder().find(func, globs=vars(__import__(func.__module__, fromlist=["_"]))):
            runner.run(test)
    assert runner.failures == 0 and runner.tries >= 5


COMPILE_FOR_SM90 = r"""
import sys
import numba.cuda.dispatcher as dispatcher
from numba import cuda, types

class Hopper:  # no GPU here: compile for an H100/H200 (sm_90) as if one were present
    compute_capability = (9, 0)

dispatcher.get_current_device = lambda: Hopper()
from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard import gpu
from coinwall.forward.dynamics.billiard.kernel import KERNEL_SOURCE

module = gpu.gpu_module(Wall.from_expression(sys.argv[1], {"eps": 99.0}), KERNEL_SOURCE, gpu.BILLIARD_LAUNCHER,
                        "coinwall_gpu")
f64, i64 = types.float64, types.int64
a1, a2, v64 = types.Array(f64, 1, "C"), types.Array(f64, 2, "C"), types.Array(i64, 1, "C")
signature = (a2, v64, v64, i64, f64, f64, a1, a2, v64, f64, f64, f64, a2, a2, a2, a2, a2,
             types.Array(types.int8, 2, "C"), v64, v64, a2)
ptx, _ = cuda.compile_ptx(module._run_gpu.py_func, signature, cc=(9, 0))
with gpu.nvvm_options(fma=False):
    exact, _ = cuda.compile_ptx(module._run_gpu.py_func, signature, cc=(9, 0))
print(ptx + "\n//// fma=0\n" + exact)
"""


@pytest.mark.slow
def test_kernel_text_compiles_for_cuda(tmp_path):
    # the simulator runs the kernel text as Python and never types it for CUDA: here numba-cuda compiles it through
    # NVVM to PTX for sm_90 (where NVVM and NVRTC are installed: a CUDA toolkit, or numba-cuda[cu12]/[cu13]); all
    # the kernel's functions are inlined into the launcher (the only call left is CUDA's own slow path of
    # trigonometry).  With gpu.nvvm_options(fma=False) NVVM fuses nothing: every float64 add, subtract and multiply
    # carries the rounding mode .rn, which also forbids ptxas to fuse it; the fused multiply-adds left are those
    # that CUDA's library functions (cos, sin, division, sqrt) are written with
    import os
    import re
    import subprocess
    import sys

    try:
        from cuda.pathfinder import load_nvidia_dynamic_lib

        load_nvidia_dynamic_lib("nvvm")
        load_nvidia_dynamic_lib("nvrtc")
    except Exception as exc:  # noqa: BLE001 -- no NVVM here: nothing to compile with
        pytest.skip(f"no NVVM or NVRTC library ({type(exc).__name__})")
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "0", "COINWALL_CACHE_DIR": str(tmp_path)}
    done = subprocess.run([sys.executable, "-c", COMPILE_FOR_SM90, ELLIPSE], capture_output=True, text=True, env=env,
                          timeout=600, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    ptx, exact = done.stdout.split("//// fma=0")
    assert ".target sm_90" in ptx and ".entry" in ptx
    called = {line.split()[0].rstrip(",") for line in ptx.split("call.uni (retval0), \n")[1:]}
    assert called <= {"__internal_trig_reduction_slowpathd"}, called

    def ops(text):
        return re.findall(r"\s((?:add|sub|mul|fma)(?:\.rn)?\.f64)\s", text)

    fused, plain = ops(ptx).count("fma.rn.f64"), sum(op in ("add.f64", "sub.f64", "mul.f64") for op in ops(ptx))
    assert plain > 0  # by default NVVM leaves some unrounded, so ptxas may fuse those too
    assert not any(op in ("add.f64", "sub.f64", "mul.f64") for op in ops(exact))
    assert 0 < ops(exact).count("fma.rn.f64") < fused


def test_scan_cells_on_the_gpu(monkeypatch):
    # a scan's cell with the option device="gpu" gives the CPU's numbers (the simulator); a worker without a GPU
    # fails its task (RuntimeError: the driver retries, then stops the scan with the cells done kept) instead of
    # storing the cell as refused
    from coinwall.cases.scan import TableSpec
    from coinwall.cases.scan.quantities import check_options, compute_cell

    spec = TableSpec(ELLIPSE, (), 0.0, None)
    cpu = compute_cell("lyapunov", spec, {"eps": 0.55}, 3.0, 11, check_options("lyapunov", {"orbits": 2,
                                                                                          "collisions": 20}))
    options = check_options("lyapunov", {"orbits": 2, "collisions": 20, "device": "gpu"})
    on_gpu = compute_cell("lyapunov", spec, {"eps": 0.55}, 3.0, 11, options)
    assert cpu["status"] == on_gpu["status"] == 1
    assert np.isclose(cpu["lambda_collision"], on_gpu["lambda_collision"], rtol=0, atol=1e-12 if SIMULATOR else 0.5)
    with pytest.raises(InvalidArgument, match="`device` must be one of"):
        check_options("lyapunov", {"device": "tpu"})
    monkeypatch.setattr(gpu, "device_status", lambda: "no CUDA GPU is usable here (test)")
    with pytest.raises(RuntimeError, match="cannot run --device gpu"):
        compute_cell("lyapunov", spec, {"eps": 0.55}, 3.0, 11, options)
