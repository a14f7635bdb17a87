"""The toss from a hand: launches drawn from a Gaussian spread, the outcome of each, and the shares of outcomes.

:func:`launch_spread` draws launches ``(v0, ω0)`` from a Gaussian hand, seeded; :func:`toss_outcomes` gives each
launch's rest state by name, when and after how many impacts it was decided, or why it was not (:class:`Tosses`);
:func:`heads_fraction` the share of each outcome under such a hand, with its standard error (:class:`Spread`).
The launch, the kernel runs and the undecided reasons are :mod:`.toss`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import json_numbers, safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_seed
from .field import STATUS, FieldTable
from .toss import UNDECIDED, _outcomes, _run_chunks, _shares, launch_states, undecided_counts

__all__ = ["Spread", "Tosses", "heads_fraction", "launch_spread", "toss_outcomes"]


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
    undecided: dict = None

    def to_dict(self):
        return {"mean_v0_omega0": list(self.mean), "sigma_v0_omega0": list(self.sigma), "samples": self.samples,
                "seed": self.seed, "fractions": {k: {"p": p, "stderr": s} for k, (p, s) in self.fractions.items()},
                "undecided": dict(self.undecided or {})}

    @safe_repr
    def __repr__(self):
        shares = ", ".join(f"{k} {p:.4f} ± {s:.4f}" for k, (p, s) in self.fractions.items())
        return f"Spread(v0 = {self.mean[0]:g} ± {self.sigma[0]:g}, ω0 = {self.mean[1]:g} ± {self.sigma[1]:g}: {shares})"


def _check_spread(mean, sigma):
    mean = tuple(float(x) for x in mean)
    sigma = tuple(float(x) for x in sigma)
    if len(mean) != 2 or len(sigma) != 2 or not all(math.isfinite(x) for x in mean + sigma) or min(sigma) < 0:
        raise InvalidArgument(f"the spread needs a mean (v0, ω0) and two standard deviations >= 0, got {mean}, "
                              f"{sigma}")
    return mean, sigma


def launch_spread(mean, sigma, samples: int, seed=None):
    """Launches drawn from a Gaussian hand: ``(v0, ω0) ~ N(mean, diag(sigma²))``, seeded.

    Parameters
    ----------
    mean : pair of float
        The mean launch velocity (κ/s) and spin (rad/s).
    sigma : pair of float
        Their standard deviations (≥ 0).
    samples : int
        How many launches.
    seed : int, optional
        The seed, an integer >= 0 (the same seed gives the same launches: v0 drawn first, then ω0).

    Returns
    -------
    v0, omega0 : ndarray (samples,)

    Raises
    ------
    InvalidArgument
        For a spread that is not two finite means and two standard deviations ≥ 0.

    Examples
    --------
    >>> v0, omega0 = launch_spread((2.0, 5.0), (0.05, 0.2), 3, seed=1)
    >>> v0.shape, omega0.shape
    ((3,), (3,))
    """
    samples = check_count("samples", samples)
    mean, sigma = _check_spread(mean, sigma)
    rng = np.random.default_rng(check_seed(seed))
    return rng.normal(mean[0], sigma[0], samples), rng.normal(mean[1], sigma[1], samples)


@dataclass(frozen=True, repr=False)
class Tosses:
    """The outcome of each launch of a toss (:func:`toss_outcomes`).

    Attributes
    ----------
    v0, omega0 : ndarray (n,)
        The launches: upward velocity (κ/s) and spin θ̇ (rad/s).
    outcome : ndarray of int (n,)
        The valley index of each rest state (``names``), −1 where undecided.
    status : ndarray of int (n,)
        The kernel's status code (:data:`.field.STATUS`): why each toss ended.
    rest_angle : ndarray (n,)
        The angle θ of the floor's normal in the body frame at rest (radians, in [0, 2π)): where the toss came to
        rest (on a face; or where a rolling resistance holds it), else the minimum of the valley it can no
        longer leave; NaN where undecided.
    time : ndarray (n,)
        When the outcome was decided (s): the impact or contact event after which the toss could not leave its
        valley, or came to rest.
    impacts : ndarray of int (n,)
        Floor impacts up to then.
    names : list of str
        The rest states' names, by valley (heads/tails/edge for a coin, else faces by their normal angle).
    table : FieldTable
    height, theta0 : float
        The launch height (κ) and orientation (rad).

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> from coinwall.forward.dynamics import toss_outcomes
    >>> tosses = toss_outcomes(table, [2.0, 3.0, 4.0], [0.05, 0.1, 0.2], height=1.2)
    >>> [tosses.names[k] for k in tosses.outcome], tosses.impacts.tolist()
    (['heads', 'tails', 'tails'], [4, 4, 5])
    """

    v0: np.ndarray
    omega0: np.ndarray
    outcome: np.ndarray
    status: np.ndarray
    rest_angle: np.ndarray
    time: np.ndarray
    impacts: np.ndarray
    names: list
    table: FieldTable
    height: float
    theta0: float

    def __len__(self):
        return int(self.outcome.size)

    @property
    def name(self) -> np.ndarray:
        """The name of each launch's rest state (``"undecided"`` where there is none)."""
        labels = np.array(list(self.names) + ["undecided"], dtype=object)
        return labels[np.where(self.outcome >= 0, self.outcome, len(self.names))]

    @property
    def reason(self) -> np.ndarray:
        """Why each undecided toss is undecided (a status word of :data:`.field.STATUS`; ``""`` if decided)."""
        words = np.array([STATUS.get(int(v), str(int(v))) for v in self.status], dtype=object)
        return np.where(self.outcome >= 0, "", words)

    def fractions(self) -> dict:
        """Share of the launches per rest state's name, and ``undecided``."""
        return _shares(self.outcome, self.names)

    def undecided_counts(self) -> dict:
        """How many launches are undecided, by reason (:func:`undecided_counts`)."""
        return undecided_counts(self.status)

    def to_dict(self) -> dict:
        return {"v0": self.v0.tolist(), "omega0": self.omega0.tolist(), "name": self.name.tolist(),
                "status": [STATUS.get(int(v), str(int(v))) for v in self.status],
                "rest_angle": json_numbers(self.rest_angle), "time": json_numbers(self.time),
                "impacts": self.impacts.tolist(), "fractions": self.fractions(),
                "undecided": self.undecided_counts(), "g": self.table.g, "e": self.table.e, "mu": self.table.mu,
                "height": self.height, "theta0": self.theta0}

    @safe_repr
    def __repr__(self):
        shares = ", ".join(f"{k} {v:.3f}" for k, v in self.fractions().items())
        return f"Tosses({len(self)} launches, e={self.table.e:g}, mu={self.table.mu:g}: {shares})"


def toss_outcomes(table: FieldTable, v0, omega0, height: float, theta0: float | None = None, impacts: int = 10_000,
                  workers=None, progress=None, device: str = "cpu") -> Tosses:
    """The outcome of each launch ``(v0[i], omega0[i])``: its rest state by name, or why it has none.

    Vectorised (all launches in the compiled kernel's parallel loop) and deterministic: the same launches give
    the same outcomes.  Draw the launches with :func:`launch_spread` for a seeded hand.

    Parameters
    ----------
    table : FieldTable
        The body's wall, the field g > 0, restitution e and friction μ.
    v0, omega0 : array_like
        Launch velocities (κ/s) and spins θ̇ (rad/s), broadcast together.
    height : float
        Launch height of the centre of mass (κ).
    theta0 : float, optional
        Launch orientation (default: heads' rest angle for a coin, else the first valley's).
    impacts : int
        The most impacts and contact events per toss; a toss still going then is undecided (``bounces``).
    workers : int, optional
        Threads of the compiled kernel.
    progress : callable, optional
        Called with the number of launches done after each chunk (4096; 2^18 on a GPU).
    device : {"cpu", "gpu"}
        All CPU cores, or a CUDA GPU, one toss per thread (:func:`.field.field_run_many`).

    Returns
    -------
    Tosses

    Raises
    ------
    InvalidArgument
        For a table without a field, a wall without valleys, a launch into the floor, bad counts, an unknown device
        or ``device="gpu"`` without a usable GPU.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> v0, omega0 = launch_spread((2.0, 5.0), (0.05, 0.2), 4, seed=1)
    >>> result = toss_outcomes(table, v0, omega0, height=1.2)
    >>> sorted(set(result.name) - {"heads", "tails"})
    []
    """
    impacts = check_count("impacts", impacts)
    states = launch_states(table, v0, omega0, height, theta0)
    out = _run_chunks(table, states, impacts, False, workers, progress, device=device)
    decided = np.isin(out["status"], (1, 3))
    outcome = np.where(decided, out["valley"], UNDECIDED)
    # at rest with friction: where it rests (on a face, or held by the rolling resistance); else its valley's minimum
    rest = np.where((out["status"] == 3) & (table.mu > 0), out["theta"],
                    table.landscape.minima[np.clip(out["valley"], 0, None)])
    rest = np.where(decided, rest, np.nan)
    return Tosses(states[:, 3].copy(), states[:, 2].copy(), outcome, out["status"], rest, out["time"],
                  out["floor_impacts"], list(table.landscape.names), table, float(height), float(states[0, 0])
                  if states.size else float("nan"))


def heads_fraction(table: FieldTable, mean, sigma, height: float, samples: int = 10_000, theta0=None, seed=None,
                   impacts: int = 10_000, catch: bool = False, workers=None, progress=None,
                   slide: bool = False, device: str = "cpu") -> Spread:
    """Outcome fractions and their standard errors for launches ``(v0, ω0) ~ N(mean, diag(sigma²))``.

    Parameters
    ----------
    table : FieldTable
        The body's wall, the field, restitution and friction.
    mean, sigma : pair of float
        The hand: the mean launch velocity and spin, and their standard deviations (:func:`launch_spread`).
    height : float
        Launch height of the centre of mass (κ).
    samples : int
        Launches.
    theta0, impacts, catch, workers, progress, slide, device
        As for :func:`basin_map`.
    seed : int, optional
        The seed of the launches.

    Returns
    -------
    Spread
        ``fractions[name] = (p, standard error)``, and the undecided tosses counted by reason.

    Raises
    ------
    InvalidArgument
        For a spread, count or launch that is not one, or a device that cannot run.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> spread = heads_fraction(FieldTable(coin, g=1.0, e=0.6, mu=0.3), (2, 5), (0.05, 0.2), 1.2, samples=50, seed=1)
    >>> sorted(spread.fractions), spread.undecided
    (['heads', 'tails'], {})
    """
    samples = check_count("samples", samples)
    v, w = launch_spread(mean, sigma, samples, seed)
    states = launch_states(table, v, w, height, theta0)
    outcome, _, status = _outcomes(table, states, impacts, catch, workers, progress, slide, device)
    fractions = {name: (p, math.sqrt(p * (1 - p) / samples)) for name, p in _shares(outcome, table.landscape.names).items()
                 if name != "undecided" or p > 0.0}
    return Spread(tuple(float(x) for x in mean), tuple(float(x) for x in sigma), samples, fractions, seed,
                  undecided_counts(status))
