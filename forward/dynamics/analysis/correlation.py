"""Heads/tails correlation of the coin: P(n), its decay time τ, and the bounces needed to forget.

Heads and tails
---------------
The paper (section III) puts an arrow along the coin's long axis and calls
"heads" the arrow pointing to the right.  The project's angle θ is measured
*clockwise from the downward wall normal to the body axis* (the arrow); the
rigid-body map in :mod:`coinwall.forward.dynamics.billiard.rigidbody` makes the axis' lab angle
``ψ = −θ − π/2``, so the arrow is the lab vector

    (cos ψ, sin ψ) = (−sin θ, −cos θ).

It points right when its x component is positive:

    heads  ⇔  sin θ < 0  ⇔  θ mod 2π ∈ (π, 2π);     tails ⇔ θ mod 2π ∈ (0, π).

(θ = 0: arrow straight down; θ = π/2: arrow to the left; θ = 3π/2: to the
right.)  The set sin θ = 0 has measure zero; it is counted as tails.  θ is
the body's orientation, the same coordinate at a bottom or a top collision.
Turning from heads to tails means crossing θ = 0 or π, where the coin
stands on its edge, which needs ``H > b(0) + b(π)`` (the coin's diameter D
for a symmetric coin); below that P(n) = 1 for every n.

P(n)
----
Default (``count="bottom"``): the probability that the state at a bottom
collision recurs ``n`` bottom collisions later.  ``count="all"``: from a
bottom collision, ``n`` collisions later counting both walls.

Statistics.  ``orbits`` independent orbits (Liouville-random starts), each
long; for each orbit the lag-n agreement frequency is computed over all its
bottom collisions (after dropping the first ``burn`` collisions, so the
start's non-stationary first flight does not count), and P(n) is the mean
over orbits with standard error ``std/√orbits`` — orbits are independent
blocks, so the error includes the correlations inside each orbit.  The decay
time τ comes from a weighted fit of ``P(n) − ½ = A exp(−n/τ)`` over lags
1 … max_lag; its standard error is a delete-one-group jackknife over groups
of orbits (the fit's own covariance would ignore that P at different lags
share the same orbits).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import json_number, safe_repr
from ...errors import InvalidArgument
from ...validation import check_choice, check_count, check_memory, is_integer
from ..billiard.table import Billiard, ensemble, random_states, simulate

__all__ = ["COUNTS", "Correlation", "TauLaw", "correlation", "fit_decay", "fit_tau_law", "heads"]

COUNTS = ("bottom", "all")
THRESHOLD = 0.01        # |P(n) − ½| below this: the paper's "non-asymptotic part reduced to 0.01"
_CHUNK_COLLISIONS = 2_000_000   # collisions held in memory at once
_GROUPS = 20            # jackknife groups
LAG_WORK_MAX = 2e11     # max_lag × (bounces + 1000·orbits) comparisons at most (a few minutes; see correlation)


def heads(theta):
    """True where the arrow (body axis) points right: ``sin θ < 0`` (module docstring).

    Parameters
    ----------
    theta : array_like
        Contact angles θ (radians).

    Returns
    -------
    ndarray of bool

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward import heads
    >>> heads(np.array([-0.5, 0.5])).tolist()
    [True, False]
    """
    return np.sin(np.asarray(theta, dtype=float)) < 0.0


def _positive_int(name, value):
    # not check_count: its message reads "an integer >= 1"; callers and tests read "positive integer"
    if not is_integer(value) or value <= 0:
        raise InvalidArgument(f"`{name}` must be a positive integer, got {value!r}")
    return int(value)


def _exp_model(n, amplitude, tau):
    return amplitude * np.exp(-n / tau)


def fit_decay(P, sigma, lags=None):
    """Weighted fit of ``P(n) − ½ = A exp(−n/τ)``; returns (A, τ) or (nan, nan) when it fails.

    The start values come from a straight-line fit of log|P − ½| on the lags where
    P − ½ exceeds twice its error; the fit itself is scipy's ``curve_fit``.
    """
    from scipy.optimize import curve_fit

    P = np.asarray(P, dtype=float)
    sigma = np.asarray(sigma, dtype=float)
    n = np.arange(P.size, dtype=float) if lags is None else np.asarray(lags, dtype=float)
    keep = n >= 1
    n, y, s = n[keep], P[keep] - 0.5, np.maximum(sigma[keep], 1e-12)
    if y.size < 2:
        return math.nan, math.nan
    if np.all(np.abs(y - y[0]) < 1e-15) and abs(y[0]) > 0:
        return float(y[0]), math.inf  # no decay at all (coin that cannot turn over)
    strong = np.abs(y) > 2 * s
    if strong.sum() >= 2:
        slope, intercept = np.polyfit(n[strong], np.log(np.abs(y[strong])), 1)
        tau0 = -1.0 / slope if slope < 0 else 10.0 * n.max()
        a0 = math.copysign(math.exp(intercept), y[strong][0])
    else:
        tau0, a0 = 1.0, float(y[0]) * math.e
    try:
        (amplitude, tau), _ = curve_fit(_exp_model, n, y, p0=(a0, tau0), sigma=s, absolute_sigma=True,
                                        bounds=([-np.inf, 1e-3], [np.inf, 1e9]), maxfev=20000)
    except (RuntimeError, ValueError):
        return math.nan, math.nan
    return float(amplitude), float(tau)


@dataclass(frozen=True, repr=False)
class Correlation:
    """Heads/tails correlation P(n) of a billiard.

    Attributes
    ----------
    P : ndarray (max_lag+1,)
        P(n) for n = 0 … max_lag (P(0) = 1 by definition).
    P_stderr : ndarray (max_lag+1,)
        Standard error of P(n) from the spread between orbits.
    heads_fraction, heads_stderr : float
        Fraction of bottom collisions showing heads and its standard error
        (½ for a body symmetric under θ → −θ).
    tau, tau_stderr : float
        Decay time of ``P(n) − ½ = A exp(−n/τ)`` (in counted collisions) and its
        jackknife standard error; ``inf`` when P never decays, NaN when the fit failed.
    amplitude : float
        A of the fit.
    n_needed : int or None
        First n with ``|P(n) − ½| < 0.01``; None if not reached by max_lag.
    n_needed_fit : float
        ``τ·log(|A|/0.01)``: where the fitted curve crosses 0.01.
    count : str
        ``"bottom"`` or ``"all"`` (module docstring).
    bounces : int
        Counted collisions used (after the burn-in), summed over orbits.
    orbits : int
        Independent orbits.
    max_lag : int
    table : Billiard
    seed : int or None
    notes : tuple of str

    Examples
    --------
    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import correlation
    >>> result = correlation(table, bounces=2000, max_lag=5, orbits=4, seed=0)
    >>> result.P.shape, result.orbits, result.count
    ((6,), 4, 'bottom')
    """

    P: np.ndarray
    P_stderr: np.ndarray
    heads_fraction: float
    heads_stderr: float
    tau: float
    tau_stderr: float
    amplitude: float
    n_needed: object
    n_needed_fit: float
    count: str
    bounces: int
    orbits: int
    max_lag: int
    table: Billiard
    seed: object = None
    notes: tuple = ()

    def to_dict(self) -> dict:
        """JSON-ready dictionary (non-finite numbers become None)."""
        return {"H": self.table.H, "b0": self.table.b0, "count": self.count, "bounces": self.bounces,
                "orbits": self.orbits, "max_lag": self.max_lag, "seed": self.seed,
                "P": [float(p) for p in self.P], "P_stderr": [float(p) for p in self.P_stderr],
                "heads_fraction": json_number(self.heads_fraction), "heads_stderr": json_number(self.heads_stderr),
                "tau": json_number(self.tau), "tau_stderr": json_number(self.tau_stderr),
                "tau_infinite": self.tau == math.inf, "amplitude": json_number(self.amplitude),
                "n_needed": self.n_needed, "n_needed_fit": json_number(self.n_needed_fit),
                "threshold": THRESHOLD, "notes": list(self.notes)}

    def decay_band(self):
        """How far one exponential describes P(n): ``(tau_low, tau_high, lags, leaves)``.

        ``[tau_low, tau_high]`` is the smallest range of τ around the fitted one (A fixed) whose curves
        ``A exp(−n/τ)`` pass within one standard error of every lag where ``|P(n) − ½|`` stands out of its error
        (more than twice it), and at least τ ± its jackknife error: the error to quote when P(n) is not one
        exponential.  ``lags`` are those lags; ``leaves`` the first of three lags in a row where the data stand
        off the fitted curve by more than twice their error and more than 10 % of it (None when none do).
        """
        n = np.arange(self.P.size, dtype=float)
        y, s = np.abs(self.P - 0.5), self.P_stderr
        if not (math.isfinite(self.tau) and math.isfinite(self.amplitude)) or self.amplitude == 0:
            return math.nan, math.nan, np.array([], dtype=int), None
        stat = self.tau_stderr if math.isfinite(self.tau_stderr) else 0.0
        low, high = self.tau - stat, self.tau + stat
        amplitude = abs(self.amplitude)
        fit = amplitude * np.exp(-n / self.tau)
        lags = np.flatnonzero((n >= 1) & (y > 2 * s))
        for k in lags:
            # the end of the data's error bar nearest the fitted curve, and the τ whose curve passes through it
            target = min(max(fit[k], y[k] - s[k]), y[k] + s[k])
            if 0 < target < amplitude:
                tau_k = -n[k] / math.log(target / amplitude)
                low, high = min(low, tau_k), max(high, tau_k)
        off = (n >= 1) & (np.abs(y - fit) > np.maximum(2 * s, 0.1 * fit))
        run = off[:-2] & off[1:-1] & off[2:]  # three lags in a row: not a fluctuation
        first = np.flatnonzero(run)
        return float(low), float(high), lags, (int(first[0]) if first.size else None)

    def plot(self, ax=None, name=None):
        """``|P(n) − ½|`` with error bars on a log scale, the fitted exponential with the band of τ that covers
        the data (:meth:`decay_band`) and the 0.01 threshold.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; default a new figure (Agg backend, no display needed).
        name : str, optional
            The wall as the user wrote it (``case:coin``) for the title; default its description.

        Returns
        -------
        matplotlib Axes
            Its ``.figure`` is the Figure (e.g. for :func:`~coinwall.forward.formats.figure.figure_bytes`).
        """
        from ...formats.figure import axes_or_new
        from ...formats.style import PALETTE, house_style, legend_below, plain_log_axis, wall_label

        with house_style():
            ax, own = axes_or_new(ax, (6.4, 4.4))
            n = np.arange(self.P.size)
            y = np.abs(self.P - 0.5)
            ax.errorbar(n, y, yerr=self.P_stderr, fmt="o", ms=3, color="k", elinewidth=0.8,
                        label="|P(n) − ½| ± standard error")
            if math.isfinite(self.tau):
                low, high, lags, leaves = self.decay_band()
                grid = np.linspace(0, n[-1], 400)
                curve = abs(self.amplitude) * np.exp(-grid / self.tau)
                ax.plot(grid, curve, "-", color=PALETTE[1],
                        label=f"one exponential A e^(−n/τ): τ = {self.tau:.3g} ± {self.tau_stderr:.2g} "
                              "(statistical)")
                if lags.size:
                    ax.fill_between(grid, abs(self.amplitude) * np.exp(-grid / low),
                                    abs(self.amplitude) * np.exp(-grid / high), color=PALETTE[1], alpha=0.18, lw=0,
                                    label=f"τ from {low:.3g} to {high:.3g}: covers every lag out of the noise "
                                          f"(1–{int(lags.max())})")
                if leaves is not None:
                    ax.axvline(leaves, color=PALETTE[1], lw=0.8, ls="--",
                               label=f"from n = {leaves} the data stand off one exponential (> 2σ and > 10 %)")
            ax.axhline(THRESHOLD, color="grey", ls=":", label=f"threshold {THRESHOLD:g}")
            ax.set_yscale("log")
            positive = y[(y > 0) & np.isfinite(y)]
            if positive.size:
                ax.set_ylim(max(positive.min() / 3, 1e-6), 1.0)
            plain_log_axis(ax.yaxis)
            which = "bottom-wall collisions" if self.count == "bottom" else "collisions with either wall"
            ax.set_xlabel(f"lag n ({which})")
            ax.set_ylabel("|P(n) − ½| (probability)")
            ax.set_title(f"heads/tails correlation of {wall_label(self.table.wall, name)}\n"
                         f"H = {self.table.H:g} κ, b0 = {self.table.b0:g} κ; {self.bounces} {which.split()[0]} "
                         f"bounces in {self.orbits} orbits")
            # below the x label: with a long decay time the points fill the whole top of the plot
            legend_below(ax, ncol=1)
            if own:
                ax.figure.tight_layout()
        return ax

    @safe_repr
    def __repr__(self) -> str:
        return (f"Correlation(H={self.table.H:g}, count={self.count}, τ = {self.tau:.4g} ± {self.tau_stderr:.2g}, "
                f"n_needed={self.n_needed}, P(1)={self.P[1] if self.P.size > 1 else float('nan'):.4f}, "
                f"{self.bounces} bounces in {self.orbits} orbits)")


def _orbit_agreement(traj, need, max_lag, count, burn):
    """Per-lag agreement frequencies of one orbit (None when too short), and its heads fraction."""
    # count_nonzero/k is bit for bit the mean of the boolean comparison (an exact integer over k) and
    # ~5x faster.  (A ±1 dot product is exact too, but OpenBLAS threads keep spinning after the call
    # and slow the kernel's numba threads on a 2-core machine.)
    side = traj.side[burn:]
    theta = traj.theta[burn:]
    bottom = np.flatnonzero(side == 0)
    agree = np.empty(max_lag + 1)
    agree[0] = 1.0
    if count == "bottom":
        seq = heads(theta[bottom[:need]])  # only the counted collisions need sin θ
        if seq.size <= max_lag:
            return None, None
        for n in range(1, max_lag + 1):
            agree[n] = np.count_nonzero(seq[:-n] == seq[n:]) / (seq.size - n)
        return agree, float(np.mean(seq))
    state = heads(theta)
    ref = bottom[:need]
    ref = ref[ref + max_lag < state.size]
    if ref.size == 0:
        return None, None
    at_ref = state[ref]
    for n in range(1, max_lag + 1):
        agree[n] = np.count_nonzero(at_ref == state[ref + n]) / ref.size
    return agree, float(np.mean(state[ref]))


def correlation(table: Billiard, bounces: int = 1_000_000, max_lag: int = 40, orbits: int = 100, count="bottom",
                seed=None, burn: int = 20, workers=None, progress=None, device: str = "cpu") -> Correlation:
    """P(n), τ and the bounces needed for ``|P(n) − ½| < 0.01`` (module docstring).

    Parameters
    ----------
    table : Billiard
    bounces : int
        Counted collisions in total (bottom collisions for ``count="bottom"``,
        bottom collisions used as references for ``"all"``), split equally
        between the orbits.
    max_lag : int
        Largest n (< bounces per orbit).
    orbits : int
        Independent orbits (≥ 2 for an error estimate).
    count : {"bottom", "all"}
    seed : int, optional
        Seed of the start states.
    burn : int
        Collisions dropped at the start of each orbit.
    workers : int, optional
        CPU threads for :func:`~coinwall.forward.dynamics.billiard.table.ensemble`.
    progress : callable, optional
        Called with the number of counted collisions finished so far.
    device : {"cpu", "gpu"}
        Where the orbits are computed (:func:`~coinwall.forward.dynamics.billiard.table.ensemble`); on the GPU
        in larger groups (:func:`~coinwall.forward.dynamics.billiard.gpu.group_collisions`).  The result does
        not depend on it beyond rounding.

    Returns
    -------
    Correlation

    Notes
    -----
    Bounds, checked before any work.  Memory: one group of orbits is held at a time (at most 2·10^6
    collisions, or one orbit of 2·bounces/orbits collisions if longer, 41 bytes each, plus ~100 bytes per
    collision of one orbit for its analysis) and P(n) per orbit (8·orbits·(max_lag + 1) bytes, three times
    over for the jackknife); refused when that exceeds half the available memory.  Work: the lag loop costs
    about max_lag × (bounces + 1000·orbits) comparisons (1000: the cost of one numpy call, per lag and
    orbit); refused above :data:`LAG_WORK_MAX` = 2e11 (a few minutes).

    Raises
    ------
    InvalidArgument
        For fewer than two orbits, a ``max_lag`` not below the bounces per orbit, a run too large for
        memory, or a table on which fewer than two orbits reach the bottom wall often enough.

    Examples
    --------
    P(n) for lags 0 to 5 from 2000 bottom bounces in 4 orbits (too few for a meaningful τ; a real run
    counts 10^6):

    >>> from coinwall import Billiard, Wall
    >>> table = Billiard(Wall.from_fourier(1.0, [0.2]), H=4.0)
    >>> from coinwall import correlation
    >>> result = correlation(table, bounces=2000, max_lag=5, orbits=4, seed=0)
    >>> result.P.shape, float(result.P[0])           # P(0) = 1: a bounce is on its own side
    ((6,), 1.0)
    """
    from ..billiard.gpu import check_device, group_collisions

    check_device(device)
    chunk = _CHUNK_COLLISIONS if device == "cpu" else group_collisions()
    bounces = _positive_int("bounces", bounces)
    max_lag = _positive_int("max_lag", max_lag)
    orbits = _positive_int("orbits", orbits)
    check_choice("count", count, COUNTS)
    burn = check_count("burn", burn, minimum=0)
    if orbits < 2:
        raise InvalidArgument(f"`orbits` must be at least 2 (the error comes from the spread between orbits), "
                              f"got {orbits}")
    per_orbit = bounces // orbits
    if max_lag >= per_orbit:
        raise InvalidArgument(f"`max_lag` = {max_lag} must be smaller than the bounces per orbit "
                              f"({bounces} bounces / {orbits} orbits = {per_orbit}); raise bounces or lower max_lag")
    work = max_lag * (bounces + 1000.0 * orbits)
    if work > LAG_WORK_MAX:
        raise InvalidArgument(f"`max_lag` = {max_lag} with `bounces` = {bounces} in `orbits` = {orbits} needs about "
                              f"{work:.3g} comparisons (max_lag × (bounces + 1000·orbits)), more than the "
                              f"{LAG_WORK_MAX:g} (a few minutes) one run does; lower max_lag (P(n) reaches ½ "
                              f"within a few τ) or bounces")
    # bottom collisions are about half of all; ask for a margin and continue the few orbits that fall short
    collisions = 2 * per_orbit + burn + 2 * max_lag + 64
    group = max(1, min(orbits, chunk // collisions))
    check_memory(f"`bounces` = {bounces} in `orbits` = {orbits} with `max_lag` = {max_lag} ({group} orbits of "
                 f"{collisions} collisions at a time, 141 bytes per collision; 24·(max_lag + 1) bytes per orbit)",
                 141.0 * group * collisions + 100.0 * collisions + orbits * (32.0 + 24.0 * (max_lag + 1)))
    starts = random_states(table, orbits, seed)
    agreements, heads_fractions, notes = [], [], []
    for first in range(0, orbits, group):
        trajs = ensemble(table, starts[first:first + group], collisions, workers=workers, device=device)
        for k, traj in enumerate(trajs):
            agree, frac = _orbit_agreement(traj, per_orbit, max_lag, count, burn)
            tries = 0
            while agree is None and not traj.note and tries < 4:  # rare: an orbit with few bottom hits
                state, turns = traj.resume_state()  # exact continuation (θ mod 2π and its turns)
                more = simulate(table, state, collisions, turns=turns)
                traj = _join(traj, more)
                agree, frac = _orbit_agreement(traj, per_orbit, max_lag, count, burn)
                tries += 1
            if agree is None:
                why = f" ({traj.note})" if traj.note else ""
                notes.append(f"orbit {first + k}: too few bottom collisions{why}")
                continue
            agreements.append(agree)
            heads_fractions.append(frac)
        if progress is not None:
            progress(min(orbits, first + group) * per_orbit)
    if len(agreements) < 2:
        raise InvalidArgument("fewer than two orbits produced enough bottom collisions; the table may trap orbits")
    agreements = np.array(agreements)
    m = agreements.shape[0]
    P = agreements.mean(axis=0)
    P_stderr = agreements.std(axis=0, ddof=1) / math.sqrt(m)
    heads_fraction = float(np.mean(heads_fractions))
    heads_stderr = float(np.std(heads_fractions, ddof=1) / math.sqrt(m))
    amplitude, tau = fit_decay(P, P_stderr)
    tau_stderr = math.nan
    if math.isfinite(tau):
        groups = np.array_split(np.arange(m), min(_GROUPS, m))
        taus = []
        for g in groups:
            rest = np.setdiff1d(np.arange(m), g)
            taus.append(fit_decay(agreements[rest].mean(axis=0), P_stderr)[1])
        taus = np.array(taus)
        if np.all(np.isfinite(taus)):
            G = len(groups)
            tau_stderr = float(math.sqrt((G - 1) / G * np.sum((taus - taus.mean()) ** 2)))
        else:
            notes.append("jackknife: some fits failed, no τ error")
    elif tau == math.inf:
        tau_stderr = 0.0
        notes.append("P(n) does not decay: the coin cannot turn over (H below the diameter?)")
    below = np.flatnonzero(np.abs(P - 0.5) < THRESHOLD)
    n_needed = int(below[0]) if below.size else None
    n_needed_fit = (tau * math.log(abs(amplitude) / THRESHOLD)
                    if math.isfinite(tau) and math.isfinite(amplitude) and abs(amplitude) > THRESHOLD else
                    (0.0 if math.isfinite(tau) else math.nan))
    return Correlation(P=P, P_stderr=P_stderr, heads_fraction=heads_fraction, heads_stderr=heads_stderr, tau=tau,
                       tau_stderr=tau_stderr, amplitude=amplitude, n_needed=n_needed, n_needed_fit=n_needed_fit,
                       count=count, bounces=per_orbit * m, orbits=m, max_lag=max_lag, table=table, seed=seed,
                       notes=tuple(notes))


def _join(a, b):
    """Concatenate two consecutive pieces of one orbit (times of ``b`` shifted to continue ``a``)."""
    from dataclasses import replace

    t0 = a.time[-1] if a.time.size else 0.0
    return replace(a, time=np.concatenate([a.time, b.time + t0]), theta=np.concatenate([a.theta, b.theta]),
                   eta=np.concatenate([a.eta, b.eta]), v_theta=np.concatenate([a.v_theta, b.v_theta]),
                   v_eta=np.concatenate([a.v_eta, b.v_eta]), side=np.concatenate([a.side, b.side]), note=b.note,
                   end_angle=b.end_angle if b.time.size else a.end_angle,
                   end_turns=b.end_turns if b.time.size else a.end_turns)


@dataclass(frozen=True, repr=False)
class TauLaw:
    """Fit of τ(H) to the paper's claim τ ∝ 1/(H − D), and to a free power.

    Attributes
    ----------
    c, c_stderr : float
        ``τ = c/(H − D)`` with D fixed.
    chi2_dof : float
        Reduced χ² of that one-parameter fit (≫ 1: the law does not describe the data).
    power, power_stderr : float
        ``τ = c'·(H − D)^(−p)``: fitted p (the claim is p = 1).
    D : float

    Examples
    --------
    >>> from coinwall.forward import fit_tau_law
    >>> fit_tau_law([3.0, 4.0, 6.0], [1.0, 0.5, 0.25], [0.01, 0.01, 0.01], D=2.0)
    TauLaw(τ = 1/(H − 2) ± 0.0087, χ²/dof 0; free power p = 1.000 ± 0.023)
    """

    c: float
    c_stderr: float
    chi2_dof: float
    power: float
    power_stderr: float
    D: float

    def to_dict(self) -> dict:
        """JSON-ready dictionary (non-finite numbers become None)."""
        return {name: (float(value) if math.isfinite(value) else None)
                for name, value in (("c", self.c), ("c_stderr", self.c_stderr), ("chi2_dof", self.chi2_dof),
                                    ("power", self.power), ("power_stderr", self.power_stderr), ("D", self.D))}

    @safe_repr
    def __repr__(self) -> str:
        return (f"TauLaw(τ = {self.c:.4g}/(H − {self.D:g}) ± {self.c_stderr:.2g}, χ²/dof {self.chi2_dof:.3g}; "
                f"free power p = {self.power:.3f} ± {self.power_stderr:.3f})")


def fit_tau_law(H, tau, tau_stderr, D) -> TauLaw:
    """Fit ``τ = c/(H − D)`` (weighted, one parameter) and ``τ = c'(H − D)^(−p)`` (log-log, weighted).

    Parameters
    ----------
    H : array_like
        Wall distances (units of κ).
    tau, tau_stderr : array_like
        The correlation times τ measured at them and their standard errors.
    D : float
        The distance at which the strip closes (τ diverges).

    Returns
    -------
    TauLaw

    Raises
    ------
    InvalidArgument
        With fewer than two points with ``H > D``, finite τ and positive errors.

    Examples
    --------
    τ = 1/(H − 2) exactly: ``c = 1`` and the free power ``p = 1``.

    >>> from coinwall.forward import fit_tau_law
    >>> law = fit_tau_law([3.0, 4.0, 6.0], [1.0, 0.5, 0.25], [0.01, 0.01, 0.01], D=2.0)
    >>> round(law.c, 9), round(law.power, 9)
    (1.0, 1.0)
    """
    from scipy.optimize import curve_fit

    H, tau, err = (np.asarray(v, dtype=float) for v in (H, tau, tau_stderr))
    if H.size < 2 or np.any(H <= D) or np.any(~np.isfinite(tau)) or np.any(~(err > 0)):
        raise InvalidArgument("fit_tau_law needs ≥ 2 points with H > D, finite τ and positive errors")
    x = 1.0 / (H - D)
    w = 1.0 / err**2
    c = float(np.sum(w * x * tau) / np.sum(w * x * x))
    c_stderr = float(1.0 / math.sqrt(np.sum(w * x * x)))
    chi2 = float(np.sum(w * (tau - c * x) ** 2))
    chi2_dof = chi2 / max(H.size - 1, 1)
    (_logc, p), cov = curve_fit(lambda h, a, q: a - q * np.log(h - D), H, np.log(tau), sigma=err / tau,
                               absolute_sigma=True, p0=(math.log(c), 1.0))
    return TauLaw(c=c, c_stderr=c_stderr, chi2_dof=chi2_dof, power=float(p), power_stderr=float(math.sqrt(cov[1, 1])),
                  D=float(D))
