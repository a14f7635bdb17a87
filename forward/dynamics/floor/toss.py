"""The toss that lands: the outcome of each launch, basin maps over the launch velocity and spin, and fractions.

A body (its wall b(θ), offset b0) is launched from rest orientation ``theta0`` with its centre of mass at
height ``height`` (κ, above the floor's reference η = 0), upward velocity ``v0`` (κ/s) and spin ``ω0``
(θ̇, rad/s), in the field g (κ/s²), and bounces with restitution e (and slides, rolls and rocks with friction
μ) until its outcome is decided (:mod:`.field`: energy below its valley's barrier, or at rest), or, with
``catch``, until it first meets the floor (Keller's coin, caught on landing).  :func:`toss_outcomes` gives
each launch's rest state by name, when and after how many impacts it was decided, or why it was not
(:mod:`.hand`, with :func:`.hand.launch_spread`, launches drawn from a Gaussian hand).  :func:`basin_map` computes
the outcome on a grid of (v0, ω0) with the number of floor impacts it took (the picture of Vulović and
Prange, PRA 33, 576 (1986): bands of heads and tails between hyperbolas ω0·v0 ≈ const, thinner as the
energy grows); :func:`.hand.heads_fraction` the probability of each outcome under a Gaussian spread of the
launch, with its standard error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count
from .field import FIELD_NOTES, STATUS, FieldTable, field_run_many

__all__ = ["BasinMap", "basin_map", "launch_states", "plot_basins", "reason_lines", "undecided_counts"]

# orbits per kernel call (the progress bar moves once per chunk); on a GPU 2^18, enough to keep it busy
_CHUNK = {"cpu": 4096, "gpu": 262_144}
UNDECIDED = -1
_PALETTE = ["#c8553d", "#2f6690", "#f2a541", "#3a7d44", "#8e6c8a", "#6b9080"]  # rest states' colours


def _default_theta0(table: FieldTable) -> float:
    """The rest angle the toss starts from: heads' minimum for a coin, else the first valley's."""
    land = table.landscape
    if "heads" in land.names:
        return float(land.minima[land.names.index("heads")])
    return float(land.minima[0])


def launch_states(table: FieldTable, v0, omega0, height: float, theta0: float | None = None) -> np.ndarray:
    """States ``[θ0, height, ω0, v0]`` for arrays of launch velocities and spins (broadcast together)."""
    if not isinstance(table, FieldTable):
        raise InvalidArgument(f"`table` must be a FieldTable, got {type(table).__name__}")
    if table.g <= 0:
        raise InvalidArgument("a toss needs a field: `g` must be positive")
    land = table.landscape
    if land.names and np.all(np.isinf(land.barriers)):
        # one valley without a barrier: the wall is flat (a disc), every orientation is a rest state, and the
        # outcome named after its one "minimum" would be made up
        raise InvalidArgument(f"wall {table.wall.description!r} has no valleys (b is constant within rounding): a "
                              "body resting on it can rest at any angle, so a toss has no outcome")
    theta0 = _default_theta0(table) if theta0 is None else float(theta0)
    if not math.isfinite(theta0):
        raise InvalidArgument(f"`theta0` must be a finite angle, got {theta0!r}")
    height = float(height)
    low = float(table.lower(np.array([theta0]))[0])
    if not (math.isfinite(height) and low + 1e3 * table.tol < height <= 1e6):
        raise InvalidArgument(f"`height` = {height!r} puts the body into the floor: at θ0 = {theta0:.6g} its centre "
                              f"must be above {low:.6g} and at most 1e6 (κ)")
    if table.ceiling and not height < float(table.upper(np.array([theta0]))[0]) - 1e3 * table.tol:
        raise InvalidArgument(f"`height` = {height!r} is above the ceiling at θ0 = {theta0:.6g}")
    v, w = np.broadcast_arrays(np.asarray(v0, dtype=float), np.asarray(omega0, dtype=float))
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(w))):
        raise InvalidArgument("the launch velocities and spins must be finite numbers")
    n = v.size
    return np.column_stack([np.full(n, theta0), np.full(n, height), w.ravel(), v.ravel()])


def _run_chunks(table, states, impacts, catch, workers, progress, slide=False, device="cpu") -> dict:
    """The kernel's summaries of every state, in chunks (the progress bar moves once per chunk)."""
    from .slide import settle_many

    chunk = _CHUNK.get(device, 1)  # (field_run_many checks the device)
    n = states.shape[0]
    keys = ("status", "valley", "floor_impacts", "impacts", "time")
    out = {key: np.empty(n, dtype=float if key in ("time", "theta") else np.int64) for key in keys + ("theta",)}
    for lo in range(0, n, chunk):
        hi = min(n, lo + chunk)
        if slide:
            part = settle_many(table, states[lo:hi], impacts, catch=catch, workers=workers, device=device)
        else:
            part = field_run_many(table, states[lo:hi], impacts, catch=catch, workers=workers, device=device)
        for key in keys:
            out[key][lo:hi] = part[key]
        out["theta"][lo:hi] = part["final"][:, 0]
        if progress is not None:
            progress(hi - lo)
    return out


def _outcomes(table, states, impacts, catch, workers, progress, slide=False, device="cpu"):
    """Outcome (valley index, or UNDECIDED), floor impacts and status per state, in chunks."""
    out = _run_chunks(table, states, impacts, catch, workers, progress, slide, device)
    decided = np.isin(out["status"], (1, 2, 3))
    return np.where(decided, out["valley"], UNDECIDED), out["floor_impacts"], out["status"]


def undecided_counts(status) -> dict:
    """How many tosses are undecided, by reason: the kernel's status words of :data:`.field.STATUS`.

    Parameters
    ----------
    status : array_like of int
        The kernel's status codes, one per toss.

    Returns
    -------
    dict
        ``{status word: count}`` for the undecided statuses present, most frequent first.

    Examples
    --------
    >>> undecided_counts([1, 4, 4, 0, 3])
    {'slides': 2, 'bounces': 1}
    """
    values, counts = np.unique(np.asarray(status, dtype=np.int64), return_counts=True)
    found = [(STATUS.get(int(v), str(int(v))), int(c)) for v, c in zip(values, counts) if int(v) not in (1, 2, 3)]
    return dict(sorted(found, key=lambda item: -item[1]))


def reason_lines(counts: dict, total: int) -> list:
    """One line per reason for undecided tosses: the status word, the count, the share and what it means.

    Parameters
    ----------
    counts : dict
        ``{status word: count}`` (:func:`undecided_counts`).
    total : int
        All tosses.

    Returns
    -------
    list of str

    Examples
    --------
    >>> reason_lines({'slides': 2}, 4)[0][:35]
    'slides                2 of 4 (0.500'
    """
    return [f"{word:<15s}{n:>8d} of {total} ({n / total:.4f}): {_NOTE_BY_WORD.get(word, '')}"
            for word, n in counts.items()]


_NOTE_BY_WORD = {STATUS[k]: note for k, note in FIELD_NOTES.items()}


@dataclass(frozen=True, repr=False)
class BasinMap:
    """Outcome of the toss on a grid of launch velocities ``v0`` (columns) and spins ``omega0`` (rows).

    ``outcome[i, j]`` is the valley index (``names``) for ``omega0[i]``, ``v0[j]``, or −1 where undecided
    (the impact budget was reached, or the body slides on with energy above its barrier); ``bounces`` the
    floor impacts before the outcome was decided (1 for a caught toss); ``status`` the kernel's codes.

    Attributes
    ----------
    v0, omega0 : ndarray
        The grid's launch velocities (κ/s) and spins (rad/s).
    outcome : ndarray of int (len(omega0), len(v0))
        The valley index of each toss (``names``), −1 where undecided.
    bounces : ndarray of int
        Floor impacts before the outcome was decided.
    status : ndarray of int
        The kernel's status codes (:data:`.field.STATUS`).
    names : list of str
        The outcomes' names, by valley.
    table : FieldTable
    height, theta0 : float
        The launch height and orientation.
    catch : bool
        Whether each toss was stopped at its first floor impact.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> from coinwall.forward.dynamics import basin_map
    >>> basins = basin_map(table, [2.0, 3.0], [0.05, 0.1], height=1.2)
    >>> basins.outcome.shape, basins.bounces.shape
    ((2, 2), (2, 2))
    """

    v0: np.ndarray
    omega0: np.ndarray
    outcome: np.ndarray
    bounces: np.ndarray
    status: np.ndarray
    names: list
    table: FieldTable
    height: float
    theta0: float
    catch: bool

    def fractions(self) -> dict:
        """Share of the grid per outcome name (valleys of one name added up) and ``undecided``."""
        return _shares(self.outcome, self.names)

    def status_counts(self) -> dict:
        """How many tosses ended with each of the kernel's statuses (words of :data:`.field.STATUS`)."""
        values, counts = np.unique(self.status, return_counts=True)
        return {STATUS.get(int(v), str(int(v))): int(c) for v, c in zip(values, counts)}

    def undecided_counts(self) -> dict:
        """How many tosses are undecided, by reason (:func:`undecided_counts`)."""
        return undecided_counts(self.status)

    def to_dict(self) -> dict:
        return {"v0": self.v0.tolist(), "omega0": self.omega0.tolist(), "names": list(self.names),
                "outcome": self.outcome.tolist(), "bounces": self.bounces.tolist(), "g": self.table.g,
                "e": self.table.e, "b0": self.table.b0, "H": self.table.H, "height": self.height,
                "theta0": self.theta0, "catch": self.catch, "mu": self.table.mu, "fractions": self.fractions(),
                "status": self.status_counts(), "undecided": self.undecided_counts()}

    def to_csv(self) -> str:
        lines = ["v0,omega0,outcome,name,bounces"]
        for i, w in enumerate(self.omega0):
            for j, v in enumerate(self.v0):
                k = int(self.outcome[i, j])
                name = self.names[k] if k >= 0 else "undecided"
                lines.append(f"{float(v)!r},{float(w)!r},{k},{name},{int(self.bounces[i, j])}")
        return "\n".join(lines) + "\n"

    def plot(self, title: str = "", keller: bool | None = None):
        """Two panels: the outcome (each rest state coloured, undecided grey) with, for a coin, Keller's
        hyperbolas ω0·v0/g = π(n + ¼), π(n + ¾) dashed (``keller``: draw them or not; default: for a coin
        only), and the number of floor impacts before the outcome was decided.  A caught toss has the first
        panel only (it is decided at its one floor contact, everywhere)."""
        from matplotlib.colors import BoundaryNorm, ListedColormap

        from ...formats.figure import new_figure

        if self.catch:
            fig, ax = new_figure(1, 1, figsize=(6.5, 5), constrained_layout=True)
        else:
            fig, (ax, bx) = new_figure(1, 2, figsize=(12, 5), constrained_layout=True)
        k = len(self.names)
        colours = ["#bbbbbb"] + [_PALETTE[i % len(_PALETTE)] for i in range(k)]
        cmap = ListedColormap(colours)
        norm = BoundaryNorm(np.arange(-1.5, k, 1.0), cmap.N)
        ax.pcolormesh(self.v0, self.omega0, self.outcome, cmap=cmap, norm=norm, shading="nearest",
                      rasterized=True)
        if keller is None:
            keller = self.table.landscape.coin
        if keller and self.table.g > 0:
            v = np.linspace(max(self.v0.min(), 1e-9), self.v0.max(), 400)
            for n in range(400):
                for q in (0.25, 0.75):
                    w = math.pi * (n + q) * self.table.g / v
                    if w.min() > self.omega0.max():
                        break
                    ax.plot(v, w, "k--", lw=0.6, alpha=0.6)
            ax.set_ylim(self.omega0.min(), self.omega0.max())
            ax.set_xlim(self.v0.min(), self.v0.max())
        from matplotlib.patches import Patch

        handles = [Patch(color=colours[i + 1], label=name) for i, name in enumerate(self.names)]
        if np.any(self.outcome == UNDECIDED):
            handles.append(Patch(color=colours[0], label="undecided"))
        ax.legend(handles=handles, loc="upper right", fontsize=8, frameon=True, framealpha=0.9)  # over the map: a frame
        ax.set_xlabel("launch velocity v0 (κ/s)")
        ax.set_ylabel("spin ω0 (rad/s)")
        mode = "caught at the floor" if self.catch else f"e = {self.table.e:g}, μ = {self.table.mu:g}"
        ax.set_title(f"{title + ': ' if title else ''}outcome, g = {self.table.g:g} κ/s², {mode}", fontsize=9)
        if self.catch:
            return ax
        decided = self.bounces[self.outcome != UNDECIDED]
        top = max(1, int(np.percentile(decided, 99))) if decided.size else 1
        im = bx.pcolormesh(self.v0, self.omega0, np.where(self.outcome == UNDECIDED, np.nan, self.bounces),
                           cmap="viridis", shading="nearest", vmin=0, vmax=top, rasterized=True)
        fig.colorbar(im, ax=bx, label="floor impacts before the outcome is decided", extend="max")
        bx.set_xlabel("launch velocity v0 (κ/s)")
        bx.set_ylabel("spin ω0 (rad/s)")
        bx.set_title("bounces before settling", fontsize=9)
        return ax

    @safe_repr
    def __repr__(self):
        shares = ", ".join(f"{k} {v:.3f}" for k, v in self.fractions().items())
        return (f"BasinMap({self.omega0.size}×{self.v0.size}, g={self.table.g:g}, e={self.table.e:g}, "
                f"mu={self.table.mu:g}, height {self.height:g}: {shares})")


def plot_basins(maps, titles=None):
    """The outcome panels of several :class:`BasinMap` side by side, one colour per rest state's name (the same
    colour for the same name in every panel, grey: undecided), Keller's hyperbolas on a coin's.  Returns the
    first axes.

    Parameters
    ----------
    maps : sequence of BasinMap
        Maps of one body (the same names).
    titles : sequence of str, optional
        A title per panel (default: e, μ and the rolling resistance, and the share decided).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.patches import Patch

    from ...formats.figure import new_figure

    _fig, axes = new_figure(1, len(maps), figsize=(5.6 * len(maps), 4.8), constrained_layout=True, squeeze=False)
    names = list(dict.fromkeys(maps[0].names))
    for k, (ax, result) in enumerate(zip(axes[0], maps)):
        colour = np.zeros(result.outcome.shape + (3,))
        colour[:] = (0.73, 0.73, 0.73)
        for i, name in enumerate(result.names):
            rgb = tuple(int(_PALETTE[names.index(name) % len(_PALETTE)][j:j + 2], 16) / 255 for j in (1, 3, 5))
            colour[result.outcome == i] = rgb
        extent = (result.v0.min(), result.v0.max(), result.omega0.min(), result.omega0.max())
        ax.imshow(colour, origin="lower", extent=extent, aspect="auto", interpolation="nearest")
        if result.table.landscape.coin:
            v = np.linspace(max(result.v0.min(), 1e-9), result.v0.max(), 400)
            for n in range(400):
                w = math.pi * (n + np.array([[0.25], [0.75]])) * result.table.g / v
                if w.min() > result.omega0.max():
                    break
                ax.plot(v, w[0], "k--", v, w[1], "k--", lw=0.5, alpha=0.5)
            ax.set_ylim(result.omega0.min(), result.omega0.max())
        table = result.table
        decided = 1.0 - result.fractions()["undecided"]
        ax.set_title(titles[k] if titles else f"e = {table.e:g}, μ = {table.mu:g}, rolling {table.rolling:g} κ: "
                     f"{decided:.1%} decided", fontsize=9)
        ax.set_xlabel("launch velocity v0 (κ/s)")
        ax.set_ylabel("spin ω0 (rad/s)")
    handles = [Patch(color=_PALETTE[i % len(_PALETTE)], label=name) for i, name in enumerate(names)]
    handles.append(Patch(color="#bbbbbb", label="undecided"))
    axes[0][-1].legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    return axes[0][0]


def _grid(name, values):
    arr = np.asarray(values, dtype=float).ravel()
    if arr.size == 0 or not np.all(np.isfinite(arr)):
        raise InvalidArgument(f"`{name}` must be finite numbers")
    return arr


def basin_map(table: FieldTable, v0, omega0, height: float, theta0: float | None = None, impacts: int = 10_000,
              catch: bool = False, workers=None, progress=None, slide: bool = False, device: str = "cpu") -> BasinMap:
    """The outcome of the toss on the grid ``v0`` × ``omega0`` (see the module docstring).

    ``impacts`` bounds the impacts per toss (an undecided toss after that many is marked −1); ``progress`` is
    called with the number of tosses done after each chunk.  ``slide=True`` follows tosses that come to slide
    on a smooth floor above their barrier until they lift off (:func:`.slide.settle_many`; slow, ~50 ms each).

    Parameters
    ----------
    table : FieldTable
        The wall, the field ``g > 0``, the restitution and the friction of the floor.
    v0 : array_like
        Launch velocities of the centre of mass, upwards (κ/s): the columns of the map.
    omega0 : array_like
        Launch spins θ̇ (rad/s): the rows of the map.
    height : float
        Launch height of the centre of mass above the floor (κ).
    theta0 : float, optional
        Launch orientation (default: heads' rest angle for a coin).
    impacts : int
        Floor impacts per toss before it is marked undecided.
    catch : bool
        Stop each toss at its first floor impact (a toss caught in the hand) instead of letting it bounce.
    workers : int, optional
        Threads of the compiled kernel.
    progress : callable, optional
        Called with the number of tosses done after each chunk.
    slide : bool
        Follow tosses that slide on a smooth floor above their barrier until they lift off (slow).
    device : {"cpu", "gpu"}
        Where the tosses run: the CPU's threads, or a CUDA GPU, one toss per thread
        (:func:`.field.field_run_many`).

    Returns
    -------
    BasinMap
        ``outcome[i, j]`` for ``omega0[i]``, ``v0[j]``.

    Raises
    ------
    InvalidArgument
        For a table without a field (``g ≤ 0``) or without valleys, launch grids that are not finite numbers,
        or a launch height that puts the body into the floor (or the ceiling).

    Examples
    --------
    A thin coin (the ellipse with ε = 99) launched heads up from height 1.2κ on a 3 × 4 grid:

    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable
    >>> ellipse = "sqrt((1+eps*cos(t)**2)/(1+eps))"           # the paper's eq. 18
    >>> coin = Wall.from_expression(ellipse, {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> import numpy as np
    >>> from coinwall.forward.dynamics import basin_map
    >>> v0, omega0 = np.linspace(2.0, 5.0, 4), np.linspace(0.05, 0.2, 3)
    >>> basins = basin_map(table, v0, omega0, height=1.2)
    >>> basins
    BasinMap(3×4, g=1, e=0.6, mu=0.3, height 1.2: tails 0.500, heads 0.500, undecided 0.000)
    >>> basins.names, basins.outcome.tolist()
    (['tails', 'heads'], [[1, 0, 0, 1], [1, 0, 1, 0], [1, 0, 0, 1]])
    """
    impacts = check_count("impacts", impacts)
    v = _grid("v0", v0)
    w = _grid("omega0", omega0)
    V, W = np.meshgrid(v, w)
    states = launch_states(table, V, W, height, theta0)  # (refuses a wall without valleys)
    outcome, bounces, status = _outcomes(table, states, impacts, catch, workers, progress, slide, device)
    shape = V.shape
    return BasinMap(v, w, outcome.reshape(shape), bounces.reshape(shape), status.reshape(shape),
                    list(table.landscape.names), table, float(height), float(states[0, 0]), bool(catch))


def _shares(outcome, names) -> dict:
    """Share per name (valleys of one name added up) and ``undecided``."""
    total = max(1, outcome.size)
    shares: dict = {}
    for k, name in enumerate(names):
        shares[name] = shares.get(name, 0.0) + float(np.sum(outcome == k)) / total
    shares["undecided"] = float(np.sum(outcome == UNDECIDED)) / total
    return shares
