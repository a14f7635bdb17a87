"""The toss that lands: basin maps of the outcome over the launch velocity and spin, and heads fractions.

A body (its wall b(θ), offset b0) is launched from rest orientation ``theta0`` with its centre of mass at
height ``height`` (κ, above the floor's reference η = 0), upward velocity ``v0`` (κ/s) and spin ``ω0``
(θ̇, rad/s), in the field g (κ/s²), and bounces with restitution e until its outcome is decided
(:mod:`.field`: energy below its valley's barrier, or at rest in the chattering limit), or, with
``catch``, until it first meets the floor (Keller's coin, caught on landing).  :func:`basin_map` computes
the outcome on a grid of (v0, ω0) with the number of floor impacts it took (the picture of Vulović and
Prange, PRA 33, 576 (1986): bands of heads and tails between hyperbolas ω0·v0 ≈ const, thinner as the
energy grows); :func:`heads_fraction` the probability of each outcome under a Gaussian spread of the
launch, with its standard error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_seed
from .field import STATUS, FieldTable, settle_many

__all__ = ["BasinMap", "Spread", "basin_map", "heads_fraction", "launch_states"]

_CHUNK = 4096  # orbits per kernel call (the progress bar moves once per chunk)
UNDECIDED = -1


def _default_theta0(table: FieldTable) -> float:
    """The rest angle the toss starts from: heads' minimum for a coin, else the first valley's."""
    land = table.landscape
    if "heads" in land.names:
        return float(land.minima[land.names.index("heads")])
    return float(land.minima[0])


def launch_states(table: FieldTable, v0, omega0, height: float, theta0: float | None = None) -> np.ndarray:
    """States ``[θ0, height, ω0, v0]`` for arrays of launch velocities and spins (broadcast together)."""
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


def _outcomes(table, states, impacts, catch, workers, progress, slide=False):
    """Outcome (valley index, or UNDECIDED), floor impacts and status per state, in chunks."""
    n = states.shape[0]
    outcome = np.empty(n, dtype=np.int64)
    bounces = np.empty(n, dtype=np.int64)
    status = np.empty(n, dtype=np.int64)
    for lo in range(0, n, _CHUNK):
        hi = min(n, lo + _CHUNK)
        out = settle_many(table, states[lo:hi], impacts, catch=catch, workers=workers, follow_slides=slide)
        decided = np.isin(out["status"], (1, 2, 3))
        outcome[lo:hi] = np.where(decided, out["valley"], UNDECIDED)
        bounces[lo:hi] = out["floor_impacts"]
        status[lo:hi] = out["status"]
        if progress is not None:
            progress(hi - lo)
    return outcome, bounces, status


@dataclass(frozen=True, repr=False)
class BasinMap:
    """Outcome of the toss on a grid of launch velocities ``v0`` (columns) and spins ``omega0`` (rows).

    ``outcome[i, j]`` is the valley index (``names``) for ``omega0[i]``, ``v0[j]``, or −1 where undecided
    (the impact budget was reached, or the body slides on with energy above its barrier); ``bounces`` the
    floor impacts before the outcome was decided (1 for a caught toss); ``status`` the kernel's codes.
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
        """Share of the grid per outcome name (and ``undecided``)."""
        total = self.outcome.size
        shares = {name: float(np.mean(self.outcome == k)) for k, name in enumerate(self.names)}
        shares["undecided"] = float(np.mean(self.outcome == UNDECIDED)) if total else 0.0
        return shares

    def status_counts(self) -> dict:
        values, counts = np.unique(self.status, return_counts=True)
        return {STATUS.get(int(v), str(int(v))): int(c) for v, c in zip(values, counts)}

    def to_dict(self) -> dict:
        return {"v0": self.v0.tolist(), "omega0": self.omega0.tolist(), "names": list(self.names),
                "outcome": self.outcome.tolist(), "bounces": self.bounces.tolist(), "g": self.table.g,
                "e": self.table.e, "b0": self.table.b0, "H": self.table.H, "height": self.height,
                "theta0": self.theta0, "catch": self.catch, "fractions": self.fractions(),
                "status": self.status_counts()}

    def to_csv(self) -> str:
        lines = ["v0,omega0,outcome,name,bounces"]
        for i, w in enumerate(self.omega0):
            for j, v in enumerate(self.v0):
                k = int(self.outcome[i, j])
                name = self.names[k] if k >= 0 else "undecided"
                lines.append(f"{float(v)!r},{float(w)!r},{k},{name},{int(self.bounces[i, j])}")
        return "\n".join(lines) + "\n"

    def plot(self, title: str = "", keller: bool = True):
        """Two panels: the outcome (heads/tails coloured, undecided grey) with Keller's hyperbolas
        ω0·v0/g = π(n + ¼), π(n + ¾) dashed, and the number of floor impacts before the outcome was decided.
        A caught toss has the first panel only (it is decided at its one floor contact, everywhere)."""
        from matplotlib.colors import BoundaryNorm, ListedColormap

        from ...formats.figure import new_figure

        if self.catch:
            fig, ax = new_figure(1, 1, figsize=(6.5, 5), constrained_layout=True)
        else:
            fig, (ax, bx) = new_figure(1, 2, figsize=(12, 5), constrained_layout=True)
        k = len(self.names)
        palette = ["#c8553d", "#2f6690", "#f2a541", "#3a7d44", "#8e6c8a", "#6b9080"]
        colours = ["#bbbbbb"] + [palette[i % len(palette)] for i in range(k)]
        cmap = ListedColormap(colours)
        norm = BoundaryNorm(np.arange(-1.5, k, 1.0), cmap.N)
        ax.pcolormesh(self.v0, self.omega0, self.outcome, cmap=cmap, norm=norm, shading="nearest",
                      rasterized=True)
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
        mode = "caught at the floor" if self.catch else f"e = {self.table.e:g}"
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
                f"height {self.height:g}: {shares})")


def _grid(name, values):
    arr = np.asarray(values, dtype=float).ravel()
    if arr.size == 0 or not np.all(np.isfinite(arr)):
        raise InvalidArgument(f"`{name}` must be finite numbers")
    return arr


def basin_map(table: FieldTable, v0, omega0, height: float, theta0: float | None = None, impacts: int = 10_000,
              catch: bool = False, workers=None, progress=None, slide: bool = False) -> BasinMap:
    """The outcome of the toss on the grid ``v0`` × ``omega0`` (see the module docstring).

    ``impacts`` bounds the impacts per toss (an undecided toss after that many is marked −1); ``progress`` is
    called with the number of tosses done after each chunk.  ``slide=True`` follows tosses that come to slide
    on a smooth floor above their barrier until they lift off (:func:`.field.settle_many`; slow, ~50 ms each).
    """
    if not isinstance(table, FieldTable):
        raise InvalidArgument(f"`table` must be a FieldTable, got {type(table).__name__}")
    if table.g <= 0:
        raise InvalidArgument("a toss needs a field: `g` must be positive")
    impacts = check_count("impacts", impacts)
    v = _grid("v0", v0)
    w = _grid("omega0", omega0)
    land = table.landscape
    if land.names and np.all(np.isinf(land.barriers)):
        # one valley without a barrier: the wall is flat (a disc), every orientation is a rest state, and the
        # outcome named after its one "minimum" would be made up
        raise InvalidArgument(f"wall {table.wall.description!r} has no valleys (b is constant within rounding): a "
                              "body resting on it can rest at any angle, so a toss has no outcome")
    theta0 = _default_theta0(table) if theta0 is None else float(theta0)
    V, W = np.meshgrid(v, w)
    states = launch_states(table, V, W, height, theta0)
    outcome, bounces, status = _outcomes(table, states, impacts, catch, workers, progress, slide)
    shape = V.shape
    return BasinMap(v, w, outcome.reshape(shape), bounces.reshape(shape), status.reshape(shape),
                    list(table.landscape.names), table, float(height), theta0, bool(catch))


@dataclass(frozen=True, repr=False)
class Spread:
    """Outcome probabilities under a Gaussian spread of the launch: ``fractions[name] = (p, standard error)``,
    the binomial error ``√(p(1 − p)/n)`` of ``n`` independent draws (undecided tosses counted as their own
    outcome)."""

    mean: tuple
    sigma: tuple
    samples: int
    fractions: dict
    seed: object

    def to_dict(self):
        return {"mean_v0_omega0": list(self.mean), "sigma_v0_omega0": list(self.sigma), "samples": self.samples,
                "seed": self.seed, "fractions": {k: {"p": p, "stderr": s} for k, (p, s) in self.fractions.items()}}

    @safe_repr
    def __repr__(self):
        shares = ", ".join(f"{k} {p:.4f} ± {s:.4f}" for k, (p, s) in self.fractions.items())
        return f"Spread(v0 = {self.mean[0]:g} ± {self.sigma[0]:g}, ω0 = {self.mean[1]:g} ± {self.sigma[1]:g}: {shares})"


def heads_fraction(table: FieldTable, mean, sigma, height: float, samples: int = 10_000, theta0=None, seed=None,
                   impacts: int = 10_000, catch: bool = False, workers=None, progress=None,
                   slide: bool = False) -> Spread:
    """Outcome fractions and their standard errors for launches ``(v0, ω0) ~ N(mean, diag(sigma²))``."""
    samples = check_count("samples", samples)
    mean = tuple(float(x) for x in mean)
    sigma = tuple(float(x) for x in sigma)
    if len(mean) != 2 or len(sigma) != 2 or not all(math.isfinite(x) for x in mean + sigma) or min(sigma) < 0:
        raise InvalidArgument(f"the spread needs a mean (v0, ω0) and two standard deviations >= 0, got {mean}, "
                              f"{sigma}")
    rng = np.random.default_rng(check_seed(seed))
    v = rng.normal(mean[0], sigma[0], samples)
    w = rng.normal(mean[1], sigma[1], samples)
    states = launch_states(table, v, w, height, theta0)
    outcome, _, _ = _outcomes(table, states, impacts, catch, workers, progress, slide)
    names = list(table.landscape.names) + ["undecided"]
    fractions = {}
    for k, name in enumerate(names):
        hit = outcome == (k if name != "undecided" else UNDECIDED)
        p = float(np.mean(hit))
        if name == "undecided" and p == 0.0:
            continue
        fractions[name] = (p, math.sqrt(p * (1 - p) / samples))
    return Spread(mean, sigma, samples, fractions, seed)
