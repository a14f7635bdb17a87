"""The basin-boundary (uncertainty) exponent of Grebogi, Ott and Yorke for the toss that lands.

A launch ``x = (v0, ω0)`` is *ε-uncertain* when the outcome (heads, tails, … or undecided) at ``x − εu`` or
``x + εu`` differs from the one at ``x``, for a direction u (here: random, in the launch box scaled to the unit
square).  The fraction of ε-uncertain launches in a box scales as ``f(ε) ∝ ε^α`` for small ε; α is the
uncertainty exponent, ``α = D − d`` with D = 2 the dimension of the launch plane and d the box-counting
dimension of the basin boundary (Grebogi, McDonald, Ott & Yorke, Phys. Lett. A 99, 415 (1983)).  α = 1 for a
smooth boundary; α < 1 for a fractal one, where a better hand (a smaller ε) buys little certainty.

Why α = 1 for a smooth boundary (the no-bounce toss, Keller's hyperbolas ω0 v0/g = π(n ± ¼)): the box holds
finitely many boundary curves, of total length L (in the scaled coordinates), each smooth.  A launch x at
distance s from a curve, whose normal there makes the angle φ with u, is uncertain iff ``ε |cos φ| ≥ s``
(the segment x ± εu crosses the curve once; for ε below the curves' radii of curvature and their spacing,
no other crossing).  So the uncertain set is a band of width ``2 ε |cos φ|`` about each curve, of area
``ε ∫ 2|cos φ| dl``, and averaging over the random direction (E|cos φ| = 2/π):
``f(ε) = (4/π) L ε / A + O(ε²)``, with A the box's area (1 here): α = 1, and the prefactor gives the
boundary length.

The exponent is fitted by weighted least squares to ``log f`` against ``log ε`` (weights from the binomial
errors, ``σ(log f) = √((1 − f)/(f n))``, each ε drawing its own launches, so the points are independent); its
standard error is the fit's, scaled up by √(χ²/dof) when the points scatter more than their errors.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import json_number, safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_seed
from .field import FieldTable

__all__ = ["Uncertainty", "plot_uncertainty", "uncertainty_exponent"]


@dataclass(frozen=True, repr=False)
class Uncertainty:
    """Fractions of ε-uncertain launches and the fitted exponent.

    Attributes
    ----------
    epsilons : ndarray
        ε, as a fraction of the launch box's sides.
    fractions : ndarray
        f(ε): the share of uncertain launches.
    counts : ndarray
        Uncertain launches, of ``samples`` per ε.
    samples : int
    alpha, alpha_stderr : float
        The fitted exponent and its standard error (nan when fewer than two ε have uncertain launches).
    prefactor : float
        ``f(ε) ≈ prefactor · ε^alpha``.
    v0, omega0 : tuple
        The launch box: ``(low, high)`` of the launch velocity and of the spin.
    e : float
        The restitution of the table (``catch``: the toss was caught at the floor).
    catch : bool

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> from coinwall.forward.dynamics import uncertainty_exponent
    >>> uncertainty_exponent(table, (2, 5), (0.05, 0.2), 1.2, epsilons=(0.01, 0.003), samples=100)
    Uncertainty(e = 0.6: α = 0.337 ± 0.196 from 2 ε in [0.003, 0.01], 100 launches each)
    """

    epsilons: np.ndarray
    fractions: np.ndarray
    counts: np.ndarray
    samples: int
    alpha: float
    alpha_stderr: float
    prefactor: float
    v0: tuple
    omega0: tuple
    e: float
    catch: bool

    def to_dict(self) -> dict:
        return {"epsilons": self.epsilons.tolist(), "fractions": self.fractions.tolist(),
                "counts": self.counts.tolist(), "samples": self.samples, "alpha": json_number(self.alpha),
                "alpha_stderr": json_number(self.alpha_stderr), "prefactor": json_number(self.prefactor),
                "v0": list(self.v0), "omega0": list(self.omega0), "e": self.e, "catch": self.catch}

    @safe_repr
    def __repr__(self):
        mode = "caught" if self.catch else f"e = {self.e:g}"
        return (f"Uncertainty({mode}: α = {self.alpha:.3f} ± {self.alpha_stderr:.3f} from {self.epsilons.size} ε in "
                f"[{self.epsilons.min():.2g}, {self.epsilons.max():.2g}], {self.samples} launches each)")


def _fit(eps, frac, n):
    """Weighted least squares of log f on log ε: (slope, its standard error, prefactor)."""
    use = frac > 0
    if use.sum() < 2:
        return math.nan, math.nan, math.nan
    x, f = np.log(eps[use]), frac[use]
    y = np.log(f)
    w = f * n / np.maximum(1.0 - f, 1e-12)        # 1/σ² of log f
    W, Wx, Wy = w.sum(), (w * x).sum(), (w * y).sum()
    Wxx, Wxy = (w * x * x).sum(), (w * x * y).sum()
    det = W * Wxx - Wx * Wx
    slope = (W * Wxy - Wx * Wy) / det
    intercept = (Wxx * Wy - Wx * Wxy) / det
    stderr = math.sqrt(W / det)
    dof = use.sum() - 2
    if dof > 0:
        chi2 = float((w * (y - intercept - slope * x) ** 2).sum())
        stderr *= max(1.0, math.sqrt(chi2 / dof))
    return float(slope), float(stderr), float(math.exp(intercept))


def uncertainty_exponent(table: FieldTable, v0, omega0, height: float, epsilons=(1e-2, 3e-3, 1e-3, 3e-4),
                         samples: int = 20_000, theta0=None, seed=0, impacts: int = 10_000, catch: bool = False,
                         workers=None, progress=None, device: str = "cpu") -> Uncertainty:
    """The uncertainty exponent of the toss's outcome over the launch box ``v0 × omega0`` (module docstring).

    Parameters
    ----------
    table : FieldTable
        The floor, field and restitution.
    v0, omega0 : pair of float
        The launch box: ``(low, high)`` of the launch velocity (κ/s) and of the spin (rad/s).
    height : float
        Launch height of the centre of mass (κ).
    epsilons : sequence of float
        ε as fractions of the box's sides, in (0, 0.1].
    samples : int
        Launches per ε (three tosses each).
    theta0, impacts, catch, workers, device
        As for :func:`.toss.basin_map` (``device="gpu"``: the tosses on a CUDA GPU).
    seed : int
        Seed of the launches and directions.
    progress : callable, optional
        Called with the number of tosses done after each batch (``3 * samples`` tosses per ε in all); the result
        does not depend on it.

    Returns
    -------
    Uncertainty
        f(ε) for each ε, with the fitted exponent α and its standard error.

    Raises
    ------
    InvalidArgument
        For a table without a field, a launch box that is not two pairs ``low < high``, or fewer than two ε
        in (0, 0.1].

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics import FieldTable
    >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
    >>> table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
    >>> from coinwall.forward.dynamics import uncertainty_exponent
    >>> result = uncertainty_exponent(table, (2, 5), (0.05, 0.2), 1.2, epsilons=(0.01, 0.003), samples=100)
    >>> result.counts.tolist(), result.samples
    ([33, 22], 100)
    """
    from ..billiard.gpu import check_device
    from .toss import _outcomes, launch_states

    if not isinstance(table, FieldTable):
        raise InvalidArgument(f"`table` must be a FieldTable, got {type(table).__name__}")
    if table.g <= 0:
        raise InvalidArgument("a toss needs a field: `g` must be positive")
    samples = check_count("samples", samples)
    impacts = check_count("impacts", impacts)
    check_device(device)  # (before any work)
    box = []
    for name, pair in (("v0", v0), ("omega0", omega0)):
        try:
            lo, hi = (float(x) for x in pair)
        except (TypeError, ValueError):
            raise InvalidArgument(f"`{name}` must be a pair (low, high), got {pair!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise InvalidArgument(f"`{name}` must be a pair of finite numbers low < high, got {pair!r}")
        box.append((lo, hi))
    eps = np.asarray(epsilons, dtype=float).ravel()
    if eps.size < 2 or not np.all(np.isfinite(eps)) or eps.min() <= 0 or eps.max() > 0.1:
        raise InvalidArgument(f"`epsilons` must be at least two numbers in (0, 0.1], got {list(np.ravel(epsilons))}")
    (vlo, vhi), (wlo, whi) = box
    rng = np.random.default_rng(check_seed(seed))
    counts = np.zeros(eps.size, dtype=np.int64)
    for i, e in enumerate(eps):
        # launches whose ±ε neighbours stay in the box
        u = rng.uniform(e, 1.0 - e, (samples, 2))
        angle = rng.uniform(0.0, 2.0 * math.pi, samples)
        d = e * np.column_stack([np.cos(angle), np.sin(angle)])
        pts = np.concatenate([u, u - d, u + d])
        v = vlo + (vhi - vlo) * pts[:, 0]
        w = wlo + (whi - wlo) * pts[:, 1]
        states = launch_states(table, v, w, height, theta0)
        outcome, _, _ = _outcomes(table, states, impacts, catch, workers, progress, device=device)
        mid, low, high = outcome[:samples], outcome[samples:2 * samples], outcome[2 * samples:]
        counts[i] = int(np.sum((low != mid) | (high != mid)))
    fractions = counts / samples
    alpha, stderr, prefactor = _fit(eps, fractions, samples)
    return Uncertainty(eps, fractions, counts, samples, alpha, stderr, prefactor, box[0], box[1], table.e, bool(catch))


def plot_uncertainty(results, title: str = ""):
    """f(ε) against ε (log–log, house style) for each :class:`Uncertainty` of ``results``, with its fitted
    power law and α in the legend, and the slope 1 of a smooth boundary for reference.  Returns the axes."""
    from ...formats.figure import new_figure

    _, ax = new_figure(figsize=(6.4, 4.8), constrained_layout=True)
    for r in results:
        err = np.sqrt(np.maximum(r.fractions * (1 - r.fractions), 0) / r.samples)
        label = ("caught (no bounce)" if r.catch else f"e = {r.e:g}") + f": α = {r.alpha:.3f} ± {r.alpha_stderr:.3f}"
        bars = ax.errorbar(r.epsilons, r.fractions, yerr=2 * err, fmt="o", ms=4, capsize=2, label=label)
        grid = np.geomspace(r.epsilons.min(), r.epsilons.max(), 50)
        ax.plot(grid, r.prefactor * grid ** r.alpha, "-", lw=0.8, color=bars[0].get_color())
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("ε (fraction of the launch box's sides)")
    ax.set_ylabel("f(ε): share of ε-uncertain launches")
    ax.set_title(title or "uncertainty exponent of the basin boundary", fontsize=9)
    ax.legend(fontsize=7)
    return ax
