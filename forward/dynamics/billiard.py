"""The billiard: a point particle in the (θ, η) strip between the two walls.

With ``η = y/κ`` the free motion of the body between two flat walls is a
free point particle in the plane (θ, η) with the Euclidean metric, periodic
in θ, between the lower wall ``η = b0 + b(θ)`` and the upper wall
``η = H − (b0 + b(θ + π))``, reflecting specularly (paper, eqs. 1–8 and
13–14).  Units: κ; unit speed, so time equals path length.

This module holds the table (:class:`Billiard`), the result (:class:`Trajectory`),
the checks of the inputs and the public entry points :func:`simulate`, :func:`ensemble`,
:func:`random_states` and :func:`compile_kernel`.  The motion itself is computed by one
of the two :data:`METHODS`:

* ``"kernel"``: the numba kernel, :mod:`._kernel` (the search for the next collision and
  why it cannot miss one), compiled per wall by :mod:`.kernel` from the cell bounds of
  :mod:`.cellbounds`;
* ``"reference"``: the plain-numpy stepper of :mod:`.reference`, slow and simple, the
  yardstick the kernel is tested against.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..angles import TWO_PI
from ..display import safe_repr
from ..errors import InvalidArgument, InvalidWall
from ..validation import check_choice, check_count, is_integer
from ..wall import Wall
from .cellbounds import CELLS, SAMPLES
from .kernel import compiled, run, run_many
from .reference import reference_run

__all__ = ["Billiard", "Trajectory", "simulate", "random_states", "ensemble", "compile_kernel", "METHODS",
           "CELLS", "SAMPLES", "HIT_TOL"]

METHODS = ("kernel", "reference")
HIT_TOL = 1e-13      # a gap below tol·max(1, H, scale) is a contact
_GAP_GRID = 4096


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
            raise InvalidArgument(f"`wall` must be a coinwall.forward.Wall, got {type(self.wall).__name__}")
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

    @safe_repr
    def __repr__(self) -> str:
        return f"Billiard({self.wall!r}, H={self.H:g}, b0={self.b0:g}, gap {self.gap_min:.4g}..{self.gap_max:.4g})"


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

    @safe_repr
    def __repr__(self) -> str:
        n = self.time.size
        if n == 0:
            return f"Trajectory(0 collisions{', ' + self.note if self.note else ''})"
        bottom = float(np.mean(self.side == 0))
        extra = f", note: {self.note}" if self.note else ""
        return (f"Trajectory({n} collisions, {self.method}, t_end={self.time[-1]:.6g}, "
                f"bottom fraction {bottom:.3f}{extra})")


# ---------------------------------------------------------------------------------------------------- inputs
def _check_collisions(collisions) -> int:
    # not check_count: its message says "an integer >= 1", and callers (and tests) read "positive integer"
    if not is_integer(collisions) or collisions <= 0:
        raise InvalidArgument(f"`collisions` must be a positive integer, got {collisions!r}")
    return int(collisions)


def _check_table(table):
    if not isinstance(table, Billiard):
        raise InvalidArgument(f"`table` must be a coinwall.forward.dynamics.Billiard, got {type(table).__name__}")


def _check_method(method):
    check_choice("method", method, METHODS)


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
    n = check_count("n", n)
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


def compile_kernel(table: Billiard) -> float:
    """Compile (or load from numba's disk cache) the kernels for ``table``'s wall; return the seconds it took.

    Both the single-orbit kernel (:func:`simulate`) and the parallel one (:func:`ensemble`).
    """
    import time

    _check_table(table)
    start = time.perf_counter()
    comp = compiled(table)
    states = random_states(table, 1, seed=0)
    run(comp, table, states[0], -1, 1)
    ensemble(table, states, 1, workers=1)  # the parallel driver is a separate compiled function
    return time.perf_counter() - start




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
    collisions = _check_collisions(collisions)
    unit, speed, leaving = _check_states(table, state)
    if method == "reference":
        rows, note = reference_run(table, unit[0], int(leaving[0]), collisions)
        cols = list(zip(*rows)) if rows else [[] for _ in range(6)]
        return _trajectory(table, np.asarray(state, dtype=float).ravel(), speed[0], cols, note, method)
    rows, note = run(compiled(table), table, unit[0], int(leaving[0]), collisions)
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
    collisions = _check_collisions(collisions)
    unit, speed, leaving = _check_states(table, states, "states")
    starts = np.array(states, dtype=float).reshape(-1, 4)
    if method == "reference":
        return [simulate(table, s, collisions, method) for s in starts]
    if workers is not None:
        workers = check_count("workers", workers)
    runs = run_many(compiled(table), table, unit, leaving, collisions, workers)
    return [_trajectory(table, starts[k], speed[k], rows, note, method) for k, (rows, note) in enumerate(runs)]
