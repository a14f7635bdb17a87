"""The billiard: a point particle in the (θ, η) strip between the two walls.

With ``η = y/κ`` the free motion of the body between two flat walls is a
free point particle in the plane (θ, η) with the Euclidean metric, periodic
in θ, between the lower wall ``η = b0 + b(θ)`` and the upper wall
``η = H − (b0 + b(θ + π))``, reflecting specularly (paper, eqs. 1–8 and
13–14).  Units: κ; unit speed, so time equals path length.

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
(from dense sampling, see :func:`_cell_bounds` for the margin and the check
that enforces it), and a *proxy*: the quintic Hermite interpolant ``p_j`` of
the exact b, b', b'' at the cell's ends with a bound ``e_j ≥ |b − p_j|`` on
the cell (sampled with a margin and checked the same way, see
:func:`_cell_proxies`; ~1e-8 where the ε = 99 coin is sharpest, ~1e-11
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
site tripled the compile time (3 → 12 s) for nothing more.

The reference stepper (``method="reference"``) is deliberately simple and uses
only :meth:`Wall.derivatives`: conservative advancement with the *global*
Lipschitz bound ``|g'| ≤ |v_η| + |v_θ| max|b'|`` (steps ``g/Λ``), stopping when
the gap is below ``tol``; the first step away from a wall uses the global
bound on |b''| of the smooth pieces (and never crosses a kink).  It is slow
(linear convergence, a casadi call per step) and is the yardstick the kernel
is tested against.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, field

import numpy as np

from ..errors import InvalidArgument, InvalidWall
from ..wall import Wall

__all__ = ["Billiard", "Trajectory", "simulate", "random_states", "ensemble", "compile_kernel", "METHODS"]

TWO_PI = 2.0 * math.pi
METHODS = ("kernel", "reference")
CELLS = 128          # uniform cells per period (kinks add more)
SAMPLES = 32         # samples per cell for the bounds
HIT_TOL = 1e-13      # a gap below tol·max(1, H, scale) is a contact
_GAP_GRID = 4096
_REFERENCE_MAX_STEPS = 200_000


# ---------------------------------------------------------------------------------------------------- table
@dataclass(frozen=True, repr=False)
class Billiard:
    """The billiard table: the strip between the two walls of ``wall`` at distance ``H``.

    Parameters / attributes
    -----------------------
    wall : Wall
        The wall function b(θ).
    H : float
        Distance between the flat walls (units of κ).
    b0 : float
        Offset added to the wall (``b0 + b`` is the support function).
    gap_min, gap_max : float
        Minimum and maximum over θ of the strip height
        ``upper(θ) − lower(θ) = H − 2 b0 − b(θ) − b(θ + π)`` (on a 4096-point
        grid).  ``gap_min < 0`` means some angles are out of reach (the coin
        cannot turn over); ``gap_max ≤ 0`` is refused.
    """

    wall: Wall
    H: float
    b0: float = 0.0
    gap_min: float = field(init=False)
    gap_max: float = field(init=False)

    def __post_init__(self):
        if not isinstance(self.wall, Wall):
            raise InvalidArgument(f"`wall` must be a forward.Wall, got {type(self.wall).__name__}")
        for name in ("H", "b0"):
            value = getattr(self, name)
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise InvalidArgument(f"`{name}` must be a real number, got {value!r}") from None
            if isinstance(value, bool) or not math.isfinite(number):
                raise InvalidArgument(f"`{name}` must be a finite number, got {value!r}")
            object.__setattr__(self, name, number)
        theta = np.linspace(0.0, TWO_PI, _GAP_GRID, endpoint=False)
        gap = self.upper(theta) - self.lower(theta)
        object.__setattr__(self, "gap_min", float(gap.min()))
        object.__setattr__(self, "gap_max", float(gap.max()))
        if self.gap_max <= 0.0:
            need = self.H - self.gap_max
            raise InvalidArgument(f"`H` = {self.H:g} leaves no room for motion (the walls overlap at every angle); "
                                  f"need H > {need:.6g} = min over θ of 2·b0 + b(θ) + b(θ+π)")

    def lower(self, theta):
        """Lower wall ``b0 + b(θ)`` (numpy, vectorised)."""
        return self.b0 + self.wall(theta)

    def upper(self, theta):
        """Upper wall ``H − b0 − b(θ + π)`` (numpy, vectorised)."""
        return self.H - self.b0 - self.wall(np.asarray(theta, dtype=float) + math.pi)

    @property
    def tol(self) -> float:
        """Contact tolerance: a gap below this is a collision."""
        return HIT_TOL * max(1.0, abs(self.H), self.wall.scale)

    def area_perimeter(self, points: int = 20000):
        """Area and perimeter of the billiard domain over one period (trapezoid on ``points`` angles).

        Only the parts where the strip is open (``upper > lower``) count;
        the perimeter is the arc length of both walls there.  Used by the
        Santaló mean-free-path check ``⟨τ⟩ = π·Area/Perimeter``.
        """
        theta = np.linspace(0.0, TWO_PI, points, endpoint=False)
        b, d1, _ = self.wall.derivatives(theta)
        bu, du, _ = self.wall.derivatives(theta + math.pi)
        gap = self.H - 2 * self.b0 - b - bu
        open_ = gap > 0
        h = TWO_PI / points
        area = float(np.sum(np.where(open_, gap, 0.0)) * h)
        perimeter = float(np.sum(np.where(open_, np.sqrt(1 + d1**2) + np.sqrt(1 + du**2), 0.0)) * h)
        return area, perimeter

    def __repr__(self) -> str:
        try:
            return (f"Billiard({self.wall!r}, H={self.H:g}, b0={self.b0:g}, "
                    f"gap {self.gap_min:.4g}..{self.gap_max:.4g})")
        except Exception:  # a repr must never raise
            return "Billiard(<unprintable>)"


# ---------------------------------------------------------------------------------------------------- results
@dataclass(frozen=True, repr=False)
class Trajectory:
    """Collisions of one orbit, in order (one entry per collision).

    Attributes
    ----------
    time : ndarray (n,)
        Time of each collision since the start (unit speed: also path length;
        for a start speed s ≠ 1, time = path length / s).
    theta : ndarray (n,)
        Contact angle, unwrapped (continuous; take ``% 2π`` yourself).
    eta : ndarray (n,)
        Contact height (on the wall to ~1e-12).
    v_theta, v_eta : ndarray (n,)
        Velocity after the specular reflection (the start speed is kept).
    side : ndarray (n,) of int8
        0 = bottom wall (η = lower), 1 = top wall.
    start : ndarray (4,)
        The initial state ``[theta, eta, v_theta, v_eta]``.
    table : Billiard
    method : str
        ``"kernel"`` or ``"reference"``.
    note : str
        Empty when all requested collisions were computed; otherwise why the
        orbit stopped early (a free flight parallel to the walls that never
        collides again, or a stepper that did not converge).
    """

    time: np.ndarray
    theta: np.ndarray
    eta: np.ndarray
    v_theta: np.ndarray
    v_eta: np.ndarray
    side: np.ndarray
    start: np.ndarray
    table: Billiard
    method: str = "kernel"
    note: str = ""

    def __len__(self) -> int:
        return int(self.time.size)

    @property
    def final_state(self) -> np.ndarray:
        """State right after the last collision (start of a continuation); the start if there is none."""
        if self.time.size == 0:
            return self.start.copy()
        return np.array([self.theta[-1], self.eta[-1], self.v_theta[-1], self.v_eta[-1]])

    def __repr__(self) -> str:
        try:
            n = self.time.size
            if n == 0:
                return f"Trajectory(0 collisions{', ' + self.note if self.note else ''})"
            bottom = float(np.mean(self.side == 0))
            extra = f", note: {self.note}" if self.note else ""
            return (f"Trajectory({n} collisions, {self.method}, t_end={self.time[-1]:.6g}, "
                    f"bottom fraction {bottom:.3f}{extra})")
        except Exception:  # a repr must never raise
            return "Trajectory(<unprintable>)"


# ---------------------------------------------------------------------------------------------------- inputs
def _check_count(collisions) -> int:
    if isinstance(collisions, bool) or not isinstance(collisions, (int, np.integer)):
        raise InvalidArgument(f"`collisions` must be a positive integer, got {collisions!r}")
    if collisions <= 0:
        raise InvalidArgument(f"`collisions` must be a positive integer, got {collisions}")
    return int(collisions)


def _check_table(table):
    if not isinstance(table, Billiard):
        raise InvalidArgument(f"`table` must be a forward.billiard.Billiard, got {type(table).__name__}")


def _check_method(method):
    if method not in METHODS:
        raise InvalidArgument(f"`method` must be one of {', '.join(METHODS)}, got {method!r}")


def _check_states(table: Billiard, states, name="state"):
    """Validate states (m, 4); return (unit-speed states, speeds, leaving side per state: -1/0/1)."""
    try:
        arr = np.array(states, dtype=float)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`{name}` must be numbers [theta, eta, v_theta, v_eta]") from None
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 4 or arr.shape[0] == 0:
        raise InvalidArgument(f"`{name}` must have shape (4,) or (n, 4) [theta, eta, v_theta, v_eta], "
                              f"got shape {np.shape(states)}")
    bad = np.flatnonzero(~np.all(np.isfinite(arr), axis=1))
    if bad.size:
        raise InvalidArgument(f"`{name}` {arr[bad[0]].tolist()} must be finite")
    speed = np.hypot(arr[:, 2], arr[:, 3])
    if np.any(speed == 0):
        i = int(np.flatnonzero(speed == 0)[0])
        raise InvalidArgument(f"`{name}` {arr[i].tolist()} has zero velocity; the particle must move")
    lower = table.lower(arr[:, 0])
    upper = table.upper(arr[:, 0])
    tol = 10 * table.tol
    leaving = np.full(arr.shape[0], -1, dtype=np.int64)
    for i in range(arr.shape[0]):
        th, eta, vt, ve = arr[i]
        if not (math.isfinite(lower[i]) and math.isfinite(upper[i])):
            raise InvalidWall(f"wall {table.wall.description!r} is not finite at θ = {th:.9g} or θ + π, where "
                              f"`{name}` {arr[i].tolist()} starts; the billiard needs a finite wall")
        if not (lower[i] - tol <= eta <= upper[i] + tol):
            raise InvalidArgument(f"`{name}` {arr[i].tolist()} is outside the strip: at θ = {th:.6g} η must lie "
                                  f"between {lower[i]:.6g} and {upper[i]:.6g}")
        on_lower, on_upper = eta - lower[i] <= tol, upper[i] - eta <= tol
        if on_lower or on_upper:
            side = 0 if on_lower else 1
            slope = table.wall.derivatives(np.array([th + side * math.pi]))[1][0] * (1 if side == 0 else -1)
            inward = (ve - slope * vt) * (1 if side == 0 else -1)  # v·n with n pointing into the strip
            if inward <= 0:
                raise InvalidArgument(f"`{name}` {arr[i].tolist()} is on the {'lower' if side == 0 else 'upper'} "
                                      f"wall and moves out of the strip; reverse its velocity or move it inside")
            leaving[i] = side
    unit = arr.copy()
    unit[:, 2:] /= speed[:, None]
    return unit, speed, leaving


def random_states(table: Billiard, n: int, seed=None) -> np.ndarray:
    """``n`` states uniform in the Liouville measure of ``table``.

    Position uniform in the area of the strip (rejection from the bounding
    box, angles where the strip is closed are never chosen), direction
    uniform on the circle, unit speed.  Same ``seed`` ⇒ same states.

    Returns
    -------
    ndarray (n, 4)
        ``[theta, eta, v_theta, v_eta]`` with theta in [0, 2π).
    """
    _check_table(table)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n <= 0:
        raise InvalidArgument(f"`n` must be a positive integer, got {n!r}")
    rng = np.random.default_rng(seed)
    theta_grid = np.linspace(0.0, TWO_PI, _GAP_GRID, endpoint=False)
    lo = float(np.min(table.lower(theta_grid)))
    hi = float(np.max(table.upper(theta_grid)))
    out = np.empty((0, 2))
    while out.shape[0] < n:
        batch = max(64, 2 * (n - out.shape[0]))
        theta = rng.uniform(0.0, TWO_PI, batch)
        eta = rng.uniform(lo, hi, batch)
        # keep a safety distance so a state is never "on" a wall
        inside = (eta > table.lower(theta) + 1e3 * table.tol) & (eta < table.upper(theta) - 1e3 * table.tol)
        out = np.vstack([out, np.column_stack([theta[inside], eta[inside]])])
    out = out[:n]
    angle = rng.uniform(0.0, TWO_PI, n)
    return np.column_stack([out, np.cos(angle), np.sin(angle)])


# ---------------------------------------------------------------------------------------------------- reference
def _sample_bounds(wall: Wall, points: int = 8192):
    """max|b'| and max|b''| of the smooth pieces, from samples with a margin (for the reference stepper)."""
    theta = (np.arange(points) + 0.5) * (TWO_PI / points)
    _, d1, d2 = wall.derivatives(theta)
    kinks = np.array([k.angle for k in wall.kinks])
    if kinks.size:
        # drop samples next to a kink: there the sampled b'' sees the kink, not the smooth piece
        dist = np.abs((theta[:, None] - kinks[None, :] + math.pi) % TWO_PI - math.pi).min(axis=1)
        keep = dist > 2 * TWO_PI / points
        d2 = d2[keep]
        d1max = max(float(np.max(np.abs(d1))), max(max(abs(k.slope_left), abs(k.slope_right)) for k in wall.kinks))
    else:
        d1max = float(np.max(np.abs(d1)))
    d1max = d1max * 1.01 + float(np.max(np.abs(np.diff(d1)))) + 1e-12
    d2max = float(np.max(np.abs(d2))) * 1.01 + float(np.max(np.abs(np.diff(d2)))) + 1e-12
    return d1max, d2max, kinks


def _polish(table, th, eta, vt, ve, side, t):
    """Brent's method on the exact wall from a point with gap ≤ tol, if a sign change is near; else ``t``."""
    from scipy.optimize import brentq

    def gap(s):
        if side == 0:
            return eta + ve * s - table.lower(th + vt * s)
        return table.upper(th + vt * s) - eta - ve * s

    g0 = gap(t)
    if g0 <= 0.0:
        return t
    for width in (1e-12, 1e-10, 1e-8):
        if gap(t + width) < 0.0:
            return brentq(gap, t, t + width, xtol=1e-16, rtol=1e-15, maxiter=200)
    return t  # a graze below tol without a crossing: the contact is where the gap is smallest, to tol


def _reference_run(table: Billiard, state, leaving: int, collisions: int):
    wall = table.wall
    lip, curv, kinks = _sample_bounds(wall)
    tol = table.tol
    th, eta, vt, ve = (float(x) for x in state)
    rows = []
    note = ""
    clock = 0.0
    for _ in range(collisions):
        lam = abs(ve) + abs(vt) * lip
        t = 0.0
        hit = -1
        for step in range(_REFERENCE_MAX_STEPS):
            b, d1, _ = wall.derivatives(np.array([th + vt * t, th + math.pi + vt * t]))
            g = np.array([eta + ve * t - table.b0 - b[0], table.H - table.b0 - b[1] - eta - ve * t])
            if step == 0 and leaving >= 0:
                # on the wall just left: g = 0, g' > 0; a second-order step that does not cross a kink
                g1 = (ve - vt * d1[0]) if leaving == 0 else (-ve - vt * d1[1])
                tau = 2.0 * g1 / (vt * vt * curv) if vt != 0 else math.inf
                if kinks.size and vt != 0:
                    phi = th + leaving * math.pi
                    ahead = ((kinks - phi) * np.sign(vt)) % TWO_PI
                    ahead = ahead[ahead > 0]
                    if ahead.size:
                        tau = min(tau, float(ahead.min()) / abs(vt))
                other = 1 - leaving
                tau = min(tau, g[other] / lam)
                t += tau
                continue
            k = int(np.argmin(g))
            if g[k] <= tol:
                hit = k
                t = _polish(table, th, eta, vt, ve, k, t)
                b, d1, _ = wall.derivatives(np.array([th + vt * t, th + math.pi + vt * t]))
                break
            t += float(g[k]) / lam
        else:
            note = f"reference stepper did not converge within {_REFERENCE_MAX_STEPS} steps"
            break
        th, eta = th + vt * t, eta + ve * t
        slope = float(d1[0]) if hit == 0 else -float(d1[1])
        dot = ve - slope * vt
        norm = 1.0 + slope * slope
        vt, ve = vt + 2.0 * dot * slope / norm, ve - 2.0 * dot / norm
        speed = math.hypot(vt, ve)
        vt, ve = vt / speed, ve / speed
        clock += t
        rows.append((clock, th, eta, vt, ve, hit))
        leaving = hit
    return rows, note


# ---------------------------------------------------------------------------------------------------- kernel
def _cell_bounds(wall: Wall, cells: int = CELLS, samples: int = SAMPLES):
    """Cells of the period and per-cell bounds for the kernel.

    Edges: a uniform grid of ``cells`` cells, plus every kink angle (a grid edge
    within 1e-9 of a kink is replaced by it).  Per cell j, from ``samples`` + 1
    points including both ends (b) and ``samples`` interior points (b''):

    * ``bmax_j = max b + max |Δb|`` and ``c_j = max b'' + max |Δb''|`` where Δ is
      the difference between neighbouring samples: the true maximum between
      two samples exceeds the sampled one by at most about half the local
      variation, so the margin is twice what the first-order estimate needs.
    * The bounds are then *checked* on a shifted grid 4 times finer; where a
      check fails the margin of that cell is doubled and the check repeated
      (so an unresolved narrow feature cannot slip through silently).

    Also the quintic proxy of b per cell and its error bound (:func:`_cell_proxies`).
    Returns a dict of arrays; :func:`_cell_table` packs them for the kernel.
    """
    kinks = sorted(k.angle % TWO_PI for k in wall.kinks)
    edges = list(np.linspace(0.0, TWO_PI, cells + 1))
    for a in kinks:
        i = int(np.argmin(np.abs(np.array(edges) - a)))
        if abs(edges[i] - a) < 1e-9:
            edges[i] = a
            if i == 0:
                edges[-1] = a + TWO_PI
            if i == cells:
                edges[0] = a - TWO_PI
        else:
            edges.append(a)
    edges = np.array(sorted(edges))
    if edges[0] != 0.0:  # a kink moved the seam; keep the period [0, 2π] exactly
        edges[0], edges[-1] = 0.0, TWO_PI
    m = edges.size - 1
    width = np.diff(edges)
    u = np.linspace(0.0, 1.0, samples + 1)
    pts_b = edges[:-1, None] + width[:, None] * u[None, :]
    # b'' inside the open cell only: at a kink edge b'' includes the other side
    v = (np.arange(samples) + 0.5) / samples
    v = np.concatenate([[1e-7], v, [1 - 1e-7]])
    pts_2 = edges[:-1, None] + width[:, None] * v[None, :]
    b = wall(pts_b.ravel()).reshape(pts_b.shape)
    d2 = wall.derivatives(pts_2.ravel())[2].reshape(pts_2.shape)
    margin_b = np.max(np.abs(np.diff(b, axis=1)), axis=1) + 1e-12 * wall.scale
    margin_2 = np.max(np.abs(np.diff(d2, axis=1)), axis=1) + 1e-9 * (1 + np.max(np.abs(d2)))
    bmax = b.max(axis=1)
    cmax = d2.max(axis=1)
    fine = 4 * samples
    w = (np.arange(fine) + 0.37) / fine
    pts_f = edges[:-1, None] + width[:, None] * w[None, :]
    bf, _, d2f = (x.reshape(pts_f.shape) for x in wall.derivatives(pts_f.ravel()))
    _require_finite(wall, (pts_b, pts_2, pts_f, pts_f), (b, d2, bf, d2f))
    margin_b = _widen(margin_b, bmax, bf.max(axis=1))
    margin_2 = _widen(margin_2, cmax, d2f.max(axis=1))
    bmax = bmax + margin_b
    cmax = cmax + margin_2
    d3max = _third_derivative_bound(pts_2, d2, pts_f, d2f)
    bmin_global = float(np.min(b) - np.max(margin_b))
    slope_left = np.full(m + 1, np.nan)
    slope_right = np.full(m + 1, np.nan)
    for k in wall.kinks:
        a = k.angle % TWO_PI
        for i in np.flatnonzero(np.abs(edges - a) < 1e-12):
            slope_left[i], slope_right[i] = k.slope_left, k.slope_right
        if abs(a) < 1e-12 or abs(a - TWO_PI) < 1e-12:
            slope_left[[0, m]], slope_right[[0, m]] = k.slope_left, k.slope_right
    lookup = np.searchsorted(edges, np.linspace(0.0, TWO_PI, cells, endpoint=False), side="right") - 1
    lookup = np.clip(lookup, 0, m - 1).astype(np.int64)
    proxy, perr, p2max, p2abs = _cell_proxies(wall, edges, slope_left, slope_right, samples)
    return {"edges": edges, "bmax": bmax, "cmax": cmax, "slope_left": slope_left, "slope_right": slope_right,
            "lookup": lookup, "nunif": cells, "wmin": bmin_global, "wmax": float(bmax.max()),
            "proxy": proxy, "perr": perr, "p2max": p2max, "p2abs": p2abs, "d3max": d3max}


def _widen(margin, base, check):
    """Double ``margin`` per cell until ``base + margin`` covers ``check`` (at most 60 times).

    The bounds are sampled maxima plus a margin; ``check`` is the same quantity sampled
    on a finer, shifted grid, so a cell whose margin was too small cannot slip through.
    """
    margin = np.array(margin, dtype=float)
    for _ in range(60):
        bad = check > base + margin
        if not bad.any():
            break
        margin[bad] *= 2
    return margin


def _require_finite(wall: Wall, points, values):
    """InvalidWall naming the first angle where a sampled b or b'' is nan or infinite.

    The wall was checked on a grid when it was made; the kernel's denser sampling can still
    land on a pole or a domain error between those points, and a nan bound would silently
    turn a cell into "no contact here".
    """
    for pts, vals in zip(points, values):
        bad = ~np.isfinite(vals)
        if bad.any():
            angle = float(np.asarray(pts).ravel()[np.flatnonzero(bad.ravel())[0]] % TWO_PI)
            raise InvalidWall(f"wall {wall.description!r} is not finite at θ = {angle:.9g} (b or b'' is nan or "
                              f"infinite there; found by the billiard's dense sampling): the billiard needs a "
                              f"finite wall")


def _third_derivative_bound(pts, d2, pts_f, d2f):
    """Per-cell bound of |b'''| from the slopes of sampled b'' (interior points of each cell).

    Twice the largest difference quotient of neighbouring samples plus the
    largest change between neighbouring quotients, then checked against the
    quotients on the finer shifted grid (doubled where they exceed it).  Used
    only to decide when a contact found by a second-order step needs no
    confirming evaluation (the Taylor remainder of that step, see the kernel).
    """
    q = np.abs(np.diff(d2, axis=1) / np.diff(pts, axis=1))
    bound = 2.0 * q.max(axis=1) + np.abs(np.diff(q, axis=1)).max(axis=1) + 1e-9
    qf = np.abs(np.diff(d2f, axis=1) / np.diff(pts_f, axis=1)).max(axis=1)
    return _widen(bound, 0.0, qf)


def _cell_proxies(wall: Wall, edges, slope_left, slope_right, samples: int = SAMPLES):
    """Per cell j a quintic proxy ``p_j`` of b and a bound ``e_j`` of ``|b − p_j|`` on the cell.

    ``p_j(s) = Σ_k c_k s^k`` (k = 0..5) with ``s = φ − edges[j]`` is the quintic
    Hermite interpolant of the exact b, b', b'' at both cell ends (one-sided
    values at a kink, so the proxy follows the smooth piece inside the cell).
    Its error is O(w⁶ max|b⁽⁶⁾|): ~1e-8 where the ε = 99 coin is sharpest
    (b ≈ 0.1 there), near rounding elsewhere.  ``e_j`` is sampled like the other
    cell bounds: twice the largest sampled |b − p| plus the largest change
    between neighbouring samples plus a rounding floor, then checked on a
    shifted grid 4 times finer (margin doubled where the check fails).
    ``p2max_j ≥ max p_j''`` over the cell is rigorous for the polynomial: the
    sampled maximum plus max|p'''| times half the sample spacing; ``p2abs_j ≥ max |p_j''|`` likewise.
    """
    m = edges.size - 1
    width = np.diff(edges)
    b_e, d_e, c_e = wall.derivatives(edges)
    curv_left = np.full(m + 1, np.nan)
    curv_right = np.full(m + 1, np.nan)
    for k in wall.kinks:
        a = k.angle % TWO_PI
        near = np.abs(edges - a) < 1e-12
        if abs(a) < 1e-12 or abs(a - TWO_PI) < 1e-12:
            near[[0, m]] = True
        curv_left[near], curv_right[near] = k.curvature_left, k.curvature_right
    # one-sided values inside cell j: from the right at its left end, from the left at its right end
    d0 = np.where(np.isnan(slope_right[:-1]), d_e[:-1], slope_right[:-1])
    d1 = np.where(np.isnan(slope_left[1:]), d_e[1:], slope_left[1:])
    e0 = np.where(np.isnan(curv_right[:-1]), c_e[:-1], curv_right[:-1])
    e1 = np.where(np.isnan(curv_left[1:]), c_e[1:], curv_left[1:])
    b0, b1, w = b_e[:-1], b_e[1:], width
    proxy = np.empty((m, 6))
    proxy[:, 0], proxy[:, 1], proxy[:, 2] = b0, d0, 0.5 * e0
    r0 = b1 - (b0 + w * (d0 + w * 0.5 * e0))
    r1 = (d1 - (d0 + w * e0)) * w
    r2 = (e1 - e0) * w * w
    proxy[:, 3] = (10.0 * r0 - 4.0 * r1 + 0.5 * r2) / w**3
    proxy[:, 4] = (-15.0 * r0 + 7.0 * r1 - r2) / w**4
    proxy[:, 5] = (6.0 * r0 - 3.0 * r1 + 0.5 * r2) / w**5

    def polynomial(s, derivative=0):
        out = np.zeros_like(s)
        for k in range(5, derivative - 1, -1):
            factor = math.factorial(k) // math.factorial(k - derivative)
            out = out * s + factor * proxy[:, k, None]
        return out

    def error(u):
        s = width[:, None] * u[None, :]
        b = wall((edges[:-1, None] + s).ravel()).reshape(s.shape)
        return b - polynomial(s)

    u = np.concatenate([[1e-9], (np.arange(2 * samples) + 0.5) / (2 * samples), [1 - 1e-9]])
    err = error(u)
    _require_finite(wall, [edges[:-1, None] + width[:, None] * u[None, :]], [err])
    floor = 1e-14 * max(1.0, wall.scale)
    perr = 2.0 * np.max(np.abs(err), axis=1) + np.max(np.abs(np.diff(err, axis=1)), axis=1) + floor
    fine = 8 * samples
    perr = _widen(perr, 0.0, np.max(np.abs(error((np.arange(fine) + 0.37) / fine)), axis=1))
    grid = np.linspace(0.0, 1.0, 65)
    p2 = polynomial(width[:, None] * grid[None, :], 2)
    p3 = 6 * np.abs(proxy[:, 3]) + 24 * np.abs(proxy[:, 4]) * width + 60 * np.abs(proxy[:, 5]) * width**2
    between = p3 * width / 128 * 1.01  # how far p'' can rise between grid points
    p2max = p2.max(axis=1) + between
    p2abs = np.abs(p2).max(axis=1) + between
    return np.ascontiguousarray(proxy), perr, p2max, p2abs


def _cell_table(bounds) -> np.ndarray:
    """The cell bounds as one (m, 16) table for the kernel (one row, one cache line or two, per cell).

    Columns: left and right edge, bmax, c (bound of b''), the kink slopes seen when
    entering through the left edge (moving forward) and through the right edge
    (moving backward; NaN where the edge is no kink), the quintic proxy c0..c5,
    its error bound e, max p'', the bound of |b'''| and max |p''|.  One table instead of a dozen arrays keeps
    the per-call bookkeeping of numba small.
    """
    edges = bounds["edges"]
    m = edges.size - 1
    table = np.empty((m, 16))
    table[:, 0] = edges[:-1]
    table[:, 1] = edges[1:]
    table[:, 2] = bounds["bmax"]
    table[:, 3] = bounds["cmax"]
    table[:, 4] = bounds["slope_right"][:-1]
    table[:, 5] = bounds["slope_left"][1:]
    table[:, 6:12] = bounds["proxy"]
    table[:, 12] = bounds["perr"]
    table[:, 13] = bounds["p2max"]
    table[:, 14] = bounds["d3max"]
    table[:, 15] = bounds["p2abs"]
    return np.ascontiguousarray(table)


KERNEL_SOURCE = '''
TWO_PI = 2.0 * math.pi
INV_TWO_PI = 1.0 / TWO_PI
PI = math.pi
INF = math.inf
ROUND_T = 1e-15  # a time interval this small (relative) is rounding
# columns of the cell table (one row per cell, see _cell_table)
LEFT, RIGHT, BMAX, CMAX, SLOPE_FWD, SLOPE_BWD, P0, P1, P2, P3, P4, P5, PERR, P2MAX, D3MAX, P2ABS = range(16)
POS_TOL = 0.01  # a second-order contact is taken unconfirmed when its Taylor remainder is below POS_TOL·tol


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
    if tcap < t_hi:
        t_hi = tcap
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
    i = int(x * (nunif * INV_TWO_PI))
    if i >= nunif:
        i = nunif - 1
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
    while True:
        t_out = (cells[j, edge] + start) * ivt
        if t_out > t_hi:
            t_out = t_hi
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
                if g1_leave == g1_leave:
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
                        if slope == slope:
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
def _run(state, leaving, n, H, b0, c, cells, lookup, wmin, wmax, tol,
         out_time, out_theta, out_eta, out_vt, out_ve, out_side):
    theta = state[0]
    eta = state[1]
    vt = state[2]
    ve = state[3]
    c = carray(_data_pointer(c), c.shape)
    cells = carray(_data_pointer(cells), cells.shape)
    lookup = carray(_data_pointer(lookup), lookup.shape)
    wraps = math.floor(theta / TWO_PI)
    th = theta - wraps * TWO_PI
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
        leaving = side
    return n, 0


@njit(cache=True, parallel=True)
def _run_many(states, leaving, n, H, b0, c, cells, lookup, wmin, wmax, tol,
              out_time, out_theta, out_eta, out_vt, out_ve, out_side, done, status):
    for k in prange(states.shape[0]):
        d, s = _run(states[k], leaving[k], n, H, b0, c, cells, lookup, wmin, wmax, tol,
                    out_time[k], out_theta[k], out_eta[k], out_vt[k], out_ve[k], out_side[k])
        done[k] = d
        status[k] = s
'''

_HEADER = ("import math\nimport numpy as np\nfrom numba import carray, njit, prange, types\n"
           "from numba.extending import intrinsic\n\n"
           "OPTIONS = dict(cache=True, error_model='numpy')\n\n")
_NOTES = {1: "free flight: the particle moves parallel to the walls in an open channel and never collides again",
          2: "the kernel's root search did not converge (a near-tangent graze?)",
          3: "the wall evaluated to nan or infinity where the particle met it (a pole or a domain error of the "
             "expression between the angles it was checked on)"}


class _Compiled:
    """The kernel for one wall: the generated module plus the wall's constants and cell bounds."""

    def __init__(self, wall: Wall):
        from .wallcode import load_module, wall_source

        source, constants = wall_source(wall, "@njit(**OPTIONS)\n")
        self.module = load_module(_HEADER + source + KERNEL_SOURCE, "coinwall_billiard")
        self.constants = np.ascontiguousarray(constants, dtype=float)
        self.bounds = _cell_bounds(wall)
        self.cells = _cell_table(self.bounds)

    def args(self, table: Billiard):
        bd = self.bounds
        return (float(table.H), float(table.b0), self.constants, self.cells, bd["lookup"], bd["wmin"], bd["wmax"],
                float(table.tol))


_KERNELS: "weakref.WeakKeyDictionary[Wall, _Compiled]" = weakref.WeakKeyDictionary()


def _compiled(table: Billiard) -> _Compiled:
    # bounds depend on the wall only (H and b0 are run-time arguments): one entry per wall object
    comp = _KERNELS.get(table.wall)
    if comp is None:
        comp = _KERNELS[table.wall] = _Compiled(table.wall)
    return comp


def compile_kernel(table: Billiard) -> float:
    """Compile (or load from numba's disk cache) the kernels for ``table``'s wall; return the seconds it took.

    Both the single-orbit kernel (:func:`simulate`) and the parallel one (:func:`ensemble`).
    """
    import time

    _check_table(table)
    start = time.perf_counter()
    comp = _compiled(table)
    states = random_states(table, 1, seed=0)
    _kernel_run(comp, table, states[0], -1, 1)
    ensemble(table, states, 1, workers=1)  # the parallel driver is a separate compiled function
    return time.perf_counter() - start


def _kernel_run(comp, table, state, leaving, collisions):
    out = [np.empty(collisions) for _ in range(5)] + [np.empty(collisions, dtype=np.int8)]
    done, status = comp.module._run(np.ascontiguousarray(state, dtype=float), int(leaving), collisions,
                                    *comp.args(table), *out)
    return [o[:done] for o in out], _NOTES.get(int(status), "")


# ---------------------------------------------------------------------------------------------------- API
def _trajectory(table, start, speed, rows, note, method):
    time, theta, eta, vt, ve, side = rows
    return Trajectory(time=np.asarray(time, dtype=float) / speed, theta=np.asarray(theta, dtype=float),
                      eta=np.asarray(eta, dtype=float), v_theta=np.asarray(vt, dtype=float) * speed,
                      v_eta=np.asarray(ve, dtype=float) * speed, side=np.asarray(side, dtype=np.int8),
                      start=np.array(start, dtype=float), table=table, method=method, note=note)


def simulate(table: Billiard, state, collisions: int, method: str = "kernel") -> Trajectory:
    """Follow one orbit for ``collisions`` collisions.

    Parameters
    ----------
    table : Billiard
    state : array_like (4,)
        ``[theta, eta, v_theta, v_eta]``: inside the strip, or on a wall moving
        into the strip (e.g. :attr:`Trajectory.final_state`, to continue an orbit).
    collisions : int
        Number of collisions (> 0).
    method : {"kernel", "reference"}
        The numba kernel, or the plain-numpy reference stepper (slow).

    Returns
    -------
    Trajectory
    """
    _check_table(table)
    _check_method(method)
    collisions = _check_count(collisions)
    unit, speed, leaving = _check_states(table, state)
    if method == "reference":
        rows, note = _reference_run(table, unit[0], int(leaving[0]), collisions)
        cols = list(zip(*rows)) if rows else [[] for _ in range(6)]
        return _trajectory(table, np.asarray(state, dtype=float).ravel(), speed[0], cols, note, method)
    rows, note = _kernel_run(_compiled(table), table, unit[0], int(leaving[0]), collisions)
    return _trajectory(table, np.asarray(state, dtype=float).ravel(), speed[0], rows, note, method)


def ensemble(table: Billiard, states, collisions: int, method: str = "kernel", workers=None) -> list:
    """Follow many orbits in parallel (numba threads over orbits).

    Each orbit is computed by the same sequential code whatever the number of
    threads, so the result does not depend on ``workers``.

    Parameters
    ----------
    table : Billiard
    states : array_like (n, 4)
        Start states (e.g. from :func:`random_states`).
    collisions : int
        Collisions per orbit.
    method : {"kernel", "reference"}
        ``"reference"`` runs the orbits one after the other.
    workers : int, optional
        Number of threads (default: numba's default, all cores).

    Returns
    -------
    list of Trajectory
    """
    _check_table(table)
    _check_method(method)
    collisions = _check_count(collisions)
    unit, speed, leaving = _check_states(table, states, "states")
    starts = np.array(states, dtype=float).reshape(-1, 4)
    if method == "reference":
        return [simulate(table, s, collisions, method) for s in starts]
    import numba

    if workers is not None:
        if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers <= 0:
            raise InvalidArgument(f"`workers` must be a positive integer or None, got {workers!r}")
        workers = min(int(workers), numba.config.NUMBA_NUM_THREADS)
    comp = _compiled(table)
    m = unit.shape[0]
    out = [np.empty((m, collisions)) for _ in range(5)] + [np.empty((m, collisions), dtype=np.int8)]
    done = np.zeros(m, dtype=np.int64)
    status = np.zeros(m, dtype=np.int64)
    previous = numba.get_num_threads()
    try:
        if workers is not None:
            numba.set_num_threads(workers)
        comp.module._run_many(unit, leaving, collisions, *comp.args(table), *out, done, status)
    finally:
        numba.set_num_threads(previous)
    return [_trajectory(table, starts[k], speed[k], [o[k, :done[k]] for o in out], _NOTES.get(int(status[k]), ""),
                        method) for k in range(m)]
