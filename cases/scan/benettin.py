"""Largest Lyapunov exponents of a whole ensemble with the bookkeeping in arrays (one scan cell's hot loop).

:func:`coinwall.forward.dynamics.lyapunov.lyapunov_many` is Benettin's two-orbit method with a Python loop
over the orbits in every renormalisation round: each round it validates every state again
(:func:`~coinwall.forward.dynamics.billiard.ensemble` checks each one in a Python loop), builds a
:class:`~coinwall.forward.dynamics.billiard.Trajectory` per orbit and finds each orbit's state at t* with
its own ``searchsorted``.  For 100 orbits × 1000 collisions that is ~1 s of Python against ~0.1 s of kernel
(measured in tests/benchmarks/bench_scan.py), the "0.7 s per grid point" measured when scans were first built.

:func:`lyapunov_batch` is the same method, the same arithmetic and the same random numbers, with each
round one call of the compiled ensemble kernel (``_run_many`` of :mod:`coinwall.forward.dynamics.kernel`)
on preallocated arrays and the bookkeeping done on whole arrays: the states between rounds lie in the
middle of a free flight, inside the strip by construction, so they need no checks.  It reproduces
``lyapunov_many`` to rounding (tests/test_scan.py).  It could move to ``forward/dynamics/lyapunov.py``
and replace the loop there.
"""

from __future__ import annotations

import math

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.validation import check_count, check_memory

__all__ = ["lyapunov_batch"]


def _reduce(states):
    """θ reduced to [0, 2π) and its whole turns, as ``billiard._check_states`` does before the kernel."""
    turns = np.floor(states[:, 0] / TWO_PI)
    reduced = states[:, 0] - turns * TWO_PI
    over, under = reduced >= TWO_PI, reduced < 0.0
    reduced[over], turns[over] = reduced[over] - TWO_PI, turns[over] + 1
    reduced[under], turns[under] = reduced[under] + TWO_PI, turns[under] - 1
    return reduced, turns.astype(np.int64)


def _nudge(table, base, delta, d0):
    """``base + d0·delta``, or ``base − d0·delta`` where the former leaves the strip (as in lyapunov.py)."""
    out = base + d0 * delta
    margin = 100 * table.tol
    # both walls in one evaluation: a casadi call costs ~0.4 ms whatever its length, as much as the kernel
    # spends on 100 orbits; the values are those of table.lower/upper (b0 + b(θ), H − b0 − b(θ + π))
    m = out.shape[0]
    b = table.wall(np.concatenate([out[:, 0], np.asarray(out[:, 0], dtype=float) + math.pi]))
    lower, upper = table.b0 + b[:m], table.H - table.b0 - b[m:]
    bad = (out[:, 1] <= lower + margin) | (out[:, 1] >= upper - margin)
    out[bad] = base[bad] - d0 * delta[bad]
    return out


def lyapunov_batch(table, states, collisions: int = 2000, every: int = 10, d0: float = 1e-9, seed=0,
                   transient: int = 3, threads: int | None = 1):
    """λ per collision and per unit time of each orbit started at ``states`` (Benettin, arrays only).

    Parameters
    ----------
    table : Billiard
    states : ndarray (m, 4)
        Start states strictly inside the strip (e.g. from
        :func:`~coinwall.forward.dynamics.billiard.random_states`); not on a wall.
    collisions, every, d0, seed, transient
        As in :func:`coinwall.forward.dynamics.lyapunov.lyapunov_many` (same meaning, same defaults,
        same random separation directions for the same ``seed``).
    threads : int or None
        numba threads for the kernel; 1 in a scan, where the parallelism is one process per core.

    Returns
    -------
    per_collision, per_time : ndarray (m,)
        NaN for an orbit that stopped early (a free flight, a grazing failure).
    collisions_used : ndarray (m,) of int
    """
    import numba

    from coinwall.forward.dynamics.kernel import compiled

    transient = check_count("transient", transient, minimum=0)
    collisions = check_count("collisions", collisions)
    every = check_count("every", every)
    if not (isinstance(d0, (int, float)) and math.isfinite(d0) and 0 < d0 < 1e-3):
        raise InvalidArgument(f"`d0` must be a number in (0, 1e-3), got {d0!r}")
    ref = np.array(states, dtype=float).reshape(-1, 4)
    m = ref.shape[0]
    if m == 0:
        raise InvalidArgument("`states` must hold at least one state")
    n = every + 2  # the companion needs two collisions past t* so its list always covers t*
    check_memory(f"{m} orbits (2 × {n} collisions of 41 bytes, and bookkeeping)", 2.0 * m * (41 * n + 300))
    ref[:, 2:] /= np.hypot(ref[:, 2], ref[:, 3])[:, None]
    rng = np.random.default_rng(seed)
    direction = rng.normal(size=(m, 4))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    comp = _nudge(table, ref, direction, d0)
    kernel = compiled(table)
    args = kernel.args(table)
    log_sum, time, used = np.zeros(m), np.zeros(m), np.zeros(m, dtype=np.int64)
    alive = np.ones(m, dtype=bool)
    # the kernel's output arrays, reused every round (2m rows: the references, then their companions)
    out = [np.empty((2 * m, n)) for _ in range(5)] + [np.empty((2 * m, n), dtype=np.int8)]
    done, status, last = np.zeros(2 * m, dtype=np.int64), np.zeros(2 * m, dtype=np.int64), np.empty((2 * m, 2))
    columns = np.arange(n)
    rounds = -(-collisions // every)
    previous = numba.get_num_threads()
    try:
        if threads is not None:
            numba.set_num_threads(min(int(threads), numba.config.NUMBA_NUM_THREADS))
        for step in range(rounds + transient):
            idx = np.flatnonzero(alive)
            if idx.size == 0:
                break
            k = idx.size
            both = np.vstack([ref[idx], comp[idx]])
            speed = np.hypot(both[:, 2], both[:, 3])  # the companion's is not exactly 1: time scales with it
            unit = both.copy()
            unit[:, 0], turns = _reduce(both)
            unit[:, 2:] /= speed[:, None]
            leaving = np.full(2 * k, -1, dtype=np.int64)  # mid-flight starts: on neither wall
            rows = [o[:2 * k] for o in out]
            kernel.call("_run_many", unit, turns, leaving, n, *args, *rows, done[:2 * k], status[:2 * k],
                        last[:2 * k])
            t_all, th_all, eta_all, vt_all, ve_all = (rows[c] for c in range(5))
            t_all = t_all / speed[:, None]
            vt_all, ve_all = vt_all * speed[:, None], ve_all * speed[:, None]
            ok = (done[:k] >= every + 1) & (done[k:2 * k] >= every + 1)
            alive[idx[~ok]] = False
            t_star = 0.5 * (t_all[:k, every - 1] + t_all[:k, every])
            t_star2 = np.concatenate([t_star, t_star])
            # the last collision before t* of each orbit (searchsorted side="right" − 1, on valid columns only)
            valid = columns[None, :] < done[:2 * k, None]
            last_k = np.count_nonzero(valid & (t_all <= t_star2[:, None]), axis=1) - 1
            rows_i = np.arange(2 * k)
            safe = np.maximum(last_k, 0)
            start_state = both  # before the first collision the orbit is still in its first flight
            p = np.where((last_k >= 0)[:, None],
                         np.column_stack([th_all[rows_i, safe], eta_all[rows_i, safe], vt_all[rows_i, safe],
                                          ve_all[rows_i, safe]]), start_state)
            dt = np.where(last_k >= 0, t_star2 - t_all[rows_i, safe], t_star2)
            at = np.column_stack([p[:, 0] + p[:, 2] * dt, p[:, 1] + p[:, 3] * dt, p[:, 2], p[:, 3]])
            x, y = at[:k], at[k:]
            delta = y - x
            d = np.linalg.norm(delta, axis=1)
            same = ~(d > 0.0)  # identical orbits (d0 underflowed): restart along the initial direction
            delta[same], d[same] = direction[idx[same]], d0
            good = idx[ok]
            if step >= transient:
                log_sum[good] += np.log(d[ok] / d0)
                time[good] += t_star[ok]
                used[good] += every
            # θ carried reduced mod 2π; the companion is rebuilt from x, so the separation is unchanged
            x[:, 0] -= TWO_PI * np.floor(x[:, 0] / TWO_PI)
            ref[good] = x[ok]
            comp[good] = _nudge(table, x[ok], delta[ok] / d[ok, None], d0)
    finally:
        numba.set_num_threads(previous)
    per_collision = np.where(alive, log_sum / np.maximum(used, 1), np.nan)
    per_time = np.where(alive, log_sum / np.where(time > 0, time, 1.0), np.nan)
    return per_collision, per_time, used
