"""Simple statistics of one long orbit: mean free time (against Santaló's formula) and the share of
bottom-wall collisions, accumulated over a run that is computed in pieces of bounded memory."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import json_number, safe_repr
from ...validation import check_count
from ..billiard.table import Billiard, simulate

__all__ = ["MAX_COLLISIONS", "OrbitStatistics", "orbit_statistics"]

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
