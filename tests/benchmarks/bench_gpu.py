"""Benchmark of the billiard kernel on a CUDA GPU against all the machine's CPU cores, in one run, with its invariants.

Run:  python tests/benchmarks/bench_gpu.py [--orbits M] [--collisions N] [--launches L] [--cpu-orbits K]
                                           [--threads T] [--variants LIST] [--tosses T] [--cpu-tosses K]
                                           [--toss-impacts N] [--json FILE] [--smoke]

The toss (the field kernel on the GPU: tosses/s and events/s against all CPU cores, with its own invariants) is
measured after the billiard; tests/benchmarks/_gpu_toss.py says how, and prints its block (``toss coin: ...``,
``toss egg friction: ...``) before the summary line.  ``--tosses 0`` leaves it out.

Two tables: the coin (the ellipse wall with ε = 99, H = 3) and the paper's mixed ellipse (ε = 0.55, H = 1.9; it
has islands, so its orbits are not all chaotic).  The GPU helpers (the variants' kernels, the layouts of the
collision arrays, one collision from given states) are in tests/benchmarks/_gpu_runs.py.

What each figure means (the same work on both sides: every orbit makes L launches of N collisions, each launch
continuing every orbit from where the last one stopped, so the start-up of the first flight is not what is timed;
compile time and a first warm round are excluded on both sides):

* ``gpu kernel``: M Liouville-random orbits (:func:`random_states`), one per GPU thread (the CPU kernel's text
  compiled for CUDA, ``coinwall.forward.dynamics.billiard.gpu``), timed from the launch to the end of the kernel
  (``cuda.synchronize``); every collision is written to the GPU's memory and stays there.  This is the rate of
  the commands that reduce on the GPU (``simulate --orbits``: :func:`.orbitstats.ensemble_statistics`).
* ``gpu copy``: the same launch's collisions (41 bytes each) copied to the host, into new numpy arrays (what
  ``ensemble(..., device="gpu")`` and the analyses that read every collision do: the host's first touch of each
  page is part of it) and into page-locked buffers allocated beforehand (the transfer itself); ``with copies``
  is the kernel and the first of these together.  This bounds the commands that bring every collision back.
* ``cpu kernel``: K of the same kind of orbits, the same L × N collisions each, on all CPU cores (numba threads,
  the ``_run_many`` that ``ensemble`` calls, into arrays allocated once), best of three after a warm round; and
  the same on one thread.  ``ns/collision/core`` is the time × cores / collisions: it equals the one-thread
  figure when the cores scale perfectly, so the reader can see the baseline is sane.  ``gpu/cpu`` is the ratio
  of the two kernel rates.
* ``cpu ensemble()``: the K orbits × N collisions through :func:`ensemble`, the per-orbit Trajectory objects
  included (what a user's script gets); ``gpu ensemble()``: the same on the GPU.
* ``simulate --orbits``: :func:`.orbitstats.ensemble_statistics` end to end, GPU (M orbits × L·N collisions:
  the collisions stay on the GPU, ~80 bytes per orbit come back) and CPU (K orbits).

Invariants, over every collision of the first launch of the first 32,768 orbits:

* speed: ``max | |v| − 1 |`` (the kernel keeps the speed 1 to rounding);
* contact: every collision lies on the wall it hit, ``|η − wall(θ)| ≤ tol`` (the table's contact tolerance,
  ``1e-13·max(1, H, max b)``) plus the rounding of the unwrapped θ (4 ulp(θ)·(1 + |b'|)), the wall evaluated
  independently (numpy on casadi's expression, not the GPU's code);
* no flight through a wall: the midpoint of every flight lies strictly inside the strip;
* the one-step check (:mod:`coinwall.forward.dynamics.billiard.onestep`, whose docstring derives the bound), over
  the first 8,192 of those orbits (2.09 × 10⁶ collisions), in two forms: ``same state`` — from each state the GPU reported, the GPU's next
  collision (a launch of one collision) against the CPU's, both from identical floats, so every difference is the
  arithmetic's; ``orbit`` — the orbit's own next collision against the CPU's from the reported state, whose
  unwrapped θ is rounded (2 ulp(|θ|): 4e-12 at |θ| = 6000); this form also sees a skipped collision.  Each
  collision is held to the bound of what the kernel guarantees (its contact within ``tol`` of the wall, so two
  contacts on one flight at most ``4 tol/|g'|`` apart in time, ``|g'| = |v·n|·√(1 + b'²)``): ``ok`` when every
  next collision is on the same wall and within its bound.  Printed too: the largest relative difference, how
  many exceed 1e-12, and the worst collisions (incidence ``|v·n|``, b'', both contacts' residuals); and the orbit
  form on the CPU's own orbits, the control;
* mean free time against Santaló's ``π·A/P`` (derivation below), within 2σ.

Santaló's mean free time on the billiard strip.  The table is the flat cylinder θ ∈ [0, 2π) (periodic), η between
``b0 + b(θ)`` and ``H − b0 − b(θ + π)``: area ``A = ∫ (H − 2 b0 − b(θ) − b(θ + π))⁺ dθ`` and wall length
``P = ∫ (√(1 + b'(θ)²) + √(1 + b'(θ + π)²)) dθ`` over the angles where the strip is open.  The particle moves at
unit speed; the Liouville measure ``dθ dη dφ`` (φ the direction) is invariant, of total mass ``2π A``.  Under it
the particles meet a piece ``ds`` of wall at the rate ``ds ∫ cos ψ dψ / (2π A) = 2 ds / (2π A)`` (ψ from the inward
normal, over the half circle of incoming directions), so collisions come at the rate ``P/(π A)`` per particle and
the mean free time is ``τ = π A / P``.  The rate holds at every instant for orbits started in the Liouville measure
(the motion is stationary), so in a *fixed* window ``[0, T]`` an orbit makes ``N(T)`` collisions with
``E[N(T)] = T P/(π A)`` exactly, on any table, chaotic or not.  The benchmark takes ``T`` = the earliest time at
which an orbit of the first launch made its N-th collision, the rate ``r_k = N_k(T)/T`` of each orbit, and
``τ̂ = 1/mean(r)`` with ``σ = std(r)/(√M mean(r)²)`` (orbits are independent; a chaotic orbit's collisions are
not, which is why the error comes from the spread between orbits).  ``A`` and ``P`` come from
``Billiard.area_perimeter`` (trapezoid on 20,000 angles: exponentially accurate for these analytic walls).  A 2σ
band is missed by chance 4.6 % of the time; the seed is fixed, so a run is reproducible.

Targets (the GPU's): ≥ 10⁹ collisions/s on the coin on an H100/H200-class GPU, and ≥ 20× all the CPU cores of
the same machine.

Variants, on the coin, each measured exactly as the headline (M orbits, L launches of N; a variant that cannot
compile or run says so and the others go on): ``nofma`` — the launcher compiled with NVVM's ``-fma=0`` (no
contraction of ``a·b + c``: the CPU kernel's arithmetic operation for operation, CUDA's ``cos``/``sin`` apart),
with its one-step check (same state); ``orbits4`` — 4·M orbits per launch (a smaller share of the last, partly
idle wave of blocks); ``coalesced`` — the collision arrays laid out collision-major, so that the 32 threads of a
warp store each collision to one contiguous stretch (a new compile: the arrays are strided); ``nowrite`` — the
same compiled kernel writing every collision of an orbit to one place (stride 0: the stores stay in the cache;
what a kernel that keeps nothing per collision would gain at most); ``regs144`` — at most 144 registers a thread
(ptxas, sm_90: 28 bytes of spills against none at the kernel's 154) in blocks of 64 threads, so that 14 warps fit
on a multiprocessor instead of 12; ``threads64``/``threads256`` — other block sizes.

Output: a line on the CPU, then one block per table (numbers here are placeholders)::

    cpu: 16 numba threads (threading layer omp), 16 logical CPUs
    table coin: ellipse eps=99, H=3 (tol 3e-13), santalo 2.27336
      gpu  NVIDIA H200 (compute capability 9.0), 128 threads/block, 154 registers/thread, compile 12.8 s, fma on
      gpu kernel  262144 orbits x 4 launches x 256 = 2.68e+08 collisions in 0.576 s: 4.66e+08 /s
      gpu copy    2.75e+09 bytes: new arrays 1.6 s (1.7 GB/s), pinned 0.11 s (25 GB/s); with copies 1.4e+08 /s
      cpu kernel  16 threads, 32768 orbits x 4 x 256 = 3.36e+07 collisions in 0.53 s: 6.3e+07 /s (254 ns/collision/core)
      cpu kernel  1 thread, 256 orbits x 4 x 256: 231 ns/collision (16 threads scale 0.91 of perfect)
      gpu/cpu 7.4
      cpu ensemble() 32768 orbits x 256: 1.1e+07 /s; gpu ensemble(): 9.5e+06 /s (Trajectory objects included)
      simulate --orbits: gpu 4.1e+08 /s (262144 orbits x 1024), cpu 5.9e+07 /s (32768 orbits); mean free time vs
        santalo z = 0.31, -0.72 ok
      speed max||v|-1| 2.2e-16 ok
      contact max residual 8e-13 = 2.7 tol ok
      through-wall flights 0 of 8.36e+06 ok; orbits stopped early 0
      one-step same state: max 1.3e-13, 0 above 1e-12, max/bound 2e-05, grazes 0, other wall 0 over 2.09e+06 ok
      one-step orbit: max 9.1e-12, 12 above 1e-12, max/bound 0.003, grazes 0, other wall 0 over 2.09e+06 ok
      one-step orbit, the CPU's own orbits (control): max 2.2e-12, 8 above 1e-12, max/bound 0.16, ... ok
        worst same state: diff 1.3e-13 (v_eta) bound 2e-09; wall 1 phi 1.6526 b' 0.63 b'' 4.5 |v.n| 0.013 ...
      free time 2.27291 +- 0.00051 vs santalo 2.27336: z = -0.88 ok
      targets: >= 1e9/s MISS, >= 20x cpu MISS

(the ``worst`` lines: the three largest differences of each form, the component, its bound, the wall, the contact
angle φ, b' and b'' there, the incidence |v·n|, the flight time, |θ| of the start, and the residual
``η − wall(θ)`` of the CPU's contact and of the other one).  The control applies the orbit form to the CPU's own
first launch (2^13 of its orbits): what the rounding of the reported θ alone gives.

then one line per variant (``variant coin nofma: 4.3e+08 /s (0.92 of the headline in this run); 154
registers/thread, compiled in 12.5 s; one-step same state ...``), one line ``summary: ...`` with the
invariants' verdict, and ``--json FILE`` writes the same numbers as JSON (after each table and variant, so a run
cut short keeps what it measured).  The exit status is 1 when an invariant fails (the targets are reported, not
enforced), 2 when there is no GPU (outside ``--smoke``, which runs in numba's CUDA simulator at a few orbits and
collisions).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
import warnings

import numpy as np

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
TABLES = (("coin", 99.0, 3.0), ("ellipse", 0.55, 1.9))
ONE_STEP_LIMIT = 1e-12     # the difference reported as "above" (the bound of each collision is what passes or fails)
CHECKED_ORBITS = 2 ** 15   # the invariants read the first launch of this many orbits (all of it: every collision)
ONE_STEP_ORBITS = 2 ** 13  # the one-step checks: every collision of the first launch of this many orbits
VARIANTS = ("nofma", "orbits4", "coalesced", "nowrite", "regs144")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # (python -P does not put this folder on the path)

from _gpu_runs import carry_kernel, collision_rows, gpu_step, registers_per_thread, variant_kernel


def run_gpu(table, states, n, launches, threads, kernel=None, layout="C", keep=CHECKED_ORBITS, copies=False, fma=None):
    """M orbits × L launches of n collisions on the GPU (coinwall's kernel, or ``kernel``; a kernel compiles at its
    first launch, with NVVM's ``-fma`` set to ``fma``, by default coinwall's :data:`~gpu.FMA`).  Returns a dict:
    seconds (kernel time), collisions, the first launch's rows/done/status of the first ``keep`` orbits (host),
    registers, and with ``copies`` the seconds to copy one launch's collisions into new arrays and into
    page-locked ones, and its bytes."""
    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.kernel import compiled
    from coinwall.forward.dynamics.billiard.table import _check_states

    cuda = gpu.cuda_module()
    kernel = kernel or gpu._billiard_module(table.wall)._run_gpu
    carry = carry_kernel()
    unit, _speed, leaving, turns = _check_states(table, states, "states")
    m = unit.shape[0]
    H, b0, c, cells, lookup, wmin, wmax, tol = compiled(table).args(table)
    consts = [cuda.to_device(np.ascontiguousarray(a)) for a in (c, cells, lookup)]
    d_states, d_turns, d_leaving = (cuda.to_device(np.ascontiguousarray(a)) for a in (unit, turns, leaving))
    outs = collision_rows(cuda, m, n, layout)
    d_done, d_status = cuda.device_array(m, dtype=np.int64), cuda.device_array(m, dtype=np.int64)
    d_last = cuda.device_array((m, 2))
    blocks = (m + threads - 1) // threads
    head, tail = (float(H), float(b0)), (float(wmin), float(wmax), float(tol))
    result = {"seconds": 0.0, "collisions": 0}
    for launch in range(launches):
        cuda.synchronize()
        start = time.perf_counter()
        with gpu.nvvm_options(fma=gpu.FMA if fma is None else fma):
            kernel[blocks, threads](d_states, d_turns, d_leaving, n, *head, *consts, *tail, *outs, d_done, d_status,
                                    d_last)
        carry[blocks, threads](d_states, d_turns, d_leaving, outs[2], outs[3], outs[4], outs[5], d_done, d_last)
        cuda.synchronize()
        result["seconds"] += time.perf_counter() - start
        done = d_done.copy_to_host()
        result["collisions"] += int(done.sum())
        if launch == 0 and keep:
            result["first"] = ([np.asarray(o[:keep].copy_to_host() if hasattr(o, "copy_to_host") else o[:keep])
                                for o in outs], done[:keep], d_status.copy_to_host()[:keep])
        if launch == 0 and copies:
            result["bytes"] = sum(o.size * o.dtype.itemsize for o in outs)
            start = time.perf_counter()
            fresh = [o.copy_to_host() for o in outs]
            result["copy_new"] = time.perf_counter() - start
            del fresh
            try:  # (a report only: a machine that cannot lock 2.8 GB of host memory says so)
                pinned = [cuda.pinned_array(o.shape, dtype=o.dtype) for o in outs]
                for o, p in zip(outs, pinned):  # (a first copy: the driver maps the buffers)
                    o.copy_to_host(p)
                start = time.perf_counter()
                for o, p in zip(outs, pinned):
                    o.copy_to_host(p)
                result["copy_pinned"] = time.perf_counter() - start
                del pinned
            except Exception as exc:  # noqa: BLE001
                result["copy_pinned"] = math.nan
                print(f"  (page-locked copy failed: {type(exc).__name__}: {str(exc).splitlines()[0][:120]})")
    result["registers"] = registers_per_thread(kernel, layout)
    return result


def _cores() -> int:
    import numba

    return int(numba.config.NUMBA_NUM_THREADS)


def run_cpu(table, states, n, launches, workers=None, repeats=3, keep=0):
    """The same protocol on the CPU: ``_run_many`` (what ensemble calls) on ``workers`` numba threads into arrays
    allocated once, L launches each continuing the last; a warm round, then the best of ``repeats``.  Returns
    (seconds, collisions, the first launch's rows and done of the first ``keep`` orbits)."""
    from coinwall.forward.dynamics.billiard.kernel import _run_threads, compiled
    from coinwall.forward.dynamics.billiard.table import _check_states

    comp = compiled(table)
    unit0, _speed, leaving0, turns0 = _check_states(table, states, "states")
    m = unit0.shape[0]
    out = [np.empty((m, n)) for _ in range(5)] + [np.empty((m, n), dtype=np.int8)]
    done, status, last = np.zeros(m, dtype=np.int64), np.zeros(m, dtype=np.int64), np.empty((m, 2))
    rows = np.arange(m)
    best, total = math.inf, 0
    for round_ in range(repeats + 1):
        unit, leaving, turns = unit0.copy(), leaving0.copy(), turns0.copy()
        seconds, total = 0.0, 0
        for launch in range(launches):
            start = time.perf_counter()
            _run_threads(comp, table, unit, turns, leaving, n, workers, out, done, status, last)
            seconds += time.perf_counter() - start
            total += int(done.sum())
            if round_ == 0 and launch == 0 and keep:
                first = ([o[:keep].copy() for o in out], done[:keep].copy())
            moved = done > 0
            at = np.maximum(done - 1, 0)
            unit[moved] = np.column_stack([last[:, 0], out[2][rows, at], out[3][rows, at], out[4][rows, at]])[moved]
            turns[moved] = last[moved, 1].astype(np.int64)
            leaving[moved] = out[5][rows, at][moved]
        if round_:
            best = min(best, seconds)
    return (best, total, first) if keep else (best, total)


def invariants(table, rows, done, status):
    """Speed, contact, flights and Santaló on the first launch (rows: time, θ, η, v_θ, v_η, side)."""
    n = rows[0].shape[1]
    full = done == n
    out = {"orbits_stopped": int(np.count_nonzero(~full))}
    t, th, et, a, b, sd = (x[full] for x in rows)
    out["speed"] = float(np.max(np.abs(np.hypot(a, b) - 1.0)))
    bottom = sd == 0
    flat_th = th.ravel()
    wall_th = flat_th + np.where(bottom.ravel(), 0.0, math.pi)
    value, slope, _ = table.wall.derivatives(wall_th)
    residual = np.where(bottom.ravel(), et.ravel() - (table.b0 + value), (table.H - table.b0 - value) - et.ravel())
    allowed = table.tol + 4 * np.spacing(np.abs(flat_th)) * (1 + np.abs(slope))
    out["contact"] = float(np.max(np.abs(residual)))
    out["contact_ok"] = bool(np.all(np.abs(residual) <= allowed))
    out["tol"] = float(table.tol)
    dt = np.diff(t, axis=1)
    mid_th = (th[:, :-1] + 0.5 * a[:, :-1] * dt).ravel()
    mid_eta = (et[:, :-1] + 0.5 * b[:, :-1] * dt).ravel()
    through = (mid_eta <= table.lower(mid_th)) | (mid_eta >= table.upper(mid_th))
    out["through"] = int(np.count_nonzero(through))
    out["flights"] = int(mid_th.size)
    window = float(np.min(t[:, -1]))
    rate = np.count_nonzero(t <= window, axis=1) / window
    tau = 1.0 / rate.mean()
    sigma = float(rate.std(ddof=1) / math.sqrt(rate.size) / rate.mean() ** 2)
    area, perimeter = table.area_perimeter()
    santalo = math.pi * area / perimeter
    out.update(free_time=float(tau), free_time_sigma=sigma, santalo=santalo, z=float((tau - santalo) / sigma))
    out["ok"] = bool(out["orbits_stopped"] == 0 and out["speed"] < 1e-14 and out["contact_ok"] and out["through"] == 0
                     and abs(out["z"]) <= 2.0)
    return out


def trajectories(table, rows, done, count):
    """The first ``count`` orbits of a launch's rows as Trajectory objects (full orbits only)."""
    from coinwall.forward.dynamics.billiard.table import Trajectory

    n = rows[0].shape[1]
    return [Trajectory(time=rows[0][k], theta=rows[1][k], eta=rows[2][k], v_theta=rows[3][k], v_eta=rows[4][k],
                       side=rows[5][k], start=np.zeros(4), table=table) for k in range(min(count, len(done)))
            if done[k] == n]


def one_step(table, trajs, device):
    """The one-step check as a dict of what is printed and stored."""
    from coinwall.forward.dynamics.billiard.onestep import one_step_check

    check = one_step_check(table, trajs, device=device, worst=3)
    return {"max": check.max_difference, "above": int(np.count_nonzero(check.differences > ONE_STEP_LIMIT)),
            "ratio": check.max_ratio, "grazes": check.grazes, "other_wall": check.other_wall,
            "collisions": check.collisions, "ok": check.ok, "worst": check.worst}


def _one_step_line(label, s) -> str:
    return (f"one-step {label}: max {s['max']:.2g}, {s['above']} above {ONE_STEP_LIMIT:g}, max/bound {s['ratio']:.2g}, "
            f"grazes {s['grazes']}, other wall {s['other_wall']} over {s['collisions']:.3g} {ok(s['ok'])}")


def _worst_lines(label, s):
    for w in s["worst"][:3]:
        name = max(w["differences"], key=w["differences"].get)
        yield (f"    worst {label}: diff {w['differences'][name]:.2g} ({name}) bound {w['bounds'][name]:.2g}; "
               f"wall {w['side']} phi {w['phi']:.4f} b' {w['slope']:.3g} b'' {w['curvature']:.3g} |v.n| "
               f"{w['incidence']:.2g} flight {w['flight']:.3g} |theta| {w['start_theta']:.3g}; residual cpu "
               f"{w['residual_cpu']:.2g} other {w['residual_other']:.2g}")


def ok(flag) -> str:
    return "ok" if flag else "FAILED"


def _user_paths(table, states, cpu_states, n, launches):
    """ensemble() and ensemble_statistics() end to end, collisions/s (the commands' own rates)."""
    from coinwall.forward.dynamics.analysis.orbitstats import ensemble_statistics
    from coinwall.forward.dynamics.billiard.table import ensemble

    out = {}
    for device, sample in (("cpu", cpu_states), ("gpu", cpu_states)):
        ensemble(table, sample[:2], 2, device=device)
        start = time.perf_counter()
        got = ensemble(table, sample, n, device=device)
        out[f"ensemble_{device}"] = sum(len(t) for t in got) / (time.perf_counter() - start)
        del got
    area, perimeter = table.area_perimeter()
    santalo = math.pi * area / perimeter
    for device, sample in (("gpu", states), ("cpu", cpu_states)):
        start = time.perf_counter()
        stats = ensemble_statistics(table, sample, n * launches, device=device)
        out[f"statistics_{device}"] = stats.collisions / (time.perf_counter() - start)
        out[f"statistics_{device}_z"] = (stats.mean_free_time - santalo) / stats.mean_free_time_stderr
    out["statistics_ok"] = bool(abs(out["statistics_gpu_z"]) <= 3 and abs(out["statistics_cpu_z"]) <= 3)
    return out


def measure_table(name, eps, H, args, threads, device, report):
    from coinwall.forward import Wall
    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.table import Billiard, random_states

    table = Billiard(Wall.from_expression(ELLIPSE, {"eps": eps}), H)
    states = random_states(table, args.orbits, seed=1)
    start = time.perf_counter()
    run_gpu(table, states[:threads], 2, 1, threads, keep=0)  # compile (and load) outside the timing
    compile_seconds = time.perf_counter() - start
    g = run_gpu(table, states, args.collisions, args.launches, threads, copies=(name == "coin"))
    rate = g["collisions"] / g["seconds"]
    rows, done, status = g.pop("first")
    cpu_states = random_states(table, args.cpu_orbits, seed=2)
    cores = _cores()
    cpu_seconds, cpu_total, (cpu_rows, cpu_done) = run_cpu(table, cpu_states, args.collisions, args.launches,
                                                             keep=ONE_STEP_ORBITS)
    one = min(args.cpu_orbits, 256)
    one_seconds, one_total = run_cpu(table, cpu_states[:one], args.collisions, args.launches, workers=1, repeats=2)
    cpu_rate = cpu_total / cpu_seconds
    per_core = cpu_seconds * cores / cpu_total * 1e9
    single = one_seconds / one_total * 1e9
    checks = invariants(table, rows, done, status)
    trajs = trajectories(table, rows, done, ONE_STEP_ORBITS)
    del rows
    same = one_step(table, trajs, "gpu")
    orbit = one_step(table, trajs, None)
    control = one_step(table, trajectories(table, cpu_rows, cpu_done, ONE_STEP_ORBITS), None)
    del cpu_rows
    paths = _user_paths(table, states, cpu_states, args.collisions, args.launches)
    print(f"table {name}: ellipse eps={eps:g}, H={H:g} (tol {table.tol:.3g}), santalo {checks['santalo']:.6g}")
    print(f"  gpu  {device}, {threads} threads/block, {g['registers'] or '?'} registers/thread, compile "
          f"{compile_seconds:.1f} s, fma {'on' if gpu.FMA else 'off'}")
    print(f"  gpu kernel  {args.orbits} orbits x {args.launches} launches x {args.collisions} = {g['collisions']:.3g} "
          f"collisions in {g['seconds']:.3g} s: {rate:.3g} /s")
    if "copy_new" in g:
        per_launch = g["collisions"] / args.launches
        with_copies = per_launch / (g["seconds"] / args.launches + g["copy_new"])
        print(f"  gpu copy    {g['bytes']:.3g} bytes: new arrays {g['copy_new']:.2g} s ({g['bytes'] / g['copy_new'] / 1e9:.2g} "
              f"GB/s), pinned {g['copy_pinned']:.2g} s ({g['bytes'] / g['copy_pinned'] / 1e9:.2g} GB/s); with copies "
              f"{with_copies:.3g} /s")
        g["rate_with_copies"] = with_copies
    print(f"  cpu kernel  {cores} threads, {args.cpu_orbits} orbits x {args.launches} x {args.collisions} = "
          f"{cpu_total:.3g} collisions in {cpu_seconds:.3g} s: {cpu_rate:.3g} /s ({per_core:.0f} ns/collision/core)")
    print(f"  cpu kernel  1 thread, {one} orbits x {args.launches} x {args.collisions}: {single:.0f} ns/collision "
          f"({cores} threads scale {single / per_core:.2f} of perfect)")
    print(f"  gpu/cpu {rate / cpu_rate:.3g}")
    print(f"  cpu ensemble() {args.cpu_orbits} orbits x {args.collisions}: {paths['ensemble_cpu']:.3g} /s; gpu "
          f"ensemble(): {paths['ensemble_gpu']:.3g} /s (Trajectory objects included)")
    print(f"  simulate --orbits: gpu {paths['statistics_gpu']:.3g} /s ({args.orbits} orbits x "
          f"{args.launches * args.collisions}), cpu {paths['statistics_cpu']:.3g} /s ({args.cpu_orbits} orbits); "
          f"mean free time vs santalo z = {paths['statistics_gpu_z']:.2f}, {paths['statistics_cpu_z']:.2f} "
          f"{ok(paths['statistics_ok'])}")
    print(f"  speed max||v|-1| {checks['speed']:.2g} {ok(checks['speed'] < 1e-14)}")
    print(f"  contact max residual {checks['contact']:.2g} = {checks['contact'] / checks['tol']:.2g} tol "
          f"{ok(checks['contact_ok'])}")
    print(f"  through-wall flights {checks['through']} of {checks['flights']:.3g} {ok(checks['through'] == 0)}; "
          f"orbits stopped early {checks['orbits_stopped']}")
    print("  " + _one_step_line("same state", same))
    print("  " + _one_step_line("orbit", orbit))
    print("  " + _one_step_line("orbit, the CPU's own orbits (control)", control))
    for line in list(_worst_lines("same state", same)) + list(_worst_lines("orbit", orbit)):
        print(line)
    print(f"  free time {checks['free_time']:.6g} +- {checks['free_time_sigma']:.2g} vs santalo "
          f"{checks['santalo']:.6g}: z = {checks['z']:.2f} {ok(abs(checks['z']) <= 2)}")
    targets = {"rate_1e9": rate >= 1e9, "vs_cpu_20x": rate >= 20 * cpu_rate}
    if name == "coin":
        print(f"  targets: >= 1e9/s {'PASS' if targets['rate_1e9'] else 'MISS'}, >= 20x cpu "
              f"{'PASS' if targets['vs_cpu_20x'] else 'MISS'}")
    sys.stdout.flush()
    verdict = checks["ok"] and same["ok"] and orbit["ok"] and control["ok"] and paths["statistics_ok"]
    report["tables"][name] = dict(checks, eps=eps, H=H, gpu=g, gpu_rate=rate, cpu_rate=cpu_rate,
                                  cpu_collisions=cpu_total, cpu_ns_per_collision_core=per_core,
                                  cpu_ns_per_collision_one_thread=single, ratio=rate / cpu_rate, threads=threads,
                                  compile_seconds=compile_seconds, one_step_same_state=same, one_step_orbit=orbit,
                                  one_step_orbit_cpu_control=control,
                                  user_paths=paths, targets=targets, ok=verdict)
    return table, states, rate, trajs, verdict


def run_variants(table, states, trajs, args, threads, headline, names, out, save):
    """The variants of the module docstring, each as the headline, into ``out`` ({name: dict}; ``save()`` after
    each)."""

    for name in names:
        start = time.perf_counter()
        try:  # a variant is a report, not a check: one that cannot compile or run says so and the others go on
            kernel, layout, t, sample, extra = None, "C", threads, states, ""
            if name == "nofma":
                kernel = variant_kernel(table.wall, fma=False)
                run_gpu(table, states[:t], 2, 1, t, kernel=kernel, keep=0, fma=False)  # compile
            elif name == "orbits4":
                from coinwall.forward.dynamics.billiard.table import random_states

                sample = random_states(table, 4 * args.orbits, seed=1)
            elif name in ("coalesced", "nowrite"):
                layout = name
                run_gpu(table, states[:t], 2, 1, t, layout=layout, keep=0)  # compile (once for both)
            elif name == "regs144":
                kernel, t = variant_kernel(table.wall, registers=144), 64
                run_gpu(table, states[:t], 2, 1, t, kernel=kernel, keep=0)  # compile
            elif name.startswith("threads"):
                t = int(name[len("threads"):])
            else:
                raise ValueError(f"unknown variant {name!r}")
            compiled_in = time.perf_counter() - start
            got = run_gpu(table, sample, args.collisions, args.launches, t, kernel=kernel, layout=layout, keep=0,
                          fma=False if name == "nofma" else None)
            rate = got["collisions"] / got["seconds"]
            entry = {"rate": rate, "relative": rate / headline, "registers": got["registers"],
                     "compile_seconds": compiled_in}
            if name == "nofma":
                entry["one_step_same_state"] = one_step(table, trajs, gpu_step(table, kernel, fma=False))
                extra = "; " + _one_step_line("same state", entry["one_step_same_state"])
        except Exception as exc:  # noqa: BLE001
            print(f"variant coin {name}: failed ({type(exc).__name__}: {str(exc).splitlines()[0][:200]})")
            continue
        out[name] = entry
        save()
        print(f"variant coin {name}: {rate:.3g} /s ({entry['relative']:.2f} of the headline in this run); "
              f"{got['registers'] or '?'} registers/thread, compiled in {compiled_in:.1f} s{extra}")
        if name == "nofma":
            for line in _worst_lines("same state", entry["one_step_same_state"]):
                print(line)
        sys.stdout.flush()


def _first_parallel_run():
    from coinwall.forward import Wall
    from coinwall.forward.dynamics.billiard.table import Billiard, ensemble, random_states

    table = Billiard(Wall.from_expression(ELLIPSE, {"eps": 99.0}), 3.0)
    ensemble(table, random_states(table, 2, seed=0), 2)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--orbits", type=int, default=2 ** 18, help="GPU orbits (default 2^18)")
    parser.add_argument("--collisions", type=int, default=256, help="collisions per orbit and launch (default 256)")
    parser.add_argument("--launches", type=int, default=4, help="launches, each continuing the last (default 4)")
    parser.add_argument("--cpu-orbits", type=int, default=2 ** 15, help="CPU orbits (default 2^15)")
    parser.add_argument("--threads", type=int, default=128, help="threads per block (default 128)")
    parser.add_argument("--variants", default=",".join(VARIANTS),
                        help=f"variants on the coin, comma-separated (default {','.join(VARIANTS)}; also threadsT; "
                             "'' for none)")
    parser.add_argument("--tosses", type=int, default=2 ** 18, help="GPU tosses per table (default 2^18; 0: none)")
    parser.add_argument("--cpu-tosses", type=int, default=2 ** 14, help="CPU tosses per table (default 2^14)")
    parser.add_argument("--toss-impacts", type=int, default=10_000, help="records per toss at most (default 10000)")
    parser.add_argument("--json", default=None, help="write the numbers as JSON to this file")
    parser.add_argument("--smoke", action="store_true", help="a few orbits in numba's CUDA simulator")
    args = parser.parse_args(argv)
    # small launches (the compiles, the sampled one-step launches) warn of low occupancy: not what is measured
    warnings.filterwarnings("ignore", message=".*Grid size .* will likely result in GPU under-utilization")
    if args.smoke:
        os.environ["NUMBA_ENABLE_CUDASIM"] = "1"  # before numba is imported
        args.orbits, args.collisions, args.launches, args.cpu_orbits = 6, 12, 2, 6
        args.tosses, args.cpu_tosses, args.toss_impacts = min(args.tosses, 4), 4, 12
    import numba

    from coinwall.forward.dynamics.billiard import gpu

    why = gpu.device_status()
    if why:
        print(f"bench_gpu: no GPU to measure: {why}")
        return 2
    device = gpu.device_name()
    report = {"device": device, "cores": _cores(), "tables": {}}
    _first_parallel_run()  # numba picks its threading layer at the first parallel run
    report["threading_layer"] = numba.threading_layer()
    print(f"cpu: {_cores()} numba threads (threading layer {report['threading_layer']}), {os.cpu_count()} logical CPUs")
    verdicts = []

    def save():  # after each step: a run cut short by its time limit keeps what it measured
        report["ok"] = all(verdicts)
        if args.json:
            with open(args.json, "w", encoding="utf-8") as fh:
                json.dump(report, fh, indent=1, default=float)

    for name, eps, H in TABLES:
        table, states, rate, trajs, verdict = measure_table(name, eps, H, args, args.threads, device, report)
        if name == "coin":
            coin = (table, states, rate, trajs)
        verdicts.append(verdict)
        save()
    names = [v for v in args.variants.split(",") if v.strip()]
    report["variants"] = {}
    run_variants(coin[0], coin[1], coin[3], args, args.threads, coin[2], names, report["variants"], save)
    if args.tosses > 0:
        from _gpu_toss import measure_tosses

        verdicts.append(measure_tosses(args.tosses, args.cpu_tosses, args.toss_impacts, _cores(), report))
        save()
    print(f"summary: invariants {'ok' if all(verdicts) else 'FAILED'}; coin "
          f"{report['tables']['coin']['gpu_rate']:.3g} /s, {report['tables']['coin']['ratio']:.3g}x the "
          f"{_cores()} cores on {device}")
    save()
    return 0 if all(verdicts) else 1


if __name__ == "__main__":
    sys.exit(main())
