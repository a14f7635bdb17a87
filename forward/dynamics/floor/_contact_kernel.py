"""The contact phase, compiled by numba: a body sliding or rolling on the floor, integrated to its next event.

Source as people and tools read it, never imported by coinwall: :mod:`.fieldkernel` joins the text after the
marker line to the friction kernel's (:mod:`._friction_kernel`, whose docstring has the equations of motion)
and the field kernel's.  :func:`_contact` follows one phase: the events at the current state first (the level
below its valley's barrier, rolling against its resistance come to a stop, Painlevé, lift-off, sliding
stopping, rolling slipping, a kink reached), then one step of the integration as long as the bounds allow.

The events and why none is passed
---------------------------------
The events are the zeros of functions of the state: D (sliding's determinant: Painlevé's paradox, resolved by
the tangential impact), N = g + B''θ̇² (lift-off while sliding), σu_t (sliding stops), μF_n ∓ F_t (rolling needs
more friction than there is), θ̇ (with a rolling resistance: its couple turns round), and the distances to the
kinks at the ends of the piece.  Every step is at most as long as the events allow, by bounds on their rates
over the step (conservative advancement, as the flight's search): over the step ``|θ̇| ≤ W``; the wall's
derivatives are bounded from their values at θ and the cell's bounds of |b'''| and |b''''| (the cell table's,
sampled with a checked margin like the search's other bounds); these bound |θ̈| (A), |θ⃛| (J), the rate L_k of
each event function and D from below, and a step τ ≤ h_k/L_k cannot carry h_k through zero (D keeps this step
at half its value: D ≥ D/2 over the step is what bounds F_n).  The other event functions are met by second-order
steps: the rate ḣ_k now is known exactly and the second derivative bounded, |ḧ_k| ≤ K_k over the step, so that
h_k + ḣ_k τ − ½K_k τ² > 0 (``_root_step``) keeps h_k from zero and a zero is reached in a few steps, not by a
fixed share of what is left at each (the slip, N and μF_n ∓ F_t take the longer of their first- and second-order
steps).  For θ̇ and the distances to the kinks K is A or J; for the slip σu_t it is built from the bounds of Ḟ_n,
θ̈ and θ⃛; the rates of N (Ṅ = B'''θ̇³ + 2B''θ̇θ̈) and of μF_n ∓ F_t (through θ⃛ = (ṅ − θ̈ṁ)/m, the rolling
θ̈ = n/m differentiated) take the wall's b''' at θ (``wall_b3``, generated with the wall's other code), their
second derivatives the cell's bound of |b''''| (for rolling through a bound of |θ⁗|, from mθ⁗ = n̈ − 2ṁθ⃛ − m̈θ̈).
On the quadratic continuation of a piece at its kink (the last 1e-12 rad, :func:`._friction_kernel._piece`), and
for an expression whose b''' has no generated code (``wall_b3`` gives NaN), N and μF_n ∓ F_t take first-order
steps only.  An event whose function has just been zero
(the slip that just started) is looked for again once its function has left a band of 10 tolerances.  The
declared approximations are the flight's (cell bounds from dense sampling, the contact tolerance) and the
integration's: Dormand–Prince 5(4) steps whose local error is at most ``STEP_TOL`` (1e-10 of the state's
scale; the rolling disc and Housner's block in the tests are within 1e-10 of their closed forms), the step
shortened and repeated where it is not.  The time at which a toss's level falls below its barrier is known to
within a step (the level is checked at each step; it only falls).

Lift-off.  The free flight from a lift-off opens its gap only cubically; it is sampled until the gap is 1000
contact tolerances, each sample close enough to the last that the gap cannot dip more than one tolerance below
them between (f'' ≥ −(g + θ̇² max b''): :func:`._friction_kernel._liftoff`), and handed to the flight search from
there; a gap that comes back below the floor first is a re-contact (a floor impact).

Never an endless loop: a toss's phases take at most ``CONTACT_STEPS`` steps together, each event a row of the
caller's bounded record; rolling without resistance that completes a period (three turning points, or a whole
turn) without an event would repeat for ever and stops at once ("rolls"); a corner's impacts are capped.
"""

# Everything above the marker line only makes this file importable and lintable on its own.

import math

from numba import njit

from ..billiard._search import (
    D3MAX,
    D4MAX,
    INF,
    LEFT,
    RIGHT,
    SLOPE_BWD,
    SLOPE_FWD,
    TWO_PI,
    _root_step,
    wall_b2,
    wall_b3,
)
from ._friction_kernel import (
    C_BUDGET,
    C_EVENT,
    C_FLIGHT,
    C_NOTFINITE,
    C_PAINLEVE,
    C_REST,
    C_ROLLS,
    C_SETTLED,
    EV_CORNER,
    EV_JAM,
    EV_LIFTOFF,
    EV_ROLL,
    EV_SLIP,
    EVENT_TOL,
    KINK_NEAR,
    STEP_ANGLE,
    STEP_TIME,
    STEP_TOL,
    _accel,
    _corner,
    _friction_impact,
    _is_kink,
    _kink_cells,
    _kink_step,
    _level,
    _liftoff,
    _piece,
    _roll_or_slip,
    _spin_sign,
    _start_phase,
)

__all__ = []  # nothing public: the kernel is called through coinwall.forward.dynamics.floor.field

CACHE = True
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


# ---- contact kernel: the text from the line after this one to the end of the file is joined to the field kernel ----

@njit(inline='always', **OPTIONS)
def _first_or_second(h, hdot, K, L):
    # a step for which the event function h > 0 keeps its sign: |ḣ| ≤ L over it (first order), or ḣ now and
    # |ḧ| ≤ K over it (second order, a zero met in a few steps): the longer; first order where ḣ is unknown (NaN)
    # or K is not finite (the second-order step is NaN then, and no comparison takes it)
    tau = h / L
    second = _root_step(h, hdot, K)
    return second if second > tau else tau


@njit(inline='always', **OPTIONS)
def _side_angle(xk, wraps, jk, m):
    # the kink's angle as seen from cell jk (2π for the last cell's right edge, 0 for the first's left edge)
    if jk == 0 and xk >= TWO_PI:
        return xk - TWO_PI, wraps + 1
    if jk == m - 1 and xk <= 0.0:
        return xk + TWO_PI, wraps - 1
    return xk, wraps


@njit(**OPTIONS)
def _contact(x, wraps, j, w, vx, sig, b0, g, e, mu, rr, chatter, tol, lscale, c, cells, valleys, settle, budget):
    # one contact phase on the piece of cell j, from θ = x (+ wraps turns; x within the cell), θ̇ = w, ξ̇ = vx,
    # sliding with σ = sig (±1) or rolling (sig = 0) against the rolling resistance rr, to its next event (module
    # docstring).  Returns (code, kind, x, wraps, j, w, vx, sig, η, η̇, dt, impacts, mode, leave, steps): code C_*;
    # kind the event (EV_*); mode 1: in contact on cell j; 2: on the face at the right edge of cell j; 0: in the
    # air, strictly inside the table (leave NaN) or leaving the floor at a kink (leave: the gap's rate there);
    # 3: back on the floor just after a lift-off (a re-contact: the caller's floor impact).  budget: the steps
    # this phase may take; the caller reads how many it took from the time spent
    m = cells.shape[0]
    B, s, B2 = _piece(x, j, c, cells)
    B += b0
    if sig == 2:  # no consistent motion on the floor from here (Painlevé)
        return C_PAINLEVE, 0, x, wraps, j, w, vx, sig, B, s * w, 0.0, 0, 1, math.nan, 0
    tscale = math.sqrt(lscale / g)
    wscale = 1.0 / tscale
    time = 0.0
    if sig == 0:
        vx = B * w
    energy = 0.5 * w * w * (1.0 + B * B + s * s) + g * B
    uscale = abs(vx) + abs(B * w) + math.sqrt(g * lscale)
    sw = _spin_sign(sig, B, s, w, mu, rr)
    armed = False
    turns = 0
    start = x + wraps * TWO_PI
    tacc = 0.01 * tscale  # the accuracy's step, adapted (Dormand–Prince's error estimate)
    for _step in range(budget):
        if not (abs(B) < INF and abs(s) < INF and abs(B2) < INF):
            return C_NOTFINITE, 0, x, wraps, j, w, vx, sig, B, s * w, time, 0, 1, math.nan, _step
        if settle:
            lev, bar = _level(x, B, s, w, vx, b0, g, valleys)
            if lev < bar:
                return C_SETTLED, 0, x, wraps, j, w, vx, sig, B, s * w, time, 0, 1, math.nan, _step
        if rr > 0.0 and sw * w <= EVENT_TOL * wscale:
            # θ̇ has come to 0 against the rolling resistance: it turns back, or the resistance holds it
            w = 0.0
            sw = _spin_sign(sig, B, s, 0.0, mu, rr)
            if sw == 0.0:
                if sig != 0:  # sliding without turning (F_n = g, θ fixed) to a stop, in closed form
                    time += abs(vx) / (mu * g)
                vx = 0.0
                if abs(s) <= rr:
                    return C_REST, 0, x, wraps, j, 0.0, 0.0, 0, B, 0.0, time, 0, 1, math.nan, _step
                if sig != 0:
                    return C_EVENT, EV_ROLL, x, wraps, j, 0.0, 0.0, 0, B, 0.0, time, 0, 1, math.nan, _step
                sw = -1.0 if s > 0.0 else 1.0
        a, fx, fn = _accel(B, s, B2, w, sig, g, mu, rr, sw)
        D = 1.0
        N = 0.0
        u = 0.0
        hp = 0.0
        hm = 0.0
        lift = False
        # ---- the events at this state
        if sig != 0:
            D = 1.0 + s * (s + rr * sw) - mu * sig * s * B
            N = g + B2 * w * w
            u = sig * (vx - B * w)
            if D <= EVENT_TOL:
                # no consistent sliding (Painlevé's paradox): the tangential impact, in which friction alone presses
                # the contact into the floor until the slip stops (Stronge's law, as any impact)
                vt2, ve2, vx2, _p = _friction_impact(w, s * w, vx, s, B, e, mu)
                rate = ve2 - s * vt2
                if rate > chatter:
                    return C_FLIGHT, EV_JAM, x, wraps, j, vt2, vx2, 0, B, ve2, time, 1, 0, rate, _step
                nsig = _start_phase(B, s, B2, vt2, vx2, g, mu, rr)
                if nsig == 2 or _p == 0.0:
                    return C_PAINLEVE, 0, x, wraps, j, w, vx, sig, B, s * w, time, 0, 1, math.nan, _step
                return C_EVENT, EV_JAM, x, wraps, j, vt2, vx2, nsig, B, s * vt2, time, 1, 1, math.nan, _step
            lift = N <= EVENT_TOL * g
            if not lift:
                if armed:
                    stick = u <= EVENT_TOL * uscale
                else:
                    armed = u > 10.0 * EVENT_TOL * uscale
                    stick = u < -10.0 * EVENT_TOL * uscale  # the slip turned back at once: it sticks after all
                if stick:
                    vx = B * w
                    nxt = _roll_or_slip(B, s, B2, w, g, mu, rr)
                    if nxt == 2:
                        return C_PAINLEVE, 0, x, wraps, j, w, vx, sig, B, s * w, time, 0, 1, math.nan, _step
                    return (C_EVENT, EV_ROLL if nxt == 0 else EV_SLIP, x, wraps, j, w, vx, nxt, B, s * w, time, 0, 1,
                            math.nan, _step)
        else:
            hp = mu * fn - fx
            hm = mu * fn + fx
            if armed:
                slip = min(hp, hm) <= EVENT_TOL * g
            else:
                armed = min(hp, hm) > 10.0 * EVENT_TOL * g
                slip = min(hp, hm) < -10.0 * EVENT_TOL * g
            if slip:
                if fn <= EVENT_TOL * g:
                    lift = True
                else:
                    return (C_EVENT, EV_SLIP, x, wraps, j, w, vx, -1 if fx > 0.0 else 1, B, s * w, time, 0, 1,
                            math.nan, _step)
        if lift:
            t, gap = _liftoff(x, w, B, s * w, b0, g, tol, c, cells)
            return (C_FLIGHT, EV_LIFTOFF, x + w * t, wraps, j, w, vx, sig, B + s * w * t - 0.5 * g * t * t,
                    s * w - g * t, time + t, 0, 0 if gap > 0.0 else 3, math.nan, _step)
        # ---- a kink at an end of the piece reached: the corner meets the floor
        lo = cells[j, LEFT]
        hi = cells[j, RIGHT]
        kink_lo = _is_kink(j, True, cells)
        kink_hi = _is_kink(j, False, cells)
        corner = False
        forward = True
        if kink_hi and x >= hi - KINK_NEAR and (w > 0.0 or (w == 0.0 and a >= 0.0)):
            corner = True
        elif kink_lo and x <= lo + KINK_NEAR and (w < 0.0 or (w == 0.0 and a <= 0.0)):
            corner = True
            forward = False
        if corner:
            jl, jr, xk = _kink_cells(j, forward, cells)
            bk, _, _ = wall_b2(xk, c)
            Bk = b0 + bk
            vt2, ve2, vx2, hits, nxt = _corner(jl, jr, xk, w, s * w, vx, b0, e, mu, chatter, c, cells)
            if nxt == 2:
                xl, wl = _side_angle(xk, wraps, jl, m)
                return C_EVENT, EV_CORNER, xl, wl, jl, 0.0, vx2, 0, Bk, 0.0, time, hits, 2, math.nan, _step
            if nxt == 0:
                jn = jr if vt2 > 0.0 else jl
                xn, wn = _side_angle(xk, wraps, jn, m)
                rate = ve2 - (cells[jr, SLOPE_FWD] if vt2 > 0.0 else cells[jl, SLOPE_BWD]) * vt2
                return C_FLIGHT, EV_CORNER, xn, wn, jn, vt2, vx2, 0, Bk, ve2, time, hits, 0, rate, _step
            jn = jr if nxt == 1 else jl
            xn, wn = _side_angle(xk, wraps, jn, m)
            Bn, sn, B2n = _piece(xn, jn, c, cells)
            Bn += b0
            nsig = _start_phase(Bn, sn, B2n, vt2, vx2, g, mu, rr)
            if nsig == 2:
                return C_PAINLEVE, EV_CORNER, xn, wn, jn, vt2, vx2, 0, Bn, sn * vt2, time, hits, 1, math.nan, _step
            return C_EVENT, EV_CORNER, xn, wn, jn, vt2, vx2, nsig, Bn, sn * vt2, time, hits, 1, math.nan, _step
        # ---- the step: bounds over it, then the events' and the kinks' limits
        aw = abs(w)
        W = 1.25 * aw + 1e-3 * wscale
        tau = min(tacc, STEP_TIME * tscale)
        if aw > 0.0:
            tau = min(tau, STEP_ANGLE / aw)
        jb = j - 1 if j > 0 else m - 1
        jf = j + 1 if j + 1 < m else 0
        S3 = cells[j, D3MAX]
        S4 = cells[j, D4MAX]
        if not kink_lo:
            S3 = max(S3, cells[jb, D3MAX])
            S4 = max(S4, cells[jb, D4MAX])
            tau = min(tau, (x - lo + (cells[jb, RIGHT] - cells[jb, LEFT])) / W)
        if not kink_hi:
            S3 = max(S3, cells[jf, D3MAX])
            S4 = max(S4, cells[jf, D4MAX])
            tau = min(tau, (hi - x + (cells[jf, RIGHT] - cells[jf, LEFT])) / W)
        # B''' now: the wall's, except on the quadratic continuation of a piece at its kink (_piece), where the
        # rates below are left unknown (NaN: first-order steps)
        B3 = math.nan
        if not ((kink_lo and x < lo + KINK_NEAR) or (kink_hi and x > hi - KINK_NEAR)):
            B3 = wall_b3(x, c)
        delta = W * tau
        aB2 = abs(B2)
        S2 = aB2 + S3 * delta
        S1 = abs(s) + aB2 * delta + 0.5 * S3 * delta * delta
        S0 = abs(B) + abs(s) * delta + 0.5 * aB2 * delta * delta + S3 * delta * delta * delta / 6.0
        LD = 0.0
        Dmin = 1.0
        Fmax = 0.0
        Mi = 1.0 / (1.0 - 0.25 * rr * rr)  # 1/(1 + B² + s(s ± rr)) ≤ Mi
        if sig != 0:
            LD = W * (2.0 * S1 * S2 + rr * S2 + mu * (S2 * S0 + S1 * S1))
            if LD > 0.0:
                tau = min(tau, 0.5 * D / LD)
            Dmin = 0.5 * D
            Fmax = (g + S2 * W * W) / Dmin
            A = Fmax * (S1 + mu * S0 + rr)
        else:
            A = Mi * ((S1 + rr) * (g + S2 * W * W) + S0 * S1 * W * W)
        if aw + A * tau > W:
            tau = (W - aw) / A
        if sig != 0:
            LN = S3 * W * W * W + 2.0 * S2 * W * A
            Lu = mu * Fmax + S1 * W * W + S0 * A
            J = (LN + Fmax * LD) / Dmin * (S1 + mu * S0 + rr) + Fmax * (S2 + mu * S1) * W
            if LN > 0.0:
                # Ṅ = B'''θ̇³ + 2B''θ̇θ̈ now, N̈ = B''''θ̇⁴ + 5B'''θ̇²θ̈ + 2B''(θ̈² + θ̇θ⃛) bounded over the step
                KN = S4 * W * W * W * W + 5.0 * S3 * W * W * A + 2.0 * S2 * (A * A + W * J)
                tau = min(tau, _first_or_second(N, B3 * w * w * w + 2.0 * B2 * w * a, KN, LN))
            if armed and Lu > 0.0:
                # u̇ = σ(ξ̈ − B'θ̇² − Bθ̈) now, ü = σ(−μσḞ_n − B''θ̇³ − 3B'θ̇θ̈ − Bθ⃛) bounded over the step: the
                # second-order step (a zero met in a few steps, not geometrically) or the first-order one
                Ku = mu * (LN + Fmax * LD) / Dmin + S2 * W * W * W + 3.0 * S1 * W * A + S0 * J
                tau = min(tau, max(u / Lu, _root_step(u, sig * (fx - s * w * w - B * a), Ku)))
        else:
            # θ̈ = n/m with n = −(s + rr sw)(g + B''θ̇²) − B s θ̇², m = 1 + B² + s(s + rr sw): θ⃛ = (ṅ − θ̈ ṁ)/m
            ndot = (S2 * W * (g + S2 * W * W) + (S1 + rr) * (S3 * W * W * W + 2.0 * S2 * W * A)
                    + (S1 * S1 + S0 * S2) * W * W * W + 2.0 * S0 * S1 * W * A)
            mdot = (2.0 * S0 * S1 + 2.0 * S1 * S2 + rr * S2) * W
            J = Mi * (ndot + A * mdot)
            Lh = mu * (3.0 * S2 * W * A + S1 * J + S3 * W * W * W) + S2 * W * W * W + 3.0 * S1 * W * A + S0 * J
            if armed and Lh > 0.0:
                # μF_n ∓ F_t: their rates now, from Ḟ_n = 3B''θ̇θ̈ + B'θ⃛ + B'''θ̇³ and Ḟ_t = B''θ̇³ + 3B'θ̇θ̈ + Bθ⃛
                # (θ⃛ = (ṅ − θ̈ṁ)/m exactly), and their second derivatives bounded over the step through
                # |θ⁗| = |n̈ − 2ṁθ⃛ − m̈θ̈|/m ≤ Q: F̈_n = B''''θ̇⁴ + 6B'''θ̇²θ̈ + 3B''θ̈² + 4B''θ̇θ⃛ + B'θ⁗,
                # F̈_t = B'''θ̇⁴ + 6B''θ̇²θ̈ + 3B'θ̈² + 4B'θ̇θ⃛ + Bθ⁗ (n = −qP − BB'θ̇², P = g + B''θ̇², q = B' + rr sw)
                q = s + rr * sw
                P = g + B2 * w * w
                jn = (-B2 * w * P - q * (B3 * w * w * w + 2.0 * B2 * w * a) - (s * s + B * B2) * w * w * w
                      - 2.0 * B * s * w * a - a * (2.0 * B * s + B2 * (q + s)) * w) / (1.0 + B * B + s * q)
                dfn = 3.0 * B2 * w * a + s * jn + B3 * w * w * w
                dft = B2 * w * w * w + 3.0 * s * w * a + B * jn
                W4 = W * W * W * W
                AJ = A * A + W * J
                n2 = ((S3 * W * W + S2 * A) * (g + S2 * W * W) + 2.0 * S2 * W * (S3 * W * W * W + 2.0 * S2 * W * A)
                      + (S1 + rr) * (S4 * W4 + 5.0 * S3 * W * W * A + 2.0 * S2 * AJ)
                      + (3.0 * S1 * S2 + S0 * S3) * W4 + 5.0 * (S1 * S1 + S0 * S2) * W * W * A + 2.0 * S0 * S1 * AJ)
                m2 = ((2.0 * S1 * S1 + 2.0 * S0 * S2 + 2.0 * S2 * S2 + (2.0 * S1 + rr) * S3) * W * W
                      + (2.0 * S0 * S1 + (2.0 * S1 + rr) * S2) * A)
                Q = Mi * (n2 + 2.0 * J * mdot + A * m2)
                Kh = (mu * (S4 * W4 + 6.0 * S3 * W * W * A + 3.0 * S2 * A * A + 4.0 * S2 * W * J + S1 * Q)
                      + S3 * W4 + 6.0 * S2 * W * W * A + 3.0 * S1 * A * A + 4.0 * S1 * W * J + S0 * Q)
                tau = min(tau, _first_or_second(hp, mu * dfn - dft, Kh, Lh),
                          _first_or_second(hm, mu * dfn + dft, Kh, Lh))
        if rr > 0.0:  # θ̇ must not pass zero inside a step (the resistance turns round there)
            tau = min(tau, _root_step(max(sw * w, 0.0), sw * a, J))
        if kink_hi:
            tau = min(tau, _kink_step(hi - x, -w, -a, A, J))
        if kink_lo:
            tau = min(tau, _kink_step(x - lo, w, a, A, J))
        if not (tau > 0.0):
            tau = 0.0
        # ---- one Dormand–Prince 5(4) step of (θ, θ̇, ξ̇), repeated shorter while its error estimate is too large
        tmax = tau
        for _try in range(40):
            xn, wn, vxn, err = _dp_step(x, w, vx, a, fx, tau, j, c, cells, b0, sig, g, mu, rr, sw,
                                        STEP_TOL * (aw + wscale), STEP_TOL * uscale)
            if err <= 1.0:
                break
            tau *= max(0.2, 0.9 * err ** -0.2)
        grow = 5.0 if err <= 1e-10 else min(5.0, max(0.2, 0.9 * err ** -0.2))
        tacc = max(tacc, tau * grow) if tau < tmax else tau * grow
        time += tau
        # the cell: across plain edges; never past a kink (the steps stop short of it, rounding aside)
        while xn > cells[j, RIGHT]:
            if _is_kink(j, False, cells):
                xn = cells[j, RIGHT]
                break
            j = j + 1 if j + 1 < m else 0
            if j == 0:
                xn -= TWO_PI
                wraps += 1
        while xn < cells[j, LEFT]:
            if _is_kink(j, True, cells):
                xn = cells[j, LEFT]
                break
            j = j - 1 if j > 0 else m - 1
            if j == m - 1:
                xn += TWO_PI
                wraps -= 1
        x = xn
        B, s, B2 = _piece(x, j, c, cells)
        B += b0
        if rr > 0.0 and sw * wn < 0.0:
            wn = 0.0
        if sig == 0:
            if rr == 0.0:
                # rolling keeps its energy: θ̇ back on the energy integral (not near a turning point, where θ̇ is
                # ill-conditioned in θ: there the step's own θ̇ is kept)
                p = 2.0 * (energy - g * B) / (1.0 + B * B + s * s)
                if p > 1e-6 * g * lscale:
                    wn = math.sqrt(p) if wn > 0.0 else -math.sqrt(p)
                if w != 0.0 and (wn > 0.0) != (w > 0.0):
                    turns += 1
                if turns >= 3 or abs(x + wraps * TWO_PI - start) >= TWO_PI:
                    return C_ROLLS, 0, x, wraps, j, wn, B * wn, sig, B, s * wn, time, 0, 1, math.nan, _step
            vxn = B * wn  # no slip
        w = wn
        vx = vxn
    return C_BUDGET, 0, x, wraps, j, w, vx, sig, B, s * w, time, 0, 1, math.nan, budget


@njit(inline='always', **OPTIONS)
def _dp_rate(x, w, tau, j, c, cells, b0, sig, g, mu, rr, sw):
    # θ̈ and ξ̈ at a stage of the step
    Bs, ss, B2s = _piece(x, j, c, cells)
    a, f, _fn = _accel(Bs + b0, ss, B2s, w, sig, g, mu, rr, sw)
    return a, f


@njit(**OPTIONS)
def _dp_step(x, w, vx, a1, f1, h, j, c, cells, b0, sig, g, mu, rr, sw, wtol, vtol):
    # one Dormand–Prince 5(4) step of θ' = θ̇, θ̇' = θ̈(θ, θ̇), ξ̇' = ξ̈(θ, θ̇) from (x, w, vx) with the rates (a1, f1)
    # there; returns the fifth-order state and the error estimate in units of the tolerances (θ: STEP_TOL rad,
    # θ̇: wtol, ξ̇: vtol)
    x2 = x + h * (w / 5.0)
    w2 = w + h * (a1 / 5.0)
    a2, _f2 = _dp_rate(x2, w2, h, j, c, cells, b0, sig, g, mu, rr, sw)  # (ξ̈'s weight there is 0)
    x3 = x + h * (3.0 / 40.0 * w + 9.0 / 40.0 * w2)
    w3 = w + h * (3.0 / 40.0 * a1 + 9.0 / 40.0 * a2)
    a3, f3 = _dp_rate(x3, w3, h, j, c, cells, b0, sig, g, mu, rr, sw)
    x4 = x + h * (44.0 / 45.0 * w - 56.0 / 15.0 * w2 + 32.0 / 9.0 * w3)
    w4 = w + h * (44.0 / 45.0 * a1 - 56.0 / 15.0 * a2 + 32.0 / 9.0 * a3)
    a4, f4 = _dp_rate(x4, w4, h, j, c, cells, b0, sig, g, mu, rr, sw)
    x5 = x + h * (19372.0 / 6561.0 * w - 25360.0 / 2187.0 * w2 + 64448.0 / 6561.0 * w3 - 212.0 / 729.0 * w4)
    w5 = w + h * (19372.0 / 6561.0 * a1 - 25360.0 / 2187.0 * a2 + 64448.0 / 6561.0 * a3 - 212.0 / 729.0 * a4)
    a5, f5 = _dp_rate(x5, w5, h, j, c, cells, b0, sig, g, mu, rr, sw)
    x6 = x + h * (9017.0 / 3168.0 * w - 355.0 / 33.0 * w2 + 46732.0 / 5247.0 * w3 + 49.0 / 176.0 * w4
                  - 5103.0 / 18656.0 * w5)
    w6 = w + h * (9017.0 / 3168.0 * a1 - 355.0 / 33.0 * a2 + 46732.0 / 5247.0 * a3 + 49.0 / 176.0 * a4
                  - 5103.0 / 18656.0 * a5)
    a6, f6 = _dp_rate(x6, w6, h, j, c, cells, b0, sig, g, mu, rr, sw)
    b1, b3, b4, b5, b6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
    xn = x + h * (b1 * w + b3 * w3 + b4 * w4 + b5 * w5 + b6 * w6)
    wn = w + h * (b1 * a1 + b3 * a3 + b4 * a4 + b5 * a5 + b6 * a6)
    vxn = vx + h * (b1 * f1 + b3 * f3 + b4 * f4 + b5 * f5 + b6 * f6)
    a7, f7 = _dp_rate(xn, wn, h, j, c, cells, b0, sig, g, mu, rr, sw)
    e1, e3, e4, e5, e6, e7 = (71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
                              -1.0 / 40.0)
    ex = abs(h * (e1 * w + e3 * w3 + e4 * w4 + e5 * w5 + e6 * w6 + e7 * wn)) / STEP_TOL
    ew = abs(h * (e1 * a1 + e3 * a3 + e4 * a4 + e5 * a5 + e6 * a6 + e7 * a7)) / wtol
    ev = abs(h * (e1 * f1 + e3 * f3 + e4 * f4 + e5 * f5 + e6 * f6 + e7 * f7)) / vtol
    return xn, wn, vxn, max(ex, ew, ev)
