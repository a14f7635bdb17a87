"""Benchmark: the time to P(n) ± 0.002 for n ≤ 40 at H = 1.2 D, ε = 99 coin.

Run:  python tests/benchmarks/bench_correlation.py [--quick] [--orbits 100] [--seeds 10] [--repeat 3]

The table.  The paper's coin wall ``sqrt((1+eps*cos(t)**2)/(1+eps))`` with ε = 99 (an expression
wall), diameter D = b(0) + b(π) = 2 (units of κ), H = 1.2 D = 2.4; n counts bottom collisions
(the default of :func:`coinwall.forward.dynamics.analysis.correlation.correlation`), ``max_lag = 40``, ``orbits = 100``.

What is timed.  Every timed run is a fresh Python process (this file re-runs itself with
``--child``) that imports coinwall, builds the wall and the table, compiles the kernel, then calls
``correlation(table, bounces=N, max_lag=40, orbits=100, seed=1)`` on all cores (``workers=None``).
"compile/load" is ``coinwall.forward.dynamics.billiard.table.compile_kernel`` plus one tiny ``ensemble`` call:
compile_kernel warms only the serial kernel, the parallel one compiles on its first call; numba's
disk cache makes both a load after the very first run.  "user pays" is the process's whole
wall-clock time as measured by this parent process (interpreter start, imports, table, the
correlation call, exit) minus compile/load.  The command line is timed the same way, once, at the
1σ answer (``coinwall correlation ... --json``; that time includes the compile/load).

Criterion.  "±0.002" is ambiguous, so both readings are reported:
  1σ: max over n = 1…40 of P_stderr(n) ≤ 0.002;
  2σ: a 95 % half-width 2·P_stderr ≤ 0.002, i.e. max P_stderr ≤ 0.001.
N doubles from 1e5 until both hold; reported: the smallest N on that grid, the N where a log-log
fit of max P_stderr against N (slope ≈ −½ expected) crosses each threshold, and a run 5 % above
that crossing (the answer if it meets the goal).  All grid runs
use seed 1, so they follow the same orbits for longer: the grid points are not independent.

Is the error bar honest?  At the 1σ answer N, correlation runs in this process with seeds 1…k
(independent start states); the spread of P(n) between seeds (std, ddof 1) is compared with the
mean reported P_stderr(n).  The ratio should be ≈ 1; with k seeds a single lag's ratio scatters
by about 1/√(2(k−1)) (0.24 for k = 10), and the lags share orbits, so pooling 40 lags narrows this
much less than √40.  Nothing is asserted: the ratio is reported.

Baselines in the same run (in this process, warm, median of ``--repeat``, at each answer N):
the kernel alone (``coinwall.forward.dynamics.billiard.table.ensemble`` over the same orbits and collisions, no analysis)
gives the cost of the analysis; ``correlation(..., workers=1)`` gives the parallel speed-up.

``--smoke``: each step once at 20,000 bounces of 4 orbits, one fresh run (seconds; checks the script, not the numbers).
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"
EPS = 99.0
H_OVER_D = 1.2
MAX_LAG = 40
THRESHOLD = 0.002
START = 100_000
LIMIT = 64_000_000  # give up doubling beyond this (would take minutes)


def _table():
    from coinwall.forward import Wall
    from coinwall.forward.dynamics.billiard.table import Billiard

    wall = Wall.from_expression(COIN, {"eps": EPS})
    diameter = float(wall(0.0)) + float(wall(math.pi))
    return Billiard(wall, H_OVER_D * diameter), diameter


def _child(bounces, orbits, seed):
    """Run in a fresh process: print one JSON line with the timings of the stages."""
    start = time.perf_counter()
    from coinwall.forward.dynamics.analysis.correlation import correlation
    from coinwall.forward.dynamics.billiard.table import compile_kernel, ensemble, random_states

    imported = time.perf_counter()
    table, diameter = _table()
    setup = time.perf_counter()
    compile_seconds = compile_kernel(table)
    # compile_kernel warms the serial kernel only; the parallel one (_run_many, used by ensemble) is
    # compiled or loaded on its first call: ~1.4 s with a cold cache, which is compilation too
    begin = time.perf_counter()
    ensemble(table, random_states(table, 2, 0), 1)
    parallel_seconds = time.perf_counter() - begin
    begin = time.perf_counter()
    result = correlation(table, bounces=bounces, max_lag=MAX_LAG, orbits=orbits, seed=seed)
    end = time.perf_counter()
    print(json.dumps({"bounces": result.bounces, "orbits": result.orbits, "H": table.H, "D": diameter,
                      "import_s": imported - start, "setup_s": setup - imported,
                      "compile_s": compile_seconds + parallel_seconds,
                      "compile_kernel_s": compile_seconds, "parallel_compile_s": parallel_seconds,
                      "correlation_s": end - begin, "max_stderr": float(max(result.P_stderr[1:])),
                      "tau": result.tau, "notes": list(result.notes)}))


def _environment():
    env = dict(os.environ)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def fresh_run(bounces, orbits, seed=1):
    """Time one correlation in a fresh process; returns the child's record plus ``total_s`` and ``user_s``."""
    start = time.perf_counter()
    done = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", str(bounces), "--orbits", str(orbits),
                           "--seed", str(seed)], capture_output=True, text=True, env=_environment())
    total = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"child failed:\n{done.stderr}")
    record = json.loads(done.stdout.strip().splitlines()[-1])
    record["total_s"] = total
    record["user_s"] = total - record["compile_s"]
    return record


def fresh_cli(bounces, H, orbits, seed=1):
    """Wall-clock seconds of ``coinwall correlation ... --json`` in a fresh process, and its max P_stderr."""
    code = "import sys; from coinwall.cases.cli import main; sys.exit(main())"
    argv = [sys.executable, "-c", code, "correlation", COIN, "--param", f"eps={EPS:g}", "--H", repr(H),
            "--bounces", str(bounces), "--max-lag", str(MAX_LAG), "--orbits", str(orbits), "--seed", str(seed),
            "--json"]
    start = time.perf_counter()
    done = subprocess.run(argv, capture_output=True, text=True, env=_environment())
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"coinwall failed:\n{done.stderr}")
    return seconds, max(json.loads(done.stdout)["P_stderr"][1:])


def crossing(records, threshold):
    """N where the log-log fit of max P_stderr against N crosses ``threshold``; and the fitted slope."""
    import numpy as np

    n = np.log([r["bounces"] for r in records])
    s = np.log([r["max_stderr"] for r in records])
    if n.size < 2:
        r = records[0]
        return r["bounces"] * (r["max_stderr"] / threshold) ** 2, math.nan  # σ ∝ N^(−½) assumed
    slope, intercept = np.polyfit(n, s, 1)
    return float(math.exp((math.log(threshold) - intercept) / slope)), float(slope)


def seed_check(bounces, orbits, seeds):
    """Spread of P(n) between seeds against the reported P_stderr (module docstring)."""
    import numpy as np

    from coinwall.forward.dynamics.analysis.correlation import correlation

    table, _ = _table()
    runs = [correlation(table, bounces=bounces, max_lag=MAX_LAG, orbits=orbits, seed=s) for s in range(1, seeds + 1)]
    P = np.array([r.P[1:] for r in runs])
    err = np.array([r.P_stderr[1:] for r in runs])
    spread = P.std(axis=0, ddof=1)
    reported = err.mean(axis=0)
    ratio = spread / reported
    pooled = math.sqrt(np.sum(spread**2) / np.sum(reported**2))
    return {"pooled": pooled, "min": float(ratio.min()), "median": float(np.median(ratio)), "max": float(ratio.max()),
            "expected_scatter": 1 / math.sqrt(2 * (seeds - 1)), "max_reported": float(err.max()),
            "max_spread": float(spread.max()), "mean_max_reported": float(err.max(axis=1).mean())}


def baselines(bounces, orbits, repeat):
    """Medians (s) of: the kernel alone, correlation on all cores, correlation on one core (warm, in process)."""
    import numpy as np

    from coinwall.forward.dynamics.analysis.correlation import _CHUNK_COLLISIONS, correlation
    from coinwall.forward.dynamics.billiard.table import compile_kernel, ensemble, random_states

    table, _ = _table()
    compile_kernel(table)
    starts = random_states(table, orbits, 1)
    ensemble(table, starts[:2], 10)  # numba's thread pool
    per_orbit = bounces // orbits
    collisions = 2 * per_orbit + 20 + 2 * MAX_LAG + 64  # what correlation asks for (burn = 20)
    group = max(1, min(orbits, _CHUNK_COLLISIONS // collisions))
    times = {"kernel": [], "all cores": [], "one core": []}
    for _ in range(repeat):
        start = time.perf_counter()
        for first in range(0, orbits, group):
            ensemble(table, starts[first:first + group], collisions)
        times["kernel"].append(time.perf_counter() - start)
        for name, workers in (("all cores", None), ("one core", 1)):
            start = time.perf_counter()
            correlation(table, bounces=bounces, max_lag=MAX_LAG, orbits=orbits, seed=1, workers=workers)
            times[name].append(time.perf_counter() - start)
    return {k: float(np.median(v)) for k, v in times.items()}


def _row(r):
    return (f"{r['bounces']:>10,d} {r['max_stderr']:10.5f} {r['correlation_s']:9.2f} {r['user_s']:9.2f} "
            f"{r['import_s'] + r['setup_s']:8.2f} {r['compile_s']:8.2f}")


def _smoke(bounces=20_000, orbits=4):
    """Each step of the benchmark once, at sizes that take seconds."""
    record = fresh_run(bounces, orbits)
    print(_row(record))
    # the fit of σ against N, on the fresh run and a copy of it at four times N with half the error
    fitted, slope = crossing([record, {**record, "bounces": 4 * bounces, "max_stderr": record["max_stderr"] / 2}],
                             THRESHOLD)
    print(f"fit σ ∝ N^{slope:.3f} crosses {THRESHOLD} at N = {fitted:,.0f}")
    base = baselines(bounces, orbits, 1)
    print(f"kernel alone {base['kernel']:.3f} s, correlation {base['all cores']:.3f} s, "
          f"one core {base['one core']:.3f} s")
    check = seed_check(bounces, orbits, 2)
    print(f"spread between 2 seeds / reported P_stderr = {check['pooled']:.2f}")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1σ reading only, 4 seeds, no repeats")
    parser.add_argument("--orbits", type=int, default=100, help="independent orbits (default 100, the library's)")
    parser.add_argument("--seeds", type=int, default=10, help="seeds for the error-bar check (default 10)")
    parser.add_argument("--repeat", type=int, default=3, help="fresh runs of each answer, and in-process repeats")
    parser.add_argument("--child", type=int, default=None, metavar="BOUNCES", help=argparse.SUPPRESS)
    parser.add_argument("--seed", type=int, default=1, help=argparse.SUPPRESS)
    parser.add_argument("--smoke", action="store_true", help="every step once, tiny sizes: checks the script")
    args = parser.parse_args(argv)
    if args.child is not None:
        _child(args.child, args.orbits, args.seed)
        return 0
    if args.smoke:
        return _smoke()
    if args.quick:
        args.seeds, args.repeat = min(args.seeds, 4), 1
    goals = {"1σ": THRESHOLD} if args.quick else {"1σ": THRESHOLD, "2σ": THRESHOLD / 2}

    print(f"coin ε = {EPS:g}, H = {H_OVER_D} D, max_lag {MAX_LAG}, {args.orbits} orbits, bottom collisions, "
          f"all cores; each row a fresh process, seed 1")
    print(f"{'bounces N':>10} {'max σ(P)':>10} {'corr. s':>9} {'user s':>9} {'import+':>8} {'compile':>8}")
    records, bounces = [], START
    while True:
        record = fresh_run(bounces, args.orbits)
        records.append(record)
        print(_row(record), flush=True)
        if record["max_stderr"] <= min(goals.values()) or bounces >= LIMIT:
            break
        bounces *= 2
    print(f"(H = {records[0]['H']:g}, D = {records[0]['D']:g}; 'user s' = whole process − compile/load; "
          f"'import+' = imports and table)")

    answers = {}
    for name, goal in goals.items():
        hit = next((r for r in records if r["max_stderr"] <= goal), None)
        fitted, slope = crossing(records, goal)
        if hit is None:
            print(f"{name}: max σ ≤ {goal} NOT reached by N = {records[-1]['bounces']:,d}")
            continue
        print(f"{name} (max P_stderr ≤ {goal:g}): N = {hit['bounces']:,d} on the doubling grid; "
              f"fit σ ∝ N^{slope:.3f} crosses at N = {fitted:,.0f}")
        # the grid is coarse (×2): try 5 % above the fitted crossing, kept only if it meets the goal
        refined = int(math.ceil(1.05 * fitted / 10_000) * 10_000)
        if refined < hit["bounces"]:
            trial = fresh_run(refined, args.orbits)
            print(f"   N = {refined:,d}: max P_stderr {trial['max_stderr']:.5f} "
                  f"({'meets' if trial['max_stderr'] <= goal else 'misses'} the goal)")
            if trial["max_stderr"] <= goal:
                hit = trial
        runs = [hit] + [fresh_run(hit["bounces"], args.orbits) for _ in range(args.repeat - 1)]
        user = [r["user_s"] for r in runs]
        answers[name] = hit
        print(f"   answer N = {hit['bounces']:,d}: user pays {statistics.median(user):.2f} s "
              f"(median of {len(user)} fresh runs, {min(user):.2f}–{max(user):.2f}), of which correlation() "
              f"{statistics.median(r['correlation_s'] for r in runs):.2f} s; compile/load "
              f"{statistics.median(r['compile_s'] for r in runs):.2f} s not included")
    if "1σ" not in answers:
        return 1
    n1 = answers["1σ"]["bounces"]

    seconds, cli_err = fresh_cli(n1, answers["1σ"]["H"], args.orbits)
    print(f"command line at N = {n1:,d}: `coinwall correlation ... --json` {seconds:.2f} s wall clock "
          f"(compile/load included), max P_stderr {cli_err:.5f}")

    for answer in answers.values():
        n = answer["bounces"]
        base = baselines(n, args.orbits, args.repeat)
        print(f"in process, warm, N = {n:,d} (median of {args.repeat}): kernel alone {base['kernel']:.3f} s, "
              f"correlation {base['all cores']:.3f} s (analysis {base['all cores'] - base['kernel']:+.3f} s, "
              f"ratio {base['all cores'] / base['kernel']:.2f}), one core {base['one core']:.3f} s "
              f"(parallel speed-up {base['one core'] / base['all cores']:.2f}x)")

    check = seed_check(n1, args.orbits, args.seeds)
    print(f"error bar check at N = {n1:,d}, {args.seeds} seeds: spread between seeds / reported P_stderr = "
          f"{check['pooled']:.2f} pooled over n = 1…{MAX_LAG} (per lag {check['min']:.2f}–{check['max']:.2f}, "
          f"median {check['median']:.2f}; one lag's ratio scatters by ±{check['expected_scatter']:.2f}); "
          f"max spread {check['max_spread']:.5f}, max reported {check['max_reported']:.5f}")
    typical = n1 * (check["mean_max_reported"] / THRESHOLD) ** 2
    print(f"   max P_stderr at N = {n1:,d} averaged over the seeds: {check['mean_max_reported']:.5f} "
          f"(seed 1: {answers['1σ']['max_stderr']:.5f}); for a typical seed the 1σ goal needs N ≈ {typical:,.0f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
