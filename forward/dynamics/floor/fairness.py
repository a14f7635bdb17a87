"""Fairness of a bouncing toss: how many floor bounces make it fair, as a function of the restitution e.

The paper's coin application ends with the casinos' remark: dice are made to bounce (off a wall, on the
table) because bounces randomise the outcome.  Here the question is asked of the toss that lands
(:mod:`.field`, :mod:`.toss`): a hand launches the body with ``(v0, ω0)`` spread as a Gaussian about a
nominal toss; a croupier stops it at its n-th floor impact and reads the face that is down, i.e. the valley
of b(θ) the contact angle is in (n = 1 is Keller's coin, caught on landing).  A toss that has settled before
its n-th impact (its level below its valley's barrier: it can never change valley) or come to rest
(the chattering limit, below its barrier) keeps its outcome; one that came to rest above its barrier (it
slides: status ``slides`` of the kernel) has no outcome and is counted as undecided.

For each n = 1 … ``bounces`` the result holds the share of each outcome, the *bias*
``p_n − ½`` of the heads share among the decided tosses (``p_n = heads/(heads + tails)``) and its binomial
standard error ``√(p(1 − p)/n_decided)``.  :meth:`Fairness.fair_after` is the first n from which the bias
stays within a tolerance (0.001 for the casino question) *and* is resolved: its 2σ band lies inside the
tolerance, which needs about 10⁶ tosses for 0.001.  With few tosses the answer is ``None`` (unresolved),
never a guess.

How the n-th impact is reached (O(n) per toss, all tosses at once in the compiled kernel): the kernel is
run to the first floor contact (``catch``), the settling rule of the kernel is applied to each toss caught
(level below its barrier: settled; gap-opening rate below :attr:`.FieldTable.chatter`: at rest), and the
others are lifted off the floor before the next round: from the contact, moving away with normal rate
``u = η̇ − b'θ̇ > 0``, the gap is at least ``u s − ½ K s²`` with ``K = g + θ̇² max|b''|`` (the reference
stepper's bound, :func:`.reference.sample_bounds`), so the flight is free of impacts up to ``s = u/K``,
where the gap is at least ``u²/(2K)``; the state there is strictly inside the table (the kernel's
requirement for the parallel runs).  A toss whose certified gap there is below 20 contact tolerances is a
chattering one the kernel would have declared at rest; it is treated so.  Smooth walls only (a corner in
the way needs the kernel's own search, which the parallel entry point does not expose).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import json_numbers, safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_seed
from .field import FieldTable, field_run_many

__all__ = ["Fairness", "fairness", "fairness_curve", "plot_fairness"]

_CHUNK = 200_000  # tosses per pass (memory: about 0.2 kB per toss)


@dataclass(frozen=True, repr=False)
class Fairness:
    """Outcome shares of a bouncing toss stopped at its n-th floor impact, n = 1 … len(bounces).

    Attributes
    ----------
    e : float
        The coefficient of restitution.
    bounces : ndarray (k,)
        n = 1 … k.
    heads, tails, undecided : ndarray (k,)
        Shares of all tosses (they sum to 1).
    bias : ndarray (k,)
        ``heads/(heads + tails) − ½`` (nan when no toss is decided).
    stderr : ndarray (k,)
        Binomial standard error of ``bias``.
    settled : ndarray (k,)
        Share of the tosses whose outcome was decided (settled or at rest below the barrier) by the n-th impact.
    samples : int
    mean, sigma : tuple
        The launch spread: ``(v0, ω0)`` and their standard deviations.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable, fairness
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> smooth = FieldTable(coin, g=1.0, e=0.6)          # frictionless floor
    >>> result = fairness(smooth, (3.0, 0.15), (0.3, 0.02), height=1.2, bounces=5, samples=200)
    >>> result
    Fairness(e=0.6, 200 tosses, 5 bounces: last bias -0.2250 ± 0.0316, not shown fair to 0.001)
    >>> bool(abs(result.heads + result.tails + result.undecided - 1).max() < 1e-12)
    True
    """

    e: float
    bounces: np.ndarray
    heads: np.ndarray
    tails: np.ndarray
    undecided: np.ndarray
    bias: np.ndarray
    stderr: np.ndarray
    settled: np.ndarray
    samples: int
    mean: tuple
    sigma: tuple

    def fair_after(self, tolerance: float = 1e-3, sigmas: float = 2.0):
        """The first n from which ``|bias| + sigmas·stderr ≤ tolerance`` holds for every later n computed, or
        ``None`` when it never does (the toss is not shown fair to ``tolerance`` within the bounces computed —
        a biased settled outcome, or too few samples to resolve the tolerance)."""
        ok = np.abs(self.bias) + sigmas * self.stderr <= tolerance
        ok &= np.isfinite(self.bias)
        if not ok[-1]:
            return None
        bad = np.flatnonzero(~ok)
        return int(self.bounces[bad[-1] + 1]) if bad.size else int(self.bounces[0])

    def to_dict(self) -> dict:
        return {"e": self.e, "bounces": self.bounces.tolist(), "heads": json_numbers(self.heads),
                "tails": json_numbers(self.tails), "undecided": json_numbers(self.undecided),
                "bias": json_numbers(self.bias), "stderr": json_numbers(self.stderr),
                "settled": json_numbers(self.settled), "samples": self.samples, "mean_v0_omega0": list(self.mean),
                "sigma_v0_omega0": list(self.sigma), "fair_after_0.001": self.fair_after()}

    @safe_repr
    def __repr__(self):
        n = self.fair_after()
        fair = f"fair to 0.001 from bounce {n}" if n is not None else "not shown fair to 0.001"
        return (f"Fairness(e={self.e:g}, {self.samples} tosses, {self.bounces.size} bounces: last bias "
                f"{self.bias[-1]:+.4f} ± {self.stderr[-1]:.4f}, {fair})")


def _lift(table, states, curv):
    """States on the floor, moving away, advanced by the certified impact-free time u/K (module docstring).
    Returns (states, ok): ``ok`` False where the certified gap is below 20 contact tolerances."""
    th, eta, vt, ve = states.T
    _, d1, _ = table.wall.derivatives(th)
    u = ve - d1 * vt
    K = table.g + vt * vt * curv
    s = np.where(u > 0, u / K, 0.0)
    gap_bound = np.where(u > 0, 0.5 * u * u / K, 0.0)
    out = np.column_stack([th + vt * s, eta + ve * s - 0.5 * table.g * s * s, vt, ve - table.g * s])
    return out, gap_bound > 20.0 * table.tol


def fairness(table: FieldTable, mean, sigma, height: float, bounces: int = 30, samples: int = 100_000,
             theta0=None, seed=0, workers=None) -> Fairness:
    """Outcome shares of the toss stopped at its n-th floor impact, n = 1 … ``bounces`` (module docstring).

    Parameters
    ----------
    table : FieldTable
        A smooth wall in a field g > 0 (a floor, or a floor and a ceiling), frictionless.
    mean, sigma : pair of float
        The launch ``(v0, ω0)`` (κ/s, rad/s) and its standard deviations: ``(v0, ω0) ~ N(mean, diag(σ²))``.
    height : float
        Launch height of the centre of mass (κ), as in :func:`.toss.launch_states`.
    bounces : int
        Floor impacts to follow (the largest n).
    samples : int
        Tosses.
    theta0 : float, optional
        Launch orientation (default: heads' rest angle for a coin, see :func:`.toss.launch_states`).
    seed : int
        Seed of the launch draws.
    workers : int, optional
        Threads of the compiled kernel.

    Returns
    -------
    Fairness

    Raises
    ------
    InvalidArgument
        For a table without a field, a wall with corners, a floor with friction, a spread without a mean and
        two standard deviations ≥ 0, or more than 10000 bounces or 10^8 samples.

    Examples
    --------
    200 tosses launched heads up: all are heads at the first floor impact, and the bias moves with each
    bounce (far too few tosses for a fair verdict):

    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable, fairness
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> smooth = FieldTable(coin, g=1.0, e=0.6)          # frictionless floor
    >>> result = fairness(smooth, (3.0, 0.15), (0.3, 0.02), height=1.2, bounces=5, samples=200)
    >>> result.heads.round(3).tolist()
    [1.0, 0.655, 0.195, 0.295, 0.275]
    """
    from ..billiard.reference import sample_bounds
    from .toss import launch_states

    if not isinstance(table, FieldTable):
        raise InvalidArgument(f"`table` must be a FieldTable, got {type(table).__name__}")
    if table.g <= 0:
        raise InvalidArgument("a toss needs a field: `g` must be positive")
    if table.wall.kinks:
        raise InvalidArgument(f"`fairness` needs a smooth wall; {table.wall.description!r} has corners")
    if table.mu > 0.0:
        raise InvalidArgument("`fairness` stops each toss at its floor impacts on a frictionless floor (`mu` = 0); with "
                              "friction the contact phases between impacts are followed by `heads_fraction`")
    bounces = check_count("bounces", bounces)
    samples = check_count("samples", samples)
    if bounces > 10_000 or samples > 10 ** 8:
        raise InvalidArgument(f"`bounces` must be at most 10000 and `samples` at most 1e8, got {bounces} and {samples}")
    mean = tuple(float(x) for x in mean)
    sigma = tuple(float(x) for x in sigma)
    if len(mean) != 2 or len(sigma) != 2 or not all(math.isfinite(x) for x in mean + sigma) or min(sigma) < 0:
        raise InvalidArgument(f"the spread needs a mean (v0, ω0) and two standard deviations >= 0, got {mean}, "
                              f"{sigma}")
    _, curv, _ = sample_bounds(table.wall)
    land = table.landscape
    names = land.names
    heads_k = names.index("heads") if "heads" in names else 0
    counts = np.zeros((bounces, 3))  # heads, tails (any other valley), undecided
    settled_counts = np.zeros(bounces)
    rng = np.random.default_rng(check_seed(seed))
    done = 0
    while done < samples:
        m = min(_CHUNK, samples - done)
        v = rng.normal(mean[0], sigma[0], m)
        w = rng.normal(mean[1], sigma[1], m)
        states = launch_states(table, v, w, height, theta0)
        outcome = np.full(m, -1, dtype=np.int64)     # the valley now (at the last impact, or decided)
        decided = np.zeros(m, dtype=bool)
        lost = np.zeros(m, dtype=bool)               # sliding above the barrier, or a kernel failure
        alive = np.ones(m, dtype=bool)
        for n in range(bounces):
            idx = np.flatnonzero(alive)
            if idx.size:
                out = field_run_many(table, states[idx], 1, catch=True, workers=workers)
                caught = out["status"] == 2
                lost[idx[~caught]] = True
                alive[idx[~caught]] = False
                idx, fin, valley = idx[caught], out["final"][caught], out["valley"][caught]
                outcome[idx] = valley
                th, eta, vt, ve = fin.T
                level = eta - table.b0 + 0.5 * (vt * vt + ve * ve) / table.g
                below = level < land.barriers[valley]
                _, d1, _ = table.wall.derivatives(th)
                rest = (ve - d1 * vt) < table.chatter
                lifted, ok = _lift(table, fin, curv)
                rest |= ~ok
                decided[idx[below]] = True
                lost[idx[~below & rest]] = True
                alive[idx[below | rest]] = False
                go = ~(below | rest)
                states[idx[go]] = lifted[go]
            heads = (outcome == heads_k) & ~lost
            tails = (outcome >= 0) & (outcome != heads_k) & ~lost
            counts[n] += [heads.sum(), tails.sum(), m - heads.sum() - tails.sum()]
            settled_counts[n] += decided.sum()
        done += m
    shares = counts / samples
    decided_n = counts[:, 0] + counts[:, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        p = counts[:, 0] / decided_n
        stderr = np.sqrt(p * (1 - p) / decided_n)
    return Fairness(table.e, np.arange(1, bounces + 1), shares[:, 0], shares[:, 1], shares[:, 2], p - 0.5, stderr,
                    settled_counts / samples, samples, mean, sigma)


def fairness_curve(wall, restitutions, mean, sigma, height: float, g: float = 1.0, b0: float = 0.0,
                   bounces: int = 30, samples: int = 100_000, tolerance: float = 1e-3, seed=0, workers=None):
    """:func:`fairness` for each e of ``restitutions`` (a floor only): a list of :class:`Fairness`, and the
    bounces after which each is fair to ``tolerance`` (``None``: not shown within ``bounces``).

    Parameters
    ----------
    wall : Wall
        A smooth wall.
    restitutions : sequence of float
        The coefficients of restitution e, one :class:`Fairness` each.
    mean, sigma, height, bounces, samples, seed, workers
        As for :func:`fairness`.
    g : float
        The field (κ/s²).
    b0 : float
        Offset added to the wall.
    tolerance : float
        ``|bias|`` at which a toss counts as fair.

    Returns
    -------
    curves : list of Fairness
        One per restitution.
    fair_after : list of int or None
        The bounces after which each is fair to ``tolerance`` (within twice its standard error), ``None``
        when not shown within ``bounces``.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import fairness_curve
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> curves, fair_after = fairness_curve(coin, [0.6], (3.0, 0.15), (0.3, 0.02), 1.2, bounces=5, samples=200)
    >>> len(curves), fair_after
    (1, [None])
    """
    results = []
    for e in restitutions:
        table = FieldTable(wall, g=g, e=float(e), b0=b0)
        results.append(fairness(table, mean, sigma, height, bounces=bounces, samples=samples, seed=seed,
                                workers=workers))
    return results, [r.fair_after(tolerance) for r in results]


def plot_fairness(results, tolerance: float = 1e-3, title: str = ""):
    """Two panels (house style): |bias| after n floor bounces for each :class:`Fairness` of ``results`` (a list,
    one per e; error bars 2σ, the tolerance dashed), and the bounce from which each is fair to 0.01 and to
    ``tolerance`` against e (open markers: not shown within the bounces computed).  Returns the first axes."""
    from ...formats.figure import new_figure

    _fig, (ax, bx) = new_figure(1, 2, figsize=(12, 4.8), constrained_layout=True)
    for r in results:
        line, = ax.plot(r.bounces, np.abs(r.bias), "o-", ms=3, lw=1, label=f"e = {r.e:g}")
        ax.fill_between(r.bounces, np.maximum(np.abs(r.bias) - 2 * r.stderr, 1e-5), np.abs(r.bias) + 2 * r.stderr,
                        color=line.get_color(), alpha=0.15, lw=0)
    ax.axhline(tolerance, color="k", ls="--", lw=0.8, label=f"{tolerance:g}")
    ax.axhline(0.01, color="0.5", ls=":", lw=0.8, label="0.01")
    ax.set_yscale("log")
    ax.set_ylim(1e-5, 0.5)
    ax.set_xlabel("floor bounce n at which the toss is stopped")
    ax.set_ylabel("|P(heads) − ½| among decided tosses (band: ±2σ)")
    ax.set_title(title or f"bias after n bounces ({results[0].samples} tosses per e)", fontsize=9)
    ax.legend(fontsize=7, ncol=2)
    es = np.array([r.e for r in results])
    top = max(int(r.bounces[-1]) for r in results)
    for tol, marker, colour in ((0.01, "s", "0.4"), (tolerance, "o", "C3")):
        n = [r.fair_after(tol) for r in results]
        shown = np.array([x is not None for x in n])
        values = np.array([x if x is not None else top + 1 for x in n], dtype=float)
        bx.plot(es[shown], values[shown], marker, color=colour, ls="-", label=f"fair to {tol:g} (2σ resolved)")
        bx.plot(es[~shown], values[~shown], marker, color=colour, mfc="none", ls="none",
                label=f"not shown fair to {tol:g} within {top} bounces")
    bx.set_xlabel("coefficient of restitution e")
    bx.set_ylabel("bounces to a fair toss")
    bx.set_ylim(0, top + 2)
    bx.legend(fontsize=7)
    bx.set_title("the casinos' bounce", fontsize=9)
    return ax
