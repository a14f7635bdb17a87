"""The critical offset of data, as a certified interval.

Each sample says only that the wall at ``θ_i`` lies in ``[b_i − w_i, b_i + w_i]``
(:mod:`coinwall.forward.sampledata`).  Over every wall consistent with the data:

* **the lower end** ``b_c⁻`` is certified with no assumption: the least offset for which *some*
  values ``s_i`` inside the intervals are support values of a convex body.  Support values at sorted
  directions (gaps below π) belong to a convex body iff every discrete radius of curvature is ≥ 0
  (each line keeps a piece of the polygon), and ``ρ_i(b0 + s) = b0 + ρ_i(s)`` is linear in ``s`` with
  three neighbours, so this is the linear programme

      minimise t  subject to  t + ρ_i(s) ≥ 0,  lo_i ≤ s_i ≤ hi_i,

  solved by scipy's HiGHS.  The true wall's own values are feasible at its own ``b_c`` (its support
  lines bound it), so ``b_c⁻ ≤ b_c``.  The value reported is not HiGHS's objective (good to its
  feasibility tolerance) but a bound recomputed from its dual multipliers ``y ≥ 0``, ``Σy = 1``:
  ``t ≥ Σ y_i (−ρ_i(s))`` for every feasible ``s``, whose least value over the box is a sum of
  per-sample extremes — a certificate that holds whatever the solver's accuracy;

* **the upper end** ``b_c⁺`` needs an assumption about the wall *between* samples (a dip of
  ``b + b''`` narrower than the spacing is invisible to any data).  The assumption used, stated with
  every result (:data:`ASSUMPTION`): *between two samples ``b + b''`` dips no lower than its
  discrete values on either side and their slopes predict* — it may fall between samples as a smooth
  minimum or a V would, by as much as the smaller of the descent into the gap and the ascent out of
  it (with a factor 2 to spare); edges of the body (positive spikes of the discrete curvature, which
  can only raise it) and steps (a vertex window meeting an arc) are no dips.  On the lowest discrete
  values consistent with the intervals (``ρ_i − tol_i``) this gives ``b_c⁺``.

Where ``b0`` lies below ``b_c⁻`` the data certainly need corners (Case III); above ``b_c⁺`` the
body is certainly convex (under the assumption); in between the data cannot decide, and the result
says so.

Dense data are thinned first (:func:`coinwall.forward.sampledata.thin`): samples closer than their own
uncertainty say nothing the geometry can use (the discrete curvature of lines a hair apart is their rounding
divided by the square of the hair), so the spacing at which the certified interval is narrowest is chosen from a
ladder, and the rest of the samples are kept for the closing check.  Thinning drops constraints, so the
lower end stays certified.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.sampledata import curvature_coefficients, thin
from coinwall.forward.sampledata import discrete_rho as curvature

__all__ = ["ASSUMPTION", "CriticalBound", "certified_critical", "lp_lower_bound", "upper_bound"]

#: the assumption the upper end of the interval rests on (module docstring)
ASSUMPTION = ("between samples, b + b'' dips no lower than its discrete values on either side and their slopes "
              "predict (piecewise smooth, with edges and steps where the data show them)")
#: the LP is solved on at most this many samples (HiGHS takes ~1 s at 10⁵); denser data are thinned
MAX_LP_SAMPLES = 20_000


@dataclass(frozen=True, repr=False)
class CriticalBound:
    """The critical offset of data as an interval.

    Attributes
    ----------
    lower : float
        Certified: no wall consistent with the data has a smaller ``b_c`` (a linear programme).
    upper : float
        No wall consistent with the data *and* with :attr:`assumption` has a larger ``b_c``.
    estimate : float
        The best single value (the discrete curvature's minimum corrected for the spacing), inside
        ``[lower, upper]``.
    assumption : str
        What :attr:`upper` rests on.
    used : ndarray of int
        The samples the geometry used (all of them, or a thinned subset of dense data).
    spacing : float
        The thinning spacing (rad; 0 if none).
    lp_gap : float
        HiGHS's objective minus the certified lower end (how far the solver was from its own bound).
    """

    lower: float
    upper: float
    estimate: float
    assumption: str
    used: np.ndarray
    spacing: float
    lp_gap: float

    def regimes(self, b0: float, tol: float = 0.0) -> tuple[str, ...]:
        """The regimes the data allow at offset ``b0``: ``("corner",)`` below :attr:`lower`,
        ``("convex",)`` above :attr:`upper`, else the ones between (``"critical"`` always among them)."""
        if b0 < self.lower - tol:
            return ("corner",)
        if b0 > self.upper + tol:
            return ("convex",)
        allowed = []
        if b0 > self.lower + tol:
            allowed.append("corner")
        allowed.append("critical")
        if b0 < self.upper - tol:
            allowed.append("convex")
        return tuple(allowed)

    def __repr__(self) -> str:
        return (f"CriticalBound(b_c in [{self.lower:.6g}, {self.upper:.6g}], estimate {self.estimate:.6g}, "
                f"{self.used.size} samples used)")


def curvature_range(theta, lo, hi):
    """The least and the largest ``ρ_i`` over values in the boxes ``[lo, hi]`` (each ρ_i depends on
    three values, so its extremes are taken independently)."""
    a, c, d = curvature_coefficients(theta)
    lo_prev, hi_prev, lo_next, hi_next = np.roll(lo, 1), np.roll(hi, 1), np.roll(lo, -1), np.roll(hi, -1)
    least = (np.minimum(a * lo_prev, a * hi_prev) + np.minimum(c * lo, c * hi)
             + np.minimum(d * lo_next, d * hi_next))
    most = (np.maximum(a * lo_prev, a * hi_prev) + np.maximum(c * lo, c * hi)
            + np.maximum(d * lo_next, d * hi_next))
    return least, most


def lp_lower_bound(theta, lo, hi) -> tuple[float, float]:
    """The certified lower end of ``b_c`` (module docstring) and HiGHS's own objective.

    Returns ``(certified, objective)``; ``certified ≤ objective`` up to rounding."""
    from scipy.optimize import linprog
    from scipy.sparse import coo_matrix

    theta = np.asarray(theta, float)
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    n = theta.size
    a, c, d = curvature_coefficients(theta)
    # variables: s_0 … s_{n−1}, t.  Rows: −t − ρ_i(s) ≤ 0
    rows = np.repeat(np.arange(n), 4)
    cols = np.stack([(np.arange(n) - 1) % n, np.arange(n), (np.arange(n) + 1) % n, np.full(n, n)], axis=1).ravel()
    vals = np.stack([-a, -c, -d, -np.ones(n)], axis=1).ravel()
    matrix = coo_matrix((vals, (rows, cols)), shape=(n, n + 1)).tocsr()
    # centre and scale the values: the LP is then well conditioned for any units
    middle = 0.5 * (lo + hi)
    cost = np.zeros(n + 1)
    cost[n] = 1.0
    bounds = np.column_stack([lo - middle, hi - middle])
    bounds = np.vstack([bounds, [-np.inf, np.inf]])
    rhs = curvature(theta, middle)  # −t − ρ(s' + middle) ≤ 0  ⇔  −t − ρ(s') ≤ ρ(middle)
    res = linprog(cost, A_ub=matrix, b_ub=rhs, bounds=bounds, method="highs")
    crude = -float(np.min(curvature_range(theta, lo, hi)[1]))  # y = the best single sample
    if res.status != 0 or res.ineqlin is None:
        return crude, crude
    y = np.maximum(-np.asarray(res.ineqlin.marginals, float), 0.0)
    total = float(y.sum())
    if not total > 0:
        return crude, float(res.fun)
    y = y / total
    # Σ_i y_i ρ_i(s) = Σ_j C_j s_j; its largest value over the box
    coef = np.roll(y * a, -1) + y * c + np.roll(y * d, 1)
    best = float(np.sum(np.maximum(coef * lo, coef * hi)))
    return max(-best, crude), float(res.fun)


def upper_bound(theta, lo, hi, rho_low=None) -> float:
    """The upper end of ``b_c`` under :data:`ASSUMPTION` (module docstring)."""
    theta = np.asarray(theta, float)
    r = curvature_range(theta, lo, hi)[0] if rho_low is None else np.asarray(rho_low, float)
    n = r.size
    # spikes (edges of the body: a positive mass of b + b'' inside a kernel) can only raise the discrete
    # values; clip each to the larger of its second neighbours so that they do not pass for slopes
    clipped = np.minimum(r, np.maximum(np.roll(r, 2), np.roll(r, -2))) if n >= 5 else r
    gaps = np.diff(np.append(theta, theta[0] + TWO_PI))  # gap g: between sample g and g + 1
    left = clipped  # value at the gap's left end
    right = np.roll(clipped, -1)
    descent = np.maximum(np.roll(clipped, 1) - left, 0.0) * gaps / np.roll(gaps, 1)
    ascent = np.maximum(np.roll(clipped, -2) - right, 0.0) * gaps / np.roll(gaps, -1)
    dip = 2.0 * np.minimum(descent, ascent)
    lowest = np.minimum(left, right) - dip
    return -float(np.min(np.minimum(lowest, r)))


def _width(theta, lo, hi):
    """The crude certified interval of ``b_c`` (no LP): [−max ρ_i⁺, upper]."""
    least, most = curvature_range(theta, lo, hi)
    return -float(np.min(most)), upper_bound(theta, lo, hi, least)


def choose_spacing(theta, lo, hi, *, max_samples: int = MAX_LP_SAMPLES):
    """The thinning (indices, spacing) at which the crude certified interval of ``b_c`` is narrowest, among
    a ladder of spacings from the data's own to a tenth of a radian (at least 64 samples kept)."""
    theta = np.asarray(theta, float)
    n = theta.size
    gaps = np.diff(np.append(theta, theta[0] + TWO_PI))
    candidates = []
    if n <= max_samples:
        candidates.append((np.arange(n), 0.0))
    spacing = max(float(np.median(gaps)), TWO_PI / (4 * max_samples)) if n > 8 else 0.0
    while spacing > 0 and TWO_PI / spacing >= 64:
        idx = thin(theta, spacing)
        if idx.size <= max_samples and idx.size >= 8:
            candidates.append((idx, spacing))
        spacing *= 1.6
    if not candidates:
        idx = thin(theta, TWO_PI / max_samples)
        candidates.append((idx, TWO_PI / max_samples))
    found = []
    for idx, spacing in candidates:
        if np.max(np.diff(np.append(theta[idx], theta[idx[0]] + TWO_PI))) >= math.pi * (1 - 1e-9):
            continue
        low, high = _width(theta[idx], lo[idx], hi[idx])
        found.append((high - low, idx, spacing))
    if not found:
        return np.arange(n), 0.0
    # the finest spacing whose interval is nearly the narrowest: resolution is worth a little width
    narrowest = min(f[0] for f in found)
    scale = max(float(np.max(np.abs(hi))), float(np.max(np.abs(lo))), 1.0)
    for width, idx, spacing in found:
        if width <= 2.0 * narrowest + 1e-9 * scale:
            return idx, spacing
    return found[-1][1], found[-1][2]  # pragma: no cover - the narrowest always qualifies


def _estimate(theta, values):
    """The discrete b_c with the leading spacing correction at its minimum (as for exact data)."""
    rho = curvature(theta, values)
    n = rho.size
    i = int(np.argmin(rho))
    left, mid, right = rho[(i - 1) % n], rho[i], rho[(i + 1) % n]
    second = left - 2.0 * mid + right
    between = (left - right) ** 2 / (8.0 * second) if second > 0 else 0.0
    return -float(mid - second / 12.0 - min(between, abs(left - mid) + abs(right - mid)))


def certified_critical(theta, b, halfwidth) -> CriticalBound:
    """The certified interval of the critical offset of interval data (module docstring).

    Parameters
    ----------
    theta : ndarray
        Distinct sorted angles in [0, 2π).
    b, halfwidth : ndarray
        The wall at ``theta`` lies within ``b ± halfwidth``.
    """
    theta = np.asarray(theta, float)
    b = np.asarray(b, float)
    w = np.asarray(halfwidth, float)
    lo, hi = b - w, b + w
    idx, spacing = choose_spacing(theta, lo, hi)
    t, l_, h_ = theta[idx], lo[idx], hi[idx]
    certified, objective = lp_lower_bound(t, l_, h_)
    upper = upper_bound(t, l_, h_)
    estimate = min(max(_estimate(t, b[idx]), certified), upper)
    lower = min(certified, estimate)
    idx.setflags(write=False)
    return CriticalBound(lower + 0.0, upper + 0.0, estimate + 0.0, ASSUMPTION, idx, spacing,
                         max(objective - certified, 0.0))
