"""The certify stage of a sampled wall: what every wall and body consistent with the samples' intervals share.

Each sample says only that the wall at ``θ_i`` lies in ``[b_i − w_i, b_i + w_i]``
(:mod:`coinwall.forward.sampledata`).  This module turns those intervals into statements, each with what it
rests on (docs/theory.md, "What the data certify"):

* **b_c** as an interval (the lower end certified with no assumption, the upper end under
  :data:`ASSUMPTION`) and **the critical angles**: :func:`critical_bound` and :class:`CriticalBound`, defined
  in :mod:`coinwall.inverse.criticalbound` (whose docstring says how) and imported from here like the rest;
* **forced corners** at the offset ``b0``: windows ``[θ_i, θ_j]`` (two samples or more) through which every
  consistent body turns along at most ``L`` of boundary (:func:`certify`).  A consistent body touches line
  ``k`` on that line's piece between its neighbours, so its boundary from its touch point on line ``i`` to the
  one on line ``j`` is at most the sum of the pieces ``ℓ_k = ρ_k·(tan(Δ₋/2) + tan(Δ₊/2))``, ``i ≤ k ≤ j``: linear
  in the values, its largest value over every consistent set of values a small linear programme, certified
  from its dual like the lower end of b_c;
* **possible corners**: runs of samples where zero curvature is within the intervals but is not forced.

``b_c`` is computed on the thinning of dense data, from a ladder of spacings, where its interval is narrowest
(:mod:`coinwall.inverse.criticalbound`).  Corners are looked for at every spacing of that ladder, the data's
own included: a window the full data resolve is never lost.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.sampledata import curvature_coefficients

from .criticalbound import ASSUMPTION, CriticalBound, critical_bound, curvature_range, cyclic_runs, lp_lower_bound
from .tolerances import OFFSET_TOLERANCE

__all__ = ["ASSUMPTION", "Certificate", "CriticalBound", "DataCorner", "certify", "critical_bound",
           "curvature_range", "cyclic_runs", "data_critical_offset", "lp_lower_bound"]

#: most local linear programmes one certification solves for the length of corner windows (~2 ms each)
MAX_CORNER_PROGRAMMES = 200
#: a run of samples longer than this at one spacing gets no programme of its own (a coarser spacing has it)
MAX_CORNER_LINES = 3000
#: a window is a forced corner only when its mean radius of curvature is at most this fraction of the median
#: support value (:func:`certify`)
CORNER_RADIUS_FRACTION = 0.1


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
