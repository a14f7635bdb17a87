"""KAM boundary of the elliptic billiard: for each H, the ε above which no measurable regular region remains.

Criterion (stated, adjustable): at a given (ε, H), ``orbits`` Liouville-random
orbits are classified by their largest Lyapunov exponent
(:func:`coinwall.forward.dynamics.analysis.lyapunov.chaotic_fraction`, threshold ``3·log(N)/N`` per
collision over N collisions).  The motion counts as *fully chaotic* when the
regular fraction is below ``regular_max`` (default 1 %; with the default 100
orbits that means no regular orbit at all).  ε_c(H) is found by bisection in
log ε inside ``bracket`` (``steps`` halvings).  The bisection assumes the
regular fraction falls monotonically with ε; islands that reappear above the
bracket point found are not searched for.  Islands smaller than about
1/orbits of phase space are below the resolution of the criterion.

Caveat (docs/dynamics.md, "Criterion sensitivity"): the assumption is
violated.  Near the boundary the regular fraction is ~1 % in islands around a
stable tilted period-2 orbit, which exists over a wide window of ε (at H = 2,
from ε ≈ 4.05 to ≈ 21.8), and it is not monotonic in ε; whether 100 orbits hit an
island there is luck, so the ε_c found moves by factors of several with the seed.
Treat the result as one sign change of the criterion, not as *the* boundary.

The paper's fit (eq. 20): ``ε ≈ 1/H + 17/H²``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import json_numbers, safe_repr
from ...errors import InvalidArgument
from ...validation import check_count
from ...wall import Wall
from ..billiard.table import Billiard
from .islands import ELLIPSE_WALL, paper_boundary
from .lyapunov import chaotic_fraction

__all__ = ["KamBoundary", "kam_boundary"]

KAM_WORK_MAX = 1e10   # collision-equivalents one kam_boundary call may take (about an hour; see kam_boundary)
_ROUND_COST = 2000    # one renormalisation round's Python overhead, in collisions (~0.7 ms at 3e6 collisions/s)


@dataclass(frozen=True, repr=False)
class KamBoundary:
    """Measured KAM boundary ε_c(H).

    Attributes
    ----------
    H : ndarray (k,)
    eps_low, eps_high : ndarray (k,)
        Final bisection bracket: at ``eps_low`` a regular region was found, at
        ``eps_high`` none (NaN/inf when the bracket did not straddle the boundary).
    eps : ndarray (k,)
        Geometric mean of the bracket (the estimate); NaN where the bracket held no boundary
        (:meth:`not_found`), never an answer.
    paper : ndarray (k,)
        ``1/H + 17/H²``.
    orbits, collisions : int
        Orbits per (ε, H) and collisions per orbit.
    regular_max : float
        Criterion: regular fraction below this counts as fully chaotic.
    history : tuple
        Per H, the list of (ε, regular fraction) evaluated.

    Examples
    --------
    A run costs seconds (orbits of the ellipse at each bisection step); the paper's fit ``ε ≈ 1/H + 17/H²``
    (:func:`~coinwall.forward.paper_boundary`) is what it is compared with:

    >>> from coinwall.forward import paper_boundary
    >>> [round(float(paper_boundary(H)), 4) for H in (5.0, 10.0, 20.0)]
    [0.88, 0.27, 0.0925]
    """

    H: np.ndarray
    eps_low: np.ndarray
    eps_high: np.ndarray
    eps: np.ndarray
    paper: np.ndarray
    orbits: int
    collisions: int
    regular_max: float
    history: tuple

    def to_dict(self) -> dict:
        return {"H": json_numbers(self.H), "eps": json_numbers(self.eps), "eps_low": json_numbers(self.eps_low),
                "eps_high": json_numbers(self.eps_high),
                "paper": json_numbers(self.paper), "orbits": self.orbits, "collisions": self.collisions,
                "regular_max": self.regular_max, "not_found": self.not_found(),
                "criterion": f"regular fraction < {self.regular_max:g} among {self.orbits} Liouville-random orbits, "
                             f"orbit regular if lambda/collision <= 3 log(N)/N over N = {self.collisions}",
                "history": [[[float(e), float(f)] for e, f in h] for h in self.history]}

    def table(self) -> str:
        """Plain-text table H, ε_c (bracket), paper, ratio; "—" where the bracket held no boundary
        (:meth:`not_found` says why)."""
        lines = ["     H    eps_c   [low, high]          paper   ratio"]
        for h, e, lo, hi, p in zip(self.H, self.eps, self.eps_low, self.eps_high, self.paper):
            if math.isfinite(e):
                lines.append(f"{h:6.3g} {e:8.4g}   [{lo:.4g}, {hi:.4g}]   {p:8.4g}   {e / p:5.3f}")
            else:
                lines.append(f"{h:6.3g} {'—':>8}   {'(not found)':18}   {p:8.4g}   {'—':>5}")
        return "\n".join(lines)

    def not_found(self) -> list[str]:
        """One sentence per H whose bracket held no boundary: why, and what to change."""
        out = []
        for h, e, lo, hi in zip(self.H, self.eps, self.eps_low, self.eps_high):
            if math.isfinite(e):
                continue
            if not math.isfinite(hi):
                out.append(f"H = {h:g}: no ε_c found: a regular region remains at the top of the bracket, ε = "
                           f"{lo:.4g}; raise the bracket's top")
            else:
                out.append(f"H = {h:g}: no ε_c found: the motion is already fully chaotic at the bottom of the "
                           f"bracket, ε = {hi:.4g}; lower the bracket's bottom")
        return out

    def plot(self, ax=None):
        """ε_c(H) with its bracket against the paper's curve ``1/H + 17/H²``.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; default a new figure (Agg backend, no display needed).

        Returns
        -------
        matplotlib Axes
            Its ``.figure`` is the Figure (e.g. for :func:`~coinwall.forward.formats.figure.figure_bytes`).
        """
        from ...formats.figure import axes_or_new
        from ...formats.style import house_style, plain_log_axis

        with house_style():
            ax, own = axes_or_new(ax, (6.4, 4.4))
            grid = np.linspace(min(self.H.min(), 1.5), self.H.max() * 1.1, 200)
            ax.plot(grid, paper_boundary(grid), "k-", label=r"paper: $1/H + 17/H^2$")
            ax.errorbar(self.H, self.eps, yerr=[self.eps - self.eps_low, self.eps_high - self.eps], fmt="o",
                        label=f"measured: bisection bracket (regular < {self.regular_max:.0%})")
            ax.set_yscale("log")
            # one number format for every label, major and minor: 0.5, 2, 40 (not 6×10⁰ beside 1.0)
            plain_log_axis(ax.yaxis)
            ax.set_xlabel("wall distance H (κ)")
            ax.set_ylabel("critical ellipse parameter ε_c (dimensionless)")
            ax.set_title("KAM boundary of the ellipse wall sqrt((1+ε cos²θ)/(1+ε))\n"
                         f"{self.orbits} orbits × {self.collisions} collisions per (ε, H)")
            # below the axes: the measured points may lie anywhere around the paper's curve
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
            if own:
                ax.figure.tight_layout()
        return ax

    @safe_repr
    def __repr__(self) -> str:
        pairs = ", ".join(f"H={h:g}: {e:.3g}" for h, e in zip(self.H, self.eps))
        return f"KamBoundary({pairs}; criterion regular < {self.regular_max:g}, {self.orbits} orbits)"


def kam_boundary(H_values, bracket=(0.05, 50.0), steps: int = 7, orbits: int = 100, collisions: int = 1000,
                 regular_max: float = 0.01, seed: int = 0, workers=None, progress=None,
                 device: str = "cpu") -> KamBoundary:
    """ε_c(H) for the paper's ellipse wall by bisection on log ε (module docstring).

    Parameters
    ----------
    H_values : sequence of float
        Wall distances (units of κ); the table must be open at the smallest ε
        of the bracket (H > 2/√(1+ε_low)), else InvalidArgument.
    bracket : (float, float)
        Initial ε interval.
    steps : int
        Bisection steps (final bracket ratio ``(high/low)^(1/2^steps)``).
    orbits, collisions : int
        Orbits per evaluation and collisions per orbit.
    regular_max : float
        Regular fraction below which the motion counts as fully chaotic.
    seed : int
    workers : int, optional
        CPU threads.
    progress : callable, optional
        Called after each evaluation with no argument.
    device : {"cpu", "gpu"}
        Where the orbits are computed (:func:`.lyapunov.lyapunov_many`).

    Returns
    -------
    KamBoundary
        ε_c for each H, with the bracket each bisection ended on.

    Raises
    ------
    InvalidArgument
        For H values that are not finite and positive or leave the table closed at the bracket's low end,
        a bad bracket or ``regular_max``, or a run above the work bound.

    Examples
    --------
    The bisection runs the Lyapunov classification of :func:`chaotic_fraction` at each step (seconds at
    these sizes). A table closed at the bracket's low end is refused before any work:

    >>> from coinwall import kam_boundary
    >>> from coinwall.forward import paper_boundary
    >>> round(float(paper_boundary(10.0)), 6)                # the paper's eq. 20 at H = 10
    0.27
    >>> kam_boundary([1.0])
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidArgument: `H` = 1 leaves no room for motion (the walls overlap at every angle); need H > 1.9518 = min over θ of 2·b0 + b(θ) + b(θ+π)

    Notes
    -----
    Work bound, checked before any work: each of the ``len(H_values)·(steps + 2)`` evaluations follows
    ``orbits`` orbits and their companions through ``collisions/10 + 3`` renormalisation rounds of 12
    collisions each (:func:`.lyapunov.lyapunov_many`, ``every = 10``), and each round costs about
    2000 collisions of Python overhead; a request above :data:`KAM_WORK_MAX` = 1e10 of those (about an
    hour at 3·10^6 collisions/s) is refused.
    """
    from ..billiard.gpu import check_device

    check_device(device)
    H_values = np.atleast_1d(np.asarray(H_values, dtype=float))
    if H_values.size == 0 or np.any(~np.isfinite(H_values)) or np.any(H_values <= 0.0):
        raise InvalidArgument(f"`H` values must be finite and positive (units of κ), got {H_values.tolist()}")
    lo0, hi0 = (float(v) for v in bracket) if len(bracket) == 2 else (math.nan, math.nan)
    if not (0 < lo0 < hi0 and math.isfinite(hi0)):
        raise InvalidArgument(f"`bracket` must be two numbers 0 < low < high, got {bracket!r}")
    steps = check_count("steps", steps, minimum=0)
    orbits = check_count("orbits", orbits)
    collisions = check_count("collisions", collisions)
    evaluations = H_values.size * (steps + 2)
    work = evaluations * (-(-collisions // 10) + 3) * (24.0 * orbits + _ROUND_COST)
    if work > KAM_WORK_MAX:
        raise InvalidArgument(f"`collisions` = {collisions} with `orbits` = {orbits} over {evaluations} evaluations "
                              f"({H_values.size} H × (steps + 2)) is about {work:.3g} collisions of work (each orbit "
                              f"with its companion, plus {_ROUND_COST} a renormalisation round), more than the "
                              f"{KAM_WORK_MAX:g} (about an hour) one run does; lower collisions, orbits or steps")
    for H in H_values:  # the narrowest table is the one at the smallest ε: refuse before any work
        Billiard(Wall.from_expression(ELLIPSE_WALL, {"eps": lo0}), float(H))
    if not (0 < regular_max < 1):
        raise InvalidArgument(f"`regular_max` must be in (0, 1), got {regular_max!r}")

    def regular(eps, H):
        wall = Wall.from_expression(ELLIPSE_WALL, {"eps": eps})
        frac = chaotic_fraction(Billiard(wall, H), orbits, collisions, seed=seed, workers=workers, device=device)
        if progress is not None:
            progress()
        return frac.regular_fraction

    lows, highs, history = [], [], []
    for H in H_values:
        hist = []
        lo, hi = lo0, hi0
        f_hi = regular(hi, H)
        hist.append((hi, f_hi))
        if f_hi >= regular_max:  # still regular at the top of the bracket
            lows.append(hi), highs.append(math.inf), history.append(tuple(hist))
            continue
        f_lo = regular(lo, H)
        hist.append((lo, f_lo))
        if f_lo < regular_max:  # already chaotic at the bottom
            lows.append(0.0), highs.append(lo), history.append(tuple(hist))
            continue
        for _ in range(steps):
            mid = math.sqrt(lo * hi)
            f = regular(mid, H)
            hist.append((mid, f))
            if f < regular_max:
                hi = mid
            else:
                lo = mid
        lows.append(lo), highs.append(hi), history.append(tuple(hist))
    lows, highs = np.array(lows), np.array(highs)
    with np.errstate(invalid="ignore"):
        eps = np.where(np.isfinite(highs) & (lows > 0), np.sqrt(lows * highs), np.nan)
    return KamBoundary(H=H_values, eps_low=lows, eps_high=highs, eps=eps, paper=paper_boundary(H_values),
                       orbits=int(orbits), collisions=int(collisions), regular_max=float(regular_max),
                       history=tuple(history))
