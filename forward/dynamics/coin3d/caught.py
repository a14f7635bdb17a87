"""Caught tosses: the precessing coin of Diaconis, Holmes & Montgomery, simulated, and fitted to counts.

A coin launched heads up (its normal ``a`` vertical) with angular momentum ``L`` at the angle ψ from the
normal precesses: ``a`` turns about the fixed ``L`` at the rate Ω = |L|/I₁, so the angle between ``a`` and
the vertical start direction obeys ``cos θ(t) = cos²ψ + sin²ψ cos Ω t`` (:mod:`.top`, where this is the
flight with ``ℓ_z = ℓ₃ = Ω cos ψ`` and ``θ̇(0) = Ω sin ψ`` through the pole θ = 0).  Caught in a horizontal
hand at time t the coin shows the side it started with iff ``cos θ(t) > 0``.  Over flights long against
1/Ω the phase Ωt is uniform and (DHM, SIAM Rev. 49 (2007) 211)

    P(same side) = ½ + arcsin(cot² ψ)/π    (ψ ≥ 45°; 1 for ψ < 45°).

:func:`simulate_caught` draws flights (:func:`.top.state_after`, compiled) and counts; :func:`fit_psi` turns
counts of same-side landings into ψ: by the likelihood-ratio interval of the binomial proportion (the
profile likelihood of ψ, since ψ ↦ P is monotone), for one ψ, or for a spread of ψ about 90°
(ψ = 90° − |δ|, δ ~ N(0, σ²): a hand that flips with a small, random wobble) with its σ.

Counts pooled over several people are not one binomial when the people differ: each flips with his own
proportion, and the pooled proportion then varies more than the binomial says.  :func:`overdispersion`
measures it (Pearson's χ² of the groups against their pooled proportion, over its degrees of freedom: the
quasi-binomial dispersion φ, McCullagh & Nelder, *Generalized Linear Models*, 2nd ed., §4.5), and
``fit_psi(..., dispersion=φ, dof=k − 1)`` widens the interval accordingly: the quasi-likelihood interval
``{p : 2 (log L(p̂) − log L(p)) ≤ φ F₀.₉₅(1, k − 1)}`` (the F quantile, not χ², because φ is estimated from
the same k groups).  It keeps the pooled estimate and scales its variance by φ, the model of a variance
proportional to the binomial one; a bootstrap over the groups is the check that assumes no such shape
(``tests/cases/test_coin3d_data.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_finite, check_seed

__all__ = ["PsiFit", "dhm_same_side", "fit_psi", "likelihood_interval", "overdispersion", "psi_from_same_side",
           "sigma_from_same_side", "simulate_caught", "spread_same_side"]

_CHI2_95 = 3.841458820694124  # the 95 % quantile of χ² with one degree of freedom


def dhm_same_side(psi):
    """DHM's P(same side) for a coin caught after a long flight, ψ in radians (vectorised).

    Parameters
    ----------
    psi : float or array_like
        The angle ψ between the angular momentum and the coin's normal (radians).

    Returns
    -------
    float or ndarray
        ``½ + arcsin(cot² ψ)/π`` for ψ ≥ 45°, 1 below.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward.dynamics import dhm_same_side
    >>> dhm_same_side(np.radians([90.0, 45.0])).round(12).tolist()      # no precession: fair; 45°: never turns
    [0.5, 1.0]
    """
    psi = np.asarray(psi, dtype=float)
    with np.errstate(divide="ignore"):
        cot2 = (np.cos(psi) / np.sin(psi)) ** 2
    return np.where(cot2 >= 1.0, 1.0, 0.5 + np.arcsin(np.minimum(cot2, 1.0)) / math.pi)


def psi_from_same_side(p):
    """The ψ (radians, in [45°, 90°]) with ``dhm_same_side(ψ) = p``; 90° for p ≤ ½ (the model's edge)."""
    p = np.clip(np.asarray(p, dtype=float), 0.5, 1.0)
    with np.errstate(divide="ignore"):  # p = ½: arctan(inf) = 90°, exactly the model's edge
        return np.arctan(1.0 / np.sqrt(np.sin(math.pi * (p - 0.5))))


_GH = np.polynomial.hermite_e.hermegauss(80)


def spread_same_side(sigma):
    """P(same side) when ψ = 90° − |δ|, δ ~ N(0, σ²) (σ in radians; Gauss–Hermite over δ, 80 nodes)."""
    x, w = _GH
    out = []
    for s in np.atleast_1d(np.asarray(sigma, dtype=float)):
        out.append(float(np.sum(w * dhm_same_side(math.pi / 2 - np.abs(s * x))) / math.sqrt(2 * math.pi)))
    return np.array(out) if np.ndim(sigma) else out[0]


def sigma_from_same_side(p):
    """The σ (radians) of the spread model with ``spread_same_side(σ) = p`` (0 for p ≤ ½)."""
    from scipy.optimize import brentq

    p = float(p)
    if p <= 0.5:
        return 0.0
    if p >= spread_same_side(1.5):
        return 1.5
    return brentq(lambda s: spread_same_side(s) - p, 0.0, 1.5, xtol=1e-12)


@dataclass(frozen=True, repr=False)
class PsiFit:
    """ψ (and σ of the spread model) consistent with ``same`` same-side landings in ``flips`` caught flips.

    Attributes
    ----------
    same, flips : int
    p, p_low, p_high : float
        The proportion and its 95 % likelihood-ratio interval, bounded to [½, 1] where the model lives
        (``p_low`` = ½ when the interval reaches below ½).
    psi, psi_low, psi_high : float
        ψ in degrees at p and at the interval's ends (``psi_low`` from ``p_high``).
    sigma, sigma_low, sigma_high : float
        σ of the spread model in degrees, likewise.
    dispersion : float
        The variance factor the intervals allow for (1: binomial; φ > 1: quasi-binomial, see
        :func:`overdispersion`).

    Examples
    --------
    >>> from coinwall.forward.dynamics import fit_psi
    >>> fit = fit_psi(178_078, 350_757)
    >>> fit.same, fit.flips, round(fit.p, 4)
    (178078, 350757, 0.5077)
    """

    same: int
    flips: int
    p: float
    p_low: float
    p_high: float
    psi: float
    psi_low: float
    psi_high: float
    sigma: float
    sigma_low: float
    sigma_high: float
    dispersion: float = 1.0

    def to_dict(self) -> dict:
        return dict(self.__dict__)

    @safe_repr
    def __repr__(self):
        spread = "" if self.dispersion == 1.0 else f", dispersion {self.dispersion:.3g}"
        return (f"PsiFit({self.same}/{self.flips} = {self.p:.5f} [{self.p_low:.5f}, {self.p_high:.5f}]: "
                f"ψ = {self.psi:.2f}° [{self.psi_low:.2f}, {self.psi_high:.2f}], "
                f"σ = {self.sigma:.2f}° [{self.sigma_low:.2f}, {self.sigma_high:.2f}]{spread})")


def likelihood_interval(k: int, n: int, threshold: float = _CHI2_95):
    """The likelihood-ratio interval of a binomial proportion, ``k`` successes in ``n`` trials:
    ``{p : 2 (log L(k/n) − log L(p)) ≤ threshold}`` (default 3.84, the 95 % quantile of χ² with one degree
    of freedom; :func:`fit_psi` passes φ F₀.₉₅(1, dof) for overdispersed counts).

    Parameters
    ----------
    k, n : int
        Successes and trials.
    threshold : float
        The largest drop of twice the log-likelihood inside the interval.

    Returns
    -------
    (float, float)
        The ends of the interval, in [0, 1].

    Examples
    --------
    >>> lo, hi = likelihood_interval(50, 100)
    >>> round(lo, 4), round(hi, 4)
    (0.4029, 0.5971)
    """
    from scipy.optimize import brentq

    p = k / n

    def loglik(q):
        q = min(max(q, 1e-300), 1 - 1e-16)
        return k * math.log(q) + (n - k) * math.log1p(-q)

    top = loglik(p)

    threshold = check_finite("threshold", threshold)

    def drop(q):
        return 2 * (top - loglik(q)) - threshold

    lo = 0.0 if k == 0 else brentq(drop, 1e-300, p, xtol=1e-15)
    hi = 1.0 if k == n else brentq(drop, p, 1 - 1e-16, xtol=1e-15)
    return lo, hi


def overdispersion(same, flips):
    """The quasi-binomial dispersion of counts in groups: ``(φ, statistic, dof)``.

    ``statistic`` is Pearson's χ² of the groups' counts against their pooled proportion p,
    ``Σ (k_i − n_i p)² / (n_i p (1 − p))``, on ``dof = groups − 1`` degrees of freedom; ``φ`` is
    ``statistic / dof``, and 1 when that is smaller (fewer differences than binomial noise: no widening).

    Parameters
    ----------
    same, flips : array of int
        Successes and trials of each group (at least two groups).

    Returns
    -------
    (float, float, int)
        φ, Pearson's statistic, its degrees of freedom.

    Raises
    ------
    InvalidArgument
        Fewer than two groups, counts that are not whole numbers with ``0 ≤ same ≤ flips``, or a pooled
        proportion of 0 or 1 (no variance to scale).

    Examples
    --------
    >>> phi, statistic, dof = overdispersion([10, 30], [40, 40])  # 25 % and 75 %: far more than binomial noise
    >>> round(phi, 2), round(statistic, 2), dof
    (20.0, 20.0, 1)
    """
    k = np.asarray(same)
    n = np.asarray(flips)
    if k.ndim != 1 or k.shape != n.shape or k.size < 2:
        raise InvalidArgument("`same` and `flips` must be counts of at least two groups, one number each")
    if not (np.issubdtype(k.dtype, np.integer) and np.issubdtype(n.dtype, np.integer)):
        raise InvalidArgument("`same` and `flips` must be whole numbers")
    if np.any(n <= 0) or np.any(k < 0) or np.any(k > n):
        raise InvalidArgument("every group needs flips > 0 and 0 <= same <= flips")
    p = k.sum() / n.sum()
    if p in (0.0, 1.0):
        raise InvalidArgument("the pooled proportion is 0 or 1: there is no binomial variance to scale")
    statistic = float(np.sum((k - n * p) ** 2 / (n * p * (1 - p))))
    dof = int(k.size - 1)
    return max(1.0, statistic / dof), statistic, dof


def fit_psi(same: int, flips: int, dispersion: float = 1.0, dof: int | None = None) -> PsiFit:
    """ψ and σ from counts (see the module docstring): estimates at the proportion, 95 % intervals from the
    likelihood-ratio interval of the proportion mapped through the monotone model.

    Parameters
    ----------
    same, flips : int
        Same-side landings and caught flips.
    dispersion : float
        φ ≥ 1 of :func:`overdispersion` when the flips pool people who differ (1: one binomial).
    dof : int, optional
        The degrees of freedom φ was estimated with; the interval then uses φ F₀.₉₅(1, dof) in place of
        the χ² quantile 3.84 (required with φ > 1).

    Returns
    -------
    PsiFit

    Raises
    ------
    InvalidArgument
        Counts out of range, φ < 1 or not finite, or φ > 1 without ``dof``.

    Examples
    --------
    >>> fit = fit_psi(178_078, 350_757)            # Bartoš et al. (2023), all flips as one binomial
    >>> round(fit.psi, 2), round(fit.psi_low, 2), round(fit.psi_high, 2)
    (81.16, 80.28, 82.16)
    >>> wide = fit_psi(178_078, 350_757, dispersion=5.64, dof=47)   # with the spread between the 48 tossers
    >>> round(wide.psi_low, 1), round(wide.psi_high, 1)
    (79.1, 83.9)
    """
    flips = check_count("flips", flips)
    same = check_count("same", same, minimum=0, maximum=flips)
    dispersion = check_finite("dispersion", dispersion)
    if dispersion < 1.0:
        raise InvalidArgument(f"`dispersion` must be at least 1 (1: binomial), got {dispersion:g}")
    threshold = _CHI2_95
    if dispersion > 1.0:
        if dof is None:
            raise InvalidArgument("a `dispersion` above 1 needs the `dof` it was estimated with")
        from scipy.stats import f as f_distribution

        threshold = dispersion * float(f_distribution.ppf(0.95, 1, check_count("dof", dof)))
    p = same / flips
    lo, hi = likelihood_interval(same, flips, threshold)
    deg = 180 / math.pi

    def psi(q):
        return float(psi_from_same_side(q)) * deg

    return PsiFit(same, flips, p, max(lo, 0.5), max(hi, 0.5), psi(p), psi(hi), psi(lo),
                  sigma_from_same_side(p) * deg, sigma_from_same_side(lo) * deg, sigma_from_same_side(hi) * deg,
                  dispersion)


def simulate_caught(psi: float, samples: int, seed=None, omega: float = 240.0, flight=None, g: float = 1.0):
    """P(same side) and its binomial standard error for ``samples`` caught tosses with angle ψ (radians):
    spin rate ``omega`` (rad/s; ≈ 38 rev/s, DHM's measured rate), flight times uniform in ``flight`` (s;
    default 0.4 s to 0.4 s + 8 periods 2π/Ω, so that the phase Ωt is exactly uniform, as DHM's long-flight
    limit assumes).  The body does not matter (the axis motion depends on ℓ only).

    Parameters
    ----------
    psi : float
        The angle ψ (radians, in [0, π]).
    samples : int
        Caught tosses.
    seed : int, optional
        Seed of the flight times and phases.
    omega : float
        Spin rate (rad/s).
    flight : (float, float), optional
        The range of flight times (s).
    g : float
        The field (it sets the flight, not the outcome).

    Returns
    -------
    p : float
        The share of same-side catches.
    stderr : float
        Its binomial standard error.

    Raises
    ------
    InvalidArgument
        For ψ outside [0, π] or a bad flight range.

    Examples
    --------
    Simulated catches agree with DHM's formula (0.5195 ± 0.011 against 0.5099 at ψ = 80°):

    >>> import numpy as np
    >>> from coinwall.forward.dynamics import dhm_same_side, simulate_caught
    >>> p, stderr = simulate_caught(np.radians(80.0), 2000, seed=0)
    >>> round(p, 4), bool(abs(p - dhm_same_side(np.radians(80.0))) < 3 * stderr)
    (0.5195, True)
    """
    from ...revolution import coin
    from .top import TopTable, state_after

    psi = check_finite("psi", psi)
    if not 0.0 <= psi <= math.pi:
        raise InvalidArgument(f"`psi` must be an angle in [0, π], got {psi:g}")
    samples = check_count("samples", samples, maximum=100_000_000)
    omega = check_finite("omega", omega)
    if flight is None:
        flight = (0.4, 0.4 + 8 * 2 * math.pi / omega)
    lo, hi = (check_finite("flight", x) for x in flight)
    if not 0 < lo <= hi:
        raise InvalidArgument(f"`flight` must be two times 0 < lo <= hi, got {flight!r}")
    rng = np.random.default_rng(check_seed(seed))
    times = rng.uniform(lo, hi, samples)
    table = TopTable(coin(1.0, 0.1), g=g)
    height = 0.5 * g * hi * hi + 10.0  # high enough that the (absent) floor never matters
    states = np.tile([0.0, height, omega * math.sin(psi), 0.5 * g * hi], (samples, 1))
    ell = omega * math.cos(psi)
    out = state_after(table, states, ell, ell, times)
    same = np.cos(out[:, 0]) > 0
    p = float(same.mean())
    return p, math.sqrt(p * (1 - p) / samples)
