"""Every global minimiser of ``ρ = b + b''`` of a formula wall, from certified ranges on cells.

The period is cut into cells (a uniform grid, cut again at every kink and break), and on each cell
:func:`coinwall.forward.wallbounds.curvature_ranges` gives an interval holding every value of ρ there.
The value at each cell's middle is an upper bound ``U`` of the minimum; a cell whose lower end lies above
``U`` holds no minimiser and is dropped.  Every other cell is cut in eight, and the parts judged again, until
its range is as narrow as the rounding of ρ allows (or the cell is :data:`MIN_WIDTH` wide).  What is left
is a certificate:

* ``min ρ ∈ [lower, upper]``: ``lower`` is the least lower end of the cells left, ``upper`` the least
  value found;
* every global minimiser lies in one of the *windows* (runs of cells left), and on every window ρ stays
  within ``spread`` of ``lower``: a second dip reaches a window only if it is that close to the minimum.

Nothing is assumed of the wall's symmetry, and no local search is trusted: a dip narrower than the first
grid is found because the range of a cell that holds it reaches down into it.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import safe_repr

__all__ = ["CELLS", "INTERVAL_WIDTH", "MIN_WIDTH", "CellMinimum", "certified_minimum"]

#: Uniform cells of the first grid (kinks and breaks add more).
CELLS = 256
#: Cells are not halved below this width (rad): there the rounding of ρ decides, not the cell.
MIN_WIDTH = 1e-11
#: A window at least this wide (rad) is reported as an interval of minima (the stick's arcs), a narrower
#: one as an angle with its half-width as uncertainty.
INTERVAL_WIDTH = 1e-3
#: Windows closer than this (rad) are reported as one.
WINDOW_GAP = 1e-5
#: Width (rad) of the cell beside each kink or break that follows its own side's formula up to it.
BESIDE = 1e-4
#: Most cells judged in one search (about 1.5 s on one core for a formula of a hundred operations; the walls
#: of the tests need a few hundred to a few thousand): a wall whose ranges narrow only in proportion to the
#: cells (two branches of a max equal on a whole arc) stops there, with the certificate it reached.
_BUDGET = 12_000
_EPS = float(np.finfo(float).eps)
_SPLIT = 8  # children of a cell that is cut again: three halvings per round


@dataclass(frozen=True, repr=False)
class CellMinimum:
    """The result of :func:`certified_minimum`.

    Attributes
    ----------
    value : float
        ρ at the best angle found, as floating point evaluates it (within [lower, upper]).
    lower, upper : float
        Certified bounds of ``min ρ``.
    windows : tuple of (float, float)
        Every global minimiser lies in one of these angle ranges (``lo < hi``; ``hi`` may exceed 2π for a
        window across the seam), sorted by their start in [0, 2π).
    spread : float
        On every window, ``ρ ≤ lower + spread``.
    cells : int
        How many cells were judged.
    complete : bool
        Whether the certificate covers the whole period (False when :attr:`uncertified` is not empty).
    uncertified : tuple of (float, float)
        Where ρ has no finite range on cells of the least width though its values are finite (``b''``
        unbounded: the flat points of a superellipse), or where the budget ran out before the ranges
        narrowed (two branches of a max equal on a whole arc, the square root of a square): there ρ
        counts by its values at the cells' middles; :attr:`lower` and :attr:`spread` are certified outside.
    """

    value: float
    lower: float
    upper: float
    windows: tuple
    spread: float
    cells: int
    complete: bool = True
    uncertified: tuple = ()

    @safe_repr
    def __repr__(self) -> str:
        return (f"CellMinimum(value={self.value:.17g}, lower={self.lower:.17g}, upper={self.upper:.17g}, "
                f"{len(self.windows)} windows, spread={self.spread:.3g}, cells={self.cells})")


def _first_cells(cuts, cells: int):
    """The first cells and their reference angles (NaN for none).

    A uniform grid whose points near a cut (within a tenth of a cell) give way to it; beside every cut a
    cell :data:`BESIDE` wide (less where cuts are closer) whose branches of ``abs``/``min``/``max`` are
    those at its middle, so that its range is that of its own side's formula up to the cut.
    """
    step = TWO_PI / cells
    grid = np.arange(cells) * step
    cuts = np.unique(np.mod(np.asarray(cuts, dtype=float), TWO_PI))
    if not cuts.size:
        return grid, np.append(grid[1:], TWO_PI), np.full(cells, np.nan)
    gap = np.abs(np.angle(np.exp(1j * (grid[:, None] - cuts[None, :]))))
    grid = grid[np.min(gap, axis=1) > 0.1 * step]
    apart = np.diff(np.concatenate([cuts, [cuts[0] + TWO_PI]]))
    beside = np.minimum(BESIDE, np.minimum(apart, np.roll(apart, 1)) / 3.0)  # per cut
    extra = np.concatenate([cuts - beside, cuts + beside])
    gap = np.abs(np.angle(np.exp(1j * (grid[:, None] - extra[None, :]))))
    grid = grid[np.min(gap, axis=1) > 2.0 * beside.max()]
    points = np.unique(np.mod(np.concatenate([grid, cuts, extra]), TWO_PI))
    edges = np.concatenate([points, [points[0] + TWO_PI]])
    lo, hi = edges[:-1], edges[1:]
    ref = np.full(lo.size, np.nan)
    mid = 0.5 * lo + 0.5 * hi
    for cut, width in zip(cuts, beside):
        distance = np.abs(np.angle(np.exp(1j * (mid - cut))))
        ref[np.abs(distance - 0.5 * width) < 1e-3 * width] = mid[np.abs(distance - 0.5 * width) < 1e-3 * width]
    return lo, hi, ref


def certified_minimum(ranges, cuts=(), kinks=(), *, cells: int = CELLS, min_width: float = MIN_WIDTH,
                      budget: int = _BUDGET) -> CellMinimum:
    """The minimum of a periodic function from certified ranges on cells, with every global minimiser.

    Parameters
    ----------
    ranges : callable
        ``(lo, hi, decide) ↦ (lower, upper)`` on arrays of cells, each interval holding every value of
        the function on its cell (a cell of width 0 is a point; ``decide``: see
        :class:`coinwall.forward.wallbounds.CurvatureRanges`), e.g.
        :func:`coinwall.forward.wallbounds.curvature_ranges`.
    cuts : array_like
        Angles no cell may straddle (kinks, breaks).
    kinks : array_like
        The cuts that split a window (a point mass of ``b''`` there).
    cells : int
        Uniform cells of the first grid.
    min_width : float
        Cells are not halved below this width.
    budget : int
        Most cells judged.

    Returns
    -------
    CellMinimum

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.wallbounds import curvature_ranges
    >>> found = certified_minimum(curvature_ranges(Wall.from_expression("1 + 0.1*cos(3*t)")))
    >>> round(found.value, 12), bool(found.upper - found.lower < 1e-13)       # ρ = 1 − 0.8 cos 3θ
    (0.2, True)
    >>> [round(float(np.mod(0.5 * (lo + hi), 2 * np.pi)), 6) for lo, hi in found.windows]   # 0, 2π/3, 4π/3
    [2.094395, 4.18879, 0.0]
    """
    lo, hi, ref = _first_cells(cuts, cells)
    best, best_value = math.inf, math.nan
    kept = []
    judged = 0
    tau = 0.0
    while lo.size:
        n = lo.size
        mid = 0.5 * lo + 0.5 * hi
        low, high = ranges(np.concatenate([lo, mid]), np.concatenate([hi, mid]), np.concatenate([ref, ref]))
        judged += n
        cell_lo, cell_hi, point_lo, point_hi = low[:n], high[:n], low[n:], high[n:]
        finite = np.isfinite(point_hi)
        if finite.any():
            i = int(np.argmin(np.where(finite, point_hi, np.inf)))
            if point_hi[i] < best:
                best = float(point_hi[i])
                best_value = float(0.5 * point_lo[i] + 0.5 * point_hi[i])
            tau = 16.0 * _EPS * max(1.0, abs(best))
        alive = ~(cell_lo > best)
        rounding = np.where(np.isfinite(point_hi - point_lo), point_hi - point_lo, np.inf)
        settled = alive & ((cell_hi - cell_lo <= np.maximum(tau, 4.0 * rounding)) | (hi - lo <= min_width))
        split = alive & ~settled
        out_of_budget = judged + _SPLIT * int(split.sum()) > budget
        keep = alive if out_of_budget else settled
        # a kept cell is certified where its range is finite and it was settled (not left by the budget)
        kept.append((lo[keep], hi[keep], cell_lo[keep], cell_hi[keep], point_lo[keep],
                     np.isfinite(cell_lo[keep]) & settled[keep]))
        if out_of_budget:
            break
        lo, hi, ref = lo[split], hi[split], ref[split]
        inner = lo[:, None] + (hi - lo)[:, None] * (np.arange(1, _SPLIT) / _SPLIT)[None, :]
        edges = np.concatenate([lo[:, None], inner, hi[:, None]], axis=1)
        lo, hi, ref = edges[:, :-1].ravel(), edges[:, 1:].ravel(), np.repeat(ref, _SPLIT)
    k_lo, k_hi, k_low, k_high, k_mid, certain = (np.concatenate(parts) for parts in zip(*kept))
    if not math.isfinite(best) or not np.all(np.isfinite(k_mid) | certain):
        return CellMinimum(best_value, -math.inf, best, ((0.0, TWO_PI),), math.inf, judged, False)
    # what the certificate leaves out: cells whose range is not finite (b'' unbounded: a superellipse's flat
    # point, the square root of a square at a kink) and cells the budget left unsettled; there ρ counts by its
    # value at the cell's middle, and they are named
    k_low = np.where(certain, k_low, k_mid)
    k_high = np.where(certain, k_high, k_mid)
    left = ~(k_low > best)
    open_cells = ~certain
    uncertified = _windows(k_lo[open_cells], k_hi[open_cells], ()) if open_cells.any() else ()
    k_lo, k_hi, k_low, k_high = k_lo[left], k_hi[left], k_low[left], k_high[left]
    lower = float(np.min(k_low))
    spread = float(np.max(k_high)) - lower
    windows = _windows(k_lo, k_hi, kinks)
    # the estimate: the least value across the narrowest window (a cell's middle may miss the minimiser
    # by the window's width, and ρ by its curvature times that squared)
    a, b = min(windows, key=lambda w: w[1] - w[0])
    across = np.linspace(a, b, 65)
    low, high = ranges(across, across, np.full(across.size, np.nan))
    with np.errstate(invalid="ignore"):
        centre = 0.5 * low + 0.5 * high
    if np.isfinite(centre).any():
        best_value = min(best_value, float(np.nanmin(np.where(np.isfinite(centre), centre, np.nan))))
    value = min(max(best_value, lower), best)
    return CellMinimum(value, lower, best, windows, spread, judged, not uncertified, uncertified)


def _kink_between(a, b, kinks) -> bool:
    return bool(kinks.size) and bool(np.any(np.mod(kinks - a, TWO_PI) <= b - a))


def _windows(lo, hi, kinks):
    """Runs of touching cells; a run through 0 is one window.  Two runs that meet at a kink stay apart when
    both are at least :data:`INTERVAL_WIDTH` long (arcs of minima either side of an edge: the stick's), and
    are one window otherwise (a minimum at the kink itself, approached from both sides)."""
    order = np.argsort(lo, kind="stable")
    lo, hi = lo[order], hi[order]
    kinks = np.mod(np.asarray(kinks, dtype=float), TWO_PI)
    ends = np.flatnonzero(lo[1:] != hi[:-1])
    starts = np.concatenate([[0], ends + 1])
    stops = np.concatenate([ends, [lo.size - 1]])
    runs = [[float(lo[a]), float(hi[b])] for a, b in zip(starts, stops)]
    if len(runs) > 1 and abs(runs[-1][1] - (runs[0][0] + TWO_PI)) < 1e-12:
        runs[0] = [runs[-1][0], runs[0][1] + TWO_PI]  # across the seam: from the last run's start
        runs.pop()
    if len(runs) == 1 and runs[0][1] - runs[0][0] >= TWO_PI - 1e-12 and kinks.size:
        runs = [[float(kinks[0]), float(kinks[0]) + TWO_PI]]  # the whole circle: start at a kink
    windows = []
    for run in runs:  # each run, cut again at the kinks inside it
        cuts = sorted(run[0] + np.mod(k - run[0], TWO_PI) for k in kinks)
        edges = [run[0]] + [c for c in cuts if run[0] < c < run[1]] + [run[1]]
        for a, b in itertools.pairwise(edges):
            if windows and windows[-1][1] == a and min(b - a, windows[-1][1] - windows[-1][0]) < INTERVAL_WIDTH:
                windows[-1][1] = b
            else:
                windows.append([a, b])
    if len(windows) > 1 and abs(windows[-1][1] - (windows[0][0] + TWO_PI)) < 1e-12 and \
            min(windows[0][1] - windows[0][0], windows[-1][1] - windows[-1][0]) < INTERVAL_WIDTH:
        windows[0] = [windows[-1][0], windows[0][1] + TWO_PI]  # a minimum at a kink at 0
        windows.pop()
    # windows a hair apart (cells between them dropped on the rounding of one value) are one: their union still
    # holds every minimiser, and one minimum is not reported twice
    merged = []
    for window in sorted(windows):
        if merged and window[0] - merged[-1][1] < WINDOW_GAP and not _kink_between(merged[-1][1], window[0], kinks):
            merged[-1][1] = max(merged[-1][1], window[1])
        else:
            merged.append(list(window))
    if len(merged) > 1 and merged[0][0] + TWO_PI - merged[-1][1] < WINDOW_GAP \
            and not _kink_between(merged[-1][1], merged[0][0] + TWO_PI, kinks):
        merged[0] = [merged[-1][0], merged[0][1] + TWO_PI]
        merged.pop()
    windows = merged
    out = []
    for a, b in windows:
        shift = TWO_PI * math.floor(a / TWO_PI)
        out.append((a - shift, b - shift))
    return tuple(sorted(out))
