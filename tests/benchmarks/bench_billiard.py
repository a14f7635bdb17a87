"""Benchmark of the billiard kernel against a simple conservative-advancement stepper, and its cost.

Run:  python tests/benchmarks/bench_billiard.py [--collisions N] [--rounds R] [--count] [--smoke]

The comparison is against a stepper written for this benchmark and compiled with numba like the kernel, with
the same exactness goal: it advances by the *global* Lipschitz bound
``g/(|v_η| + |v_θ| max|b'|)`` until the gap is below the same tolerance, then takes the
same Newton step on the exact wall; the first step away from a wall uses the global bound
on |b''| (smooth walls only).  Both run single-threaded on the same orbit start in the same
process; compile time is excluded (one warm-up run each).  For the headline number the
two are timed alternately for several rounds (kernel best of 3, then baseline once, per
round), so a slow phase of the shared machine hits both; the other lines are best of 3.  Every
line is CPU time (``time.process_time``: a slow phase of the machine that takes the CPU away is not
counted).  The kernel of one git revision against another's: ``python tests/benchmarks/kernel_ab.py REV_A REV_B``.
"""

import argparse
import math
import sys
import time

import numpy as np

from coinwall.forward import Wall
from coinwall.forward.dynamics.billiard.kernel import compiled as _compiled
from coinwall.forward.dynamics.billiard.reference import sample_bounds as _sample_bounds
from coinwall.forward.dynamics.billiard.table import Billiard, random_states, simulate
from coinwall.forward.dynamics.billiard.wallcode import load_module, wall_source

BASELINE = '''
TWO_PI = 2.0 * math.pi
PI = math.pi


@njit(cache=CACHE)
def baseline(state, leaving, n, H, b0, c, lip, curv, tol):
    th = state[0] % TWO_PI
    eta = state[1]
    vt = state[2]
    ve = state[3]
    total = 0.0
    for i in range(n):
        lam = abs(ve) + abs(vt) * lip
        t = 0.0
        if leaving >= 0:  # leave the wall: second-order step with the global |b''| bound
            if leaving == 0:
                b, d1 = wall_b1(th, c)
                g1 = ve - vt * d1
                bo, do = wall_b1(th + PI, c)
                go = H - b0 - bo - eta
            else:
                b, d1 = wall_b1(th + PI, c)
                g1 = -ve - vt * d1
                bo, do = wall_b1(th, c)
                go = eta - b0 - bo
            t = min(2.0 * g1 / (vt * vt * curv + 1e-300), go / lam)
        side = -1
        for it in range(10000000):
            bl, dl = wall_b1(th + vt * t, c)
            bu, du = wall_b1(th + PI + vt * t, c)
            gl = eta + ve * t - b0 - bl
            gu = H - b0 - bu - eta - ve * t
            if gl <= tol:
                side = 0
                g1 = ve - vt * dl
                if g1 < 0.0:
                    t += gl / (-g1)
                break
            if gu <= tol:
                side = 1
                g1 = -ve - vt * du
                if g1 < 0.0:
                    t += gu / (-g1)
                break
            t += min(gl, gu) / lam
        th = (th + vt * t) % TWO_PI
        eta += ve * t
        total += t
        if side == 0:
            b, d1 = wall_b1(th, c)
            s = d1
        else:
            b, d1 = wall_b1(th + PI, c)
            s = -d1
        dot = ve - s * vt
        nn = 1.0 + s * s
        vt = vt + 2.0 * dot * s / nn
        ve = ve - 2.0 * dot / nn
        sp = math.sqrt(vt * vt + ve * ve)
        vt /= sp
        ve /= sp
        leaving = side
    return total
'''


def _baseline_module(wall):
    source, constants = wall_source(wall, "@njit(cache=CACHE)\n")
    header = "import math\nfrom numba import njit\n\n"
    return load_module(header + source + BASELINE, "coinwall_bench_baseline"), constants


def _cpu_run(module, state, collisions, args):
    # one orbit through a kernel module's _run; CPU seconds and the six output columns
    out = [np.empty(collisions) for _ in range(5)] + [np.empty(collisions, dtype=np.int8)]
    last = np.empty(2)
    start = time.process_time()
    done, status = module._run(state, 0, -1, collisions, *args, *out, last)
    seconds = time.process_time() - start
    if done != collisions:  # a rate over an orbit that stopped early would be meaningless
        raise RuntimeError(f"kernel stopped after {done} of {collisions} collisions (status {status})")
    return seconds, out


def rate_kernel(table, collisions, seed=1):
    state = random_states(table, 1, seed)[0]
    simulate(table, state, 10)  # compile / load
    best = math.inf
    for _ in range(3):
        start = time.process_time()
        traj = simulate(table, state, collisions)
        best = min(best, time.process_time() - start)
    if len(traj) != collisions:  # a rate over an orbit that stopped early would be meaningless
        raise RuntimeError(f"kernel stopped after {len(traj)} of {collisions} collisions: {traj.note}")
    return collisions / best, traj.time[-1] / collisions


def count_work(table, collisions=20_000, seed=1):
    """Work per collision of the kernel: cells tested, box tests failed, proxy steps, wall evaluations.

    The kernel's own source is run as plain Python (numba decorators replaced by the identity)
    with counters added at fixed lines, so the counts are those of the compiled kernel's
    algorithm (not its timing).
    """
    from coinwall.forward.dynamics.billiard.kernel import KERNEL_SOURCE, SEARCH_SOURCE

    source, constants = wall_source(table.wall)
    counts = {"cells": 0, "box_failed": 0, "proxy_steps": 0, "wall_evaluations": 0}
    probes = [("            walked += 1\n", "            walked += 1\n            counts['cells'] += 1\n"),
              ("        # the box test failed in cell j: the proxy and exact stages decide\n",
               "        # the box test failed in cell j: the proxy and exact stages decide\n"
               "        counts['box_failed'] += 1\n"),
              ("                s = vt * t - a\n",
               "                s = vt * t - a\n                counts['proxy_steps'] += 1\n")]
    kernel = SEARCH_SOURCE + KERNEL_SOURCE
    for anchor, replacement in probes:
        if kernel.count(anchor) != 1:
            raise RuntimeError("count_work: the kernel source changed; update the probes")
        kernel = kernel.replace(anchor, replacement)
    namespace = {"math": math, "np": np, "njit": lambda *a, **k: (lambda f: f), "prange": range,
                 "OPTIONS": {}, "CACHE": False, "counts": counts,
                 # plain Python has no reference counts to avoid: the arrays themselves serve as views
                 "carray": lambda array, shape: array, "intrinsic": lambda f: (lambda array: array), "types": None}
    exec(source, namespace)  # our own generated source
    wall_b1, wall_b2 = namespace["wall_b1"], namespace["wall_b2"]

    def counted1(phi, c):
        counts["wall_evaluations"] += 1
        return wall_b1(phi, c)

    def counted2(phi, c):
        counts["wall_evaluations"] += 1
        return wall_b2(phi, c)

    exec(kernel, namespace)
    namespace["wall_b1"], namespace["wall_b2"] = counted1, counted2
    comp = _compiled(table)
    state = random_states(table, 1, seed)[0]
    out = [np.empty(collisions) for _ in range(5)] + [np.empty(collisions, dtype=np.int8)]
    last = np.empty(2)
    done, _ = namespace["_run"](state, 0, -1, collisions, *comp.args(table), *out, last)
    return {k: v / done for k, v in counts.items()}


def rate_baseline(table, collisions, seed=1, repeats=3):
    module, constants = _baseline_module(table.wall)
    lip, curv, _ = _sample_bounds(table.wall)
    state = random_states(table, 1, seed)[0]
    module.baseline(state, -1, 10, table.H, table.b0, constants, lip, curv, table.tol)
    seconds = math.inf
    for _ in range(repeats):  # best of 3, like the kernel
        start = time.process_time()
        total = module.baseline(state, -1, collisions, table.H, table.b0, constants, lip, curv, table.tol)
        seconds = min(seconds, time.process_time() - start)
    return collisions / seconds, total / collisions


def interleaved(table, collisions, rounds=5, seed=1):
    """Kernel and baseline timed alternately, ``rounds`` times each (one run of each per round).

    This machine is shared and has slow phases lasting seconds to minutes, in which both
    rates drop by up to a third: timing the two back to back, round after round, puts them
    in the same phase.  Returns the best rates, the median of the per-round ratios, all
    per-round kernel rates and the mean free times.
    """
    base_n = max(collisions // 20, 10_000)
    kernel_rates, base_rates = [], []
    for _ in range(rounds):
        k, mft = rate_kernel(table, collisions, seed)
        b, mft_base = rate_baseline(table, base_n, seed, repeats=1)
        kernel_rates.append(k)
        base_rates.append(b)
    ratios = np.array(kernel_rates) / np.array(base_rates)
    return max(kernel_rates), max(base_rates), float(np.median(ratios)), kernel_rates, mft, mft_base


def ensemble_line(table, collisions, rounds):
    """An ensemble on every core against one orbit on one thread: wall-clock time per collision, alternately.

    ``ensemble`` runs its orbits on numba's threads (one orbit per thread at a time); 16 orbits share the
    collisions of the single orbit, so both do the same work.
    """
    import numba

    from coinwall.forward.dynamics.billiard.table import ensemble

    cores = numba.config.NUMBA_NUM_THREADS
    orbits = 16
    states = random_states(table, orbits, seed=5)
    per_orbit = max(collisions // orbits, 1000)
    ensemble(table, states, 100, workers=cores)  # compile or load the parallel kernel
    single, many = [], []
    for _ in range(rounds):
        numba.set_num_threads(1)
        start = time.perf_counter()
        simulate(table, states[0], per_orbit * orbits)
        single.append((time.perf_counter() - start) / (per_orbit * orbits))
        numba.set_num_threads(cores)
        start = time.perf_counter()
        ensemble(table, states, per_orbit, workers=cores)
        many.append((time.perf_counter() - start) / (per_orbit * orbits))
    numba.set_num_threads(1)
    ratio = float(np.median(np.array(many) / np.array(single)))
    print(f"ensemble of {orbits} orbits on {cores} threads against one orbit on one thread (wall clock, "
          f"{rounds} alternating rounds): {1e9 * np.median(many):.0f} against {1e9 * np.median(single):.0f} "
          f"ns/collision, ratio {ratio:.2f}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--collisions", type=int, default=2_000_000)
    parser.add_argument("--count", action="store_true", help="also count the kernel's work per collision")
    parser.add_argument("--rounds", type=int, default=7, help="interleaved rounds of each comparison (default 7)")
    parser.add_argument("--smoke", action="store_true",
                        help="a run of a few seconds through every part of the benchmark (numbers meaningless)")
    args = parser.parse_args(argv)
    import numba

    from coinwall.cases.ellipse import ellipse_wall

    numba.set_num_threads(1)
    n, rounds = (20_000, 1) if args.smoke else (args.collisions, args.rounds)
    coin = ellipse_wall(99.0)
    table = Billiard(coin, 3.0)
    kernel, base, ratio, rates, mft, mft_base = interleaved(table, n, rounds)
    print(f"coin eps=99, H=3 (1.5 D), single thread, {rounds} interleaved rounds: "
          f"kernel best {kernel / 1e6:.2f} M coll/s (rounds: {', '.join(f'{r / 1e6:.2f}' for r in rates)}), "
          f"baseline stepper best {base / 1e6:.3f} M coll/s, ratio {kernel / base:.1f}x best/best, "
          f"{ratio:.1f}x median per round (mean free time {mft:.4f} / {mft_base:.4f})")
    print("cost against H (coin, eps=99):")
    for H in ((2.2, 12.0) if args.smoke else (2.2, 3.0, 6.0, 12.0)):
        r, mft = rate_kernel(Billiard(coin, H), n // 2)
        print(f"  H={H:5.1f}: {r / 1e6:.2f} M coll/s, mean free time {mft:.3f}, {1e9 / r:.0f} ns/collision")
    print("cost against wall complexity (Fourier walls, H = 3):")
    rng = np.random.default_rng(0)
    for harmonics in ((5,) if args.smoke else (5, 20, 80)):
        k = np.arange(1, harmonics + 1)
        amp = 0.3 / k**2  # a smooth, convex-enough wall: b'' stays moderate
        wall = Wall.from_fourier(1.0, amp * rng.uniform(-1, 1, harmonics), amp * rng.uniform(-1, 1, harmonics))
        r, mft = rate_kernel(Billiard(wall, 3.0), n // 4)
        print(f"  {harmonics:3d} harmonics: {r / 1e6:.2f} M coll/s, {1e9 / r:.0f} ns/collision")
    ensemble_line(table, n, rounds)
    bd = _compiled(table).bounds
    print(f"(cells per period: {bd['edges'].size - 1})")
    if args.count or args.smoke:
        count = 500 if args.smoke else 20_000
        work = count_work(table, count)
        print(f"work per collision (coin, H = 3; {count} collisions run as plain Python): "
              + ", ".join(f"{k} {v:.2f}" for k, v in work.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
