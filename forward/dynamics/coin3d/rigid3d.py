"""The direct 3-D simulation of a body of revolution between horizontal walls: the cross-check of :mod:`.top`.

Nothing here uses the reduction.  The state is the centre of mass ``r`` and its velocity, the orientation
as a unit quaternion ``q`` (body → lab; the body's symmetry axis is its third axis ``e₃``) and the angular
momentum ``L`` in the lab.  Between impacts the motion is exact: ``r`` is a parabola and the torque-free
symmetric top turns as

    R(t) = Rot(L̂, Ω t) · R(0) · Rot(e₃, ν t),     Ω = |L|/I₁,   ν = L₃ (1/I₃ − 1/I₁),   L₃ = L·a,

(its angular velocity is ``L/I₁ + ν a = I⁻¹L``, and L stays fixed).  The lowest point of the body is found
from its 3-D shape: for a polygonal meridian (vertices (ρ_k, ζ_k), rounding ε) the lowest point of the ring
k is ``ζ_k a + ρ_k d̂`` with d̂ the unit vector across the axis pointing most downwards, lowered by ε; for an
ellipsoid the support point ``S n/√(nᵀS n)``, ``S = R diag(A², A², C²) Rᵀ``.  The impact is the frictionless
Newton impulse at that point with the full inertia tensor:

    J = −(1 + e) u / (1/M + (q × n)·I⁻¹(q × n)),    V += J n / M,    L += q × J n,

with ``u = n·(V + ω × q)`` the contact point's normal velocity.  The next impact is found by conservative
advancement (``|dh/dt| ≤ |ω × a| R``, as in :mod:`._top_kernel` but in plain numpy) and Brent's method.
Slow (pure Python): meant for tens to thousands of impacts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...revolution import Revolution
from ...validation import check_count, check_finite
from .top import first_root  # a quadratic's root: nothing of the reduction

__all__ = ["Rigid3D", "Trajectory3D", "from_reduced", "simulate_3d", "to_reduced"]


def _qmul(p, q):
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _qrot(axis, angle):
    n = np.linalg.norm(axis)
    if n == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[math.cos(angle / 2)], np.asarray(axis) / n * math.sin(angle / 2)])


def _matrix(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


@dataclass(frozen=True, repr=False)
class Rigid3D:
    """The body, the walls and the field in physical units (lengths of the body; time in s).

    Attributes
    ----------
    body : Revolution
    g : float
        Gravity (length/s², ≥ 0) along −z.
    e : float
        Restitution in (0, 1].
    H : float or None
        Height of the ceiling (the floor is z = 0); ``None``: a floor only.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward.revolution import coin
    >>> from coinwall.forward.dynamics import Rigid3D, simulate_3d
    >>> system = Rigid3D(coin(1.0, 0.2), g=1.0, e=0.5)
    >>> state = (np.array([0.0, 0.0, 2.0]), np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), np.array([0.3, 0.0, 0.0]))
    >>> system.body.kind, system.H
    ('polygon', None)
    """

    body: Revolution
    g: float = 0.0
    e: float = 1.0
    H: float | None = None

    def __post_init__(self):
        if not isinstance(self.body, Revolution):
            raise InvalidArgument(f"`body` must be a Revolution, got {type(self.body).__name__}")
        if check_finite("g", self.g) < 0:
            raise InvalidArgument(f"`g` must be >= 0, got {self.g:g}")
        if not 0 < check_finite("e", self.e) <= 1:
            raise InvalidArgument(f"`e` must be in (0, 1], got {self.e:g}")
        if self.H is not None:
            check_finite("H", self.H)

    def inverse_inertia(self, R):
        b = self.body
        return R @ np.diag([1 / b.I1, 1 / b.I1, 1 / b.I3]) @ R.T

    def extreme_point(self, R, down: bool):
        """The body point (relative to the centre, lab frame) lowest (``down``) or highest."""
        n = np.array([0.0, 0.0, -1.0 if down else 1.0])
        b = self.body
        a = R[:, 2]
        if b.kind == "ellipsoid":
            A, C = b.semi_axes
            S = R @ np.diag([A * A, A * A, C * C]) @ R.T
            Sn = S @ n
            return Sn / math.sqrt(float(n @ Sn))
        across = n - (n @ a) * a
        norm = np.linalg.norm(across)
        dhat = across / norm if norm > 0 else np.zeros(3)
        pts = b.vertices[:, 1:2] * a[None, :] + b.vertices[:, 0:1] * dhat[None, :]
        k = int(np.argmax(pts @ n))
        return pts[k] + b.rounding * n

    def gaps(self, z, R):
        """Floor gap and ceiling gap (inf without one)."""
        low = z + self.extreme_point(R, True)[2]
        up = math.inf if self.H is None else self.H - (z + self.extreme_point(R, False)[2])
        return low, up


@dataclass(frozen=True, repr=False)
class Trajectory3D:
    """The impacts of the 3-D simulation: ``time``, position ``r`` (n, 3), velocity ``v`` (n, 3), quaternion
    ``q`` (n, 4), angular momentum ``L`` (n, 3) just after each impact, the ``wall`` hit (0 floor, 1 ceiling).

    Attributes
    ----------
    time : ndarray (n,)
        Time of each impact since the start (s).
    r, v : ndarray (n, 3)
        Position and velocity of the centre of mass just after each impact.
    q : ndarray (n, 4)
        The orientation as a unit quaternion.
    L : ndarray (n, 3)
        The angular momentum (lab frame).
    wall : ndarray (n,) of int
        0 floor, 1 ceiling.
    system : Rigid3D
    status : str
        Why the simulation ended.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward.revolution import coin
    >>> from coinwall.forward.dynamics import Rigid3D, simulate_3d
    >>> system = Rigid3D(coin(1.0, 0.2), g=1.0, e=0.5)
    >>> state = (np.array([0.0, 0.0, 2.0]), np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), np.array([0.3, 0.0, 0.0]))
    >>> trajectory = simulate_3d(system, state, 3)
    >>> trajectory.r.shape, trajectory.wall.tolist()
    ((3, 3), [0, 0, 0])
    """

    time: np.ndarray
    r: np.ndarray
    v: np.ndarray
    q: np.ndarray
    L: np.ndarray
    wall: np.ndarray
    system: Rigid3D
    status: str

    def reduced(self) -> np.ndarray:
        """(θ, η, θ̇, η̇, ℓ_z, ℓ₃) after each impact (units of :mod:`.top`)."""
        return np.array([to_reduced(self.system, r, v, q, L) for r, v, q, L in zip(self.r, self.v, self.q, self.L)])

    def energy(self) -> np.ndarray:
        """Kinetic (translation + rotation) plus potential energy after each impact."""
        out = []
        for r, v, q, L in zip(self.r, self.v, self.q, self.L):
            R = _matrix(q)
            omega = self.system.inverse_inertia(R) @ L
            out.append(0.5 * self.system.body.mass * float(v @ v) + 0.5 * float(L @ omega)
                       + self.system.body.mass * self.system.g * r[2])
        return np.array(out)

    @safe_repr
    def __repr__(self):
        return f"Trajectory3D({self.time.size} impacts, {self.status})"


def to_reduced(system: Rigid3D, r, v, q, L):
    """The reduced billiard's (θ, η, θ̇, η̇, ℓ_z, ℓ₃) of a 3-D state."""
    b = system.body
    k1 = b.kappa1
    R = _matrix(np.asarray(q, dtype=float))
    a = R[:, 2]
    omega = system.inverse_inertia(R) @ L
    adot = np.cross(omega, a)
    rh = math.hypot(a[0], a[1])
    theta = math.atan2(rh, a[2])
    if rh > 0:
        thd = (a[0] * adot[0] + a[1] * adot[1]) / rh * a[2] - rh * adot[2]
    else:
        thd = math.copysign(math.hypot(adot[0], adot[1]), a[2])
    return np.array([theta, r[2] / k1, thd, v[2] / k1, L[2] / b.I1, float(L @ a) / b.I1])


def from_reduced(system: Rigid3D, state, lz, l3, spin_angle: float = 0.0, azimuth: float = 0.0,
                 drift=(0.0, 0.0)):
    """A 3-D state ``(r, v, q, L)`` with the reduced state (θ, η, θ̇, η̇) and ``ℓ_z``, ``ℓ₃``: the axis at tilt θ
    and ``azimuth``, turned by ``spin_angle`` about itself, the centre drifting horizontally at ``drift``."""
    th, eta, thd, etad = (float(x) for x in state)
    b = system.body
    k1 = b.kappa1
    s, c = math.sin(th), math.cos(th)
    q = _qmul(_qrot([0, 0, 1], azimuth), _qmul(_qrot([0, 1, 0], th), _qrot([0, 0, 1], spin_angle)))
    e_theta = np.array([c, 0.0, -s])
    e_phi = np.array([0.0, 1.0, 0.0])
    a = np.array([s, 0.0, c])
    p = 0.0 if s == 0 else (lz - l3 * c) / s
    ell = thd * e_phi - p * e_theta + l3 * a
    rz = _matrix(_qrot([0, 0, 1], azimuth))
    L = b.I1 * (rz @ ell)
    r = np.array([0.0, 0.0, eta * k1])
    v = np.array([drift[0], drift[1], etad * k1])
    return r, v, q, L


def _flight(system, r0, v0, q0, L):
    b = system.body
    a0 = _matrix(q0)[:, 2]
    L3 = float(L @ a0)
    Om = np.linalg.norm(L) / b.I1
    nu = L3 * (1 / b.I3 - 1 / b.I1)
    g = system.g

    def at(t):
        q = _qmul(_qrot(L, Om * t), _qmul(q0, _qrot([0, 0, 1], nu * t)))
        r = r0 + v0 * t - 0.5 * g * t * t * np.array([0, 0, 1.0])
        return r, v0 - g * t * np.array([0, 0, 1.0]), q

    speed = np.linalg.norm(np.cross(L / b.I1, a0))  # |ȧ|: ω's part across the axis
    return at, speed


_MAX_STEPS = 400_000


def simulate_3d(system: Rigid3D, state, impacts: int) -> Trajectory3D:
    """Follow ``state = (r, v, q, L)`` through ``impacts`` impacts (see the module docstring).  A state on a
    wall (gap below 1e-9 of the body's reach) leaves it first.

    Parameters
    ----------
    system : Rigid3D
    state : tuple of array_like
        ``(r, v, q, L)``: position (3,), velocity (3,), unit quaternion (4,) and angular momentum (3,).
    impacts : int
        Impacts to follow.

    Returns
    -------
    Trajectory3D

    Examples
    --------
    A coin dropped flat from height 2, slowly tumbling, bounces lower each time (e = 0.5):

    >>> import numpy as np
    >>> from coinwall.forward.revolution import coin
    >>> from coinwall.forward.dynamics import Rigid3D, simulate_3d
    >>> system = Rigid3D(coin(1.0, 0.2), g=1.0, e=0.5)
    >>> state = (np.array([0.0, 0.0, 2.0]), np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]), np.array([0.3, 0.0, 0.0]))
    >>> trajectory = simulate_3d(system, state, 3)
    >>> trajectory
    Trajectory3D(3 impacts, impact budget reached)
    >>> trajectory.r[:, 2].round(4).tolist()
    [0.3624, 0.2489, 0.2822]
    """
    from scipy.optimize import brentq

    impacts = check_count("impacts", impacts)
    r, v, q, L = (np.array(x, dtype=float) for x in state)
    b = system.body
    reach = b.reach
    out = {k: [] for k in ("time", "r", "v", "q", "L", "wall")}
    clock = 0.0
    start = np.array(system.gaps(r[2], _matrix(q)))
    leaving = int(np.argmin(start)) if start.min() <= 1e-9 * reach else -1
    status = "impact budget reached"
    for _ in range(impacts):
        at, speed = _flight(system, r, v, q, L)
        lam = speed * reach

        def gaps(t, at=at):
            rr, _, qq = at(t)
            return np.array(system.gaps(rr[2], _matrix(qq)))

        t = 0.0
        if leaving >= 0:  # off the wall by doubling (a cross-check, not a certified search; see .top)
            t = 1e-14
            while gaps(t)[leaving] <= 1e-9 * reach and t < 1e3:
                t *= 2.0
        hit = -1
        for _step in range(_MAX_STEPS):
            gp = gaps(t)
            k = int(np.argmin(gp))
            if gp[k] <= 1e-12 * reach:
                hit = k
                break
            vz = v[2] - system.g * t
            steps = [first_root(gp[0], vz - lam, system.g)]
            if system.H is not None:
                steps.append(first_root(gp[1], -vz - lam, -system.g))
            tau = min(steps)
            if not math.isfinite(tau) or (system.H is None and system.g == 0 and vz >= 0 and r[2] + v[2] * t > reach):
                break
            t += tau
        if hit < 0:
            status = "free flight (no further impact)"
            break

        def gap(s, k=hit, gaps=gaps):
            return float(gaps(s)[k])

        if gap(t) > 0:
            width = 1e-12
            while width < 1e-3 and gap(t + width) >= 0:
                width *= 4
            if gap(t + width) < 0:
                t = brentq(gap, t, t + width, xtol=1e-16, rtol=1e-15, maxiter=400)
        r, v, q = at(t)
        q = q / np.linalg.norm(q)
        R = _matrix(q)
        n = np.array([0.0, 0.0, 1.0 if hit == 0 else -1.0])
        point = system.extreme_point(R, hit == 0)
        Iinv = system.inverse_inertia(R)
        omega = Iinv @ L
        u = float(n @ (v + np.cross(omega, point)))
        arm = np.cross(point, n)
        J = -(1 + system.e) * u / (1 / b.mass + float(arm @ Iinv @ arm))
        v = v + J * n / b.mass
        L = L + J * arm
        clock += t
        for key, value in (("time", clock), ("r", r), ("v", v), ("q", q), ("L", L), ("wall", hit)):
            out[key].append(value)
        leaving = hit
    return Trajectory3D(np.array(out["time"]), np.array(out["r"]).reshape(-1, 3), np.array(out["v"]).reshape(-1, 3),
                        np.array(out["q"]).reshape(-1, 4), np.array(out["L"]).reshape(-1, 3),
                        np.array(out["wall"], dtype=np.int8), system, status)

