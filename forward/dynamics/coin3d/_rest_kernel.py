"""The compiled loop of :func:`.rest.rest_outcomes`: bounce each toss until it cannot leave its valley.

Imported only by :mod:`.rest` inside the function that runs it (numba is a heavy import).  The flight, the
certified search for the next impact and the impact itself are :mod:`._top_kernel`'s; this module adds the
landscape of each toss and the test after every floor impact (read :mod:`.rest` for the rule).
"""

import math

import numpy as np
from numba import njit, prange

from ._top_kernel import OPTIONS, impact, next_impact, state_at, support

__all__ = []  # called through coinwall.forward.dynamics.coin3d.rest

#: status codes (as in :data:`.rest.REST_STATUS`)
BUDGET, SETTLED, REST, SLIDES = 0, 1, 3, 4


@njit(**OPTIONS)
def potential(s, c, lz, l3):
    """The top's V(θ) = (ℓz − ℓ3 cos θ)²/(2 sin²θ) for 0 < θ < π, written as in :func:`._top_kernel.setup`."""
    if c >= 0.0:
        p = (lz - l3) / s + l3 * (s / (1.0 + c))
    else:
        p = (lz + l3) / s - l3 * (s / (1.0 - c))
    return 0.5 * p * p


@njit(parallel=True, **OPTIONS)
def rest_many(states, lz, l3, impacts, g, e, kind, verts, eps, ea, ec, reach, tol, chatter, grid, faces,
              outcome, status, floors):
    """For each toss: the face it rests on (``outcome``: 0 heads, 1 edge, 2 tails, −1 none), its status and
    its floor impacts.  ``grid``: tilts in (0, π) for the landscape U = V + g b; ``faces``: the tilts of the
    maxima of b (the boundaries of the faces of the body at rest without spin), sorted."""
    m = states.shape[0]
    n = grid.size
    for j in prange(m):
        # the landscape of this toss on the grid, and its interior local maxima
        u = np.empty(n)
        for i in range(n):
            s = math.sin(grid[i])
            c = math.cos(grid[i])
            h, _, _ = support(s, c, 0.0, 0.0, False, kind, verts, eps, ea, ec)
            u[i] = potential(s, c, lz[j], l3[j]) + g * h
        peaks = np.empty(n, dtype=np.int64)
        k = 0
        for i in range(1, n - 1):
            if u[i] > u[i - 1] and u[i] >= u[i + 1]:
                peaks[k] = i
                k += 1
        theta, eta, w, v = states[j, 0], states[j, 1], states[j, 2], states[j, 3]
        leaving = -1
        code = BUDGET
        found = -1
        floor = 0
        for _ in range(impacts):
            t, wall, hit = next_impact(theta, eta, w, v, lz[j], l3[j], leaving, g, 0.0, False, kind, verts, eps, ea,
                                       ec, reach, tol, math.inf)
            if hit != 0:
                code = hit
                break
            theta, eta, w, v = state_at(theta, eta, w, v, lz[j], l3[j], g, t)
            w, v = impact(theta, w, v, wall, e, kind, verts, eps, ea, ec)
            leaving = wall
            floor += 1
            s = math.sin(theta)
            c = math.cos(theta)
            if s <= 0.0:
                continue  # on a pole (a face flat on the floor at the fold): the valley test needs 0 < θ < π
            _, _, slope = support(s, c, 0.0, 0.0, False, kind, verts, eps, ea, ec)
            rest = v - slope * w < chatter
            if rest:  # the bounces died out: no normal velocity is left
                f = (v - slope * w) / (1.0 + slope * slope)
                w += f * slope
                v -= f
            level = 0.5 * (w * w + v * v) + potential(s, c, lz[j], l3[j]) + g * eta
            # the valley of θ between the grid's maxima; its barrier is the lower of the two (a pole: none)
            left = -1
            for q in range(k):
                if grid[peaks[q]] < theta:
                    left = q
            barrier = math.inf
            if left >= 0:
                barrier = min(barrier, u[peaks[left]])
            if left + 1 < k:
                barrier = min(barrier, u[peaks[left + 1]])
            if level < barrier:
                lo = peaks[left] if left >= 0 else 0
                hi = peaks[left + 1] if left + 1 < k else n - 1
                best = lo
                for i in range(lo, hi + 1):
                    if u[i] < u[best]:
                        best = i
                face = 0
                for q in range(faces.size):
                    if faces[q] < grid[best]:
                        face += 1
                found = 0 if face == 0 else (2 if face == faces.size else 1)
                code = REST if rest else SETTLED
                break
            if rest:
                code = SLIDES
                break
        outcome[j] = found
        status[j] = code
        floors[j] = floor


def _unused():  # keeps numpy imported for numba's array typing in this module's namespace
    return np
