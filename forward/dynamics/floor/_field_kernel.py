"""The field kernel, compiled by numba: flights in a constant field, restitution, and settling.

Like :mod:`._kernel` this file is the kernel's source as people and tools read it; it is never imported
by coinwall.  :mod:`.fieldkernel` reads the text after the marker line, joins it after a wall's generated code
(:mod:`.wallcode`), the shared search and the friction kernel's texts (:mod:`._friction_kernel`,
:mod:`._contact_kernel`) and loads the whole as one module named after its hash (numba's ``cache=True`` then
finds the machine code again in the next process).

The flight
----------
Between impacts ``θ(t) = θ0 + ω t``, ``η(t) = η0 + v t − ½ g t²`` (g: the field in κ/s², pointing to −η).
The gap to a wall, measured vertically, has the same form for both walls,

    f(t) = A + B t − ½ Q t² − b(φ0 + ω t),

floor: ``A = η0 − b0, B = v, Q = g, φ0 = θ0``; ceiling (if any): ``A = H − b0 − η0, B = −v, Q = −g,
φ0 = θ0 + π``.  The next impact is the smallest t > 0 with ``f(t) = 0`` over the walls present.

Why the search cannot skip a root.  It is the billiard kernel's search (:mod:`._kernel`, read it for the
details) with the straight line ``A + B t`` replaced by the parabola ``L(t) = A + B t − ½ Q t²``: the same
code, :func:`._search._search`, compiled into both kernels (this file adds the window of a parabola, the
flight without rotation, the impact and settling).  Every bound it uses stays a bound:

1. *Band and box test.*  A contact needs ``L(t) ≤ max b + tol``; the window of such times is computed from
   the roots of the quadratic (a concave ``L``, the floor under gravity, is in the band from its first
   crossing on and must meet the wall before ``L`` falls below ``min b``; a convex ``L``, the ceiling, only
   while inside a bounded interval).  A concave ``L`` that starts in the band rising and leaves it above
   ``max b + tol`` before coming back is searched in two windows: the time between has no contact, since
   ``L`` is above the band at both of its ends (checked by evaluating ``L`` there) and concave.  The windows
   of both walls are searched in the order they start, each capped by the earliest contact found so far.
   Per cell the minimum of ``L`` over the time the flight spends over the
   cell is at an end of that time for a concave ``L`` and at an end or at the vertex for a convex one; if it
   is above ``bmax_j + tol`` the cell has no contact.
2. *Proxy stage.*  ``G = L − p_j − e_j − tol`` is a lower bound of ``f − tol``, and
   ``G'' = −Q − ω² p_j'' ≥ −(Q + ω² max p_j'')``: the parabola ``G + G'τ − ½ K_p τ²`` with
   ``K_p = Q + ω² max p_j''`` bounds ``G(t + τ)`` from below, so its smallest positive root is a step that
   cannot pass a contact (conservative advancement).
3. *Exact stage.*  The same steps on the exact f with ``f'' ≥ −(Q + ω² c_j)``, ``c_j ≥ max b''`` on the
   cell; the second-order finish uses ``f'' = −Q − ω² b''`` (the field adds no third derivative, so the
   Taylor remainder of the billiard kernel is unchanged).
4. *Curving-away runs.*  Just after an impact on a wall that curves away (``c_j ≤ 0``) the gap is convex
   when ``Q ≤ 0`` too (``f'' = −Q − ω² b'' ≥ 0``), and the search skips the run as the billiard's does; under
   gravity on the floor (``Q > 0``) it does not (the parabola bends back towards the floor).

So every time interval skipped is certified by a lower bound of f (box, proxy or exact parabola): the
iterates never pass the first contact.  The guarantee is exactly the billiard kernel's, with the same
declared approximations (contact tolerance ``tol``; cell bounds from dense sampling with a checked margin,
not interval arithmetic; time intervals below rounding of t are not resolved).  A flight without rotation
(ω = 0) meets the wall at the first root of a quadratic, solved in closed form.  With ``g = 0`` and
``e = 1`` the search and the reflection are the billiard kernel's (the same code), except that the window of
a flight comes from the quadratic's roots (the billiard's from one product with 1/v_η, so the two agree to
rounding) and the speed is not renormalised (the field kernel conserves energy by its arithmetic alone).

The impact
----------
Newton's law on the normal velocity in the billiard metric: with the slope ``s`` of the wall at the
contact (``s = b'`` on the floor, ``−b'(θ+π)`` on the ceiling) and ``n ∝ (−s, 1)``,
``f = (1 + e)(v − s ω)/(1 + s²)``, ``ω += f s``, ``v −= f`` (e = 1: the specular reflection of the
billiard).  This is the rigid body's frictionless impulse at the contact point: :mod:`.field` derives it.
With friction (μ > 0) a floor impact is :func:`._friction_kernel._friction_impact` instead (Stronge's
energetic restitution, Routh's integration; it also changes ξ̇, the horizontal velocity); the ceiling stays
frictionless.  With μ = 0 the code path is the one above, unchanged (the same results to the bit).

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
which the impact model cannot follow; the valley reported is the one it is in).  With friction (μ > 0) the level
counts the horizontal motion too (friction can turn it into rotation), and a body at rest above its barrier
stays on the floor: the contact phases (:mod:`._contact_kernel`) follow it, each event a record, until it lifts
off (back to the flight search), settles, comes to rest, or is undecided with a reason (rolling for ever,
Painlevé, the steps' budget).  The number of records is bounded by the caller (status 0 when it is reached:
"not settled").
"""

# Everything above the marker line only makes this file importable and lintable on its own; none of it
# reaches the compiled module (the imports and OPTIONS come from kernel.HEADER there).

import math

import numpy as np
from numba import carray, njit, prange

from ..billiard._search import (
    INF,
    LEFT,
    PI,
    RIGHT,
    TWO_PI,
    _advance,
    _data_pointer,
    _earlier,
    _impact,
    _leaving_rate,
    _reduce,
    _search,
    wall_b1,
)
from ._contact_kernel import _contact, _side_angle
from ._friction_kernel import (
    C_EVENT,
    C_FLIGHT,
    C_PAINLEVE,
    C_REST,
    CONTACT_STEPS,
    EV_END,
    EV_FACE,
    KINK_NEAR,
    _cell_of,
    _face,
    _friction_impact,
    _is_kink,
    _landing,
    _piece,
    _start_phase,
    _valley,
)

__all__ = []  # nothing public: the kernel is called through coinwall.forward.dynamics.floor.field

CACHE = True
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


# ---- field kernel: the text from the line after this one to the end of the file is joined to the wall code ----

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


@njit(**OPTIONS)
def _windows(A, B, Q, lo, hi, vt):
    # _window as up to two intervals [t1, u1), [t2, u2) (t2 = u2 = INF: one): a concave L (the floor under
    # gravity) that starts in the band rising may leave it above hi and come back; the time above hi has no
    # contact, and walking its cells one by one (the whole flight up and down) was most of the cost of a toss
    t_lo, t_hi = _window(A, B, Q, lo, hi, vt)
    if Q > 0.0 and A <= hi and B > 0.0 and vt != 0.0:
        r1, r2 = _roots(A - hi, B, -0.5 * Q)
        if not math.isnan(r1) and r1 > 0.0:
            u1 = r1 * (1.0 + 1e-12) + 1e-300
            t2 = r2 * (1.0 - 1e-12)
            # L is concave: above hi at both ends of [u1, t2] means above hi on all of it (checked, not trusted
            # to the roots, which lose digits when L barely rises above hi)
            hq = 0.5 * Q
            if u1 < t2 < t_hi and A + B * u1 - hq * u1 * u1 > hi and A + B * t2 - hq * t2 * t2 > hi:
                return t_lo, u1, t2, t_hi
    return t_lo, t_hi, INF, INF


@njit(inline='always', **OPTIONS)
def _first_hit(phi0, A, B, Q, vt, ivt, t_lo, t_hi, tcap, leaving, g1_leave, c, cells, lookup, tol):
    # first t in (0, tcap) where f(t) = A + B t − ½ Q t² − b(phi0 + vt t) ≤ tol, and b' there; (INF, 0) if
    # none; negative codes as in _search (−1 no convergence, −2 non-finite wall, −3 cell budget, −4 angle).
    # [t_lo, t_hi) is the window of the flight (_window), computed by the caller
    t_hi = min(t_hi, tcap)
    if not (t_lo < t_hi):
        return INF, 0.0
    if vt == 0.0:  # no rotation: f is a quadratic in t
        b, d1 = wall_b1(phi0, c)
        if not (abs(b) < INF and abs(d1) < INF):
            return -2.0, 0.0
        if leaving:
            # on this wall at t = 0: the other root, 2B/Q (rising away and falling back), if any
            t = 2.0 * B / Q if (Q > 0.0 and B > 0.0) else INF
        else:
            r1, r2 = _roots(A - b, B, -0.5 * Q)
            t = INF
            if not math.isnan(r1):
                if r1 > 0.0:
                    t = r1
                elif r2 > 0.0:
                    t = r2
        if t >= tcap:
            return INF, 0.0
        return t, d1
    return _search(phi0, A, B, Q, vt, ivt, t_lo, t_hi, leaving, g1_leave, c, cells, lookup, tol)


@njit(**OPTIONS)
def _run(state, turns, leaving, n, H, b0, g, e, mu, rr, ceiling, catch, chatter, c, cells, lookup, wmin, wmax, tol,
         valleys, lscale, record, out_time, out_theta, out_eta, out_vt, out_ve, out_vx, out_side, summary):
    # one orbit; returns (records done, status).  A record is an impact (side 0 floor, 1 ceiling) or, with
    # friction, a contact event (side EV_*).  status: 0 all n records done (not decided), 1 settled (energy below
    # the valley's barrier), 2 caught (first floor contact, catch mode), 3 at rest (μ = 0: the chattering limit
    # below the barrier; μ > 0: on a face, or where the rolling resistance holds it), 4 at rest with energy above
    # the barrier (μ = 0: it slides), 6 free flight, 7 no convergence, 8 wall not finite, 9 angle beyond
    # float64, 10 cell budget, 11 rolls for ever, 12 no consistent motion on the floor (Painlevé), 13
    # contact-phase budget.  leaving 2: the state is on the floor, at rest in
    # the normal direction (μ > 0): the toss starts in contact.
    # summary = [θ mod 2π, turns, η, θ̇, η̇, time, floor impacts, valley, ξ̇]
    theta = state[0]
    eta = state[1]
    vt = state[2]
    ve = state[3]
    vx = state[4]
    c = carray(_data_pointer(c), c.shape)
    cells = carray(_data_pointer(cells), cells.shape)
    lookup = carray(_data_pointer(lookup), lookup.shape)
    th, wraps = _reduce(theta, turns)
    time = 0.0
    floor_hits = 0
    g1_leave = math.nan
    status = 0
    done = 0
    settle = g > 0.0 and valleys.shape[0] > 0
    mode = 0  # 0 in the air, 1 on the floor on the piece of cell jc, 2 standing on the kink at its right edge
    jc = 0
    sigc = 0
    left = CONTACT_STEPS  # the contact phases' steps left to this toss
    if leaving == 2:
        leaving = 0
        mode, jc, sigc, th, wraps, eta, vt, ve, vx = _touch(th, wraps, vt, vx, b0, g, mu, rr, c, cells, lookup)
    for i in range(n):
        kind = 0
        if mode != 0:
            if mode == 1:
                code, kind, x, wraps, jc, vt, vx, sigc, eta, ve, dt, hits, nmode, leave, steps = _contact(
                    th, wraps, jc, vt, vx, sigc, b0, g, e, mu, rr, chatter, tol, lscale, c, cells, valleys, settle,
                    left)
                left -= steps
                th = x
            else:
                jr = jc + 1 if jc + 1 < cells.shape[0] else 0
                dt, vx, nxt, sgn = _face(jc, jr, th, vx, b0, g, mu, chatter, c, cells)
                kind = EV_FACE
                hits = 0
                code = C_REST if nxt == 2 else C_EVENT
                leave = math.nan
                if nxt != 2:
                    jn = jr if nxt == 1 else jc
                    th, wraps = _side_angle(th, wraps, jn, cells.shape[0])
                    jc = jn
                    vt = 0.0
                    Bn, sn, B2n = _piece(th, jc, c, cells)
                    sigc = sgn if sgn != 0 else _start_phase(Bn + b0, sn, B2n, 0.0, vx, g, mu, rr)
                    if sigc == 2:
                        code = C_PAINLEVE
                nmode = 1
            time += dt
            floor_hits += hits
            if code != C_EVENT and code != C_FLIGHT and kind == 0:
                kind = EV_END
            if code == C_FLIGHT:
                mode = 0
                if nmode == 3:  # back on the floor just after lifting off: a floor impact there
                    th, wraps = _reduce(th, wraps)
                    _b, s = wall_b1(th, c)
                    vt, ve, vx, _p = _friction_impact(vt, ve, vx, s, eta, e, mu)
                    floor_hits += 1
                    mode, jc, sigc, th, wraps, eta, vt, ve, vx = _touch(th, wraps, vt, vx, b0, g, mu, rr, c, cells,
                                                                        lookup)
                elif math.isnan(leave):
                    leaving = -1
                    g1_leave = math.nan
                else:
                    leaving = 0
                    g1_leave = leave
            elif code == C_EVENT:
                mode = nmode
            th_r, wr = _reduce(th, wraps)
            done = i + 1
            if record:
                out_time[i] = time
                out_theta[i] = th_r + wr * TWO_PI
                out_eta[i] = eta
                out_vt[i] = vt
                out_ve[i] = ve
                out_vx[i] = vx
                out_side[i] = kind
            if code != C_EVENT and code != C_FLIGHT:
                status = (0, 0, 1, 3, 11, 12, 13, 8)[code]
                break
            if mode == 0:
                th, wraps = th_r, wr
            continue
        ivt = 1.0 / vt if vt != 0.0 else INF
        tl = INF
        tu = INF
        dl = 0.0
        du = 0.0
        # the windows of both walls once (a quadratic's roots), up to two a wall: searched in the order they
        # start, each capped by the earliest contact found so far (a window starting after it is not searched)
        w0, w1, w2, w3 = _windows(eta - b0, ve, g, wmin, wmax + tol, vt)
        w4 = INF
        w5 = INF
        w6 = INF
        w7 = INF
        if ceiling:
            w4, w5, w6, w7 = _windows(H - b0 - eta, -ve, -g, wmin, wmax + tol, vt)
        searched = 0  # bit k: window k (floor first, floor second, ceiling first, ceiling second) is done
        for k in range(4):
            # the window not yet searched that starts first (ties: the floor's, the first)
            pick = -1
            first = min(tl, tu)
            if searched & 1 == 0 and w0 < first:
                pick, first = 0, w0
            if searched & 2 == 0 and w2 < first:
                pick, first = 1, w2
            if searched & 4 == 0 and w4 < first:
                pick, first = 2, w4
            if searched & 8 == 0 and w6 < first:
                pick, first = 3, w6
            if pick < 0:
                break
            searched |= 1 << pick
            upper = pick >= 2
            if pick == 0:
                t_lo, t_hi = w0, w1
            elif pick == 1:
                t_lo, t_hi = w2, w3
            elif pick == 2:
                t_lo, t_hi = w4, w5
            else:
                t_lo, t_hi = w6, w7
            if upper:
                phi0, A, B, Q, near = th + PI, H - b0 - eta, -ve, -g, leaving == 1
            else:
                phi0, A, B, Q, near = th, eta - b0, ve, g, leaving == 0
            tk, dk = _first_hit(phi0, A, B, Q, vt, ivt, t_lo, t_hi, min(tl, tu), near, g1_leave, c, cells, lookup,
                                tol)
            if upper:
                if tk < tu:
                    tu, du = tk, dk
            elif tk < tl:
                tl, dl = tk, dk
            if tk < 0.0:
                break
        t, side, s, code = _earlier(tl, dl, tu, du, vt)
        if code != 0:
            status = (0, 8, 10, 9, 7, 6)[code]
            break
        th, wraps = _advance(th, wraps, vt * t)
        eta += ve * t - 0.5 * g * t * t
        ve -= g * t
        time += t
        if side == 0 and mu > 0.0:
            # Coulomb friction, Stronge's e; on a kink of b, the impacts at both corners of the face
            kink, thk, vt2, ve2, vx2, hits, sk = _landing(th, vt, ve, vx, b0, e, mu, chatter, c, cells, lookup)
            if kink:
                if thk < th - PI:  # the kink at 2π is the one at 0 of the next turn
                    wraps += 1
                elif thk > th + PI:
                    wraps -= 1
                th, vt, ve, vx, s = thk, vt2, ve2, vx2, sk
                floor_hits += hits - 1
            else:
                vt, ve, vx, _p = _friction_impact(vt, ve, vx, s, eta, e, mu)
        else:
            vt, ve = _impact(vt, ve, s, e)  # Newton's restitution on the normal velocity
        g1_leave = _leaving_rate(side, vt, ve, s)
        done = i + 1
        if record:
            out_time[i] = time
            out_theta[i] = th + wraps * TWO_PI
            out_eta[i] = eta
            out_vt[i] = vt
            out_ve[i] = ve
            out_vx[i] = vx
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
                if mu > 0.0:  # friction can turn the horizontal motion into rotation: its energy counts
                    level = eta - b0 + 0.5 * (vt * vt + ve * ve + vx * vx) / g
                else:
                    level = eta - b0 + 0.5 * (vt * vt + ve * ve) / g
                if level < valleys[_valley(th, valleys), 1]:
                    # (with friction the body is not at rest yet: it slides and rolls on in its valley)
                    status = 3 if rest and mu == 0.0 else 1
                    break
                if rest:
                    if mu == 0.0:
                        status = 4
                        break
                    # the bounces died out above the barrier: the body stays on the floor (contact phases)
                    mode, jc, sigc, th, wraps, eta, vt, ve, vx = _touch(th, wraps, vt, vx, b0, g, mu, rr, c, cells,
                                                                        lookup)
            elif mu > 0.0 and g > 0.0 and g1_leave < chatter:
                # no valleys to settle in (an orbit followed for its own sake), but the bounces died out all the same
                f = (ve - s * vt) / (1.0 + s * s)
                vt = vt + f * s
                mode, jc, sigc, th, wraps, eta, vt, ve, vx = _touch(th, wraps, vt, vx, b0, g, mu, rr, c, cells, lookup)
    summary[0] = th
    summary[1] = wraps
    summary[2] = eta
    summary[3] = vt
    summary[4] = ve
    summary[5] = time
    summary[6] = floor_hits
    summary[7] = _valley(th, valleys)
    summary[8] = vx
    return done, status


@njit(**OPTIONS)
def _touch(th, wraps, vt, vx, b0, g, mu, rr, c, cells, lookup):
    # the body put on the floor at θ = th with no normal velocity: (mode, cell, phase, θ, turns, η, θ̇, η̇, ξ̇);
    # mode 1 on the piece of the cell, 2 standing on a kink (at the right edge of the cell returned)
    th, wraps = _reduce(th, wraps)
    j = _cell_of(th, cells, lookup)
    lo = cells[j, LEFT]
    hi = cells[j, RIGHT]
    if _is_kink(j, True, cells) and th <= lo + KINK_NEAR:
        th = lo
    elif _is_kink(j, False, cells) and th >= hi - KINK_NEAR:
        th = hi
    B, s, B2 = _piece(th, j, c, cells)
    B += b0
    sig = _start_phase(B, s, B2, vt, vx, g, mu, rr)
    return 1, j, sig, th, wraps, B, vt, s * vt, vx


@njit(cache=CACHE, parallel=True)
def _run_many(states, n, H, b0, g, e, mu, rr, ceiling, catch, chatter, c, cells, lookup, wmin, wmax, tol, valleys, lscale,
              done, status, summary):
    # many orbits in parallel, summaries only (no records)
    dummy_f = np.empty(1)
    dummy_i = np.empty(1, dtype=np.int8)
    for k in prange(states.shape[0]):
        d, s = _run(states[k], 0, -1, n, H, b0, g, e, mu, rr, ceiling, catch, chatter, c, cells, lookup, wmin, wmax, tol,
                    valleys, lscale, False, dummy_f, dummy_f, dummy_f, dummy_f, dummy_f, dummy_f, dummy_i, summary[k])
        done[k] = d
        status[k] = s
