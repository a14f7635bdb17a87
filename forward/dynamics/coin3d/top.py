"""The coin in three dimensions: a body of revolution on a floor (and under a ceiling) is a 2-D billiard.

The reduction (derived in ``docs/coin3d.md``)
---------------------------------------------
A body of revolution (mass M, moments I₁ = I₂ across and I₃ along its symmetry axis ``a``) moves under
gravity between impacts with frictionless horizontal walls.  With θ ∈ [0, π] the tilt of ``a`` from the
upward vertical, φ its azimuth, ψ the spin about ``a`` and z the height of the centre of mass, the
Lagrangian is ``½M(ẋ² + ẏ² + ż²) + ½I₁(θ̇² + φ̇² sin²θ) + ½I₃(ψ̇ + φ̇ cos θ)² − M g z``.  φ and ψ are cyclic:
``L_z = I₁ φ̇ sin²θ + L₃ cos θ`` and ``L₃ = I₃(ψ̇ + φ̇ cos θ)`` are constant in flight.  They are constant
through impacts too: the wall pushes vertically at the lowest point q, which lies in the plane of ``a`` and
the vertical, so the angular impulse ``q × J ẑ`` is horizontal and perpendicular to ``a`` (along the line of
nodes) and changes neither ``L·ẑ`` nor ``L·a``.  Eliminating φ̇ (Routh), with ``η = z/κ₁`` (κ₁ = √(I₁/M)),
``ℓ = L/I₁`` and energies per ``Mκ₁²``:

    E = ½(θ̇² + η̇²) + V(θ) + g η + ℓ₃² I₁/(2 I₃),     V(θ) = (ℓ_z − ℓ₃ cos θ)² / (2 sin² θ),

a unit point mass in the (θ, η) plane with the Euclidean metric, the torque-free symmetric top's effective
potential V (the last term is constant) and the field g (in κ₁/s²).  The walls: the floor ``η = b(θ)``,
``b = h/κ₁`` with h the support function of the body downwards (:mod:`..revolution`), the ceiling
``η = H − b(π − θ)``.  The impulse changes (θ̇, η̇) along the wall's normal ``(−b', 1)`` with Newton's law on
the normal velocity (the lever arm of the contact is ``κ₁ b'``, exactly as for the planar body,
:mod:`.field`).  With ``ℓ_z = ℓ₃ = 0``, V = 0 and the axis turns in a vertical plane: the paper's planar
coin, with θ folded into [0, π] (``θ_planar`` and ``−θ_planar`` are the same tilt).

Between impacts cos θ is sinusoidal in time: the axis precesses uniformly about the fixed angular momentum
(:mod:`._top_kernel` computes it as a rotation; :func:`reference_run` from the sinusoid
``u = cos θ``, ``ü = −Ω² u + ℓ_z ℓ₃`` with ``Ω² = θ̇² + p² + ℓ₃²``, p the azimuthal speed).
When ``ℓ_z ≠ ±ℓ₃`` the potential is a barrier at the poles; when ``ℓ_z = ±ℓ₃`` the axis passes through
the vertical and θ is reflected at 0 or π (the fold).  Status codes are in :data:`STATUS`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...revolution import Revolution
from ...validation import check_count, check_finite

__all__ = ["STATUS", "TopFlight", "TopTable", "energy", "first_root", "potential", "reference_run", "sides_at_bounces",
           "state_after", "top_run"]

STATUS = {0: "impact budget reached", 1: "settled (energy below the equator's barrier)",
          2: "caught", 6: "free flight (no further impact)",
          7: "the root search did not converge", 11: "a face met the wall flat at a pole (no departure window)"}


@dataclass(frozen=True, repr=False)
class TopTable:
    """A body of revolution on a floor (and optionally under a ceiling) in a field, with restitution.

    Parameters
    ----------
    body : Revolution
    g : float
        The field in κ₁/s² along −η (≥ 0).
    e : float
        Newton's coefficient of restitution on the normal velocity, in (0, 1].
    H : float or None
        Height of the ceiling (κ₁) above the floor's reference; ``None``: a floor only.
    tol : float
        Contact tolerance (κ₁).

    Examples
    --------
    >>> from coinwall.forward.revolution import coin
    >>> from coinwall.forward.dynamics import TopTable
    >>> table = TopTable(coin(1.0, 0.2), g=1.0, e=0.5)          # a thick coin on a floor
    >>> h = float(table.floor(0.3))                              # the floor's height at tilt θ = 0.3
    >>> table
    TopTable(coin r=1 thickness=0.2, g=1, e=0.5, H=None)
    >>> round(h, 6)
    0.776945
    """

    body: Revolution
    g: float = 0.0
    e: float = 1.0
    H: float | None = None
    tol: float = 1e-12

    def __post_init__(self):
        if not isinstance(self.body, Revolution):
            raise InvalidArgument(f"`body` must be a Revolution, got {type(self.body).__name__}")
        g = check_finite("g", self.g)
        if g < 0:
            raise InvalidArgument(f"`g` must be >= 0, got {g:g}")
        e = check_finite("e", self.e)
        if not 0.0 < e <= 1.0:
            raise InvalidArgument(f"`e` must be in (0, 1], got {e:g}")
        if self.H is not None:
            H = check_finite("H", self.H)
            width = float(np.max(self._b(np.linspace(0, math.pi, 2001)) + self._b(math.pi - np.linspace(0, math.pi,
                                                                                                      2001))))
            if not H > width:
                raise InvalidArgument(f"`H` must exceed the body's largest height b(θ) + b(π − θ) = {width:.6g} (κ₁), "
                                      f"got {H:g}")
        tol = check_finite("tol", self.tol)
        if not 0 < tol < 1e-3:
            raise InvalidArgument(f"`tol` must be in (0, 1e-3), got {tol:g}")

    def _b(self, theta):
        return self.body.wall(theta)

    def floor(self, theta):
        """``b(θ)``: the floor in (θ, η)."""
        return self._b(np.asarray(theta, dtype=float))

    def ceiling(self, theta):
        """``H − b(π − θ)`` (``inf`` without a ceiling)."""
        th = np.asarray(theta, dtype=float)
        if self.H is None:
            return np.full(th.shape, np.inf)
        return self.H - self._b(math.pi - th)

    def kernel_args(self):
        kind, verts, eps, ea, ec, reach = self.body.kernel_params()
        return (float(self.g), float(self.e), float(self.H) if self.H is not None else 0.0, self.H is not None,
                kind, verts, eps, ea, ec, reach, float(self.tol))

    @safe_repr
    def __repr__(self):
        return f"TopTable({self.body.name}, g={self.g:g}, e={self.e:g}, H={self.H})"


def potential(theta, lz, l3):
    """The top's effective potential ``V(θ) = (ℓ_z − ℓ₃ cos θ)²/(2 sin²θ)`` (units 1/s²), finite at a pole
    the axis can reach (ℓ_z = ±ℓ₃: ``ℓ₃² tan²(θ/2)/2`` resp. ``ℓ₃² cot²(θ/2)/2``), ``inf`` at a barrier."""
    th = np.asarray(theta, dtype=float)
    s, c = np.sin(th), np.cos(th)
    with np.errstate(divide="ignore", invalid="ignore"):
        upper = (lz - l3) / s + l3 * s / (1 + c)
        lower = (lz + l3) / s - l3 * s / (1 - c)
        p = np.where(c >= 0, upper, lower)
        at_pole = s == 0
        p = np.where(at_pole & (np.where(c > 0, lz - l3, lz + l3) == 0), 0.0, p)
        p = np.where(at_pole & (np.where(c > 0, lz - l3, lz + l3) != 0), np.inf, p)
    return 0.5 * p * p


def energy(table: TopTable, theta, eta, v_theta, v_eta, lz, l3):
    """``½(θ̇² + η̇²) + V(θ) + g η`` (per M κ₁², without the constant spin term ℓ₃² I₁/(2 I₃))."""
    return (0.5 * (np.asarray(v_theta) ** 2 + np.asarray(v_eta) ** 2) + potential(theta, lz, l3)
            + table.g * np.asarray(eta))


@dataclass(frozen=True, repr=False)
class TopFlight:
    """The impacts of one orbit: ``time`` (since the start), the state just after each impact
    (``theta``, ``eta``, ``v_theta``, ``v_eta``) and the ``wall`` hit (0 floor, 1 ceiling); ``status``.

    Attributes
    ----------
    time : ndarray (n,)
        Time of each impact since the start.
    theta, eta, v_theta, v_eta : ndarray (n,)
        The state just after each impact: tilt, height of the centre of mass and their rates.
    wall : ndarray (n,) of int
        0 floor, 1 ceiling.
    lz, l3 : float
        The conserved ``ℓ_z`` and ``ℓ₃`` (rad/s).
    status : str
        Why the orbit ended.
    method : str
        ``"kernel"`` or ``"reference"``.

    Examples
    --------
    >>> from coinwall.forward.revolution import coin
    >>> from coinwall.forward.dynamics import TopTable
    >>> table = TopTable(coin(1.0, 0.2), g=1.0, e=0.5)          # a thick coin on a floor
    >>> h = float(table.floor(0.3))                              # the floor's height at tilt θ = 0.3
    >>> from coinwall.forward.dynamics import top_run
    >>> flight = top_run(table, [0.3, h + 1.0, 0.5, 0.0], 0.0, 0.0, 5)
    >>> flight.wall.tolist(), flight.status
    ([0, 0, 0, 0, 0], 'impact budget reached')
    """

    time: np.ndarray
    theta: np.ndarray
    eta: np.ndarray
    v_theta: np.ndarray
    v_eta: np.ndarray
    wall: np.ndarray
    lz: float
    l3: float
    status: str
    method: str

    @property
    def impacts(self) -> int:
        return int(self.time.size)

    def states(self) -> np.ndarray:
        return np.column_stack([self.theta, self.eta, self.v_theta, self.v_eta])

    @safe_repr
    def __repr__(self):
        return f"TopFlight({self.impacts} impacts, ℓz={self.lz:g}, ℓ3={self.l3:g}, {self.status}, {self.method})"


def _check_state(table, state, lz, l3):
    try:
        arr = np.array(state, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`state` must be four numbers [theta, eta, v_theta, v_eta], got {state!r}") from None
    if arr.shape != (4,) or not np.all(np.isfinite(arr)):
        raise InvalidArgument(f"`state` must be four finite numbers [theta, eta, v_theta, v_eta], got {state!r}")
    if not 0.0 <= arr[0] <= math.pi:
        raise InvalidArgument(f"`state` tilt θ must be in [0, π], got {arr[0]!r}")
    lz = check_finite("lz", lz)
    l3 = check_finite("l3", l3)
    if not math.isfinite(float(potential(arr[0], lz, l3))):
        raise InvalidArgument(f"θ = {arr[0]!r} is a pole the axis cannot reach with ℓz = {lz:g}, ℓ3 = {l3:g} "
                              "(ℓz must equal ±ℓ3 there)")
    low = float(table.floor(arr[0]))
    if not arr[1] > low + 10 * table.tol:
        raise InvalidArgument(f"`state` η = {arr[1]:.6g} is not above the floor b(θ) = {low:.6g}")
    if table.H is not None and not arr[1] < float(table.ceiling(arr[0])) - 10 * table.tol:
        raise InvalidArgument(f"`state` η = {arr[1]:.6g} is not below the ceiling")
    return arr, lz, l3


def top_run(table: TopTable, state, lz: float, l3: float, impacts: int, method: str = "kernel") -> TopFlight:
    """One orbit for ``impacts`` impacts from ``state`` = (θ, η, θ̇, η̇) strictly inside the table, with the
    conserved ``ℓ_z = L_z/I₁`` and ``ℓ₃ = L₃/I₁`` (rad/s).  ``method``: ``"kernel"`` (numba) or
    ``"reference"`` (:func:`reference_run`).

    Parameters
    ----------
    table : TopTable
    state : array_like (4,)
        ``(θ, η, θ̇, η̇)``: tilt in [0, π], height of the centre of mass (κ₁) and their rates.
    lz, l3 : float
        ``ℓ_z = L_z/I₁`` and ``ℓ₃ = L₃/I₁`` (rad/s).
    impacts : int
        Impacts to follow.
    method : {"kernel", "reference"}

    Returns
    -------
    TopFlight

    Raises
    ------
    InvalidArgument
        For a state that is not four finite numbers, a tilt outside [0, π] or at a pole that ``ℓ_z``, ``ℓ₃``
        forbid, a height not between the walls, or an unknown method.

    Examples
    --------
    The compiled kernel and the plain reference stepper follow the same orbit:

    >>> from coinwall.forward.revolution import coin
    >>> from coinwall.forward.dynamics import TopTable
    >>> table = TopTable(coin(1.0, 0.2), g=1.0, e=0.5)          # a thick coin on a floor
    >>> h = float(table.floor(0.3))                              # the floor's height at tilt θ = 0.3
    >>> from coinwall.forward.dynamics import top_run
    >>> kernel = top_run(table, [0.3, h + 1.0, 0.5, 0.0], 0.0, 0.0, 5)
    >>> reference = top_run(table, [0.3, h + 1.0, 0.5, 0.0], 0.0, 0.0, 5, method="reference")
    >>> bool(abs(kernel.theta - reference.theta).max() < 1e-8)
    True
    """
    if not isinstance(table, TopTable):
        raise InvalidArgument(f"`table` must be a TopTable, got {type(table).__name__}")
    impacts = check_count("impacts", impacts, maximum=100_000_000)
    arr, lz, l3 = _check_state(table, state, lz, l3)
    if method == "reference":
        rows, code = reference_run(table, arr, lz, l3, impacts)
        cols = [np.array(c, dtype=float) for c in zip(*rows)] if rows else [np.empty(0) for _ in range(6)]
        return TopFlight(*cols[:5], cols[5].astype(np.int8), lz, l3, STATUS[code], method)
    if method != "kernel":
        raise InvalidArgument(f"`method` must be 'kernel' or 'reference', got {method!r}")
    k = _kernel()

    out = [np.empty(impacts) for _ in range(5)] + [np.empty(impacts, dtype=np.int8)]
    done, code = k.run(arr, lz, l3, -1, impacts, *table.kernel_args(), math.inf, *out)
    return TopFlight(*[o[:done] for o in out[:5]], out[5][:done], lz, l3, STATUS[int(code)], method)


def _kernel():
    """:mod:`._top_kernel`, its functions given coinwall's kernel cache on first use."""
    from ..billiard.wallcode import cache_module
    from . import _top_kernel

    cache_module(_top_kernel)
    return _top_kernel


def state_after(table: TopTable, states, lz, l3, times) -> np.ndarray:
    """(θ, η, θ̇, η̇) of many free flights (no walls) after their own ``times`` (compiled, parallel)."""
    k = _kernel()

    arr = np.ascontiguousarray(np.asarray(states, dtype=float).reshape(-1, 4))
    n = arr.shape[0]
    lz = np.ascontiguousarray(np.broadcast_to(np.asarray(lz, dtype=float), (n,)))
    l3 = np.ascontiguousarray(np.broadcast_to(np.asarray(l3, dtype=float), (n,)))
    times = np.ascontiguousarray(np.broadcast_to(np.asarray(times, dtype=float), (n,)))
    if not (np.all(np.isfinite(arr)) and np.all(np.isfinite(lz)) and np.all(np.isfinite(l3))
            and np.all(np.isfinite(times))):
        raise InvalidArgument("states, ℓz, ℓ3 and times must be finite numbers")
    out = np.empty((n, 4))
    k.states_at_many(arr, lz, l3, float(table.g), times, out)
    return out


def sides_at_bounces(table: TopTable, states, lz, l3, bounces: int):
    """The side up (+1: cos θ > 0, −1: cos θ < 0) at each of the first ``bounces`` floor impacts of many tosses
    (compiled, parallel over tosses); returns ``(sides (m, bounces) int8, status (m,))``.  A toss whose energy
    after a floor impact is below the barrier of the equator, ``ℓz²/2 + g b(π/2)`` (the least energy with which
    the axis can pass θ = π/2), keeps its side for ever: its remaining bounces get that side (status 1).  After
    another early stop the sides are 0."""
    k = _kernel()

    bounces = check_count("bounces", bounces, maximum=100_000)
    arr = np.ascontiguousarray(np.asarray(states, dtype=float).reshape(-1, 4))
    n = arr.shape[0]
    lz = np.ascontiguousarray(np.broadcast_to(np.asarray(lz, dtype=float), (n,)))
    l3 = np.ascontiguousarray(np.broadcast_to(np.asarray(l3, dtype=float), (n,)))
    if not (np.all(np.isfinite(arr)) and np.all(np.isfinite(lz)) and np.all(np.isfinite(l3))):
        raise InvalidArgument("states, ℓz and ℓ3 must be finite numbers")
    if np.any((arr[:, 0] < 0) | (arr[:, 0] > math.pi)):
        raise InvalidArgument("every toss's tilt θ must be in [0, π]")
    if not np.all(np.isfinite(potential(arr[:, 0], lz, l3))):
        raise InvalidArgument("a toss starts at a pole its ℓz, ℓ3 forbid (at θ = 0 or π, ℓz must equal ±ℓ3)")
    low = table.floor(arr[:, 0])
    if not np.all(arr[:, 1] > low + 10 * table.tol):
        raise InvalidArgument("every toss must start above the floor")
    if table.H is not None and not np.all(arr[:, 1] < table.ceiling(arr[:, 0]) - 10 * table.tol):
        raise InvalidArgument("every toss must start below the ceiling")
    sides = np.zeros((n, bounces), dtype=np.int8)
    status = np.zeros(n, dtype=np.int64)
    k.sides_many(arr, lz, l3, bounces, *table.kernel_args(), math.inf, sides, status)
    return sides, status


# ---------------------------------------------------------------------------------------------------- reference
_REFERENCE_MAX_STEPS = 400_000


def _reference_flight(theta0, w0, lz, l3):
    """The flight from the sinusoid of u = cos θ: returns a function t -> (θ, θ̇) (plain numpy)."""
    u0 = math.cos(theta0)
    s0 = math.sin(theta0)
    ud0 = -s0 * w0
    p = float(np.sqrt(2 * potential(theta0, lz, l3)))
    om2 = w0 * w0 + p * p + l3 * l3
    om = math.sqrt(om2)
    uc = lz * l3 / om2 if om2 > 0 else u0

    def at(t):
        if om == 0:
            return theta0, 0.0
        u = uc + (u0 - uc) * math.cos(om * t) + ud0 / om * math.sin(om * t)
        ud = -(u0 - uc) * om * math.sin(om * t) + ud0 * math.cos(om * t)
        u = min(1.0, max(-1.0, u))
        th = math.acos(u)
        # θ̇² = Ω² − ℓ₃² − p(θ)² (the energy), its sign that of −u̇
        rate2 = om2 - l3 * l3 - 2 * float(potential(th, lz, l3))
        thd = math.copysign(math.sqrt(max(rate2, 0.0)), -ud)
        return th, thd

    return at, om, math.sqrt(max(om2 - l3 * l3, 0.0))


def reference_run(table: TopTable, state, lz, l3, impacts):
    """The plain-numpy twin of the kernel (slow): the sinusoid of cos θ, conservative advancement with the
    first-order bound ``|dh/dt| ≤ R |ȧ|``, the step off a wall from the same second-order bound as the
    kernel but with its own arithmetic, and Brent's method for the root.  Returns ``(rows, status)`` with
    rows ``(time, θ, η, θ̇, η̇, wall)``."""
    from scipy.optimize import brentq

    body = table.body
    k1 = body.kappa1
    reach = body.reach / k1
    g, e = table.g, table.e
    th, eta, w, v = (float(x) for x in state)
    rows = []
    clock = 0.0
    leaving = -1
    for _ in range(impacts):
        at, om, speed = _reference_flight(th, w, lz, l3)
        lam = reach * speed

        def gaps(t, at=at, eta=eta, v=v):
            tt, _ = at(t)
            h = eta + v * t - 0.5 * g * t * t
            out = [h - float(table.floor(tt))]
            if table.H is not None:
                out.append(float(table.ceiling(tt)) - h)
            return np.array(out)

        t = 0.0
        if leaving >= 0:
            # step off the wall by doubling from 1e-14 s until the gap exceeds 1e3·tol: simple, not certified
            # (a re-impact within that time would be missed; the kernel's second-order step is certified)
            t = 1e-14 * max(1.0, 1.0 / max(om, 1e-300))
            while gaps(t)[leaving] <= 1e3 * table.tol and t < 1e3:
                t *= 2.0
        hit = -1
        for _step in range(_REFERENCE_MAX_STEPS):
            gp = gaps(t)
            k = int(np.argmin(gp))
            if gp[k] <= table.tol:
                hit = k
                break
            ve = v - g * t
            steps = [first_root(gp[0], ve - lam, g)]
            if table.H is not None:
                steps.append(first_root(gp[1], -ve - lam, -g))
            tau = min(steps)
            if not math.isfinite(tau) or (table.H is None and g == 0 and ve >= 0 and eta + v * t - reach > 0):
                return rows, 6
            t += tau
        if hit < 0:
            return rows, 7

        def gap(s, k=hit, gaps=gaps):
            return float(gaps(s)[k])

        if gap(t) > 0.0:
            width = 1e-12
            while width < 1e-3 and gap(t + width) >= 0.0:
                width *= 4
            if gap(t + width) < 0.0:
                t = brentq(gap, t, t + width, xtol=1e-16, rtol=1e-15, maxiter=400)
        th, thd = at(t)
        eta, w, v = eta + v * t - 0.5 * g * t * t, thd, v - g * t
        clock += t
        _, d = body.support(th if hit == 0 else math.pi - th)
        slope = float(d) / k1  # floor: b'(θ); ceiling η = H − b(π − θ): slope b'(π − θ)
        fimp = (1 + e) * (v - slope * w) / (1 + slope * slope)
        w, v = w + fimp * slope, v - fimp
        rows.append((clock, th, eta, w, v, hit))
        leaving = hit
    return rows, 0


def first_root(f0, f1, K):
    """Smallest τ > 0 with f0 + f1 τ − ½ K τ² = 0 (f0 > 0; K of either sign), ``inf`` if none: the step of
    conservative advancement on the lower bound f0 + f1 τ − ½ K τ² of a gap."""
    disc = f1 * f1 + 2 * K * f0
    if disc < 0:
        return math.inf
    if f1 < 0:
        return 2 * f0 / (-f1 + math.sqrt(disc))
    if K > 0:
        return (f1 + math.sqrt(disc)) / K
    return math.inf
