"""The field kernel, compiled by numba: flights in a constant field, restitution, and settling.

Like :mod:`._kernel` this file is the kernel's source as people and tools read it; it is never imported
by coinwall.  :mod:`.field` reads the text after the marker line, joins it after a wall's generated code
(:mod:`.wallcode`) and loads the whole as one module named after its hash (numba's ``cache=True`` then
finds the machine code again in the next process).

The flight
----------
Between impacts ``θ(t) = θ0 + ω t``, ``η(t) = η0 + v t − ½ g t²`` (g: the field in κ/s², pointing to −η).
The gap to a wall, measured vertically, has the same form for both walls,

    f(t) = A + B t − ½ Q t² − b(φ0 + ω t),

floor: ``A = η0 − b0, B = v, Q = g, φ0 = θ0``; ceiling (if any): ``A = H − b0 − η0, B = −v, Q = −g,
φ0 = θ0 + π``.  The next impact is the smallest t > 0 with ``f(t) = 0`` over the walls present.

Why the search cannot skip a root.  It is the billiard kernel's search (:mod:`._kernel`, read it for the
details) with the straight line ``A + B t`` replaced by the parabola ``L(t) = A + B t − ½ Q t²``.  Every
bound it uses stays a bound:

1. *Band and box test.*  A contact needs ``L(t) ≤ max b + tol``; the window of such times is computed from
   the roots of the quadratic (a concave ``L``, the floor under gravity, is in the band from its first
   crossing on and must meet the wall before ``L`` falls below ``min b``; a convex ``L``, the ceiling, only
   while inside a bounded interval).  Per cell the minimum of ``L`` over the time the flight spends over the
   cell is at an end of that time for a concave ``L`` and at an end or at the vertex for a convex one; if it
   is above ``bmax_j + tol`` the cell has no contact.
2. *Proxy stage.*  ``G = L − p_j − e_j − tol`` is a lower bound of ``f − tol``, and
   ``G'' = −Q − ω² p_j'' ≥ −(Q + ω² max p_j'')``: the parabola ``G + G'τ − ½ K_p τ²`` with
   ``K_p = Q + ω² max p_j''`` bounds ``G(t + τ)`` from below, so its smallest positive root is a step that
   cannot pass a contact (conservative advancement).
3. *Exact stage.*  The same steps on the exact f with ``f'' ≥ −(Q + ω² c_j)``, ``c_j ≥ max b''`` on the
   cell; the second-order finish uses ``f'' = −Q − ω² b''`` (the field adds no third derivative, so the
   Taylor remainder of the billiard kernel is unchanged).

So every time interval skipped is certified by a lower bound of f (box, proxy or exact parabola): the
iterates never pass the first contact.  The guarantee is exactly the billiard kernel's, with the same
declared approximations (contact tolerance ``tol``; cell bounds from dense sampling with a checked margin,
not interval arithmetic; time intervals below rounding of t are not resolved).  A flight without rotation
(ω = 0) meets the wall at the first root of a quadratic, solved in closed form.  With ``g = 0`` and
``e = 1`` the search and the reflection are the billiard kernel's, operation for operation, except that
the speed is not renormalised (the field kernel conserves energy by its arithmetic alone).

The impact
----------
Newton's law on the normal velocity in the billiard metric: with the slope ``s`` of the wall at the
contact (``s = b'`` on the floor, ``−b'(θ+π)`` on the ceiling) and ``n ∝ (−s, 1)``,
``f = (1 + e)(v − s ω)/(1 + s²)``, ``ω += f s``, ``v −= f`` (e = 1: the specular reflection of the
billiard).  This is the rigid body's frictionless impulse at the contact point: :mod:`.field` derives it.

Settling (floor present, g > 0)
-------------------------------
After every floor impact the energy level ``λ = E/g = η + (ω² + v²)/(2g)`` (a height, κ) is compared with
the *barrier* of the valley the body is in: the valleys of ``b`` are the intervals between consecutive
local maxima of b (``valleys``: one row per valley, ``[left maximum angle, barrier, minimum angle]``, the
barrier being the lower of the two maxima, ``+inf`` for a wall with one valley).  Since ``η ≥ b0 + b(θ)``
and the kinetic energy is ≥ 0, ``λ − b0 < barrier`` confines θ to that valley for ever: the outcome is
decided (status 1).  The chattering limit (ever smaller bounces in finite time): when the rate at which the
gap opens just after a floor impact, ``ḟ = v − s ω``, is below ``chatter = √(2 g δ)`` (a free bounce on a
flat floor would rise less than δ), the normal velocity is set to zero and the body is at rest on the floor
(status 3 when then below its valley's barrier, 4 when not: it slides on with energy above the barrier,
which the impact model cannot follow; the valley reported is the one it is in).  The number of impacts is
bounded by the caller (status 0 when it is reached: "not settled").
"""

# Everything above the marker line only makes this file importable and lintable on its own; none of it
# reaches the compiled module (the imports and OPTIONS come from kernel.HEADER there).

import math

import numpy as np
from numba import carray, njit, prange, types
from numba.extending import intrinsic

__all__ = []  # nothing public: the kernel is called through coinwall.forward.dynamics.floor.field

CACHE = True
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


def wall_b1(phi, c):
    """Stand-in for the generated ``wall_b1(phi, c) -> (b, b')`` (see :func:`.wallcode.wall_source`)."""
    raise NotImplementedError("the kernel runs joined to a wall's generated code: see coinwall.forward.dynamics.floor.field")


def wall_b2(phi, c):
    """Stand-in for the generated ``wall_b2(phi, c) -> (b, b', b'')`` (see :func:`.wallcode.wall_source`)."""
    raise NotImplementedError("the kernel runs joined to a wall's generated code: see coinwall.forward.dynamics.floor.field")


# ---- field kernel: the text from the line after this one to the end of the file is joined to the wall code ----

TWO_PI = 2.0 * math.pi
INV_TWO_PI = 1.0 / TWO_PI
PI = math.pi
INF = math.inf
ROUND_T = 1e-15
LEFT, RIGHT, BMAX, CMAX, SLOPE_FWD, SLOPE_BWD, P0, P1, P2, P3, P4, P5, PERR, P2MAX, D3MAX, P2ABS = range(16)
POS_TOL = 0.01
MAX_ANGLE = 17592186044416.0
CELL_BUDGET = 134217728


@intrinsic
def _data_pointer(typingctx, arr):
    # as in _kernel: rebuild arrays as views without a reference count (no atomics per call)
    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, args[0]).data
    return types.CPointer(arr.dtype)(arr), codegen


@njit(**OPTIONS)
def _root_step(g0, g1, K):
    # smallest τ > 0 with g0 + g1 τ − ½ K τ² = 0 (g0 ≥ 0), ∞ if none, or a lower bound of it (as in _kernel;
    # K may be negative here: a convex parabola, whose smallest root is the same formula)
    if g1 < 0.0 and K > 0.0 and 2.0 * K * g0 <= g1 * g1:
        return g0 * (-g1) / (g1 * g1 + 0.5 * K * g0)
    disc = g1 * g1 + 2.0 * K * g0
    if disc < 0.0:
        return INF
    if g1 < 0.0:
        return 2.0 * g0 / (-g1 + math.sqrt(disc))
    if K > 0.0:
        return (g1 + math.sqrt(disc)) / K
    return INF


@njit(**OPTIONS)
def _roots(a, b, c):
    # real roots r1 ≤ r2 of a + b t + c t² (NaN, NaN if none; one root twice when c = 0)
    if c == 0.0:
        if b == 0.0:
            return math.nan, math.nan
        r = -a / b
        return r, r
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return math.nan, math.nan
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    if q == 0.0:
        return 0.0, 0.0
    r1 = q / c
    r2 = a / q
    if r1 > r2:
        return r2, r1
    return r1, r2


@njit(**OPTIONS)
def _window(A, B, Q, lo, hi, vt):
    # the times [t_lo, t_hi) where L(t) = A + B t − ½ Q t² may meet a wall whose values lie in [lo, hi]:
    # t_lo the first t ≥ 0 with L ≤ hi, t_hi the first later t with L < lo (the gap is negative there, so the
    # contact came before) or the end of the interval L ≤ hi; (INF, INF) if L never comes down to hi
    c = -0.5 * Q
    if A <= hi:
        t_lo = 0.0
    else:
        r1, r2 = _roots(A - hi, B, c)
        if math.isnan(r1):
            return INF, INF
        if r1 > 0.0:
            t_lo = r1
        elif r2 > 0.0:
            t_lo = r2
        else:
            return INF, INF
    t_hi = INF
    if Q > 0.0 or (Q == 0.0 and B < 0.0):
        # L eventually falls below lo: the last root of L = lo (the concave L is above lo before it)
        r1, r2 = _roots(A - lo, B, c)
        if not math.isnan(r2):
            t_hi = max(r2, t_lo) * (1.0 + 1e-12) + 1e-300
    elif Q < 0.0:
        # convex L: inside the band only up to the larger root of L = hi; below lo between the roots of L = lo
        r1, r2 = _roots(A - hi, B, c)
        if not math.isnan(r2):
            t_hi = max(r2, 0.0) * (1.0 + 1e-12) + 1e-300
        s1, _s2 = _roots(A - lo, B, c)
        if not math.isnan(s1) and s1 > t_lo:
            t_hi = min(t_hi, s1 * (1.0 + 1e-12) + 1e-300)
    else:
        # B ≥ 0 and Q = 0: a rising or horizontal line; rising: above hi after (hi − A)/B
        if B > 0.0:
            t_hi = (hi - A) / B
        elif vt != 0.0:  # horizontal: one period of θ decides
            t_hi = 1.01 * TWO_PI / abs(vt) + 1.0
    return t_lo, t_hi


@njit(inline='always', **OPTIONS)
def _first_hit(phi0, A, B, Q, vt, ivt, tcap, leaving, g1_leave, c, cells, lookup, wmin, wmax, tol):
    # first t in (0, tcap) where f(t) = A + B t − ½ Q t² − b(phi0 + vt t) ≤ tol, and b' there; (INF, 0) if
    # none; negative codes as in _kernel (−1 no convergence, −2 non-finite wall, −3 cell budget, −4 angle)
    t_lo, t_hi = _window(A, B, Q, wmin, wmax + tol, vt)
    t_hi = min(t_hi, tcap)
    if not (t_lo < t_hi):
        return INF, 0.0
    hq = 0.5 * Q
    if vt == 0.0:  # no rotation: f is a quadratic in t
        b, d1 = wall_b1(phi0, c)
        if not (abs(b) < INF and abs(d1) < INF):
            return -2.0, 0.0
        if leaving:
            # on this wall at t = 0: the other root, 2B/Q (rising away and falling back), if any
            t = 2.0 * B / Q if (Q > 0.0 and B > 0.0) else INF
        else:
            r1, r2 = _roots(A - b, B, -hq)
            t = INF
            if not math.isnan(r1):
                if r1 > 0.0:
                    t = r1
                elif r2 > 0.0:
                    t = r2
        if t >= tcap:
            return INF, 0.0
        return t, d1
    m = cells.shape[0]
    nunif = lookup.shape[0]
    phi = phi0 + vt * t_lo
    off = TWO_PI * math.floor(phi * INV_TWO_PI)
    x = phi - off
    if x >= TWO_PI:
        x -= TWO_PI
        off += TWO_PI
    elif x < 0.0:
        x += TWO_PI
        off -= TWO_PI
    if not (0.0 <= x < TWO_PI):
        return -4.0, 0.0
    i = int(x * (nunif * INV_TWO_PI))
    if i >= nunif:
        i = nunif - 1
    elif i < 0:
        i = 0
    j = lookup[i]
    while j < m - 1 and cells[j, RIGHT] <= x:
        j += 1
    while j > 0 and cells[j, LEFT] > x:
        j -= 1
    if vt < 0.0 and x == cells[j, LEFT]:
        j -= 1
        if j < 0:
            j = m - 1
            off -= TWO_PI
    vt2 = vt * vt
    edge = RIGHT if vt > 0.0 else LEFT
    start = off - phi0
    t_in = t_lo
    at_edge = False
    walked = 0
    # the vertex of a convex L (ceiling under gravity), where its minimum over a cell may lie
    t_vertex = B / Q if Q < 0.0 else -1.0
    while True:
        walked += 1
        if walked > CELL_BUDGET:
            return -3.0, 0.0
        t_out = (cells[j, edge] + start) * ivt
        t_out = min(t_out, t_hi)
        l_in = A + B * t_in - hq * t_in * t_in
        l_out = A + B * t_out - hq * t_out * t_out
        lmin = min(l_in, l_out)
        if t_in < t_vertex < t_out:
            lmin = min(lmin, A + B * t_vertex - hq * t_vertex * t_vertex)
        if lmin <= cells[j, BMAX] + tol and t_out >= t_in:
            t = t_in
            clear = False
            if leaving and t == 0.0:
                if not math.isnan(g1_leave):
                    g1 = g1_leave
                else:
                    b, d1 = wall_b1(phi0, c)
                    g1 = B - vt * d1
                t = _root_step(0.0, g1, Q + vt2 * cells[j, CMAX])
                clear = not (t < t_out)
            if not clear:
                a = cells[j, LEFT] + start
                e = cells[j, PERR]
                Kp = Q + vt2 * cells[j, P2MAX]
                Ka = vt2 * cells[j, P2ABS] + max(0.0, -Q)
                c0 = cells[j, P0]
                c1 = cells[j, P1]
                c2 = cells[j, P2]
                c3 = cells[j, P3]
                c4 = cells[j, P4]
                c5 = cells[j, P5]
                c2d = 2.0 * c2
                c3d = 3.0 * c3
                c4d = 4.0 * c4
                c5d = 5.0 * c5
                for it in range(64):
                    s = vt * t - a
                    s2 = s * s
                    p = (c0 + c1 * s) + s2 * ((c2 + c3 * s) + s2 * (c4 + c5 * s))
                    G = A + B * t - hq * t * t - p - e - tol
                    if G <= e:
                        break
                    dp = (c1 + c2d * s) + s2 * ((c3d + c4d * s) + s2 * c5d)
                    G1 = B - Q * t - vt * dp
                    tau = _root_step(G, G1, Kp)
                    if not (t + tau < t_out):
                        clear = True
                        break
                    t += tau
                    if G + G1 * tau + 0.5 * Ka * tau * tau <= e:
                        break
            if not clear:
                K = Q + vt2 * cells[j, CMAX]
                D3 = abs(vt) * vt2 * cells[j, D3MAX]
                for it in range(1000):
                    b, d1, d2 = wall_b2(phi0 + vt * t, c)
                    second = True
                    if it == 0 and at_edge and t == t_in:
                        slope = cells[j, SLOPE_FWD] if vt > 0.0 else cells[j, SLOPE_BWD]
                        if not math.isnan(slope):
                            d1 = slope
                            second = False
                    g0 = A + B * t - hq * t * t - b
                    g1 = B - Q * t - vt * d1
                    if not (abs(g0) < INF and abs(g1) < INF):
                        return -2.0, 0.0
                    if second and g1 < 0.0:
                        dn = g0 / (-g1)
                        g2 = -Q - vt2 * d2
                        dh = dn + 0.5 * g2 * dn * dn / (-g1)
                        rem = D3 * dh * dh * abs(dh) / 6.0
                        res = abs(g0 + dh * (g1 + 0.5 * g2 * dh)) + rem
                        slope_err = 0.5 * D3 * dh * dh / abs(vt)
                        if (res <= POS_TOL * tol and rem <= 1e-17 * abs(g1) and slope_err <= 1e-17 * (1.0 + abs(d1))
                                and t + dh < t_out):
                            if g0 <= tol:
                                return t + dh, d1 + vt * d2 * dh
                            tau = _root_step(g0, g1, K)
                            if (t + dh) - (t + tau) <= ROUND_T * (1.0 + t):
                                return t + dh, d1 + vt * d2 * dh
                    if g0 <= tol:
                        if g1 < 0.0:
                            tn = t + g0 / (-g1)
                            bn, dn = wall_b1(phi0 + vt * tn, c)
                            gn = A + B * tn - hq * tn * tn - bn
                            if abs(gn) < abs(g0) or g0 < 0.0:
                                return tn, dn
                        return t, d1
                    tau = _root_step(g0, g1, K)
                    if not (t + tau < t_out):
                        break
                    if t + tau == t and g0 <= -g1 * 4.5e-16 * t:
                        return t, d1
                    if g1 < 0.0:
                        tn = t + g0 / (-g1)
                        if tn - (t + tau) <= ROUND_T * (1.0 + t) and tn < t_out:
                            bn, dn = wall_b1(phi0 + vt * tn, c)
                            gn = A + B * tn - hq * tn * tn - bn
                            if abs(gn) <= tol:
                                return tn, dn
                    t += tau
                else:
                    return -1.0, 0.0
        if t_out >= t_hi:
            return INF, 0.0
        if vt > 0.0:
            j += 1
            if j == m:
                j = 0
                off += TWO_PI
                start = off - phi0
        else:
            j -= 1
            if j < 0:
                j = m - 1
                off -= TWO_PI
                start = off - phi0
        t_in = t_out
        at_edge = True


@njit(**OPTIONS)
def _valley(x, valleys):
    # index of the valley holding the angle x in [0, 2π): valleys[k, 0] are the sorted left maxima
    nv = valleys.shape[0]
    if nv <= 1:
        return 0
    lo = 0
    hi = nv
    while lo < hi:  # number of left maxima ≤ x
        mid = (lo + hi) // 2
        if valleys[mid, 0] <= x:
            lo = mid + 1
        else:
            hi = mid
    k = lo - 1
    if k < 0:
        k = nv - 1
    return k


@njit(**OPTIONS)
def _run(state, turns, leaving, n, H, b0, g, e, ceiling, catch, chatter, c, cells, lookup, wmin, wmax, tol, valleys,
         record, out_time, out_theta, out_eta, out_vt, out_ve, out_side, summary):
    # one orbit; returns (impacts done, status).  status: 0 all n impacts done (not settled), 1 settled (energy
    # below the valley's barrier), 2 caught (first floor contact, catch mode), 3 at rest (chattering limit) and
    # settled, 4 at rest with energy above the barrier, 6 free flight (never meets a wall again), 7 no
    # convergence, 8 wall not finite, 9 angle beyond float64, 10 cell budget.
    # summary = [θ mod 2π, turns, η, ω, v, time, floor impacts, valley]
    theta = state[0]
    eta = state[1]
    vt = state[2]
    ve = state[3]
    c = carray(_data_pointer(c), c.shape)
    cells = carray(_data_pointer(cells), cells.shape)
    lookup = carray(_data_pointer(lookup), lookup.shape)
    wraps = math.floor(theta / TWO_PI)
    th = theta - wraps * TWO_PI
    wraps += turns
    time = 0.0
    floor_hits = 0
    g1_leave = math.nan
    status = 0
    done = 0
    settle = g > 0.0 and valleys.shape[0] > 0
    for i in range(n):
        ivt = 1.0 / vt if vt != 0.0 else INF
        # the wall whose band the flight reaches first is searched first; its time caps the other search
        tl = INF
        tu = INF
        dl = 0.0
        du = 0.0
        lower_first = True
        if ceiling:
            lo_l, _hi_l = _window(eta - b0, ve, g, wmin, wmax + tol, vt)
            lo_u, _hi_u = _window(H - b0 - eta, -ve, -g, wmin, wmax + tol, vt)
            lower_first = lo_l <= lo_u
        for k in range(2 if ceiling else 1):
            upper = (not lower_first) if k == 0 else lower_first
            tcap = INF if k == 0 else (tl if lower_first else tu)
            if upper:
                phi0, A, B, Q, near = th + PI, H - b0 - eta, -ve, -g, leaving == 1
            else:
                phi0, A, B, Q, near = th, eta - b0, ve, g, leaving == 0
            tk, dk = _first_hit(phi0, A, B, Q, vt, ivt, tcap, near, g1_leave, c, cells, lookup, wmin, wmax, tol)
            if upper:
                tu, du = tk, dk
            else:
                tl, dl = tk, dk
        if tl == -2.0 or tu == -2.0:
            status = 8
            break
        if tl == -3.0 or tu == -3.0:
            status = 10
            break
        if tl == -4.0 or tu == -4.0:
            status = 9
            break
        if tl < 0.0 or tu < 0.0:
            status = 7
            break
        if tu < tl:
            t = tu
            side = 1
            s = -du
        else:
            t = tl
            side = 0
            s = dl
        if t == INF:
            status = 6
            break
        if not (abs(vt * t) < MAX_ANGLE):
            status = 9
            break
        th += vt * t
        eta += ve * t - 0.5 * g * t * t
        ve -= g * t
        time += t
        if th >= TWO_PI or th < 0.0:
            kk = math.floor(th / TWO_PI)
            th -= kk * TWO_PI
            wraps += kk
        # Newton's restitution on the normal velocity (billiard metric, n ∝ (−s, 1))
        f = (1.0 + e) * (ve - s * vt) / (1.0 + s * s)
        vt = vt + f * s
        ve = ve - f
        if side == 0:
            g1_leave = ve - vt * s
        else:
            g1_leave = -ve + vt * s
        done = i + 1
        if record:
            out_time[i] = time
            out_theta[i] = th + wraps * TWO_PI
            out_eta[i] = eta
            out_vt[i] = vt
            out_ve[i] = ve
            out_side[i] = side
        leaving = side
        if side == 0:
            floor_hits += 1
            if catch:
                status = 2
                break
            if settle:
                rest = g1_leave < chatter
                if rest:
                    # the chattering limit: take the normal velocity away (the body rests on the floor)
                    f = (ve - s * vt) / (1.0 + s * s)
                    vt = vt + f * s
                    ve = ve - f
                    g1_leave = 0.0
                level = eta - b0 + 0.5 * (vt * vt + ve * ve) / g
                if level < valleys[_valley(th, valleys), 1]:
                    status = 3 if rest else 1
                    break
                if rest:
                    status = 4
                    break
    summary[0] = th
    summary[1] = wraps
    summary[2] = eta
    summary[3] = vt
    summary[4] = ve
    summary[5] = time
    summary[6] = floor_hits
    summary[7] = _valley(th, valleys)
    return done, status


@njit(cache=CACHE, parallel=True)
def _run_many(states, n, H, b0, g, e, ceiling, catch, chatter, c, cells, lookup, wmin, wmax, tol, valleys,
              done, status, summary):
    # many orbits in parallel, summaries only (no collision records)
    dummy_f = np.empty(1)
    dummy_i = np.empty(1, dtype=np.int8)
    for k in prange(states.shape[0]):
        d, s = _run(states[k], 0, -1, n, H, b0, g, e, ceiling, catch, chatter, c, cells, lookup, wmin, wmax, tol,
                    valleys, False, dummy_f, dummy_f, dummy_f, dummy_f, dummy_f, dummy_i, summary[k])
        done[k] = d
        status[k] = s
