"""The result of following one orbit of the billiard: its collisions, in order (:class:`Trajectory`).

:func:`~coinwall.forward.dynamics.billiard.table.simulate` and
:func:`~coinwall.forward.dynamics.billiard.table.ensemble` return it; :mod:`.table`, which holds the table it
refers to, imports it from here (``from coinwall.forward.dynamics.billiard.table import Trajectory`` works).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...angles import TWO_PI
from ...display import safe_repr

__all__ = ["Trajectory"]


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
    end_angle, end_turns : float, int
        The last contact angle as the kernel holds it: reduced to [0, 2π), and its whole turns
        (``theta[-1] ≈ end_angle + 2π·end_turns``).  :meth:`resume_state` continues from these exactly;
        the unwrapped ``theta[-1]`` loses precision as it grows (one ulp is 3.6e-12 at 2e4 rad).

    Examples
    --------
    >>> from coinwall import Billiard, Wall, simulate
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> orbit = simulate(table, [0.0, 2.0, 0.6, 0.8], 10)
    >>> len(orbit), orbit.side.tolist()
    (10, [1, 0, 1, 0, 1, 0, 1, 0, 1, 0])
    >>> state, turns = orbit.resume_state()      # continue the orbit exactly
    >>> len(simulate(table, state, 5, turns=turns))
    5
    """

    time: np.ndarray
    theta: np.ndarray
    eta: np.ndarray
    v_theta: np.ndarray
    v_eta: np.ndarray
    side: np.ndarray
    start: np.ndarray
    table: Billiard  # noqa: F821 (a name only: .table, which defines Billiard, imports this module)
    method: str = "kernel"
    note: str = ""
    end_angle: float = math.nan
    end_turns: int = 0

    def __len__(self) -> int:
        return int(self.time.size)

    @property
    def final_state(self) -> np.ndarray:
        """State right after the last collision (start of a continuation); the start if there is none."""
        if self.time.size == 0:
            return self.start.copy()
        return np.array([self.theta[-1], self.eta[-1], self.v_theta[-1], self.v_eta[-1]])

    def resume_state(self):
        """``(state, turns)``: the state after the last collision with θ in [0, 2π) exactly as the kernel
        holds it, and the whole turns to add; ``simulate(table, state, n, turns=turns)`` continues the orbit
        exactly however long it has run (and reports the same unwrapped θ)."""
        if self.time.size == 0 or not math.isfinite(self.end_angle):
            state = self.final_state
            turns = math.floor(state[0] / TWO_PI)
            state[0] -= turns * TWO_PI
            return state, int(turns)
        return (np.array([self.end_angle, self.eta[-1], self.v_theta[-1], self.v_eta[-1]]), int(self.end_turns))

    @safe_repr
    def __repr__(self) -> str:
        n = self.time.size
        if n == 0:
            return f"Trajectory(0 collisions{', ' + self.note if self.note else ''})"
        bottom = float(np.mean(self.side == 0))
        extra = f", note: {self.note}" if self.note else ""
        return (f"Trajectory({n} collisions, {self.method}, t_end={self.time[-1]:.6g}, "
                f"bottom fraction {bottom:.3f}{extra})")
