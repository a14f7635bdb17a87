"""The certified search for the next contact, shared by the billiard kernel and the field kernel.

Like :mod:`._kernel` and :mod:`._field_kernel` this file is source as people and tools read it; it is never
imported by coinwall.  The text after the marker line below is joined after a wall's generated code and before
either kernel's own text (:func:`.kernel.kernel_module`), so that both kernels compile *one* implementation of
the search: the walk over the cells, the box test, the proxy stage, the exact stage with its second-order
finish, and the certified step.  Why the search never passes a contact is said in :mod:`._kernel` (straight
flights) and :mod:`._field_kernel` (parabolic flights); this docstring says what is shared and how.

The gap along a flight is ``f(t) = A + B t − ½ Q t² − b(φ0 + v_θ t)``: the billiard passes ``Q = 0`` (a
straight flight), the field kernel the field (``±g``).  With ``Q = 0`` every expression of the search reduces
to the billiard's operation for operation (``x − 0·t² = x`` and ``0 + x = x`` exactly in floating point), so
the billiard's collisions are bit for bit those of its straight-line search.  Each kernel computes the window
of times ``[t_lo, t_hi)`` in which its flight is inside the band ``[min b, max b]`` of the wall (a line: one
product with ``1/B``; a parabola: the roots of a quadratic) and handles a flight without rotation (v_θ = 0) in
closed form; :func:`_search` does the rest.  It is a plain numba function inlined at its single call site in
each kernel (``inline='always'``), so sharing it costs no call.
"""

# Everything above the marker line only makes this file importable and lintable on its own; none of it
# reaches the compiled module (imports and OPTIONS come from kernel.HEADER, wall_b1/wall_b2 from the wall's
# generated code).  TWO_PI is defined below the marker, not imported, because the generated module must
# stand alone: it is loaded from numba's cache folder, not from the package.

import math

from numba import njit, types
from numba.extending import intrinsic

__all__ = []  # nothing public: the search is compiled into the kernels of coinwall.forward.dynamics.billiard.kernel

CACHE = True  # wallcode.load_module sets it False: it gives each function coinwall's cache itself
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


def wall_b1(phi, c):
    """Stand-in for the generated ``wall_b1(phi, c) -> (b, b')`` (see :func:`.wallcode.wall_source`)."""
    raise NotImplementedError("the search runs joined to a wall's generated code: see coinwall.forward.dynamics.billiard.kernel")


def wall_b2(phi, c):
    """Stand-in for the generated ``wall_b2(phi, c) -> (b, b', b'')`` (see :func:`.wallcode.wall_source`)."""
    raise NotImplementedError("the search runs joined to a wall's generated code: see coinwall.forward.dynamics.billiard.kernel")


def wall_b3(phi, c):
    """Stand-in for the generated ``wall_b3(phi, c) -> b'''`` (see :func:`.wallcode.wall_source`)."""
    raise NotImplementedError("the search runs joined to a wall's generated code: see coinwall.forward.dynamics.billiard.kernel")


# ---- search: the text from the line after this one to the end of the file is joined to the wall code ----

TWO_PI = 2.0 * math.pi
INV_TWO_PI = 1.0 / TWO_PI
PI = math.pi
INF = math.inf
ROUND_T = 1e-15  # a time interval this small (relative) is rounding
SIXTH = 1.0 / 6.0
# columns of the cell table (one row per cell, see cellbounds.cell_table)
(LEFT, RIGHT, BMAX, CMAX, SLOPE_FWD, SLOPE_BWD, P0, P1, P2, P3, P4, P5, PERR, P2MAX, D3MAX, P2ABS,
 RUN_FWD, NEXT_FWD, RUN_BWD, NEXT_BWD, D4MAX) = range(21)
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
