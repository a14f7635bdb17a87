"""The critical offset of a sampled wall as an interval, and every angle where ``b + b''`` may reach its least
value: the first part of the certify stage (:mod:`coinwall.inverse.certify`, which re-exports the public names
of this module).

Each sample says only that the wall at ``θ_i`` lies in ``[b_i − w_i, b_i + w_i]``
(:mod:`coinwall.forward.sampledata`).  This module turns those intervals into statements about ``b_c``, each
with what it rests on (docs/theory.md, "What the data certify"):

* **b_c, lower end** (no assumption): the least offset for which *some* values ``s_i`` inside the intervals
  are support values of a convex body.  Support values at sorted directions (gaps below π) belong to a convex
  body iff every discrete radius of curvature is ≥ 0, and ``ρ_i(b0 + s) = b0 + ρ_i(s)`` is linear in ``s``
  with three neighbours: the linear programme ``minimise t subject to t + ρ_i(s) ≥ 0, lo_i ≤ s_i ≤ hi_i``,
  solved by scipy's HiGHS.  The value reported is rebuilt from its dual multipliers ``y ≥ 0, Σy = 1``:
  ``t ≥ Σ y_i (−ρ_i(s))`` for every feasible ``s``, whose least value over the box is a sum of per-sample
  extremes — a bound that holds whatever the solver's accuracy;
* **b_c, upper end** (under :data:`ASSUMPTION`): between two samples ``b + b''`` dips no lower than its
  discrete values on either side and their slopes predict (by twice the smaller of the descent into the gap
  and the ascent out of it); edges (positive spikes of the discrete curvature) and steps are no dips;
* **the critical angles**: every sample, or gap, where ``b + b''`` may reach its least value (its lowest
  possible value there at most ``−b_c⁻``, the largest the least value can be).

Samples closer than their own uncertainty say little about curvature (the discrete curvature of lines a hair
apart is their rounding over the square of the hair): ``b_c`` is computed at the spacing, from a ladder, where
its interval is narrowest; thinning drops constraints, so the lower end stays certified.  The ladder is kept
(:attr:`CriticalBound.ladder`): :func:`~coinwall.inverse.certify.certify` looks for corners at every spacing
of it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.sampledata import curvature_coefficients, thin
from coinwall.forward.sampledata import discrete_rho as curvature

__all__ = ["ASSUMPTION", "CriticalBound", "critical_bound", "curvature_range", "cyclic_runs", "lp_lower_bound"]

#: the assumption the upper end of the interval rests on (module docstring)
ASSUMPTION = ("between samples, b + b'' dips no lower than its discrete values on either side and their slopes "
              "predict (piecewise smooth, with edges and steps where the data show them)")
#: the LP of the lower end is solved on at most this many samples (HiGHS takes ~1 s at 10⁵); denser data are thinned
MAX_LP_SAMPLES = 20_000


@dataclass(frozen=True, repr=False)
class CriticalBound:
    """The critical offset of data as an interval, and where its minimum may lie (independent of ``b0``).

    Attributes
    ----------
    lower : float
        Certified: no wall consistent with the data has a smaller ``b_c`` (a linear programme).
    upper : float
        No wall consistent with the data *and* with :attr:`assumption` has a larger ``b_c``.
    estimate : float
        The best single value (the discrete curvature's minimum corrected for the spacing), in ``[lower, upper]``.
    assumption : str
        What :attr:`upper` rests on.
    used : ndarray of int
        The samples the interval was computed on (all of them, or a thinned subset of dense data).
    spacing : float
        The thinning spacing (rad; 0 if none).
    angles, intervals : tuple
        Every angle where ``b + b''`` may reach its least value (one per run of candidate samples: the midpoint
        of a run of three or more, else its best estimate); the runs of three or more (vertex windows).
    angle_tolerance : float
        How far the true minimiser of each run may be from its reported angle (rad).
    ladder : tuple of (ndarray, float)
        The thinnings looked at, finest first (indices, spacing); corners are looked for on each.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.inverse.certify import certify
    >>> theta = np.radians(np.arange(360.0))
    >>> corners = np.exp(2j * np.pi * np.arange(5) / 5)          # a regular pentagon's vertices
    >>> b = np.max(np.outer(np.cos(theta), corners.real) + np.outer(np.sin(theta), corners.imag), axis=1)
    >>> found = certify(theta, np.round(b, 8), np.full(360, 5e-9), 0.0)
    >>> bound = found.bound                 # a polygon: b_c = 0, within the certified interval
    >>> bool(bound.lower <= 0.0 <= bound.upper), len(bound.angles)
    (True, 5)
    """

    lower: float
    upper: float
    estimate: float
    assumption: str
    used: np.ndarray
    spacing: float
    angles: tuple = ()
    intervals: tuple = ()
    angle_tolerance: float = 0.0
    ladder: tuple = field(default=(), repr=False)

    def __repr__(self) -> str:
        return (f"CriticalBound(b_c in [{self.lower:.6g}, {self.upper:.6g}], estimate {self.estimate:.6g}, "
                f"{self.used.size} samples used, {len(self.angles)} critical angles)")



def cyclic_runs(mask) -> tuple[np.ndarray, np.ndarray]:
    """``(starts, lengths)`` of the runs of True in a cyclic boolean array (a run may wrap past the end).

    Parameters
    ----------
    mask : ndarray of bool

    Returns
    -------
    starts, lengths : ndarray of int
        Where each run starts and how long it is.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.inverse.certify import cyclic_runs
    >>> cyclic_runs(np.array([True, False, False, True, True]))      # one run: 3, 4, 0
    (array([3]), array([3]))
    """
    mask = np.asarray(mask, bool)
    n = mask.size
    if n == 0 or not mask.any():
        return np.zeros(0, int), np.zeros(0, int)
    if mask.all():
        return np.array([0]), np.array([n])
    shift = int(np.argmin(mask))  # a False entry: no run wraps past it
    edges = np.diff(np.concatenate([[0], np.roll(mask, -shift).astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return (starts + shift) % n, stops - starts


def curvature_range(theta, lo, hi):
    """The least and the largest ``ρ_i`` over values in the boxes ``[lo, hi]`` (each ρ_i depends on
    three values, so its extremes are taken independently).

    Parameters
    ----------
    theta : array_like (n,)
        Sorted angles in [0, 2π).
    lo, hi : array_like (n,)
        The lower and upper ends of each sample's interval.

    Returns
    -------
    low, high : ndarray (n,)
        The least and the largest discrete radius of curvature at each sample.

    Examples
    --------
    The unit circle's wall, sampled every 10° to ±0.001: ρ = 1 is within ``[low, high]`` at every sample.

    >>> import numpy as np
    >>> from coinwall.inverse.certify import curvature_range
    >>> theta = np.radians(np.arange(0.0, 360.0, 10.0))
    >>> low, high = curvature_range(theta, np.full(36, 0.999), np.full(36, 1.001))
    >>> round(float(low.min()), 4), round(float(high.max()), 4)
    (0.8694, 1.1306)
    """
    a, c, d = curvature_coefficients(theta)
    lo_prev, hi_prev, lo_next, hi_next = np.roll(lo, 1), np.roll(hi, 1), np.roll(lo, -1), np.roll(hi, -1)
    least = (np.minimum(a * lo_prev, a * hi_prev) + np.minimum(c * lo, c * hi)
             + np.minimum(d * lo_next, d * hi_next))
    most = (np.maximum(a * lo_prev, a * hi_prev) + np.maximum(c * lo, c * hi)
            + np.maximum(d * lo_next, d * hi_next))
    return least, most


def lp_lower_bound(theta, lo, hi) -> tuple[float, float]:
    """The certified lower end of ``b_c`` (module docstring) and HiGHS's own objective.

    Returns ``(certified, objective)``; ``certified ≤ objective`` up to rounding.

    Parameters
    ----------
    theta : array_like (n,)
        Sorted angles in [0, 2π).
    lo, hi : array_like (n,)
        The lower and upper ends of each sample's interval.

    Returns
    -------
    certified : float
        No wall inside the intervals has a smaller ``b_c`` (from the linear programme's dual).
    objective : float
        HiGHS's own optimum.

    Examples
    --------
    The unit circle sampled every 10° to ±0.001 (its ``b_c`` is −1):

    >>> import numpy as np
    >>> from coinwall.inverse.certify import lp_lower_bound
    >>> theta = np.radians(np.arange(0.0, 360.0, 10.0))
    >>> certified, objective = lp_lower_bound(theta, np.full(36, 0.999), np.full(36, 1.001))
    >>> round(certified, 6), certified <= objective + 1e-12
    (-1.001, True)
    """
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
    bounds = np.vstack([np.column_stack([lo - middle, hi - middle]), [-np.inf, np.inf]])
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


def _lowest_in_gaps(theta, r):
    """The lowest value ``b + b''`` may take in each gap (gap g between samples g and g + 1) under
    :data:`ASSUMPTION`, from the lowest discrete values ``r`` the intervals allow."""
    n = r.size
    # spikes (edges of the body: a positive mass of b + b'' inside a kernel) can only raise the discrete
    # values; clip each to the larger of its second neighbours so that they do not pass for slopes
    clipped = np.minimum(r, np.maximum(np.roll(r, 2), np.roll(r, -2))) if n >= 5 else r
    gaps = np.diff(np.append(theta, theta[0] + TWO_PI))
    left, right = clipped, np.roll(clipped, -1)
    descent = np.maximum(np.roll(clipped, 1) - left, 0.0) * gaps / np.roll(gaps, 1)
    ascent = np.maximum(np.roll(clipped, -2) - right, 0.0) * gaps / np.roll(gaps, -1)
    return np.minimum(left, right) - 2.0 * np.minimum(descent, ascent)


def choose_spacing(theta, lo, hi, *, max_samples: int = MAX_LP_SAMPLES):
    """``(indices, spacing, ladder)``: the thinning at which the crude certified interval of ``b_c`` is
    narrowest (or the finest within a factor 2 of it), among a ladder of spacings from the data's own to a
    tenth of a radian (at least 64 samples kept); ``ladder`` is every thinning looked at, finest first, the
    data's own included."""
    theta = np.asarray(theta, float)
    n = theta.size
    gaps = np.diff(np.append(theta, theta[0] + TWO_PI))
    ladder = [(np.arange(n), 0.0)]
    spacing = float(np.median(gaps)) * 1.6 if n > 8 else 0.0
    while spacing > 0 and TWO_PI / spacing >= 64:
        idx = thin(theta, spacing)
        if 8 <= idx.size < ladder[-1][0].size:
            ladder.append((idx, spacing))
        spacing *= 1.6
    found = []
    for idx, spacing in ladder:
        if idx.size > max_samples or np.max(np.diff(np.append(theta[idx], theta[idx[0]] + TWO_PI))) >= math.pi * (
                1 - 1e-9):
            continue
        least, most = curvature_range(theta[idx], lo[idx], hi[idx])
        upper = -float(min(np.min(_lowest_in_gaps(theta[idx], least)), np.min(least)))
        found.append((upper + float(np.min(most)), idx, spacing))
    if not found:
        idx = thin(theta, TWO_PI / max_samples)
        return idx, TWO_PI / max_samples, tuple(ladder)
    # the finest spacing whose interval is nearly the narrowest: resolution is worth a little width
    narrowest = min(f[0] for f in found)
    scale = max(float(np.max(np.abs(hi))), float(np.max(np.abs(lo))), 1.0)
    width, idx, spacing = next(f for f in found if f[0] <= 2.0 * narrowest + 1e-9 * scale)
    return idx, spacing, tuple(ladder)


def _estimate(theta, values):
    """The discrete b_c with the leading spacing correction at its minimum (as for exact data)."""
    rho = curvature(theta, values)
    n = rho.size
    i = int(np.argmin(rho))
    left, mid, right = rho[(i - 1) % n], rho[i], rho[(i + 1) % n]
    second = left - 2.0 * mid + right
    between = (left - right) ** 2 / (8.0 * second) if second > 0 else 0.0
    return -float(mid - second / 12.0 - min(between, abs(left - mid) + abs(right - mid)))


def _critical_angles(theta, values, least, lowest_gap, lower):
    """The critical angles (module docstring): where the lowest possible ``ρ`` — at a sample, or inside a gap
    under :data:`ASSUMPTION` — is at most ``−lower``, the largest value the minimum can have.  Samples and gaps
    alternate around the circle; each run of them is one place the minimum may be: an interval where the run
    holds three samples or more (a vertex window), else one angle (the parabola through the discrete values
    around the run's least one)."""
    n = theta.size
    slack = 1e-12 * max(1.0, float(np.max(np.abs(values))))
    cells = np.empty(2 * n, bool)  # sample 0, gap 0, sample 1, gap 1, …
    cells[0::2] = least <= -lower + slack
    cells[1::2] = lowest_gap <= -lower + slack
    if not cells.any():  # rounding: the sample of least ρ
        cells[2 * int(np.argmin(least))] = True
    rho = curvature(theta, values)
    before = np.diff(np.concatenate([[theta[-1] - TWO_PI], theta]))
    after = np.roll(before, -1)
    unwrapped = np.concatenate([theta, theta + TWO_PI])
    angles, intervals, tolerance = [], [], 0.0
    starts, lengths = cyclic_runs(cells)
    holds = [bool(np.any((start + np.arange(length)) % 2 == 0)) for start, length in zip(starts, lengths)]
    m = len(holds)
    for r, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist())):
        cell = (start + np.arange(length)) % (2 * n)
        samples = cell[cell % 2 == 0] // 2
        if samples.size == 0 and m > 1 and (holds[r - 1] or holds[(r + 1) % m]):
            # a gap next to an edge's sample, beside a run of samples: the run's own minimum reaches into it
            continue
        # the run's extent: from its first cell's start to its last cell's end (a gap spans to the next sample)
        lo = float(theta[cell[0] // 2])
        last = int(cell[-1])
        hi_index = last // 2 + (last % 2)
        span = TWO_PI if length >= 2 * n else float(np.mod(unwrapped[hi_index] - lo, TWO_PI))
        if samples.size >= 3:
            intervals.append((lo, lo + span))
            angles.append(float(np.mod(lo + 0.5 * span, TWO_PI)))
            tolerance = max(tolerance, 0.5 * span)
            continue
        if samples.size == 0:  # inside one gap
            angles.append(float(np.mod(lo + 0.5 * span, TWO_PI)))
            tolerance = max(tolerance, 0.5 * span)
            continue
        k = int(samples[np.argmin(rho[samples])])
        left, mid, right = rho[(k - 1) % n], rho[k], rho[(k + 1) % n]
        second = left - 2.0 * mid + right
        shift = float(np.clip(0.5 * (left - right) / second, -0.5, 0.5)) if second > 0 else 0.0
        where = theta[k] + shift * (after[k] if shift > 0 else before[k])
        angles.append(float(np.mod(where, TWO_PI)))
        tolerance = max(tolerance, float(np.mod(where - lo, TWO_PI)), float(np.mod(lo + span - where, TWO_PI)))
    order = np.argsort(angles)
    return tuple(angles[i] for i in order), tuple(sorted(intervals)), tolerance


def critical_bound(theta, b, halfwidth) -> CriticalBound:
    """The certified interval of the critical offset of interval data and its critical angles (module docstring).

    Parameters
    ----------
    theta : ndarray
        Distinct sorted angles in [0, 2π).
    b, halfwidth : ndarray
        The wall at ``theta`` lies within ``b ± halfwidth``.

    Returns
    -------
    CriticalBound

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    >>> bound = critical_bound(theta, 1 + 0.1 * np.cos(3 * theta), np.full(360, 5e-9))
    >>> bool(bound.lower <= -0.2 <= bound.upper), len(bound.angles)
    (True, 3)
    """
    theta = np.asarray(theta, float)
    b = np.asarray(b, float)
    w = np.asarray(halfwidth, float)
    lo, hi = b - w, b + w
    idx, spacing, ladder = choose_spacing(theta, lo, hi)
    t, l_, h_ = theta[idx], lo[idx], hi[idx]
    certified, _ = lp_lower_bound(t, l_, h_)
    least = curvature_range(t, l_, h_)[0]
    lowest_gap = _lowest_in_gaps(t, least)
    upper = -float(min(np.min(lowest_gap), np.min(least)))
    estimate = min(max(_estimate(t, b[idx]), certified), upper)
    lower = min(certified, estimate)
    angles, intervals, tolerance = _critical_angles(t, b[idx], least, lowest_gap, lower)
    idx.setflags(write=False)
    return CriticalBound(lower + 0.0, upper + 0.0, estimate + 0.0, ASSUMPTION, idx, spacing, angles, intervals,
                         tolerance, ladder)
