"""The critical offset of noisy samples: an estimate with a confidence interval, under a stated assumption.

Samples with standard deviations (``b_sd``, ``theta_sd``) are statistics, not bounds: no interval is
certain, and ``b + b''`` of noise of size σ at spacing Δ is of size σ/Δ².  What can be said is a confidence
interval for ``b_c = −min(b + b'')`` under an assumption about the wall's smoothness (docs/theory.md,
"Noisy samples"):

* **the estimate.**  The wall's first ``K`` harmonics are fitted by weighted least squares (weights
  ``1/sd²``); ``K`` is the last harmonic whose amplitude is beyond what noise reaches by chance in any of
  the harmonics looked at (5 %, Bonferroni: the last one the data resolve).  ``ρ̂ = b̂ + b̂''`` is linear in the data, its covariance exact;
* **the assumption** (the *tail bound* ``T``): ``b + b''`` differs from its first ``K`` harmonics by at most
  ``T`` at every angle.  Its default is read off the data: the resolved amplitudes ``a_k`` are enveloped by
  ``A·q^k`` (``q`` from their decay, at least 0.1 and at most 0.9 — at most 1/2 from two, 1/2 from fewer;
  ``A`` the least that lies above every one),
  and ``T = Σ_{k>K} (k² − 1)·A·q^k`` — the harmonics the noise hides, had they gone on decaying as the
  resolved ones do.  Walls with kinks decay slowly, give a large ``T`` and a wide interval; a user who knows
  better sets ``T``;
* **the interval.**  ``|ρ̂(θ) − ρ(θ)| ≤ z·s(θ) + T`` at every angle at once with probability ``level``, ``s``
  the standard deviation of ``ρ̂(θ)`` and ``z`` the ``level`` quantile of ``max_θ |ρ̂ − E ρ̂|/s`` (simulated
  from the exact covariance, on a grid of 64 points per harmonic).  Then
  ``b_c ∈ [−min(ρ̂ + zs + T), −min(ρ̂ − zs − T)]``: an interval that covers the truth with probability at
  least ``level`` whenever the assumption holds.

``coinwall solve`` and ``coinwall fit`` report it for samples given with standard deviations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.errors import InvalidArgument, InvalidWall

__all__ = ["NoisyCritical", "noisy_critical"]

#: confidence level of the interval
LEVEL = 0.95
#: most harmonics fitted (and at most a quarter of the distinct angles)
MAX_HARMONICS = 64
#: simulated draws of the noise for the simultaneous quantile
DRAWS = 4000


@dataclass(frozen=True)
class NoisyCritical:
    """The critical offset of noisy samples (:func:`noisy_critical`).

    Attributes
    ----------
    estimate : float
        ``−min ρ̂`` of the fitted harmonics.
    lower, upper : float
        The confidence interval of ``b_c`` at :attr:`level` (under :attr:`assumption`).
    level : float
        Its confidence level.
    harmonics : int
        ``K``, the harmonics fitted.
    tail : float
        ``T``, the tail bound the interval assumes; :attr:`tail_given` says whether the user set it.
    tail_given : bool
    quantile : float
        ``z``, the simultaneous quantile of the noise of ``ρ̂``.
    angles : tuple of float
        Where the least ``b + b''`` may be: one angle (its estimate) per run of angles whose interval reaches
        below the least upper end.
    sd : float
        The typical standard deviation of one sample (root mean square over the angles).
    samples : int
        How many distinct angles the estimate used.

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.radians(np.arange(360.0))
    >>> wall = np.sqrt((1 + np.cos(theta) ** 2) / 2)      # the ellipse x² + 2y² = 1: b_c = −0.5
    >>> from coinwall.inverse.noise import noisy_critical
    >>> found = noisy_critical(theta, wall + 1e-3 * np.random.default_rng(1).standard_normal(360), 1e-3)
    >>> round(found.lower, 3), round(found.upper, 3), found.level, found.angles
    (-0.514, -0.472, 0.95, (0.0, 3.141592653589793))
    """

    estimate: float
    lower: float
    upper: float
    level: float
    harmonics: int
    tail: float
    tail_given: bool
    quantile: float
    angles: tuple
    sd: float
    samples: int

    @property
    def assumption(self) -> str:
        """The smoothness the interval rests on, in words."""
        source = "given" if self.tail_given else "from the decay of the resolved harmonics"
        return (f"b + b'' differs from its first {self.harmonics} harmonics by at most {self.tail:.3g} ({source})")

    def regimes(self, b0: float) -> tuple[str, ...]:
        """The regimes at ``b0`` the interval allows: ``corner`` below it, ``convex`` above, else all three."""
        if b0 < self.lower:
            return ("corner",)
        if b0 > self.upper:
            return ("convex",)
        return ("corner", "critical", "convex")

    def to_dict(self) -> dict:
        return {"estimate": self.estimate, "lower": self.lower, "upper": self.upper, "level": self.level,
                "harmonics": self.harmonics, "tail_bound": self.tail,
                "tail_bound_source": "given" if self.tail_given else "data", "quantile": self.quantile,
                "angles": list(self.angles), "sd": self.sd, "samples": self.samples, "assumption": self.assumption}


def _design(theta, K):
    k = np.arange(1, K + 1)
    return np.column_stack([np.ones_like(theta), np.cos(np.outer(theta, k)), np.sin(np.outer(theta, k))])


def _fit(theta, y, weight, K):
    """Weighted least squares of the harmonics 0..K: coefficients and their covariance."""
    X = _design(theta, K)
    normal = X.T @ (X * weight[:, None])
    try:
        cov = np.linalg.inv(normal)
    except np.linalg.LinAlgError:
        raise InvalidWall(f"samples: {K} harmonics cannot be fitted to these angles (too few, or bunched)") from None
    return cov @ (X.T @ (weight * y)), cov


def _amplitudes(coef, cov, K):
    a, b = coef[1:K + 1], coef[K + 1:]
    se = np.sqrt(np.diag(cov))
    return np.hypot(a, b), np.hypot(se[1:K + 1], se[K + 1:])


def _default_tail(amp, resolved, K):
    """``Σ_{k>K} (k² − 1) A q^k``, ``A q^k`` the least geometric envelope above every resolved amplitude."""
    k = np.arange(1, amp.size + 1)
    keep = np.zeros(amp.size, bool)
    keep[resolved] = True
    keep &= (k <= K) & (k >= 2)
    if np.count_nonzero(keep) >= 2:
        slope = np.polyfit(k[keep], np.log(amp[keep]), 1)[0]
        # two points say little about a decay: no slower than halving then
        q = float(min(max(math.exp(slope), 0.1), 0.9 if np.count_nonzero(keep) >= 3 else 0.5))
    else:
        q = 0.5
    scale = float(np.max(amp[keep] / q ** k[keep])) if keep.any() else 0.0
    tail = np.arange(K + 1, K + 400)
    return float(np.sum((tail**2 - 1.0) * scale * q**tail))


def noisy_critical(theta, b, sd, *, tail: float | None = None, level: float = LEVEL, seed: int = 0) -> NoisyCritical:
    """The critical offset of samples with standard deviations: an estimate and a confidence interval
    (module docstring).

    Parameters
    ----------
    theta : array_like
        Distinct angles (radians, any order).
    b : array_like
        The samples (means, where several were taken at one angle).
    sd : float or array_like
        The standard deviation of each (positive).
    tail : float, optional
        The tail bound ``T`` the interval assumes; default from the data.
    level : float
        Confidence level, in (0, 1).
    seed : int
        Seed of the simulation of the simultaneous quantile (the result is reproducible).

    Returns
    -------
    NoisyCritical

    Raises
    ------
    InvalidArgument
        A standard deviation that is not positive, or below the precision of the values; a bad ``tail`` or
        ``level``.
    InvalidWall
        Too few angles for a fit.

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.radians(np.arange(360.0))
    >>> wall = np.sqrt((1 + np.cos(theta) ** 2) / 2)      # b_c = −0.5
    >>> found = noisy_critical(theta, wall + 1e-3 * np.random.default_rng(1).standard_normal(360), 1e-3)
    >>> bool(found.lower <= -0.5 <= found.upper), bool(found.upper - found.lower < 0.1)
    (True, True)
    """
    theta = np.mod(np.asarray(theta, float).ravel(), TWO_PI)
    b = np.asarray(b, float).ravel()
    sd = np.broadcast_to(np.asarray(sd, float), b.shape).astype(float)
    order = np.argsort(theta)
    theta, b, sd = theta[order], b[order], sd[order]
    if not (0 < level < 1):
        raise InvalidArgument(f"`level` must lie between 0 and 1, got {level!r}")
    if tail is not None and not (math.isfinite(tail) and tail >= 0):
        raise InvalidArgument(f"`tail`: the tail bound must be a finite number ≥ 0, got {tail!r}")
    scale = max(float(np.max(np.abs(b))), 1e-300)
    if not np.all(np.isfinite(sd)) or np.any(sd <= 0):
        raise InvalidArgument("`b_sd`: every standard deviation must be a positive finite number")
    if np.min(sd) < 1e-13 * scale:
        raise InvalidArgument(f"`b_sd` {float(np.min(sd)):.3g} is below the precision of the values themselves "
                              f"(~1e-13 of {scale:.3g}): samples known that well are exact; give no standard deviation")
    n = theta.size
    if n < 16:
        raise InvalidWall(f"samples: {n} distinct angles; an estimate from noisy samples needs at least 16")
    weight = 1.0 / sd**2
    top = max(2, min(MAX_HARMONICS, n // 4))
    coef, cov = _fit(theta, b, weight, top)
    amp, amp_se = _amplitudes(coef, cov, top)
    # resolved: above what noise reaches by chance in any of the harmonics looked at (5 %, Bonferroni; the
    # amplitude of pure noise is Rayleigh distributed, P(a > c·se) = exp(−c²/2))
    resolved = np.flatnonzero(amp > math.sqrt(2.0 * math.log(20.0 * top)) * amp_se)
    K = int(max(2, resolved[-1] + 1 if resolved.size else 2))
    tail_given = tail is not None
    if tail is None:
        tail = _default_tail(amp, resolved, K)
    coef, cov = _fit(theta, b, weight, K)
    k = np.arange(1, K + 1)
    grid = np.linspace(0.0, TWO_PI, 64 * K, endpoint=False)
    R = _design(grid, K) * np.concatenate([[1.0], 1.0 - k**2, 1.0 - k**2])[None, :]
    rho = R @ coef
    spread = np.sqrt(np.einsum("ij,jk,ik->i", R, cov, R))
    chol = np.linalg.cholesky(cov + 1e-300 * np.eye(cov.shape[0]))
    draws = np.random.default_rng(seed).standard_normal((DRAWS, chol.shape[0])) @ chol.T
    z = float(np.quantile(np.max(np.abs(draws @ R.T) / spread[None, :], axis=1), level))
    low, high = rho - z * spread - tail, rho + z * spread + tail
    lower, upper = -float(np.min(high)), -float(np.min(low))
    estimate = -float(np.min(rho))
    # where the least value may be: runs of grid angles whose interval reaches below the least upper end
    from .certify import cyclic_runs

    starts, lengths = cyclic_runs(low <= np.min(high))
    angles = []
    for start, length in zip(starts.tolist(), lengths.tolist()):
        idx = (start + np.arange(length)) % grid.size
        angles.append(float(grid[idx[np.argmin(rho[idx])]]))
    return NoisyCritical(estimate + 0.0, lower + 0.0, upper + 0.0, float(level), K, float(tail), tail_given, z,
                         tuple(sorted(angles)), float(np.sqrt(np.mean(sd**2))), int(n))
