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

Outcomes
--------
With gravity the floor's wall is a potential landscape: ``λ = E/g = η + (θ̇² + η̇²)/(2g) ≥ b0 + b(θ)``.
The *valleys* are the intervals between consecutive local maxima of b; a body whose level ``λ − b0`` is
below the lower of its valley's two maxima (the valley's *barrier*, at least the lowest saddle of all) can
never leave it: the outcome is decided (:func:`landscape`).  For a coin (two valleys whose minima are on
either side, ``sin θ < 0`` and ``> 0``) the valleys are named heads and tails (the convention of
:func:`.correlation.heads`).  The chattering limit and the bounded count: see :mod:`._field_kernel`.
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
from ..billiard.kernel import source_after_marker
from ..billiard.table import HEIGHT_MAX, HIT_TOL, Billiard

__all__ = ["CHATTER_HEIGHT", "FIELD_NOTES", "FIELD_SOURCE", "STATUS", "FieldTable", "Flight", "Landscape",
           "field_run", "field_run_many", "landscape", "reference_run"]

_MARKER = ("# ---- field kernel: the text from the line after this one to the end of the file is joined to the "
           "wall code ----\n")
#: a floor impact after which the gap opens slower than √(2 g δ), δ = CHATTER_HEIGHT·max(1, scale) κ, is rest
CHATTER_HEIGHT = 1e-9
METHODS = ("kernel", "reference")
#: the kernel's status codes
STATUS = {0: "bounces", 1: "settled", 2: "caught", 3: "rest", 4: "slides", 6: "free", 7: "no-convergence",
          8: "wall-not-finite", 9: "angle-overflow", 10: "cell-budget"}
FIELD_NOTES = {
    0: "the impact budget was reached before the outcome was decided",
    4: "the bounces died out (chattering limit) with the energy still above the valley's barrier: the body "
       "slides on the floor and the impact model cannot follow it; the valley reported is where it was",
    6: "free flight: the body never meets a wall again",
    7: "the root search did not converge (a near-tangent graze?)",
    8: "the wall evaluated to nan or infinity where the body met it",
    9: "a flight carried θ beyond 1.8e13 rad, where float64 no longer resolves the contact angle",
    10: "the search for the next impact walked more than 2^27 cells without deciding",
}


FIELD_SOURCE = source_after_marker(__package__, "_field_kernel.py", _MARKER)


# ---------------------------------------------------------------------------------------------------- landscape
@dataclass(frozen=True, repr=False)
class Landscape:
    """The valleys of the floor's wall b(θ) (b0 not included; the valleys do not depend on it).

    Attributes
    ----------
    minima : ndarray (k,)
        The angle of each valley's minimum, in [0, 2π), in the order of the valleys.
    maxima : ndarray (k,)
        The left maximum of each valley (valley i spans ``[maxima[i], maxima[i+1])``, cyclically).
    barriers : ndarray (k,)
        The lower of each valley's two maxima (b's value; ``inf`` for a wall with a single valley).
    names : list of str
        ``heads``/``tails`` for a coin (two valleys, minima with ``sin θ < 0`` and ``> 0``), else
        ``rest θ=…`` by the angle of the minimum.
    table : ndarray (k, 3)
        ``[left maximum, barrier, minimum]`` per valley, sorted by the left maximum: the kernel's input.
    """

    minima: np.ndarray
    maxima: np.ndarray
    barriers: np.ndarray
    names: list
    table: np.ndarray

    def valley(self, theta):
        """Index of the valley holding each angle (the kernel's rule)."""
        x = np.mod(np.asarray(theta, dtype=float), TWO_PI)
        if self.maxima.size <= 1:
            return np.zeros(x.shape, dtype=np.int64)
        k = np.searchsorted(self.table[:, 0], x, side="right") - 1
        return np.where(k < 0, self.maxima.size - 1, k)

    @safe_repr
    def __repr__(self):
        parts = [f"{n} (min θ={m:.4g}, barrier {b:.4g})" for n, m, b in zip(self.names, self.minima, self.barriers)]
        return f"Landscape({'; '.join(parts)})"


def landscape(wall: Wall, points: int = 16384) -> Landscape:
    """The valleys of ``wall`` (local maxima and minima of b, refined on the exact wall).

    Extrema are found on a grid of ``points`` angles (strict local extrema of the sampled b, cyclic) and
    refined by a bounded scalar search on b within one grid step (b is continuous, kinks included; the value
    at an extremum is accurate to rounding even where the angle is known only to ~1e-8).  Extrema closer in
    b than 1e-12·scale to both neighbours are ignored (flat or rounding wiggles).
    """
    from scipy.optimize import minimize_scalar

    theta = np.arange(points) * (TWO_PI / points)
    b = wall(theta)
    if not np.all(np.isfinite(b)):
        raise InvalidWall(f"wall {wall.description!r} is not finite everywhere on [0, 2π)")
    h = TWO_PI / points
    prev, nxt = np.roll(b, 1), np.roll(b, -1)
    flat = 1e-12 * wall.scale
    is_max = (b > prev) & (b >= nxt) & ((b - np.minimum(prev, nxt)) > 0)
    is_min = (b < prev) & (b <= nxt)

    def refine(i, sign):
        res = minimize_scalar(lambda x: sign * float(wall(np.array([x]))[0]), bounds=(theta[i] - h, theta[i] + h),
                              method="bounded", options={"xatol": 1e-12})
        x = float(res.x) % TWO_PI
        return x, float(wall(np.array([x]))[0])

    maxima = [refine(i, -1.0) for i in np.flatnonzero(is_max)]
    minima = [refine(i, 1.0) for i in np.flatnonzero(is_min)]
    # drop pairs that are rounding wiggles: a maximum less than `flat` above the minima next to it
    if maxima and minima and max(v for _, v in maxima) - min(v for _, v in minima) <= flat:
        maxima, minima = [], []
    if len(maxima) <= 1:
        lo = min(minima, key=lambda m: m[1]) if minima else (float(theta[int(np.argmin(b))]), float(b.min()))
        left = maxima[0][0] if maxima else 0.0
        table = np.array([[left, math.inf, lo[0]]])
        return Landscape(np.array([lo[0]]), np.array([left]), np.array([math.inf]), [f"rest θ={lo[0]:.4g}"], table)
    maxima.sort()
    mx = np.array([a for a, _ in maxima])
    mv = np.array([v for _, v in maxima])
    k = mx.size
    mins = np.empty(k)
    barriers = np.empty(k)
    for i in range(k):
        left, right = mx[i], mx[(i + 1) % k] + (TWO_PI if i == k - 1 else 0.0)
        inside = [(v, a) for a, v in minima if left < a < right or left < a + TWO_PI < right]
        if inside:
            mins[i] = min(inside)[1]
        else:  # no sampled minimum between two maxima (cannot happen for strict extrema): the midpoint
            mins[i] = (0.5 * (left + right)) % TWO_PI
        barriers[i] = min(mv[i], mv[(i + 1) % k])
    names = [f"rest θ={m:.4g}" for m in mins]
    if k == 2 and np.sign(np.sin(mins[0])) * np.sign(np.sin(mins[1])) < 0:
        names = ["heads" if math.sin(m) < 0 else "tails" for m in mins]
    table = np.column_stack([mx, barriers, mins])
    return Landscape(mins, mx, barriers, names, np.ascontiguousarray(table))


# ---------------------------------------------------------------------------------------------------- table
@dataclass(frozen=True, repr=False)
class FieldTable:
    """A floor (and optionally a ceiling) for ``wall`` in a constant field ``g``, with restitution ``e``.

    Parameters
    ----------
    wall : Wall
    g : float
        The field in κ/s² along −η (≥ 0; 0: no field).
    e : float
        Newton's coefficient of restitution on the normal velocity, in (0, 1] (1: elastic).
    b0 : float
        Offset of the wall (``b0 + b`` is the support function), as in :class:`.billiard.Billiard`.
    H : float or None
        Distance of the ceiling (units of κ); ``None``: a floor only.
    settle : bool
        Whether an orbit ends once its level is below its valley's barrier (the outcome is then decided; the
        default).  ``False`` for elastic orbits followed for their own sake (a wedge, where the single valley
        would end every orbit at its first impact): the kernel gets no valley table and never settles.
    landscape : Landscape
        The valleys of the floor (:func:`landscape`); with ``settle=False``, without the kernel's valley table.
    """

    wall: Wall
    g: float = 0.0
    e: float = 1.0
    b0: float = 0.0
    H: float | None = None
    settle: bool = True
    landscape: Landscape = field(init=False)

    def __post_init__(self):
        if not isinstance(self.wall, Wall):
            raise InvalidArgument(f"`wall` must be a coinwall.forward.Wall, got {type(self.wall).__name__}")
        for name in ("g", "e", "b0"):
            value = getattr(self, name)
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise InvalidArgument(f"`{name}` must be a real number, got {value!r}") from None
            if isinstance(value, bool) or not math.isfinite(number):
                raise InvalidArgument(f"`{name}` must be a finite number, got {value!r}")
            object.__setattr__(self, name, number)
        if not (self.g == 0.0 or 1e-9 <= self.g <= 1e12):
            raise InvalidArgument(f"`g` must be 0 or a field between 1e-9 and 1e12 κ/s², got {self.g!r}")
        if not 0.0 < self.e <= 1.0:
            raise InvalidArgument(f"`e` must be a coefficient of restitution in (0, 1], got {self.e!r}")
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
            land = Landscape(land.minima, land.maxima, land.barriers, land.names, np.empty((0, 3)))
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

    def energy(self, eta, v_theta, v_eta):
        """Energy per M κ²: ``½(θ̇² + η̇²) + g η``."""
        return 0.5 * (np.asarray(v_theta) ** 2 + np.asarray(v_eta) ** 2) + self.g * np.asarray(eta)

    @safe_repr
    def __repr__(self):
        top = f", H={self.H:g}" if self.H is not None else ", floor only"
        return f"FieldTable({self.wall!r}, g={self.g:g}, e={self.e:g}, b0={self.b0:g}{top})"


# ---------------------------------------------------------------------------------------------------- results
@dataclass(frozen=True, repr=False)
class Flight:
    """Impacts of one orbit in the field, in order, and how it ended.

    ``time, theta, eta, v_theta, v_eta, side`` per impact (velocities just after it; θ unwrapped; side 0 the
    floor, 1 the ceiling).  ``status`` is a key of :data:`STATUS` (a word), ``valley`` the index into
    ``table.landscape`` where θ was at the end, ``outcome`` its name (or ``None`` when the status does not
    decide one), ``note`` why it stopped when that is not an outcome.
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

    def __len__(self):
        return int(self.time.size)

    @property
    def outcome(self):
        if self.status in ("settled", "caught", "rest"):
            return self.table.landscape.names[self.valley]
        return None

    @property
    def energy(self) -> np.ndarray:
        return self.table.energy(self.eta, self.v_theta, self.v_eta)

    @safe_repr
    def __repr__(self):
        return (f"Flight({len(self)} impacts ({self.floor_impacts} on the floor), {self.status}, "
                f"outcome {self.outcome})")


# ---------------------------------------------------------------------------------------------------- kernel
class _FieldKernel:
    def __init__(self, wall: Wall):
        from ..billiard.kernel import compiled, kernel_module

        base = compiled(_WallHolder(wall))  # the billiard's constants and cell bounds of this wall (kept per wall)
        # the wall's code, the search the billiard kernel compiles too (_search.py), then this kernel's text
        self.module, _ = kernel_module(wall, FIELD_SOURCE, "coinwall_field")
        self.constants, self.bounds, self.cells = base.constants, base.bounds, base.cells

    def call(self, name, *args):
        return getattr(self.module, name)(*args)

    def args(self, table: FieldTable):
        H = float(table.H) if table.H is not None else 0.0
        return (H, float(table.b0), float(table.g), float(table.e), table.H is not None)

    def wall_args(self, table: FieldTable):
        bd = self.bounds
        return (self.constants, self.cells, bd["lookup"], bd["wmin"], bd["wmax"], float(table.tol),
                table.landscape.table)


class _WallHolder:
    # kernel.compiled() keys its cache on ``table.wall``
    def __init__(self, wall):
        self.wall = wall


_FIELD_KERNELS: dict = {}


def _kernel(table: FieldTable) -> _FieldKernel:
    import weakref

    global _FIELD_KERNELS
    if not isinstance(_FIELD_KERNELS, weakref.WeakKeyDictionary):
        _FIELD_KERNELS = weakref.WeakKeyDictionary()
    comp = _FIELD_KERNELS.get(table.wall)
    if comp is None:
        comp = _FIELD_KERNELS[table.wall] = _FieldKernel(table.wall)
    return comp


# ---------------------------------------------------------------------------------------------------- inputs
def _check_state(table: FieldTable, state, leaving=None):
    """A state [θ, η, θ̇, η̇]: finite, on or above the floor (and below the ceiling); the wall it is on."""
    try:
        arr = np.array(state, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InvalidArgument("`state` must be numbers [theta, eta, v_theta, v_eta]") from None
    if arr.shape != (4,) or not np.all(np.isfinite(arr)):
        raise InvalidArgument(f"`state` must be four finite numbers [theta, eta, v_theta, v_eta], got {state!r}")
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
    """One orbit in the field for at most ``impacts`` impacts, stopping when its outcome is decided.

    ``catch=True`` stops at the first floor contact (the coin caught at the floor: Keller's toss).  A state on
    a wall (η on it to 10·tol) must move into the table; it leaves that wall.  ``method`` is ``"kernel"``
    (compiled) or ``"reference"`` (:func:`reference_run`).
    """
    if not isinstance(table, FieldTable):
        raise InvalidArgument(f"`table` must be a FieldTable, got {type(table).__name__}")
    impacts = _check_impacts(impacts)
    check_memory(f"`impacts` = {impacts} (41 bytes per impact)", 41.0 * impacts)
    arr, leaving = _check_state(table, state)
    if method == "reference":
        rows, status, valley, floor_hits = reference_run(table, arr, leaving, impacts, catch)
        cols = [np.array(c, dtype=float) for c in zip(*rows)] if rows else [np.empty(0) for _ in range(6)]
        return _flight(table, arr, cols, status, valley, floor_hits, method)
    if method != "kernel":
        raise InvalidArgument(f"`method` must be one of {METHODS}, got {method!r}")
    comp = _kernel(table)
    out = [np.empty(impacts) for _ in range(5)] + [np.empty(impacts, dtype=np.int8)]
    summary = np.empty(8)
    turns = math.floor(arr[0] / TWO_PI)
    start = arr.copy()
    start[0] -= turns * TWO_PI
    done, status = comp.call("_run", start, int(turns), leaving, impacts, *comp.args(table), bool(catch),
                             table.chatter, *comp.wall_args(table), True, *out, summary)
    cols = [o[:done] for o in out]
    return _flight(table, arr, cols, int(status), int(summary[7]), int(summary[6]), method)


def _flight(table, start, cols, status, valley, floor_hits, method):
    time, theta, eta, vt, ve, side = cols
    return Flight(time=np.asarray(time, dtype=float), theta=np.asarray(theta, dtype=float),
                  eta=np.asarray(eta, dtype=float), v_theta=np.asarray(vt, dtype=float),
                  v_eta=np.asarray(ve, dtype=float), side=np.asarray(side, dtype=np.int8), start=np.asarray(start),
                  table=table, status=STATUS.get(status, str(status)), valley=int(valley),
                  floor_impacts=int(floor_hits), method=method, note=FIELD_NOTES.get(status, ""))


def field_run_many(table: FieldTable, states, impacts: int, catch: bool = False, workers=None):
    """Many orbits in parallel (numba threads), summaries only.

    Returns a dict of arrays: ``status`` (codes of :data:`STATUS`), ``valley``, ``floor_impacts``,
    ``impacts``, ``time`` (of the last impact) and ``final`` (n, 4) states (θ reduced mod 2π).  States must
    be strictly inside the table (not on a wall).
    """
    import numba

    impacts = _check_impacts(impacts)
    arr = np.array(states, dtype=float).reshape(-1, 4)
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
    comp = _kernel(table)
    m = arr.shape[0]
    done = np.zeros(m, dtype=np.int64)
    status = np.zeros(m, dtype=np.int64)
    summary = np.zeros((m, 8))
    previous = numba.get_num_threads()
    try:
        if workers is not None:
            numba.set_num_threads(min(check_count("workers", workers), numba.config.NUMBA_NUM_THREADS))
        comp.call("_run_many", np.ascontiguousarray(arr), impacts, *comp.args(table), bool(catch), table.chatter,
                  *comp.wall_args(table), done, status, summary)
    finally:
        numba.set_num_threads(previous)
    return {"status": status, "valley": summary[:, 7].astype(np.int64), "floor_impacts": summary[:, 6].astype(np.int64),
            "impacts": done, "time": summary[:, 5], "final": summary[:, [0, 2, 3, 4]]}


# ---------------------------------------------------------------------------------------------------- reference
_REFERENCE_MAX_STEPS = 400_000


def reference_run(table: FieldTable, state, leaving: int, impacts: int, catch: bool = False):
    """The plain-numpy twin of the kernel: conservative advancement with a global Lipschitz bound.

    On ``[t, t + τ]`` the gap ``f = A + B t − ½ Q t² − b(φ0 + ω t)`` has ``f' ≥ −Λ − |Q| τ`` with
    ``Λ = |B − Q t| + |ω| max|b'|``, so ``f(t + τ) ≥ f(t) − Λ τ − ½ |Q| τ²``: the positive root of that
    bound is a step that cannot pass a root.  The first step off the wall just left uses
    ``f'' ≥ −(Q + ω² max|b''|)`` and never crosses a kink.  It stops at ``f ≤ tol`` and polishes with
    Brent's method when a sign change is within 1e-8.  Slow (linear convergence, a casadi call per step).
    Returns ``(rows, status, valley, floor impacts)`` with rows ``(time, θ, η, θ̇, η̇, side)``.
    """
    from scipy.optimize import brentq

    from ..billiard.reference import sample_bounds

    wall = table.wall
    lip, curv, kinks = sample_bounds(wall)
    tol = table.tol
    g, e, b0 = table.g, table.e, table.b0
    H = table.H
    th, eta, vt, ve = (float(x) for x in state)
    rows = []
    clock = 0.0
    floor_hits = 0
    status = 0
    valleys = table.landscape
    walls = (0, 1) if table.ceiling else (0,)

    def gaps(t):
        phis = np.array([th + vt * t, th + math.pi + vt * t])
        b, d1, _ = wall.derivatives(phis)
        h = eta + ve * t - 0.5 * g * t * t
        out = [h - b0 - b[0]]
        if table.ceiling:
            out.append(H - b0 - b[1] - h)
        return np.array(out), d1

    for _ in range(impacts):
        t = 0.0
        hit = -1
        for step in range(_REFERENCE_MAX_STEPS):
            gp, d1 = gaps(t)
            rate = abs(ve - g * t) + abs(vt) * lip
            if step == 0 and leaving >= 0:
                q = g if leaving == 0 else -g
                g1 = (ve - vt * d1[0]) if leaving == 0 else (-ve - vt * d1[1])
                K = q + vt * vt * curv
                if K > 0:
                    tau = 2.0 * g1 / K
                elif g1 > 0:
                    tau = math.inf
                else:
                    tau = 0.0
                if kinks.size and vt != 0:
                    phi = th + leaving * math.pi
                    ahead = ((kinks - phi) * np.sign(vt)) % TWO_PI
                    ahead = ahead[ahead > 1e-12]
                    if ahead.size:
                        tau = min(tau, float(ahead.min()) / abs(vt))
                if len(walls) == 2:
                    other = gp[1 - leaving]
                    tau = min(tau, 2 * other / (rate + math.sqrt(rate * rate + 2 * g * other)))
                if not math.isfinite(tau):
                    break
                t += tau
                continue
            k = int(np.argmin(gp))
            if gp[k] <= tol:
                hit = k
                break
            f = float(gp[k]) if len(walls) == 1 else float(gp.min())
            t += 2.0 * f / (rate + math.sqrt(rate * rate + 2.0 * g * f))
        if hit < 0:
            status = 6 if step < _REFERENCE_MAX_STEPS - 1 else 7
            break

        def gap(s, k=hit):
            return float(gaps(s)[0][k])

        if gap(t) > 0.0:
            for width in (1e-12, 1e-10, 1e-8):
                if gap(t + width) < 0.0:
                    t = brentq(gap, t, t + width, xtol=1e-16, rtol=1e-15, maxiter=200)
                    break
        _, d1 = gaps(t)
        th, eta, ve = th + vt * t, eta + ve * t - 0.5 * g * t * t, ve - g * t
        clock += t
        s = float(d1[0]) if hit == 0 else -float(d1[1])
        fimp = (1.0 + e) * (ve - s * vt) / (1.0 + s * s)
        vt, ve = vt + fimp * s, ve - fimp
        rows.append((clock, th, eta, vt, ve, hit))
        leaving = hit
        if hit == 0:
            floor_hits += 1
            if catch:
                status = 2
                break
            if g > 0:
                rest = (ve - vt * s) < table.chatter
                if rest:
                    fimp = (ve - s * vt) / (1.0 + s * s)
                    vt, ve = vt + fimp * s, ve - fimp
                level = eta - b0 + 0.5 * (vt * vt + ve * ve) / g
                if level < valleys.barriers[int(valleys.valley(th))]:
                    status = 3 if rest else 1
                    break
                if rest:
                    status = 4
                    break
    return rows, status, int(valleys.valley(th)), floor_hits


# ---------------------------------------------------------------------------------------------------- sliding
_SLIDES_MAX = 20


def slide(table: FieldTable, state, duration=None):
    """Follow the body sliding on a smooth frictionless floor from ``state`` (on the floor, no normal velocity)
    until it lifts off; return the first state in the air after lift-off, or ``None`` if it slides on.

    On the floor ``η = B(θ) = b0 + b(θ)`` the motion is one-dimensional:
    ``(1 + B'²) θ̈ + B' B'' θ̇² + g B' = 0`` (energy ``½(1 + B'²)θ̇² + g B`` is conserved; no friction, no
    loss), with the contact force ``λ = (g + B'' θ̇²)/(1 + B'²)`` along the normal.  It lifts off where λ
    falls to zero (B'' < 0: over a convex part of the wall, e.g. the coin's edge); there the gap opens only
    cubically, so the free flight is followed (in closed form) until the gap is 10⁴ contact tolerances, with
    the gap checked positive on 32 points of the way.  ``duration`` (default 30·√(max(1, scale)/g)) bounds the
    time on the floor; ``None`` is returned when it does not lift off in that time (it rocks on the floor for
    ever in a frictionless world), or when the wall has corners (a sliding body meeting a corner needs an
    impact model this function does not have).
    """
    from scipy.integrate import solve_ivp

    if table.wall.kinks or table.g <= 0:
        return None
    g, b0, wall = table.g, table.b0, table.wall
    scale = max(1.0, wall.scale)
    T = duration if duration is not None else 30.0 * math.sqrt(scale / g)

    from ..billiard.wallcode import python_wall

    d = python_wall(wall, order=2)  # the generated plain-Python b, b', b'' of one angle (no casadi call per step)

    def rhs(_t, y):
        _, d1, d2 = d(y[0])
        return [y[1], -d1 * (g + d2 * y[1] ** 2) / (1.0 + d1 * d1)]

    def lift(_t, y):
        return g + d(y[0])[2] * y[1] ** 2

    lift.terminal, lift.direction = True, -1
    th0, w0 = float(state[0]), float(state[2])
    if lift(0.0, [th0, w0]) > 0:
        sol = solve_ivp(rhs, (0.0, T), [th0, w0], method="DOP853", rtol=1e-11, atol=1e-12, events=lift)
        if sol.status != 1:
            return None
        th0, w0 = (float(x) for x in sol.y_events[0][0])
    b, d1, _ = d(th0)
    eta0, v0 = b0 + b, d1 * w0
    tol = table.tol
    dt = 1e-9 * math.sqrt(scale / g)

    def gap(s):
        return eta0 + v0 * s - 0.5 * g * s * s - b0 - float(wall(np.array([th0 + w0 * s]))[0])

    for _ in range(200):
        if gap(dt) > 1e4 * tol:
            break
        dt *= 1.5
    else:
        return None
    if min(gap(dt * k / 32) for k in range(1, 33)) <= 0:
        return None
    return np.array([th0 + w0 * dt, eta0 + v0 * dt - 0.5 * g * dt * dt, w0, v0 - g * dt])


def settle_many(table: FieldTable, states, impacts: int, catch: bool = False, workers=None, follow_slides=True):
    """:func:`field_run_many`, with orbits that come to slide on the floor above their barrier (status 4)
    followed on the floor (:func:`slide`) and back into the air until they settle, up to 20 times each.

    Returns the dict of :func:`field_run_many` plus ``slides`` (how often each orbit slid).  An orbit still
    sliding at the end keeps status 4 (no outcome).  ``follow_slides=False`` skips the sliding (it is
    Python, about 50 ms per slide: the cost of a basin map with many sliding tosses).
    """
    out = field_run_many(table, states, impacts, catch=catch, workers=workers)
    out["slides"] = np.zeros(out["status"].size, dtype=np.int64)
    if catch or not follow_slides:
        return out
    stuck = np.zeros(out["status"].size, dtype=bool)  # slid without lifting off: slides for ever
    for _ in range(_SLIDES_MAX):
        todo = np.flatnonzero((out["status"] == 4) & ~stuck)
        if todo.size == 0:
            break
        resumed, where = [], []
        for k in todo:
            air = slide(table, out["final"][k])
            if air is not None:
                resumed.append(air)
                where.append(k)
            else:
                stuck[k] = True
        if not where:
            break
        where = np.array(where)
        left = np.maximum(impacts - out["impacts"][where], 1)
        more = field_run_many(table, np.array(resumed), int(left.max()), workers=workers)
        out["slides"][where] += 1
        for name in ("status", "valley", "final"):
            out[name][where] = more[name]
        out["impacts"][where] += more["impacts"]
        out["floor_impacts"][where] += more["floor_impacts"]
        out["time"][where] = np.nan  # (the time on the floor is not tracked)
    return out
