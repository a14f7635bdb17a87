"""Poincaré section of the billiard at the bottom wall: contact angle θ_c against angle of incidence φ_c.

The section of the paper's figures 2 and 3 (section III): at every collision
with the *bottom* wall ``η = b0 + b(θ)`` record

* ``θ_c`` — the contact angle, reduced mod 2π to [0, 2π);
* ``φ_c`` — the angle between the velocity and the local wall normal,
  in (−π/2, π/2).

Convention for φ_c.  With the unit tangent ``T = (1, b')/√(1+b'²)`` and the
unit normal pointing into the strip ``N = (−b', 1)/√(1+b'²)`` at the contact
point, ``φ_c = atan2(v·T, v·N)`` for the velocity ``v`` *after* the
reflection.  Specular reflection keeps ``v·T`` and flips ``v·N``, so |φ_c| is
both the angle of incidence and the angle of reflection, and its sign is the
direction of the motion along the wall (φ_c > 0: θ increasing).  ``sin φ_c``
is the Birkhoff momentum conjugate to arc length, so the section is the
collision map in (almost) canonical coordinates.  For a flat wall (the circle,
ε = 0) ``v_θ`` is conserved and every orbit is a horizontal line φ_c = const:
the whispering-gallery orbits (a fast-spinning body) are the lines near
φ_c = ±π/2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...angles import TWO_PI
from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_memory
from ..billiard.table import Billiard, random_states, simulate

__all__ = ["PoincareSection", "incidence_angle", "poincare_section"]

_CHUNK_COLLISIONS = 2_000_000   # collisions (41 bytes each) held in memory at once
BYTES_PER_POINT = 24            # θ_c, φ_c and the orbit index of one point of the section


def incidence_angle(table: Billiard, theta, v_theta, v_eta, side=0):
    """Signed angle φ between the post-collision velocity and the inward wall normal.

    Parameters
    ----------
    table : Billiard
    theta, v_theta, v_eta : array_like
        Contact angle and velocity after the reflection.
    side : int or array_like of int
        0 = bottom wall, 1 = top wall (the top wall's inward normal points down;
        its tangent still points towards increasing θ).

    Returns
    -------
    ndarray
        φ in [−π/2, π/2] (module docstring for the convention).

    Examples
    --------
    On the flat bottom at θ = 0 (``b'(0) = 0``) a velocity (0.6, 0.8) makes the angle atan(0.6/0.8) with
    the normal:

    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall.forward import incidence_angle
    >>> round(float(incidence_angle(table, 0.0, 0.6, 0.8, 0)), 12)
    0.643501108793
    """
    theta = np.asarray(theta, dtype=float)
    top = np.broadcast_to(np.asarray(side) != 0, theta.shape)
    # only the wall actually hit is needed: the lower wall's slope b'(θ), the upper wall's −b'(θ+π).
    # One derivatives call on the contact angles, shifted by π where the top was hit, instead of both
    # walls at every point (the wall evaluation is most of the cost for an expression wall)
    slope = table.wall.derivatives(np.where(top, theta + math.pi, theta))[1]
    slope = np.where(top, -slope, slope)
    sign = np.where(top, -1.0, 1.0)
    tangential = np.asarray(v_theta) + slope * np.asarray(v_eta)
    normal = sign * (np.asarray(v_eta) - slope * np.asarray(v_theta))
    return np.arctan2(tangential, normal)


@dataclass(frozen=True, repr=False)
class PoincareSection:
    """Bottom-wall Poincaré section of several orbits.

    Attributes
    ----------
    theta : ndarray (m,)
        Contact angle θ_c mod 2π, in [0, 2π).
    phi : ndarray (m,)
        Angle of incidence φ_c to the local normal, in [−π/2, π/2]
        (module docstring for the sign).
    orbit : ndarray (m,) of int
        Index of the orbit each point belongs to (0 … orbits−1).
    starts : ndarray (orbits, 4)
        Start states ``[theta, eta, v_theta, v_eta]``.
    collisions : int
        Collisions (either wall) followed per orbit.
    table : Billiard
    notes : tuple of str
        One entry per orbit that stopped early (``"orbit k: <why>"``).

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import poincare_section
    >>> section = poincare_section(table, orbits=4, collisions=100, seed=0)
    >>> section.theta.shape == section.phi.shape == section.orbit.shape, sorted(set(section.orbit.tolist()))
    (True, [0, 1, 2, 3])
    """

    theta: np.ndarray
    phi: np.ndarray
    orbit: np.ndarray
    starts: np.ndarray
    collisions: int
    table: Billiard
    notes: tuple = ()

    @property
    def orbits(self) -> int:
        """Number of orbits."""
        return int(self.starts.shape[0])

    def to_dict(self) -> dict:
        """JSON-ready dictionary (lists of floats)."""
        return {"H": self.table.H, "b0": self.table.b0, "orbits": self.orbits, "collisions": self.collisions,
                "convention": "theta_c = contact angle mod 2pi (bottom wall); phi_c = atan2(v.T, v.N) after "
                              "reflection, N inward normal, T tangent towards increasing theta",
                "theta": self.theta.tolist(), "phi": self.phi.tolist(), "orbit": self.orbit.tolist(),
                "starts": self.starts.tolist(), "notes": list(self.notes)}

    def to_csv(self) -> str:
        """The points as CSV text: header ``theta_c,phi_c,orbit``, angles in radians to full precision."""
        import io

        text = io.StringIO()
        text.write("theta_c,phi_c,orbit\n")
        np.savetxt(text, np.column_stack([self.theta, self.phi, self.orbit]), delimiter=",",
                   fmt=["%.17g", "%.17g", "%d"])
        return text.getvalue()

    def plot(self, ax=None, markersize=0.6, title=None, name=None):
        """Scatter φ_c against θ_c (radians, ticks at multiples of π), one colour per orbit.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; default a new figure (Agg backend, no display needed).
        markersize : float
            Marker area in points² (as ``scatter``'s ``s``).
        title : str, optional
            Default: the wall (``name`` as the user wrote it, else its description and parameters), the wall
            distance and the number of orbits and collisions.
        name : str, optional
            The wall's name for the default title (``case:ellipse-0.55``).

        Returns
        -------
        matplotlib Axes
            Its ``.figure`` is the Figure (e.g. for :func:`~coinwall.forward.formats.figure.figure_bytes`).
        """
        import matplotlib.pyplot as plt

        from ...formats.figure import axes_or_new
        from ...formats.style import house_style, wall_label

        with house_style():
            ax, own = axes_or_new(ax, (7, 5))
            cmap = plt.get_cmap("tab20" if self.orbits <= 20 else "turbo")
            # one marker-only line per orbit rather than one scatter with a colour per point: Agg stamps a
            # line's identical markers from one cached raster, ~10x faster for millions of points, and no
            # (points, 4) colour array is built; orbits are drawn in order, as the scatter drew them
            size = math.sqrt(markersize)
            cuts = np.flatnonzero(np.diff(self.orbit)) + 1
            runs = zip(np.r_[0, cuts], np.r_[cuts, self.orbit.size]) if self.orbit.size else ()
            for first, last in runs:
                k = int(self.orbit[first])
                colour = cmap(k % 20 if self.orbits <= 20 else k / max(self.orbits - 1, 1))
                ax.plot(self.theta[first:last], self.phi[first:last], linestyle="none", marker="o",
                        markersize=size, markeredgewidth=0, color=colour, rasterized=True)
            ax.grid(False)  # the points are the picture
            ax.set_xlim(0, TWO_PI)
            ax.set_ylim(-0.5 * math.pi, 0.5 * math.pi)
            ax.set_xticks([k * 0.5 * math.pi for k in range(5)], ["0", "π/2", "π", "3π/2", "2π"])
            ax.set_yticks([k * 0.25 * math.pi for k in range(-2, 3)], ["−π/2", "−π/4", "0", "π/4", "π/2"])
            ax.set_xlabel("contact angle θ_c (rad)")
            ax.set_ylabel("angle of incidence φ_c (rad)")
            ax.set_title(title or f"bottom-wall Poincaré section of {wall_label(self.table.wall, name)}\n"
                                  f"H = {self.table.H:g} κ, {self.orbits} orbits × {self.collisions} collisions "
                                  f"({self.theta.size} points, one colour per orbit)")
            if own:
                ax.figure.tight_layout()
        return ax

    @safe_repr
    def __repr__(self) -> str:
        return (f"PoincareSection({self.theta.size} points, {self.orbits} orbits × {self.collisions} collisions, "
                f"H={self.table.H:g}{', ' + str(len(self.notes)) + ' stopped early' if self.notes else ''})")


def poincare_section(table: Billiard, orbits: int = 60, collisions: int = 2000, seed=None, states=None,
                     workers=None, progress=None, device: str = "cpu") -> PoincareSection:
    """Bottom-wall Poincaré section of ``orbits`` orbits.

    The orbits are followed in groups of at most ``_CHUNK_COLLISIONS`` collisions in all (on the GPU
    :func:`~coinwall.forward.dynamics.billiard.gpu.group_collisions`; an orbit longer than that alone, in
    pieces continued exactly on the CPU), so memory stays bounded by 82 MB (GPU: that group) plus the section's
    points (24 bytes each, at most one per collision); a request whose points would not fit in half the
    available memory is refused before any work.  Every orbit is computed from its own start state by the
    same code, so the result does not depend on the grouping.

    Parameters
    ----------
    table : Billiard
    orbits : int
        Number of orbits (ignored when ``states`` is given).
    collisions : int
        Collisions (either wall) per orbit; about half are bottom collisions.
    seed : int, optional
        Seed of :func:`~coinwall.forward.dynamics.billiard.table.random_states` (Liouville-uniform starts).
    states : array_like (k, 4), optional
        Explicit start states instead of random ones.
    workers : int, optional
        CPU threads for :func:`~coinwall.forward.dynamics.billiard.table.ensemble`.
    progress : callable, optional
        Called with the number of orbits finished so far, after each group.
    device : {"cpu", "gpu"}
        Where the orbits are computed (:func:`~coinwall.forward.dynamics.billiard.table.ensemble`); on the GPU
        in groups of up to :func:`~coinwall.forward.dynamics.billiard.gpu.group_collisions` collisions.

    Returns
    -------
    PoincareSection

    Raises
    ------
    InvalidArgument
        For explicit ``states`` that hold no state, states outside the strip, or a section that would not
        fit in memory.

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import poincare_section
    >>> section = poincare_section(table, orbits=4, collisions=100, seed=0)
    >>> section
    PoincareSection(201 points, 4 orbits × 100 collisions, H=4)
    >>> bool(abs(section.phi).max() <= 3.1416 / 2)      # incidence angles in [−π/2, π/2]
    True
    """
    from ..billiard.gpu import check_device, group_collisions

    check_device(device)
    chunk = _CHUNK_COLLISIONS if device == "cpu" else group_collisions()
    collisions = check_count("collisions", collisions)
    if workers is not None:
        workers = check_count("workers", workers)
    count = check_count("orbits", orbits) if states is None else int(np.size(states) // 4)
    check_memory(f"{count} orbits × `collisions` = {collisions} (up to {BYTES_PER_POINT} bytes per collision for "
                 f"the section's points)", float(BYTES_PER_POINT) * count * collisions + 41.0 * chunk)
    if states is None:
        states = random_states(table, count, seed)
    starts = np.array(states, dtype=float).reshape(-1, 4)
    n = starts.shape[0]
    if n == 0:
        raise InvalidArgument("`states` must hold at least one start state [theta, eta, v_theta, v_eta], got none")
    group = max(1, min(n, chunk // collisions))
    thetas, phis, counts, notes = [], [], [], []
    for first in range(0, n, group):
        if collisions > chunk:  # one long orbit, in pieces (on the CPU: one orbit is one thread)
            theta, phi, note = _long_orbit(table, starts[first], collisions)
            thetas.append(theta)
            phis.append(phi)
            counts.append(theta.size)
            if note:
                notes.append(f"orbit {first}: {note}")
            if progress is not None:
                progress(first + 1)
            continue
        theta, v_theta, v_eta, got, note = _bottom_collisions(table, starts[first:first + group], collisions, workers,
                                                             device)
        counts.extend(got.tolist())
        notes.extend(f"orbit {first + k}: {why}" for k, why in note)
        # one call per group rather than per orbit: the wall is evaluated in blocks
        phis.append(incidence_angle(table, theta, v_theta, v_eta))
        thetas.append(np.mod(theta, TWO_PI))
        del theta, v_theta, v_eta
        if progress is not None:
            progress(min(n, first + group))
    # concatenate one field at a time, freeing its pieces, so the peak is the section plus one field
    theta = np.concatenate(thetas)
    del thetas
    phi = np.concatenate(phis)
    del phis
    orbit = np.repeat(np.arange(n, dtype=np.int64), counts)
    return PoincareSection(theta=theta, phi=phi, orbit=orbit, starts=starts, collisions=collisions, table=table,
                           notes=tuple(notes))


def _bottom_collisions(table, starts, collisions, workers, device):
    """The bottom-wall collisions of a group of orbits, as :func:`ensemble` would give them (θ unwrapped, the velocity
    at the start speed), read from the kernel's arrays without a Trajectory per orbit; on the GPU only θ, v_θ, v_η and
    the wall come back (25 of the 41 bytes of a collision).  Returns θ, v_θ, v_η, the count per orbit and the notes
    ``(orbit in the group, why it stopped)``."""
    from ..billiard.kernel import NOTES, _run_threads, compiled
    from ..billiard.table import _check_states

    unit, speed, leaving, turns = _check_states(table, starts, "states")
    m = unit.shape[0]
    keep = (False, True, False, True, True, True)  # time and η are not read
    rows = [np.empty((m, collisions), dtype=np.int8 if c == 5 else float) if keep[c] or device == "cpu" else None
            for c in range(6)]
    done, status, last = np.zeros(m, dtype=np.int64), np.zeros(m, dtype=np.int64), np.empty((m, 2))
    if device == "gpu":
        from ..billiard.gpu import run_into

        run_into(table, unit, turns, leaving, collisions, rows, done, status, last)
    else:
        _run_threads(compiled(table), table, unit, turns, leaving, collisions, workers, rows, done, status, last)
    bottom = (np.arange(collisions)[None, :] < done[:, None]) & (rows[5] == 0)
    scale = np.broadcast_to(speed[:, None], bottom.shape)[bottom]
    notes = [(k, NOTES.get(int(status[k]), "")) for k in np.flatnonzero(status != 0)]
    return (rows[1][bottom], rows[3][bottom] * scale, rows[4][bottom] * scale, np.count_nonzero(bottom, axis=1),
            notes)


def _long_orbit(table, start, collisions):
    """Bottom-wall points (θ_c mod 2π, φ_c) of one orbit longer than a group, followed in pieces of
    ``_CHUNK_COLLISIONS`` continued exactly (:meth:`~.billiard.Trajectory.resume_state`); and its note."""
    thetas, phis = [], []
    state, turns, done, note = start, 0, 0, ""
    while done < collisions:
        traj = simulate(table, state, min(_CHUNK_COLLISIONS, collisions - done), turns=turns)
        bottom = traj.side == 0
        thetas.append(np.mod(traj.theta[bottom], TWO_PI))
        phis.append(incidence_angle(table, traj.theta[bottom], traj.v_theta[bottom], traj.v_eta[bottom]))
        done += len(traj)
        note = traj.note
        if note or not len(traj):
            break
        state, turns = traj.resume_state()
        del traj, bottom
    return np.concatenate(thetas), np.concatenate(phis), note
