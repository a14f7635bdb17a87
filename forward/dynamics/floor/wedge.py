"""The wedge limit: at the bottom of a valley of b(θ) the body on a floor in gravity is a wedge billiard.

Near a corner of the wall at the bottom of a valley, ``b(θ) ≈ b_min + k |θ − θ_min|`` (slopes ±k), and a body
whose energy is just above the bottom stays so close to it that the floor is two straight lines: a point in
the field g inside a symmetric V, the gravitational wedge billiard of Lehtihet and Miller (Physica D 21, 93,
1986).  The half-angle φ of the wedge (from the vertical) is ``cot φ = k``.  A dumbbell (two equal point
masses at the ends of a massless rod of length 2κ) has the wall ``|cos θ|``, k = 1: φ = 45°, the integrable
case (the motion splits into two independent bounces, along each wall's normal, with the field's
components g/√2 — the normal velocity towards each wall is only ever reversed by that wall).  Between 45°
and 90° the wedge is chaotic (a positive Lyapunov exponent, the statement checked here).

Three tables, one quantity (:func:`wedge_lyapunov`):

* ``"kernel"``: the compiled field kernel on the exact wedge :func:`wedge_wall`: straight walls of slope ±k
  for |θ − π/2| ≤ 1; the orbits are started with their level below k, so they never leave the V.
* ``"map"``: an independent plain-numpy wedge billiard, :func:`wedge_flight` (impacts as the larger root of a
  quadratic per wall, the specular reflection written out; it shares no code with the kernel).
* ``"dumbbell"``: the field kernel on the wall ``c |cos θ|`` of a body (a segment of half-length c κ: a
  dumbbell for c = 1) at a small level ``level`` above the valley's bottom; the wedge is its limit as the
  level goes to zero (the walls' curvature is a relative correction of order level²).

The exponent is Benettin's: a reference orbit and a companion a distance ``d0`` (times the start level)
away in (θ, η, θ̇, η̇) are compared at the same time, in the middle of the reference's flight after every
``every`` impacts, the logarithm of the growth accumulated and the companion put back at ``d0`` along the separation (as
:mod:`.lyapunov` does for the billiard).  The exponent is per impact; the dynamics is invariant under
``(θ, η) → s (θ, η)``, ``t → √s t`` about the wedge's vertex, so the exponent per impact does not depend on
the energy.  A regular orbit's separation grows linearly, so its finite-time exponent is about log(N)/N
after N impacts; :func:`.lyapunov.default_threshold` (3·log(N)/N) separates the two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_seed
from ...wall import Wall

__all__ = ["WEDGE_CAP", "WedgeLyapunov", "plot_wedge", "wedge_flight", "wedge_lyapunov", "wedge_slope", "wedge_wall"]

#: :func:`wedge_wall` is the exact V for |θ − π/2| ≤ WEDGE_CAP
WEDGE_CAP = 1.0
METHODS = ("kernel", "map", "dumbbell")
_LEVEL_SHARE = 0.4  # start levels as a share of k·WEDGE_CAP (the V is exact below it)
_MAX_RATIO = 1e8    # a segment whose separation grew more than this met the vertex on one orbit only


def wedge_slope(half_angle: float) -> float:
    """The wall slope k = cot φ of a wedge of half-angle φ (degrees, from the vertical, in (0, 90))."""
    try:
        phi = float(half_angle)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`half_angle` must be a number of degrees, got {half_angle!r}") from None
    if not 0.0 < phi < 90.0:
        raise InvalidArgument(f"`half_angle` must be between 0 and 90 degrees (exclusive), got {half_angle!r}")
    return 1.0 / math.tan(math.radians(phi))


def wedge_wall(half_angle: float) -> Wall:
    """The exact wedge of half-angle φ (degrees) as a wall: straight, ``b = k |θ − π/2|`` (k = cot φ) for
    ``|θ − π/2| ≤ 1``, a smooth hump elsewhere.

    ``b = k·max(|arcsin(clip(cos θ, ±sin 1.2))|, A (1 − sin θ)/2)`` with ``A = 2/(1 − cos 1)``: on [0, π]
    ``arcsin(cos θ) = π/2 − θ`` exactly (the clip, at |θ − π/2| = 1.2, keeps arcsin's derivative finite); the
    hump ``A(1 − cos x)/2`` (x = θ − π/2) is convex in |x| ≤ π/2, zero at x = 0 and equal to |x| at |x| = 1,
    so it is below the V inside and above it outside: the floor is the exact V for |x| ≤ 1 (:data:`WEDGE_CAP`),
    one valley, one maximum (at 3π/2, no flat parts).
    """
    clip = math.sin(1.2)
    hump = 1.0 / (1.0 - math.cos(WEDGE_CAP))
    return Wall.from_expression(f"k*max(abs(arcsin(min(max(cos(t), -{clip!r}), {clip!r}))), {hump!r}*(1 - sin(t)))",
                                {"k": wedge_slope(half_angle)})


def wedge_flight(slope: float, g: float, state, impacts: int):
    """``impacts`` impacts of a point in the field ``g`` inside the wedge ``η = slope·|θ − π/2|`` (plain numpy).

    Independent of the field kernel: from a state inside, the gap to the line ``η = σ k (θ − π/2)``
    (σ = ±1) is the quadratic ``c + B t − ½ g t²`` (c ≥ 0 inside, the wall just left has c = 0 up to
    rounding and B > 0), whose larger root is the next meeting with that line; the earlier of the two is
    the impact (before it both gaps are positive, so the point is on the wedge itself).  The velocity is
    reflected specularly, ``v − 2 (v·n) n`` with ``n = (−σk, 1)/√(1 + k²)``.  Returns the arrays
    ``time, theta, eta, v_theta, v_eta`` just after each impact.
    """
    k, g = float(slope), float(g)
    x, z, vx, vz = float(state[0]) - 0.5 * math.pi, float(state[1]), float(state[2]), float(state[3])
    norm = math.sqrt(1.0 + k * k)
    out = np.empty((impacts, 5))
    clock = 0.0
    for i in range(impacts):
        best, side = math.inf, 0
        for sigma in (-1.0, 1.0):
            c = z - sigma * k * x
            b = vz - sigma * k * vx
            disc = b * b + 2.0 * g * max(c, 0.0)
            t = (b + math.sqrt(disc)) / g
            if 0.0 < t < best:
                best, side = t, sigma
        x, z, vz = x + vx * best, z + vz * best - 0.5 * g * best * best, vz - g * best
        nx, nz = -side * k / norm, 1.0 / norm
        vn = vx * nx + vz * nz
        vx, vz = vx - 2.0 * vn * nx, vz - 2.0 * vn * nz
        clock += best
        out[i] = (clock, x + 0.5 * math.pi, z, vx, vz)
    return tuple(out[:, j] for j in range(5))


@dataclass(frozen=True, repr=False)
class WedgeLyapunov:
    """Largest Lyapunov exponent per impact of wedge orbits.

    Attributes
    ----------
    half_angle : float
        φ in degrees (the slope k = cot φ; for ``"dumbbell"``, the limit's half-angle atan(1/c)).
    method : str
        ``"kernel"``, ``"map"`` or ``"dumbbell"`` (module docstring).
    exponents : ndarray
        The finite-time exponent of each orbit (per impact).
    impacts : int
        Impacts of each reference orbit.
    discarded : int
        Segments left out because one orbit of the pair met the vertex and the other did not (their growth
        is not a linear one); expected 0.
    level : float or None
        For ``"dumbbell"``: the start level above the valley's bottom (κ).

    Examples
    --------
    >>> from coinwall.forward.dynamics import wedge_lyapunov
    >>> result = wedge_lyapunov(30.0, orbits=2, impacts=200, method="map")
    >>> result.exponents.shape, result.discarded
    ((2,), 0)
    """

    half_angle: float
    method: str
    exponents: np.ndarray
    impacts: int
    discarded: int
    level: float | None = None

    @property
    def exponent(self) -> float:
        """Mean of the orbits' exponents."""
        return float(np.mean(self.exponents))

    @property
    def stderr(self) -> float:
        """Standard error of the mean over the orbits (0 for one orbit)."""
        n = self.exponents.size
        return float(np.std(self.exponents, ddof=1) / math.sqrt(n)) if n > 1 else 0.0

    @property
    def threshold(self) -> float:
        """3·log(N)/N: the largest finite-time exponent a regular orbit reaches, times three."""
        return 3.0 * math.log(self.impacts) / self.impacts

    def to_dict(self) -> dict:
        return {"half_angle": self.half_angle, "method": self.method, "exponent": self.exponent,
                "stderr": self.stderr, "orbits": int(self.exponents.size), "impacts": self.impacts,
                "threshold": self.threshold, "discarded": self.discarded, "level": self.level}

    @safe_repr
    def __repr__(self):
        return (f"WedgeLyapunov(φ = {self.half_angle:g}°, {self.method}: λ = {self.exponent:.4g} ± {self.stderr:.2g} "
                f"per impact, {self.exponents.size} orbits × {self.impacts} impacts)")


def _at(record, j, start, g, t):
    """The state at time t on the flight after impact j of ``record`` (j = −1: from ``start`` at time 0)."""
    if j < 0:
        t0, th, eta, vt, ve = 0.0, *start
    else:
        t0, th, eta, vt, ve = (r[j] for r in record)
    s = t - t0
    return np.array([th + vt * s, eta + ve * s - 0.5 * g * s * s, vt, ve - g * s])


def _orbit_exponent(run, start, g, segments, every, d0, rng):
    """Benettin's exponent per impact of one orbit: ``run(state, n)`` gives the n impacts after ``state``."""
    a = np.asarray(start, dtype=float)
    direction = rng.normal(size=4)
    b = a + d0 * direction / np.linalg.norm(direction)
    total, counted, discarded = 0.0, 0, 0
    for _ in range(segments):
        ra = run(a, every + 1)
        t_star = 0.5 * (ra[0][every - 1] + ra[0][every])
        n = every + 4
        while True:
            rb = run(b, n)
            if rb[0][-1] > t_star:
                break
            n *= 2
        j = int(np.searchsorted(rb[0], t_star, side="right")) - 1
        sa = _at(ra, every - 1, a, g, t_star)
        sb = _at(rb, j, b, g, t_star)
        d = float(np.linalg.norm(sb - sa))
        if d / d0 > _MAX_RATIO or d == 0.0:
            discarded += 1
            direction = rng.normal(size=4)
            b = sa + d0 * direction / np.linalg.norm(direction)
        else:
            total += math.log(d / d0)
            counted += 1
            b = sa + (d0 / d) * (sb - sa)
        a = sa
    return total / max(1, counted * every), discarded


def _starts(slope, g, level, orbits, rng, centre=0.5 * math.pi):
    """States inside the V with the level (energy/g above the vertex) ``level``, random position and direction."""
    states = []
    while len(states) < orbits:
        x = rng.uniform(-0.5, 0.5) * level / slope
        z = rng.uniform(slope * abs(x), level)
        if z <= slope * abs(x) + 1e-3 * level or z >= 0.95 * level:
            continue
        speed = math.sqrt(2.0 * g * (level - z))
        angle = rng.uniform(0.0, 2.0 * math.pi)
        states.append([centre + x, z, speed * math.cos(angle), speed * math.sin(angle)])
    return np.array(states)


def wedge_lyapunov(half_angle: float, orbits: int = 8, impacts: int = 20_000, every: int = 10, d0: float = 1e-7,
                   seed=0, method: str = "kernel", level: float = 1e-3, g: float = 1.0) -> WedgeLyapunov:
    """Largest Lyapunov exponent per impact of the gravitational wedge of half-angle φ (module docstring).

    Parameters
    ----------
    half_angle : float
        φ in degrees, in (0, 90); for ``method="dumbbell"`` the wall is ``c |cos θ|`` with c = cot φ.
    orbits : int
        Orbits (random starts at one energy); the result's ``stderr`` is their spread.
    impacts : int
        Impacts per orbit (rounded down to a multiple of ``every``).
    every : int
        Impacts between renormalisations.
    d0 : float
        Separation of the companion orbit, relative to the start level (the scale of the orbits: the
        linear regime of the separation is a fixed share of it).
    seed : int
        Seed of the starts and the first separations.
    method : str
        ``"kernel"`` (the field kernel on :func:`wedge_wall`), ``"map"`` (:func:`wedge_flight`) or
        ``"dumbbell"`` (the field kernel on ``c |cos θ|`` at ``level`` above the bottom).
    level : float
        Start level above the vertex for ``"dumbbell"`` (κ); the wedge methods start at 0.4 of the cap.
    g : float
        The field (κ/s²); the exponent per impact does not depend on it.

    Returns
    -------
    WedgeLyapunov

    Raises
    ------
    InvalidArgument
        For a bad method, ``d0``, ``g`` or ``level``, or fewer impacts than ``every``.
    RuntimeError
        When the field kernel stops an orbit before its impacts are done.

    Examples
    --------
    Two orbits of the explicit wedge map at φ = 30°, 200 impacts each:

    >>> from coinwall.forward.dynamics import wedge_lyapunov
    >>> wedge_lyapunov(30.0, orbits=2, impacts=200, method="map")
    WedgeLyapunov(φ = 30°, map: λ = 0.01519 ± 0.0036 per impact, 2 orbits × 200 impacts)
    """
    slope = wedge_slope(half_angle)
    orbits = check_count("orbits", orbits)
    every = check_count("every", every)
    impacts = check_count("impacts", impacts)
    if impacts < every:
        raise InvalidArgument(f"`impacts` ({impacts}) must be at least `every` ({every})")
    if method not in METHODS:
        raise InvalidArgument(f"`method` must be one of {METHODS}, got {method!r}")
    if not (isinstance(d0, (int, float)) and 0.0 < d0 < 1e-3):
        raise InvalidArgument(f"`d0` must be a separation in (0, 1e-3), got {d0!r}")
    if not (isinstance(g, (int, float)) and 0.0 < g <= 1e6):
        raise InvalidArgument(f"`g` must be a field in (0, 1e6], got {g!r}")
    rng = np.random.default_rng(check_seed(seed))
    segments = impacts // every
    if method == "map":
        top = _LEVEL_SHARE * slope * WEDGE_CAP

        def run(state, n):
            return wedge_flight(slope, g, state, n)
    else:
        from .field import FieldTable, field_run

        if method == "kernel":
            table = FieldTable(wedge_wall(half_angle), g=g, e=1.0, settle=False)
            top = _LEVEL_SHARE * slope * WEDGE_CAP
        else:
            if not (isinstance(level, (int, float)) and 1e-6 <= level <= 0.5):
                raise InvalidArgument(f"`level` must be between 1e-6 and 0.5 (κ), got {level!r}")
            table = FieldTable(Wall.from_expression("c*abs(cos(t))", {"c": slope}), g=g, e=1.0, settle=False)
            top = float(level)

        def run(state, n):
            flight = field_run(table, state, n)
            if len(flight) < n:
                raise RuntimeError(f"the field kernel stopped after {len(flight)} impacts ({flight.status}) in the "
                                   "wedge, where every orbit bounces for ever")
            return flight.time, flight.theta, flight.eta, flight.v_theta, flight.v_eta
    starts = _starts(slope, g, top, orbits, rng)
    exponents, discarded = [], 0
    for start in starts:
        lam, lost = _orbit_exponent(run, start, g, segments, every, d0 * top, rng)
        exponents.append(lam)
        discarded += lost
    return WedgeLyapunov(float(half_angle), method, np.array(exponents), segments * every, discarded,
                         float(level) if method == "dumbbell" else None)


def plot_wedge(results, title: str = ""):
    """λ per impact against the half-angle (house style): one series per method among ``results`` (a list of
    :class:`WedgeLyapunov`), error bars 2σ over the orbits, and the regular orbits' 3·log(N)/N.  Returns the axes."""
    from ...formats.figure import new_figure

    _, ax = new_figure(figsize=(6.4, 4.8), constrained_layout=True)
    labels = {"map": "numpy wedge", "kernel": "field kernel, exact wedge", "dumbbell": "field kernel, c|cos θ| body"}
    markers = {"map": "o", "kernel": "s", "dumbbell": "^"}
    for method in ("map", "kernel", "dumbbell"):
        rows = sorted((r for r in results if r.method == method), key=lambda r: r.half_angle)
        if not rows:
            continue
        level = f" (level {rows[0].level:g})" if method == "dumbbell" else ""
        ax.errorbar([r.half_angle for r in rows], [r.exponent for r in rows], yerr=[2 * r.stderr for r in rows],
                    fmt=markers[method] + ("-" if method == "map" else ""), ms=5, capsize=2, lw=0.8, mfc="none"
                    if method != "map" else None, label=labels[method] + level)
    threshold = max(r.threshold for r in results)
    ax.axhline(threshold, color="k", ls="--", lw=0.8, label=f"3 log(N)/N = {threshold:.1e} (regular orbits below)")
    ax.axvline(45.0, color="0.6", ls=":", lw=0.8)
    ax.set_xlabel("wedge half-angle φ (degrees from the vertical)")
    ax.set_ylabel("largest Lyapunov exponent λ per impact")
    ax.set_title(title or "the wedge limit: integrable at 45°, chaotic from 45° to 90°", fontsize=9)
    ax.legend(fontsize=7)
    return ax
