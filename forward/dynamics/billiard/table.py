"""The billiard: a point particle in the (θ, η) strip between the two walls.

With ``η = y/κ`` the free motion of the body between two flat walls is a
free point particle in the plane (θ, η) with the Euclidean metric, periodic
in θ, between the lower wall ``η = b0 + b(θ)`` and the upper wall
``η = H − (b0 + b(θ + π))``, reflecting specularly (paper, eqs. 1–8 and
13–14).  Units: κ; unit speed, so time equals path length.

This module holds the table (:class:`Billiard`), the checks of the inputs and the public entry
points :func:`simulate`, :func:`ensemble`, :func:`random_states` and :func:`compile_kernel`; the
result, :class:`Trajectory`, is defined in :mod:`.trajectory` and imported here.  The motion itself
is computed by one of the two :data:`METHODS`:

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

from ...angles import TWO_PI
from ...display import safe_repr
from ...errors import InvalidArgument, InvalidWall
from ...validation import check_choice, check_count, check_memory, check_range, check_seed, is_integer
from ...wall import Wall
from .cellbounds import CELLS, SAMPLES
from .kernel import compiled, run, run_many
from .reference import reference_run
from .trajectory import Trajectory

__all__ = ["BYTES_PER_COLLISION", "CELLS", "HEIGHT_MAX", "HIT_TOL", "METHODS", "MIN_OPENING", "SAMPLES", "Billiard",
           "Trajectory", "compile_kernel", "ensemble", "random_states", "simulate"]

METHODS = ("kernel", "reference")
HIT_TOL = 1e-13      # a gap below tol·max(1, H, scale) is a contact
_GAP_GRID = 4096
HEIGHT_MAX = 1e6     # largest |b0| and wall size max|b| (units of κ); H up to 4·HEIGHT_MAX (Billiard docstring)
MIN_OPENING = 1e4    # the widest opening of the strip must be at least this many contact tolerances
BYTES_PER_COLLISION = 41   # five float64 columns and one int8 (Trajectory)
_DRAWS_MIN_FRACTION = 1e-6  # random_states refuses a table where fewer draws than this fall inside
_DRAW_BUDGET_MIN = 2e6      # random_states draws at least this many (~0.5 s) before it gives up


# ---------------------------------------------------------------------------------------------------- table
@dataclass(frozen=True, repr=False)
class Billiard:
    """The billiard table: the strip between the two walls of ``wall`` at distance ``H``.

    Parameters
    ----------
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

    Valid range (why: the kernel's arithmetic must stay meaningful in float64, unit roundoff u = 1.1e-16).
    Heights (η, H, b0, b) enter the kernel as absolute numbers: the gap ``A + B t − b`` of a flight is formed
    with an error of about u·H, and a flight that crosses the strip carries θ by about H·|v_θ/v_η|, so the
    contact angle after reduction mod 2π is known to about u·H per unit of |v_θ/v_η|.  With
    ``|b0| ≤ HEIGHT_MAX = 1e6``, ``max|b| ≤ 1e6`` and ``H ≤ 4e6`` (room for both at their limits) that error
    is below u·4e6 ≈ 4.4e-10 (κ, or rad per unit of |v_θ/v_η|), and the contact tolerance
    ``tol = 1e-13·max(1, H, scale)`` is at most 4e-7 of a unit: contacts and cell indices stay meaningful.
    Far beyond (H = 1e50, 1e100) θ loses every digit in one flight, its cell index is garbage and the
    search would loop or read outside its table; those values are refused here.  At the other end, the
    widest opening ``gap_max`` must be at least ``MIN_OPENING = 1e4`` contact tolerances: a strip narrower
    than that is within a few thousand tolerances of both walls everywhere and the kernel cannot tell a
    bounce from rounding (``random_states`` also keeps 1e3 tolerances from each wall).  The lower end is
    therefore ``H ≥ min_θ(2 b0 + b(θ) + b(θ+π)) + 1e4·tol``; the message of a refused H names that value.

    Examples
    --------
    A wall ``1 + 0.2 cos θ`` (a circle's wall with its centre of mass off centre) at ``H = 4``: the strip's
    height ``H − b(θ) − b(θ + π) = 2`` is the same at every angle.

    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> round(table.gap_min, 12), round(table.gap_max, 12)
    (2.0, 2.0)
    >>> float(table.lower(0.0)), float(table.upper(0.0))      # b(0) = 1.2 below, H − b(π) = 3.2 above
    (1.2, 3.2)
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
        precision = "so that float64 keeps the contact angle to 1e-9 in one flight (Billiard docstring)"
        if not self.wall.scale <= HEIGHT_MAX:
            raise InvalidWall(f"wall {self.wall.description!r} reaches |b| = {self.wall.scale:.3g}; the billiard "
                              f"needs max |b| <= {HEIGHT_MAX:g} (units of κ), {precision}")
        check_range("b0", self.b0, -HEIGHT_MAX, HEIGHT_MAX, why=precision)
        check_range("H", self.H, -4 * HEIGHT_MAX, 4 * HEIGHT_MAX, why=precision)
        theta = np.linspace(0.0, TWO_PI, _GAP_GRID, endpoint=False)
        gap = self.upper(theta) - self.lower(theta)
        object.__setattr__(self, "gap_min", float(gap.min()))
        object.__setattr__(self, "gap_max", float(gap.max()))
        if self.gap_max <= 0.0:
            need = self.H - self.gap_max
            raise InvalidArgument(f"`H` = {self.H:g} leaves no room for motion (the walls overlap at every angle); "
                                  f"need H > {need:.6g} = min over θ of 2·b0 + b(θ) + b(θ+π)")
        if self.gap_max < MIN_OPENING * self.tol:
            need = self.H - self.gap_max + MIN_OPENING * self.tol
            raise InvalidArgument(f"`H` = {self.H!r} opens the strip by only {self.gap_max:.3g} at its widest; the "
                                  f"billiard needs at least {MIN_OPENING:g} contact tolerances "
                                  f"({MIN_OPENING * self.tol:.3g}) to tell a bounce from rounding: "
                                  f"use H >= {need:.12g}")

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
    """Validate states (m, 4); return (unit-speed states with θ reduced to [0, 2π), speeds, leaving side per
    state: -1/0/1, whole turns of θ per state).

    A state with |θ| ≥ 2π (e.g. an unwrapped :attr:`Trajectory.final_state`) carries an error of a few ulp
    of θ (3.6e-12 at 2e4 rad), which moves the wall under it by |b'| times that: the tolerance for "on the
    wall" is widened by that much, so such a state is still read as the contact it came from.
    """
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
    turns = np.floor(arr[:, 0] / TWO_PI)
    reduced = arr[:, 0] - turns * TWO_PI  # the kernel's own reduction, done here so the checks use it too
    over, under = reduced >= TWO_PI, reduced < 0.0
    reduced[over], turns[over] = reduced[over] - TWO_PI, turns[over] + 1
    reduced[under], turns[under] = reduced[under] + TWO_PI, turns[under] - 1
    lower = table.lower(reduced)
    upper = table.upper(reduced)
    tols = np.full(arr.shape[0], 10 * table.tol)
    far = np.abs(arr[:, 0]) >= TWO_PI
    if far.any():
        slopes = np.abs(table.wall.derivatives(np.concatenate([reduced[far], reduced[far] + math.pi]))[1])
        slope = np.maximum(slopes[:far.sum()], slopes[far.sum():])
        tols[far] += 8 * np.spacing(np.abs(arr[far, 0])) * (1.0 + np.nan_to_num(slope, nan=0.0, posinf=0.0))
    leaving = np.full(arr.shape[0], -1, dtype=np.int64)
    for i in range(arr.shape[0]):
        _, eta, vt, ve = arr[i]
        th, tol = reduced[i], tols[i]
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
    unit[:, 0] = reduced
    unit[:, 2:] /= speed[:, None]
    return unit, speed, leaving, turns.astype(np.int64)


def random_states(table: Billiard, n: int, seed=None) -> np.ndarray:
    """``n`` states uniform in the Liouville measure of ``table``.

    Position uniform in the area of the strip (rejection from the bounding
    box, angles where the strip is closed are never chosen), direction
    uniform on the circle, unit speed.  Same ``seed`` ⇒ same states.

    Parameters
    ----------
    table : Billiard
    n : int
        Number of states (≥ 1).
    seed : int, optional
        Seed of the random generator (``None``: fresh entropy).

    Returns
    -------
    ndarray (n, 4)
        ``[theta, eta, v_theta, v_eta]`` with theta in [0, 2π).

    Raises
    ------
    InvalidArgument
        For a bad ``n`` or ``seed``, or a strip so narrow that almost no random draw lands inside it.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall import Billiard, Wall, random_states
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> states = random_states(table, 3, seed=1)
    >>> states.shape
    (3, 4)
    >>> bool(np.all((states[:, 1] > table.lower(states[:, 0])) & (states[:, 1] < table.upper(states[:, 0]))))
    True
    >>> np.hypot(states[:, 2], states[:, 3]).round(12).tolist()      # unit speed
    [1.0, 1.0, 1.0]
    """
    _check_table(table)
    n = check_count("n", n)
    check_memory(f"`n` = {n} start states (about 100 bytes each while they are drawn)", 100.0 * n)
    rng = np.random.default_rng(check_seed(seed))
    theta_grid = np.linspace(0.0, TWO_PI, _GAP_GRID, endpoint=False)
    lo = float(np.min(table.lower(theta_grid)))
    hi = float(np.max(table.upper(theta_grid)))
    margin = 1e3 * table.tol  # a safety distance so a state is never "on" a wall
    fraction = _inside_fraction(table, table.H, theta_grid, margin)
    if not fraction >= _DRAWS_MIN_FRACTION:
        raise InvalidArgument(_too_narrow(table, fraction, theta_grid, margin))
    # rejection sampling: about n/fraction draws; the budget is 20 times that and at least 2e6 draws (~0.2 s;
    # the grid estimate can be far too high for a sliver narrower than its spacing), so a table where almost
    # nothing is accepted ends with a message instead of looping
    budget = _DRAW_BUDGET_MIN + 20.0 * n / fraction
    out = np.empty((0, 2))
    draws = 0
    while out.shape[0] < n:
        if draws >= budget:
            raise InvalidArgument(_too_narrow(table, out.shape[0] / max(draws, 1), theta_grid, margin,
                                              f"{out.shape[0]} of {draws} random draws"))
        batch = int(min(max(64, 2 * (n - out.shape[0]) / fraction), 1_000_000))
        draws += batch
        theta = rng.uniform(0.0, TWO_PI, batch)
        eta = rng.uniform(lo, hi, batch)
        inside = (eta > table.lower(theta) + margin) & (eta < table.upper(theta) - margin)
        out = np.vstack([out, np.column_stack([theta[inside], eta[inside]])])
    out = out[:n]
    angle = rng.uniform(0.0, TWO_PI, n)
    return np.column_stack([out, np.cos(angle), np.sin(angle)])


def _inside_fraction(table, H, theta, margin):
    """Share of the box [0, 2π) × [min lower, max upper] farther than ``margin`` from both walls (grid estimate)."""
    lower = table.lower(theta)
    upper = table.upper(theta) + (H - table.H)
    height = float(np.max(upper) - np.min(lower))
    return float(np.mean(np.clip(upper - lower - 2 * margin, 0.0, None))) / height if height > 0 else 0.0


def _too_narrow(table, fraction, theta, margin, measured="a grid of 4096 angles"):
    """The message of :func:`random_states` for a strip that (almost) never accepts a draw, with an H that would."""
    low, high = table.H, table.H + 4.0 * max(1.0, table.wall.scale)
    for _ in range(100):  # bisection for the H where a fraction 1e-3 of the box is inside
        mid = 0.5 * (low + high)
        low, high = (mid, high) if _inside_fraction(table, mid, theta, margin) < 1e-3 else (low, mid)
    return (f"cannot draw {'enough ' if measured != 'a grid of 4096 angles' else ''}start states: only a fraction "
            f"{fraction:.3g} of the box θ in [0, 2π), η in [min lower wall, max upper wall] lies inside the strip "
            f"(at least {margin:.3g} from both walls; from {measured}) at `H` = {table.H!r}; H >= {high:.6g} would "
            f"put 1e-3 of it inside")


def compile_kernel(table: Billiard, device: str = "cpu") -> float:
    """Compile (or load from numba's disk cache) the kernels for ``table``'s wall; return the seconds it took.

    Both the single-orbit kernel (:func:`simulate`) and the parallel one (:func:`ensemble`); with
    ``device="gpu"`` the parallel one is the GPU's (compiled in memory, in each process).

    Parameters
    ----------
    table : Billiard
    device : {"cpu", "gpu"}
        Where the parallel kernel will run.

    Returns
    -------
    float
        Seconds spent (near zero once the kernels are cached for this wall).

    Raises
    ------
    InvalidArgument
        For a table that is not a :class:`Billiard` or an unknown device (or ``"gpu"`` without one).

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall.forward.dynamics import compile_kernel
    >>> seconds = compile_kernel(table)
    >>> seconds >= 0.0
    True
    """
    import time

    from .gpu import check_device

    _check_table(table)
    check_device(device)
    start = time.perf_counter()
    comp = compiled(table)
    states = random_states(table, 1, seed=0)
    run(comp, table, states[0], -1, 1)
    ensemble(table, states, 1, workers=1, device=device)  # the parallel driver is a separate compiled function
    return time.perf_counter() - start




# ---------------------------------------------------------------------------------------------------- API
def _trajectory(table, start, speed, rows, note, method, end=(math.nan, 0)):
    time, theta, eta, vt, ve, side = rows
    return Trajectory(time=np.asarray(time, dtype=float) / speed, theta=np.asarray(theta, dtype=float),
                      eta=np.asarray(eta, dtype=float), v_theta=np.asarray(vt, dtype=float) * speed,
                      v_eta=np.asarray(ve, dtype=float) * speed, side=np.asarray(side, dtype=np.int8),
                      start=np.array(start, dtype=float), table=table, method=method, note=note,
                      end_angle=float(end[0]) if len(time) else math.nan, end_turns=int(end[1]) if len(time) else 0)


def _check_turns(turns, m):
    """Whole turns to add to the start angles: an integer or one per state."""
    arr = np.broadcast_to(np.asarray(turns), (m,)) if np.ndim(turns) else np.full(m, turns, dtype=object)
    if not all(is_integer(t) for t in arr.tolist()) or any(abs(int(t)) > 2 ** 50 for t in arr.tolist()):
        raise InvalidArgument(f"`turns` must be whole numbers of turns (integers up to 2^50), got {turns!r}")
    return np.array([int(t) for t in arr.tolist()], dtype=np.int64)


def simulate(table: Billiard, state, collisions: int, method: str = "kernel", turns: int = 0) -> Trajectory:
    """Follow one orbit for ``collisions`` collisions.

    Parameters
    ----------
    table : Billiard
    state : array_like (4,)
        ``[theta, eta, v_theta, v_eta]``: inside the strip, or on a wall moving
        into the strip (e.g. :attr:`Trajectory.final_state`, to continue an orbit; for an
        exact continuation however long the orbit, use :meth:`Trajectory.resume_state`).
    collisions : int
        Number of collisions (> 0); the kernel holds them all (41 bytes each; refused up front
        when that exceeds half the available memory: use :func:`.orbitstats.orbit_statistics`
        to stream a long orbit).
    method : {"kernel", "reference"}
        The numba kernel, or the plain-numpy reference stepper (slow).
    turns : int
        Whole turns added to the start angle (θ = state θ + 2π·turns), as returned by
        :meth:`Trajectory.resume_state`; the reported θ continue the earlier piece's.

    Returns
    -------
    Trajectory

    Raises
    ------
    InvalidArgument
        For a table that is not a :class:`Billiard`, a state outside the strip (or on a wall moving out of
        it), a collision count that is not a positive integer or does not fit in memory, or an unknown method.

    Examples
    --------
    Unit speed at 37° to the walls from the middle of the strip: the orbit alternates between the walls,
    and the numba kernel and the plain-numpy reference stepper agree.

    >>> import numpy as np
    >>> from coinwall import Billiard, Wall, simulate
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> orbit = simulate(table, [0.0, 2.0, 0.6, 0.8], 10)
    >>> orbit
    Trajectory(10 collisions, kernel, t_end=23.23, bottom fraction 0.500)
    >>> reference = simulate(table, [0.0, 2.0, 0.6, 0.8], 10, method="reference")
    >>> bool(np.allclose(orbit.theta, reference.theta, atol=1e-9))
    True
    """
    _check_table(table)
    _check_method(method)
    collisions = _check_collisions(collisions)
    extra = _check_turns(turns, 1)[0]
    per = BYTES_PER_COLLISION if method == "kernel" else 400  # the reference keeps Python floats in lists
    check_memory(f"`collisions` = {collisions} ({per} bytes per collision)", float(per) * collisions)
    unit, speed, leaving, whole = _check_states(table, state)
    start = np.asarray(state, dtype=float).ravel()
    if method == "reference":
        rows, note = reference_run(table, unit[0], int(leaving[0]), collisions)
        cols = [list(c) for c in zip(*rows)] if rows else [[] for _ in range(6)]
        cols[1] = np.asarray(cols[1], dtype=float) + TWO_PI * float(whole[0] + extra)
        return _trajectory(table, start, speed[0], cols, note, method)
    rows, note, end = run(compiled(table), table, unit[0], int(leaving[0]), collisions, int(whole[0] + extra))
    return _trajectory(table, start, speed[0], rows, note, method, end)


def ensemble(table: Billiard, states, collisions: int, method: str = "kernel", workers=None, turns=0,
             device: str = "cpu") -> list:
    """Follow many orbits in parallel (numba threads over orbits, or one GPU thread per orbit).

    Each orbit is computed by the same sequential code whatever the number of
    threads, so the result does not depend on ``workers``; on the GPU it is the same kernel text compiled
    for CUDA, whose collisions agree with the CPU's to rounding (:mod:`.gpu`).

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
        Number of CPU threads (default: numba's default, all cores; not used on the GPU).
    turns : int or array_like of int
        Whole turns added to the start angles (see :func:`simulate`).
    device : {"cpu", "gpu"}
        Where the kernel runs: all CPU cores, or a CUDA GPU (``pip install 'coinwall[gpu]'``; the orbits go to
        it in groups that fit its memory).  The GPU pays off from about 10^4 orbits.

    Returns
    -------
    list of Trajectory
        All held in memory: 41 bytes per collision and orbit (refused up front when that exceeds half
        the available memory).

    Raises
    ------
    InvalidArgument
        Bad states or counts, an unknown ``method`` or ``device``, ``device="gpu"`` without a usable GPU, or
        ``method="reference"`` with ``device="gpu"``.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> orbits = ensemble(table, random_states(table, 3, seed=1), 5)
    >>> [len(o) for o in orbits]
    [5, 5, 5]
    """
    from .gpu import check_device

    _check_table(table)
    _check_method(method)
    check_device(device)
    if method == "reference" and device == "gpu":
        raise InvalidArgument("`method` = 'reference' runs on the CPU only; use method='kernel' with device='gpu'")
    collisions = _check_collisions(collisions)
    m = int(np.size(states) // 4) if np.ndim(states) else 0
    check_memory(f"{m} orbits × `collisions` = {collisions} ({BYTES_PER_COLLISION} bytes per collision)",
                 float(BYTES_PER_COLLISION) * collisions * max(m, 1))
    unit, speed, leaving, whole = _check_states(table, states, "states")
    starts = np.array(states, dtype=float).reshape(-1, 4)
    extra = _check_turns(turns, starts.shape[0])
    if method == "reference":
        return [simulate(table, s, collisions, method, turns=int(k)) for s, k in zip(starts, extra)]
    if workers is not None:
        workers = check_count("workers", workers)
    runs = run_many(compiled(table), table, unit, leaving, collisions, workers, whole + extra, device)
    return [_trajectory(table, starts[k], speed[k], rows, note, method, end)
            for k, (rows, note, end) in enumerate(runs)]
