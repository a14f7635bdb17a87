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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...display import safe_repr
from ...errors import InvalidArgument
from ...validation import check_count, check_finite, check_seed

__all__ = ["PsiFit", "dhm_same_side", "fit_psi", "likelihood_interval", "psi_from_same_side", "sigma_from_same_side",
           "simulate_caught", "spread_same_side"]

_CHI2_95 = 3.841458820694124  # the 95 % quantile of χ² with one degree of freedom


def dhm_same_side(psi):
    """DHM's P(same side) for a coin caught after a long flight, ψ in radians (vectorised)."""
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

    def to_dict(self) -> dict:
        return dict(self.__dict__)

    @safe_repr
    def __repr__(self):
        return (f"PsiFit({self.same}/{self.flips} = {self.p:.5f} [{self.p_low:.5f}, {self.p_high:.5f}]: "
                f"ψ = {self.psi:.2f}° [{self.psi_low:.2f}, {self.psi_high:.2f}], "
                f"σ = {self.sigma:.2f}° [{self.sigma_low:.2f}, {self.sigma_high:.2f}])")


def likelihood_interval(k: int, n: int):
    """The 95 % likelihood-ratio interval of a binomial proportion, ``k`` successes in ``n`` trials:
    ``{p : 2 (log L(k/n) − log L(p)) ≤ 3.84}``."""
    from scipy.optimize import brentq

    p = k / n

    def loglik(q):
        q = min(max(q, 1e-300), 1 - 1e-16)
        return k * math.log(q) + (n - k) * math.log1p(-q)

    top = loglik(p)

    def drop(q):
        return 2 * (top - loglik(q)) - _CHI2_95

    lo = 0.0 if k == 0 else brentq(drop, 1e-300, p, xtol=1e-15)
    hi = 1.0 if k == n else brentq(drop, p, 1 - 1e-16, xtol=1e-15)
    return lo, hi


def fit_psi(same: int, flips: int) -> PsiFit:
    """ψ and σ from counts (see the module docstring): estimates at the proportion, 95 % intervals from the
    likelihood-ratio interval of the proportion mapped through the monotone model."""
    flips = check_count("flips", flips)
    same = check_count("same", same, minimum=0, maximum=flips)
    p = same / flips
    lo, hi = likelihood_interval(same, flips)
    deg = 180 / math.pi

    def psi(q):
        return float(psi_from_same_side(q)) * deg

    return PsiFit(same, flips, p, max(lo, 0.5), max(hi, 0.5), psi(p), psi(hi), psi(lo),
                  sigma_from_same_side(p) * deg, sigma_from_same_side(lo) * deg, sigma_from_same_side(hi) * deg)


def simulate_caught(psi: float, samples: int, seed=None, omega: float = 240.0, flight=None, g: float = 1.0):
    """P(same side) and its binomial standard error for ``samples`` caught tosses with angle ψ (radians):
    spin rate ``omega`` (rad/s; ≈ 38 rev/s, DHM's measured rate), flight times uniform in ``flight`` (s;
    default 0.4 s to 0.4 s + 8 periods 2π/Ω, so that the phase Ωt is exactly uniform, as DHM's long-flight
    limit assumes).  The body does not matter (the axis motion depends on ℓ only)."""
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
