"""Benettin's method the straightforward way, as a second method for ``lyapunov_many``.

One Python loop over the orbits in every renormalisation round, built on the public API only: every
round :func:`~coinwall.forward.dynamics.billiard.table.ensemble` follows each orbit and its companion (checking
every state), and each orbit's state at t* is found from its own :class:`Trajectory` with
``searchsorted``.  This was the library's implementation before the bookkeeping moved into arrays; it
stays here so that the array version is compared with an independent loop (tests/cases/scan/test_scan.py and
tests/benchmarks/bench_scan.py, which times both).
"""

import math

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.dynamics.billiard.table import ensemble

__all__ = ["lyapunov_loop"]


def _state_at(traj, t):
    """State of an orbit at time t from its collision list (free flight after the last collision before t)."""
    k = int(np.searchsorted(traj.time, t, side="right")) - 1
    if k < 0:
        p, dt = traj.start, t
    else:
        p = np.array([traj.theta[k], traj.eta[k], traj.v_theta[k], traj.v_eta[k]])
        dt = t - traj.time[k]
    return np.array([p[0] + p[2] * dt, p[1] + p[3] * dt, p[2], p[3]])


def _nudge(table, base, delta, d0):
    """``base + d0·delta`` (unit ``delta``), or ``base − d0·delta`` when the former leaves the strip."""
    out = base + d0 * delta
    margin = 100 * table.tol
    bad = (out[:, 1] <= table.lower(out[:, 0]) + margin) | (out[:, 1] >= table.upper(out[:, 0]) - margin)
    out[bad] = base[bad] - d0 * delta[bad]
    return out


def lyapunov_loop(table, states, collisions=2000, every=10, d0=1e-9, seed=0, workers=None, transient=3):
    """(per_collision, per_time, collisions used, time, notes) of each orbit, as ``lyapunov_many`` defines them."""
    ref = np.array(states, dtype=float).reshape(-1, 4)
    ref[:, 2:] /= np.hypot(ref[:, 2], ref[:, 3])[:, None]
    m = ref.shape[0]
    rng = np.random.default_rng(seed)
    direction = rng.normal(size=(m, 4))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    comp = _nudge(table, ref, direction, d0)
    log_sum, time, used = np.zeros(m), np.zeros(m), np.zeros(m, dtype=np.int64)
    alive = np.ones(m, dtype=bool)
    notes = []
    for step in range(-(-collisions // every) + transient):
        idx = np.flatnonzero(alive)
        if idx.size == 0:
            break
        trajs = ensemble(table, np.vstack([ref[idx], comp[idx]]), every + 2, workers=workers)
        xs, deltas, rows = [], [], []
        for j, i in enumerate(idx):
            r, c = trajs[j], trajs[j + idx.size]
            if len(r) < every + 1 or len(c) < every + 1:
                alive[i] = False
                notes.append(f"orbit {i}: {r.note or c.note or 'stopped early'}")
                continue
            t_star = 0.5 * (r.time[every - 1] + r.time[every])
            x, y = _state_at(r, t_star), _state_at(c, t_star)
            delta = y - x
            d = float(np.linalg.norm(delta))
            if not d > 0.0:
                delta, d = direction[i], d0
            if step >= transient:
                log_sum[i] += math.log(d / d0)
                time[i] += t_star
                used[i] += every
            x[0] -= TWO_PI * math.floor(x[0] / TWO_PI)
            ref[i] = x
            xs.append(x)
            deltas.append(delta / d)
            rows.append(i)
        if rows:
            comp[rows] = _nudge(table, np.array(xs), np.array(deltas), d0)
    per_collision = np.where(alive, log_sum / np.maximum(used, 1), np.nan)
    per_time = np.where(alive, log_sum / np.where(time > 0, time, 1.0), np.nan)
    return per_collision, per_time, used, time, tuple(notes)
