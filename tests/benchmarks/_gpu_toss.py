"""The toss part of bench_gpu.py: the field kernel on the GPU against all CPU cores, in the same run, with invariants.

Two tables, each a Gaussian hand of launches (:func:`launch_spread`, seeded) followed until decided:

* ``coin``: case:coin's wall (the ellipse with ε = 99), g = 1, e = 0.6, no friction, launched at height 1.2 from
  (v0, ω0) ~ N((2, 5), diag(0.5², 2²)): flights and Newton's impacts only;
* ``egg friction``: the ellipse with ε = 0.3, g = 1, e = 0.3, μ = 0.3 and a rolling resistance of 0.01 κ, launched
  at height 1.5 from N((1.5, 3), diag(0.5², 2²)): most tosses end on the floor, so the contact phases (lift-offs,
  rolling and slipping integrated by Dormand–Prince steps, the resistance) are most of the work, and threads of
  one warp take very different paths.

What is timed: :func:`field_run_many` on each device (the summaries only come back), after a warm call of a few
tosses (the compile); the GPU on T tosses, the CPU on all its numba threads on K, best of two.  ``tosses/s`` and
``events/s`` (an event is a record of the kernel: an impact or a contact event), and ``gpu/cpu`` their ratio.

Invariants (each "ok" or "FAILED"):

* energy: no toss ends with more energy than it was launched with, ``E = ½(θ̇² + η̇² + ξ̇²) + g η`` (restitution
  and friction only take it away; the kernel's arithmetic to 1e-12 of the launch's energy), on both devices;
* floor: every toss ends on or above the floor, ``η ≥ b0 + b(θ) − 10 tol``, the wall evaluated independently (numpy
  on casadi's expression), on both devices;
* failures: no toss ends with a failure status (no convergence, wall not finite, angle overflow, cell budget);
* records: the first R tosses' records on the GPU (its launcher writing every record) against ``field_run`` on the
  CPU, over each toss's first 3 events: the largest absolute difference, ok when ≤ 1e-9 (the same kernel text: in
  the simulator the difference is 0; on a GPU rounding, which 3 events of a toss amplify little);
* fractions: each outcome's share on the GPU (T tosses) against the CPU's (K, other launches of the same hand)
  within 3 combined binomial standard errors.

Output, per table (numbers here are placeholders; ``report["tosses"]`` in the JSON has the same)::

    toss egg friction: FieldTable(...), 75% of the tosses with contact events
      gpu  262144 tosses in 1.2 s: 2.2e+05 tosses/s, 2.6e+06 events/s (11.8 events a toss)
      cpu  16 threads, 16384 tosses in 0.9 s: 1.8e+04 tosses/s, 2.1e+05 events/s
      gpu/cpu 12 (tosses), 12 (events)
      energy: end / launch - 1 at most -0.36 ok; lowest end above the floor 0 tol ok; failures 0 ok
      records of 256 tosses x 3 events, gpu vs cpu: max difference 3e-15 ok; outcome shares gpu vs cpu max |z| 1.1 ok
"""

from __future__ import annotations

import math
import time

import numpy as np

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
FAILURES = (7, 8, 9, 10)  # field.STATUS: no-convergence, wall-not-finite, angle-overflow, cell-budget
RECORDED = 256            # tosses whose records are compared
EVENTS = 3                # their first events


def _tables():
    from coinwall.forward import Wall
    from coinwall.forward.dynamics.floor.field import FieldTable

    coin = FieldTable(Wall.from_expression(ELLIPSE, {"eps": 99.0}), g=1.0, e=0.6)
    egg = FieldTable(Wall.from_expression(ELLIPSE, {"eps": 0.3}), g=1.0, e=0.3, mu=0.3, rolling=0.01)
    return (("coin", coin, 1.2, (2.0, 5.0)), ("egg friction", egg, 1.5, (1.5, 3.0)))


def _states(table, height, mean, n, seed):
    from coinwall.forward.dynamics.floor.hand import launch_spread
    from coinwall.forward.dynamics.floor.toss import launch_states

    v0, omega0 = launch_spread(mean, (0.5, 2.0), n, seed=seed)
    return launch_states(table, v0, omega0, height)


def _timed(table, states, impacts, device, repeats):
    from coinwall.forward.dynamics.floor.field import field_run_many

    field_run_many(table, states[:4], impacts, device=device)  # compile (or load) outside the timing
    best, out = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = field_run_many(table, states, impacts, device=device)
        best = min(best, time.perf_counter() - start)
    return best, out


def _end_checks(table, states, out):
    """(largest energy gain relative to the launch's energy, lowest end height above the floor in tol, failures)."""
    start = table.energy(states[:, 1], states[:, 2], states[:, 3])
    theta, eta, vt, ve = out["final"].T
    end = table.energy(eta, vt, ve, out["v_xi"])
    gain = float(np.max((end - start) / np.maximum(np.abs(start), 1.0)))
    floor = float(np.min((eta - (table.b0 + table.wall(theta))) / table.tol))
    return gain, floor, int(np.isin(out["status"], FAILURES).sum())


def _records(table, states, impacts):
    """The largest difference between the GPU's records and field_run's over the first EVENTS of each toss."""
    from coinwall.forward.dynamics.floor.field import field_run
    from coinwall.forward.dynamics.floor.fieldgpu import run_gpu

    sample = states[:RECORDED]
    got = run_gpu(table, np.column_stack([sample, np.zeros(len(sample))]), EVENTS, False, record=True)
    worst = 0.0
    for k, state in enumerate(sample):
        flight = field_run(table, state, EVENTS)
        if int(got["done"][k]) != len(flight) or not np.array_equal(got["side"][k, :len(flight)], flight.side):
            return math.inf
        for name in ("time", "theta", "eta", "v_theta", "v_eta", "v_xi"):
            worst = max(worst, float(np.max(np.abs(got[name][k, :len(flight)] - getattr(flight, name)), initial=0.0)))
    return worst


def _shares(table, out):
    """Each outcome's share (valleys of one name together) and the undecided's."""
    index = np.where(np.isin(out["status"], (1, 2, 3)), out["valley"], -1)
    shares = {"undecided": float(np.mean(index == -1))}
    for k, name in enumerate(table.landscape.names):
        shares[name] = shares.get(name, 0.0) + float(np.mean(index == k))
    return shares


def _fractions_z(table, gpu_out, cpu_out):
    """The largest |z| between the devices' shares of an outcome (undecided included)."""
    a, b = _shares(table, gpu_out), _shares(table, cpu_out)
    na, nb = gpu_out["status"].size, cpu_out["status"].size
    worst = 0.0
    for name in a:
        p = (a[name] * na + b[name] * nb) / (na + nb)
        if 0.0 < p < 1.0:
            worst = max(worst, abs(a[name] - b[name]) / math.sqrt(p * (1 - p) * (1 / na + 1 / nb)))
    return worst


def measure_tosses(tosses, cpu_tosses, impacts, cores, report):
    """Print and store (``report["tosses"]``) the toss figures of both tables; returns the invariants' verdict."""
    report["tosses"] = {}
    verdict = True
    for name, table, height, mean in _tables():
        states = _states(table, height, mean, tosses, seed=1)
        cpu_states = _states(table, height, mean, cpu_tosses, seed=2)
        gpu_seconds, gpu_out = _timed(table, states, impacts, "gpu", 1)
        cpu_seconds, cpu_out = _timed(table, cpu_states, impacts, "cpu", 2)
        gpu_rate, cpu_rate = tosses / gpu_seconds, cpu_tosses / cpu_seconds
        gpu_events, cpu_events = gpu_out["impacts"].sum() / gpu_seconds, cpu_out["impacts"].sum() / cpu_seconds
        checks = {"gpu": _end_checks(table, states, gpu_out), "cpu": _end_checks(table, cpu_states, cpu_out)}
        energy_ok = all(c[0] <= 1e-12 for c in checks.values())
        floor_ok = all(c[1] >= -10.0 for c in checks.values())
        failures_ok = all(c[2] == 0 for c in checks.values())
        records = _records(table, states, impacts)
        z = _fractions_z(table, gpu_out, cpu_out)
        ok = energy_ok and floor_ok and failures_ok and records <= 1e-9 and z <= 3.0
        verdict = verdict and ok
        contact = float(np.mean(gpu_out["impacts"] > gpu_out["floor_impacts"]))
        print(f"toss {name}: {table!r}, {contact:.0%} of the tosses with contact events")
        print(f"  gpu  {tosses} tosses in {gpu_seconds:.3g} s: {gpu_rate:.3g} tosses/s, {gpu_events:.3g} events/s "
              f"({gpu_out['impacts'].mean():.3g} events a toss)")
        print(f"  cpu  {cores} threads, {cpu_tosses} tosses in {cpu_seconds:.3g} s: {cpu_rate:.3g} tosses/s, "
              f"{cpu_events:.3g} events/s")
        print(f"  gpu/cpu {gpu_rate / cpu_rate:.3g} (tosses), {gpu_events / cpu_events:.3g} (events)")
        print(f"  energy: end / launch - 1 at most {max(c[0] for c in checks.values()):.2g} {_ok(energy_ok)}; lowest end "
              f"above the floor {min(c[1] for c in checks.values()):.3g} tol {_ok(floor_ok)}; failures "
              f"{sum(c[2] for c in checks.values())} {_ok(failures_ok)}")
        print(f"  records of {min(RECORDED, tosses)} tosses x {EVENTS} events, gpu vs cpu: max difference {records:.2g} "
              f"{_ok(records <= 1e-9)}; outcome shares gpu vs cpu max |z| {z:.2f} {_ok(z <= 3.0)}")
        report["tosses"][name] = {"table": repr(table), "tosses": tosses, "cpu_tosses": cpu_tosses,
                                  "gpu_tosses_per_s": gpu_rate, "cpu_tosses_per_s": cpu_rate,
                                  "gpu_events_per_s": float(gpu_events), "cpu_events_per_s": float(cpu_events),
                                  "energy_gain": max(c[0] for c in checks.values()),
                                  "floor_tol": min(c[1] for c in checks.values()),
                                  "failures": sum(c[2] for c in checks.values()), "records_max_difference": records,
                                  "fractions_z": z, "ok": ok}
    return verdict


def _ok(flag):
    return "ok" if flag else "FAILED"
