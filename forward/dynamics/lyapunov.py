"""Largest Lyapunov exponent of billiard orbits, and the chaotic fraction of phase space.

Method (Benettin's two-orbit renormalisation, using only the public kernel API).
A reference orbit and a companion started a distance ``d0`` away in the 4-d
state space (θ, η, v_θ, v_η) are followed with
:func:`~coinwall.forward.dynamics.billiard.ensemble`.  Every ``every`` collisions of the
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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..angles import TWO_PI
from ..display import safe_repr
from ..errors import InvalidArgument
from ..validation import check_count, check_memory
from .billiard import Billiard, ensemble, random_states

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


def _numbers(values) -> list:
    """Floats for JSON: nan and ±inf become None."""
    return [float(v) if math.isfinite(v) else None for v in np.asarray(values, dtype=float).ravel()]


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
        return {"per_collision": _numbers(self.per_collision), "per_time": _numbers(self.per_time),
                "collisions": [int(n) for n in self.collisions], "time": _numbers(self.time),
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


def _state_at(traj_time, theta, eta, vt, ve, start, t):
    """State of an orbit at time t from its collision list (free flight after the last collision before t)."""
    k = int(np.searchsorted(traj_time, t, side="right")) - 1
    if k < 0:
        p = start
        dt = t
    else:
        p = np.array([theta[k], eta[k], vt[k], ve[k]])
        dt = t - traj_time[k]
    return np.array([p[0] + p[2] * dt, p[1] + p[3] * dt, p[2], p[3]])


def _nudge(table, base, delta, d0):
    """``base + d0·delta`` (unit ``delta``), or ``base − d0·delta`` when the former leaves the strip."""
    out = base + d0 * delta
    margin = 100 * table.tol
    bad = (out[:, 1] <= table.lower(out[:, 0]) + margin) | (out[:, 1] >= table.upper(out[:, 0]) - margin)
    out[bad] = base[bad] - d0 * delta[bad]
    return out


def lyapunov_many(table: Billiard, states, collisions: int = 2000, every: int = 10, d0: float = 1e-9, seed=0,
                  workers=None, transient: int = 3) -> LyapunovResult:
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
        Threads for :func:`~coinwall.forward.dynamics.billiard.ensemble`.
    transient : int
        Renormalisation intervals run first and not counted, while the
        random initial separation turns into the most unstable direction
        (otherwise the estimate carries an O(1/N) bias from the
        projection of the random start direction).

    Returns
    -------
    LyapunovResult
        ``collisions`` and ``time`` count only the intervals after the transient.
    """
    transient = check_count("transient", transient, minimum=0)
    collisions = check_count("collisions", collisions)
    every = check_count("every", every)
    if not (isinstance(d0, (int, float)) and math.isfinite(d0) and 0 < d0 < 1e-3):
        raise InvalidArgument(f"`d0` must be a number in (0, 1e-3), got {d0!r}")
    ref = np.array(states, dtype=float).reshape(-1, 4)
    if ref.shape[0] == 0:
        raise InvalidArgument("`states` must hold at least one state")
    ref[:, 2:] /= np.hypot(ref[:, 2], ref[:, 3])[:, None]
    m = ref.shape[0]
    check_memory(f"{m} orbits ((every + 2) collisions of 41 bytes for each orbit and its companion, and 300 bytes "
                 f"of bookkeeping per orbit)", m * (2.0 * 41 * (every + 2) + 300.0))
    rng = np.random.default_rng(seed)
    direction = rng.normal(size=(m, 4))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    comp = _nudge(table, ref, direction, d0)
    log_sum = np.zeros(m)
    time = np.zeros(m)
    used = np.zeros(m, dtype=np.int64)
    alive = np.ones(m, dtype=bool)
    notes = []
    rounds = -(-collisions // every)
    for step in range(rounds + int(transient)):
        counted = step >= transient
        idx = np.flatnonzero(alive)
        if idx.size == 0:
            break
        # the companion gets two extra collisions so that its collision list always covers t*
        trajs = ensemble(table, np.vstack([ref[idx], comp[idx]]), every + 2, workers=workers)
        xs, deltas, rows = [], [], []
        for j, i in enumerate(idx):
            r, c = trajs[j], trajs[j + idx.size]
            if len(r) < every + 1 or len(c) < every + 1:
                alive[i] = False
                notes.append(f"orbit {i}: {r.note or c.note or 'stopped early'}")
                continue
            t_star = 0.5 * (r.time[every - 1] + r.time[every])
            x = _state_at(r.time, r.theta, r.eta, r.v_theta, r.v_eta, r.start, t_star)
            y = _state_at(c.time, c.theta, c.eta, c.v_theta, c.v_eta, c.start, t_star)
            delta = y - x
            d = float(np.linalg.norm(delta))
            if not d > 0.0:  # identical orbits (cannot happen unless d0 underflows): restart the direction
                delta, d = direction[i], d0
            if counted:
                log_sum[i] += math.log(d / d0)
                time[i] += t_star
                used[i] += every
            # carry θ reduced mod 2π (never the unwrapped angle, whose precision falls as it grows); the
            # companion is rebuilt from x below, so both keep the same turns and the separation is unchanged
            x[0] -= TWO_PI * math.floor(x[0] / TWO_PI)
            ref[i] = x
            xs.append(x)
            deltas.append(delta / d)
            rows.append(i)
        if rows:
            comp[rows] = _nudge(table, np.array(xs), np.array(deltas), d0)
    per_collision = np.where(alive, log_sum / np.maximum(used, 1), np.nan)
    per_time = np.where(alive, log_sum / np.where(time > 0, time, 1.0), np.nan)
    return LyapunovResult(per_collision=per_collision, per_time=per_time, collisions=used, time=time,
                          starts=np.array(states, dtype=float).reshape(-1, 4), every=every, d0=float(d0),
                          notes=tuple(notes))


def lyapunov(table: Billiard, state, collisions: int = 2000, every: int = 10, d0: float = 1e-9, seed=0,
             transient: int = 3) -> LyapunovResult:
    """Largest Lyapunov exponent of the orbit started at ``state`` (see :func:`lyapunov_many`)."""
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
                "regular_fraction": _numbers([self.regular_fraction])[0], "threshold": self.threshold,
                "collisions": self.collisions, "exponents": self.exponents.to_dict()}

    @safe_repr
    def __repr__(self) -> str:
        return (f"ChaoticFraction({self.fraction:.3f} ± {self.stderr:.3f}: {self.regular} of {self.orbits} orbits "
                f"regular, λ threshold {self.threshold:.3g}/collision over {self.collisions} collisions)")


def chaotic_fraction(table: Billiard, orbits: int = 100, collisions: int = 2000, threshold=None, every: int = 10,
                     seed=0, workers=None) -> ChaoticFraction:
    """Fraction of phase space that is chaotic: classify Liouville-random orbits by their Lyapunov exponent.

    Parameters
    ----------
    table : Billiard
    orbits : int
        Number of orbits sampled with :func:`~coinwall.forward.dynamics.billiard.random_states`.
    collisions : int
        Collisions per orbit.
    threshold : float, optional
        An orbit is chaotic when its λ per collision exceeds this; default
        :func:`default_threshold` ``3·log(N)/N``.
    every, seed, workers
        As in :func:`lyapunov_many` (``seed`` also seeds the start states).

    Returns
    -------
    ChaoticFraction
    """
    orbits = check_count("orbits", orbits)
    collisions = check_count("collisions", collisions)
    if threshold is None:
        threshold = default_threshold(collisions)
    elif not (isinstance(threshold, (int, float)) and math.isfinite(threshold) and threshold > 0):
        raise InvalidArgument(f"`threshold` must be a positive number, got {threshold!r}")
    states = random_states(table, orbits, seed)
    result = lyapunov_many(table, states, collisions, every, seed=seed, workers=workers)
    lam = result.per_collision[np.isfinite(result.per_collision)]
    n = int(lam.size)
    chaotic = int(np.count_nonzero(lam > threshold))
    fraction = chaotic / n if n else float("nan")
    stderr = math.sqrt(fraction * (1 - fraction) / n) if n else float("nan")
    return ChaoticFraction(fraction=fraction, stderr=stderr, regular=n - chaotic, orbits=n, threshold=float(threshold),
                           collisions=collisions, exponents=result)
