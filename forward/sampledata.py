"""Walls as data: every sample is an interval.

A sample ``(θ_i, b_i)`` written in a file is known only to its digits: ``θ_i`` to ``±σθ_i`` and
``b_i`` to ``±σb_i`` (half a unit of the last digit written, or what the user says).  What the
geometry needs is how far the wall *at the nominal angle* ``θ_i`` may be from ``b_i``:

    |b(θ_i) − b_i| ≤ w_i = σb_i + S_i σθ_i,     S_i ≥ max |b'| on [θ_i − σθ_i, θ_i + σθ_i].

The slope bound ``S_i`` is certified for any wall that is a support function at some offset (the
premise of the whole question): with ``h = b0 + b`` and ``ρ = h + h'' ≥ 0``, ``h'' ≥ −h ≥ −H`` where
``H`` bounds ``h``; so on an angular span ``s`` to the left of θ_i the secant is at most
``h'(θ_i) + s H`` and to the right at least ``h'(θ_i) − s H``:

    sec(θ_a, θ_i) − s H ≤ h'(θ_i) ≤ sec(θ_i, θ_c) + s H.

The secants are taken over spans long enough that the values' own rounding does not swamp them,
and their rounding is added.  ``b'`` may jump *up* at an edge of the body (inside the window), never
down, and the two one-sided secants bound both sides.

Samples at the same angle (duplicates, or angles that round to the same value) are merged: the wall
at that angle lies in the intersection of their intervals; an empty intersection is an
inconsistency in the data, named with the two samples.

This module only builds the intervals (:func:`sample_intervals`); what they imply for the critical
offset and the body is in :mod:`coinwall.inverse.certify` (docs/theory.md, "Data as intervals").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .angles import TWO_PI
from .errors import InvalidWall

__all__ = ["SampleData", "sample_intervals", "grid_scatter", "curvature_coefficients", "discrete_rho", "thin"]

_EPS = float(np.finfo(float).eps)
#: angles closer than this (rad, after reduction mod 2π) are one angle: a duplicate sample
SAME_ANGLE = 1e-9


@dataclass(frozen=True, repr=False)
class SampleData:
    """Samples of a wall as intervals at distinct nominal angles.

    Attributes
    ----------
    theta : ndarray
        Distinct angles in [0, 2π), sorted.
    b : ndarray
        The middle of the interval in which the wall at ``theta`` lies.
    halfwidth : ndarray
        ``|b(θ_i) − b_i| ≤ halfwidth_i``: the values' rounding plus the slope times the angles' rounding
        (and, for merged duplicates, the intersection of their intervals).
    sigma_b, sigma_theta : ndarray
        The largest value and angle half-widths of the samples merged at each angle.
    slope : ndarray
        The certified bound on ``|b'|`` near each angle that turned ``sigma_theta`` into a value error.
    count : ndarray
        How many input samples each angle holds.
    notes : tuple of str
        What the reader of the samples decided about them that a user should know (a designed grid taken
        as exact, or not).
    sd : ndarray or None
        Standard deviation of :attr:`b` at each angle (the mean of the samples there), where the samples
        came with standard deviations of their values or angles (statistics: the solvers estimate); None
        for samples known to their intervals only.

    Examples
    --------
    >>> from coinwall.forward.sampledata import sample_intervals
    >>> data = sample_intervals([0.0, 1.0, 2.0, 3.0, 4.0, 5.0], [1.0] * 6, 0.01)
    >>> data
    SampleData(6 angles, 0 merged duplicates, largest half-width 0.01)
    >>> data.count.tolist()
    [1, 1, 1, 1, 1, 1]
    """

    theta: np.ndarray
    b: np.ndarray
    halfwidth: np.ndarray
    sigma_b: np.ndarray
    sigma_theta: np.ndarray
    slope: np.ndarray
    count: np.ndarray
    notes: tuple = ()
    sd: np.ndarray | None = None

    @property
    def merged(self) -> int:
        """Input samples merged into another at the same angle."""
        return int(np.sum(self.count) - self.count.size)

    @property
    def lower(self) -> np.ndarray:
        return self.b - self.halfwidth

    @property
    def upper(self) -> np.ndarray:
        return self.b + self.halfwidth

    def __repr__(self) -> str:
        return (f"SampleData({self.theta.size} angles, {self.merged} merged duplicates, "
                f"largest half-width {float(np.max(self.halfwidth)):.3g})")


def _neighbours_at_least(theta, span):
    """Index of the nearest sample at least ``span`` before (cyclically) each sample, and after."""
    n = theta.size
    ext = np.concatenate([theta - TWO_PI, theta, theta + TWO_PI])
    before = np.searchsorted(ext, theta - span, side="right") - 1  # last with ext <= theta - span
    after = np.searchsorted(ext, theta + span, side="left")  # first with ext >= theta + span
    return before, after, ext, n


def _slope_bound(theta, b, sigma_b, sigma_theta, h_bound, noise):
    """A bound ``S_i`` on |b'| near each sample (module docstring), from secants over spans that the
    rounding of values and angles does not swamp.

    The values at the nominal angles are off by up to ``σb + S σθ`` themselves, so a secant over a span
    ``s`` is off by ``(σb_i + σb_a + S (σθ_i + σθ_a)) / s``; with the curvature term ``s H`` this gives
    ``S (1 − (σθ_i + σθ_a)/s) ≥ |secant| + (σb_i + σb_a)/s + s H``, solved for S (spans ≥ 4 σθ)."""
    n = theta.size
    typical = float(np.median(noise)) if n else 0.0
    span = math.sqrt(4.0 * typical / max(h_bound, 1e-300)) if typical > 0 else 0.0
    gaps = np.diff(np.append(theta, theta[0] + TWO_PI))
    span = min(max(span, float(np.min(gaps)), 4.0 * float(np.max(sigma_theta))), TWO_PI / 16)
    before, after, ext, _ = _neighbours_at_least(theta, span)
    ext_b = np.concatenate([b, b, b])
    ext_s = np.concatenate([sigma_b, sigma_b, sigma_b])
    ext_t = np.concatenate([sigma_theta, sigma_theta, sigma_theta])
    i = np.arange(n) + n
    bounds = []
    for j in (before, after):
        length = np.abs(ext[i] - ext[j])
        secant = np.abs(ext_b[i] - ext_b[j]) / length
        shrink = np.maximum(1.0 - (ext_t[i] + ext_t[j]) / length, 0.25)
        bounds.append((secant + (ext_s[i] + ext_s[j]) / length + length * h_bound) / shrink)
    # h'(θ_i) lies between the left secant's lower and the right secant's upper bound
    return np.maximum(bounds[0], bounds[1])


def _grid_verdict(theta, b, halfwidth, sd, step):
    """The note on a designed grid: exact where the samples' scatter is within their own errors (3 standard
    deviations of uniform rounding, ``w/√3``, or of the given noise) or falls off with the order of the
    differences (a smooth wall, not noise); else not exact."""
    scatter = grid_scatter(np.asarray(b, float)[np.argsort(np.mod(theta, TWO_PI))])
    allowed = 3.0 * float(np.median(halfwidth)) / math.sqrt(3.0)
    if sd is not None:
        allowed = max(allowed, 3.0 * float(np.median(sd)))
    every = f"every {math.degrees(step):.6g}°"
    if scatter[2] > allowed and scatter[2] >= 0.5 * scatter[0]:
        return (f"the angles look like a designed grid ({every}), but the values scatter about a smooth wall by "
                f"about {scatter[2]:.2g}, more than their digits allow ({allowed:.2g}): the grid is not taken as "
                f"exact, every angle is known to ±{0.5 * math.degrees(step):.6g}°",)
    errors = "standard deviations" if sd is not None else "digits"
    return (f"the angles are a designed grid ({every}), taken as exact: the values agree (their scatter about a "
            f"smooth wall, {scatter[2]:.2g}, is within what their {errors} allow)",)


def grid_scatter(values) -> tuple[float, float, float]:
    """Robust estimates of the scatter of samples on a uniform grid of angles about a smooth wall, from their
    4th, 6th and 8th cyclic differences: ``median |Δᵏb| / (0.6745 √C(2k, k))``, the standard deviation of
    independent noise at each order.  Independent noise gives the same value at every order; a smooth wall's
    contribution falls with the order (by ``(2 sin(mΔ/2))²`` per two orders for a harmonic m); the kinks of a
    polygon touch only the few differences around each (the median passes them by).  Fewer than 48 samples:
    zeros (no verdict).

    Parameters
    ----------
    values : array_like (n,)
        Wall values on a uniform grid of angles over one period.

    Returns
    -------
    (float, float, float)
        The noise's standard deviation estimated from the 4th, 6th and 8th differences.

    Examples
    --------
    >>> theta = np.radians(np.arange(360.0))
    >>> smooth = np.sqrt((1 + np.cos(theta) ** 2) / 2)
    >>> bool(grid_scatter(smooth)[2] < 1e-12)
    True
    >>> noisy = smooth + 1e-3 * np.random.default_rng(0).standard_normal(360)
    >>> [round(s, 3) for s in grid_scatter(noisy)]
    [0.001, 0.001, 0.001]
    """
    from math import comb

    values = np.asarray(values, float)
    if values.size < 48:
        return 0.0, 0.0, 0.0
    out = []
    diff = values
    for order in range(1, 9):
        diff = np.roll(diff, -1) - diff
        if order in (4, 6, 8):
            out.append(float(np.median(np.abs(diff))) / (0.6745 * math.sqrt(comb(2 * order, order))))
    return tuple(out)


def thin(theta, spacing: float) -> np.ndarray:
    """Indices of a subset of sorted angles about ``spacing`` apart: the first angle in each bin of that width,
    then any kept angle closer than half the spacing to the one kept before it dropped (vectorised: 10⁶
    angles in milliseconds).  Consecutive kept angles are between ``spacing/2`` and ``2·spacing`` apart
    where the data are dense enough, and the wrap from the last to the first is respected.

    Parameters
    ----------
    theta : array_like (n,)
        Sorted angles in [0, 2π).
    spacing : float
        The spacing wanted (rad).

    Returns
    -------
    ndarray of int
        Indices into ``theta`` of the angles kept.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward.sampledata import thin
    >>> kept = thin(np.radians(np.arange(360.0)), np.radians(10.0))     # every degree, thinned to 10°
    >>> kept.size, kept[:3].tolist()
    (36, [0, 10, 20])
    """
    theta = np.asarray(theta, float)
    if spacing <= 0 or theta.size < 2:
        return np.arange(theta.size)
    bins = np.floor((theta - theta[0]) / spacing).astype(np.int64)
    keep = np.flatnonzero(np.r_[True, bins[1:] != bins[:-1]])
    for _ in range(3):
        gaps = np.diff(theta[keep])
        close = np.flatnonzero(gaps < 0.5 * spacing) + 1
        if close.size == 0:
            break
        # drop every other of a run of close ones, so that a run does not vanish whole
        drop = close[np.r_[True, np.diff(close) > 1]]
        keep = np.delete(keep, drop)
    if keep.size > 1 and theta[keep[0]] + TWO_PI - theta[keep[-1]] < 0.5 * spacing:
        keep = keep[:-1]
    return keep


def curvature_coefficients(theta):
    """``ρ_i = a_i h_{i−1} + c_i h_i + d_i h_{i+1}`` (cyclic): the discrete radius of curvature of support values
    at sorted angles, the length of the piece of line i between lines i∓1 over ``tan(Δ₋/2) + tan(Δ₊/2)``
    (docs/theory.md, "Walls as data").  The one place the formula is written.

    Parameters
    ----------
    theta : array_like (n,)
        Sorted angles in [0, 2π).

    Returns
    -------
    a, c, d : ndarray (n,)
        The coefficients of ``h_{i−1}``, ``h_i`` and ``h_{i+1}``.

    Examples
    --------
    The unit circle (``h = 1``) has ρ = 1 at every sample:

    >>> import numpy as np
    >>> from coinwall.forward.sampledata import curvature_coefficients
    >>> theta = np.radians(np.arange(0.0, 360.0, 10.0))
    >>> a, c, d = curvature_coefficients(theta)
    >>> bool(np.allclose(a + c + d, 1.0))
    True
    """
    theta = np.asarray(theta, dtype=float)
    before = np.diff(np.concatenate([[theta[-1] - TWO_PI], theta]))
    after = np.roll(before, -1)
    norm = np.tan(before / 2) + np.tan(after / 2)
    return 1.0 / (np.sin(before) * norm), -(1.0 / np.tan(before) + 1.0 / np.tan(after)) / norm, \
        1.0 / (np.sin(after) * norm)


def discrete_rho(theta, values):
    """The discrete radius of curvature of support ``values`` at sorted ``theta``: the same linear form as
    :func:`curvature_coefficients`, evaluated as the piece length ``(h_{i∓1} − h_i cos Δ∓)/sin Δ∓`` (which
    keeps its digits where lines a hair apart make the coefficients cancel).

    Parameters
    ----------
    theta : array_like (n,)
        Sorted angles in [0, 2π).
    values : array_like (n,)
        Support values at them.

    Returns
    -------
    ndarray (n,)
        The discrete radius of curvature at each sample.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward.sampledata import discrete_rho
    >>> theta = np.radians(np.arange(0.0, 360.0, 10.0))
    >>> discrete_rho(theta, 2.0 + 0 * theta)[:3].round(12).tolist()       # a circle of radius 2
    [2.0, 2.0, 2.0]
    """
    theta = np.asarray(theta, dtype=float)
    values = np.asarray(values, dtype=float)
    before = np.diff(np.concatenate([[theta[-1] - TWO_PI], theta]))
    after = np.roll(before, -1)
    length = ((np.roll(values, 1) - values * np.cos(before)) / np.sin(before)
              + (np.roll(values, -1) - values * np.cos(after)) / np.sin(after))
    return length / (np.tan(before / 2) + np.tan(after / 2))


def _h_bound(theta, b, noise):
    """A bound on ``h = b0 + b`` at the least offset that makes the wall convex — the scale of ``h''``
    the slope bound needs.  Estimated from the discrete curvature of the data on samples far enough
    apart that their rounding (``noise``) moves it by less than a tenth of the wall's size, with a
    margin of 2."""
    scale = max(float(np.max(np.abs(b))), 1e-300)
    spacing = min(math.sqrt(40.0 * float(np.max(noise)) / scale), TWO_PI / 16)
    idx = thin(theta, spacing) if theta.size > 16 and spacing > 0 else np.arange(theta.size)
    if idx.size < 8:
        return 4.0 * scale
    rho = discrete_rho(theta[idx], b[idx])
    b_c = max(-float(np.min(rho)), -float(np.min(b)))
    return 2.0 * max(float(np.max(b)) + b_c, scale)


def sample_intervals(theta, b, sigma_b=None, sigma_theta=None, labels=None, *, merge: str = "intersect", sd=None,
                     theta_sd=None, grid=None) -> SampleData:
    """The samples as intervals at distinct angles (module docstring).

    Parameters
    ----------
    theta, b : array_like
        Angles (radians, any range: reduced mod 2π) and wall values, finite, same length.
    sigma_b, sigma_theta : float or array_like, optional
        Half-widths of the values and of the angles (radians), one or one per sample; default a few
        ulps (numbers at face value).
    labels : sequence of str, optional
        How to name each sample in a message (``"line 17"``); default ``"sample k"`` (1-based).
    merge : {"intersect", "mean"}
        Samples at one angle: the intersection of their intervals (data known to their digits), or, for
        noisy measurements that scatter beyond their digits, their mean with a half-width that covers
        every one of them.
    sd, theta_sd : float or array_like, optional
        Standard deviations of the values and of the angles (radians), one or one per sample: statistics,
        kept apart from the half-widths (:attr:`SampleData.sd`); with either, samples at one angle are averaged.
    grid : float, optional
        The step (radians) of a uniform grid the angles were written on: exact — the design of the data — where
        the values agree, their scatter about a smooth wall (:func:`grid_scatter`) within what their half-widths
        (or standard deviations) allow; where it is not, every angle is taken to ``±grid/2``.  A note says which
        (:attr:`SampleData.notes`).

    Returns
    -------
    SampleData

    Examples
    --------
    Two samples at one angle (2π is 0) are merged into the intersection of their intervals:

    >>> import numpy as np
    >>> from coinwall.forward.sampledata import sample_intervals
    >>> data = sample_intervals([0.0, 2 * np.pi, 1.0, 2.0, 3.0, 4.0, 5.0], [1.0, 1.005, 1, 1, 1, 1, 1], 0.01)
    >>> data.theta.size, data.count.tolist()[0], round(float(data.b[0]), 4), round(float(data.halfwidth[0]), 4)
    (6, 2, 1.0025, 0.0075)

    Raises
    ------
    InvalidWall
        Two samples at the same angle whose intervals do not overlap (named), or bad half-widths.
    """
    theta = np.asarray(theta, dtype=float).ravel()
    b = np.asarray(b, dtype=float).ravel()
    n_in = theta.size
    face = 2.0 * _EPS * np.maximum(np.abs(b), np.finfo(float).tiny)

    def spread(value, name, floor):
        if value is None:
            return floor
        arr = np.asarray(value, dtype=float)
        if arr.ndim > 1 or arr.size not in (1, n_in) or not np.all(np.isfinite(arr)) or np.any(arr < 0):
            raise InvalidWall(f"`{name}` must be one finite number ≥ 0 or one per sample")
        return np.maximum(np.broadcast_to(arr, (n_in,)).astype(float), floor)

    sb = spread(sigma_b, "b_halfwidth", face)
    st = spread(sigma_theta, "theta_halfwidth", 4.0 * _EPS * np.maximum(np.abs(theta), TWO_PI))
    statistical = sd is not None or theta_sd is not None
    notes = () if grid is None else _grid_verdict(theta, b, sb, sd, grid)
    if len(notes) and "not taken as exact" in notes[0]:
        st = np.maximum(st, 0.5 * grid)
    if statistical:
        merge = "mean"
        var_b = spread(sd, "b_sd", np.zeros(n_in)) ** 2
        var_t = spread(theta_sd, "theta_sd", np.zeros(n_in)) ** 2
    reduced = np.mod(theta, TWO_PI)
    reduced[reduced >= TWO_PI] = 0.0
    order = np.argsort(reduced, kind="stable")
    reduced, values, sb, st = reduced[order], b[order], sb[order], st[order]
    if statistical:
        var_b, var_t = var_b[order], var_t[order]
    # groups of one angle: consecutive angles within SAME_ANGLE (and the wrap from 2π to 0)
    new = np.ones(reduced.size, bool)
    new[1:] = np.diff(reduced) > SAME_ANGLE
    group = np.cumsum(new) - 1
    if reduced.size > 1 and reduced[0] + TWO_PI - reduced[-1] <= SAME_ANGLE and group[-1] > 0:
        group[group == group[-1]] = 0
    m = int(group.max()) + 1
    count = np.bincount(group, minlength=m)
    # the nominal angle of a group: its first member (a wrapped group keeps the angle near 0)
    first = np.full(m, -1)
    first[group[::-1]] = np.arange(reduced.size)[::-1]
    angle = reduced[first]
    spread_angle = np.zeros(m)
    np.maximum.at(spread_angle, group, np.abs(np.mod(reduced - angle[group] + np.pi, TWO_PI) - np.pi))
    mean = np.bincount(group, weights=values, minlength=m) / count
    sig_b = np.zeros(m)
    np.maximum.at(sig_b, group, sb)
    sig_t = np.zeros(m)
    np.maximum.at(sig_t, group, st)
    sig_t = sig_t + spread_angle
    key = np.argsort(angle, kind="stable")
    if not np.array_equal(key, np.arange(m)):  # the wrapped group moved to the front
        remap = np.empty(m, int)
        remap[key] = np.arange(m)
        group = remap[group]
        angle, mean, sig_b, sig_t, count = angle[key], mean[key], sig_b[key], sig_t[key], count[key]
    if m >= 3:
        # the angles' rounding makes the values noisy too, by up to |b'| σθ (|b'| ≤ the wall's size, roughly)
        noise = sig_b + np.max(np.abs(values)) * sig_t
        bound = _h_bound(angle, mean, noise)
        slope = _slope_bound(angle, mean, sig_b, sig_t, bound, noise)
    else:
        slope = np.full(m, 2.0 * float(np.max(np.abs(values))) if values.size else 0.0)
    # each input sample's interval at its group's nominal angle
    offset = np.abs(np.mod(reduced - angle[group] + np.pi, TWO_PI) - np.pi)
    width = sb + slope[group] * (st + offset)
    lo = np.full(m, -np.inf)
    hi = np.full(m, np.inf)
    np.maximum.at(lo, group, values - width)
    np.minimum.at(hi, group, values + width)
    if merge == "mean":
        lo = np.full(m, np.inf)
        hi = np.full(m, -np.inf)
        np.minimum.at(lo, group, values - width)
        np.maximum.at(hi, group, values + width)
    elif merge != "intersect":
        raise InvalidWall(f"`merge` must be 'intersect' or 'mean', got {merge!r}")
    bad = np.flatnonzero(lo > hi)
    if bad.size:
        g = int(bad[0])
        members = np.flatnonzero(group == g)
        a = members[np.argmax((values - width)[members])]
        c = members[np.argmin((values + width)[members])]
        name = (lambda k: labels[order[k]]) if labels is not None else (lambda k: f"sample {order[k] + 1}")
        raise InvalidWall(
            f"samples: {name(a)} and {name(c)} are at the same angle θ ≡ {angle[g]:.9g} (mod 2π) but disagree: "
            f"b = {values[a]:.9g} ± {width[a]:.2g} and b = {values[c]:.9g} ± {width[c]:.2g} do not overlap")
    middle = 0.5 * (lo + hi) if merge == "intersect" else mean
    halfwidth = 0.5 * (hi - lo) if merge == "intersect" else np.maximum(hi - mean, mean - lo)
    # a lone sample keeps its own value and half-width exactly
    member = np.empty(m, int)
    member[group] = np.arange(reduced.size)
    single = count == 1
    middle[single] = values[member[single]]
    halfwidth[single] = width[member[single]]
    deviation = None
    if statistical:
        # the standard deviation of each angle's mean: the values' and, through the slope bound, the angles'
        variance = np.bincount(group, weights=var_b + slope[group] ** 2 * var_t, minlength=m) / count**2
        deviation = np.sqrt(variance)
        deviation.setflags(write=False)
    for arr in (angle, middle, halfwidth, sig_b, sig_t, slope, count):
        arr.setflags(write=False)
    return SampleData(angle, middle, halfwidth, sig_b, sig_t, slope, count, notes, deviation)
