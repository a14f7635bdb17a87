"""The kernel's cells: the period cut into cells and, per cell, the bounds that make the search certain.

The kernel (:mod:`._kernel`) walks a ray cell by cell.  A cell is a piece of the period on which
the wall is smooth (a uniform grid of :data:`CELLS` cells, cut again at every kink); for each cell
this module computes an upper bound of b, an upper bound of b'', bounds of |b'''| and |b''''|, the quintic
Hermite proxy of b with a bound of its error, and the kinks' one-sided slopes, all from dense
sampling with a margin that is then checked on a finer shifted grid.  They are packed into one
(m, 21) table (:func:`cell_table`), the layout the kernel's column constants name.
"""

from __future__ import annotations

import math

import numpy as np

from ...angles import TWO_PI
from ...errors import InvalidWall
from ...wall import Wall

__all__ = ["CELLS", "SAMPLES", "cell_bounds", "cell_proxies", "cell_table", "concave_runs"]

CELLS = 128          # uniform cells per period (kinks add more)
SAMPLES = 32         # samples per cell for the bounds


def cell_bounds(wall: Wall, cells: int = CELLS, samples: int = SAMPLES):
    """Cells of the period and per-cell bounds for the kernel.

    Edges: a uniform grid of ``cells`` cells, plus every kink angle (a grid edge
    within 1e-9 of a kink is replaced by it).  Per cell j, from ``samples`` + 1
    points including both ends (b) and ``samples`` interior points (b''):

    * ``bmax_j = max b + max |Δb|`` and ``c_j = max b'' + max |Δb''|`` where Δ is
      the difference between neighbouring samples: the true maximum between
      two samples exceeds the sampled one by at most about half the local
      variation, so the margin is twice what the first-order estimate needs.
    * The bounds are then *checked* on a shifted grid 4 times finer; where a
      check fails the margin of that cell is doubled and the check repeated
      (so an unresolved narrow feature cannot slip through silently).

    Also the quintic proxy of b per cell and its error bound (:func:`cell_proxies`).
    Returns a dict of arrays; :func:`cell_table` packs them for the kernel.
    """
    kinks = sorted(k.angle % TWO_PI for k in wall.kinks)
    edges = list(np.linspace(0.0, TWO_PI, cells + 1))
    for a in kinks:
        i = int(np.argmin(np.abs(np.array(edges) - a)))
        if abs(edges[i] - a) < 1e-9:
            edges[i] = a
            if i == 0:
                edges[-1] = a + TWO_PI
            if i == cells:
                edges[0] = a - TWO_PI
        else:
            edges.append(a)
    edges = np.array(sorted(edges))
    if edges[0] != 0.0:  # a kink moved the seam; keep the period [0, 2π] exactly
        edges[0], edges[-1] = 0.0, TWO_PI
    m = edges.size - 1
    width = np.diff(edges)
    u = np.linspace(0.0, 1.0, samples + 1)
    pts_b = edges[:-1, None] + width[:, None] * u[None, :]
    # b'' inside the open cell only: at a kink edge b'' includes the other side
    v = (np.arange(samples) + 0.5) / samples
    v = np.concatenate([[1e-7], v, [1 - 1e-7]])
    pts_2 = edges[:-1, None] + width[:, None] * v[None, :]
    b = wall(pts_b.ravel()).reshape(pts_b.shape)
    d2 = wall.derivatives(pts_2.ravel())[2].reshape(pts_2.shape)
    margin_b = np.max(np.abs(np.diff(b, axis=1)), axis=1) + 1e-12 * wall.scale
    margin_2 = np.max(np.abs(np.diff(d2, axis=1)), axis=1) + 1e-9 * (1 + np.max(np.abs(d2)))
    bmax = b.max(axis=1)
    cmax = d2.max(axis=1)
    fine = 4 * samples
    w = (np.arange(fine) + 0.37) / fine
    pts_f = edges[:-1, None] + width[:, None] * w[None, :]
    bf, _, d2f = (x.reshape(pts_f.shape) for x in wall.derivatives(pts_f.ravel()))
    _require_finite(wall, (pts_b, pts_2, pts_f, pts_f), (b, d2, bf, d2f))
    margin_b = _widen(margin_b, bmax, bf.max(axis=1))
    margin_2 = _widen(margin_2, cmax, d2f.max(axis=1))
    bmax = bmax + margin_b
    cmax = cmax + margin_2
    d3max, d4max = _higher_derivative_bounds(pts_2, d2, pts_f, d2f)
    bmin_global = float(np.min(b) - np.max(margin_b))
    slope_left = np.full(m + 1, np.nan)
    slope_right = np.full(m + 1, np.nan)
    for k in wall.kinks:
        a = k.angle % TWO_PI
        for i in np.flatnonzero(np.abs(edges - a) < 1e-12):
            slope_left[i], slope_right[i] = k.slope_left, k.slope_right
        if abs(a) < 1e-12 or abs(a - TWO_PI) < 1e-12:
            slope_left[[0, m]], slope_right[[0, m]] = k.slope_left, k.slope_right
    lookup = np.searchsorted(edges, np.linspace(0.0, TWO_PI, cells, endpoint=False), side="right") - 1
    lookup = np.clip(lookup, 0, m - 1).astype(np.int64)
    proxy, perr, p2max, p2abs = cell_proxies(wall, edges, slope_left, slope_right, samples)
    return {"edges": edges, "bmax": bmax, "cmax": cmax, "slope_left": slope_left, "slope_right": slope_right,
            "lookup": lookup, "nunif": cells, "wmin": bmin_global, "wmax": float(bmax.max()),
            "proxy": proxy, "perr": perr, "p2max": p2max, "p2abs": p2abs, "d3max": d3max,
            "d4max": d4max}


def _widen(margin, base, check):
    """Double ``margin`` per cell until ``base + margin`` covers ``check`` (at most 60 times).

    The bounds are sampled maxima plus a margin; ``check`` is the same quantity sampled
    on a finer, shifted grid, so a cell whose margin was too small cannot slip through.
    """
    margin = np.array(margin, dtype=float)
    for _ in range(60):
        bad = check > base + margin
        if not bad.any():
            break
        margin[bad] *= 2
    return margin


def _require_finite(wall: Wall, points, values):
    """InvalidWall naming the first angle where a sampled b or b'' is nan or infinite.

    The wall was checked on a grid when it was made; the kernel's denser sampling can still
    land on a pole or a domain error between those points, and a nan bound would silently
    turn a cell into "no contact here".
    """
    for pts, vals in zip(points, values):
        bad = ~np.isfinite(vals)
        if bad.any():
            angle = float(np.asarray(pts).ravel()[np.flatnonzero(bad.ravel())[0]] % TWO_PI)
            raise InvalidWall(f"wall {wall.description!r} is not finite at θ = {angle:.9g} (b or b'' is nan or "
                              f"infinite there; found by the billiard's dense sampling): the billiard needs a "
                              f"finite wall")


def _higher_derivative_bounds(pts, d2, pts_f, d2f):
    """Per-cell bounds of |b'''| and |b''''| from the slopes of sampled b'' (interior points of each cell).

    |b'''|: twice the largest difference quotient of neighbouring samples plus the
    largest change between neighbouring quotients, then checked against the
    quotients on the finer shifted grid (doubled where they exceed it).  |b''''|:
    the same rule one order up, on the difference quotients of those quotients
    (between the samples' midpoints), checked likewise.  The search uses the first
    to decide when a contact found by a second-order step needs no confirming
    evaluation (the Taylor remainder of that step, see the kernel); the contact
    phases on the floor use both to bound their event functions over a step.
    """
    def quotients(x, y):
        return np.diff(y, axis=1) / np.diff(x, axis=1), 0.5 * (x[:, 1:] + x[:, :-1])

    def rule(q):
        return 2.0 * np.abs(q).max(axis=1) + np.abs(np.diff(q, axis=1)).max(axis=1) + 1e-9

    q3, mid = quotients(pts, d2)
    q3f, midf = quotients(pts_f, d2f)
    q4, q4f = quotients(mid, q3)[0], quotients(midf, q3f)[0]
    return _widen(rule(q3), 0.0, np.abs(q3f).max(axis=1)), _widen(rule(q4), 0.0, np.abs(q4f).max(axis=1))


def cell_proxies(wall: Wall, edges, slope_left, slope_right, samples: int = SAMPLES):
    """Per cell j a quintic proxy ``p_j`` of b and a bound ``e_j`` of ``|b − p_j|`` on the cell.

    ``p_j(s) = Σ_k c_k s^k`` (k = 0..5) with ``s = φ − edges[j]`` is the quintic
    Hermite interpolant of the exact b, b', b'' at both cell ends (one-sided
    values at a kink, so the proxy follows the smooth piece inside the cell).
    Its error is O(w⁶ max|b⁽⁶⁾|): ~1e-8 where the ε = 99 coin is sharpest
    (b ≈ 0.1 there), near rounding elsewhere.  ``e_j`` is sampled like the other
    cell bounds: twice the largest sampled |b − p| plus the largest change
    between neighbouring samples plus a rounding floor, then checked on a
    shifted grid 4 times finer (margin doubled where the check fails).
    ``p2max_j ≥ max p_j''`` over the cell is rigorous for the polynomial: the
    sampled maximum plus max|p'''| times half the sample spacing; ``p2abs_j ≥ max |p_j''|`` likewise.
    """
    m = edges.size - 1
    width = np.diff(edges)
    b_e, d_e, c_e = wall.derivatives(edges)
    curv_left = np.full(m + 1, np.nan)
    curv_right = np.full(m + 1, np.nan)
    for k in wall.kinks:
        a = k.angle % TWO_PI
        near = np.abs(edges - a) < 1e-12
        if abs(a) < 1e-12 or abs(a - TWO_PI) < 1e-12:
            near[[0, m]] = True
        curv_left[near], curv_right[near] = k.curvature_left, k.curvature_right
    # one-sided values inside cell j: from the right at its left end, from the left at its right end
    d0 = np.where(np.isnan(slope_right[:-1]), d_e[:-1], slope_right[:-1])
    d1 = np.where(np.isnan(slope_left[1:]), d_e[1:], slope_left[1:])
    e0 = np.where(np.isnan(curv_right[:-1]), c_e[:-1], curv_right[:-1])
    e1 = np.where(np.isnan(curv_left[1:]), c_e[1:], curv_left[1:])
    b0, b1, w = b_e[:-1], b_e[1:], width
    proxy = np.empty((m, 6))
    proxy[:, 0], proxy[:, 1], proxy[:, 2] = b0, d0, 0.5 * e0
    r0 = b1 - (b0 + w * (d0 + w * 0.5 * e0))
    r1 = (d1 - (d0 + w * e0)) * w
    r2 = (e1 - e0) * w * w
    proxy[:, 3] = (10.0 * r0 - 4.0 * r1 + 0.5 * r2) / w**3
    proxy[:, 4] = (-15.0 * r0 + 7.0 * r1 - r2) / w**4
    proxy[:, 5] = (6.0 * r0 - 3.0 * r1 + 0.5 * r2) / w**5

    def polynomial(s, derivative=0):
        out = np.zeros_like(s)
        for k in range(5, derivative - 1, -1):
            factor = math.factorial(k) // math.factorial(k - derivative)
            out = out * s + factor * proxy[:, k, None]
        return out

    def error(u):
        s = width[:, None] * u[None, :]
        b = wall((edges[:-1, None] + s).ravel()).reshape(s.shape)
        return b - polynomial(s)

    u = np.concatenate([[1e-9], (np.arange(2 * samples) + 0.5) / (2 * samples), [1 - 1e-9]])
    err = error(u)
    _require_finite(wall, [edges[:-1, None] + width[:, None] * u[None, :]], [err])
    floor = 1e-14 * max(1.0, wall.scale)
    perr = 2.0 * np.max(np.abs(err), axis=1) + np.max(np.abs(np.diff(err, axis=1)), axis=1) + floor
    fine = 8 * samples
    perr = _widen(perr, 0.0, np.max(np.abs(error((np.arange(fine) + 0.37) / fine)), axis=1))
    grid = np.linspace(0.0, 1.0, 65)
    p2 = polynomial(width[:, None] * grid[None, :], 2)
    p3 = 6 * np.abs(proxy[:, 3]) + 24 * np.abs(proxy[:, 4]) * width + 60 * np.abs(proxy[:, 5]) * width**2
    between = p3 * width / 128 * 1.01  # how far p'' can rise between grid points
    p2max = p2.max(axis=1) + between
    p2abs = np.abs(p2).max(axis=1) + between
    return np.ascontiguousarray(proxy), perr, p2max, p2abs


def cell_table(bounds) -> np.ndarray:
    """The cell bounds as one (m, 21) table for the kernel (one row, two or three cache lines, per cell).

    Columns: left and right edge, bmax, c (bound of b''), the kink slopes seen when
    entering through the left edge (moving forward) and through the right edge
    (moving backward; NaN where the edge is no kink), the quintic proxy c0..c5,
    its error bound e, max p'', the bound of |b'''|, max |p''|, and the *curving-away runs*
    (:func:`concave_runs`): where the run of cells with ``c ≤ 0`` that starts at this cell ends going
    forward and the cell after it, then the same going backward; last the bound of |b''''| (for the contact
    phases on the floor; after the billiard's columns, whose places it leaves as they were).  One table instead
    of a dozen arrays keeps the per-call bookkeeping of numba small.
    """
    edges = bounds["edges"]
    m = edges.size - 1
    table = np.empty((m, 21))
    table[:, 0] = edges[:-1]
    table[:, 1] = edges[1:]
    table[:, 2] = bounds["bmax"]
    table[:, 3] = bounds["cmax"]
    table[:, 4] = bounds["slope_right"][:-1]
    table[:, 5] = bounds["slope_left"][1:]
    table[:, 6:12] = bounds["proxy"]
    table[:, 12] = bounds["perr"]
    table[:, 13] = bounds["p2max"]
    table[:, 14] = bounds["d3max"]
    table[:, 15] = bounds["p2abs"]
    table[:, 16:20] = concave_runs(edges, bounds["cmax"], bounds["slope_left"], bounds["slope_right"])
    table[:, 20] = bounds["d4max"]
    return np.ascontiguousarray(table)


def concave_runs(edges, cmax, slope_left, slope_right) -> np.ndarray:
    """Per cell the ends of the run of cells, starting at it, on which the wall curves away (``c ≤ 0``).

    Parameters
    ----------
    edges : ndarray (m + 1,)
        The cell edges, 0 to 2π.
    cmax : ndarray (m,)
        The per-cell upper bounds of b''.
    slope_left, slope_right : ndarray (m + 1,)
        The one-sided slopes at the edges that are kinks, NaN elsewhere.

    Returns
    -------
    ndarray (m, 4)
        Per cell j: the far edge of its run going forward (an angle, 2π more where the run wraps past the
        seam) and the index of the cell after the run; the far edge going backward (2π less where it
        wraps) and the index of the cell before the run.

    Notes
    -----
    A run is a maximal stretch of consecutive cells (around the period) whose bound of b'' is ≤ 0 and
    whose inner edges are no kinks (a kink is a point mass of b'', possibly positive), at most m − 1 cells
    long.  On it the gap of a flight that has just left the wall is convex, so the kernel skips the whole run
    after a reflection from a point of it (see :mod:`._search`).  For a cell with ``c > 0`` the run is the
    cell itself.
    """
    m = edges.size - 1
    concave = np.asarray(cmax) <= 0.0
    kink = ~(np.isnan(slope_left) & np.isnan(slope_right))  # edge i lies between cell i − 1 and cell i
    kink[0] = kink[m] = kink[0] or kink[m]
    # joined[k]: cell k and cell k + 1 (mod m) belong to one run
    joined = concave & np.roll(concave, -1) & ~kink[1:]
    out = np.empty((m, 4))
    # the last (first) cell of the run through k, by one sweep over the doubled index range (linear time;
    # a plain loop: m is a few hundred)
    last = np.empty(2 * m, dtype=np.int64)
    last[2 * m - 1] = 2 * m - 1
    for k in range(2 * m - 2, -1, -1):
        last[k] = last[k + 1] if joined[k % m] else k
    first = np.empty(2 * m, dtype=np.int64)
    first[0] = 0
    for k in range(1, 2 * m):
        first[k] = first[k - 1] if joined[(k - 1) % m] else k
    for j in range(m):
        end = min(int(last[j]), j + m - 2) if concave[j] else j
        out[j, 0] = edges[end % m + 1] + TWO_PI * (end // m)
        out[j, 1] = (end + 1) % m
        k = j + m  # the same cell in the upper copy, so that a run may reach back past the seam
        begin = max(int(first[k]), k - m + 2) if concave[j] else k
        out[j, 2] = edges[begin % m] - TWO_PI * (1 - begin // m)
        out[j, 3] = (begin - 1) % m
    return out
