"""Tosses on a GPU (device="gpu"): the field kernel's text compiled for CUDA, checked against the CPU kernel.

The default run executes the GPU code path in numba's CUDA simulator (tests/conftest.py sets
NUMBA_ENABLE_CUDASIM=1): the kernel text (flights, impacts with restitution and Coulomb friction, the contact
phases, rolling resistance) runs as Python, one thread per toss, and must give the CPU kernel's records to the
bit.  On a real GPU (NUMBA_ENABLE_CUDASIM=0, tests/benchmarks/gpu_check.sh) rounding differs (fused multiply-adds,
CUDA's cos/sin), so records are compared to rounding over the first few events, where chaos has not yet amplified
it.  Sizes are small: the simulator runs a contact phase's Runge–Kutta steps as Python.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard import gpu
from coinwall.forward.dynamics.floor import field
from coinwall.forward.dynamics.floor.fieldgpu import run_gpu
from coinwall.forward.dynamics.floor.hand import heads_fraction, toss_outcomes
from coinwall.forward.dynamics.floor.toss import basin_map, launch_states
from coinwall.forward.dynamics.floor.uncertainty import uncertainty_exponent
from coinwall.forward.errors import InvalidArgument

numba = pytest.importorskip("numba")
pytest.importorskip("numba.cuda", reason="numba-cuda is not installed (pip install 'coinwall[gpu]')")
SIMULATOR = bool(numba.config.ENABLE_CUDASIM)

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
# a pentagon as drawn: vertices to two decimals, the centre of mass at their mean; its wall is the support function
# max_k (x_k cos t + y_k sin t), with a kink at every vertex's normal cone edge (five faces to rest on)
PENTAGON = [[1.1, 0.01], [0.35, 1.06], [-0.9, 0.63], [-0.85, -0.69], [0.3, -1.01]]


def _pentagon():
    return Wall.from_expression("max(" + ", ".join(f"{x!r}*cos(t) + {y!r}*sin(t)" for x, y in PENTAGON) + ")")


def _cases():
    """(table, launches (v0, ω0), height, records, the event kinds the CPU's records must contain): each case makes
    the kernel take the paths it names, so that the comparison covers them."""
    coin = Wall.from_expression(ELLIPSE, {"eps": 99.0})
    egg = Wall.from_expression(ELLIPSE, {"eps": 0.3})
    return {
        # Newton's restitution, settling by energy
        "frictionless coin": (field.FieldTable(coin, g=1.0, e=0.6), [(2.0, 5.0), (2.3, 4.0), (1.5, 7.0)], 1.2, 300,
                              {0}),
        # Coulomb friction alone: lift-offs, rolling and slipping on the floor, and a toss that rolls for ever
        "friction": (field.FieldTable(egg, g=1.0, e=0.3, mu=0.3), [(1.0, 5.5), (2.0, -3.0)], 1.5, 30, {0, 3, 4, 5, 8}),
        # rolling resistance: rolling phases that end at rest in a valley
        "rolling resistance": (field.FieldTable(egg, g=1.0, e=0.3, mu=0.3, rolling=0.01), [(0.735, -1.305),
                                                                                           (0.714, -0.251)], 1.5, 300,
                               {0, 4, 8}),
        # a polygon: impacts on kinks (both corners of a face), rolling over corners
        "pentagon with friction": (field.FieldTable(_pentagon(), g=1.0, e=0.5, mu=0.4), [(0.5, -1.5), (1.0, 3.0),
                                                                                         (1.5, -4.0)], 2.5, 300,
                                   {0, 4, 6}),
    }


CASES = _cases()
COLUMNS = ("time", "theta", "eta", "v_theta", "v_eta", "v_xi", "side")


@pytest.mark.parametrize("name", sorted(CASES))
def test_gpu_tosses_are_the_cpus(name):
    # every record of every toss (time, θ, η, θ̇, η̇, ξ̇ and the event kind), the status and the outcome: the GPU's
    # launcher against field_run on the CPU, toss by toss; and field_run_many's summaries on both devices
    table, launches, height, n, kinds = CASES[name]
    v0, omega0 = np.array(launches).T
    states = launch_states(table, v0, omega0, height)
    flights = [field.field_run(table, s, n) for s in states]
    assert kinds <= set(np.concatenate([f.side for f in flights]).tolist()), "the case no longer takes its paths"
    on_gpu = run_gpu(table, np.column_stack([states, np.zeros(len(states))]), n, False, record=True)
    for k, flight in enumerate(flights):
        done = int(on_gpu["done"][k])
        assert field.STATUS[int(on_gpu["status"][k])] == flight.status or not SIMULATOR
        first = done if SIMULATOR else min(done, len(flight), 3)  # (chaos: see the module docstring)
        assert done == len(flight) or not SIMULATOR
        for column in COLUMNS:
            got, want = on_gpu[column][k, :first], getattr(flight, column)[:first]
            if SIMULATOR or column == "side":
                assert np.array_equal(got, want), (column, k)
            else:
                assert np.allclose(got, want, rtol=0, atol=1e-9), (column, k)
    cpu = field.field_run_many(table, states, n)
    gpu_many = field.field_run_many(table, states, n, device="gpu")
    assert cpu.keys() == gpu_many.keys()
    for key in cpu:
        if SIMULATOR:
            assert np.array_equal(cpu[key], gpu_many[key]), key
    assert np.array_equal(cpu["valley"], [f.valley for f in flights])


def test_toss_functions_take_the_device():
    # the library functions behind `coinwall toss` and `coinwall design` give the CPU's numbers on the GPU (in the
    # simulator to the bit; on a real GPU a launch within rounding of a basin boundary may land on the other face)
    table, _, height, _, _ = CASES["frictionless coin"]
    v0, omega0 = np.array([1.8, 2.0, 2.2]), np.array([4.0, 5.0, 6.0])

    def same(a, b):
        return np.array_equal(a, b) if SIMULATOR else np.mean(np.asarray(a) == np.asarray(b)) >= 0.5

    a, b = (toss_outcomes(table, v0, omega0, height, device=d) for d in ("cpu", "gpu"))
    assert same(a.outcome, b.outcome) and same(a.status, b.status)
    # times: to the bit in the simulator; on a GPU, whose compiler fuses multiply-adds, within rounding carried
    # through a few bounces (exact equality of float times failed there)
    assert same(a.time, b.time) if SIMULATOR else np.mean(np.isclose(a.time, b.time, rtol=1e-9, atol=0)) >= 0.5
    a, b = (basin_map(table, v0, omega0, height, device=d) for d in ("cpu", "gpu"))
    assert same(a.outcome, b.outcome) and same(a.bounces, b.bounces)
    a, b = (heads_fraction(table, (2.0, 5.0), (0.1, 0.3), height, samples=6, seed=2, device=d) for d in ("cpu", "gpu"))
    assert a.fractions == b.fractions or not SIMULATOR
    # caught tosses (one flight each) keep the simulator quick: 3 × 8 launches per ε
    a, b = (uncertainty_exponent(table, (1.5, 2.5), (3.0, 7.0), height, epsilons=(0.05, 0.1), samples=8, catch=True,
                                 device=d) for d in ("cpu", "gpu"))
    assert same(a.counts, b.counts)
    from coinwall.inverse.design.bounce import toss

    states = launch_states(table, v0, omega0, height)
    (ia, _, sa), (ib, _, sb) = (toss(table.wall, states, e=0.6, g=1.0, device=d) for d in ("cpu", "gpu"))
    assert same(ia, ib) and same(sa, sb)
    with pytest.raises(InvalidArgument, match="`device` must be one of"):
        toss_outcomes(table, v0, omega0, height, device="cuda")


def test_toss_scan_cells_on_the_gpu():
    # a scan's toss cell with device="gpu" gives the CPU's numbers (the simulator)
    from coinwall.cases.scan import TableSpec
    from coinwall.cases.scan.quantities import check_options, compute_cell

    spec = TableSpec(ELLIPSE, (), 0.0, None)
    cells = [compute_cell("toss", spec, {"eps": 99.0, "restitution": 0.6}, 1.2, 5,
                          check_options("toss", {"tosses": 6, "device": device})) for device in ("cpu", "gpu")]
    assert cells[0]["status"] == cells[1]["status"] == 1
    assert cells[0] == cells[1] or not SIMULATOR


def test_toss_command_on_the_gpu(capsys):
    # `coinwall toss --device gpu` runs (in the simulator) and prints the CPU's summary
    from coinwall.cases.cli.main import main

    argv = ["toss", "case:coin", "--g", "1", "--e", "0.6", "--mu", "0.3", "--height", "1.2", "--v0", "1.8:2.2:2",
            "--omega", "4:6:2", "--json"]
    docs = []
    for device in ("cpu", "gpu"):
        assert main(argv + ["--device", device]) == 0
        docs.append(json.loads(capsys.readouterr().out))
    assert docs[0] == docs[1] or not SIMULATOR
    assert sum(docs[1]["fractions"].values()) == pytest.approx(1.0)


def test_device_refused_in_one_line(monkeypatch, capsys):
    # "gpu" where numba-cuda is missing: one line naming --device and exit status 2 from the command line, before
    # any work, for the toss's three modes and the bounce design; --device where it does nothing is refused too
    from coinwall.cases.cli.main import main

    def missing():
        raise ImportError("No module named 'numba.cuda'")

    monkeypatch.setattr(gpu, "cuda_module", missing)
    toss = ["toss", "case:coin", "--height", "1.2", "--v0", "1:3:2", "--omega", "3:5:2", "--device", "gpu"]
    rect = "abs(cos(t)) + h*abs(sin(t))"
    for argv in (toss, toss + ["--spread", "2,5,0.05,0.2", "--samples", "10"],
                 toss + ["--uncertainty", "1e-3:1e-2:2", "--samples", "10"],
                 ["design", rect, "--param", "h=0.2:2", "--target", "edge=1/3", "--model", "bounce", "--device",
                  "gpu"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--device" in err[0] and "numba-cuda is not installed" in err[0], err
    assert main(["design", rect, "--param", "h=0.2:2", "--target", "edge=1/3", "--model", "drop", "--device",
                 "gpu"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--device does nothing in the drop toss" in err[0], err
    for argv in (toss + ["--workers", "2"], ["design", rect, "--param", "h=0.2:2", "--target", "edge=1/3", "--model",
                                             "bounce", "--device", "gpu", "--workers", "2"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--workers sets the CPU's threads" in err[0], err
    with pytest.raises(InvalidArgument, match="numba-cuda is not installed"):
        field.field_run_many(CASES["friction"][0], [[0.3, 2.0, 1.0, 0.5]], 10, device="gpu")


COMPILE_FOR_SM90 = r"""
import sys
import numba.cuda.dispatcher as dispatcher
from numba import cuda, types

class Hopper:  # no GPU here: compile for an H100/H200 (sm_90) as if one were present
    compute_capability = (9, 0)

dispatcher.get_current_device = lambda: Hopper()
from coinwall.forward import Wall
from coinwall.forward.dynamics.floor import fieldgpu

module = fieldgpu._module(Wall.from_expression(sys.argv[1]))
f64, i64, b1 = types.float64, types.int64, types.boolean
a1, a2, v64 = types.Array(f64, 1, "C"), types.Array(f64, 2, "C"), types.Array(i64, 1, "C")
signature = (a2, i64, f64, f64, f64, f64, f64, f64, b1, b1, f64, a1, a2, v64, f64, f64, f64, a2, f64, a1,
             types.Array(types.int8, 1, "C"), v64, v64, a2)
ptx, _ = cuda.compile_ptx(module._field_gpu.py_func, signature, cc=(9, 0))
print(ptx)
"""


@pytest.mark.slow
def test_field_kernel_text_compiles_for_cuda(tmp_path):
    # the simulator runs the kernel text as Python and never types it for CUDA: here numba-cuda compiles the whole
    # field kernel (flights, Stronge/Routh impacts, the contact phases with their Runge–Kutta steps, rolling
    # resistance) through NVVM to PTX for sm_90, for the pentagon's wall (where NVVM and NVRTC are installed).  The
    # only calls left are CUDA's own slow paths of trigonometry and pow (the contact phases' step control)
    import os
    import subprocess
    import sys

    try:
        from cuda.pathfinder import load_nvidia_dynamic_lib

        load_nvidia_dynamic_lib("nvvm")
        load_nvidia_dynamic_lib("nvrtc")
    except Exception as exc:  # noqa: BLE001 -- no NVVM here: nothing to compile with
        pytest.skip(f"no NVVM or NVRTC library ({type(exc).__name__})")
    env = {**os.environ, "NUMBA_ENABLE_CUDASIM": "0", "COINWALL_CACHE_DIR": str(tmp_path)}
    wall = "max(" + ", ".join(f"{x!r}*cos(t) + {y!r}*sin(t)" for x, y in PENTAGON) + ")"
    done = subprocess.run([sys.executable, "-c", COMPILE_FOR_SM90, wall], capture_output=True, text=True, env=env,
                          timeout=900, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    ptx = done.stdout
    assert ".target sm_90" in ptx and ".entry" in ptx
    called = {line.split()[0].rstrip(",") for line in ptx.split("call.uni (retval0), \n")[1:]}
    assert called <= {"__internal_trig_reduction_slowpathd", "__internal_accurate_pow"}, called
