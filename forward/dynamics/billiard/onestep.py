"""The one-step check: from each state of an orbit, the CPU kernel's next collision against another's.

A GPU and the CPU run the same kernel text but round differently (the CUDA compiler fuses ``a·b + c`` into one
rounding, its ``cos``/``sin`` are not the CPU's), and chaos amplifies rounding: whole orbits part after tens of
collisions.  What must hold is agreement *collision by collision*: from the state after collision i, both
devices find the same next collision.  :func:`one_step_check` measures that in two forms:

* ``device="gpu"`` (or ``"cpu"``): the device's next collision from the *same* reported state as the CPU's.
  Both start from identical floats, so every difference is the arithmetic's.
* ``device=None``: the orbit's own next collision (collision i + 1) against the CPU's from collision i.  The
  reported θ is unwrapped (``θ mod 2π + 2π·turns``, rounded), so the CPU starts up to 2 ulp(|θ|) away from the
  state the device held: 4e-12 at |θ| = 6000, an angle the coin's shallow flights reach within 64 collisions.
  This form also sees a skipped collision (the CPU's search stops at the first contact).

What the kernel guarantees, and so the bound each collision is held to.  The kernel returns a contact where the
gap along the flight, ``g(t) = A + B t − b(φ0 + v_θ t)`` (lower wall; the upper one alike), satisfies
``|g| ≤ tol`` (the table's contact tolerance; its finishing steps usually land within rounding of the root,
but ``tol`` is what it promises).  Write ``τ = tol + ρ + |b'|·δ``: ρ = 16 u·max(1, H)·(1 + |b'|) covers the
rounding of g's evaluation (u = 2^-52), and ``|b'|·δ`` the wall's move under a start displaced by δ in θ.  Two
contacts ``t1``, ``t2`` on the same flight, each with ``|g| ≤ τ``, differ by ``|t1 − t2| ≤ 2τ / min|g'|`` over
``[t1, t2]``.  With ``|g'|`` taken at the contact and ``|g''| ≤ 2 v_θ² |b''|`` there, ``min|g'| ≥ |g'|/2``
whenever ``|g'|² ≥ 8 τ |g''|`` (then ``|t1 − t2| ≤ 4τ/|g'|`` keeps ``|g''|·|t1 − t2| ≤ |g'|/2``), so::

    Δt ≤ 4 τ / |g'|,          |g'| = |B − v_θ b'|  (= |v·n|·√(1 + b'²), n the wall's normal)

and the contact's angle moves by ``Δφ ≤ |v_θ| Δt + δ``, its height by ``|v_η| Δt``, the wall's slope there by
``Δs ≤ |b''| Δφ + 16 u (1 + |b'|)`` (the slope's own rounding), and the reflected velocity, ``v' = (I − 2 n nᵀ) v``
with ``n ∝ (−s, 1)``, by ``|Δv'| ≤ 4 |Δn| |v| ≤ 4 Δs``.  Each of the five numbers compared (time of flight, θ,
η, v_θ, v_η) gets that bound plus 4 ulp of its own value (and, for the orbit's own next collision, 2 ulp of the
cumulative time that the flight time is a difference of), relative to ``max(1, |value|)`` as the differences
are.  A collision outside ``|g'|² ≥ 8 τ |g''|`` is a graze, where the contact is not determined to first order:
it is counted (``grazes``) and held to no bound; a next collision on the other wall, or none, fails.  The bound
is the kernel's promise, not its typical accuracy: differences are usually of the order of rounding times the
same ``1/|g'|`` (the ``differences`` and the worst collisions show it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["OneStep", "next_collisions", "one_step_check"]

U = 2.0 ** -52
TWO_PI = 2.0 * math.pi
NAMES = ("time", "theta", "eta", "v_theta", "v_eta")


@dataclass(frozen=True, repr=False)
class OneStep:
    """The outcome of :func:`one_step_check`.

    Attributes
    ----------
    collisions : int
        Collisions compared.
    differences : ndarray (collisions,)
        Per collision, the largest of the five relative differences (time of flight, θ, η, v_θ, v_η, each
        ``|a − b| / max(1, |b|)``); ``inf`` where the next collision is on the other wall or missing.
    ratios : ndarray (collisions,)
        Per collision, the largest difference over its bound (module docstring); 0 for a graze.
    grazes : int
        Collisions outside the first-order regime of the bound (held to none).
    other_wall : int
        Collisions where the two next collisions are on different walls, or one is missing.
    worst : list of dict
        The collisions with the largest differences: where (orbit, collision), the five differences and bounds,
        the wall (side), the contact angle φ, b', b'', the incidence |v·n|, the flight time, |θ| of the start
        and both contacts' residuals ``η − wall(θ)`` evaluated independently (numpy on the wall's expression).
    """

    collisions: int
    differences: np.ndarray
    ratios: np.ndarray
    grazes: int
    other_wall: int
    worst: list

    @property
    def max_difference(self) -> float:
        """The largest relative difference (0 without collisions)."""
        return float(self.differences.max()) if self.collisions else 0.0

    @property
    def max_ratio(self) -> float:
        """The largest difference over its bound (≤ 1: every collision within what the kernel guarantees)."""
        return float(self.ratios.max()) if self.collisions else 0.0

    @property
    def ok(self) -> bool:
        """Every next collision on the same wall and within its bound."""
        return self.other_wall == 0 and self.max_ratio <= 1.0

    def __repr__(self) -> str:
        return (f"OneStep({self.collisions} collisions, max difference {self.max_difference:.3g}, max/bound "
                f"{self.max_ratio:.3g}, grazes {self.grazes}, other wall {self.other_wall})")


def next_collisions(table, states, turns, leaving, device: str = "cpu"):
    """One collision of the billiard kernel from each unit-speed state, on the CPU or the GPU.

    Parameters
    ----------
    table : Billiard
    states : ndarray (m, 4)
        θ in [0, 2π), η, v_θ, v_η with unit speed.
    turns, leaving : ndarray (m,) of int64
        Whole turns of θ, and the wall each state is on (−1: none).
    device : {"cpu", "gpu"}

    Returns
    -------
    ndarray (m, 5), ndarray (m,) of int8, ndarray (m,) of int64
        Time of flight, unwrapped θ, η, v_θ, v_η of the next collision; its wall; 1 where it was found.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics.billiard.table import Billiard
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> nxt, side, found = next_collisions(table, np.array([[1.0, 2.0, 0.6, -0.8]]), np.zeros(1, np.int64),
    ...                                    -np.ones(1, np.int64))
    >>> int(found[0]), int(side[0])
    (1, 0)
    """
    from .kernel import _run_threads, compiled

    m = states.shape[0]
    out = [np.empty((m, 1)) for _ in range(5)] + [np.empty((m, 1), dtype=np.int8)]
    done, status, last = np.zeros(m, dtype=np.int64), np.zeros(m, dtype=np.int64), np.empty((m, 2))
    args = (np.ascontiguousarray(states, dtype=float), np.ascontiguousarray(turns, dtype=np.int64),
            np.ascontiguousarray(leaving, dtype=np.int64), 1)
    if device == "gpu":
        from .gpu import run_into

        run_into(table, *args, out, done, status, last)
    else:
        _run_threads(compiled(table), table, *args, None, out, done, status, last)
    return np.column_stack([o[:, 0] for o in out[:5]]), out[5][:, 0], done


def _bounds(table, start, nxt, side, delta, time_error):
    """Per collision: the five relative bounds (module docstring), |g'|, the graze mask and (φ, b', b'')."""
    theta = nxt[:, 1]
    phi = np.mod(theta, TWO_PI) + np.where(side == 1, math.pi, 0.0)
    _, slope, curve = table.wall.derivatives(phi)
    vt, ve = start[:, 2], start[:, 3]
    B = np.where(side == 1, -ve, ve)
    rate = np.abs(B - vt * slope)
    tau = table.tol + 16 * U * max(1.0, table.H) * (1 + np.abs(slope)) + np.abs(slope) * delta
    g2 = 2.0 * vt * vt * np.abs(curve)
    graze = rate * rate <= 8.0 * tau * g2  # (a flight along a straight wall, rate 0, too)
    dt = 4.0 * tau / np.where(graze, 1.0, rate)
    dphi = np.abs(vt) * dt + delta
    ds = np.abs(curve) * dphi + 16 * U * (1 + np.abs(slope))
    absolute = np.column_stack([dt + time_error, dphi, np.abs(ve) * dt, 4 * ds, 4 * ds])
    bound = absolute / np.maximum(1.0, np.abs(nxt)) + 4 * U
    return bound, rate / np.hypot(1.0, slope), graze, phi, slope, curve


def _residual(table, theta, eta, side):
    """``η − wall(θ)`` towards the strip's inside, the wall evaluated by numpy on its expression."""
    phi = theta + np.where(side == 1, math.pi, 0.0)
    b = table.wall.derivatives(phi)[0]
    return np.where(side == 1, (table.H - table.b0 - b) - eta, eta - (table.b0 + b))


def one_step_check(table, trajectories, device=None, worst: int = 5) -> OneStep:
    """From each collision of ``trajectories``, the CPU kernel's next collision against the orbit's own next one
    (``device=None``) or against ``device``'s next collision from the same state (module docstring).

    Parameters
    ----------
    table : Billiard
    trajectories : list of Trajectory
        Orbits of unit start speed (what :func:`~.table.random_states` draws), computed on any device.
    device : {None, "gpu", "cpu"} or callable
        None: compare with collision i + 1 of each orbit; "gpu"/"cpu": with that device's one collision from
        the state after collision i as the orbit reports it; a callable ``(states, turns, leaving)`` → what
        :func:`next_collisions` returns: with its collisions (another compiled kernel, say).
    worst : int
        How many of the largest differences to describe in :attr:`OneStep.worst`.

    Returns
    -------
    OneStep

    Raises
    ------
    InvalidArgument
        An unknown device, or ``"gpu"`` without a usable GPU.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics.billiard.table import Billiard, ensemble, random_states
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> check = one_step_check(table, ensemble(table, random_states(table, 2, seed=0), 6))
    >>> check.collisions, check.ok, check.max_difference < 1e-12
    (10, True, True)
    """
    from .gpu import check_device

    if isinstance(device, str):
        check_device(device)
    pieces = [t for t in trajectories if len(t) >= 2]
    if not pieces:
        return OneStep(0, np.zeros(0), np.zeros(0), 0, 0, [])
    before = [np.concatenate([getattr(t, f)[:-1] for t in pieces]) for f in ("theta", "eta", "v_theta", "v_eta")]
    turns = np.floor(before[0] / TWO_PI)
    reduced = before[0] - TWO_PI * turns
    over, under = reduced >= TWO_PI, reduced < 0.0  # (the product may round across a multiple of 2π)
    reduced[over], turns[over] = reduced[over] - TWO_PI, turns[over] + 1
    reduced[under], turns[under] = reduced[under] + TWO_PI, turns[under] - 1
    start = np.column_stack([reduced] + before[1:])
    leaving = np.concatenate([t.side[:-1] for t in pieces]).astype(np.int64)
    cpu, cpu_side, cpu_found = next_collisions(table, start, turns.astype(np.int64), leaving, "cpu")
    if device is None:
        other = np.column_stack([np.concatenate([np.diff(t.time) for t in pieces])] + [
            np.concatenate([getattr(t, f)[1:] for t in pieces]) for f in NAMES[1:]])
        other_side = np.concatenate([t.side[1:] for t in pieces])
        other_found = np.ones(start.shape[0], dtype=np.int64)
        delta = 2 * np.spacing(np.abs(before[0]))
        time_error = 2 * np.spacing(np.abs(np.concatenate([t.time[1:] for t in pieces])))
    else:
        step = device if callable(device) else (lambda *a: next_collisions(table, *a, device))
        other, other_side, other_found = step(start, turns.astype(np.int64), leaving)
        delta, time_error = 0.0, 0.0
    with np.errstate(invalid="ignore", over="ignore"):  # (a missing collision's row holds anything: set apart below)
        diff = np.abs(other - cpu) / np.maximum(1.0, np.abs(cpu))
    bound, incidence, graze, phi, slope, curve = _bounds(table, start, cpu, cpu_side, delta, time_error)
    differences = diff.max(axis=1)
    ratios = np.where(graze, 0.0, (diff / bound).max(axis=1))  # (a graze's bound, computed at rate 1, is not used)
    apart = (cpu_found != 1) | (other_found != 1) | (cpu_side != other_side)
    differences[apart], ratios[apart] = np.inf, np.inf
    where = np.concatenate([np.stack([np.full(len(t) - 1, k), np.arange(1, len(t))], axis=1)
                            for k, t in enumerate(pieces)])
    described = []
    top = np.argpartition(differences, -min(worst, differences.size))[-worst:] if worst > 0 else []
    for i in sorted(top, key=lambda i: -differences[i]):
        described.append({
            "orbit": int(where[i, 0]), "collision": int(where[i, 1]),
            "differences": dict(zip(NAMES, diff[i].tolist())), "bounds": dict(zip(NAMES, bound[i].tolist())),
            "side": int(cpu_side[i]), "phi": float(phi[i]), "slope": float(slope[i]), "curvature": float(curve[i]),
            "incidence": float(incidence[i]), "flight": float(cpu[i, 0]), "start_theta": float(abs(before[0][i])),
            "residual_cpu": float(_residual(table, cpu[i, 1], cpu[i, 2], cpu_side[i])),
            "residual_other": float(_residual(table, other[i, 1], other[i, 2], other_side[i])),
            "graze": bool(graze[i]), "other_wall": bool(apart[i])})
    return OneStep(collisions=int(start.shape[0]), differences=differences, ratios=ratios,
                   grazes=int(np.count_nonzero(graze & ~apart)), other_wall=int(np.count_nonzero(apart)),
                   worst=described)
