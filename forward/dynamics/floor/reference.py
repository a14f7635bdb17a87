"""The plain-numpy twin of the field kernel: the frictionless flight, impact and settling, simple and slow.

:func:`reference_run` finds each impact by conservative advancement with a global Lipschitz bound of the wall
and polishes it with Brent's method; it shares no code with the compiled kernel (:mod:`._field_kernel`) and is
its yardstick (``tests/forward/dynamics/floor/test_toss.py``).  It knows Newton's frictionless impacts only:
friction is checked against the direct rigid-body simulation and closed forms instead.
"""

from __future__ import annotations

import math

import numpy as np

from ...angles import TWO_PI

__all__ = ["reference_run"]

_REFERENCE_MAX_STEPS = 400_000


def reference_run(table, state, leaving: int, impacts: int, catch: bool = False):
    """The plain-numpy twin of the kernel: conservative advancement with a global Lipschitz bound.

    On ``[t, t + τ]`` the gap ``f = A + B t − ½ Q t² − b(φ0 + ω t)`` has ``f' ≥ −Λ − |Q| τ`` with
    ``Λ = |B − Q t| + |ω| max|b'|``, so ``f(t + τ) ≥ f(t) − Λ τ − ½ |Q| τ²``: the positive root of that
    bound is a step that cannot pass a root.  The first step off the wall just left uses
    ``f'' ≥ −(Q + ω² max|b''|)`` and never crosses a kink.  It stops at ``f ≤ tol`` and polishes with
    Brent's method when a sign change is within 1e-8.  Slow (linear convergence, a casadi call per step).
    Returns ``(rows, status, valley, floor impacts)`` with rows ``(time, θ, η, θ̇, η̇, side)``.
    """
    from scipy.optimize import brentq

    from ..billiard.reference import sample_bounds

    wall = table.wall
    lip, curv, kinks = sample_bounds(wall)
    tol = table.tol
    g, e, b0 = table.g, table.e, table.b0
    H = table.H
    th, eta, vt, ve = (float(x) for x in state)
    rows = []
    clock = 0.0
    floor_hits = 0
    status = 0
    valleys = table.landscape
    walls = (0, 1) if table.ceiling else (0,)

    def gaps(t):
        phis = np.array([th + vt * t, th + math.pi + vt * t])
        b, d1, _ = wall.derivatives(phis)
        h = eta + ve * t - 0.5 * g * t * t
        out = [h - b0 - b[0]]
        if table.ceiling:
            out.append(H - b0 - b[1] - h)
        return np.array(out), d1

    for _ in range(impacts):
        t = 0.0
        hit = -1
        for step in range(_REFERENCE_MAX_STEPS):
            gp, d1 = gaps(t)
            rate = abs(ve - g * t) + abs(vt) * lip
            if step == 0 and leaving >= 0:
                q = g if leaving == 0 else -g
                g1 = (ve - vt * d1[0]) if leaving == 0 else (-ve - vt * d1[1])
                K = q + vt * vt * curv
                if K > 0:
                    tau = 2.0 * g1 / K
                elif g1 > 0:
                    tau = math.inf
                else:
                    tau = 0.0
                if kinks.size and vt != 0:
                    phi = th + leaving * math.pi
                    ahead = ((kinks - phi) * np.sign(vt)) % TWO_PI
                    ahead = ahead[ahead > 1e-12]
                    if ahead.size:
                        tau = min(tau, float(ahead.min()) / abs(vt))
                if len(walls) == 2:
                    other = gp[1 - leaving]
                    tau = min(tau, 2 * other / (rate + math.sqrt(rate * rate + 2 * g * other)))
                if not math.isfinite(tau):
                    break
                t += tau
                continue
            k = int(np.argmin(gp))
            if gp[k] <= tol:
                hit = k
                break
            f = float(gp[k]) if len(walls) == 1 else float(gp.min())
            t += 2.0 * f / (rate + math.sqrt(rate * rate + 2.0 * g * f))
        if hit < 0:
            status = 6 if step < _REFERENCE_MAX_STEPS - 1 else 7
            break

        def gap(s, k=hit):
            return float(gaps(s)[0][k])

        if gap(t) > 0.0:
            for width in (1e-12, 1e-10, 1e-8):
                if gap(t + width) < 0.0:
                    t = brentq(gap, t, t + width, xtol=1e-16, rtol=1e-15, maxiter=200)
                    break
        _, d1 = gaps(t)
        th, eta, ve = th + vt * t, eta + ve * t - 0.5 * g * t * t, ve - g * t
        clock += t
        s = float(d1[0]) if hit == 0 else -float(d1[1])
        fimp = (1.0 + e) * (ve - s * vt) / (1.0 + s * s)
        vt, ve = vt + fimp * s, ve - fimp
        rows.append((clock, th, eta, vt, ve, hit))
        leaving = hit
        if hit == 0:
            floor_hits += 1
            if catch:
                status = 2
                break
            if g > 0:
                rest = (ve - vt * s) < table.chatter
                if rest:
                    fimp = (ve - s * vt) / (1.0 + s * s)
                    vt, ve = vt + fimp * s, ve - fimp
                level = eta - b0 + 0.5 * (vt * vt + ve * ve) / g
                if level < valleys.barriers[int(valleys.valley(th))]:
                    status = 3 if rest else 1
                    break
                if rest:
                    status = 4
                    break
    return rows, status, int(valleys.valley(th)), floor_hits
