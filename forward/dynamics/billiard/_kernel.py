"""The billiard kernel, compiled by numba: the search for the next collision and the orbit loop.

This file is the kernel's source as people and tools read it.  It is never imported by coinwall:
:mod:`.kernel` reads its text, keeps what follows the marker line below and joins it after the
generated code of one wall (:mod:`.wallcode`) and the text of the certified search (:mod:`._search`,
which the field kernel :mod:`._field_kernel` compiles too: one implementation of the search for both),
so that the compiled module is a real file whose name is the hash of its content and numba's
``cache=True`` finds it again in the next process.  This file holds the straight-line window, the
vertical ray, the reflection and the orbit loop; the docstring below is the guarantee of the whole.

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
   it).  Where ``K_p ≤ 0`` (G convex, the wall curving away: most contacts
   of the coin) the same expression is a lower bound of the root too, by
   ``sqrt(a² − x) ≤ a − x/2a``: between Newton's step and the root, at
   least 2/3 of it, no square root; a parabola without a root clears the
   cell.  If a step leaves the cell, the cell has no contact.  Steps stop
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
re-detect the collision that was just processed.  When the wall just left curves away there
(the cell's bound ``c_j ≤ 0``), the gap is convex (``g'' = −v_θ² b'' ≥ 0``) over the whole run of
such cells that follows without a kink (:func:`~.cellbounds.concave_runs`), so ``g ≥ g'(0) t > 0``
up to the run's end: the walk skips the run at once instead of testing its cells one by one (most of
the cells a rising ray passes over on the coin).  Of the two walls, the one
whose band the ray is in first is searched first, and its hit time caps the
search on the other (so a shallow ray never searches far ahead in time on
one wall while the other is hit at once).

The kernel is compiled with numba's ``error_model="numpy"`` (no zero-division
branches: every division of the kernel has a nonzero denominator by
construction, and in the generated wall code a division by zero gives inf/nan
as casadi does: a wall sample that is not finite makes the cell bounds refuse the
wall, and a non-finite gap in the exact stage stops the orbit with a note, so a
pole between checked angles is never read as "no contact") and without ``fastmath`` (which could reorder the polish and
the bounds).  All per-cell data is one (m, 21) table.  numba increments and
decrements the reference count of every array argument with atomic
instructions on each call; ``_run`` therefore rebuilds its arrays as views
without a reference count (``numba.carray`` on the data pointer) before the
searches, and the search is inlined at a single call site (a loop over the
two walls).  The atomics are ~13 % of the samples of a profile otherwise; inlining is
worth 5-10 %; the walk over the cells whose box test passes is a loop of its own (sharing one
loop with the proxy and exact stages, the compiler reloads a dozen registers at every cell of
the walk), worth ~4 % (``tests/benchmarks/kernel_ab.py`` compares two revisions).  The search (:func:`._search._search`)
is inlined into :func:`_first_hit`, itself inlined at one call site in ``_run``; the straight
flight passes ``Q = 0`` to it, which reduces every expression to the straight-line one exactly.
"""

# Everything above the marker line only makes this file importable and lintable on its own; none of
# it reaches the compiled module.  There the imports and OPTIONS come from ``kernel.HEADER`` (the
# same names), ``wall_b1``/``wall_b2`` from the wall's generated code, which is placed first, and the
# constants and the search from the text of _search.py, placed next.

import math

from numba import carray, njit, prange

from ._search import (
    INF,
    PI,
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

__all__ = []  # nothing public: the kernel is called through coinwall.forward.dynamics.billiard.kernel

CACHE = True  # wallcode.load_module sets it False: it gives each function coinwall's cache itself
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


# ---- kernel: the text from the line after this one to the end of the file is joined to the wall code ----

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
    return _search(phi0, A, B, 0.0, vt, ivt, t_lo, t_hi, leaving, g1_leave, c, cells, lookup, tol)


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
    th, wraps = _reduce(theta, turns)
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
        t, side, s, code = _earlier(tl, dl, tu, du, vt)
        if code != 0:
            return i, (0, 3, 5, 4, 2, 1)[code]
        th, wraps = _advance(th, wraps, vt * t)
        eta += ve * t
        time += t
        vt, ve = _impact(vt, ve, s, 1.0)
        # keeps the speed 1 to rounding over long runs: the reflection preserves |v|² = 1 up to a few ulps
        # (x = 1 + δ, |δ| ~ 1e-16), and one Newton step for 1/sqrt(x) from 1, 1 − δ/2, is 1/sqrt(x) to
        # O(δ²) ~ 1e-32: the same normalisation as a square root and a division without their ~35 cycles
        # on the critical path (a start speed far from 1, which the callers never pass, takes the exact way)
        v2 = vt * vt + ve * ve
        scale = 1.5 - 0.5 * v2 if abs(v2 - 1.0) < 1e-6 else 1.0 / math.sqrt(v2)
        vt *= scale
        ve *= scale
        g1_leave = _leaving_rate(side, vt, ve, s)
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
