"""Largest Lyapunov exponent of billiard orbits, and the chaotic fraction of phase space.

Method (Benettin's two-orbit renormalisation).
A reference orbit and a companion started a distance ``d0`` away in the 4-d
state space (θ, η, v_θ, v_η) are followed by the compiled ensemble kernel
(the one :func:`~coinwall.forward.dynamics.billiard.table.ensemble` runs).  Every ``every`` collisions of the
reference orbit the two are compared *at the same time* t*, chosen in the
middle of the reference's next free flight (so neither orbit is at a wall and
the states are smooth functions of the start; the companion's state at t* is
its last collision before t* advanced by free flight).  The separation ``d``
is recorded, ``log(d/d0)`` accumulated, and the companion is put back at
distance ``d0`` along the separation vector (which, after a few intervals,
aligns with the most unstable direction).  Then

    λ_time      = Σ log(d_i/d0) / t_total           (per unit time, units of 1/κ-path length)
    λ_collision = Σ log(d_i/d0) / collisions_total  (per collision, either wall)

The ratio is the mean free time (Abramov).  The component of the separation
along the flow does not grow exponentially, so it does not bias λ.  The
speed is 1 for every state (the kernel normalises it), so perturbations of
the velocity that change the speed are irrelevant.

Finite-time exponents of regular orbits decay like ``log(N)/N``; chaotic ones
converge to λ > 0.  :func:`chaotic_fraction` classifies each orbit as chaotic
when ``λ_collision > threshold`` with the stated default
``threshold = 3·log(N)/N`` for N collisions per orbit (three times the
largest finite-time value a regular orbit with linear separation growth
reaches — linear growth ``d ∝ n`` gives ``log(N)/N``).

Bookkeeping in arrays.  All orbits and their companions go through the kernel together, one call per
renormalisation round on preallocated arrays, and the states at t* are found on whole arrays: a loop
over the orbits in Python cost about 8 times the kernel's own time (docs/performance.md).  The start
states are checked once, as :func:`~coinwall.forward.dynamics.billiard.table.ensemble` checks them; the
states between rounds lie in the middle of a free flight, inside the strip by construction, and need no
check.  Both walls are evaluated in one call where a companion is placed: a casadi call costs about
0.4 ms whatever its length, as much as the kernel spends on 100 orbits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...angles import TWO_PI
from ...display import json_number, json_numbers, safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_memory, check_seed
from ..billiard.table import Billiard, random_states

__all__ = [
    "ChaoticFraction",
    "LyapunovResult",
    "chaotic_fraction",
    "default_threshold",
    "lyapunov",
    "lyapunov_many",
]


def default_threshold(collisions: int) -> float:
    """Chaos threshold per collision ``3·log(N)/N`` for N collisions (module docstring)."""
    return 3.0 * math.log(collisions) / collisions


@dataclass(frozen=True, repr=False)
class LyapunovResult:
    """Largest Lyapunov exponents of one or several orbits.

    Attributes
    ----------
    per_collision : ndarray (m,)
        λ per collision (either wall); NaN for an orbit that stopped early.
    per_time : ndarray (m,)
        λ per unit time (unit speed: per unit path length in the (θ, η) plane).
    collisions : ndarray (m,) of int
        Collisions of the reference orbit actually used.
    time : ndarray (m,)
        Time covered.
    starts : ndarray (m, 4)
    every : int
        Collisions between renormalisations.
    d0 : float
        Renormalised separation.
    notes : tuple of str
        Orbits that stopped early and why.

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import lyapunov
    >>> result = lyapunov(table, [0.0, 2.0, 0.6, 0.8], collisions=200)
    >>> result.per_collision.round(3).tolist(), result.collisions.tolist()
    ([0.621], [200])
    """

    per_collision: np.ndarray
    per_time: np.ndarray
    collisions: np.ndarray
    time: np.ndarray
    starts: np.ndarray
    every: int
    d0: float
    notes: tuple = ()

    def to_dict(self) -> dict:
        """JSON-ready dictionary (lists of floats; non-finite numbers become None)."""
        return {"per_collision": json_numbers(self.per_collision), "per_time": json_numbers(self.per_time),
                "collisions": [int(n) for n in self.collisions], "time": json_numbers(self.time),
                "starts": np.asarray(self.starts, dtype=float).tolist(), "every": self.every, "d0": self.d0,
                "notes": list(self.notes)}

    @safe_repr
    def __repr__(self) -> str:
        m = self.per_collision.size
        if m == 1:
            return (f"LyapunovResult(λ = {self.per_collision[0]:.4g}/collision = {self.per_time[0]:.4g}/time, "
                    f"{int(self.collisions[0])} collisions)")
        return (f"LyapunovResult({m} orbits, λ/collision median {np.nanmedian(self.per_collision):.4g}, "
                f"range {np.nanmin(self.per_collision):.4g}..{np.nanmax(self.per_collision):.4g})")


def _reduce(states):
    """θ reduced to [0, 2π) and its whole turns, as ``billiard._check_states`` does before the kernel."""
    turns = np.floor(states[:, 0] / TWO_PI)
    reduced = states[:, 0] - turns * TWO_PI
    over, under = reduced >= TWO_PI, reduced < 0.0
    reduced[over], turns[over] = reduced[over] - TWO_PI, turns[over] + 1
    reduced[under], turns[under] = reduced[under] + TWO_PI, turns[under] - 1
    return reduced, turns.astype(np.int64)


def _nudge(table, base, delta, d0):
    """``base + d0·delta`` (unit ``delta``), or ``base − d0·delta`` where the former leaves the strip."""
    out = base + d0 * delta
    margin = 100 * table.tol
    # both walls in one evaluation (module docstring); the values are those of table.lower/upper:
    # b0 + b(θ) and H − b0 − b(θ + π)
    m = out.shape[0]
    b = table.wall(np.concatenate([out[:, 0], np.asarray(out[:, 0], dtype=float) + math.pi]))
    lower, upper = table.b0 + b[:m], table.H - table.b0 - b[m:]
    bad = (out[:, 1] <= lower + margin) | (out[:, 1] >= upper - margin)
    out[bad] = base[bad] - d0 * delta[bad]
    return out


def lyapunov_many(table: Billiard, states, collisions: int = 2000, every: int = 10, d0: float = 1e-9, seed=0,
                  workers=None, transient: int = 3, device: str = "cpu") -> LyapunovResult:
    """Largest Lyapunov exponent of each orbit started at ``states`` (Benettin, module docstring).

    Parameters
    ----------
    table : Billiard
    states : array_like (m, 4)
        Start states (inside the strip).
    collisions : int
        Collisions of each reference orbit (rounded up to a multiple of ``every``).
    every : int
        Collisions between renormalisations; the separation must stay small
        (≪ 1) over ``every`` collisions: ``d0·exp(λ·every)`` ≲ 1e-4.
    d0 : float
        Separation after each renormalisation (> 0, ≪ 1; 1e-9 keeps it far
        above rounding (1e-16) and far below the scale of the wall).
    seed : int
        Seed of the random initial separation direction.
    workers : int, optional
        numba threads for the kernel (default: numba's default, all cores); 1 in a scan, where the
        parallelism is one process per core.  Each orbit is followed by the same sequential code, so the
        result does not depend on it.
    transient : int
        Renormalisation intervals run first and not counted, while the
        random initial separation turns into the most unstable direction
        (otherwise the estimate carries an O(1/N) bias from the
        projection of the random start direction).
    device : {"cpu", "gpu"}
        Where the kernel runs each round (:func:`~coinwall.forward.dynamics.billiard.table.ensemble`); the
        bookkeeping between rounds stays on the CPU.  The GPU pays off from about 10^4 orbits.

    Returns
    -------
    LyapunovResult
        ``collisions`` and ``time`` count only the intervals after the transient; ``notes`` name the
        orbits that stopped early and why (their exponents are NaN).

    Raises
    ------
    InvalidArgument
        For states outside the strip, counts that are not positive integers, a ``d0`` that is not small and
        positive, or a run that does not fit in memory.

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import random_states
    >>> from coinwall.forward import lyapunov_many
    >>> result = lyapunov_many(table, random_states(table, 3, seed=1), collisions=100, workers=1)
    >>> result.per_collision.shape, result.collisions.tolist()
    ((3,), [100, 100, 100])
    """
    import numba

    from ..billiard.gpu import check_device
    from ..billiard.kernel import NOTES, compiled
    from ..billiard.table import _check_states, _check_table

    _check_table(table)
    check_device(device)
    transient = check_count("transient", transient, minimum=0)
    collisions = check_count("collisions", collisions)
    every = check_count("every", every)
    if not (isinstance(d0, (int, float)) and math.isfinite(d0) and 0 < d0 < 1e-3):
        raise InvalidArgument(f"`d0` must be a number in (0, 1e-3), got {d0!r}")
    if workers is not None:
        workers = check_count("workers", workers)
    try:
        ref = np.array(states, dtype=float).reshape(-1, 4)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`states` must be numbers of shape (m, 4) [theta, eta, v_theta, v_eta], got "
                              f"shape {np.shape(states)}") from None
    m = ref.shape[0]
    if m == 0:
        raise InvalidArgument("`states` must hold at least one state")
    n = every + 2  # the companion gets two extra collisions so that its collision list always covers t*
    check_memory(f"{m} orbits ((every + 2) collisions of 41 bytes for each orbit and its companion, and 300 bytes "
                 f"of bookkeeping per orbit)", m * (2.0 * 41 * n + 300.0))
    starts = ref.copy()
    ref[:, 2:] /= np.hypot(ref[:, 2], ref[:, 3])[:, None]
    rng = np.random.default_rng(check_seed(seed))
    direction = rng.normal(size=(m, 4))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    comp = _nudge(table, ref, direction, d0)
    # the start states (and their companions) are checked as ensemble() checks them: inside the strip, moving
    # into it from a wall; a start on a wall leaves that wall
    checked = _check_states(table, np.vstack([ref, comp]), "states")
    kernel = compiled(table)
    args = kernel.args(table)
    log_sum, time, used = np.zeros(m), np.zeros(m), np.zeros(m, dtype=np.int64)
    alive = np.ones(m, dtype=bool)
    notes = []
    # the kernel's output arrays, reused every round (2m rows: the references, then their companions)
    out = [np.empty((2 * m, n)) for _ in range(5)] + [np.empty((2 * m, n), dtype=np.int8)]
    done, status, last = np.zeros(2 * m, dtype=np.int64), np.zeros(2 * m, dtype=np.int64), np.empty((2 * m, 2))
    columns = np.arange(n)
    rounds = -(-collisions // every)
    previous = numba.get_num_threads()
    try:
        if workers is not None:
            numba.set_num_threads(min(workers, numba.config.NUMBA_NUM_THREADS))
        for step in range(rounds + transient):
            idx = np.flatnonzero(alive)
            if idx.size == 0:
                break
            k = idx.size
            both = np.vstack([ref[idx], comp[idx]])
            if step == 0:
                unit, speed, leaving, turns = checked
            else:  # mid-flight states: on neither wall
                speed = np.hypot(both[:, 2], both[:, 3])  # the companion's is not exactly 1: time scales with it
                unit = both.copy()
                unit[:, 0], turns = _reduce(both)
                unit[:, 2:] /= speed[:, None]
                leaving = np.full(2 * k, -1, dtype=np.int64)
            rows = [o[:2 * k] for o in out]
            if device == "gpu":
                from ..billiard.gpu import run_into

                run_into(table, unit, turns, leaving, n, rows, done[:2 * k], status[:2 * k], last[:2 * k])
            else:
                kernel.call("_run_many", unit, turns, leaving, n, *args, *rows, done[:2 * k], status[:2 * k],
                            last[:2 * k])
            t_all, th_all, eta_all, vt_all, ve_all = (rows[c] for c in range(5))
            t_all = t_all / speed[:, None]
            vt_all, ve_all = vt_all * speed[:, None], ve_all * speed[:, None]
            ok = (done[:k] >= every + 1) & (done[k:2 * k] >= every + 1)
            for j in np.flatnonzero(~ok):
                why = NOTES.get(int(status[j]), "") or NOTES.get(int(status[k + j]), "") or "stopped early"
                notes.append(f"orbit {idx[j]}: {why}")
            alive[idx[~ok]] = False
            t_star = 0.5 * (t_all[:k, every - 1] + t_all[:k, every])
            t_star2 = np.concatenate([t_star, t_star])
            # the last collision before t* of each orbit (searchsorted side="right" − 1, on valid columns only)
            valid = columns[None, :] < done[:2 * k, None]
            last_k = np.count_nonzero(valid & (t_all <= t_star2[:, None]), axis=1) - 1
            rows_i = np.arange(2 * k)
            safe = np.maximum(last_k, 0)
            # before its first collision an orbit is still in its first flight, from its start state
            p = np.where((last_k >= 0)[:, None],
                         np.column_stack([th_all[rows_i, safe], eta_all[rows_i, safe], vt_all[rows_i, safe],
                                          ve_all[rows_i, safe]]), both)
            dt = np.where(last_k >= 0, t_star2 - t_all[rows_i, safe], t_star2)
            at = np.column_stack([p[:, 0] + p[:, 2] * dt, p[:, 1] + p[:, 3] * dt, p[:, 2], p[:, 3]])
            x, y = at[:k], at[k:]
            delta = y - x
            d = np.linalg.norm(delta, axis=1)
            same = ~(d > 0.0)  # identical orbits (cannot happen unless d0 underflows): restart the direction
            delta[same], d[same] = direction[idx[same]], d0
            good = idx[ok]
            if step >= transient:
                log_sum[good] += np.log(d[ok] / d0)
                time[good] += t_star[ok]
                used[good] += every
            # carry θ reduced mod 2π (never the unwrapped angle, whose precision falls as it grows); the
            # companion is rebuilt from x below, so both keep the same turns and the separation is unchanged
            x[:, 0] -= TWO_PI * np.floor(x[:, 0] / TWO_PI)
            ref[good] = x[ok]
            comp[good] = _nudge(table, x[ok], delta[ok] / d[ok, None], d0)
    finally:
        numba.set_num_threads(previous)
    per_collision = np.where(alive, log_sum / np.maximum(used, 1), np.nan)
    per_time = np.where(alive, log_sum / np.where(time > 0, time, 1.0), np.nan)
    return LyapunovResult(per_collision=per_collision, per_time=per_time, collisions=used, time=time,
                          starts=starts, every=every, d0=float(d0), notes=tuple(notes))


def lyapunov(table: Billiard, state, collisions: int = 2000, every: int = 10, d0: float = 1e-9, seed=0,
             transient: int = 3) -> LyapunovResult:
    """Largest Lyapunov exponent of the orbit started at ``state`` (see :func:`lyapunov_many`).

    Parameters
    ----------
    table : Billiard
    state : array_like (4,)
        The start state ``[theta, eta, v_theta, v_eta]`` (inside the strip).
    collisions, every, d0, seed, transient
        As in :func:`lyapunov_many`.

    Returns
    -------
    LyapunovResult
        One orbit's exponent per collision and per unit time.

    Raises
    ------
    InvalidArgument
        As :func:`lyapunov_many`: a state outside the strip, or counts that are not positive integers.

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import lyapunov
    >>> lyapunov(table, [0.0, 2.0, 0.6, 0.8], collisions=200)
    LyapunovResult(λ = 0.621/collision = 0.146/time, 200 collisions)
    """
    return lyapunov_many(table, np.asarray(state, dtype=float).reshape(1, 4), collisions, every, d0, seed,
                         workers=1, transient=transient)


@dataclass(frozen=True, repr=False)
class ChaoticFraction:
    """Share of phase space (Liouville measure) filled by chaotic orbits, by sampling.

    Attributes
    ----------
    fraction : float
        Fraction of the sampled orbits with ``λ_collision > threshold``.
    stderr : float
        Binomial standard error ``sqrt(f(1−f)/n)`` of ``fraction``.
    regular : int
        Number of orbits classified regular.
    orbits : int
        Number of orbits with a result (orbits that stopped early are left out).
    threshold : float
        Classification threshold on λ per collision.
    collisions : int
        Collisions per orbit.
    exponents : LyapunovResult
        Every orbit's exponent.

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import chaotic_fraction
    >>> result = chaotic_fraction(table, orbits=8, collisions=200, seed=0)
    >>> result.fraction, result.regular, result.orbits
    (0.5, 4, 8)
    """

    fraction: float
    stderr: float
    regular: int
    orbits: int
    threshold: float
    collisions: int
    exponents: LyapunovResult

    @property
    def regular_fraction(self) -> float:
        """``regular / orbits`` (computed from the counts: ``1 − fraction`` rounds, e.g. 1 − 399/400 < 1/400)."""
        return self.regular / self.orbits if self.orbits else float("nan")

    def to_dict(self) -> dict:
        """JSON-ready dictionary (the per-orbit exponents under ``"exponents"``)."""
        return {"fraction": self.fraction, "stderr": self.stderr, "regular": self.regular, "orbits": self.orbits,
                "regular_fraction": json_number(self.regular_fraction), "threshold": self.threshold,
                "collisions": self.collisions, "exponents": self.exponents.to_dict()}

    @safe_repr
    def __repr__(self) -> str:
        return (f"ChaoticFraction({self.fraction:.3f} ± {self.stderr:.3f}: {self.regular} of {self.orbits} orbits "
                f"regular, λ threshold {self.threshold:.3g}/collision over {self.collisions} collisions)")


def chaotic_fraction(table: Billiard, orbits: int = 100, collisions: int = 2000, threshold=None, every: int = 10,
                     seed=0, workers=None, device: str = "cpu") -> ChaoticFraction:
    """Fraction of phase space that is chaotic: classify Liouville-random orbits by their Lyapunov exponent.

    Parameters
    ----------
    table : Billiard
    orbits : int
        Number of orbits sampled with :func:`~coinwall.forward.dynamics.billiard.table.random_states`.
    collisions : int
        Collisions per orbit.
    threshold : float, optional
        An orbit is chaotic when its λ per collision exceeds this; default
        :func:`default_threshold` ``3·log(N)/N``.
    every, seed, workers, device
        As in :func:`lyapunov_many` (``seed`` also seeds the start states).

    Returns
    -------
    ChaoticFraction

    Raises
    ------
    InvalidArgument
        For a threshold that is not a positive number, or counts that are not positive integers.

    Examples
    --------
    Eight Liouville-random orbits of 200 collisions each, classified by their exponent:

    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import chaotic_fraction
    >>> chaotic_fraction(table, orbits=8, collisions=200, seed=0)
    ChaoticFraction(0.500 ± 0.177: 4 of 8 orbits regular, λ threshold 0.0795/collision over 200 collisions)
    """
    orbits = check_count("orbits", orbits)
    collisions = check_count("collisions", collisions)
    if threshold is None:
        threshold = default_threshold(collisions)
    elif not (isinstance(threshold, (int, float)) and math.isfinite(threshold) and threshold > 0):
        raise InvalidArgument(f"`threshold` must be a positive number, got {threshold!r}")
    states = random_states(table, orbits, seed)
    result = lyapunov_many(table, states, collisions, every, seed=seed, workers=workers, device=device)
    lam = result.per_collision[np.isfinite(result.per_collision)]
    n = int(lam.size)
    chaotic = int(np.count_nonzero(lam > threshold))
    fraction = chaotic / n if n else float("nan")
    stderr = math.sqrt(fraction * (1 - fraction) / n) if n else float("nan")
    return ChaoticFraction(fraction=fraction, stderr=stderr, regular=n - chaotic, orbits=n, threshold=float(threshold),
                           collisions=collisions, exponents=result)
