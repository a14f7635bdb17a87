"""The reference stepper (``method="reference"``): plain numpy, slow, and the yardstick of the kernel.

It is deliberately simple and uses only :meth:`Wall.derivatives`: conservative advancement with the
*global* Lipschitz bound ``|g'| ≤ |v_η| + |v_θ| max|b'|`` (steps ``g/Λ``), stopping when the gap is
below ``tol``; the first step away from a wall uses the global bound on |b''| of the smooth pieces
(and never crosses a kink).  It is slow (linear convergence, a casadi call per step) and is what the
kernel is tested against.
"""

from __future__ import annotations

import math

import numpy as np

from ...angles import TWO_PI
from ...wall import Wall

__all__ = ["reference_run", "sample_bounds"]

_REFERENCE_MAX_STEPS = 200_000


def sample_bounds(wall: Wall, points: int = 8192):
    """max|b'| and max|b''| of the smooth pieces, from samples with a margin (for the reference stepper)."""
    theta = (np.arange(points) + 0.5) * (TWO_PI / points)
    _, d1, d2 = wall.derivatives(theta)
    kinks = np.array([k.angle for k in wall.kinks])
    if kinks.size:
        # drop samples next to a kink: there the sampled b'' sees the kink, not the smooth piece
        dist = np.abs((theta[:, None] - kinks[None, :] + math.pi) % TWO_PI - math.pi).min(axis=1)
        keep = dist > 2 * TWO_PI / points
        d2 = d2[keep]
        d1max = max(float(np.max(np.abs(d1))), max(max(abs(k.slope_left), abs(k.slope_right)) for k in wall.kinks))
    else:
        d1max = float(np.max(np.abs(d1)))
    d1max = d1max * 1.01 + float(np.max(np.abs(np.diff(d1)))) + 1e-12
    d2max = float(np.max(np.abs(d2))) * 1.01 + float(np.max(np.abs(np.diff(d2)))) + 1e-12
    return d1max, d2max, kinks


def _polish(table, th, eta, vt, ve, side, t):
    """Brent's method on the exact wall from a point with gap ≤ tol, if a sign change is near; else ``t``."""
    from scipy.optimize import brentq

    def gap(s):
        if side == 0:
            return eta + ve * s - table.lower(th + vt * s)
        return table.upper(th + vt * s) - eta - ve * s

    g0 = gap(t)
    if g0 <= 0.0:
        return t
    for width in (1e-12, 1e-10, 1e-8):
        if gap(t + width) < 0.0:
            return brentq(gap, t, t + width, xtol=1e-16, rtol=1e-15, maxiter=200)
    return t  # a graze below tol without a crossing: the contact is where the gap is smallest, to tol


def reference_run(table, state, leaving: int, collisions: int):
    """One orbit of unit speed from ``state`` (``leaving``: the wall it starts on, -1 for none).

    Returns the rows ``(time, θ, η, v_θ, v_η, side)`` of the collisions found and a note that is
    empty unless the stepper stopped early.
    """
    wall = table.wall
    lip, curv, kinks = sample_bounds(wall)
    tol = table.tol
    th, eta, vt, ve = (float(x) for x in state)
    rows = []
    note = ""
    clock = 0.0
    for _ in range(collisions):
        lam = abs(ve) + abs(vt) * lip
        t = 0.0
        hit = -1
        for step in range(_REFERENCE_MAX_STEPS):
            b, d1, _ = wall.derivatives(np.array([th + vt * t, th + math.pi + vt * t]))
            g = np.array([eta + ve * t - table.b0 - b[0], table.H - table.b0 - b[1] - eta - ve * t])
            if step == 0 and leaving >= 0:
                # on the wall just left: g = 0, g' > 0; a second-order step that does not cross a kink
                g1 = (ve - vt * d1[0]) if leaving == 0 else (-ve - vt * d1[1])
                tau = 2.0 * g1 / (vt * vt * curv) if vt != 0 else math.inf
                if kinks.size and vt != 0:
                    phi = th + leaving * math.pi
                    ahead = ((kinks - phi) * np.sign(vt)) % TWO_PI
                    ahead = ahead[ahead > 0]
                    if ahead.size:
                        tau = min(tau, float(ahead.min()) / abs(vt))
                other = 1 - leaving
                tau = min(tau, g[other] / lam)
                t += tau
                continue
            k = int(np.argmin(g))
            if g[k] <= tol:
                hit = k
                t = _polish(table, th, eta, vt, ve, k, t)
                b, d1, _ = wall.derivatives(np.array([th + vt * t, th + math.pi + vt * t]))
                break
            t += float(g[k]) / lam
        else:
            note = f"reference stepper did not converge within {_REFERENCE_MAX_STEPS} steps"
            break
        th, eta = th + vt * t, eta + ve * t
        slope = float(d1[0]) if hit == 0 else -float(d1[1])
        dot = ve - slope * vt
        norm = 1.0 + slope * slope
        vt, ve = vt + 2.0 * dot * slope / norm, ve - 2.0 * dot / norm
        speed = math.hypot(vt, ve)
        vt, ve = vt / speed, ve / speed
        clock += t
        rows.append((clock, th, eta, vt, ve, hit))
        leaving = hit
    return rows, note
