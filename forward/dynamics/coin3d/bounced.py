"""Bounced tosses: the DHM toss landing on a frictionless floor (or between two walls), side by bounce.

The toss (SI units in, the billiard's units inside): a coin of radius ``radius`` and ``thickness`` leaves the
hand heads up (θ = 0) at ``height`` above the floor, upward speed uniform in ``speed``, spin |L|/I₁ normal
with mean and spread ``spin``, its angular momentum at the angle ψ from the normal (so
``ℓ_z = ℓ₃ = Ω cos ψ``, ``θ̇(0) = Ω sin ψ``).  It falls onto the floor and bounces with Newton's
restitution ``e`` (:mod:`.top`).  :func:`same_side_by_bounce` reports, for every n up to ``bounces``, the
probability that the side up (the sign of cos θ) at the n-th floor impact is the side it started with:
the coin stopped dead at its n-th bounce (n = 0 would be the catch).  A toss whose energy falls below the
equator's barrier keeps its side for ever (:func:`.top.sides_at_bounces`).

Why bounces do not make the frictionless coin fair.  A frictionless floor conserves ``L_z`` and ``L₃``
(:mod:`.top`); the toss starts with ``L_z = L₃ = |L| cos ψ``, and lying flat tails up would need
``L₃ = −L_z``.  The top's potential ``V = ℓ₃² tan²(θ/2)/2`` (ℓ_z = ℓ₃) is a well at heads-up and a wall at
tails-up, so as the bounces take energy away the coin is held on the side it started on: the share of the
start side *grows* with the bounces.  Friction at the floor (a tangential impulse, whose torque changes L_z
and L₃) is what a real coin needs to forget its start.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_finite, check_seed

__all__ = ["BounceStudy", "plot_studies", "same_side_by_bounce"]


@dataclass(frozen=True, repr=False)
class BounceStudy:
    """``same[n−1]``: P(side up at the n-th floor impact = start side), ``stderr`` its binomial error over the
    tosses that reached that impact (``reached``); ``settled``: the share settled below the equator's
    barrier within the bounces; ``status``: counts of :data:`.top.STATUS` codes; the inputs.

    Attributes
    ----------
    same : ndarray (bounces,)
        P(side up at the n-th floor impact = start side).
    stderr : ndarray (bounces,)
        Its binomial standard error.
    reached : ndarray of int (bounces,)
        Tosses that reached the n-th impact.
    settled : float
        Share settled below the equator's barrier within the bounces.
    status : dict
        Counts of the kernel's status codes.
    inputs : dict
        The parameters of the study.

    Examples
    --------
    >>> from coinwall.forward.dynamics import same_side_by_bounce
    >>> study = same_side_by_bounce(80.0, 0.5, samples=200, bounces=3, seed=0)
    >>> study.same.tolist(), study.reached.tolist()
    ([0.53, 0.555, 0.555], [200, 200, 200])
    """

    same: np.ndarray
    stderr: np.ndarray
    reached: np.ndarray
    settled: float
    status: dict
    inputs: dict

    @property
    def enough(self) -> np.ndarray:
        """Whether each bounce was reached by enough tosses for its share (:data:`~coinwall.forward.estimates.MIN_SAMPLES`)."""
        from ...estimates import MIN_SAMPLES

        return self.reached >= MIN_SAMPLES

    def shares(self) -> list:
        """P(same side) at each bounce as a :class:`~coinwall.forward.estimates.Share` (with its sample size)."""
        from ...estimates import share

        return [share(round(p * k), k) for p, k in zip(self.same, self.reached)]

    @property
    def failed(self) -> int:
        """Tosses the search could not follow (:data:`.top.STATUS` 7): missing data, not physics."""
        from .top import STATUS

        return int(self.status.get(STATUS[7], 0))

    def bounces_to_fair(self, within: float = 0.001):
        """The first n with ``|P − ½| < within`` by more than two standard errors' margin, among the bounces
        reached by enough tosses (None if none)."""
        ok = (np.abs(self.same - 0.5) + 2 * self.stderr < within) & self.enough
        idx = np.flatnonzero(ok)
        return int(idx[0]) + 1 if idx.size else None

    def to_dict(self) -> dict:
        """JSON-ready: each bounce's share is null where fewer than enough tosses reached it."""
        ok = self.enough
        return {"same": [float(p) if k else None for p, k in zip(self.same, ok)],
                "stderr": [float(e) if k else None for e, k in zip(self.stderr, ok)],
                "reached": self.reached.tolist(), "enough": ok.tolist(), "failed": self.failed,
                "settled": self.settled, "status": self.status, "inputs": self.inputs,
                "bounces_to_fair_0.001": self.bounces_to_fair()}

    @safe_repr
    def __repr__(self):
        head = ", ".join(f"{p:.4f}" if k else "—" for p, k in zip(self.same[:5], self.enough[:5]))
        return (f"BounceStudy(e={self.inputs['e']:g}, ψ={self.inputs['psi_degrees']:g}°: P(same) by bounce "
                f"{head}{', …' if self.same.size > 5 else ''}; settled {self.settled:.3f})")


def same_side_by_bounce(psi_degrees: float, e: float, samples: int = 10_000, bounces: int = 10, seed=None,
                        radius: float = 0.012, thickness: float = 0.00175, height: float = 1.0,
                        speed=(2.2, 2.7), spin=(240.0, 20.0), g: float = 9.81, ceiling: float | None = None,
                        progress=None):
    """Simulate ``samples`` tosses (see the module docstring); lengths in metres, speeds in m/s, spin in rad/s.
    ``ceiling``: a second wall that high above the floor (m; the paper's two walls), else none.  ``progress``
    is called with the number of tosses done after each batch (batches of about 20,000 toss-bounces, a
    fraction of a second each, so that Ctrl-C is answered within a second); the result does not depend on it.

    Parameters
    ----------
    psi_degrees : float
        The angle ψ between the angular momentum and the coin's normal (degrees, in [0, 180]).
    e : float
        Restitution of the floor.
    samples : int
        Tosses.
    bounces : int
        Floor impacts followed.
    seed : int, optional
        Seed of the launches.
    radius, thickness : float
        The coin (m).
    height : float
        Launch height (m).
    speed : (float, float)
        Range of launch speeds (m/s).
    spin : (float, float)
        Spin rate and its spread (rad/s).
    g : float
        Gravity (m/s²).
    ceiling : float, optional
        A second wall this high above the floor (m).
    progress : callable, optional
        Called with the tosses done after each batch.

    Returns
    -------
    BounceStudy

    Raises
    ------
    InvalidArgument
        For ψ outside [0, 180]°, a launch height below the coin's reach, a bad speed or spin range, or a
        ceiling below the launch.

    Examples
    --------
    A 1-euro-sized coin at ψ = 80° bouncing on a floor with e = 0.5:

    >>> from coinwall.forward.dynamics import same_side_by_bounce
    >>> same_side_by_bounce(80.0, 0.5, samples=200, bounces=3, seed=0)
    BounceStudy(e=0.5, ψ=80°: P(same) by bounce 0.5300, 0.5550, 0.5550; settled 0.000)
    """
    from ...revolution import coin
    from .top import STATUS, TopTable, sides_at_bounces

    psi = math.radians(check_finite("psi_degrees", psi_degrees))
    if not 0 <= psi <= math.pi:
        raise InvalidArgument(f"`psi_degrees` must be in [0, 180], got {psi_degrees:g}")
    samples = check_count("samples", samples, maximum=10_000_000)
    bounces = check_count("bounces", bounces, maximum=10_000)
    body = coin(radius, thickness)
    k1 = body.kappa1
    g = check_finite("g", g)
    height = check_finite("height", height)
    if not height > body.reach:
        raise InvalidArgument(f"`height` must be above the coin's reach {body.reach:g} m, got {height:g}")
    lo, hi = (check_finite("speed", s) for s in speed)
    mean, sd = (check_finite("spin", s) for s in spin)
    if not (lo <= hi and sd >= 0):
        raise InvalidArgument(f"`speed` must be LO <= HI and the spin's spread >= 0, got {speed!r}, {spin!r}")
    H = None
    if ceiling is not None:
        H = check_finite("ceiling", ceiling) / k1
        if not ceiling > height + body.reach:
            raise InvalidArgument(f"`ceiling` must be above the launch height plus the coin's reach, got {ceiling:g}")
    table = TopTable(body, g=g / k1, e=e, H=H)
    rng = np.random.default_rng(check_seed(seed))
    v = rng.uniform(lo, hi, samples) / k1
    om = np.abs(rng.normal(mean, sd, samples))
    states = np.column_stack([np.zeros(samples), np.full(samples, height / k1), om * math.sin(psi), v])
    ell = om * math.cos(psi)
    sides = np.empty((samples, bounces), dtype=np.int8)
    status = np.empty(samples, dtype=np.int64)
    batch = max(100, 20_000 // bounces)
    for lo in range(0, samples, batch):  # each toss is independent: batches give the same numbers as one call
        hi = min(samples, lo + batch)
        sides[lo:hi], status[lo:hi] = sides_at_bounces(table, states[lo:hi], ell[lo:hi], ell[lo:hi], bounces)
        if progress is not None:
            progress(hi - lo)
    reached = np.sum(sides != 0, axis=0)
    same = np.sum(sides == 1, axis=0) / np.maximum(reached, 1)
    stderr = np.sqrt(same * (1 - same) / np.maximum(reached, 1))
    codes, counts = np.unique(status, return_counts=True)
    inputs = {"psi_degrees": float(psi_degrees), "e": float(e), "samples": samples, "bounces": bounces, "seed": seed,
              "radius": radius, "thickness": thickness, "height": height, "speed": list(speed), "spin": list(spin),
              "g": g, "ceiling": ceiling}
    return BounceStudy(same, stderr, reached, float(np.mean(status == 1)),
                       {STATUS.get(int(c), str(int(c))): int(n) for c, n in zip(codes, counts)}, inputs)


def plot_studies(studies, caught: float | None = None):
    """P(same side) against the bounce for each study (one curve per restitution / setting), with ±2 standard
    errors; ``caught``: the caught share (a horizontal line)."""
    from ...formats.figure import new_figure
    from ...formats.style import house_style

    with house_style():
        fig, ax = new_figure(figsize=(7, 4.2), constrained_layout=True)
        for label, study in studies.items():
            ok = study.enough  # a bounce reached by too few tosses has no share to draw
            n = np.arange(1, study.same.size + 1)[ok]
            ax.errorbar(n, study.same[ok], yerr=2 * study.stderr[ok], marker="o", ms=3, capsize=2, lw=1, label=label)
        ax.axhline(0.5, color="k", lw=0.8, ls="--", label="fair")
        if caught is not None:
            ax.axhline(caught, color="0.4", lw=0.8, ls=":", label=f"caught in the hand (data): {caught:.4f}")
        first = next(iter(studies.values())).inputs
        ax.set_xlabel("floor impact n (count)")
        ax.set_ylabel("P(side up at impact n = start side) (dimensionless)")
        ax.set_title(f"frictionless coin, ψ = {first['psi_degrees']:.2f}°, {first['samples']} tosses per curve")
        ax.legend(loc="upper left")
    return fig
