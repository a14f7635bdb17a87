"""The certify stage of a sampled wall: what every wall and body consistent with the samples' intervals share.

Each sample says only that the wall at ``θ_i`` lies in ``[b_i − w_i, b_i + w_i]``
(:mod:`coinwall.forward.sampledata`).  This module turns those intervals into statements, each with what it
rests on (docs/theory.md, "What the data certify"):

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
  possible value there at most ``−b_c⁻``, the largest the least value can be);
* **forced corners** at the offset ``b0``: windows ``[θ_i, θ_j]`` (two samples or more) through which every
  consistent body turns along at most ``L`` of boundary (:func:`certify`).  A consistent body touches line
  ``k`` on that line's piece between its neighbours, so its boundary from its touch point on line ``i`` to the
  one on line ``j`` is at most the sum of the pieces ``ℓ_k = ρ_k·(tan(Δ₋/2) + tan(Δ₊/2))``, ``i ≤ k ≤ j``: linear
  in the values, its largest value over every consistent set of values a small linear programme, certified
  from its dual like the lower end of b_c;
* **possible corners**: runs of samples where zero curvature is within the intervals but is not forced.

Samples closer than their own uncertainty say little about curvature (the discrete curvature of lines a hair
apart is their rounding over the square of the hair): ``b_c`` is computed at the spacing, from a ladder, where
its interval is narrowest; thinning drops constraints, so the lower end stays certified.  Corners are looked
for at every spacing of the ladder, the data's own included: a window the full data resolve is never lost.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.sampledata import curvature_coefficients, thin
from coinwall.forward.sampledata import discrete_rho as curvature

from .tolerances import OFFSET_TOLERANCE

__all__ = ["ASSUMPTION", "Certificate", "CriticalBound", "DataCorner", "certify", "critical_bound",
           "curvature_range", "cyclic_runs", "data_critical_offset", "lp_lower_bound"]

#: the assumption the upper end of the interval rests on (module docstring)
ASSUMPTION = ("between samples, b + b'' dips no lower than its discrete values on either side and their slopes "
              "predict (piecewise smooth, with edges and steps where the data show them)")
#: the LP of the lower end is solved on at most this many samples (HiGHS takes ~1 s at 10⁵); denser data are thinned
MAX_LP_SAMPLES = 20_000
#: most local linear programmes one certification solves for the length of corner windows (~2 ms each)
MAX_CORNER_PROGRAMMES = 200
#: a run of samples longer than this at one spacing gets no programme of its own (a coarser spacing has it)
MAX_CORNER_LINES = 3000
#: a window is a forced corner only when its mean radius of curvature is at most this fraction of the median
#: support value (:func:`certify`)
CORNER_RADIUS_FRACTION = 0.1


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


@dataclass(frozen=True)
class DataCorner:
    """A window of normal angles where the samples force (or allow) a corner.

    Attributes
    ----------
    window : (float, float)
        ``[start, end]`` (rad, unwrapped, ``end ≥ start``): the normals of the samples inside it.
    samples : int
        How many samples (at the spacing that found it) lie in the window.
    length : float
        Certified: every body consistent with the samples turns through the whole window along a piece of
        boundary at most this long; ``inf`` for a possible corner (nothing certified), finite for a forced one.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.inverse.certify import certify
    >>> theta = np.radians(np.arange(360.0))
    >>> corners = np.exp(2j * np.pi * np.arange(5) / 5)          # a regular pentagon's vertices
    >>> b = np.max(np.outer(np.cos(theta), corners.real) + np.outer(np.sin(theta), corners.imag), axis=1)
    >>> found = certify(theta, np.round(b, 8), np.full(360, 5e-9), 0.0)
    >>> corner = found.corners[0]
    >>> [round(angle, 4) for angle in corner.window], corner.length < 1e-4
    ([0.7156, 1.7977], True)
    """

    window: tuple
    samples: int
    length: float

    @property
    def width(self) -> float:
        return float(self.window[1] - self.window[0])

    def to_dict(self) -> dict:
        forced = math.isfinite(self.length)
        return {"window": list(self.window), "samples": self.samples, "length": self.length if forced else None,
                "forced": forced}


@dataclass(frozen=True, repr=False)
class Certificate:
    """What the samples certify at one offset ``b0`` (:func:`certify`).

    Attributes
    ----------
    bound : CriticalBound
        The interval of ``b_c`` and the critical angles.
    b0 : float
    corners : tuple of DataCorner
        The forced corners, by angle.
    possible : tuple of DataCorner
        Windows where the data allow a corner they do not force (at any spacing of the ladder).
    regimes : tuple of str
        The regimes the data allow at ``b0``; one when they decide it.
    regime : str
        The decided regime, or ``"critical"`` where they do not decide (the body is then the simplest one).
    band : coinwall.inverse.band.Band or None
        The envelopes of every consistent body at ``b0`` (None below ``b_c⁻``, where there is none).

    Examples
    --------
    A regular pentagon's support function at every degree, rounded to 8 decimals: the data force its five
    corners.

    >>> import numpy as np
    >>> from coinwall.inverse.certify import certify
    >>> theta = np.radians(np.arange(360.0))
    >>> corners = np.exp(2j * np.pi * np.arange(5) / 5)          # a regular pentagon's vertices
    >>> b = np.max(np.outer(np.cos(theta), corners.real) + np.outer(np.sin(theta), corners.imag), axis=1)
    >>> found = certify(theta, np.round(b, 8), np.full(360, 5e-9), 0.0)
    >>> found
    Certificate(b0=0, critical, 5 forced corners, 0 possible)
    """

    bound: CriticalBound
    b0: float
    corners: tuple
    possible: tuple
    regimes: tuple
    regime: str
    band: object = field(default=None, repr=False)

    def __repr__(self) -> str:
        return (f"Certificate(b0={self.b0:g}, {'/'.join(self.regimes)}, {len(self.corners)} forced corners, "
                f"{len(self.possible)} possible)")


# ---------------------------------------------------------------------------------------------- the b_c interval
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


# ---------------------------------------------------------------------------------------------- corners at b0
def _piece_norm(theta):
    """``tan(Δ₋/2) + tan(Δ₊/2)``: the piece of line i between its neighbours is ``ρ_i`` times it."""
    before = np.diff(np.concatenate([[theta[-1] - TWO_PI], theta]))
    return np.tan(before / 2) + np.tan(np.roll(before, -1) / 2)


def _window_length(theta, lo, hi, b0, first, count):
    """Certified: the largest boundary length a body with support values in ``b0 + [lo, hi]`` can have over the
    normals of samples ``first … first + count − 1`` (cyclic): the largest sum of their pieces subject to every
    discrete radius of curvature nearby ≥ 0, a local linear programme (a relaxation of the whole one, so its
    maximum is an upper bound), certified from its dual multipliers.  ``inf`` if HiGHS finds nothing."""
    from scipy.optimize import linprog
    from scipy.sparse import coo_matrix

    n = theta.size
    margin = 3
    size = min(count + 2 * margin, n)
    var = (first - margin + np.arange(size)) % n if size < n else np.arange(n)
    a, c, d = curvature_coefficients(theta)
    norm = _piece_norm(theta)
    inside = (first + np.arange(count)) % n
    # constraints b0 + ρ_k(s) ≥ 0 for the lines whose three values are all variables
    position = np.full(n, -1)
    position[var] = np.arange(var.size)
    rows_k = var[(position[(var - 1) % n] >= 0) & (position[(var + 1) % n] >= 0)]
    cols = np.stack([position[(rows_k - 1) % n], position[rows_k], position[(rows_k + 1) % n]], axis=1)
    coef = np.stack([a[rows_k], c[rows_k], d[rows_k]], axis=1)
    A = coo_matrix((coef.ravel(), (np.repeat(np.arange(rows_k.size), 3), cols.ravel())),
                   shape=(rows_k.size, var.size)).tocsr()
    # the objective: Σ_{k inside} norm_k ρ_k(s) (+ b0 Σ norm_k), as a row over the variables
    objective = np.zeros(var.size)
    for col, table in ((-1, a), (0, c), (1, d)):
        np.add.at(objective, position[(inside + col) % n], norm[inside] * table[inside])
    middle = 0.5 * (lo[var] + hi[var])
    box_lo, box_hi = lo[var] - middle, hi[var] - middle
    constant = b0 * float(norm[inside].sum()) + float(objective @ middle)
    res = linprog(-objective, A_ub=-A, b_ub=b0 + A @ middle, bounds=np.column_stack([box_lo, box_hi]),
                  method="highs")
    if res.status != 0 or res.ineqlin is None:
        return math.inf
    y = np.maximum(-np.asarray(res.ineqlin.marginals, float), 0.0)
    # for every feasible s: objective·s ≤ objective·s + Σ y_k (b0 + ρ_k(s + middle)), maximised over the box
    total = objective + A.T @ y
    bound = float(np.sum(np.maximum(total * box_lo, total * box_hi))) + float(y @ (b0 + A @ middle))
    return max(bound + constant, 0.0)


def _runs_at(theta, lo, hi, b0):
    """Runs of samples where zero curvature is within the intervals at this spacing, with the box bound of the
    boundary length over each: ``(starts, lengths, widths, box lengths)``."""
    least, most = curvature_range(theta, lo, hi)
    starts, lengths = cyclic_runs(least + b0 <= 0.0)
    n = theta.size
    pieces = np.maximum(most + b0, 0.0) * _piece_norm(theta)
    total = np.concatenate([[0.0], np.cumsum(np.concatenate([pieces, pieces]))])
    ends = starts + lengths  # exclusive, unwrapped
    box = total[ends] - total[starts]
    unwrapped = np.concatenate([theta, theta + TWO_PI])
    widths = np.where(lengths < n, unwrapped[np.minimum(ends - 1, 2 * n - 1)] - theta[starts], TWO_PI)
    return starts, lengths, widths, box


def _possible(theta, lo, hi, b0, ladder, taken):
    """Runs where zero curvature is within the intervals, narrower than π/2, at every spacing of the ladder
    (finest first), each window once and none overlapping ``taken``."""
    out = []
    for idx, _ in ladder:
        starts, lengths, widths, _ = _runs_at(theta[idx], lo[idx], hi[idx], b0)
        for start, length, width in zip(starts.tolist(), lengths.tolist(), widths.tolist()):
            window = (float(theta[idx][start]), float(theta[idx][start]) + width)
            if width < 0.5 * math.pi and not any(_overlap(window, other) for other in taken):
                out.append(DataCorner(window, int(length), math.inf))
                taken.append(window)
    return sorted(out, key=lambda c: np.mod(c.window[0], TWO_PI))


def _overlap(a, b):
    """Whether two unwrapped angular windows overlap (mod 2π)."""
    shift = np.mod(b[0] - a[0], TWO_PI)
    return bool(shift <= a[1] - a[0] or shift + (b[1] - b[0]) >= TWO_PI)


def certify(theta, b, halfwidth, b0: float, bound: CriticalBound | None = None) -> Certificate:
    """What the samples ``b ± halfwidth`` at ``theta`` certify at the offset ``b0`` (module docstring).

    A window of width ``W`` through which every consistent body turns along at most ``L`` of boundary is a
    **forced corner** when ``L/W`` (its mean radius of curvature) is below a tenth of the median support value
    ``R`` — a corner, not a bend — and either ``L`` is within the outline tolerance (the turn is a point at the
    resolution the outline is known to) or ``L/W`` is within half the width of b_c's interval (zero curvature at
    the resolution the data fix the least radius of curvature to).  Windows are looked for where zero curvature
    is within the intervals, on every thinning of the ladder.  The regime: ``corner`` below ``b_c⁻``,
    ``convex`` above ``b_c⁺``, ``critical`` in between when a corner is forced, and undecided otherwise (every
    regime the interval allows).

    Parameters
    ----------
    theta : ndarray
        Distinct sorted angles in [0, 2π).
    b, halfwidth : ndarray
        The intervals.
    b0 : float
        The offset.
    bound : CriticalBound, optional
        :func:`critical_bound` of the same data, when already computed.

    Returns
    -------
    Certificate

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.radians(np.arange(360.0))
    >>> corners = np.exp(2j * np.pi * np.arange(5) / 5)
    >>> b = np.max(np.outer(np.cos(theta), corners.real) + np.outer(np.sin(theta), corners.imag), axis=1)
    >>> found = certify(theta, np.round(b, 8), np.full(360, 5e-9), 0.0)
    >>> found.regime, len(found.corners)
    ('critical', 5)
    """
    theta = np.asarray(theta, float)
    b = np.asarray(b, float)
    w = np.asarray(halfwidth, float)
    if bound is None:
        bound = critical_bound(theta, b, w)
    lo, hi = b - w, b + w
    scale = max(1.0, float(np.max(np.abs(b + b0))))
    tol = OFFSET_TOLERANCE * scale
    band = None
    if b0 >= bound.lower - tol:  # some consistent body: the envelopes of them all (coinwall.inverse.band)
        from .band import band_of

        band = band_of(theta, b0 + lo, b0 + hi)
    outline_tolerance = band.tolerance if band is not None else 0.0
    bend = CORNER_RADIUS_FRACTION * max(float(np.median(b + b0)), 1e-300)
    resolution = 0.5 * (bound.upper - bound.lower)

    def forced(length, width):
        return length <= bend * width and (length <= outline_tolerance or length <= resolution * width)

    corners = []
    if bound.lower - tol <= b0 <= bound.upper + tol:
        budget = MAX_CORNER_PROGRAMMES
        found = []
        for idx, _ in reversed(bound.ladder):  # coarsest first: a window certified there is not solved again
            t, l_, h_ = theta[idx], lo[idx], hi[idx]
            starts, lengths, widths, box = _runs_at(t, l_, h_, b0)
            for start, length, width, length_box in zip(starts.tolist(), lengths.tolist(), widths.tolist(),
                                                        box.tolist()):
                window = (float(t[start]), float(t[start]) + width)
                if length < 2 or not 0 < width < math.pi or any(_overlap(window, c.window) for c in found):
                    continue
                certified = length_box
                if not forced(certified, width) and budget > 0 and length <= MAX_CORNER_LINES:
                    budget -= 1
                    certified = min(certified, _window_length(t, l_, h_, b0, start, length))
                if forced(certified, width):
                    found.append(DataCorner(window, int(length), certified))
        corners = sorted(found, key=lambda c: np.mod(c.window[0], TWO_PI))
    if b0 < bound.lower - tol:
        regimes = ("corner",)
    elif b0 > bound.upper + tol:
        regimes, corners = ("convex",), []
    elif corners:
        regimes = ("critical",)
    else:  # every regime the interval allows (critical always)
        regimes = tuple(r for r, ok in (("corner", b0 > bound.lower + tol), ("critical", True),
                                        ("convex", b0 < bound.upper - tol)) if ok)
    possible = []
    if regimes not in (("convex",), ("corner",)):
        possible = _possible(theta, lo, hi, b0, bound.ladder, [c.window for c in corners])
    regime = regimes[0] if len(regimes) == 1 else "critical"
    return Certificate(bound, float(b0), tuple(corners), tuple(possible), tuple(regimes), regime, band)


def data_critical_offset(wall):
    """The critical offset of a sampled wall as :func:`coinwall.inverse.critical_offset` reports it: the best
    estimate, the certified interval (:attr:`~CriticalOffset.lower`, :attr:`~CriticalOffset.upper`) and every
    critical angle (:func:`critical_bound`; computed once per wall, which is immutable).

    Parameters
    ----------
    wall : Wall
        A wall made from samples (:meth:`Wall.from_samples`, :func:`~coinwall.forward.formats.load_wall`).

    Returns
    -------
    CriticalOffset
        With :attr:`~CriticalOffset.lower`, :attr:`~CriticalOffset.upper` and the assumption the upper end
        rests on.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall import Wall, critical_offset
    >>> theta = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    >>> result = critical_offset(Wall.from_samples(theta, 1 + 0.1 * np.sin(3 * theta)))
    >>> bool(result.lower <= -0.2 <= result.upper), [round(float(a), 3) for a in result.angles]
    (True, [0.524, 2.618, 4.712])
    """
    from .critical import CriticalOffset

    data = wall.sample_data
    if data.sd is not None:  # statistics: an estimate with a confidence interval (coinwall.inverse.noise)
        from .noise import noisy_critical

        found = noisy_critical(data.theta, data.b, data.sd)
        tolerance = max(found.estimate - found.lower, found.upper - found.estimate)
        return CriticalOffset(found.estimate, found.angles, (), float(TWO_PI / (64 * found.harmonics)), tolerance,
                              found.lower, found.upper, f"a {found.level:.0%} confidence interval, assuming "
                              f"{found.assumption}", found.samples)
    bound = wall.__dict__.get("_certified_bound")
    if bound is None:
        bound = critical_bound(data.theta, data.b, data.halfwidth)
        object.__setattr__(wall, "_certified_bound", bound)
    tolerance = max(bound.estimate - bound.lower, bound.upper - bound.estimate)
    return CriticalOffset(bound.estimate, bound.angles, bound.intervals, bound.angle_tolerance, tolerance,
                          bound.lower, bound.upper, bound.assumption, int(bound.used.size))
