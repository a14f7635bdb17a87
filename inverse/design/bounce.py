"""The ``bounce`` toss: the planar body launched at random, bouncing on a floor until it comes to rest.

Units: lengths in κ (the wall's unit, as everywhere in coinwall), time in seconds, the field ``g`` in κ/s².

The launch (:class:`Launch`).  The body leaves the hand with its downward body direction θ0 uniform on the
circle (or fixed), its lowest point ``height`` above the floor (so its centre is at ``b0 + b(θ0) + height``),
an upward velocity ``v0 ~ N(mean, sd²)``, a spin ``θ̇0 ~ N(mean, sd²)`` and, on a floor with friction, a
horizontal velocity ``vx ~ N(mean, sd²)`` of the centre of mass (κ/s; default 0).  The draws are numbers
independent of the body (a uniform and two standard normals per toss, a third normal when ``vx`` has a
spread), so the same draws give the same hands for every member of a family: the common random numbers of
the design solvers.

The toss (:func:`toss`) is :mod:`coinwall.forward.dynamics.floor.field`'s: gravity, restitution ``e`` and,
with ``mu`` > 0, Coulomb friction at the floor (Stronge's impact, then sliding, rolling and rocking until the
body rests; ``rolling`` adds a rolling resistance), until the toss is decided (its energy below the barrier
of its valley, or at rest).  On a frictionless floor (``mu`` = 0, Newton's restitution) a toss whose bounces
die out above its barrier slides for ever (status ``slides``); with friction such tosses settle, and what is
left undecided is a body that rolls for ever without rolling resistance (``rolls``), an indeterminate
contact (``painleve``) or a budget reached.  :class:`Bounce` reports the odds among the decided tosses and
the undecided share beside them.  :func:`toss` is the one place a toss is run (launch states in, outcome per
launch out).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.display import safe_repr
from coinwall.forward.dynamics.floor.field import check_friction
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.validation import check_count, check_finite

from .drop import valley_hits
from .family import Valleys, outcome_sets

__all__ = ["Bounce", "Launch", "toss"]


def _pair(name, value):
    try:
        mean, sd = (check_finite(name, float(v)) for v in value)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`{name}` must be a pair (mean, standard deviation), got {value!r}") from None
    if sd < 0:
        raise InvalidArgument(f"`{name}`: the standard deviation must be >= 0, got {sd:g}")
    return mean, sd


@dataclass(frozen=True, repr=False)
class Launch:
    """The hand (module docstring): ``g`` (κ/s²), ``height`` of the lowest point (κ), ``v0``, ``omega`` and ``vx``
    as (mean, standard deviation) in κ/s, rad/s and κ/s, ``theta0`` the launch direction (None: uniform).

    ``vx``, the horizontal velocity of the centre of mass, matters only on a floor with friction
    (:class:`Bounce` refuses it on a frictionless one).

    Parameters
    ----------
    g : float
        The field (κ/s²), in [1e-9, 1e12].
    height : float
        Height of the body's lowest point above the floor at launch (κ).
    v0 : (float, float)
        Mean and standard deviation of the upward launch velocity (κ/s).
    omega : (float, float)
        Mean and standard deviation of the spin (rad/s).
    vx : (float, float)
        Mean and standard deviation of the horizontal velocity of the centre of mass (κ/s); only with friction.
    theta0 : float, optional
        The launch direction (rad); ``None``: uniform.

    Examples
    --------
    >>> Launch().draw(np.random.default_rng(0), 2).shape
    (2, 3)
    >>> Launch(vx=(0.0, 1.0)).draw(np.random.default_rng(0), 2).shape
    (2, 4)
    """

    g: float = 1.0
    height: float = 2.0
    v0: tuple = (0.0, 0.0)
    omega: tuple = (0.0, 3.0)
    theta0: float | None = None
    vx: tuple = (0.0, 0.0)

    def __post_init__(self):
        g = check_finite("g", self.g)
        if not 1e-9 <= g <= 1e12:
            raise InvalidArgument(f"`g` must be a field between 1e-9 and 1e12 κ/s², got {g:g}")
        height = check_finite("height", self.height)
        if not 0 < height <= 1e6:
            raise InvalidArgument(f"`height` (of the lowest point above the floor) must be in (0, 1e6] κ, got "
                                  f"{height:g}")
        object.__setattr__(self, "g", g)
        object.__setattr__(self, "height", height)
        object.__setattr__(self, "v0", _pair("v0", self.v0))
        object.__setattr__(self, "omega", _pair("omega", self.omega))
        object.__setattr__(self, "vx", _pair("vx", self.vx))
        if self.theta0 is not None:
            object.__setattr__(self, "theta0", check_finite("theta0", self.theta0))

    @property
    def dimensions(self) -> int:
        """Random numbers per toss: 3, and a fourth when ``vx`` has a spread."""
        return 4 if self.vx[1] > 0 else 3

    def draw(self, rng, n: int) -> np.ndarray:
        """``(n, dimensions)`` numbers of ``n`` hands: a uniform in [0, 1) and two (three) standard normals each."""
        # the fourth column is drawn after the first three, so a hand without a spread in vx draws as before
        return np.column_stack([rng.random(n)] + [rng.standard_normal(n) for _ in range(self.dimensions - 1)])

    def states(self, lower, draws) -> np.ndarray:
        """Launch states ``[θ0, η0, θ̇0, η̇0, ξ̇0]`` of the draws; ``lower(θ)`` is the floor ``b0 + b(θ)``."""
        d = np.asarray(draws, dtype=float)
        theta = np.full(d.shape[0], self.theta0) if self.theta0 is not None else 2.0 * math.pi * d[:, 0]
        eta = lower(theta) + self.height
        vx = self.vx[0] + self.vx[1] * d[:, 3] if self.vx[1] > 0 else np.full(d.shape[0], self.vx[0])
        return np.column_stack([theta, eta, self.omega[0] + self.omega[1] * d[:, 2], self.v0[0] + self.v0[1] * d[:, 1],
                                vx])

    def to_dict(self) -> dict:
        return {"g": self.g, "height": self.height, "v0": list(self.v0), "omega": list(self.omega),
                "vx": list(self.vx), "theta0": self.theta0}

    @safe_repr
    def __repr__(self):
        start = "uniform" if self.theta0 is None else f"{self.theta0:g}"
        horizontal = f", vx={self.vx[0]:g}±{self.vx[1]:g}" if self.vx != (0.0, 0.0) else ""
        return (f"Launch(g={self.g:g}, height={self.height:g}, v0={self.v0[0]:g}±{self.v0[1]:g}, "
                f"ω0={self.omega[0]:g}±{self.omega[1]:g}{horizontal}, θ0 {start})")


def toss(wall, states, *, e: float, mu: float = 0.0, rolling: float = 0.0, g: float, b0: float = 0.0,
         impacts: int = 10_000, workers=None, device: str = "cpu"):
    """The outcome of each launch: the one place the planar toss is run (:mod:`coinwall.forward.dynamics.floor.field`,
    compiled, parallel over launches).

    Parameters
    ----------
    wall : Wall
        The body's wall (units of κ).
    states : array (n, 4) or (n, 5)
        Launch states ``[θ, η, θ̇, η̇(, ξ̇)]`` (:meth:`Launch.states`), strictly above the floor; ξ̇ the horizontal
        velocity of the centre of mass (κ/s, 0 when not given).
    e, mu, rolling : float
        Restitution in (0, 1]; Coulomb's friction at the floor (≥ 0; 0: frictionless) and the rolling
        resistance (units of κ, in [0, 1], with ``mu`` > 0), as in :class:`~coinwall.forward.dynamics.floor.FieldTable`.
    g, b0 : float
        The field (κ/s²) and the wall's offset.
    impacts : int
        Impacts (and, with friction, contact events) per toss at most.
    workers : int, optional
        Threads.
    device : {"cpu", "gpu"}
        All CPU cores, or a CUDA GPU, one toss per thread
        (:func:`~coinwall.forward.dynamics.floor.field.field_run_many`).

    Returns
    -------
    tuple
        ``(index, valleys, status)``: the valley each launch rests in (−1: undecided), the :class:`.family.Valleys`
        of the kernel's landscape, the kernel's status codes.

    Raises
    ------
    InvalidArgument
        ``mu`` or ``rolling`` out of range, a wall with a single valley, a state not inside the table.

    Examples
    --------
    >>> from coinwall.forward.wall import Wall
    >>> wall = Wall.from_expression("abs(cos(t)) + h*abs(sin(t))", {"h": 0.5})
    >>> index, valleys, _ = toss(wall, [[4.7, 2.6, 0.0, 0.0]], e=0.5, g=1.0)
    >>> int(index[0]), len(valleys)
    (2, 4)
    >>> index, _, _ = toss(wall, [[4.7, 2.6, 0.0, 0.0, 0.3]], e=0.5, mu=0.3, g=1.0)
    >>> int(index[0])
    2
    """
    from coinwall.forward.dynamics.floor.field import FieldTable, field_run_many

    table = FieldTable(wall, g=g, e=e, b0=b0, mu=mu, rolling=rolling)
    land = table.landscape
    if land.names and np.all(np.isinf(land.barriers)):
        raise InvalidArgument(f"wall {wall.description!r} has a single valley: the body rests on one face whatever "
                              "its toss")
    out = field_run_many(table, np.asarray(states, dtype=float), impacts, workers=workers, device=device)
    decided = np.isin(out["status"], (1, 2, 3))
    index = np.where(decided, out["valley"], -1)
    left = land.table[:, 0]
    right = np.roll(left, -1)
    right[-1] += 2.0 * math.pi
    return index, Valleys(left, right, land.table[:, 2], 2.0 * math.pi), out["status"]


class Bounce:
    """The planar bounce toss (module docstring).

    Parameters
    ----------
    e : float
        Restitution in (0, 1].
    mu : float
        Coulomb's coefficient of friction of the floor, ≥ 0 (0: frictionless, Newton's restitution).
    rolling : float
        Rolling resistance with friction: the lever arm (units of κ, in [0, 1]) of the floor's push that
        opposes rolling (0: none; a near-round body may then roll for ever, undecided).
    launch : Launch, optional
        The hand (default :class:`Launch`'s defaults); a horizontal velocity ``vx`` needs ``mu`` > 0.
    impacts : int
        Impacts (and, with friction, contact events) per toss at most.
    workers : int, optional
        Threads of the compiled toss.
    device : {"cpu", "gpu"}
        Where the tosses run: all CPU cores, or a CUDA GPU (:func:`toss`).

    Raises
    ------
    InvalidArgument
        For ``e``, ``mu`` or ``rolling`` out of range, or a horizontal launch velocity on a frictionless floor.

    Examples
    --------
    >>> Bounce(e=0.5).name
    'bounce'
    >>> Bounce(e=0.5, mu=0.3)
    Bounce(e=0.5, mu=0.3, Launch(g=1, height=2, v0=0±0, ω0=0±3, θ0 uniform))
    """

    name = "bounce"
    exact = False

    def __init__(self, e: float = 0.6, mu: float = 0.0, launch: Launch | None = None, impacts: int = 10_000,
                 workers=None, rolling: float = 0.0, device: str = "cpu"):
        from coinwall.forward.dynamics.billiard.gpu import check_device

        e = check_finite("e", e)
        if not 0.0 < e <= 1.0:
            raise InvalidArgument(f"`e` must be a coefficient of restitution in (0, 1], got {e:g}")
        self.e = e
        self.mu, self.rolling = check_friction(mu, rolling)
        self.launch = launch if launch is not None else Launch()
        if not isinstance(self.launch, Launch):
            raise InvalidArgument(f"`launch` must be a Launch, got {type(self.launch).__name__}")
        if self.mu == 0.0 and self.launch.vx != (0.0, 0.0):
            raise InvalidArgument("a horizontal launch velocity `vx` does nothing on a frictionless floor (`mu` = 0): "
                                  "give `mu` > 0 or leave it out")
        self.impacts = check_count("impacts", impacts, maximum=10 ** 9)
        self.workers = workers
        self.device = check_device(device)

    @property
    def dimensions(self) -> int:
        return self.launch.dimensions

    def draw(self, rng, n):
        return self.launch.draw(rng, n)

    def simulate(self, kind, body, draws, names, b0=0.0):
        """Toss ``body`` (a planar wall) once per draw; returns ``(hits, undecided)`` (bool arrays)."""
        if kind != "planar":
            raise InvalidArgument("the bounce toss is planar; a body of revolution bounces in the bounce3d toss")
        states = self.launch.states(lambda th: b0 + body(th), draws)
        index, valleys, _ = toss(body, states, e=self.e, mu=self.mu, rolling=self.rolling, g=self.launch.g, b0=b0,
                                 impacts=self.impacts, workers=self.workers, device=self.device)
        return valley_hits(index, outcome_sets(valleys, names, kind)), index < 0

    def to_dict(self) -> dict:
        return {"model": self.name, "e": self.e, "mu": self.mu, "rolling": self.rolling, "impacts": self.impacts,
                "launch": self.launch.to_dict()}

    @safe_repr
    def __repr__(self):
        rolling = f", rolling={self.rolling:g}" if self.rolling else ""
        return f"Bounce(e={self.e:g}, mu={self.mu:g}{rolling}, {self.launch!r})"
