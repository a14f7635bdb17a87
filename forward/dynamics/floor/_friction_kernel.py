"""The friction kernel, compiled by numba: impacts with Coulomb friction and what the contact phases share.

Like :mod:`._field_kernel` this file is source as people and tools read it; it is never imported by coinwall.
:mod:`.fieldkernel` joins the text after the marker line below to the contact phase's (:mod:`._contact_kernel`)
and the flight loop's (:mod:`._field_kernel`), after the wall's generated code and the shared search, and
compiles the whole as one module.  Everything here is plain numba: scalars, loops, preallocated arrays, no
objects, no recursion, no exceptions.  The physics is derived in ``docs/toss.md`` ("Friction").

Units and state
---------------
Lengths in κ, mass M = 1 (both cancel).  The body's state on or above the floor is ``θ, η, θ̇, η̇`` (the
billiard's) and ``ξ̇ = ẋ/κ``, the horizontal velocity of the centre of mass, which friction couples to the
spin.  At a floor contact at angle θ the contact point is ``r = κ (s, −η)`` from the centre of mass
(``s = b'(θ)``, η the height of the centre), its velocity is ``u_t = ξ̇ − η θ̇`` along the floor and
``u_n = η̇ − s θ̇`` along the normal, and an impulse ``(P_t, P_n)`` changes

    ξ̇ += P_t,   η̇ += P_n,   θ̇ −= s P_n + η P_t,        u += W P,   W = [[1 + η², s η], [s η, 1 + s²]].

The impact (:func:`_friction_impact`): Stronge's energetic restitution with Routh's integration
-------------------------------------------------------------------------------------------------
The normal impulse P_n is the impact's clock.  While the contact slips (σ = sign u_t) ``dP_t = −μσ dP_n``; when
u_t reaches 0 it sticks (``dP_t = −(W_tn/W_tt) dP_n``) if ``|W_tn| ≤ μ W_tt``, else it slips back the other way
(σ = sign W_tn).  So u(P_n) is piecewise linear with at most two pieces (W is positive definite, so the normal
velocity rises on every piece that can last).  Compression ends where u_n = 0; restitution ends when the work
of the normal impulse in restitution is ``e²`` times minus its work in compression (Stronge's energetic
coefficient).  Both works are integrals of a piecewise linear function: closed forms, no iteration.  The
energy change is the friction work ``∫ u_t dP_t ≤ 0`` plus ``(1 − e²)`` times the compression work ``≤ 0``:
no impact creates energy, for any μ ≥ 0 and e in [0, 1].  With μ = 0 it is Newton's law ``u_n⁺ = −e u_n⁻``
(the field kernel then calls its own frictionless ``_impact``, unchanged).  The same function is the
*tangential impact* of Painlevé's paradox: a contact at rest in the normal direction whose slip would press it
into the floor (the rate of u_n per unit P_n, ``W_nn − μσW_tn``, is the sliding phase's D, negative).

Contact phases (:mod:`._contact_kernel`, with the helpers here)
---------------------------------------------------------------
When the bounces die out the body stays on the floor, η = B(θ) = b0 + b(θ) on the smooth piece of the wall under
it (a cell of the cell table, between kinks), and slides or rolls; on a corner of a polygon (B + B'' = 0)
rolling is rocking about the corner.  A rolling resistance ``rr`` (a length) adds a couple rr·F_n that opposes
θ̇ (sign sw), in both phases:

    q = s + rr·sw
    slide σ:  D = 1 + s q − μσ s B,  F_n = (g + B''θ̇²)/D,  θ̈ = F_n (μσB − q),  ξ̈ = −μσF_n
    roll:     θ̈ = (−q (g + B''θ̇²) − B s θ̇²)/(1 + B² + s q),  F_n = g + sθ̈ + B''θ̇²,  F_t = ξ̈ = sθ̇² + Bθ̈

(:func:`_accel`; s = B', all at θ).  Energy ``½(θ̇² + η̇² + ξ̇²) + gη`` falls at the rate μF_n|u_t| while sliding
and rr F_n |θ̇| always; with rr = 0 rolling keeps it.

Rest on a face (:func:`_face`).  At a kink where b has a valley bottom (slopes s₋ < 0 < s₊: a flat face of the
body) the body can stand on both corners: θ̇ = 0 and the face slides with ξ̈ = −μσg to rest in the time
|u_t|/(μg), as long as the friction's torque is carried by the two corners (s₋ ≤ μσB ≤ s₊, from the balance of
the two normal forces); otherwise it tips onto the corner the torque turns it to.  A corner reached while
rolling or sliding (:func:`_corner`) is a sequence of impacts at the two corners of the kink, at most
``CORNER_IMPACTS``, until neither approaches the floor; when both normal velocities are below ``chatter`` the
body has landed on the face.
"""

# Everything above the marker line only makes this file importable and lintable on its own; none of it
# reaches the compiled module (the imports and OPTIONS come from kernel.HEADER there, wall_b2 and the cell
# table's column names from the wall's code and the shared search).

import math

from numba import njit

from ..billiard._search import (
    CMAX,
    INF,
    LEFT,
    RIGHT,
    SLOPE_BWD,
    SLOPE_FWD,
    TWO_PI,
    _root_step,
    wall_b1,
    wall_b2,
)

__all__ = []  # nothing public: the kernel is called through coinwall.forward.dynamics.floor.field

CACHE = True
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


# ---- friction kernel: the text from the line after this one to the end of the file is joined to the field kernel ----

# event kinds, recorded in the `side` column after the impacts (0 floor, 1 ceiling)
EV_LIFTOFF = 3      # the contact force fell to zero: flight
EV_ROLL = 4         # sliding stopped: rolling without slipping
EV_SLIP = 5         # slipping began (from rolling, or in the other direction)
EV_CORNER = 6       # a kink of b met the floor: the impacts at the next corner
EV_FACE = 7         # standing on a face (two corners): sliding to rest, or tipping onto a corner
EV_END = 8          # the contact phase ended: settled, rolling for ever, or stopped (the status says which)
EV_JAM = 9          # sliding with no consistent motion (Painlevé): the tangential impact that stops the slip
# the phase's outcomes (the caller turns them into statuses)
C_EVENT = 0         # an event was reached and handled: go on in contact
C_FLIGHT = 1        # lift-off: the state is in the air, go on with the flight search
C_SETTLED = 2       # the level fell below the valley's barrier
C_REST = 3          # at rest on a face
C_ROLLS = 4         # rolling without slipping for ever (a period completed with no event)
C_PAINLEVE = 5      # sliding has no consistent motion (D ≤ 0)
C_BUDGET = 6        # the phase's step budget is spent
C_NOTFINITE = 7     # the wall is not finite where the body is
CONTACT_STEPS = 262144      # Runge–Kutta steps of the contact phases of one toss at most
CORNER_IMPACTS = 64         # impacts at one corner at most
STEP_ANGLE = 0.25           # largest turn of θ per step (rad)
STEP_TIME = 0.5             # largest step in units of √(L/g)
STEP_TOL = 1e-10            # the Runge–Kutta step's local error at most (relative to the state's scale)
EVENT_TOL = 1e-11           # an event function below EVENT_TOL times its scale is zero
KINK_NEAR = 1e-12           # an angle this close (rad) to a kink edge is on it


@njit(**OPTIONS)
def _friction_impact(vt, ve, vx, s, h, e, mu):
    # one impact at the contact point r = (s, −h) (units of κ) with Coulomb friction μ and Stronge's energetic
    # restitution e, by Routh's integration over the normal impulse (module docstring); returns (θ̇, η̇, ξ̇, P_n).
    # Also the tangential impact of Painlevé's paradox: a contact at rest in the normal direction (u_n = 0) whose
    # slip drives it into the floor (u_n falls as P_n grows, an1 < 0): compression by friction alone, until the
    # slip stops
    un = ve - s * vt
    ut = vx - h * vt
    wtt = 1.0 + h * h
    wnn = 1.0 + s * s
    wtn = s * h
    sticks = abs(wtn) <= mu * wtt
    # the piece after slipping stops (or from the start if u_t = 0): sticking, or slipping back
    if sticks:
        k2 = -wtn / wtt
        an2 = wnn - wtn * wtn / wtt
    else:
        sg2 = 1.0 if wtn > 0.0 else -1.0
        k2 = -mu * sg2
        an2 = wnn - mu * sg2 * wtn
    if ut == 0.0:
        k1 = k2
        an1 = an2
        p1 = INF
    else:
        sg = 1.0 if ut > 0.0 else -1.0
        k1 = -mu * sg
        at1 = wtn - mu * sg * wtt
        an1 = wnn - mu * sg * wtn
        p1 = -ut / at1 if sg * at1 < 0.0 else INF
    if not (un < 0.0 or (un == 0.0 and an1 < 0.0)):
        return vt, ve, vx, 0.0  # not approaching, and no slip that would drive the contact into the floor
    # compression: u_n = 0 at pc; wc = ∫ u_n dP_n over it (< 0)
    un1 = un + an1 * p1 if p1 < INF else INF
    if an1 > 0.0 and (p1 == INF or un1 >= 0.0):
        pc = -un / an1
        wc = 0.5 * un * pc
        first = True
    else:
        pc = p1 - un1 / an2
        wc = 0.5 * p1 * (un + un1) + 0.5 * un1 * (pc - p1)
        first = False
    # restitution: ∫ u_n dP_n from pc on equals e² |wc|
    rest = e * e * (-wc)
    if first:
        x = math.sqrt(2.0 * rest / an1)
        if pc + x <= p1:
            pf = pc + x
        else:
            done = 0.5 * an1 * (p1 - pc) * (p1 - pc)
            u1 = an1 * (p1 - pc)
            left = rest - done
            pf = p1 + 2.0 * left / (u1 + math.sqrt(u1 * u1 + 2.0 * an2 * left))
    else:
        pf = pc + math.sqrt(2.0 * rest / an2)
    if pf <= p1:
        pt = k1 * pf
    else:
        pt = k1 * p1 + k2 * (pf - p1)
    return vt - s * pf - h * pt, ve + pf, vx + pt, pf


@njit(inline='always', **OPTIONS)
def _piece(x, j, c, cells):
    # B − b0, B' and B'' of the smooth piece of cell j at x: one-sided at a kink edge (the piece's own slope, its
    # curvature from just inside), so that a body standing on a kink never reads the other piece
    lo = cells[j, LEFT]
    hi = cells[j, RIGHT]
    sl = cells[j, SLOPE_FWD]
    if x < lo + KINK_NEAR and not math.isnan(sl):
        b, _, _ = wall_b2(lo, c)
        _, _, d2 = wall_b2(lo + 1e-9 * (hi - lo), c)
        d = x - lo
        return b + sl * d + 0.5 * d2 * d * d, sl + d2 * d, d2
    sr = cells[j, SLOPE_BWD]
    if x > hi - KINK_NEAR and not math.isnan(sr):
        b, _, _ = wall_b2(hi, c)
        _, _, d2 = wall_b2(hi - 1e-9 * (hi - lo), c)
        d = x - hi
        return b + sr * d + 0.5 * d2 * d * d, sr + d2 * d, d2
    return wall_b2(x, c)


@njit(inline='always', **OPTIONS)
def _accel(B, s, B2, w, sig, g, mu, rr, sw):
    # θ̈, ξ̈ and the contact force F_n on the floor: sliding with σ = sig (±1), or rolling (sig = 0), against the
    # rolling resistance's couple rr·F_n, which opposes θ̇ (sw: the sign of θ̇ over the step, 0 when it rests)
    q = s + rr * sw
    if sig == 0:
        a = (-q * (g + B2 * w * w) - B * s * w * w) / (1.0 + B * B + s * q)
        return a, s * w * w + B * a, g + s * a + B2 * w * w
    fn = (g + B2 * w * w) / (1.0 + s * q - mu * sig * s * B)
    return fn * (mu * sig * B - q), -mu * sig * fn, fn


@njit(**OPTIONS)
def _cell_of(x, cells, lookup):
    # the cell holding x in [0, 2π)
    m = cells.shape[0]
    nunif = lookup.shape[0]
    i = int(x * (nunif / TWO_PI))
    if i >= nunif:
        i = nunif - 1
    elif i < 0:
        i = 0
    j = lookup[i]
    while j < m - 1 and cells[j, RIGHT] <= x:
        j += 1
    while j > 0 and cells[j, LEFT] > x:
        j -= 1
    return j


@njit(inline='always', **OPTIONS)
def _is_kink(j, left, cells):
    # whether the left (right) edge of cell j is a kink of b
    if left:
        return not math.isnan(cells[j, SLOPE_FWD])
    return not math.isnan(cells[j, SLOPE_BWD])


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
def _level(x, B, s, w, vx, b0, g, valleys):
    # (level above b0, barrier of the valley holding x): the energy per g, with the horizontal motion (friction
    # can turn it into rotation), of a body on the floor
    lev = B - b0 + 0.5 * (w * w * (1.0 + s * s) + vx * vx) / g
    return lev, valleys[_valley(x, valleys), 1]


@njit(inline='always', **OPTIONS)
def _spin_sign(sig, B, s, w, mu, rr):
    # the sign of θ̇ the rolling resistance opposes: θ̇'s own, or from θ̇ = 0 the way the other forces turn the body
    # (0: it does not turn, the resistance's couple holding theirs, |θ̈ without it| ≤ rr F_n)
    if w > 0.0:
        return 1.0
    if w < 0.0:
        return -1.0
    k = mu * sig * B - s if sig != 0 else -s
    if abs(k) <= rr:
        return 0.0
    return 1.0 if k > 0.0 else -1.0


@njit(**OPTIONS)
def _roll_or_slip(B, s, B2, w, g, mu, rr):
    # the phase at u_t = 0: 0 (rolling) if rolling needs at most μF_n, else the direction σ of the slip that
    # starts (friction then pushes with −σμF_n, opposing the force rolling would need); 2 if neither is consistent
    _a, ft, fn = _accel(B, s, B2, w, 0, g, mu, rr, _spin_sign(0, B, s, w, mu, rr))
    if abs(ft) <= mu * fn:
        return 0
    sig = -1 if ft > 0.0 else 1
    a2, f2, _fn2 = _accel(B, s, B2, w, sig, g, mu, rr, _spin_sign(sig, B, s, w, mu, rr))
    udot = f2 - s * w * w - B * a2      # d(u_t)/dt under that slip
    if sig * udot > 0.0:
        return sig
    return 2


@njit(inline='always', **OPTIONS)
def _kink_cells(j, forward, cells):
    # the cells left and right of the kink at the right (forward) or left edge of cell j, and the kink's angle
    m = cells.shape[0]
    if forward:
        return j, (j + 1 if j + 1 < m else 0), cells[j, RIGHT]
    return (j - 1 if j > 0 else m - 1), j, cells[j, LEFT]


@njit(**OPTIONS)
def _corner(jl, jr, xk, vt, ve, vx, b0, e, mu, chatter, c, cells):
    # the body is at the kink xk between cells jl and jr (pieces − and +, slopes sm < sp for a convex body):
    # impacts at the corner that approaches the floor, alternately, until neither does (at most
    # CORNER_IMPACTS).  Returns (θ̇, η̇, ξ̇, impacts, next): next 0 in the air, −1/+1 on the piece left/right of the
    # kink (its normal velocity taken away: below `chatter`), 2 on both (a face)
    sm = cells[jl, SLOPE_BWD]
    sp = cells[jr, SLOPE_FWD]
    b, _, _ = wall_b2(xk, c)
    h = b0 + b
    impacts = 0
    small = 1e-14 * (abs(vt) * (1.0 + abs(sm) + abs(sp)) + abs(ve) + chatter)
    for _ in range(CORNER_IMPACTS):
        um = ve - sm * vt
        up = ve - sp * vt
        if up < -small and up <= um:
            vt, ve, vx, _p = _friction_impact(vt, ve, vx, sp, h, e, mu)
        elif um < -small:
            vt, ve, vx, _p = _friction_impact(vt, ve, vx, sm, h, e, mu)
        else:
            break
        impacts += 1
    um = ve - sm * vt
    up = ve - sp * vt
    if um < chatter and up < chatter:
        # landed on the face: θ̇ and η̇ are gone; the face slides on with the contact's slip velocity (never faster
        # than the centre moved)
        ut = vx - h * vt
        return 0.0, 0.0, ut if abs(ut) <= abs(vx) else vx, impacts, 2
    if vt > 0.0 and up < chatter:
        return vt, sp * vt, vx, impacts, 1
    if vt < 0.0 and um < chatter:
        return vt, sm * vt, vx, impacts, -1
    return vt, ve, vx, impacts, 0


@njit(**OPTIONS)
def _landing(th, vt, ve, vx, b0, e, mu, chatter, c, cells, lookup):
    # a floor impact found by the flight search at θ = th: on a kink of b (both corners of a face at the floor) the
    # impacts at the two corners (_corner), or, when the face lands flat (the two corners approach alike) on a
    # valley bottom (s₋ ≤ 0 ≤ s₊), one impact through the centre of mass (the two corners' impulses together
    # carry no torque); elsewhere the caller's single impact.  Returns (kink?, θ, θ̇, η̇, ξ̇, impacts, slope of
    # the piece the body moves over, for the gap's rate)
    j = _cell_of(th, cells, lookup)
    m = cells.shape[0]
    if _is_kink(j, True, cells) and abs(th - cells[j, LEFT]) <= KINK_NEAR:
        jl, jr, xk = (j - 1 if j > 0 else m - 1), j, cells[j, LEFT]
    elif _is_kink(j, False, cells) and abs(th - cells[j, RIGHT]) <= KINK_NEAR:
        jl, jr, xk = j, (j + 1 if j + 1 < m else 0), cells[j, RIGHT]
    else:
        return False, th, vt, ve, vx, 0, 0.0
    sm = cells[jl, SLOPE_BWD]
    sp = cells[jr, SLOPE_FWD]
    if xk >= TWO_PI:
        xk -= TWO_PI
    if sm <= 0.0 <= sp and abs(vt) * (sp - sm) <= 1e-9 * abs(ve):
        b, _, _ = wall_b2(xk, c)
        vt, ve, vx, _p = _friction_impact(vt, ve, vx, 0.0, b0 + b, e, mu)
        return True, xk, vt, ve, vx, 1, 0.0
    vt, ve, vx, hits, _nxt = _corner(jl, jr, xk, vt, ve, vx, b0, e, mu, chatter, c, cells)
    if vt > 0.0:
        return True, xk, vt, ve, vx, hits, sp
    if vt < 0.0:
        return True, xk, vt, ve, vx, hits, sm
    return True, xk, vt, ve, vx, hits, 0.0


@njit(**OPTIONS)
def _liftoff(x, w, eta, ve, b0, g, tol, c, cells):
    # the free flight from a lift-off (gap 0, gap rate 0, gap acceleration −N ≥ 0, opening slowly): sampled at
    # times t_k until the gap exceeds 1000 tol, each step short enough that the gap between two samples cannot
    # fall more than tol below the smaller of them (f'' ≥ −K, K = g + θ̇² max b'': f ≥ min(f_k, f_k+1) − KΔ²/8).
    # Returns (t, gap): gap > 0 when the flight is clear (strictly inside the table at t), ≤ 0 if the body came
    # back to the floor first (a re-contact at t)
    cmax = cells[0, CMAX]
    for k in range(1, cells.shape[0]):
        cmax = max(cmax, cells[k, CMAX])
    K = g + w * w * cmax
    target = 1000.0 * tol
    t = 0.0
    f = 0.0
    for _ in range(100000):
        if K <= 0.0:  # the gap is convex: it only opens; one sample far enough
            dt = math.sqrt(2.0 * target / g) if g > 0.0 else 1.0
        else:
            dt = math.sqrt(8.0 * (tol + f) / K)
        for _half in range(60):
            tn = t + dt
            b, _ = wall_b1(x + w * tn, c)
            fn = eta + ve * tn - 0.5 * g * tn * tn - b0 - b
            if K <= 0.0 or fn >= f or dt * dt * K <= 8.0 * (tol + fn):
                break
            dt *= 0.5
        if fn < -tol:
            return tn, fn
        t = tn
        f = fn
        if f >= target:
            return t, f
    return t, f


@njit(**OPTIONS)
def _face(jl, jr, xk, vx, b0, g, mu, vtol, c, cells):
    # the body stands on the kink xk (a face: both corners on the floor, θ̇ = 0) sliding with ξ̇ = vx (|vx| ≤ vtol,
    # the chattering limit's speed: standing).  Returns
    # (dt, ξ̇, next, σ): next 2 at rest after sliding for dt, or −1/+1 tipped onto the piece left/right of the
    # kink (at once, sliding with σ, or after sliding to a stop, σ = 0).  The corners' normal forces F₋, F₊ ≥ 0
    # carry the weight and the friction's torque: s₋F₋ + s₊F₊ = μσB(F₋ + F₊) (θ̈ = 0), possible iff
    # s₋ ≤ μσB ≤ s₊
    sm = cells[jl, SLOPE_BWD]
    sp = cells[jr, SLOPE_FWD]
    b, _, _ = wall_b2(xk, c)
    B = b0 + b
    dt = 0.0
    if abs(vx) <= vtol:  # a slide shorter than the chattering height: standing
        vx = 0.0
    if vx != 0.0:
        sig = 1 if vx > 0.0 else -1
        lever = mu * sig * B
        if lever > sp:
            return 0.0, vx, 1, sig
        if lever < sm:
            return 0.0, vx, -1, sig
        dt = abs(vx) / (mu * g)
        vx = 0.0
    if sm > 0.0:
        return dt, vx, -1, 0
    if sp < 0.0:
        return dt, vx, 1, 0
    return dt, vx, 2, 0


@njit(inline='always', **OPTIONS)
def _kink_step(d, dd, ddd, A, J):
    # a time for which the distance d ≥ 0 to a kink stays ≥ 0, its rate being dd and its second derivative ddd
    # now, |d''| ≤ A and |d'''| ≤ J over the step: the larger of the second- and third-order certified steps
    tau = _root_step(max(d, 0.0), dd, A)
    if dd >= 0.0 and J > 0.0:
        q = 0.25 * ddd * ddd + (2.0 / 3.0) * J * dd
        if q >= 0.0:
            tau = max(tau, 3.0 * (0.5 * ddd + math.sqrt(q)) / J)
    return tau


@njit(**OPTIONS)
def _start_phase(B, s, B2, w, vx, g, mu, rr):
    # the phase a body takes up on the floor: sliding with σ = sign(u_t), or at u_t = 0 rolling or slipping
    # (_roll_or_slip; 2: no consistent motion)
    u = vx - B * w
    tol = EVENT_TOL * (abs(vx) + abs(B * w))
    if u > tol:
        return 1
    if u < -tol:
        return -1
    return _roll_or_slip(B, s, B2, w, g, mu, rr)
