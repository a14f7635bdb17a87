"""The billiard kernel, compiled by numba: the search for the next collision and the orbit loop.

This file is the kernel's source as people and tools read it.  It is never imported by coinwall:
:mod:`.kernel` reads its text, keeps what follows the marker line below and joins it after the
generated code of one wall (:mod:`.wallcode`), so that the compiled module is a real file whose
name is the hash of its content and numba's ``cache=True`` finds it again in the next process.

Finding the next collision
--------------------------
Along a ray ``θ(t) = θ0 + v_θ t``, ``η(t) = η0 + v_η t`` the distance to a
wall, measured vertically, is a *gap function* of the same form for both walls,

    g(t) = A + B t − b(φ0 + v_θ t),

lower wall: ``A = η0 − b0, B = v_η, φ0 = θ0``; upper wall:
``A = H − b0 − η0, B = −v_η, φ0 = θ0 + π``.  The next collision is the
smallest t > 0 with ``g(t) = 0`` over both walls.

Why the kernel (``method="kernel"``) cannot miss a root.  The period is cut into
cells (a uniform grid of :data:`CELLS` cells, additionally cut at every kink
of the wall, so that b is smooth inside each cell).  For each cell ``j`` we
precompute an upper bound ``bmax_j`` of b, an upper bound ``c_j`` of b''
(from dense sampling, see :func:`~.cellbounds.cell_bounds` for the margin and the check
that enforces it), and a *proxy*: the quintic Hermite interpolant ``p_j`` of
the exact b, b', b'' at the cell's ends with a bound ``e_j ≥ |b − p_j|`` on
the cell (sampled with a margin and checked the same way, see
:func:`~.cellbounds.cell_proxies`; ~1e-8 where the ε = 99 coin is sharpest, ~1e-11
typically).  The ray is then walked cell by cell:

1. *Box test*: if the line ``A + B t`` stays above ``bmax_j + tol`` during
   the time the ray spends over cell j, then ``g > tol`` there: no contact in
   this cell.  Only times when the line is inside the band [min b, max b] of
   the whole wall are walked at all.
2. *Proxy stage* (cheap, no wall evaluation): ``G = A + B t − p_j − e_j − tol``
   is a lower bound of ``g − tol``, and ``G'' ≥ −K_p`` with
   ``K_p = v_θ² max p_j''`` (rigorous for the polynomial).  So from any t with
   ``G(t) > 0`` the parabola ``G + G' τ − ½ K_p τ²`` is a lower bound of
   ``G(t + τ)`` inside the cell, and any τ up to its smallest positive root is
   a step over which g cannot reach tol (*conservative advancement*).  The
   step used is that root, or for an approaching ray with
   ``2 K_p G ≤ G'²`` the lower bound ``G|G'|/(G'² + ½ K_p G)`` of it (from
   ``sqrt(a² + x) ≤ a + x/2a``; no square root, at least 0.8 of the root,
   still second order; near a tangency the root itself, which steps past
   it).  If a step leaves the cell, the cell has no contact.  Steps stop
   when ``G ≤ e_j``: a contact may be near.  (When Taylor's bound
   ``G + G'τ + ½ v_θ² max|p_j''| τ²`` already shows that the step just taken
   ends with ``G ≤ e_j``, the stage stops there without evaluating G again.)
3. *Exact stage*: the same conservative steps on the exact gap g, with
   ``g'' ≥ −K``, ``K = v_θ² c_j``, from where the proxy stage stopped.  When
   ``g ≤ tol`` (:data:`HIT_TOL` times max(1, H, wall scale)) the iterate is
   the collision, polished onto the exact wall.  Each evaluation gives b, b'
   and b'' (``wall_b2``), so the *second-order finish* applies: from
   ``g, g' < 0, g''`` the step ``δ = δN + ½ g'' δN²/|g'|`` (δN = Newton's)
   reaches the root up to the Taylor remainder ``|v_θ|³ max|b'''| |δ|³/6``
   (``max|b'''|`` per cell, sampled like the other bounds), and the slope at
   the root is ``b' + b'' v_θ δ`` up to ``½ max|b'''| (v_θ δ)²``.  When the
   position remainder is below ``0.01·tol`` and the slope remainder below
   1e-17 (1 + |b'|), and the certified step from the same point reaches the
   root to rounding of t (1e-15 relative; the two differ by O((K + |g''|)
   δ²/|g'|)), ``t + δ`` is the first contact and the wall is not evaluated
   again.  That is the usual end of a search: one wall evaluation per
   collision.  Otherwise (a contact far into the proxy's error, e.g. where
   the ε = 99 coin is sharpest, or a graze) the older finish runs: a Newton
   step to a point confirmed on the exact wall (``|g| ≤ tol``) and the slope
   evaluated there.  A step that no longer changes t (a flight of ~1e6 time
   units at a grazing angle) is a contact if ``g ≤ |g'|·ulp(t)``.

Every interval skipped is certified by a lower bound of g (box, proxy or
exact parabola), so the iterates never pass the first contact.  The only
approximations are the declared ones: a graze whose gap never drops below
``tol`` (≈1e-13) is not a collision, one that does is; time intervals below
rounding of t (see 3.) are not resolved; and the cell bounds ``bmax_j``,
``c_j``, ``e_j`` come from dense sampling with a checked margin, not from
interval arithmetic.  Kinks of the wall are cell edges, where b'' has its
point mass; on entering a cell through a kink the kink's one-sided slope is
used, never a derivative evaluated on the wrong side, and the proxy of a cell
next to a kink interpolates the one-sided values.  Just after a reflection
the gap of the wall just left is exactly zero (up to rounding) and
``g' > 0`` (known from the reflection, no wall evaluation), so the first step
there is the positive root ``2 g'/K`` of ``g' τ − ½ K τ²``, which cannot
re-detect the collision that was just processed.  Of the two walls, the one
whose band the ray is in first is searched first, and its hit time caps the
search on the other (so a shallow ray never searches far ahead in time on
one wall while the other is hit at once).

The kernel is compiled with numba's ``error_model="numpy"`` (no zero-division
branches: every division of the kernel has a nonzero denominator by
construction, and in the generated wall code a division by zero gives inf/nan
as casadi does: a wall sample that is not finite makes the cell bounds refuse the
wall, and a non-finite gap in the exact stage stops the orbit with a note, so a
pole between checked angles is never read as "no contact") and without ``fastmath`` (which could reorder the polish and
the bounds).  All per-cell data is one (m, 16) table.  numba increments and
decrements the reference count of every array argument with atomic
instructions on each call; ``_run`` therefore rebuilds its arrays as views
without a reference count (``numba.carray`` on the data pointer) before the
searches, and the search is inlined at a single call site (a loop over the
two walls).  Measured effects, in the commit that made them: the atomics were
~13 % of the samples of a profile; inlining gave 5-10 %; a second inlined call
"""

# Everything above the marker line only makes this file importable and lintable on its own; none of
# it reaches the compiled module.  There the imports and OPTIONS come from ``kernel.HEADER`` (the
# same names) and ``wall_b1``/``wall_b2`` from the wall's generated code, which is placed first.
# TWO_PI is defined again below the marker (not imported from coinwall.forward.angles) because the
# generated module must stand alone: it is loaded from numba's cache folder, not from the package.
# The comments below still say ``_cell_table`` for what is now ``cellbounds.cell_table``: editing the
# text below the marker changes the compiled module's hash, so every cached kernel would be rebuilt.

import math

from numba import carray, njit, prange, types
from numba.extending import intrinsic

__all__ = []  # nothing public: the kernel is called through coinwall.forward.dynamics.billiard.kernel

CACHE = True  # set by wallcode.load_module: False when the kernel is compiled in memory (no trusted cache)
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


def wall_b1(phi, c):
    """Stand-in for the generated ``wall_b1(phi, c) -> (b, b')`` (see :func:`.wallcode.wall_source`)."""
    raise NotImplementedError("the kernel runs joined to a wall's generated code: see coinwall.forward.dynamics.billiard.kernel")


def wall_b2(phi, c):
    """Stand-in for the generated ``wall_b2(phi, c) -> (b, b', b'')`` (see :func:`.wallcode.wall_source`)."""
    raise NotImplementedError("the kernel runs joined to a wall's generated code: see coinwall.forward.dynamics.billiard.kernel")


# ---- kernel: the text from the line after this one to the end of the file is joined to the wall code ----

TWO_PI = 2.0 * math.pi
INV_TWO_PI = 1.0 / TWO_PI
PI = math.pi
INF = math.inf
ROUND_T = 1e-15  # a time interval this small (relative) is rounding
# columns of the cell table (one row per cell, see _cell_table)
LEFT, RIGHT, BMAX, CMAX, SLOPE_FWD, SLOPE_BWD, P0, P1, P2, P3, P4, P5, PERR, P2MAX, D3MAX, P2ABS = range(16)
POS_TOL = 0.01  # a second-order contact is taken unconfirmed when its Taylor remainder is below POS_TOL·tol
# Budgets (why an orbit may stop instead of looping; the notes are kernel.NOTES 4 and 5).  θ is reduced mod 2π
# after every flight; a flight that carries it beyond MAX_ANGLE (2^44 ≈ 1.8e13 rad, where one ulp is 0.004 rad)
# leaves nothing of the contact angle, and a cell index computed from it would be garbage.  A search that
# walks more than CELL_BUDGET cells (2^27 ≈ 10^6 turns of θ at 128 cells a turn, ~1 s) is a ray so nearly
# parallel to the walls that following it is pointless.
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
    # smallest τ > 0 with g0 + g1 τ − ½ K τ² = 0 (g0 ≥ 0), ∞ if none, or a lower bound of it
    if g1 < 0.0 and K > 0.0 and 2.0 * K * g0 <= g1 * g1:
        # sqrt(a² + x) ≤ a + x/(2a) gives a lower bound of the root without a square root, at
        # least 0.8 of it when x ≤ a² (near a tangency, a → 0, it would stall: exact root there)
        return g0 * (-g1) / (g1 * g1 + 0.5 * K * g0)
    disc = g1 * g1 + 2.0 * K * g0
    if disc < 0.0:
        return INF
    if g1 < 0.0:
        return 2.0 * g0 / (-g1 + math.sqrt(disc))
    if K > 0.0:
        return (g1 + math.sqrt(disc)) / K
    return INF


@njit(inline='always', **OPTIONS)
def _first_hit(phi0, A, B, vt, iB, ivt, tcap, leaving, g1_leave, c, cells, lookup, wmin, wmax, tol):
    # first t in (0, tcap) where g(t) = A + B t − b(phi0 + vt t) ≤ tol, and b' there;
    # (INF, 0) if none; (−1, 0) if the exact stage did not converge.  iB = 1/B and ivt = 1/vt
    # (computed once per collision by the caller: divisions are slow and on the critical path)
    if B > 0.0:
        if A > wmax:
            return INF, 0.0
        t_lo = 0.0
        t_hi = (wmax - A) * iB
    elif B < 0.0:
        # entering the band [wmin, wmax] an ulp late is harmless: the wall stays below wmax by
        # the bound margin (≥ 1e-12 of the scale), far more than the line moves in an ulp of t
        t_lo = max(0.0, (wmax - A) * iB)
        t_hi = max(0.0, (wmin - A) * iB) * (1.0 + 1e-12) + 1e-300
    else:
        if A > wmax:
            return INF, 0.0
        t_lo = 0.0
        t_hi = INF
        if vt != 0.0:  # horizontal ray: one period of θ decides
            t_hi = 1.01 * TWO_PI / abs(vt) + 1.0
    t_hi = min(t_hi, tcap)
    if not (t_lo < t_hi):
        return INF, 0.0
    if vt == 0.0:  # vertical ray: g is linear
        if B >= 0.0:
            return INF, 0.0
        b, d1 = wall_b1(phi0, c)
        if not (abs(b) < INF and abs(d1) < INF):
            return -2.0, 0.0
        t = (A - b) / (-B)
        if leaving or t <= 0.0 or t >= tcap:
            return INF, 0.0
        return t, d1
    # cell exits by a product with 1/vt: consecutive cells share their boundary time, so none is skipped
    m = cells.shape[0]
    nunif = lookup.shape[0]
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
    edge = RIGHT if vt > 0.0 else LEFT
    start = off - phi0
    t_in = t_lo
    at_edge = False
    walked = 0
    while True:
        walked += 1
        if walked > CELL_BUDGET:
            return -3.0, 0.0
        t_out = (cells[j, edge] + start) * ivt
        t_out = min(t_out, t_hi)
        if B >= 0.0:
            lmin = A + B * t_in
        else:
            lmin = A + B * t_out
        # box test: the line above max b (+ tol) over the whole cell: no contact in it
        if lmin <= cells[j, BMAX] + tol and t_out >= t_in:
            t = t_in
            clear = False
            if leaving and t == 0.0:
                # on the wall just left: g = 0 there (the collision already processed), g' > 0;
                # the certified step 2 g'/K away from it (g' from the reflection when known)
                if not math.isnan(g1_leave):
                    g1 = g1_leave
                else:
                    b, d1 = wall_b1(phi0, c)
                    g1 = B - vt * d1
                t = _root_step(0.0, g1, vt2 * cells[j, CMAX])
                clear = not (t < t_out)
            if not clear:
                # proxy stage: g − tol ≥ G = A + B t − p_j − e_j − tol; conservative steps on G
                # (curvature bound vt² max p_j'', exact for the cubic) certify [t, t + τ) contact-free
                a = cells[j, LEFT] + start
                e = cells[j, PERR]
                Kp = vt2 * cells[j, P2MAX]
                Ka = vt2 * cells[j, P2ABS]
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
                    G = A + B * t - p - e - tol
                    if G <= e:
                        break  # a contact may be near: the exact stage decides
                    dp = (c1 + c2d * s) + s2 * ((c3d + c4d * s) + s2 * c5d)
                    G1 = B - vt * dp
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
                # exact stage: conservative steps on the exact g (curvature bound vt² c_j)
                K = vt2 * cells[j, CMAX]
                D3 = abs(vt) * vt2 * cells[j, D3MAX]
                for it in range(1000):
                    b, d1, d2 = wall_b2(phi0 + vt * t, c)
                    second = True  # b'' at t belongs to this cell's smooth piece
                    if it == 0 and at_edge and t == t_in:
                        # entering through a kink: its one-sided slope, never the other side's
                        slope = cells[j, SLOPE_FWD] if vt > 0.0 else cells[j, SLOPE_BWD]
                        if not math.isnan(slope):
                            d1 = slope
                            second = False
                    g0 = A + B * t - b
                    g1 = B - vt * d1
                    if not (abs(g0) < INF and abs(g1) < INF):
                        return -2.0, 0.0  # the wall is nan or infinite here: stop, never skip silently
                    if second and g1 < 0.0:
                        # the second-order step to the root, δ = δN + ½ g'' δN²/|g'| with Newton's δN;
                        # |g(t + δ)| ≤ |model residual| + D3 |δ|³/6 (Taylor; |g⁽³⁾| ≤ |vt|³ max|b⁽³⁾|)
                        # and b' there is d1 + b'' vt δ to ½ max|b⁽³⁾| (vt δ)²: when both are below
                        # rounding scale, no confirming evaluation is needed
                        dn = g0 / (-g1)
                        g2 = -vt2 * d2
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
                                # the certified step reaches the root to rounding: it is the first contact
                                return t + dh, d1 + vt * d2 * dh
                    if g0 <= tol:
                        if g1 < 0.0:  # one Newton step on the exact wall
                            tn = t + g0 / (-g1)
                            bn, dn = wall_b1(phi0 + vt * tn, c)
                            gn = A + B * tn - bn
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
                            gn = A + B * tn - bn
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
def _run(state, turns, leaving, n, H, b0, c, cells, lookup, wmin, wmax, tol,
         out_time, out_theta, out_eta, out_vt, out_ve, out_side, last):
    # state[0] is θ reduced mod 2π by the caller and ``turns`` its whole turns (θ = state[0] + 2π·turns), so an
    # orbit continues exactly however far it has turned; last = [θ mod 2π, turns] after the last collision
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
    last[0] = th
    last[1] = wraps
    time = 0.0
    g1_leave = math.nan  # g' of the wall just left (unknown for a start on a wall)
    for i in range(n):
        # the wall whose band [min b, max b] the ray enters first is searched first: its hit time
        # caps the search on the other wall (for a shallow ray the wall "ahead" in η can be very far)
        # (the wall behind is in reach only while the ray is still inside its band)
        if ve < 0.0:
            ahead_first = not ((H - b0 - eta) <= wmax and (eta - b0) > wmax)
        else:
            ahead_first = not ((eta - b0) <= wmax and ve > 0.0 and (H - b0 - eta) > wmax)
        ive = 1.0 / ve
        ivt = 1.0 / vt
        upper_first = (ve >= 0.0) == ahead_first
        # one call site in a loop over the two walls: _first_hit is inlined, and a second copy of it
        # would double the compile time for nothing
        tu = INF
        tl = INF
        du = 0.0
        dl = 0.0
        for k in range(2):
            upper = upper_first if k == 0 else not upper_first
            tcap = INF if k == 0 else (tu if upper_first else tl)
            if upper:  # upper wall: gap H − b0 − η − v_η t − b(θ + π + v_θ t)
                phi0, A, B, iB, near = th + PI, H - b0 - eta, -ve, -ive, leaving == 1
            else:  # lower wall: gap η − b0 + v_η t − b(θ + v_θ t)
                phi0, A, B, iB, near = th, eta - b0, ve, ive, leaving == 0
            tk, dk = _first_hit(phi0, A, B, vt, iB, ivt, tcap, near, g1_leave, c, cells, lookup, wmin, wmax, tol)
            if upper:
                tu, du = tk, dk
            else:
                tl, dl = tk, dk
        if tl == -2.0 or tu == -2.0:
            return i, 3
        if tl == -3.0 or tu == -3.0:
            return i, 5
        if tl == -4.0 or tu == -4.0:
            return i, 4
        if tl < 0.0 or tu < 0.0:
            return i, 2
        if tu < tl:
            t = tu
            side = 1
            s = -du  # the slope found with the contact: no second evaluation of the wall
        else:
            t = tl
            side = 0
            s = dl
        if t == INF:
            return i, 1
        if not (abs(vt * t) < MAX_ANGLE):
            return i, 4
        th += vt * t
        eta += ve * t
        time += t
        if th >= TWO_PI or th < 0.0:
            k = math.floor(th / TWO_PI)
            th -= k * TWO_PI
            wraps += k
        f = 2.0 * (ve - s * vt) / (1.0 + s * s)
        vt = vt + f * s
        ve = ve - f
        scale = 1.0 / math.sqrt(vt * vt + ve * ve)  # keeps the speed 1 to rounding over long runs
        vt *= scale
        ve *= scale
        # g' of the wall just left (> 0 after the reflection), for the first step of the next search
        if side == 0:
            g1_leave = ve - vt * s
        else:
            g1_leave = -ve + vt * s
        out_time[i] = time
        out_theta[i] = th + wraps * TWO_PI
        out_eta[i] = eta
        out_vt[i] = vt
        out_ve[i] = ve
        out_side[i] = side
        last[0] = th
        last[1] = wraps
        leaving = side
    return n, 0


@njit(cache=CACHE, parallel=True)
def _run_many(states, turns, leaving, n, H, b0, c, cells, lookup, wmin, wmax, tol,
              out_time, out_theta, out_eta, out_vt, out_ve, out_side, done, status, last):
    for k in prange(states.shape[0]):
        d, s = _run(states[k], turns[k], leaving[k], n, H, b0, c, cells, lookup, wmin, wmax, tol,
                    out_time[k], out_theta[k], out_eta[k], out_vt[k], out_ve[k], out_side[k], last[k])
        done[k] = d
        status[k] = s
