"""Simple statistics of one long orbit: mean free time (against Santaló's formula) and the share of
bottom-wall collisions, accumulated over a run that is computed in pieces of bounded memory."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import json_number, safe_repr
from ...validation import check_count
from ..billiard.table import Billiard, simulate

__all__ = ["MAX_COLLISIONS", "EnsembleStatistics", "OrbitStatistics", "ensemble_statistics", "orbit_statistics"]

CHUNK = 200_000  # collisions per kernel call: memory bounded by 41·CHUNK bytes (8 MB), a progress report after each
#: the longest orbit one call follows: ~10 days at 10^7 collisions/s (a year at the 3·10^5/s of the reference
#: stepper's worst case is not meant), and far inside int64 and float64's exact integers (2^53 ≈ 9·10^15)
MAX_COLLISIONS = 10 ** 13


class _Shares:
    """What one orbit's statistics and an ensemble's share: Santaló's mean free time of the table and the share of
    bottom collisions (from ``table``, ``bottom`` and ``collisions``)."""

    @property
    def santalo_mean_free_time(self) -> float:
        """Santaló's mean free time ``π·Area/Perimeter`` of the table (what an ergodic orbit's mean tends to)."""
        area, perimeter = self.table.area_perimeter()
        return math.pi * area / perimeter

    @property
    def bottom_fraction(self) -> float:
        """Share of the collisions that hit the bottom wall (nan without collisions)."""
        return self.bottom / self.collisions if self.collisions else math.nan


@dataclass(frozen=True, repr=False)
class OrbitStatistics(_Shares):
    """What one orbit of ``collisions`` collisions did, without keeping its collisions.

    Attributes
    ----------
    table : Billiard
    method : str
        ``"kernel"`` or ``"reference"``.
    start, final_state : ndarray (4,)
        ``[theta, eta, v_theta, v_eta]`` at the start and after the last collision (θ unwrapped:
        continuous with the start, ``final_angle + 2π·final_turns``).
    collisions : int
        Collisions computed (fewer than asked when the orbit stopped early: see ``note``).
    total_time : float
        Time of the last collision since the start (unit speed: the path length).
    bottom : int
        Collisions with the bottom wall.
    note : str
        Empty, or why the orbit stopped early (:attr:`Trajectory.note`).
    final_angle, final_turns : float, int
        The last contact angle reduced to [0, 2π), as the kernel carries it from piece to piece, and its
        whole turns (the pieces continue exactly: θ is never re-checked at its unwrapped value).

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall.forward.dynamics import orbit_statistics
    >>> stats = orbit_statistics(table, [0.0, 2.0, 0.6, 0.8], 1000)
    >>> stats.collisions
    1000
    """

    table: Billiard
    method: str
    start: np.ndarray
    final_state: np.ndarray
    collisions: int
    total_time: float
    bottom: int
    note: str = ""
    final_angle: float = math.nan
    final_turns: int = 0

    @property
    def mean_free_time(self) -> float:
        """Mean time between collisions (nan without collisions)."""
        return self.total_time / self.collisions if self.collisions else math.nan

    def to_dict(self) -> dict:
        """JSON-ready dictionary (nan becomes None)."""
        return {"H": self.table.H, "b0": self.table.b0, "method": self.method, "collisions": self.collisions,
                "mean_free_time": json_number(self.mean_free_time),
                "santalo_mean_free_time": self.santalo_mean_free_time,
                "bottom_fraction": json_number(self.bottom_fraction), "start": [float(x) for x in self.start],
                "final_state": [float(x) for x in self.final_state], "gap_min": self.table.gap_min,
                "gap_max": self.table.gap_max, "note": self.note}

    @safe_repr
    def __repr__(self) -> str:
        return (f"OrbitStatistics({self.collisions} collisions, {self.method}, mean free time "
                f"{self.mean_free_time:.6g}, bottom fraction {self.bottom_fraction:.4f}"
                f"{', note: ' + self.note if self.note else ''})")


def orbit_statistics(table: Billiard, state, collisions: int, method: str = "kernel", progress=None) -> OrbitStatistics:
    """Follow one orbit for ``collisions`` collisions in pieces of :data:`CHUNK`, keeping only its statistics.

    Memory is bounded by one piece (41 bytes per collision, 8 MB), whatever ``collisions``; time is not,
    so ``collisions`` is at most :data:`MAX_COLLISIONS` (10^13, days of work).  Each piece
    starts from the previous one's :meth:`~.billiard.Trajectory.resume_state` (θ mod 2π and its whole
    turns), so the pieces join exactly and a run of 10^8 collisions equals one long run.

    Parameters
    ----------
    table : Billiard
    state : array_like (4,)
        Start ``[theta, eta, v_theta, v_eta]`` (as for :func:`.billiard.simulate`).
    collisions : int
        Collisions to compute (> 0).
    method : {"kernel", "reference"}
    progress : callable, optional
        Called with the number of collisions computed by each piece.

    Returns
    -------
    OrbitStatistics

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall.forward.dynamics import orbit_statistics
    >>> orbit_statistics(table, [0.0, 2.0, 0.6, 0.8], 1000)
    OrbitStatistics(1000 collisions, kernel, mean free time 3.63717, bottom fraction 0.4970)
    """
    collisions = check_count("collisions", collisions, maximum=MAX_COLLISIONS)
    start = np.array(state, dtype=float).ravel()
    current, turns, final = start, 0, start.copy()
    angle = math.nan
    done, total_time, bottom, note = 0, 0.0, 0, ""
    while done < collisions:
        traj = simulate(table, current, min(CHUNK, collisions - done), method=method, turns=turns)
        got = len(traj)
        if got:
            total_time += float(traj.time[-1])
            bottom += int(np.count_nonzero(traj.side == 0))
            final = traj.final_state
            current, turns = traj.resume_state()
            angle = float(current[0])
        done += got
        if progress is not None:
            progress(got)
        if traj.note:
            note = traj.note
            break
    return OrbitStatistics(table=table, method=method, start=start, final_state=np.array(final, dtype=float),
                           collisions=done, total_time=total_time, bottom=bottom, note=note, final_angle=angle,
                           final_turns=int(turns))


@dataclass(frozen=True, repr=False)
class EnsembleStatistics(_Shares):
    """What many orbits of ``collisions`` collisions each did, without keeping their collisions.

    The mean free time of an ensemble is estimated so that it tends to Santaló's ``π·Area/Perimeter`` for any
    table, chaotic or not.  For starts drawn from the Liouville measure (:func:`~.billiard.random_states`) the
    motion is stationary, so the collisions of each orbit come at the constant mean rate ``P/(π·A)`` (the flux of
    the invariant measure through the walls: per unit length of wall and unit of phase volume, ∫cos ψ dψ = 2
    over the incoming directions, against the 2π of directions the volume A holds): the expected number of
    collisions in a *fixed* time window ``[0, T]`` is exactly ``T·P/(π·A)``.  Each group of orbits is read in
    the window ``T`` = the earliest time at which one of them made its first piece's last collision, and each
    orbit gives the rate ``r = N(T)/T``; the estimate is ``1/mean(r)`` with the standard error
    ``stderr(r)/mean(r)²``.  (The plain ratio total time / collisions over orbits of a fixed number of
    collisions would be the *arithmetic* mean of the orbits' free times, which on a table with islands is not
    Santaló's harmonic mean, and it counts each start's first, partial flight.)

    Attributes
    ----------
    table : Billiard
    device : str
    orbits : int
    collisions : int
        Collisions computed over all orbits.
    total_time : float
        Sum of the orbits' times of their last collisions.
    bottom : int
        Collisions with the bottom wall.
    mean_free_time, mean_free_time_stderr : float
        The estimate above and its standard error (nan with fewer than two orbits with collisions).
    notes : tuple of str
        Orbits that stopped early, and why.

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import random_states
    >>> from coinwall.forward.dynamics import ensemble_statistics
    >>> ensemble_statistics(table, random_states(table, 20, seed=1), 50)
    EnsembleStatistics(20 orbits, 1000 collisions on the cpu, mean free time 2.90875 ± 0.33)
    """

    table: Billiard
    device: str
    orbits: int
    collisions: int
    total_time: float
    bottom: int
    mean_free_time: float
    mean_free_time_stderr: float
    notes: tuple = ()

    def to_dict(self) -> dict:
        """JSON-ready dictionary (nan becomes None)."""
        return {"H": self.table.H, "b0": self.table.b0, "device": self.device, "orbits": self.orbits,
                "collisions": self.collisions, "mean_free_time": json_number(self.mean_free_time),
                "mean_free_time_stderr": json_number(self.mean_free_time_stderr),
                "santalo_mean_free_time": self.santalo_mean_free_time,
                "bottom_fraction": json_number(self.bottom_fraction), "gap_min": self.table.gap_min,
                "gap_max": self.table.gap_max, "notes": list(self.notes)}

    @safe_repr
    def __repr__(self) -> str:
        return (f"EnsembleStatistics({self.orbits} orbits, {self.collisions} collisions on the {self.device}, mean "
                f"free time {self.mean_free_time:.6g} ± {self.mean_free_time_stderr:.2g})")


def _piece(table, unit, turns, leaving, n, speed, window, device, workers) -> dict:
    """One piece of :func:`ensemble_statistics`: ``n`` collisions from each unit-speed state, reduced per orbit
    (the keys of :func:`.billiard.gpu.run_statistics`, which does the same on the GPU without bringing the
    collisions back)."""
    if device == "gpu":
        from ..billiard.gpu import run_statistics

        return run_statistics(table, unit, turns, leaving, n, speed, window)
    from ..billiard.kernel import _run_threads, compiled

    m = unit.shape[0]
    rows = [np.empty((m, n)) for _ in range(5)] + [np.empty((m, n), dtype=np.int8)]
    done, status, last = np.zeros(m, dtype=np.int64), np.zeros(m, dtype=np.int64), np.empty((m, 2))
    _run_threads(compiled(table), table, unit, turns, leaving, n, workers, rows, done, status, last)
    valid = np.arange(n)[None, :] < done[:, None]
    at = np.maximum(done - 1, 0)
    final = np.column_stack([rows[c][np.arange(m), at] for c in (0, 2, 3, 4)])
    final[done == 0] = 0.0
    out = {"done": done, "status": status, "last": last, "final": final,
           "side": np.where(done > 0, rows[5][np.arange(m), at], -1).astype(np.int8),
           "bottom": np.count_nonzero(valid & (rows[5] == 0), axis=1), "counts": None}
    limit = None if window is None else window(final[:, 0], done)
    if limit is not None:
        out["counts"] = np.count_nonzero(valid & (rows[0] / speed[:, None] <= limit), axis=1)
    return out


def ensemble_statistics(table: Billiard, states, collisions: int, device: str = "cpu", workers=None,
                        progress=None) -> EnsembleStatistics:
    """Follow each of ``states`` for ``collisions`` collisions, in bounded memory, keeping only statistics.

    Orbits go in groups (2·10^6 collisions held at once on the CPU; on the GPU up to 2^28, held there,
    :func:`~.billiard.gpu.group_collisions` with ``on_host=False``, so that a launch keeps it busy), each group
    in pieces continued exactly (as :meth:`~.billiard.Trajectory.resume_state` continues an orbit) when its
    orbits are longer than a group holds.  Each piece is reduced to a few numbers per orbit where it was computed: on the GPU the
    collisions never leave it (:func:`~.billiard.gpu.run_statistics`), on the CPU they are read as arrays.

    Parameters
    ----------
    table : Billiard
    states : array_like (m, 4)
        Start states; for the mean free time to estimate Santaló's, Liouville-random
        (:func:`~.billiard.random_states`).
    collisions : int
        Collisions per orbit.
    device : {"cpu", "gpu"}
        Where the kernel runs (:func:`~.billiard.ensemble`).
    workers : int, optional
        CPU threads.
    progress : callable, optional
        Called with the number of collisions each piece computed.

    Returns
    -------
    EnsembleStatistics

    Raises
    ------
    InvalidArgument
        Bad states or counts, or ``device="gpu"`` without a usable GPU.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics.billiard.table import random_states
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> stats = ensemble_statistics(table, random_states(table, 20, seed=1), 50)
    >>> stats.orbits, stats.collisions
    (20, 1000)
    """
    from ..billiard.gpu import check_device, group_collisions
    from ..billiard.kernel import NOTES
    from ..billiard.table import _check_states

    check_device(device)
    collisions = check_count("collisions", collisions, maximum=MAX_COLLISIONS)
    starts = np.array(states, dtype=float).reshape(-1, 4)
    m = starts.shape[0]
    hold = CHUNK * 10 if device == "cpu" else group_collisions(on_host=False)
    piece = min(collisions, hold)
    group = max(1, min(m, hold // piece))
    rates, notes = [], []
    total_time, done_all, bottom = 0.0, 0, 0
    for first in range(0, m, group):
        unit, speed, leaving, turns = _check_states(table, starts[first:first + group], "states")
        alive = np.arange(unit.shape[0])
        clock = np.zeros(unit.shape[0])
        left = collisions
        while left > 0 and alive.size:
            n = min(piece, left)
            scale = speed[alive]
            window = []  # the first piece: the counts in the window [0, T] (class docstring)

            def earliest(last_time, done, scale=scale, window=window):
                ends = last_time[done > 0] / scale[done > 0]
                if ends.size and ends.min() > 0.0:
                    window.append(float(ends.min()))
                    return window[0]
                return None

            got = _piece(table, unit, turns, leaving, n, scale, earliest if left == collisions else None, device,
                         workers)
            done = got["done"]
            done_all += int(done.sum())
            bottom += int(got["bottom"].sum())
            clock[alive] += np.where(done > 0, got["final"][:, 0] / scale, 0.0)
            if got["counts"] is not None:
                rates.extend((got["counts"] / window[0]).tolist())
            stopped = (got["status"] != 0) | (done < n)
            for k in np.flatnonzero(stopped):
                notes.append(f"orbit {first + alive[k]}: {NOTES.get(int(got['status'][k]), '') or 'stopped early'}")
            keep = ~stopped
            if progress is not None:
                progress(int(done.sum()))
            left -= n
            alive = alive[keep]
            # the next piece starts on the last collision, exactly as ensemble() continues Trajectory.resume_state:
            # θ mod 2π with its turns, the velocity scaled back by the start speed and made unit again
            v = got["final"][keep, 2:] * scale[keep, None]
            unit = np.column_stack([got["last"][keep, 0], got["final"][keep, 1],
                                    v / np.hypot(v[:, 0], v[:, 1])[:, None]])
            turns = got["last"][keep, 1].astype(np.int64)
            leaving = got["side"][keep].astype(np.int64)
        total_time += float(clock.sum())
    rate = np.array(rates)
    mean = float(rate.mean()) if rate.size else math.nan
    stderr = float(rate.std(ddof=1) / math.sqrt(rate.size)) if rate.size > 1 else math.nan
    return EnsembleStatistics(table=table, device=device, orbits=m, collisions=done_all, total_time=total_time,
                              bottom=bottom, mean_free_time=1.0 / mean if mean > 0 else math.nan,
                              mean_free_time_stderr=stderr / mean ** 2 if mean > 0 else math.nan,
                              notes=tuple(notes))
