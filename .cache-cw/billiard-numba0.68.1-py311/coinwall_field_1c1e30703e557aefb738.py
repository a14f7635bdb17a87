import math
import numpy as np
from numba import carray, njit, prange, types
from numba.extending import intrinsic

OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


@njit(**OPTIONS)
def wall_b2(phi, c):
    # c = [a0, n, cos_1..cos_n, sin_1..sin_n]; cos kφ, sin kφ by the angle-addition
    # recurrence (one cos and one sin call instead of 2n; error grows like n·1e-16)
    n = int(c[1])
    c1 = math.cos(phi)
    s1 = math.sin(phi)
    ck = c1
    sk = s1
    b = c[0]
    db = 0.0
    d2b = 0.0
    for k in range(1, n + 1):
        a = c[1 + k]
        s = c[1 + n + k]
        term = a * ck + s * sk
        b += term
        db += k * (s * ck - a * sk)
        d2b -= k * k * term
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
    return b, db, d2b


@njit(**OPTIONS)
def wall_b1(phi, c):
    # b and b' only (the compiler drops the unused b'' sum)
    b, db, d2b = wall_b2(phi, c)
    return b, db

TWO_PI = 2.0 * math.pi
INV_TWO_PI = 1.0 / TWO_PI
PI = math.pi
INF = math.inf
ROUND_T = 1e-15  # a time interval this small (relative) is rounding
SIXTH = 1.0 / 6.0
# columns of the cell table (one row per cell, see cellbounds.cell_table)
(LEFT, RIGHT, BMAX, CMAX, SLOPE_FWD, SLOPE_BWD, P0, P1, P2, P3, P4, P5, PERR, P2MAX, D3MAX, P2ABS,
 RUN_FWD, NEXT_FWD, RUN_BWD, NEXT_BWD) = range(20)
POS_TOL = 0.01  # a second-order contact is taken unconfirmed when its Taylor remainder is below POS_TOL·tol
# Budgets (why an orbit may stop instead of looping).  θ is reduced mod 2π after every flight; a flight that
# carries it beyond MAX_ANGLE (2^44 ≈ 1.8e13 rad, where one ulp is 0.004 rad) leaves nothing of the contact
# angle, and a cell index computed from it would be garbage.  A search that walks more than CELL_BUDGET cells
# (2^27 ≈ 10^6 turns of θ at 128 cells a turn, ~1 s) is a flight so nearly parallel to the walls that following
# it is pointless.
MAX_ANGLE = 17592186044416.0
CELL_BUDGET = 134217728


@intrinsic
def _data_pointer(typingctx, arr):
    # the data pointer of an array, to rebuild it with numba.carray as a view *without* a reference
    # count: numba increments and decrements the count of every array argument with atomic
    # instructions on every call, which cost ~25 % of the run time when the search functions
    # received the cell table directly; the views are used only while _run's own arguments live
    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, args[0]).data
    return types.CPointer(arr.dtype)(arr), codegen


@njit(**OPTIONS)
def _root_step(g0, g1, K):
    # smallest τ > 0 with g0 + g1 τ − ½ K τ² = 0 (g0 ≥ 0), ∞ if none, or a lower bound of it (K < 0, a convex
    # parabola, has the same smallest root formula)
    if g1 < 0.0 and K > 0.0 and 2.0 * K * g0 <= g1 * g1:
        # sqrt(a² + x) ≤ a + x/(2a) gives a lower bound of the root without a square root, at
        # least 0.8 of it when x ≤ a² (near a tangency, a → 0, it would stall: exact root there)
        return g0 * (-g1) / (g1 * g1 + 0.5 * K * g0)
    disc = g1 * g1 + 2.0 * K * g0
    if g1 < 0.0 and K <= 0.0:
        # a convex parabola (K ≤ 0, x = 2|K| g0 ≤ a² = g1² when it has a root): sqrt(a² − x) ≤ a − x/(2a)
        # (concavity of sqrt) makes the same expression a lower bound of its root 2 g0/(a + sqrt(a² − x)),
        # without a square root: between Newton's step g0/a and the root, at least 2/3 of the root (the
        # denominator is ≥ ¾ a² > 0 unless a² underflows: then the general formula below)
        if disc < 0.0:
            return INF
        den = g1 * g1 + 0.5 * K * g0
        if den > 0.0:
            return g0 * (-g1) / den
    if disc < 0.0:
        return INF
    if g1 < 0.0:
        return 2.0 * g0 / (-g1 + math.sqrt(disc))
    if K > 0.0:
        return (g1 + math.sqrt(disc)) / K
    return INF


@njit(inline='always', **OPTIONS)
def _next_cell(j, m, off, phi0, forward):
    # the next cell of the walk, its whole turns and its start (off − phi0), across the seam of the period
    if forward:
        j += 1
        if j == m:
            j = 0
            off += TWO_PI
    else:
        j -= 1
        if j < 0:
            j = m - 1
            off -= TWO_PI
    return j, off, off - phi0

@njit(inline='always', **OPTIONS)
def _search(phi0, A, B, Q, vt, ivt, t_lo, t_hi, leaving, g1_leave, c, cells, lookup, tol):
    # first t in [t_lo, t_hi) where f(t) = A + B t − ½ Q t² − b(phi0 + vt t) ≤ tol, and b' there; (INF, 0) if
    # none; (−1, 0) if the exact stage did not converge, (−2, 0) the wall is not finite, (−3, 0) the cell budget
    # is spent, (−4, 0) the angle is beyond float64.  vt ≠ 0 and ivt = 1/vt (computed once per collision by the
    # caller: divisions are slow and on the critical path); [t_lo, t_hi) is the caller's window (t_lo < t_hi)
    # cell exits by a product with 1/vt: consecutive cells share their boundary time, so none is skipped
    m = cells.shape[0]
    nunif = lookup.shape[0]
    hq = 0.5 * Q
    phi = phi0 + vt * t_lo
    off = TWO_PI * math.floor(phi * INV_TWO_PI)
    x = phi - off
    if x >= TWO_PI:  # the product may round across a multiple of 2π
        x -= TWO_PI
        off += TWO_PI
    elif x < 0.0:
        x += TWO_PI
        off -= TWO_PI
    if not (0.0 <= x < TWO_PI):  # nan, or an angle beyond float64's reach: never index with it
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
    forward = vt > 0.0
    edge = RIGHT if forward else LEFT
    start = off - phi0
    t_in = t_lo
    l_in = A + B * t_in - hq * t_in * t_in  # L at t_in (after the first cell: the previous cell's l_out)
    at_edge = False
    walked = 0
    # the vertex of a convex L (the ceiling under gravity), where its minimum over a cell may lie
    t_vertex = B / Q if Q < 0.0 else -1.0
    # g' at t = 0 on the wall just left: known from the impact, or evaluated (an orbit that starts on a wall)
    g1_start = g1_leave
    if leaving and t_lo == 0.0 and math.isnan(g1_start):
        b, d1 = wall_b1(phi0, c)
        g1_start = B - vt * d1
    if leaving and t_lo == 0.0 and Q <= 0.0 and cells[j, CMAX] <= 0.0:
        # leaving a wall that curves away (b'' ≤ 0: g'' = −Q − vt² b'' ≥ 0 over the cells of this run, which
        # stops at every kink): g(0) = 0 and g'(0) > 0 make g ≥ g'(0) t > 0 up to the run's end, so no contact
        # there and the walk resumes after it (a rising flight otherwise walks every cell it passes over)
        if g1_start > 0.0:
            if forward:
                t_in = (cells[j, RUN_FWD] + start) * ivt
                jn = int(cells[j, NEXT_FWD])
                if jn <= j:
                    off += TWO_PI
            else:
                t_in = (cells[j, RUN_BWD] + start) * ivt
                jn = int(cells[j, NEXT_BWD])
                if jn >= j:
                    off -= TWO_PI
            if t_in >= t_hi:
                return INF, 0.0
            j = jn
            start = off - phi0
            at_edge = True
            l_in = A + B * t_in - hq * t_in * t_in
    while True:
        # the walk over cells whose box test passes is a tight loop of its own: in one loop with the stages
        # below (many live values) the compiler reloaded a dozen registers from the stack at every cell
        while True:
            walked += 1
            if walked > CELL_BUDGET:
                return -3.0, 0.0
            t_out = (cells[j, edge] + start) * ivt
            t_out = min(t_out, t_hi)
            # box test: L above max b (+ tol) over the whole cell: no contact in it (L's minimum over the cell is at
            # an end, or for a convex L at its vertex)
            l_out = A + B * t_out - hq * t_out * t_out
            lmin = min(l_in, l_out)
            if t_in < t_vertex < t_out:
                lmin = min(lmin, A + B * t_vertex - hq * t_vertex * t_vertex)
            if lmin <= cells[j, BMAX] + tol and t_out >= t_in:
                break
            if t_out >= t_hi:
                return INF, 0.0
            j, off, start = _next_cell(j, m, off, phi0, forward)
            t_in = t_out
            l_in = l_out
            at_edge = True
        # the box test failed in cell j: the proxy and exact stages decide
        t = t_in
        clear = False
        if leaving and t == 0.0:
            # on the wall just left: g = 0 there (the collision already processed), g' > 0;
            # the certified step 2 g'/K away from it
            t = _root_step(0.0, g1_start, Q + vt2 * cells[j, CMAX])
            clear = not (t < t_out)
        if not clear:
            # proxy stage: f − tol ≥ G = L − p_j − e_j − tol; conservative steps on G (curvature bound
            # Q + vt² max p_j'', rigorous for the polynomial) certify [t, t + τ) contact-free
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
                # Estrin's scheme for p and p' (this loop is bound by the latency of the chain)
                s = vt * t - a
                s2 = s * s
                p = (c0 + c1 * s) + s2 * ((c2 + c3 * s) + s2 * (c4 + c5 * s))
                G = A + B * t - hq * t * t - p - e - tol
                if G <= e:
                    break  # a contact may be near: the exact stage decides
                dp = (c1 + c2d * s) + s2 * ((c3d + c4d * s) + s2 * c5d)
                G1 = B - Q * t - vt * dp
                tau = _root_step(G, G1, Kp)
                if not (t + tau < t_out):
                    clear = True
                    break
                t += tau
                if G + G1 * tau + 0.5 * Ka * tau * tau <= e:
                    # Taylor: G(t + τ) ≤ G + G'τ + ½ Ka τ² ≤ e, so the test above would stop at
                    # once (the usual last step before a contact): skip evaluating the proxy
                    break
        if not clear:
            # exact stage: conservative steps on the exact f (curvature bound Q + vt² c_j)
            K = Q + vt2 * cells[j, CMAX]
            D3 = abs(vt) * vt2 * cells[j, D3MAX]
            for it in range(1000):
                b, d1, d2 = wall_b2(phi0 + vt * t, c)
                second = True  # b'' at t belongs to this cell's smooth piece
                if it == 0 and at_edge and t == t_in:
                    # entering through a kink: its one-sided slope, never the other side's
                    slope = cells[j, SLOPE_FWD] if forward else cells[j, SLOPE_BWD]
                    if not math.isnan(slope):
                        d1 = slope
                        second = False
                g0 = A + B * t - hq * t * t - b
                g1 = B - Q * t - vt * d1
                if not (abs(g0) < INF and abs(g1) < INF):
                    return -2.0, 0.0  # the wall is nan or infinite here: stop, never skip silently
                if second and g1 < 0.0:
                    # the second-order step to the root, δ = δN + ½ f'' δN²/|f'| with Newton's δN;
                    # |f(t + δ)| ≤ |model residual| + D3 |δ|³/6 (Taylor; |f⁽³⁾| ≤ |vt|³ max|b⁽³⁾|: the
                    # field adds no third derivative) and b' there is d1 + b'' vt δ to ½ max|b⁽³⁾| (vt δ)²:
                    # when both are below rounding scale, no confirming evaluation is needed
                    dn = g0 / (-g1)
                    g2 = -Q - vt2 * d2
                    dh = dn + 0.5 * g2 * dn * dn / (-g1)
                    # (the tests are written without divisions: they are on the critical path)
                    rem = D3 * dh * dh * abs(dh) * SIXTH
                    res = abs(g0 + dh * (g1 + 0.5 * g2 * dh)) + rem
                    slope_err_vt = 0.5 * D3 * dh * dh  # the slope remainder times |vt|
                    if (res <= POS_TOL * tol and rem <= 1e-17 * abs(g1)
                            and slope_err_vt <= 1e-17 * (1.0 + abs(d1)) * abs(vt) and t + dh < t_out):
                        if g0 <= tol:
                            return t + dh, d1 + vt * d2 * dh
                        tau = _root_step(g0, g1, K)
                        if (t + dh) - (t + tau) <= ROUND_T * (1.0 + t):
                            # the certified step reaches the root to rounding: it is the first contact
                            return t + dh, d1 + vt * d2 * dh
                if g0 <= tol:
                    if g1 < 0.0:  # one Newton step on the exact wall
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
                    return t, d1  # the crossing is within rounding of t (a very long, shallow flight)
                if g1 < 0.0:
                    # Newton's iterate lies beyond the certified step by O(K g²/|g'|³); once that is
                    # below rounding of t, Newton's point *is* the conservative limit: take it and
                    # confirm it on the exact wall (saves the last certified step and the polish)
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
        j, off, start = _next_cell(j, m, off, phi0, forward)
        t_in = t_out
        l_in = l_out
        at_edge = True


@njit(inline='always', **OPTIONS)
def _reduce(theta, turns):
    # θ as (θ mod 2π, whole turns): the form in which both kernels carry the angle along an orbit
    wraps = math.floor(theta / TWO_PI)
    return theta - wraps * TWO_PI, wraps + turns


@njit(inline='always', **OPTIONS)
def _earlier(tl, dl, tu, du, vt):
    # the earlier of the two walls' contacts: (t, side, slope s of the wall there in the billiard's sense,
    # code); code 0 a contact, else why the orbit stops: 1 the wall is not finite, 2 the cell budget is spent,
    # 3 the angle is beyond float64, 4 no convergence, 5 free flight (no contact at all)
    if tl == -2.0 or tu == -2.0:
        return 0.0, 0, 0.0, 1
    if tl == -3.0 or tu == -3.0:
        return 0.0, 0, 0.0, 2
    if tl == -4.0 or tu == -4.0:
        return 0.0, 0, 0.0, 3
    if tl < 0.0 or tu < 0.0:
        return 0.0, 0, 0.0, 4
    if tu < tl:
        t = tu
        side = 1
        s = -du  # the slope found with the contact: no second evaluation of the wall
    else:
        t = tl
        side = 0
        s = dl
    if t == INF:
        return t, side, s, 5
    if not (abs(vt * t) < MAX_ANGLE):
        return t, side, s, 3
    return t, side, s, 0


@njit(inline='always', **OPTIONS)
def _leaving_rate(side, vt, ve, s):
    # g' of the wall just left (> 0 after an impact), for the first step of the next search
    if side == 0:
        return ve - vt * s
    return -ve + vt * s


@njit(inline='always', **OPTIONS)
def _advance(th, wraps, dth):
    # θ mod 2π and its whole turns after a flight that turned it by dth
    th += dth
    if th >= TWO_PI or th < 0.0:
        k = math.floor(th / TWO_PI)
        th -= k * TWO_PI
        wraps += k
    return th, wraps


@njit(inline='always', **OPTIONS)
def _impact(vt, ve, s, e):
    # Newton's law on the normal velocity in the billiard metric (n ∝ (−s, 1); e = 1 the specular reflection)
    f = (1.0 + e) * (ve - s * vt) / (1.0 + s * s)
    vt = vt + f * s
    ve = ve - f
    return vt, ve

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
        if not kink_lo:
            S3 = max(S3, cells[jb, D3MAX])
            tau = min(tau, (x - lo + (cells[jb, RIGHT] - cells[jb, LEFT])) / W)
        if not kink_hi:
            S3 = max(S3, cells[jf, D3MAX])
            tau = min(tau, (hi - x + (cells[jf, RIGHT] - cells[jf, LEFT])) / W)
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
                tau = min(tau, N / LN)
            if armed and Lu > 0.0:
                tau = min(tau, u / Lu)
        else:
            # θ̈ = n/m with n = −(s + rr sw)(g + B''θ̇²) − B s θ̇², m = 1 + B² + s(s + rr sw): θ⃛ = (ṅ − θ̈ ṁ)/m
            ndot = (S2 * W * (g + S2 * W * W) + (S1 + rr) * (S3 * W * W * W + 2.0 * S2 * W * A)
                    + (S1 * S1 + S0 * S2) * W * W * W + 2.0 * S0 * S1 * W * A)
            mdot = (2.0 * S0 * S1 + 2.0 * S1 * S2 + rr * S2) * W
            J = Mi * (ndot + A * mdot)
            Lh = mu * (3.0 * S2 * W * A + S1 * J + S3 * W * W * W) + S2 * W * W * W + 3.0 * S1 * W * A + S0 * J
            if armed and Lh > 0.0:
                tau = min(tau, min(hp, hm) / Lh)
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
