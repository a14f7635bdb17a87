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


@dataclass(frozen=True, repr=False)
class OrbitStatistics:
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

    @property
    def santalo_mean_free_time(self) -> float:
        """Santaló's mean free time ``π·Area/Perimeter`` of the table (what an ergodic orbit's mean tends to)."""
        area, perimeter = self.table.area_perimeter()
        return math.pi * area / perimeter

    @property
    def bottom_fraction(self) -> float:
        """Share of the collisions that hit the bottom wall (nan without collisions)."""
        return self.bottom / self.collisions if self.collisions else math.nan

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
class EnsembleStatistics:
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

    @property
    def santalo_mean_free_time(self) -> float:
        """Santaló's mean free time ``π·Area/Perimeter`` of the table."""
        area, perimeter = self.table.area_perimeter()
        return math.pi * area / perimeter

    @property
    def bottom_fraction(self) -> float:
        """Share of the collisions that hit the bottom wall (nan without collisions)."""
        return self.bottom / self.collisions if self.collisions else math.nan

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


def ensemble_statistics(table: Billiard, states, collisions: int, device: str = "cpu", workers=None,
                        progress=None) -> EnsembleStatistics:
    """Follow each of ``states`` for ``collisions`` collisions, in bounded memory, keeping only statistics.

    Orbits go in groups (2·10^6 collisions held at once on the CPU; on the GPU
    :func:`~.billiard.gpu.group_collisions`, so that a launch keeps it busy), each group in pieces continued
    exactly (:meth:`~.billiard.Trajectory.resume_state`) when its orbits are longer than a group holds.

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
    from ..billiard.table import ensemble

    check_device(device)
    collisions = check_count("collisions", collisions, maximum=MAX_COLLISIONS)
    starts = np.array(states, dtype=float).reshape(-1, 4)
    m = starts.shape[0]
    hold = CHUNK * 10 if device == "cpu" else group_collisions()
    piece = min(collisions, hold)
    group = max(1, min(m, hold // piece))
    rates, notes = [], []
    total_time, done_all, bottom = 0.0, 0, 0
    for first in range(0, m, group):
        current, turns = starts[first:first + group], np.zeros(min(group, m - first), dtype=np.int64)
        alive = np.arange(current.shape[0])
        clock = np.zeros(current.shape[0])
        left = collisions
        while left > 0 and alive.size:
            trajs = ensemble(table, current, min(piece, left), workers=workers, turns=turns, device=device)
            if left == collisions:  # the first piece: the counts in the window [0, T] (class docstring)
                ends = [t.time[-1] for t in trajs if len(t)]
                window = min(ends) if ends else 0.0
                if window > 0.0:
                    rates += [np.count_nonzero(t.time <= window) / window for t in trajs]
            keep, nxt, nxt_turns = [], [], []
            for k, traj in zip(alive, trajs):
                got = len(traj)
                done_all += got
                bottom += int(np.count_nonzero(traj.side == 0))
                if got:
                    clock[k] += float(traj.time[-1])
                if traj.note or got < min(piece, left):
                    notes.append(f"orbit {first + k}: {traj.note or 'stopped early'}")
                    continue
                state, whole = traj.resume_state()
                keep.append(k), nxt.append(state), nxt_turns.append(whole)
            if progress is not None:
                progress(sum(len(t) for t in trajs))
            del trajs
            left -= min(piece, left)
            alive = np.array(keep, dtype=np.int64)
            if alive.size:
                current, turns = np.array(nxt), np.array(nxt_turns, dtype=np.int64)
        total_time += float(clock.sum())
    rate = np.array(rates)
    mean = float(rate.mean()) if rate.size else math.nan
    stderr = float(rate.std(ddof=1) / math.sqrt(rate.size)) if rate.size > 1 else math.nan
    return EnsembleStatistics(table=table, device=device, orbits=m, collisions=done_all, total_time=total_time,
                              bottom=bottom, mean_free_time=1.0 / mean if mean > 0 else math.nan,
                              mean_free_time_stderr=stderr / mean ** 2 if mean > 0 else math.nan,
                              notes=tuple(notes))
