"""The compiled kernel of the spinning-top billiard (:mod:`.top`): flights, the certified search, impacts.

Imported only by :mod:`.top` inside the functions that run it (numba is a heavy import).  Units: lengths in
κ₁ (the body's transverse radius of gyration), time in seconds, ``ℓ = L/I₁`` in rad/s.

The flight
----------
No torque acts between impacts, so ``ℓ`` (the angular momentum over I₁, in the lab) is fixed and the
symmetry axis ``a`` turns rigidly about it: ``ȧ = ℓ × a`` (the body's angular velocity is
``ℓ + (I₁/I₃ − 1) ℓ₃ a``, and its part along ``a`` does not move ``a``).  So ``a(t)`` is ``a(0)`` rotated
about ``ℓ̂`` by ``Ω t``, ``Ω = |ℓ|`` (Rodrigues' formula), and ``cos θ = a_z`` is a sinusoid in time.  The
flight is set up in the frame where ``a(0) = (sin θ0, 0, cos θ0)``:
``ℓ = θ̇ e_φ − p e_θ + ℓ₃ a`` with the azimuthal speed ``p = φ̇ sin θ = (ℓ_z − ℓ₃ cos θ)/sin θ``, computed as
``(ℓ_z − ℓ₃)/sin θ + ℓ₃ tan(θ/2)`` on the upper half and ``(ℓ_z + ℓ₃)/sin θ − ℓ₃ cot(θ/2)`` on the lower
(no 0/0 at a pole the axis can reach, ℓ_z = ±ℓ₃).  θ is read back as ``atan2(|a_h|, a_z)`` (no arccos
near ±1) and ``θ̇ = (a_h·ȧ_h)/|a_h| · a_z − |a_h| ȧ_z`` (``|ȧ_h|·sign a_z`` exactly at a pole: the axis
leaving the vertical).  Nothing divides by zero: the state at a pole is exact and never NaN.

The gap to the floor is ``f = η − h(θ)``; for a polygonal meridian (vertices ``(ρ_k, ζ_k)``, rounding ε)
``h = ε + max_k (ρ_k |a_h| − ζ_k a_z)``, for an ellipsoid ``h = √(A²|a_h|² + C² a_z²)``.  The ceiling's gap
is ``H − η − h(π − θ)`` (the support upwards: ``ζ → −ζ``).

Why the search never skips a collision
--------------------------------------
Every step from time t to t + τ is justified by a lower bound of the gap on [t, t + τ]:

* *First order, anywhere.*  A body point x (|x| ≤ R, the body's reach) moves relative to the centre at
  speed ≤ |ω_⊥| R = |ȧ| R (rotation about the axis moves no support point), so ``|dh/dt| ≤ Λ = R |ȧ|``
  with ``|ȧ| = |ℓ × a|`` constant in flight.  The floor gap obeys
  ``f(t + τ) ≥ f(t) + (η̇(t) − Λ) τ − ½ g τ²`` and the ceiling gap ``≥ f_c(t) − (η̇(t) + Λ) τ + ½ g τ²``;
  the step is the smallest positive root of these bounds (conservative advancement), so no root of the gap
  is passed.  This holds across kinks of h (edges, faces), where no second-order bound exists.
* *Second order, leaving a wall.*  At an impact the gap is 0, so the first-order bound gives no step.  Each
  smooth piece ``f_k = η − h_k`` has ``f_k'' ≥ −K``: ``|ä| ≤ Ω |ȧ|``; ``|a_h|'' ≤ |ȧ|²/|a_h| + Ω|ȧ|`` while
  ``|a_h| ≥ ½|a_h(0)|``, i.e. for ``τ ≤ |a_h(0)|/(2|ȧ|)``; the ellipsoid's h is a smooth function of a_z
  (``h_uu = (C² − A²) A²/h³``).  The step is the smallest positive root over the pieces of
  ``f_k(0) + f_k'(0) τ − ½ K τ²`` (and no longer than the window).  An impact exactly at a pole of a face
  (|a_h| = 0: the face flat on the wall, a set of measure zero) has no window: status 11.
* *Finish.*  When the gap is below ``tol_near`` and falling, a bracket ``[t, t + 2f/|f'|]`` with a
  negative end is looked for and the root refined by bisection-secant (Illinois) to rounding; without one
  the conservative steps go on until the gap is below ``tol`` (a graze within the contact tolerance: the
  declared approximation, as in the planar kernel).  A root pair inside one bracket shorter than
  2 f/|f'| with f < tol_near (a graze deeper than nothing but shallower than tol_near) is the other declared
  approximation.

The impact is Newton's restitution on the normal velocity in the (θ, η) metric (:mod:`.top`).
"""

import math

import numpy as np
from numba import njit, prange

__all__ = []  # called through coinwall.forward.dynamics.coin3d.top

# no cache of numba's own: top._kernel() gives every function coinwall's (billiard.wallcode.cache_module)
OPTIONS = {"cache": False, "error_model": "numpy"}
INF = math.inf
MAX_STEPS = 1_000_000
#: status codes (as in :data:`.top.STATUS`)
BUDGET, SETTLED, CAUGHT, FREE, NO_CONVERGENCE, POLE = 0, 1, 2, 6, 7, 11


@njit(**OPTIONS)
def _root_step(g0, g1, K):
    # smallest τ > 0 with g0 + g1 τ − ½ K τ² = 0 for g0 ≥ 0 (INF if none); K may be negative
    if g0 <= 0.0:
        return 0.0
    disc = g1 * g1 + 2.0 * K * g0
    if disc < 0.0:
        return INF
    if g1 < 0.0:
        return 2.0 * g0 / (-g1 + math.sqrt(disc))
    if K > 0.0:
        return (g1 + math.sqrt(disc)) / K
    return INF


@njit(**OPTIONS)
def setup(theta, w, lz, l3):
    """The flight's frame: (a0x, a0z, lx, ly, lz, Ω); a(0) = (sin θ, 0, cos θ), ℓ in that frame."""
    s = math.sin(theta)
    c = math.cos(theta)
    if theta == 0.0:
        s, c = 0.0, 1.0
    elif theta == math.pi:
        s, c = 0.0, -1.0
    if s <= 0.0:
        p = 0.0
    elif c >= 0.0:
        p = (lz - l3) / s + l3 * (s / (1.0 + c))
    else:
        p = (lz + l3) / s - l3 * (s / (1.0 - c))
    lx = -p * c + l3 * s
    ly = w
    lzz = p * s + l3 * c
    return s, c, lx, ly, lzz, math.sqrt(lx * lx + ly * ly + lzz * lzz)


@njit(**OPTIONS)
def axis(s0, c0, lx, ly, lz, om, t):
    """a(t) and ȧ(t) = ℓ × a for the frame of :func:`setup`."""
    if om == 0.0:
        return s0, 0.0, c0, 0.0, 0.0, 0.0
    nx, ny, nz = lx / om, ly / om, lz / om
    ph = om * t
    cp = math.cos(ph)
    sp = math.sin(ph)
    nd = nx * s0 + nz * c0
    cx, cy, cz = ny * c0, nz * s0 - nx * c0, -ny * s0  # n × a0
    k = nd * (1.0 - cp)
    ax = s0 * cp + cx * sp + nx * k
    ay = cy * sp + ny * k
    az = c0 * cp + cz * sp + nz * k
    dx = ly * az - lz * ay
    dy = lz * ax - lx * az
    dz = lx * ay - ly * ax
    return ax, ay, az, dx, dy, dz


@njit(**OPTIONS)
def angle(ax, ay, az, dx, dy, dz):
    """(θ, θ̇, |a_h|, d|a_h|/dt) from the axis and its rate."""
    rh = math.hypot(ax, ay)
    th = math.atan2(rh, az)
    if rh > 0.0:
        rdot = (ax * dx + ay * dy) / rh
        thd = rdot * az - rh * dz
    else:
        rdot = math.hypot(dx, dy)
        thd = rdot if az > 0.0 else -rdot
    return th, thd, rh, rdot


@njit(**OPTIONS)
def support(s, c, sdot, cdot, up, kind, verts, eps, ea, ec):
    """(h, dh/dt, h'(θ)) of the floor (up = False) or ceiling (up = True) support at sin θ = s, cos θ = c."""
    if up:
        c = -c
        cdot = -cdot
    if kind == 1:
        h = math.sqrt(ea * ea * s * s + ec * ec * c * c)
        hd = (ea * ea * s * sdot + ec * ec * c * cdot) / h
        dth = (ea * ea - ec * ec) * s * c / h
    else:
        best = -INF
        kb = 0
        for k in range(verts.shape[0]):
            v = verts[k, 0] * s - verts[k, 1] * c
            if v > best:
                best = v
                kb = k
        h = best + eps
        hd = verts[kb, 0] * sdot - verts[kb, 1] * cdot
        dth = verts[kb, 0] * c + verts[kb, 1] * s
    if up:
        dth = -dth
    return h, hd, dth


@njit(**OPTIONS)
def _gaps(eta0, v, g, H, has_ceiling, s0, c0, lx, ly, lz, om, t, kind, verts, eps, ea, ec):
    ax, ay, az, dx, dy, dz = axis(s0, c0, lx, ly, lz, om, t)
    th, thd, rh, rdot = angle(ax, ay, az, dx, dy, dz)
    eta = eta0 + v * t - 0.5 * g * t * t
    ve = v - g * t
    h, hd, _ = support(rh, az, rdot, dz, False, kind, verts, eps, ea, ec)
    ff = eta - h
    fd = ve - hd
    fc = INF
    fcd = 0.0
    if has_ceiling:
        hu, hud, _ = support(rh, az, rdot, dz, True, kind, verts, eps, ea, ec)
        fc = H - eta - hu
        fcd = -ve - hud
    return ff, fd, fc, fcd


@njit(**OPTIONS)
def _leave_step(eta0, v, g, H, has_ceiling, leaving, s0, c0, lx, ly, lz, om, speed, kind, verts, eps, ea, ec):
    # second-order step off the wall just left (see the module docstring); −1.0: cannot leave (pole / inward)
    ax, ay, az, dx, dy, dz = axis(s0, c0, lx, ly, lz, om, 0.0)
    th, thd, rh, rdot = angle(ax, ay, az, dx, dy, dz)
    if kind == 1:
        hmin = min(ea, ec)
        dd = abs(ec * ec - ea * ea)
        kh = dd * ea * ea / (hmin ** 3) * speed * speed + dd / hmin * om * speed
        window = INF
    else:
        if rh <= 0.0:
            return -1.0
        rmax = 0.0
        zmax = 0.0
        for k in range(verts.shape[0]):
            rmax = max(rmax, verts[k, 0])
            zmax = max(zmax, abs(verts[k, 1]))
        window = rh / (2.0 * speed) if speed > 0.0 else INF
        kh = rmax * (2.0 * speed * speed / rh + om * speed) + zmax * om * speed
    tau = window
    for wall in range(2):
        if wall == 1 and not has_ceiling:
            break
        sign = 1.0 if wall == 0 else -1.0
        K = sign * g + kh  # f'' ≥ −K on every smooth piece of this wall's gap
        if kind == 1:
            h, hd, _ = support(rh, az, rdot, dz, wall == 1, kind, verts, eps, ea, ec)
            f0 = (eta0 - h) if wall == 0 else (H - eta0 - h)
            f1 = (v - hd) if wall == 0 else (-v - hd)
            if f0 <= 0.0 and f1 <= 0.0:
                return -1.0
            tau = min(tau, _root_step(max(f0, 0.0), f1, K) if f0 > 0.0 else 2.0 * f1 / K if K > 0.0 else INF)
            continue
        cz = az if wall == 0 else -az
        czd = dz if wall == 0 else -dz
        for k in range(verts.shape[0]):
            hk = verts[k, 0] * rh - verts[k, 1] * cz + eps
            hkd = verts[k, 0] * rdot - verts[k, 1] * czd
            f0 = (eta0 - hk) if wall == 0 else (H - eta0 - hk)
            f1 = (v - hkd) if wall == 0 else (-v - hkd)
            if f0 <= 0.0:
                if f1 <= 0.0:
                    return -1.0
                step = 2.0 * f1 / K if K > 0.0 else INF
            else:
                step = _root_step(f0, f1, K)
            tau = min(tau, step)
    return tau


@njit(**OPTIONS)
def next_impact(theta, eta0, w, v, lz3, l3, leaving, g, H, has_ceiling, kind, verts, eps, ea, ec, reach, tol,
                tmax):
    """(t, wall, code): the first impact after leaving ``leaving`` (−1: none), within ``tmax``.

    code 0: an impact at t on ``wall`` (0 floor, 1 ceiling); 6: none before tmax (or ever); 7: the step budget
    ran out; 11: cannot leave the wall (a face flat on it, or moving into it)."""
    s0, c0, lx, ly, lz, om = setup(theta, w, lz3, l3)
    ax, ay, az, dx, dy, dz = axis(s0, c0, lx, ly, lz, om, 0.0)
    speed = math.sqrt(dx * dx + dy * dy + dz * dz)
    lam = reach * speed
    t = 0.0
    if leaving >= 0:
        t = _leave_step(eta0, v, g, H, has_ceiling, leaving, s0, c0, lx, ly, lz, om, speed, kind, verts, eps, ea,
                        ec)
        if t < 0.0:
            return 0.0, leaving, POLE
        if t > tmax:
            return tmax, -1, FREE
    tol_near = max(1e3 * tol, 1e-10)
    for _ in range(MAX_STEPS):
        ff, fd, fc, fcd = _gaps(eta0, v, g, H, has_ceiling, s0, c0, lx, ly, lz, om, t, kind, verts, eps, ea, ec)
        f = ff
        fdd = fd
        wall = 0
        if fc < ff:
            f = fc
            fdd = fcd
            wall = 1
        if f <= tol:
            if f < -tol and t > 0.0:
                return t, wall, NO_CONVERGENCE  # cannot happen with exact bounds: reported, not hidden
            return t, wall, 0
        if f <= tol_near and fdd < 0.0:
            t2 = t + 2.0 * f / (-fdd)
            f2a, _, f2c, _ = _gaps(eta0, v, g, H, has_ceiling, s0, c0, lx, ly, lz, om, t2, kind, verts, eps, ea,
                                   ec)
            f2 = f2a if wall == 0 else f2c
            if f2 < 0.0:
                return _illinois(t, f, t2, f2, wall, eta0, v, g, H, has_ceiling, s0, c0, lx, ly, lz, om, kind,
                                 verts, eps, ea, ec), wall, 0
        ve = v - g * t
        if not has_ceiling and g <= 0.0 and ve >= 0.0 and eta0 + v * t - reach > 0.0:
            return tmax, -1, FREE  # rising, clear of the floor at every tilt, no field: never back
        tau = _root_step(ff, ve - lam, g)
        if has_ceiling:
            tau = min(tau, _root_step(fc, -ve - lam, -g))
        if tau == INF or t + tau > tmax:
            return tmax, -1, FREE
        t += tau
    return t, -1, NO_CONVERGENCE


@njit(**OPTIONS)
def _illinois(a, fa, b, fb, wall, eta0, v, g, H, has_ceiling, s0, c0, lx, ly, lz, om, kind, verts, eps, ea, ec):
    # root of the gap in [a, b] with fa > 0 > fb, to rounding; returns the last point with a positive gap
    side = 0
    for _ in range(200):
        if b - a <= 4e-16 * max(abs(a), abs(b)) or b - a <= 1e-300:
            break
        m = b - fb * (b - a) / (fb - fa)
        if not (a < m < b):
            m = 0.5 * (a + b)
        f0, _, f1, _ = _gaps(eta0, v, g, H, has_ceiling, s0, c0, lx, ly, lz, om, m, kind, verts, eps, ea, ec)
        fm = f0 if wall == 0 else f1
        if fm > 0.0:
            a, fa = m, fm
            if side == 1:
                fb *= 0.5
            side = 1
        elif fm < 0.0:
            b, fb = m, fm
            if side == -1:
                fa *= 0.5
            side = -1
        else:
            return m
    return a if fa <= -fb else b


@njit(**OPTIONS)
def state_at(theta, eta0, w, v, lz3, l3, g, t):
    """(θ, η, θ̇, η̇) after a free flight of duration t."""
    s0, c0, lx, ly, lz, om = setup(theta, w, lz3, l3)
    ax, ay, az, dx, dy, dz = axis(s0, c0, lx, ly, lz, om, t)
    th, thd, rh, rdot = angle(ax, ay, az, dx, dy, dz)
    return th, eta0 + v * t - 0.5 * g * t * t, thd, v - g * t


@njit(**OPTIONS)
def impact(theta, w, v, wall, e, kind, verts, eps, ea, ec):
    """(θ̇, η̇) after Newton's restitution at the floor (wall 0) or ceiling (wall 1) at tilt θ."""
    s = math.sin(theta)
    c = math.cos(theta)
    _, _, dth = support(s, c, 0.0, 0.0, wall == 1, kind, verts, eps, ea, ec)
    slope = dth if wall == 0 else -dth  # the wall's slope dη/dθ in the (θ, η) plane
    fimp = (1.0 + e) * (v - slope * w) / (1.0 + slope * slope)
    w, v = w + fimp * slope, v - fimp
    if kind == 0:
        # at a kink of the wall (two rings touch at once: an edge or a face lying on the wall) the impulse on
        # one leaves the other moving in: impulses in turn on the piece moving in fastest, until none is
        cz = c if wall == 0 else -c
        best = -INF
        for k in range(verts.shape[0]):
            best = max(best, verts[k, 0] * s - verts[k, 1] * cz)
        for _ in range(16):
            worst = 0.0
            kw = -1
            for k in range(verts.shape[0]):
                if verts[k, 0] * s - verts[k, 1] * cz < best - 1e-12 * (1.0 + abs(best)):
                    continue
                sl = verts[k, 0] * cz + verts[k, 1] * s  # the wall's slope on this piece (floor and ceiling)
                rate = (v - sl * w) if wall == 0 else -(v - sl * w)
                if rate < worst:
                    worst = rate
                    kw = k
            if kw < 0:
                break
            sl = verts[kw, 0] * cz + verts[kw, 1] * s
            fimp = (1.0 + e) * (v - sl * w) / (1.0 + sl * sl)
            w, v = w + fimp * sl, v - fimp
    return w, v


@njit(**OPTIONS)
def run(state, lz, l3, leaving, impacts, g, e, H, has_ceiling, kind, verts, eps, ea, ec, reach, tol, tmax,
        out_time, out_theta, out_eta, out_vt, out_ve, out_wall):
    """Up to ``impacts`` impacts from ``state`` = (θ, η, θ̇, η̇); returns (done, status)."""
    theta, eta, w, v = state[0], state[1], state[2], state[3]
    clock = 0.0
    for i in range(impacts):
        t, wall, code = next_impact(theta, eta, w, v, lz, l3, leaving, g, H, has_ceiling, kind, verts, eps, ea, ec,
                                    reach, tol, tmax)
        if code != 0:
            return i, code
        theta, eta, w, v = state_at(theta, eta, w, v, lz, l3, g, t)
        w, v = impact(theta, w, v, wall, e, kind, verts, eps, ea, ec)
        clock += t
        out_time[i] = clock
        out_theta[i] = theta
        out_eta[i] = eta
        out_vt[i] = w
        out_ve[i] = v
        out_wall[i] = wall
        leaving = wall
    return impacts, BUDGET


@njit(parallel=True, **OPTIONS)
def sides_many(states, lz, l3, impacts, g, e, H, has_ceiling, kind, verts, eps, ea, ec, reach, tol, tmax,
               sides, status):
    """For each toss: the side (sign of cos θ: +1, −1, 0) at each of its first floor impacts, in ``sides``
    (m, impacts), and the status (0: all impacts reached, else the code that stopped it; sides after are 0)."""
    m = states.shape[0]
    # the side can change only through the equator θ = π/2, where the energy is at least
    # U = V(π/2) + g b(π/2) = ℓz²/2 + g b(π/2): below it the side is decided for ever
    hq, _, _ = support(1.0, 0.0, 0.0, 0.0, False, kind, verts, eps, ea, ec)
    for j in prange(m):
        theta, eta, w, v = states[j, 0], states[j, 1], states[j, 2], states[j, 3]
        leaving = -1
        floor = 0
        code = 0
        barrier = 0.5 * lz[j] * lz[j] + g * hq
        for _ in range(64 * impacts + 64):
            t, wall, code = next_impact(theta, eta, w, v, lz[j], l3[j], leaving, g, H, has_ceiling, kind, verts, eps,
                                        ea, ec, reach, tol, tmax)
            if code != 0:
                break
            theta, eta, w, v = state_at(theta, eta, w, v, lz[j], l3[j], g, t)
            w, v = impact(theta, w, v, wall, e, kind, verts, eps, ea, ec)
            leaving = wall
            if wall == 0:
                c = math.cos(theta)
                side = 1 if c > 0.0 else (-1 if c < 0.0 else 0)
                sides[j, floor] = side
                floor += 1
                if floor >= impacts:
                    break
                if g > 0.0 and side != 0:
                    sn = math.sin(theta)
                    if sn > 0.0:
                        p = (lz[j] - l3[j] * c) / sn
                    else:
                        p = 0.0
                    level = 0.5 * (w * w + v * v + p * p) + g * eta
                    if level < barrier:
                        for k in range(floor, impacts):
                            sides[j, k] = side
                        code = SETTLED
                        break
        status[j] = code


@njit(parallel=True, **OPTIONS)
def states_at_many(states, lz, l3, g, times, out):
    """Free flights of many tosses: (θ, η, θ̇, η̇) of each after its own time."""
    for j in prange(states.shape[0]):
        th, eta, w, v = state_at(states[j, 0], states[j, 1], states[j, 2], states[j, 3], lz[j], l3[j], g, times[j])
        out[j, 0] = th
        out[j, 1] = eta
        out[j, 2] = w
        out[j, 3] = v


def _unused():  # keeps numpy imported for numba's array typing in this module's namespace
    return np
