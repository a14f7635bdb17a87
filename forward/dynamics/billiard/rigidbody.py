"""Direct simulation of a rigid body bouncing between two flat walls (no billiard code), or on a floor in gravity.

This is the *other side* of the paper's theorem (sections II A–B): a planar
rigid body of mass ``m`` and radius of gyration ``κ`` moves freely (no
gravity) between frictionless flat walls at lab height ``y = 0`` and
``y = H·κ``, and collides elastically with them.  The simulation knows
nothing of wall functions: it works with the body's own geometry (a vertex
list, or an ellipse given by its semi-axes and centre) rotated into the lab
frame, finds the first instant at which the lowest (highest) point of the
body reaches the floor (ceiling), and applies the impulse computed from the
actual contact point, lever arm included (paper eq. 2 and 13), with
restitution 1 along the wall normal.  ``tests/forward/dynamics/billiard/test_rigidbody.py`` holds it to
the billiard of :mod:`.billiard`; ``docs/equivalence.md`` derives why
they must agree.

The toss that lands: the same body in a field ``g`` (physical length/s², along −y), with a floor only
(``H=None``) or floor and ceiling, and Newton's restitution ``e`` on the normal velocity of the contact point
(``v_c⁺·n = −e v_c⁻·n``).  ``tests/forward/dynamics/floor/test_toss_checks.py`` holds it to the field billiard of
:mod:`.field` impact by impact (``η = y/κ``, so the billiard's field is ``g/κ``).  With Coulomb friction ``mu``
on the floor the horizontal velocity ``ẋ`` enters (a fifth number of the state) and each floor impact follows
Stronge's energetic restitution with Routh's integration of the impulse, computed here in the lab frame from
the body's own contact point (:func:`_routh_impulse`), independently of the field kernel's closed form;
``tests/forward/dynamics/floor/test_friction.py`` holds the two to each other impact by impact.

State and coordinates
---------------------
``y``      height of the centre of mass above the floor (physical length),
``psi``    lab orientation ψ of the body axis, counter-clockwise from the lab
           +x axis (radians, unwrapped),
``ydot``   dy/dt, ``omega`` = dψ/dt (counter-clockwise angular velocity),
``xdot``   dx/dt, the horizontal velocity of the centre of mass (optional, 0 if not given).
Between impacts ``y(t) = y + ẏ t − ½ g t²`` and ``ψ(t) = ψ + ω t``.
The horizontal motion of the centre of mass is uniform between impacts and changes only at a floor impact
with friction; its position is not tracked (the floor is the same everywhere).  Body-frame coordinates have
the centre of mass at the origin and the body axis along +x.

The billiard coordinates of the project (forward/wall.py) are

    θ = −ψ − π/2,   θ̇ = −ω,   η = y/κ,   η̇ = ẏ/κ,

i.e. θ is the body-frame polar angle of the floor's outward (downward) normal,
equivalently the angle measured clockwise from that normal to the body axis.
Time is the same physical time on both sides.  See docs/equivalence.md.

Finding the collision (why it cannot be missed)
-----------------------------------------------
The body's lowest point is the minimum over *pieces* (a vertex of a polygon,
or the whole smooth ellipse) of a smooth function ``Y_k(ψ)``, the lab height
of the piece's extreme point relative to the centre of mass; the gap of piece
``k`` to the floor is ``g_k(t) = y + ẏt − ½gt² + Y_k(ψ + ωt)`` (to the ceiling,
``Hκ − y − ẏt + ½gt² − Y_k(ψ + ωt)``).  Each piece has a bound ``|Y_k''| ≤ A_k``
(a vertex: ``|p_k|``; an ellipse: ``max(a,b)²/min(a,b) + |centre|``), hence
``|g_k''| ≤ M_k = ω² A_k + g``.  From a state with all gaps positive, the downward
parabola ``g + g′s − M s²/2`` is a lower bound on ``g_k(t+s)``; no piece can
touch before the first positive root of its parabola, so stepping by the
smallest of those roots never steps over a contact.  When the limiting piece
approaches with ``g′ < 0`` and ``g ≤ g′²/(4M)``, the interval
``[t, t + 2g/|g′|]`` is certified to hold exactly one root of that piece
(``g′`` keeps its sign there and the upper bound is negative at the end) and
no root of any other piece (it lies within their safe steps); the root is
then found by Brent's method and polished by Newton steps.  Just after a
collision the piece that touched has a gap of zero up to rounding and moves
away (``g′ > 0``); its step is the positive root ``2g′/M`` of ``g′s − M s²/2``,
so the collision just processed is not found again.  The only case left is an
exactly grazing contact (``g → 0`` and ``g′ → 0`` together), which is met with
probability zero; the search then stalls and the trajectory stops with
:attr:`RigidBodyTrajectory.message` saying so, rather than guessing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_positive
from .shapes import EllipseShape, PolygonShape

__all__ = [
    "EllipseShape",
    "PolygonShape",
    "RigidBody",
    "RigidBodyTrajectory",
    "billiard_to_body",
    "body_to_billiard",
    "simulate_rigid_body",
]

_MAX_STEPS = 200_000  # safe steps per flight before a stall is reported (grazing contact)


def body_to_billiard(state, kappa: float = 1.0) -> np.ndarray:
    """Rigid-body state ``(y, ψ, ẏ, ω)`` → billiard state ``(θ, η, θ̇, η̇)``.

    ``θ = −ψ − π/2``, ``η = y/κ``, ``θ̇ = −ω``, ``η̇ = ẏ/κ`` (docs/equivalence.md).  A fifth number, the
    horizontal velocity ``ẋ``, becomes ``ξ̇ = ẋ/κ``.  Works on a single state (4,) or (5,) or rows of states.

    Parameters
    ----------
    state : array_like (4,), (5,) or (n, 4), (n, 5)
        ``(y, ψ, ẏ, ω)`` and optionally ``ẋ``.
    kappa : float
        The radius of gyration (physical length).

    Returns
    -------
    ndarray
        ``(θ, η, θ̇, η̇)`` (and ``ξ̇``), the same shape.

    Examples
    --------
    >>> from coinwall.forward import billiard_to_body, body_to_billiard
    >>> state = body_to_billiard([1.5, 0.0, 0.0, 2.0])
    >>> state.round(6).tolist()                                 # θ = −π/2, θ̇ = −ω
    [-1.570796, 1.5, -2.0, 0.0]
    >>> billiard_to_body(state).round(12).tolist()
    [1.5, 0.0, 0.0, 2.0]
    """
    s = np.asarray(state, dtype=float)
    y, psi, ydot, omega = (s[..., i] for i in range(4))
    parts = [-psi - 0.5 * math.pi, y / kappa, -omega, ydot / kappa]
    if s.shape[-1] == 5:
        parts.append(s[..., 4] / kappa)
    return np.stack(parts, axis=-1)


def billiard_to_body(state, kappa: float = 1.0) -> np.ndarray:
    """Billiard state ``(θ, η, θ̇, η̇(, ξ̇))`` → rigid-body state ``(y, ψ, ẏ, ω(, ẋ))``; inverse of
    :func:`body_to_billiard`.

    Parameters
    ----------
    state : array_like (4,), (5,) or (n, 4), (n, 5)
        ``(θ, η, θ̇, η̇)`` and optionally ``ξ̇``.
    kappa : float
        The radius of gyration (physical length).

    Returns
    -------
    ndarray
        ``(y, ψ, ẏ, ω)`` (and ``ẋ``), the same shape.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward import billiard_to_body
    >>> billiard_to_body([-np.pi / 2, 1.5, -2.0, 0.0], kappa=2.0).round(12).tolist()   # y = κη, ω = −θ̇
    [3.0, 0.0, 0.0, 2.0]
    """
    s = np.asarray(state, dtype=float)
    theta, eta, v_theta, v_eta = (s[..., i] for i in range(4))
    parts = [kappa * eta, -theta - 0.5 * math.pi, kappa * v_eta, -v_theta]
    if s.shape[-1] == 5:
        parts.append(kappa * s[..., 4])
    return np.stack(parts, axis=-1)


# ---------------------------------------------------------------------- the body between two walls
@dataclass(frozen=True, repr=False)
class RigidBody:
    """A rigid body between a floor at ``y = 0`` and a ceiling at ``y = H·κ``.

    Attributes
    ----------
    shape : PolygonShape or EllipseShape
        The outline, body frame, centre of mass at the origin, physical lengths.
    H : float
        Wall distance in units of κ (as in the billiard).
    kappa : float
        Radius of gyration (physical length).  Not derived from the shape: the
        mass distribution is independent of the outline (``shape.uniform_kappa``
        gives the uniform-density value).
    mass : float
        Mass; it cancels from the trajectory but enters the impulses and the energy.
    g : float
        Field along −y (physical length/s², ≥ 0; 0: none).  ``H=None`` (a floor only) needs ``g > 0``.
    e : float
        Newton's coefficient of restitution of the contact point's normal velocity, in (0, 1] (with friction,
        Stronge's energetic coefficient).
    mu : float
        Coulomb's coefficient of friction of the floor (≥ 0; the ceiling is frictionless).

    Raises
    ------
    InvalidArgument
        For a shape that is not one, a length or mass that is not positive, a field, restitution or friction out
        of range, or a floor that nothing brings the body back to.

    Examples
    --------
    >>> RigidBody(EllipseShape(1.0, 0.1), H=None, g=9.8, e=0.6, mu=0.3)
    RigidBody(EllipseShape(a=1, b=0.1, centre=(0, 0)), floor only, kappa=1, mass=1, g=9.8, e=0.6, mu=0.3)
    """

    shape: object
    H: float | None
    kappa: float = 1.0
    mass: float = 1.0
    g: float = 0.0
    e: float = 1.0
    mu: float = 0.0

    def __post_init__(self):
        if not isinstance(self.shape, (PolygonShape, EllipseShape)):
            raise InvalidArgument(f"`shape` must be a PolygonShape or EllipseShape, got {type(self.shape).__name__}")
        for name in ("kappa", "mass") + (("H",) if self.H is not None else ()):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        for name in ("g", "e", "mu"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise InvalidArgument(f"`{name}` must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if not 0.0 <= self.g <= 1e12:
            raise InvalidArgument(f"`g` must be a field between 0 and 1e12, got {self.g!r}")
        if not 0.0 < self.e <= 1.0:
            raise InvalidArgument(f"`e` must be a coefficient of restitution in (0, 1], got {self.e!r}")
        if not self.mu >= 0.0:
            raise InvalidArgument(f"`mu` must be a coefficient of friction >= 0, got {self.mu!r}")
        if self.H is None and self.g == 0.0:
            raise InvalidArgument("a floor without a field and without a ceiling is met at most once: give `g` > 0 "
                                  "or a ceiling `H`")

    @property
    def ceiling(self) -> float:
        """Physical height of the ceiling, ``H·κ`` (``inf`` without one)."""
        return math.inf if self.H is None else self.H * self.kappa

    def gaps(self, y: float, psi: float):
        """Floor and ceiling gaps (physical lengths) at one configuration: ``(floor, ceiling)``."""
        low, _, high, _ = self.shape.pieces(psi)
        return float(y + np.min(low)), float(self.ceiling - y - np.max(high))

    def energy(self, ydot, omega, y=0.0, xdot=0.0):
        """Energy ``½m (ẋ² + ẏ²) + ½m κ² ω² + m g y`` (ẋ: 0 unless given)."""
        return 0.5 * self.mass * (np.asarray(xdot) ** 2 + np.asarray(ydot) ** 2
                                  + self.kappa**2 * np.asarray(omega) ** 2) + self.mass * self.g * np.asarray(y)

    @safe_repr
    def __repr__(self) -> str:
        top = "floor only" if self.H is None else f"H={self.H:.6g}"
        field = f", g={self.g:.6g}, e={self.e:.6g}" if (self.g or self.e != 1.0) else ""
        field += f", mu={self.mu:.6g}" if self.mu else ""
        return f"RigidBody({self.shape!r}, {top}, kappa={self.kappa:.6g}, mass={self.mass:.6g}{field})"


@dataclass(frozen=True, repr=False)
class RigidBodyTrajectory:
    """One entry per collision, in order (arrays of length n).

    Attributes
    ----------
    time : ndarray
        Time of each collision since the start.
    y, psi : ndarray
        Centre-of-mass height and orientation (unwrapped) at the collision.
    ydot, omega : ndarray
        Velocities *after* the impulse.
    xdot : ndarray
        Horizontal velocity of the centre of mass after the impulse (changed only by friction).
    side : ndarray of int8
        0 = floor, 1 = ceiling.
    contact : ndarray, shape (n, 2)
        Contact point in the body frame.
    lever : ndarray
        Lab x of the contact point relative to the centre of mass (the lever arm).
    impulse : ndarray
        Magnitude of the impulse along the wall normal (``m`` included).
    friction : ndarray
        The impulse along the floor (``m`` included; 0 without friction and at the ceiling).
    gap : ndarray
        Smallest gap of the whole body to either wall at the collision (≈ 0: the
        contact point is on the wall; never noticeably negative: no penetration).
    start : ndarray, shape (5,)
        Initial state ``(y, ψ, ẏ, ω, ẋ)``.
    body : RigidBody
        The body and walls.
    message : str
        ``""`` if all requested collisions were found; otherwise why it stopped.

    Examples
    --------
    A stick dropped on a floor with friction, three impacts:

    >>> from coinwall import RigidBody, simulate_rigid_body
    >>> from coinwall.forward import PolygonShape
    >>> body = RigidBody(PolygonShape.stick(1.0), H=None, kappa=0.6, g=9.8, e=0.5, mu=0.4)
    >>> trajectory = simulate_rigid_body(body, [2.0, 0.3, 0.0, 5.0, 0.0], 3)
    >>> len(trajectory), trajectory.side.tolist()
    (3, [0, 0, 0])
    """

    time: np.ndarray
    y: np.ndarray
    psi: np.ndarray
    ydot: np.ndarray
    omega: np.ndarray
    xdot: np.ndarray
    side: np.ndarray
    contact: np.ndarray
    lever: np.ndarray
    impulse: np.ndarray
    friction: np.ndarray
    gap: np.ndarray
    start: np.ndarray
    body: RigidBody
    message: str = field(default="")

    @property
    def states(self) -> np.ndarray:
        """``(n, 4)`` rigid-body states ``(y, ψ, ẏ, ω)`` after each collision (``xdot`` holds ẋ)."""
        return np.stack([self.y, self.psi, self.ydot, self.omega], axis=1)

    @property
    def billiard(self) -> np.ndarray:
        """``(n, 4)`` billiard states ``(θ, η, θ̇, η̇)`` after each collision (:func:`body_to_billiard`)."""
        return body_to_billiard(self.states, self.body.kappa)

    @property
    def energy(self) -> np.ndarray:
        """Energy after each collision, ``½m (ẋ² + ẏ²) + ½m κ² ω² + m g y``."""
        return self.body.energy(self.ydot, self.omega, self.y, self.xdot)

    def __len__(self) -> int:
        return len(self.time)

    @safe_repr
    def __repr__(self) -> str:
        n = len(self.time)
        floor = int(np.sum(self.side == 0))
        tail = f", stopped: {self.message}" if self.message else ""
        span = f", t = {self.time[-1]:.6g}" if n else ""
        return f"RigidBodyTrajectory({n} collisions: {floor} floor, {n - floor} ceiling{span}{tail})"


def _all_gaps(body, y, psi, ydot, omega):
    """Gaps and their time derivatives for every piece of both walls (floor pieces first; no ceiling: floor only)."""
    low, low_slope, high, high_slope = body.shape.pieces(psi)
    if body.H is None:
        return y + low, ydot + omega * low_slope
    g = np.concatenate([y + low, body.ceiling - y - high])
    dg = np.concatenate([ydot + omega * low_slope, -ydot - omega * high_slope])
    return g, dg


def _safe_steps(g, dg, bound):
    """First positive root of ``g + g′s − M s²/2`` for every piece (inf when it has none).

    For a piece just leaving contact (``g ≲ 0``, ``g′ > 0``) the larger root is
    taken: the contact being left is the previous collision, not a new one.
    """
    steps = np.full(g.shape, np.inf)
    for k in range(g.size):
        gk, dk, mk = g[k], dg[k], bound[k]
        if mk == 0.0:
            if dk < 0.0:
                steps[k] = max(gk, 0.0) / -dk
            continue
        disc = dk * dk + 2.0 * mk * gk
        if gk <= 0.0 and dk >= 0.0:
            # the contact just processed (gap zero up to rounding), leaving: the step is the
            # positive root of g′s − M s²/2; the rounding-sized negative gap is not a new contact
            steps[k] = 2.0 * dk / mk
        elif disc < 0.0:  # gk < 0 and moving in: contact now
            steps[k] = 0.0
        elif dk < 0.0:
            # cancellation-free form of (dk + sqrt(disc))/mk
            steps[k] = max(gk, 0.0) * 2.0 / (math.sqrt(disc) - dk)
        else:
            steps[k] = (dk + math.sqrt(disc)) / mk
    return steps


def _next_collision(body, y0, psi0, ydot, omega, tol):
    """Time, piece index and side of the first contact of the flight from ``(y0, psi0)`` (in the field g).

    Returns ``(t, piece, message)``; ``t`` is None when no contact can ever happen
    or the search stalled (``message`` says which).
    """
    from scipy.optimize import brentq

    shape = body.shape
    field = body.g
    bounds_single = shape.curvature_bounds
    bound = np.concatenate([bounds_single] * (1 if body.H is None else 2)) * omega * omega + field

    def at(s):
        return _all_gaps(body, y0 + ydot * s - 0.5 * field * s * s, psi0 + omega * s, ydot - field * s, omega)

    t = 0.0
    for _ in range(_MAX_STEPS):
        g, dg = at(t)
        steps = _safe_steps(g, dg, bound)
        k = int(np.argmin(steps))
        if not math.isfinite(steps[k]):
            return None, -1, "no further collision: the body moves away from both walls for ever"
        gk, dk, mk = g[k], dg[k], bound[k]
        if dk < 0.0 and (gk <= tol or 4.0 * mk * gk <= dk * dk):
            others = np.delete(steps, k)
            limit = float(np.min(others)) if others.size else math.inf
            width = 2.0 * max(gk, 0.0) / -dk
            certified = (mk * width < -dk) and width <= limit
            if certified:
                if gk <= 0.0:
                    return t, k, ""

                def gap(s, k=k, t=t):
                    return float(at(t + s)[0][k])

                end = gap(width)
                if end < 0.0:
                    s = brentq(gap, 0.0, width, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=200)
                    # Newton polish on the smooth piece: the bracket is monotone, so it stays inside
                    for _ in range(2):
                        gg, dd = at(t + s)
                        if dd[k] < 0.0:
                            s_new = s - gg[k] / dd[k]
                            if 0.0 <= s_new <= width:
                                s = s_new
                    return t + s, k, ""
                if end == 0.0:
                    return t + width, k, ""
        # an exactly grazing piece (g = g′ = 0) gives zero steps until _MAX_STEPS: reported, not guessed
        t += steps[k]
    return None, -1, f"collision search stalled after {_MAX_STEPS} safe steps (a grazing contact)"


def _routh_impulse(W, u, mu, e):
    """The impulse ``(P_t, P_n)`` of one floor impact: Coulomb friction ``mu``, Stronge's energetic restitution.

    ``W`` (2×2, lab frame, tangential then normal) maps an impulse at the contact point to the change of its
    velocity ``u = (u_t, u_n)`` (``u_n < 0``: approaching).  The normal impulse is the clock: in each phase
    the tangential impulse grows as ``k`` times the normal one (slipping: ``k = −μ sign u_t``; stuck, if
    friction can hold it, ``k = −W_tn/W_tt``; else slipping back, ``k = −μ sign W_tn``), so u is linear in it;
    a phase ends at the first of: the slip stops, the normal velocity reaches 0 (the end of compression, whose
    work ``∫u_n dP_n`` fixes the restitution's ``−e²`` times it), the restitution's work is done (the end).
    A plain event loop over 2-vectors, written for this module apart from the field kernel's closed form.
    """
    u = np.array(u, dtype=float)
    P = np.zeros(2)
    if not u[1] < 0.0:
        return P
    compressing, work, target = True, 0.0, 0.0
    scale = abs(u[0]) + abs(u[1])
    for _ in range(16):
        slipping = abs(u[0]) > 1e-15 * scale
        if slipping:
            k = -mu * math.copysign(1.0, u[0])
        elif abs(W[0, 1]) <= mu * W[0, 0]:
            k = -W[0, 1] / W[0, 0]
        else:
            k = -mu * math.copysign(1.0, W[0, 1])
        d = np.array([k, 1.0])
        rate = W @ d
        ends = [math.inf, math.inf, math.inf]  # the slip stops, compression ends, restitution ends
        if slipping and rate[0] * u[0] < 0.0:
            ends[0] = -u[0] / rate[0]
        if compressing and rate[1] > 0.0:
            ends[1] = -u[1] / rate[1]
        if not compressing:
            left = target - work  # ∫(u_n + rate_n x) dx = left, u_n ≥ 0, rate_n > 0
            ends[2] = 2.0 * left / (u[1] + math.sqrt(u[1] * u[1] + 2.0 * rate[1] * left))
        which = int(np.argmin(ends))
        x = ends[which]
        work += u[1] * x + 0.5 * rate[1] * x * x
        P += d * x
        u += rate * x
        if which == 0:
            u[0] = 0.0
        elif which == 1:
            u[1] = 0.0
            compressing, target, work = False, -e * e * work, 0.0
            if target <= 0.0:
                break
        else:
            break
    return P


def simulate_rigid_body(body: RigidBody, state, collisions: int) -> RigidBodyTrajectory:
    """Simulate ``collisions`` wall collisions of ``body`` from ``state = (y, ψ, ẏ, ω)`` or ``(y, ψ, ẏ, ω, ẋ)``.

    Flight in the field ``body.g`` (free flight when it is 0) between collisions; at a collision with contact
    point ``r`` (lab frame, relative to the centre of mass) and wall normal
    ``n = ±ŷ`` the impulse ``J n`` with

        ``J = −(1 + e) (v_c·n) / (1/m + (r × n)²/(m κ²))``,  ``v_c = v + ω ẑ × r``,

    changes ``ẏ`` by ``J n_y / m`` and ``ω`` by ``J (r × n)/(m κ²)`` (paper
    eq. 2/13 for e = 1; ``r × n = r_x n_y`` because ``n`` is vertical).  The contact point leaves with
    ``−e`` times its normal velocity; for e = 1 this conserves ``½m ẏ² + ½m κ² ω² + m g y``.  With friction
    (``body.mu`` > 0) a floor impact's impulse has a tangential part too (:func:`_routh_impulse`), which changes
    ``ẋ`` and, through the contact point's height ``r_y``, ω.  There is no
    settling test here: a body with e < 1 on a floor bounces ever lower (the chattering limit) until the
    collision search stalls and ``message`` says so.

    Parameters
    ----------
    body : RigidBody
    state : array_like, shape (4,) or (5,)
        Initial ``(y, ψ, ẏ, ω)`` or ``(y, ψ, ẏ, ω, ẋ)``; the body must lie between the walls (a state
        touching a wall and moving away from it, e.g. just after a collision, is allowed).
    collisions : int
        Number of collisions to find (positive).

    Returns
    -------
    RigidBodyTrajectory

    Raises
    ------
    InvalidArgument
        For a state that is not 4 or 5 finite numbers, puts the body through a wall, or never reaches one.

    Examples
    --------
    >>> body = RigidBody(PolygonShape.stick(1.0), H=None, kappa=0.6, g=9.8, e=0.5, mu=0.4)
    >>> traj = simulate_rigid_body(body, [2.0, 0.3, 0.0, 5.0, 0.0], 3)
    >>> len(traj), bool(traj.friction[0] != 0.0), bool(traj.energy[-1] < body.energy(0.0, 5.0, 2.0))
    (3, True, True)
    """
    if not isinstance(body, RigidBody):
        raise InvalidArgument(f"`body` must be a RigidBody, got {type(body).__name__}")
    collisions = check_count("collisions", collisions)
    start = np.asarray(state, dtype=float).ravel()
    if start.size not in (4, 5) or not np.all(np.isfinite(start)):
        raise InvalidArgument(f"`state` must be 4 or 5 finite numbers (y, psi, ydot, omega(, xdot)), got {state!r}")
    start = np.append(start, 0.0) if start.size == 4 else start
    y, psi, ydot, omega, xdot = (float(v) for v in start)
    scale = body.shape.radius + (body.ceiling if body.H is not None else abs(y))
    tol = 1e-9 * scale
    floor_gap, ceiling_gap = body.gaps(y, psi)
    if min(floor_gap, ceiling_gap) < -tol:
        raise InvalidArgument(
            f"`state` puts the body through a wall (floor gap {floor_gap:.3g}, ceiling gap {ceiling_gap:.3g}); "
            f"it must lie between y = 0 and y = H·κ = {body.ceiling:.6g}")
    if ydot == 0.0 and omega == 0.0 and body.g == 0.0:
        raise InvalidArgument("`state` has zero velocity (ydot = omega = 0): the body never reaches a wall")

    shape, m, k2 = body.shape, body.mass, body.kappa**2
    n_pieces = len(shape.curvature_bounds)
    out = {name: np.empty(collisions) for name in ("time", "y", "psi", "ydot", "omega", "xdot", "lever", "impulse",
                                                   "friction", "gap")}
    side_out = np.empty(collisions, dtype=np.int8)
    contact_out = np.empty((collisions, 2))
    clock, message, count = 0.0, "", 0
    for i in range(collisions):
        dt, piece, message = _next_collision(body, y, psi, ydot, omega, tol)
        if dt is None:
            break
        clock += dt
        y, psi, ydot = y + ydot * dt - 0.5 * body.g * dt * dt, psi + omega * dt, ydot - body.g * dt
        side = 0 if piece < n_pieces else 1
        q = shape.contact_point(piece % n_pieces, psi, side)
        c, s = math.cos(psi), math.sin(psi)
        lever = c * q[0] - s * q[1]  # lab x of the contact point: r × n = lever · n_y
        normal = 1.0 if side == 0 else -1.0
        tangential = 0.0
        if side == 0 and body.mu > 0.0:
            ry = s * q[0] + c * q[1]  # lab y of the contact point relative to the centre of mass
            W = np.array([[1.0 / m + ry * ry / (m * k2), -lever * ry / (m * k2)],
                          [-lever * ry / (m * k2), 1.0 / m + lever * lever / (m * k2)]])
            tangential, impulse = _routh_impulse(W, (xdot - omega * ry, ydot + omega * lever), body.mu, body.e)
            xdot += tangential / m
            ydot += impulse / m
            omega += (lever * impulse - ry * tangential) / (m * k2)
        else:
            approach = normal * (ydot + omega * lever)  # v_c · n
            impulse = -(1.0 + body.e) * approach / (1.0 / m + lever * lever / (m * k2))
            ydot += impulse * normal / m
            omega += impulse * normal * lever / (m * k2)
        gaps = body.gaps(y, psi)
        out["time"][i], out["y"][i], out["psi"][i] = clock, y, psi
        out["ydot"][i], out["omega"][i], out["xdot"][i] = ydot, omega, xdot
        out["lever"][i], out["impulse"][i], out["gap"][i] = lever, impulse, min(gaps)
        out["friction"][i] = tangential
        side_out[i] = side
        contact_out[i] = q
        count = i + 1
    return RigidBodyTrajectory(
        **{name: arr[:count] for name, arr in out.items()}, side=side_out[:count], contact=contact_out[:count],
        start=start, body=body, message=message)
