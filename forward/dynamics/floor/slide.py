"""A body sliding on a smooth frictionless floor (μ = 0), followed until it lifts off again.

Without friction a toss whose bounces die out above its valley's barrier slides on the floor with its energy
kept (the kernel's status ``slides``).  :func:`slide` follows it along the floor curve (an ODE, scipy's DOP853)
until the floor's push falls to zero and it lifts off; :func:`settle_many` sends the tosses that lift off back
into the compiled kernel until they settle.  With friction (μ > 0) the kernel follows the contact phases itself
(:mod:`._contact_kernel`) and none of this is needed.
"""

from __future__ import annotations

import math

import numpy as np

from .field import FieldTable, field_run_many

__all__ = ["settle_many", "slide"]

_SLIDES_MAX = 20


def slide(table: FieldTable, state, duration=None):
    """Follow the body sliding on a smooth frictionless floor from ``state`` (on the floor, no normal velocity)
    until it lifts off; return the first state in the air after lift-off, or ``None`` if it slides on.

    On the floor ``η = B(θ) = b0 + b(θ)`` the motion is one-dimensional:
    ``(1 + B'²) θ̈ + B' B'' θ̇² + g B' = 0`` (energy ``½(1 + B'²)θ̇² + g B`` is conserved; no friction, no
    loss), with the contact force ``λ = (g + B'' θ̇²)/(1 + B'²)`` along the normal.  It lifts off where λ
    falls to zero (B'' < 0: over a convex part of the wall, e.g. the coin's edge); there the gap opens only
    cubically, so the free flight is followed (in closed form) until the gap is 10⁴ contact tolerances, with
    the gap checked positive on 32 points of the way.  ``duration`` (default 30·√(max(1, scale)/g)) bounds the
    time on the floor; ``None`` is returned when it does not lift off in that time (it rocks on the floor for
    ever in a frictionless world), or when the wall has corners (a sliding body meeting a corner needs an
    impact model this function does not have).
    """
    from scipy.integrate import solve_ivp

    if table.wall.kinks or table.g <= 0:
        return None
    g, b0, wall = table.g, table.b0, table.wall
    scale = max(1.0, wall.scale)
    T = duration if duration is not None else 30.0 * math.sqrt(scale / g)

    from ..billiard.wallcode import python_wall

    d = python_wall(wall, order=2)  # the generated plain-Python b, b', b'' of one angle (no casadi call per step)

    def rhs(_t, y):
        _, d1, d2 = d(y[0])
        return [y[1], -d1 * (g + d2 * y[1] ** 2) / (1.0 + d1 * d1)]

    def lift(_t, y):
        return g + d(y[0])[2] * y[1] ** 2

    lift.terminal, lift.direction = True, -1
    th0, w0 = float(state[0]), float(state[2])
    if lift(0.0, [th0, w0]) > 0:
        sol = solve_ivp(rhs, (0.0, T), [th0, w0], method="DOP853", rtol=1e-11, atol=1e-12, events=lift)
        if sol.status != 1:
            return None
        th0, w0 = (float(x) for x in sol.y_events[0][0])
    b, d1, _ = d(th0)
    eta0, v0 = b0 + b, d1 * w0
    tol = table.tol
    dt = 1e-9 * math.sqrt(scale / g)

    def gap(s):
        return eta0 + v0 * s - 0.5 * g * s * s - b0 - float(wall(np.array([th0 + w0 * s]))[0])

    for _ in range(200):
        if gap(dt) > 1e4 * tol:
            break
        dt *= 1.5
    else:
        return None
    if min(gap(dt * k / 32) for k in range(1, 33)) <= 0:
        return None
    return np.array([th0 + w0 * dt, eta0 + v0 * dt - 0.5 * g * dt * dt, w0, v0 - g * dt])


def settle_many(table: FieldTable, states, impacts: int, catch: bool = False, workers=None, follow_slides=True,
                device="cpu"):
    """:func:`field_run_many`, with orbits that come to slide on the floor above their barrier (status 4)
    followed on the floor (:func:`slide`) and back into the air until they settle, up to 20 times each.

    Returns the dict of :func:`field_run_many` plus ``slides`` (how often each orbit slid).  An orbit still
    sliding at the end keeps status 4 (no outcome).  ``follow_slides=False`` skips the sliding (it is
    Python, about 50 ms per slide: the cost of a basin map with many sliding tosses).  ``device``: where the
    flights run (:func:`field_run_many`; the slides are followed on the CPU).
    """
    out = field_run_many(table, states, impacts, catch=catch, workers=workers, device=device)
    out["slides"] = np.zeros(out["status"].size, dtype=np.int64)
    if catch or not follow_slides:
        return out
    stuck = np.zeros(out["status"].size, dtype=bool)  # slid without lifting off: slides for ever
    for _ in range(_SLIDES_MAX):
        todo = np.flatnonzero((out["status"] == 4) & ~stuck)
        if todo.size == 0:
            break
        resumed, where = [], []
        for k in todo:
            air = slide(table, out["final"][k])
            if air is not None:
                resumed.append(air)
                where.append(k)
            else:
                stuck[k] = True
        if not where:
            break
        where = np.array(where)
        left = np.maximum(impacts - out["impacts"][where], 1)
        more = field_run_many(table, np.array(resumed), int(left.max()), workers=workers, device=device)
        out["slides"][where] += 1
        for name in ("status", "valley", "final"):
            out[name][where] = more[name]
        out["impacts"][where] += more["impacts"]
        out["floor_impacts"][where] += more["floor_impacts"]
        out["time"][where] = np.nan  # (the time on the floor is not tracked)
    return out
