"""Flights in a field: the billiard under constant gravity, with a floor (and a ceiling) and restitution.

The set-up (the paper's "external fields").  Units: lengths in κ (the radius of gyration), time in
seconds, so the field ``g`` is in κ/s² (a field of 9.81 m/s² on a body with κ = 1 cm is g = 981 κ/s²).  The body's centre-of-mass height is ``η = y/κ``; the kinetic energy of the
vertical and rotational motion is ``½ M κ² (η̇² + θ̇²)`` and the potential energy ``M g κ η``, so in
the (θ, η) plane the body is a point of unit mass in the field ``−g`` along η, with the Euclidean metric:

    θ(t) = θ0 + ω t,    η(t) = η0 + v t − ½ g t²    (between impacts).

The floor is ``η = b0 + b(θ)``; the ceiling, when there is one, ``η = H − b0 − b(θ + π)`` (as in
:class:`.billiard.Billiard`).  The next impact is the first root of the gap, found by the compiled
kernel :mod:`._field_kernel` (certified: it never passes a root, read its docstring for the guarantee) or
by the plain-numpy twin :func:`reference_run` (simple and slow, its yardstick).

The impact: Newton's restitution on the normal velocity in the billiard metric
-----------------------------------------------------------------------------
A frictionless floor pushes the contact point q straight up with an impulse J.  With the contact point's
horizontal lever arm ``r`` about the centre of mass, mass M and moment of inertia ``I = M κ²``:
``M δẏ = J``, ``I δω = r J`` (ω the lab angular velocity) and, with ``r = κ b'(θ)`` and ``θ̇ = −ω``
(:doc:`theory`, "The rigid body is a billiard"), ``δη̇ = J/(M κ)``, ``δθ̇ = −b' δη̇``.  The contact
point's vertical velocity is

    u = ẏ − h'(θ) θ̇ = κ (η̇ − b' θ̇)          (h = κ (b0 + b): the height of the centre above it)

and its change is ``δu = J/M + r² J/I`` (the lever arm enters twice), so Newton's law ``u⁺ = −e u⁻`` gives
the closed form

    J = −(1 + e) u⁻ / (1/M + r²/I).

In the billiard: ``δη̇ = J/(Mκ) = −(1 + e)(η̇ − b'θ̇)/(1 + b'²)`` and ``δθ̇ = −b' δη̇``, i.e. the velocity
change is along the wall's normal ``N ∝ (−b', 1)`` in (θ, η) and reverses the normal component
``v·N/|N| = (η̇ − b'θ̇)/√(1 + b'²)`` times e.  So the rigid body's impulse is the billiard's restitution
on the normal velocity in the Euclidean (θ, η) metric, and e = 1 is the specular billiard.  The tangential
component ``(θ̇ + b' η̇)/√(1 + b'²)`` is kept (a frictionless contact); the energy lost in one impact is
``½ (1 − e²) v_n²`` (units M κ²).  (``tests/forward/dynamics/floor/test_toss.py`` checks the kernel's impacts against the lab
formula above, for a body of given M and κ.)

Friction
--------
With a coefficient of friction μ > 0 the floor also pushes along itself: the state gains the horizontal
velocity of the centre of mass ``ξ̇ = ẋ/κ``, each floor impact follows Stronge's energetic restitution with
Routh's integration of the impulse (no impact creates energy, for any μ and e), and a body whose bounces die
out slides, rolls and rocks on the floor until it lifts off again or settles (:mod:`._friction_kernel`, the
derivation in ``docs/toss.md``).  The ceiling, when there is one, stays frictionless.  μ = 0 is the
frictionless model above, computed by the same code as before friction existed (bit for bit).

Outcomes
--------
The valleys of b, their barriers and the names of the rest states: :mod:`.landscape`.  The chattering limit
and the bounded count: see :mod:`._field_kernel`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...angles import TWO_PI
from ...display import safe_repr
from ...errors import InvalidArgument, InvalidWall
from ...validation import check_count, check_memory, is_integer
from ...wall import Wall
from ..billiard.table import HEIGHT_MAX, HIT_TOL, Billiard
from .fieldkernel import _kernel
from .landscape import Landscape, landscape

__all__ = ["CHATTER_HEIGHT", "EVENTS", "FIELD_NOTES", "STATUS", "UNDECIDED_STATUSES", "FieldTable", "Flight",
           "check_friction", "field_run", "field_run_many"]

#: a floor impact after which the gap opens slower than √(2 g δ), δ = CHATTER_HEIGHT·max(1, scale) κ, is rest
CHATTER_HEIGHT = 1e-9
METHODS = ("kernel", "reference")
#: the kernel's status codes
STATUS = {0: "bounces", 1: "settled", 2: "caught", 3: "rest", 4: "slides", 6: "free", 7: "no-convergence",
          8: "wall-not-finite", 9: "angle-overflow", 10: "cell-budget", 11: "rolls", 12: "painleve",
          13: "contact-budget"}
#: the statuses that decide no outcome
UNDECIDED_STATUSES = tuple(v for k, v in STATUS.items() if k not in (1, 2, 3))
FIELD_NOTES = {
    0: "the budget of impacts (and contact events) was reached before the outcome was decided",
    4: "the bounces died out (chattering limit) with the energy still above the valley's barrier: the body "
       "slides on the frictionless floor and the impact model cannot follow it; the valley reported is where it was "
       "(give a friction coefficient μ > 0, or follow it with --slide)",
    6: "free flight: the body never meets a wall again",
    7: "the root search did not converge (a near-tangent graze?)",
    8: "the wall evaluated to nan or infinity where the body met it",
    9: "a flight carried θ beyond 1.8e13 rad, where float64 no longer resolves the contact angle",
    10: "the search for the next impact walked more than 2^27 cells without deciding",
    11: "the body rolls without slipping for ever with its energy above the valley's barrier: a whole period of "
        "rolling passed without an event, so it repeats (Coulomb friction has no rolling resistance)",
    12: "the body on the floor can neither roll nor slip consistently here (Painlevé's indeterminacy at a stick)",
    13: "the contact phases of the toss took 2^18 integration steps without deciding it (a body that slides and "
        "rolls on and on: give a rolling resistance)",
}
#: the events recorded in :attr:`Flight.side`: impacts, and with friction the contact events
EVENTS = {0: "floor impact", 1: "ceiling impact", 3: "lift-off", 4: "rolling", 5: "slipping",
          6: "corner", 7: "face", 8: "end", 9: "jam"}

def _number(name, value):
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`{name}` must be a real number, got {value!r}") from None
    if isinstance(value, bool) or not math.isfinite(number):
        raise InvalidArgument(f"`{name}` must be a finite number, got {value!r}")
    return number


def check_friction(mu, rolling=0.0) -> tuple:
    """``(mu, rolling)`` as numbers, checked: Coulomb's μ in [0, 1e6], the rolling resistance in [0, 1] κ and 0
    unless μ > 0.

    Raises
    ------
    InvalidArgument
        For a value that is not a number or out of its range.

    Examples
    --------
    >>> check_friction(0.3, 0.01)
    (0.3, 0.01)
    """
    mu, rolling = _number("mu", mu), _number("rolling", rolling)
    if not 0.0 <= mu <= 1e6:
        raise InvalidArgument(f"`mu` must be a coefficient of friction between 0 and 1e6, got {mu!r}")
    if not 0.0 <= rolling <= 1.0 or (rolling > 0.0 and mu == 0.0):
        raise InvalidArgument(f"`rolling` must be a rolling resistance in [0, 1] (units of κ) on a floor with "
                              f"friction (`mu` > 0), got {rolling!r}")
    return mu, rolling


# ---------------------------------------------------------------------------------------------------- table
@dataclass(frozen=True, repr=False)
class FieldTable:
    """A floor (and optionally a ceiling) for ``wall`` in a constant field ``g``, with restitution ``e`` and
    Coulomb friction ``mu`` on the floor.

    Parameters
    ----------
    wall : Wall
        The body's wall b(θ) (units of κ).
    g : float
        The field in κ/s² along −η (≥ 0; 0: no field).
    e : float
        The coefficient of restitution in [0, 1] (1: elastic): Newton's on the normal velocity without
        friction, Stronge's energetic coefficient with it (the two agree when the contact does not slip back).
        0 (perfectly plastic) needs a field and a floor only.
    b0 : float
        Offset of the wall (``b0 + b`` is the support function), as in :class:`.billiard.Billiard`.
    H : float or None
        Distance of the ceiling (units of κ); ``None``: a floor only.  The ceiling is frictionless.
    settle : bool
        Whether an orbit ends once its level is below its valley's barrier (the outcome is then decided; the
        default).  ``False`` for orbits followed for their own sake (a wedge, where the single valley would end
        every orbit at its first impact): the kernel gets no valley table and never settles.
    mu : float
        Coulomb's coefficient of friction of the floor, ≥ 0 (0: frictionless, the default).
    rolling : float
        Rolling resistance, with friction: the lever arm δ (units of κ, in [0, 1]) of the normal force whose
        couple δ·F_n opposes rolling.  0 (the default) is Coulomb friction alone, under which rolling without
        slipping keeps its energy: a near-round body may roll for ever (status ``rolls``).

    Attributes
    ----------
    landscape : Landscape
        The valleys of the floor (:func:`.landscape.landscape`); with ``settle=False``, without the kernel's
        valley table.

    Raises
    ------
    InvalidArgument
        For a value out of its range, or a floor that nothing brings the body back to.
    InvalidWall
        For a wall larger than the kernel takes.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> table.landscape.names
    ['tails', 'heads']
    """

    wall: Wall
    g: float = 0.0
    e: float = 1.0
    b0: float = 0.0
    H: float | None = None
    settle: bool = True
    mu: float = 0.0
    rolling: float = 0.0
    landscape: Landscape = field(init=False)

    def __post_init__(self):
        if not isinstance(self.wall, Wall):
            raise InvalidArgument(f"`wall` must be a coinwall.forward.Wall, got {type(self.wall).__name__}")
        for name in ("g", "e", "b0", "mu", "rolling"):
            object.__setattr__(self, name, _number(name, getattr(self, name)))
        if not (self.g == 0.0 or 1e-9 <= self.g <= 1e12):
            raise InvalidArgument(f"`g` must be 0 or a field between 1e-9 and 1e12 κ/s², got {self.g!r}")
        if not 0.0 <= self.e <= 1.0 or (self.e == 0.0 and (self.H is not None or self.g == 0.0)):
            raise InvalidArgument(f"`e` must be a coefficient of restitution in (0, 1] (0, perfectly plastic, with a "
                                  f"field and a floor only), got {self.e!r}")
        check_friction(self.mu, self.rolling)
        if self.mu > 0.0 and self.g == 0.0:
            raise InvalidArgument("friction (`mu` > 0) acts on a floor in a field: give `g` > 0")
        if not abs(self.b0) <= HEIGHT_MAX:
            raise InvalidArgument(f"`b0` must be between {-HEIGHT_MAX:g} and {HEIGHT_MAX:g}, got {self.b0!r}")
        if not self.wall.scale <= HEIGHT_MAX:
            raise InvalidWall(f"wall {self.wall.description!r} reaches |b| = {self.wall.scale:.3g}; the field "
                              f"kernel needs max |b| <= {HEIGHT_MAX:g} (units of κ)")
        if self.H is not None:
            table = Billiard(self.wall, self.H, self.b0)  # the billiard's checks of H (room, float64 range)
            object.__setattr__(self, "H", table.H)
        if self.g == 0.0 and self.H is None:
            raise InvalidArgument("a floor without a field and without a ceiling is met at most once: give `g` > 0 "
                                  "or a ceiling `H`")
        if not isinstance(self.settle, bool):
            raise InvalidArgument(f"`settle` must be True or False, got {self.settle!r}")
        land = landscape(self.wall)
        if not self.settle:  # the kernel skips the settling test when it gets an empty valley table
            land = Landscape(land.minima, land.maxima, land.barriers, land.names, np.empty((0, 3)), land.coin,
                             land.faces)
        object.__setattr__(self, "landscape", land)

    @property
    def ceiling(self) -> bool:
        return self.H is not None

    @property
    def tol(self) -> float:
        """Contact tolerance (as the billiard's)."""
        return HIT_TOL * max(1.0, abs(self.H) if self.H is not None else 0.0, self.wall.scale)

    @property
    def chatter(self) -> float:
        """Gap-opening rate below which a floor impact is rest: √(2 g δ), δ = CHATTER_HEIGHT·max(1, scale)."""
        return math.sqrt(2.0 * self.g * CHATTER_HEIGHT * max(1.0, self.wall.scale))

    def lower(self, theta):
        return self.b0 + self.wall(theta)

    def upper(self, theta):
        if self.H is None:
            return np.full(np.shape(theta), math.inf)
        return self.H - self.b0 - self.wall(np.asarray(theta, dtype=float) + math.pi)

    def energy(self, eta, v_theta, v_eta, v_xi=0.0):
        """Energy per M κ²: ``½(θ̇² + η̇² + ξ̇²) + g η`` (ξ̇ the horizontal velocity, 0 unless given)."""
        return (0.5 * (np.asarray(v_theta) ** 2 + np.asarray(v_eta) ** 2 + np.asarray(v_xi) ** 2)
                + self.g * np.asarray(eta))

    @safe_repr
    def __repr__(self):
        top = f", H={self.H:g}" if self.H is not None else ", floor only"
        friction = f", mu={self.mu:g}" if self.mu else ""
        friction += f", rolling={self.rolling:g}" if self.rolling else ""
        return f"FieldTable({self.wall!r}, g={self.g:g}, e={self.e:g}{friction}, b0={self.b0:g}{top})"


# ---------------------------------------------------------------------------------------------------- results
@dataclass(frozen=True, repr=False)
class Flight:
    """The impacts (and contact events) of one orbit in the field, in order, and how it ended.

    ``time, theta, eta, v_theta, v_eta, v_xi, side`` per record (velocities just after it; θ unwrapped; ξ̇ the
    horizontal velocity of the centre of mass); ``side`` is 0 for a floor impact, 1 for the ceiling, and with
    friction a contact event (:data:`EVENTS`).  ``status`` is a key of :data:`STATUS` (a word), ``valley`` the
    index into ``table.landscape`` where θ was at the end, ``outcome`` its name (or ``None`` when the status
    does not decide one), ``note`` why it stopped when that is not an outcome.

    Attributes
    ----------
    time, theta, eta, v_theta, v_eta : ndarray (n,)
        Each record's time, contact angle (unwrapped), height of the centre of mass and velocities after it.
    v_xi : ndarray (n,) or None
        The horizontal velocity of the centre of mass after each record (with friction).
    side : ndarray (n,) of int
        0 for a floor impact, 1 for the ceiling, else a contact event (:data:`EVENTS`).
    start : ndarray (4,)
        The start state ``[theta, eta, v_theta, v_eta]``.
    table : FieldTable
    status : str
        Why the flight ended, a key of :data:`STATUS` (``"settled"``, ``"rest"``, ...).
    valley : int
        Index into ``table.landscape`` of the valley θ was in at the end.
    floor_impacts : int
        Floor impacts in all.
    method : str
        ``"kernel"`` or ``"reference"``.
    note : str
        Why it stopped, when that is not an outcome.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> from coinwall.forward.dynamics import field_run
    >>> flight = field_run(table, [0.3, 1.5, 3.7, 0.2], 1000)
    >>> flight
    Flight(4 records (4 floor impacts), settled, outcome tails)
    >>> flight.side.tolist(), flight.floor_impacts
    ([0, 0, 0, 0], 4)
    """

    time: np.ndarray
    theta: np.ndarray
    eta: np.ndarray
    v_theta: np.ndarray
    v_eta: np.ndarray
    side: np.ndarray
    start: np.ndarray
    table: FieldTable
    status: str
    valley: int
    floor_impacts: int
    method: str = "kernel"
    note: str = ""
    v_xi: np.ndarray = None

    def __len__(self):
        return int(self.time.size)

    @property
    def outcome(self):
        """The name of the rest state (or the valley caught), ``None`` when undecided."""
        if self.status in ("settled", "caught", "rest"):
            return self.table.landscape.names[self.valley]
        return None

    @property
    def energy(self) -> np.ndarray:
        """The energy per M κ² after each record (the horizontal motion's included)."""
        vx = self.v_xi if self.v_xi is not None else 0.0
        return self.table.energy(self.eta, self.v_theta, self.v_eta, vx)

    @safe_repr
    def __repr__(self):
        return (f"Flight({len(self)} records ({self.floor_impacts} floor impacts), {self.status}, "
                f"outcome {self.outcome})")


# ---------------------------------------------------------------------------------------------------- inputs
def _check_state(table: FieldTable, state, leaving=None):
    """A state [θ, η, θ̇, η̇] or [θ, η, θ̇, η̇, ξ̇]: finite, on or above the floor (and below the ceiling); the
    wall it is on (0 floor, 1 ceiling, −1 none, 2 at rest on the floor in the normal direction: contact)."""
    try:
        arr = np.array(state, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InvalidArgument("`state` must be numbers [theta, eta, v_theta, v_eta(, v_xi)]") from None
    if arr.shape not in ((4,), (5,)) or not np.all(np.isfinite(arr)):
        raise InvalidArgument(f"`state` must be four or five finite numbers [theta, eta, v_theta, v_eta(, v_xi)], "
                              f"got {state!r}")
    if arr.size == 4:
        arr = np.append(arr, 0.0)
    if not abs(arr[0]) < 1e15:
        raise InvalidArgument(f"`state` angle {arr[0]!r} is beyond float64's resolution of an angle")
    th = float(arr[0])
    low = float(table.lower(np.array([th]))[0])
    up = float(table.upper(np.array([th]))[0])
    tol = 10 * table.tol
    if not (low - tol <= arr[1] <= up + tol):
        raise InvalidArgument(f"`state` {arr.tolist()} is outside the table: at θ = {th % TWO_PI:.6g} η must lie "
                              f"between {low:.6g} and {up:.6g}")
    if leaving is None:
        leaving = 0 if arr[1] - low <= tol else (1 if up - arr[1] <= tol else -1)
    if leaving in (0, 1):
        slope = float(table.wall.derivatives(np.array([th + leaving * math.pi]))[1][0]) * (1 if leaving == 0 else -1)
        inward = (arr[3] - slope * arr[2]) * (1 if leaving == 0 else -1)
        scale = abs(arr[3]) + abs(slope * arr[2]) + math.sqrt(table.g * max(1.0, table.wall.scale))
        if leaving == 0 and table.mu > 0.0 and abs(inward) <= 1e-12 * scale:
            return arr, 2  # on the floor, at rest in the normal direction: the toss starts in contact
        if inward <= 0:
            raise InvalidArgument(f"`state` {arr.tolist()} is on the {'floor' if leaving == 0 else 'ceiling'} and "
                                  f"moves out of the table")
    return arr, int(leaving)


def _check_impacts(n):
    if not is_integer(n) or n <= 0:
        raise InvalidArgument(f"`impacts` must be a positive integer, got {n!r}")
    return int(n)


# ---------------------------------------------------------------------------------------------------- runs
def field_run(table: FieldTable, state, impacts: int, catch: bool = False, method: str = "kernel") -> Flight:
    """One orbit in the field for at most ``impacts`` records, stopping when its outcome is decided.

    Parameters
    ----------
    table : FieldTable
        The floor, field, restitution and friction.
    state : array_like
        ``[θ, η, θ̇, η̇]`` or ``[θ, η, θ̇, η̇, ξ̇]`` (ξ̇ the horizontal velocity of the centre of mass, κ/s;
        0 when not given).  A state on a wall (η on it to 10·tol) must move into the table; it leaves that
        wall.  With friction a state on the floor with no normal velocity starts on the floor (sliding or
        rolling).
    impacts : int
        The most records: impacts, and with friction the contact events (lift-off, rolling, slipping, corners).
    catch : bool
        Stop at the first floor contact (the coin caught at the floor: Keller's toss).
    method : str
        ``"kernel"`` (compiled) or ``"reference"`` (:func:`.reference.reference_run`, frictionless only).

    Returns
    -------
    Flight

    Raises
    ------
    InvalidArgument
        For a state outside the table, a bad count or method.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> flight = field_run(FieldTable(coin, g=1.0, e=0.6, mu=0.3), [0.3, 1.5, 3.7, 0.2], 1000)
    >>> flight.status, flight.outcome
    ('settled', 'tails')
    """
    if not isinstance(table, FieldTable):
        raise InvalidArgument(f"`table` must be a FieldTable, got {type(table).__name__}")
    impacts = _check_impacts(impacts)
    check_memory(f"`impacts` = {impacts} (49 bytes per record)", 49.0 * impacts)
    arr, leaving = _check_state(table, state)
    if method == "reference":
        if table.mu > 0.0:
            raise InvalidArgument("the reference stepper is frictionless: use `method='kernel'` with `mu` > 0")
        from .reference import reference_run

        rows, status, valley, floor_hits = reference_run(table, arr[:4], leaving, impacts, catch)
        cols = [np.array(c, dtype=float) for c in zip(*rows)] if rows else [np.empty(0) for _ in range(6)]
        cols = cols[:5] + [np.zeros(cols[0].size)] + cols[5:]
        return _flight(table, arr, cols, status, valley, floor_hits, method)
    if method != "kernel":
        raise InvalidArgument(f"`method` must be one of {METHODS}, got {method!r}")
    comp = _kernel(table)
    out = [np.empty(impacts) for _ in range(6)] + [np.empty(impacts, dtype=np.int8)]
    summary = np.empty(9)
    turns = math.floor(arr[0] / TWO_PI)
    start = arr.copy()
    start[0] -= turns * TWO_PI
    done, status = comp.call("_run", start, int(turns), leaving, impacts, *comp.args(table), bool(catch),
                             table.chatter, *comp.wall_args(table), True, *out, summary)
    cols = [o[:done] for o in out]
    return _flight(table, arr, cols, int(status), _valley_of(table, summary[0], summary[7]), int(summary[6]), method)


def _valley_of(table, theta, kernels):
    """The valley holding θ: the kernel's, or, when it had no valley table (``settle=False``), the landscape's."""
    if table.settle:
        return np.asarray(kernels).astype(np.int64) if np.ndim(kernels) else int(kernels)
    found = table.landscape.valley(theta)
    return found.astype(np.int64) if np.ndim(theta) else int(found)


def _flight(table, start, cols, status, valley, floor_hits, method):
    time, theta, eta, vt, ve, vx, side = cols
    return Flight(time=np.asarray(time, dtype=float), theta=np.asarray(theta, dtype=float),
                  eta=np.asarray(eta, dtype=float), v_theta=np.asarray(vt, dtype=float),
                  v_eta=np.asarray(ve, dtype=float), side=np.asarray(side, dtype=np.int8), start=np.asarray(start),
                  table=table, status=STATUS.get(status, str(status)), valley=int(valley),
                  floor_impacts=int(floor_hits), method=method, note=FIELD_NOTES.get(status, ""),
                  v_xi=np.asarray(vx, dtype=float))


def field_run_many(table: FieldTable, states, impacts: int, catch: bool = False, workers=None,
                   device: str = "cpu") -> dict:
    """Many orbits in parallel (numba threads, or one GPU thread per orbit), summaries only.

    Parameters
    ----------
    table : FieldTable
        The floor, field, restitution and friction.
    states : array_like (n, 4) or (n, 5)
        ``[θ, η, θ̇, η̇(, ξ̇)]`` per orbit, strictly inside the table (not on a wall).
    impacts : int
        The most records per orbit (impacts and contact events).
    catch : bool
        Stop each at its first floor contact.
    workers : int, optional
        Threads (default: numba's; the CPU's only).
    device : {"cpu", "gpu"}
        Where the kernel runs: all CPU cores, or a CUDA GPU (``pip install 'coinwall[gpu]'``; the same kernel text,
        friction and contact phases included: :mod:`.fieldgpu`).  The GPU pays off from about 10^4 orbits.

    Returns
    -------
    dict of ndarray
        ``status`` (codes of :data:`STATUS`), ``valley``, ``floor_impacts``, ``impacts`` (records), ``time`` (of
        the last record), ``final`` (n, 4) states ``[θ mod 2π, η, θ̇, η̇]`` and ``v_xi`` (n,).

    Raises
    ------
    InvalidArgument
        For states that are not finite or not inside the table, an unknown ``device``, or ``device="gpu"`` without a
        usable GPU.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> out = field_run_many(table, [[0.3, 1.5, 3.7, 0.2], [2.0, 2.5, -4.0, 1.0]], 10_000)
    >>> [STATUS[int(k)] for k in out["status"]]
    ['settled', 'settled']
    """
    import numba

    from ..billiard.gpu import check_device

    impacts = _check_impacts(impacts)
    check_device(device)
    arr = np.array(states, dtype=float)
    arr = arr.reshape(1, -1) if arr.ndim == 1 else arr
    if arr.ndim != 2 or arr.shape[1] not in (4, 5):
        raise InvalidArgument(f"`states` must be rows of [theta, eta, v_theta, v_eta(, v_xi)], got shape {arr.shape}")
    if arr.shape[1] == 4:
        arr = np.column_stack([arr, np.zeros(arr.shape[0])])
    if not np.all(np.isfinite(arr)):
        raise InvalidArgument("`states` must be finite numbers")
    low, up = table.lower(arr[:, 0]), table.upper(arr[:, 0])
    inside = (arr[:, 1] > low + 10 * table.tol) & (arr[:, 1] < up - 10 * table.tol)
    if not inside.all():
        i = int(np.flatnonzero(~inside)[0])
        raise InvalidArgument(f"`states` {arr[i].tolist()} is not inside the table (η must lie strictly between "
                              f"{low[i]:.6g} and {up[i]:.6g} at that angle)")
    arr = arr.copy()
    arr[:, 0] = np.mod(arr[:, 0], TWO_PI)
    arr[arr[:, 0] >= TWO_PI, 0] = 0.0
    if device == "gpu":
        from .fieldgpu import run_gpu

        ran = run_gpu(table, arr, impacts, catch)
        done, status, summary = ran["done"], ran["status"], ran["summary"]
        return _summaries(table, done, status, summary)
    comp = _kernel(table)
    m = arr.shape[0]
    done = np.zeros(m, dtype=np.int64)
    status = np.zeros(m, dtype=np.int64)
    summary = np.zeros((m, 9))
    previous = numba.get_num_threads()
    try:
        if workers is not None:
            numba.set_num_threads(min(check_count("workers", workers), numba.config.NUMBA_NUM_THREADS))
        comp.call("_run_many", np.ascontiguousarray(arr), impacts, *comp.args(table), bool(catch), table.chatter,
                  *comp.wall_args(table), done, status, summary)
    finally:
        numba.set_num_threads(previous)
    return _summaries(table, done, status, summary)


def _summaries(table, done, status, summary):
    return {"status": status, "valley": _valley_of(table, summary[:, 0], summary[:, 7]),
            "floor_impacts": summary[:, 6].astype(np.int64),
            "impacts": done, "time": summary[:, 5], "final": summary[:, [0, 2, 3, 4]], "v_xi": summary[:, 8]}
