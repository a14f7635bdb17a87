"""Benchmark of the billiard kernel on a CUDA GPU against all the machine's CPU cores, in one run, with its invariants.

Run:  python tests/benchmarks/bench_gpu.py [--orbits M] [--collisions N] [--launches L] [--cpu-orbits K]
                                           [--threads T[,T...]] [--max-registers R[,R...]] [--json FILE] [--smoke]

Two tables: the coin (the ellipse wall with ε = 99, H = 3) and the paper's mixed ellipse (ε = 0.55, H = 1.9; it
has islands, so its orbits are not all chaotic).  For each, M Liouville-random orbits (:func:`random_states`) run
on the GPU, one orbit per thread (``coinwall.forward.dynamics.billiard.gpu``: the CPU kernel's text compiled for
CUDA), L launches of N collisions, each launch continuing every orbit from where the last one stopped (so the
start-up of the first flight is not what is timed).  The GPU's time is wall-clock time from the launch to the
end of the kernel (``cuda.synchronize``), transfers not included; the rate with the copy of every collision back
to the host is printed too.  The CPU runs K of the same orbits with N collisions on all its cores (numba threads,
``ensemble``), three times after a warm-up; its best time counts.  Compile time is excluded on both sides.

Invariants, each over the first launch of the first 32,768 orbits (every one of their N collisions; the GPU's copy
of the rest is timed, not read) unless said otherwise:

* speed: ``max | |v| − 1 |`` over every collision (the kernel keeps the speed 1 to rounding);
* contact: every collision lies on the wall it hit, ``|η − wall(θ)| ≤ tol`` (the table's contact tolerance,
  ``1e-13·max(1, H, max b)``) plus the rounding of the unwrapped θ (4 ulp(θ)·(1 + |b'|)), the wall evaluated
  independently (numpy on casadi's expression, not the GPU's code);
* no flight through a wall: the midpoint of every flight lies strictly inside the strip; and the one-step check
  on the first 64 collisions of the first 1024 orbits: from each GPU state the CPU kernel's next collision is the
  GPU's next one to 1e-12 (a skipped collision would be found there: the CPU's certified search stops at the first
  contact; later collisions carry θ unwrapped, whose last digits are lost beyond ~1e-13 at |θ| ~ 500);
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
not, which is why the error comes from the spread between orbits).  (Total time over total collisions of orbits
of N collisions each would instead average the orbits' own free times: on a table with islands that is not
Santaló's harmonic mean, and it counts each start's first, partial flight.)  ``A`` and ``P`` come from
``Billiard.area_perimeter`` (trapezoid on 20,000 angles: exponentially accurate for these analytic walls).  A 2σ
band is missed by chance 4.6 % of the time; the seed is fixed, so a run is reproducible.

Targets (the GPU's): ≥ 10⁹ collisions/s on the coin on an H100/H200-class GPU, and ≥ 20× all the CPU cores of
the same machine.

Output, one block per table (numbers here are placeholders)::

    table coin: ellipse eps=99, H=3 (tol 3e-13), santalo 2.27336
      gpu  NVIDIA H100 80GB HBM3 (compute capability 9.0), 128 threads/block, 154 registers/thread
      gpu  1048576 orbits x 4 launches x 256 = 1.07e+09 collisions in 0.9 s: 1.19e+09 /s (with copies back 4.1e+08 /s)
      cpu  16 cores, 32768 orbits x 256 = 8.39e+06 collisions in 0.4 s: 2.1e+07 /s
      gpu/cpu 56.7
      speed max||v|-1| 2.2e-16 ok
      contact max residual 1.1e-13 = 0.37 tol ok
      through-wall flights 0 of 2.7e+08 ok; one-step max 3.1e-15 over 261120 collisions ok
      free time 2.27291 +- 0.00051 vs santalo 2.27336: z = -0.88 ok
      targets: >= 1e9/s PASS, >= 20x cpu PASS

then, after both tables, one line per variant on the coin (one launch each: the other block sizes of ``--threads``,
and the launcher compiled with a register cap for each ``--max-registers``: more threads per multiprocessor against
spills to local memory; ptxas reports 154 registers and no spills uncapped, 112 bytes of spills at 128)::

    variant coin, 64 threads/block: 1.1e+09 /s (one launch; 154 registers/thread)
    variant coin, at most 128 registers, 128 threads/block: 1.3e+09 /s (one launch; 128 registers/thread, compiled in 25.0 s)

then one line ``summary: ...`` with the invariants' verdict, and ``--json FILE`` writes the same numbers as JSON.
The exit status is 1 when an invariant fails (the targets are reported, not enforced), 2 when there is no GPU
(outside ``--smoke``, which runs in numba's CUDA simulator at a few orbits and collisions).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
TABLES = (("coin", 99.0, 3.0), ("ellipse", 0.55, 1.9))
ONE_STEP_TOL = 1e-12
CHECKED_ORBITS = 2 ** 15   # the invariants read the first launch of this many orbits (all of it: every collision)
ONE_STEP_ORBITS = 1024     # the one-step check: the first ONE_STEP_COLLISIONS collisions of this many orbits
ONE_STEP_COLLISIONS = 64   # (the unwrapped θ of a long orbit holds its last digits: 1e-13 at |θ| = 500)

CARRY = '''
from numba import cuda


@cuda.jit
def carry(states, turns, leaving, eta, vt, ve, side, done, last):
    # the next launch continues each orbit from its last collision (an orbit that stopped is left as it is)
    k = cuda.grid(1)
    if k < states.shape[0]:
        d = done[k]
        if d > 0:
            states[k, 0] = last[k, 0]
            states[k, 1] = eta[k, d - 1]
            states[k, 2] = vt[k, d - 1]
            states[k, 3] = ve[k, d - 1]
            turns[k] = int(last[k, 1])
            leaving[k] = side[k, d - 1]
'''


def _carry_kernel():
    namespace = {}
    exec(compile(CARRY, "<bench_gpu carry>", "exec"), namespace)  # noqa: S102 -- our own text above
    return namespace["carry"]


def capped_kernel(wall, registers):
    """The billiard's launcher compiled with at most ``registers`` registers a thread (more threads fit on a
    multiprocessor, at the price of spills to local memory): the same kernel text, another launcher line."""
    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.kernel import KERNEL_SOURCE

    launcher = gpu.BILLIARD_LAUNCHER.replace("@cuda.jit\n", f"@cuda.jit(max_registers={int(registers)})\n")
    return gpu.gpu_module(wall, KERNEL_SOURCE, launcher, f"coinwall_gpu_r{int(registers)}")._run_gpu


def _cores() -> int:
    import numba

    return int(numba.config.NUMBA_NUM_THREADS)


def run_gpu(table, states, n, launches, threads, checked=CHECKED_ORBITS, kernel=None):
    """M orbits × L launches of n collisions on the GPU (the kernel of coinwall's GPU module, or ``kernel``);
    returns (seconds, collisions, (first launch's host rows, done, status), seconds with copies, registers per
    thread)."""
    from numba import config

    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.kernel import compiled
    from coinwall.forward.dynamics.billiard.table import _check_states

    cuda = gpu.cuda_module()
    kernel = kernel or gpu._billiard_module(table.wall)._run_gpu
    carry = _carry_kernel()
    unit, _speed, leaving, turns = _check_states(table, states, "states")
    m = unit.shape[0]
    H, b0, c, cells, lookup, wmin, wmax, tol = compiled(table).args(table)
    consts = [cuda.to_device(np.ascontiguousarray(a)) for a in (c, cells, lookup)]
    d_states, d_turns, d_leaving = (cuda.to_device(np.ascontiguousarray(a)) for a in (unit, turns, leaving))
    outs = [cuda.device_array((m, n)) for _ in range(5)] + [cuda.device_array((m, n), dtype=np.int8)]
    d_done, d_status = cuda.device_array(m, dtype=np.int64), cuda.device_array(m, dtype=np.int64)
    d_last = cuda.device_array((m, 2))
    blocks = (m + threads - 1) // threads
    scalars = (float(H), float(b0))
    tail = (float(wmin), float(wmax), float(tol))
    seconds, total, first = 0.0, 0, None
    copies = 0.0
    for launch in range(launches):
        cuda.synchronize()
        start = time.perf_counter()
        kernel[blocks, threads](d_states, d_turns, d_leaving, n, *scalars, *consts, *tail, *outs, d_done, d_status,
                                d_last)
        carry[blocks, threads](d_states, d_turns, d_leaving, outs[2], outs[3], outs[4], outs[5], d_done, d_last)
        cuda.synchronize()
        seconds += time.perf_counter() - start
        done = d_done.copy_to_host()
        total += int(done.sum())
        start = time.perf_counter()
        rows = [o.copy_to_host() for o in outs]
        copies += time.perf_counter() - start
        if launch == 0:
            first = ([o[:checked].copy_to_host() for o in outs], done[:checked], d_status.copy_to_host()[:checked])
        del rows
    registers = None
    if not config.ENABLE_CUDASIM:
        try:
            registers = int(next(iter(kernel.get_regs_per_thread().values())))
        except Exception:  # noqa: BLE001 -- a report only
            registers = None
    return seconds, total, first, seconds + copies, registers


def run_cpu(table, states, n, repeats=3):
    """The same kind of orbits on all CPU cores (numba threads); the best of ``repeats`` runs: (seconds, collisions)."""
    from coinwall.forward.dynamics.billiard.table import ensemble

    ensemble(table, states[:2], 2)  # compile or load
    best, total = math.inf, 0
    for _ in range(repeats):
        start = time.perf_counter()
        trajs = ensemble(table, states, n)
        best = min(best, time.perf_counter() - start)
        total = sum(len(t) for t in trajs)
        del trajs
    return best, total


def invariants(table, rows, done, status, sample):
    """The checks of the module docstring on the first launch (rows: time, θ, η, v_θ, v_η, side)."""
    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.table import Trajectory

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
    # flights between consecutive collisions: their midpoints strictly inside the strip
    dt = np.diff(t, axis=1)
    mid_th = (th[:, :-1] + 0.5 * a[:, :-1] * dt).ravel()
    mid_eta = (et[:, :-1] + 0.5 * b[:, :-1] * dt).ravel()
    through = (mid_eta <= table.lower(mid_th)) | (mid_eta >= table.upper(mid_th))
    out["through"] = int(np.count_nonzero(through))
    out["flights"] = int(mid_th.size)
    # the one-step check on the first orbits
    c = ONE_STEP_COLLISIONS
    trajs = [Trajectory(time=t[k, :c], theta=th[k, :c], eta=et[k, :c], v_theta=a[k, :c], v_eta=b[k, :c], side=sd[k, :c],
                        start=np.zeros(4), table=table) for k in range(min(sample, t.shape[0]))]
    out["one_step"] = float(gpu.one_step_check(table, trajs))
    out["one_step_collisions"] = int(sum(len(x) - 1 for x in trajs))
    # Santaló: the counts in the common window [0, T] (module docstring)
    window = float(np.min(t[:, -1]))
    rate = np.count_nonzero(t <= window, axis=1) / window
    tau = 1.0 / rate.mean()
    sigma = float(rate.std(ddof=1) / math.sqrt(rate.size) / rate.mean() ** 2)
    area, perimeter = table.area_perimeter()
    santalo = math.pi * area / perimeter
    out.update(free_time=float(tau), free_time_sigma=sigma, santalo=santalo, z=float((tau - santalo) / sigma))
    out["ok"] = bool(out["orbits_stopped"] == 0 and out["speed"] < 1e-14 and out["contact_ok"] and out["through"] == 0
                     and out["one_step"] <= ONE_STEP_TOL and abs(out["z"]) <= 2.0)
    return out


def ok(flag) -> str:
    return "ok" if flag else "FAILED"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--orbits", type=int, default=2 ** 18, help="GPU orbits (default 2^18)")
    parser.add_argument("--collisions", type=int, default=256, help="collisions per orbit and launch (default 256)")
    parser.add_argument("--launches", type=int, default=4, help="launches, each continuing the last (default 4)")
    parser.add_argument("--cpu-orbits", type=int, default=2 ** 15, help="CPU orbits (default 2^15)")
    parser.add_argument("--threads", default="128", help="threads per block; several (64,128,256): the first is "
                                                         "the headline, the others one launch each on the coin")
    parser.add_argument("--max-registers", default="", help="register caps to try on the coin after the main runs "
                                                            "(e.g. 128; each costs a compile)")
    parser.add_argument("--json", default=None, help="write the numbers as JSON to this file")
    parser.add_argument("--smoke", action="store_true", help="a few orbits in numba's CUDA simulator")
    args = parser.parse_args(argv)
    if args.smoke:
        os.environ["NUMBA_ENABLE_CUDASIM"] = "1"  # before numba is imported
        args.orbits, args.collisions, args.launches, args.cpu_orbits = 6, 12, 2, 6
    from coinwall.forward import Wall
    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.table import Billiard, random_states

    why = gpu.device_status()
    if why:
        print(f"bench_gpu: no GPU to measure: {why}")
        return 2
    threads = [int(x) for x in args.threads.split(",")]
    device = gpu.device_name()
    report, verdicts = {"device": device, "cores": _cores(), "tables": {}}, []
    for name, eps, H in TABLES:
        table = Billiard(Wall.from_expression(ELLIPSE, {"eps": eps}), H)
        states = random_states(table, args.orbits, seed=1)
        compile_start = time.perf_counter()
        run_gpu(table, states[:threads[0]], 2, 1, threads[0])  # compile (and load) outside the timing
        compile_seconds = time.perf_counter() - compile_start
        seconds, total, (rows, done, status), with_copies, registers = run_gpu(table, states, args.collisions,
                                                                                args.launches, threads[0])
        rate = total / seconds
        checks = invariants(table, rows, done, status, ONE_STEP_ORBITS)
        del rows
        cpu_states = random_states(table, args.cpu_orbits, seed=2)
        cpu_seconds, cpu_total = run_cpu(table, cpu_states, args.collisions)
        cpu_rate = cpu_total / cpu_seconds
        print(f"table {name}: ellipse eps={eps:g}, H={H:g} (tol {table.tol:.3g}), santalo {checks['santalo']:.6g}")
        print(f"  gpu  {device}, {threads[0]} threads/block, {registers or '?'} registers/thread, compile "
              f"{compile_seconds:.1f} s")
        print(f"  gpu  {args.orbits} orbits x {args.launches} launches x {args.collisions} = {total:.3g} collisions in "
              f"{seconds:.3g} s: {rate:.3g} /s (with copies back {total / with_copies:.3g} /s)")
        print(f"  cpu  {_cores()} cores, {args.cpu_orbits} orbits x {args.collisions} = {cpu_total:.3g} collisions in "
              f"{cpu_seconds:.3g} s: {cpu_rate:.3g} /s")
        print(f"  gpu/cpu {rate / cpu_rate:.3g}")
        print(f"  speed max||v|-1| {checks['speed']:.2g} {ok(checks['speed'] < 1e-14)}")
        print(f"  contact max residual {checks['contact']:.2g} = {checks['contact'] / checks['tol']:.2g} tol "
              f"{ok(checks['contact_ok'])}")
        print(f"  through-wall flights {checks['through']} of {checks['flights']:.3g} {ok(checks['through'] == 0)}; "
              f"one-step max {checks['one_step']:.2g} over {checks['one_step_collisions']} collisions "
              f"{ok(checks['one_step'] <= ONE_STEP_TOL)}; orbits stopped early {checks['orbits_stopped']}")
        print(f"  free time {checks['free_time']:.6g} +- {checks['free_time_sigma']:.2g} vs santalo "
              f"{checks['santalo']:.6g}: z = {checks['z']:.2f} {ok(abs(checks['z']) <= 2)}")
        targets = {"rate_1e9": rate >= 1e9, "vs_cpu_20x": rate >= 20 * cpu_rate}
        if name == "coin":
            print(f"  targets: >= 1e9/s {'PASS' if targets['rate_1e9'] else 'MISS'}, >= 20x cpu "
                  f"{'PASS' if targets['vs_cpu_20x'] else 'MISS'}")
        verdicts.append(checks["ok"])
        report["tables"][name] = dict(checks, eps=eps, H=H, gpu_rate=rate, gpu_seconds=seconds, gpu_collisions=total,
                                      gpu_rate_with_copies=total / with_copies, cpu_rate=cpu_rate,
                                      cpu_collisions=cpu_total, ratio=rate / cpu_rate, threads=threads[0],
                                      registers=registers, compile_seconds=compile_seconds, targets=targets)
        sys.stdout.flush()
    # variants, on the coin, one launch each (after the main results: a run cut short keeps those)
    table = Billiard(Wall.from_expression(ELLIPSE, {"eps": 99.0}), 3.0)
    states = random_states(table, args.orbits, seed=1)
    sweep = {}
    variants = [(f"{t} threads/block", t, None) for t in threads[1:]]
    from numba import config

    caps = [int(x) for x in args.max_registers.split(",") if x.strip()]
    if caps and config.ENABLE_CUDASIM:
        print("variant register caps: not in the simulator (its cuda.jit takes no max_registers)")
        caps = []
    variants += [(f"at most {r} registers, {threads[0]} threads/block", threads[0], r) for r in caps]
    for label, t, cap in variants:
        start = time.perf_counter()
        try:  # a variant is a report, not a check: one that cannot compile or run says so and the others go on
            kernel = capped_kernel(table.wall, cap) if cap else None
            if kernel is not None:
                run_gpu(table, states[:t], 2, 1, t, kernel=kernel)  # compile
            compiled_in = time.perf_counter() - start
            seconds, total, _, _, registers = run_gpu(table, states, args.collisions, 1, t, kernel=kernel)
        except Exception as exc:  # noqa: BLE001
            print(f"variant coin, {label}: failed ({type(exc).__name__}: {str(exc).splitlines()[0][:200]})")
            continue
        sweep[label] = total / seconds
        print(f"variant coin, {label}: {total / seconds:.3g} /s (one launch; {registers or '?'} registers/thread"
              f"{f', compiled in {compiled_in:.1f} s' if cap else ''})")
        sys.stdout.flush()
    report["variants"] = sweep
    print(f"summary: invariants {'ok' if all(verdicts) else 'FAILED'}; coin "
          f"{report['tables']['coin']['gpu_rate']:.3g} /s, {report['tables']['coin']['ratio']:.3g}x the "
          f"{_cores()} cores on {device}")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(report, fh, indent=1)
    return 0 if all(verdicts) else 1


if __name__ == "__main__":
    sys.exit(main())
