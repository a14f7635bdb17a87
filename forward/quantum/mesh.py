"""A triangle mesh of the strip that follows the walls exactly: structured in (θ, s), mapped by η = lo(θ) + s·w(θ).

The finite elements live on the reference rectangle ``x = θ``, ``y = s ∈ [0, 1]``; the map
``η = lo(θ) + s·w(θ)`` carries it onto the strip with no geometric error at all (every element is the exact
curved image of a straight one, so the walls are followed exactly, kinks included).  The Laplacian is
pulled back in :mod:`.fem`.

Where the mesh lines go (a choice, justified):

* **Columns** (lines θ = const) at every breakpoint of the walls (kinks and curvature jumps of lo and hi:
  the pulled-back coefficients are smooth inside each element, so P2 keeps its order on the stick) and at
  the necks; in between, spaced so that the cells are squares in the physical strip: ``Δθ = w(θ)/cells``
  (``cells`` rows across, ``Δη = w/cells``).  A narrow neck thus gets columns as fine as its width, which
  is the scale on which a state decays through it (``exp(−∫π/w dθ)``).
* **Symmetric**: the columns are built on a fundamental interval ([0, π/2] for a mirror-symmetric wall,
  else [0, π]) and copied by the symmetries; the rows are uniform with an even count; each cell's
  diagonal is oriented so that the triangulation itself is invariant.  The symmetries then permute the
  degrees of freedom exactly (:mod:`.symmetry`).
* **Periodic** in θ by identifying the degrees of freedom on θ = 2π with those on θ = 0.
* A region of a strip that fell apart (``w → 0`` at both ends) gets its own mesh on ``[a, b]``, with
  ``Δθ = max(w, floor)/cells``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..angles import TWO_PI
from ..display import safe_repr
from ..validation import check_count

__all__ = ["REGION_FLOOR", "StripMesh", "column_angles", "column_count", "strip_mesh"]

#: in a region of a strip that fell apart, columns are no finer than REGION_FLOOR·width_max/cells
REGION_FLOOR = 0.02
_SAMPLES = 2048
_MATCH = 1e-8
#: marks (breakpoints, necks) closer than this (rad) to each other or to an end are one mark: a sliver column
#: would only add a degenerate cell (the coefficients' kinks are then within _MERGE of a column)
_MERGE = 1e-6


@dataclass(frozen=True, repr=False)
class StripMesh:
    """The mesh of one domain of the strip and its degrees of freedom.

    Attributes
    ----------
    strip : Strip
    region : tuple of float or None
        ``(a, b)`` for one region of a strip that fell apart; None for the periodic strip.
    theta, s : ndarray
        Column angles (ascending, first and last included) and row positions in [0, 1].
    mesh : skfem.MeshTri
        The triangulation of the reference rectangle (x = θ, y = s).
    basis : skfem.CellBasis
        Lagrange elements of ``order`` on it.
    order : int
        Polynomial degree (2, 3 or 4).
    reduce : scipy.sparse matrix (all dofs × free dofs)
        Periodic identification and Dirichlet conditions: a free vector ``u`` is ``reduce @ u`` on the mesh.
    free_locations : ndarray (2, n)
        (θ, s) of each free degree of freedom.
    """

    strip: object
    region: tuple | None
    theta: np.ndarray
    s: np.ndarray
    mesh: object
    basis: object
    order: int
    reduce: object
    free_locations: np.ndarray

    @property
    def dofs(self) -> int:
        """Number of free degrees of freedom."""
        return int(self.free_locations.shape[1])

    @safe_repr
    def __repr__(self) -> str:
        where = "periodic" if self.region is None else f"region [{self.region[0]:.4g}, {self.region[1]:.4g}]"
        return f"StripMesh({where}, {self.theta.size - 1}×{self.s.size - 1} cells, P{self.order}, {self.dofs} dofs)"


def _separated(marks):
    out = []
    for t in marks:
        if not out or t - out[-1] > _MERGE:
            out.append(t)
    return out


def _cumulative(strip, a, b, cells, floor):
    theta = np.linspace(a, b, _SAMPLES + 1)
    density = cells / np.maximum(strip.width(theta), floor)
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(theta))])
    count = max(1, math.ceil(cumulative[-1] - 1e-9)) if np.isfinite(cumulative[-1]) else math.inf
    return theta, cumulative, count


def _fill(strip, a, b, cells, floor, count_only=False):
    """Column angles in (a, b] spaced Δθ = max(w, floor)/cells (equidistributing cells·∫dθ/max(w, floor));
    with ``count_only``, only how many (nothing the size of the mesh is built)."""
    theta, cumulative, count = _cumulative(strip, a, b, cells, floor)
    if count_only:
        return count
    levels = np.linspace(0.0, cumulative[-1], count + 1)[1:]
    nodes = np.interp(levels, cumulative, theta)
    nodes[-1] = b
    return nodes


def column_count(strip, cells, region=None, floor=None) -> float:
    """How many column angles :func:`column_angles` returns, without building them (the mesh's size before
    it is made: a neck of width δ gets about cells·π/√(δ·w'') columns, a flat one cells·length/δ)."""
    return column_angles(strip, cells + cells % 2, region, floor, count_only=True)


def column_angles(strip, cells, region=None, floor=None, count_only=False):
    """The column angles of :func:`strip_mesh` (see the module docstring) and each cell's orientation sign."""
    if region is not None and count_only:
        a, b = region
        floor = REGION_FLOOR * strip.width_max if floor is None else floor
        inner = [t for t in strip.breakpoints for t in (t, t + TWO_PI) if a < t < b]
        stops = _separated(sorted(t for t in set(inner) if a + _MERGE < t < b - _MERGE)) + [b]
        return 1 + sum(_fill(strip, lo, hi, cells, floor, True) for lo, hi in zip([a] + stops[:-1], stops))
    if region is not None:
        a, b = region
        floor = REGION_FLOOR * strip.width_max if floor is None else floor
        inner = [t for t in strip.breakpoints for t in (t, t + TWO_PI) if a < t < b]
        stops = _separated(sorted(t for t in set(inner) if a + _MERGE < t < b - _MERGE)) + [b]
        theta = [a]
        for stop in stops:
            theta.extend(_fill(strip, theta[-1], stop, cells, floor))
        theta = np.asarray(theta)
        return theta, np.ones(theta.size - 1, dtype=int)
    floor = 0.0 if floor is None else floor
    mirror = "mirror" in strip.symmetries
    end = 0.5 * math.pi if mirror else math.pi
    necks = [strip.neck, strip.neck + math.pi]
    if mirror:
        necks += [-n for n in necks]
    marks = {float(np.mod(t, math.pi)) for t in list(strip.breakpoints) + necks}
    if mirror:
        marks |= {math.pi - t for t in marks}
    stops = _separated(sorted(t for t in marks if _MERGE < t < end - _MERGE)) + [end]
    if count_only:
        half = 1 + sum(_fill(strip, lo, hi, cells, floor, True) for lo, hi in zip([0.0] + stops[:-1], stops))
        return (2 * half - 1 if mirror else half) * 2 - 1
    half = [0.0]
    for stop in stops:
        half.extend(_fill(strip, half[-1], stop, cells, floor))
    half = np.asarray(half)
    sign = np.ones(half.size - 1, dtype=int)
    if mirror:  # θ → π − θ reverses each cell's diagonal, so the mirrored copy has the other orientation
        half = np.concatenate([half, (math.pi - half[::-1])[1:]])
        sign = np.concatenate([sign, -sign])
    theta = np.concatenate([half, (half + math.pi)[1:]])
    theta[-1] = TWO_PI
    return theta, np.concatenate([sign, sign])


def strip_mesh(strip, cells: int = 8, order: int = 2, region=None, floor=None) -> StripMesh:
    """Mesh a domain of ``strip``: the periodic strip (``region=None``) or one of ``strip.regions``.

    Parameters
    ----------
    strip : Strip
    cells : int
        Rows of cells across the strip (rounded up to even); the columns follow (module docstring).
    order : int
        Degree of the Lagrange elements: 2 (default), 3 or 4.
    region : (float, float), optional
        One of ``strip.regions``; required when the strip fell apart.
    floor : float, optional
        Smallest width used to space the columns (default 0 for the periodic strip, REGION_FLOOR·w_max
        for a region).
    """
    import scipy.sparse as sp
    from skfem import Basis, ElementTriP2, ElementTriP3, ElementTriP4, MeshTri

    from ..errors import InvalidArgument

    cells = check_count("cells", cells, minimum=2, maximum=4096)
    cells += cells % 2
    order = check_count("order", order, minimum=2, maximum=4)
    if region is None and not strip.periodic:
        raise InvalidArgument("the strip fell apart: pass one of `strip.regions` as `region`")
    theta, sign = column_angles(strip, cells, region, floor)
    s = np.linspace(0.0, 1.0, cells + 1)
    nx, ny = theta.size, s.size
    points = np.array([np.repeat(theta, ny), np.tile(s, nx)])
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), indexing="ij")
    a = (i * ny + j).ravel()
    b, c, d = a + ny, a + ny + 1, a + 1
    # the orientation of the diagonal: sign of the column times sign of the row half (rows above the
    # middle are the swap's images of those below, with the diagonal reversed)
    flip = (np.repeat(sign, ny - 1) * np.where(j.ravel() < (ny - 1) // 2, 1, -1)) > 0
    first = np.where(flip, np.array([a, b, c]), np.array([a, b, d]))
    second = np.where(flip, np.array([a, c, d]), np.array([b, c, d]))
    mesh = MeshTri(points, np.hstack([first, second]))
    element = {2: ElementTriP2, 3: ElementTriP3, 4: ElementTriP4}[order]()
    basis = Basis(mesh, element, intorder=2 * order + 2)
    locs = basis.doflocs
    n = locs.shape[1]
    x, y = locs
    scale = max(1.0, float(np.max(np.abs(theta))))
    fixed = (y < _MATCH) | (y > 1 - _MATCH)
    rep = np.arange(n)
    if region is None:
        right = np.flatnonzero(np.abs(x - TWO_PI) < _MATCH * scale)
        left = np.flatnonzero(np.abs(x) < _MATCH * scale)
        rep[right[np.argsort(y[right])]] = left[np.argsort(y[left])]
    else:
        fixed |= (np.abs(x - theta[0]) < _MATCH * scale) | (np.abs(x - theta[-1]) < _MATCH * scale)
    free = np.flatnonzero((rep == np.arange(n)) & ~fixed)
    column = np.full(n, -1)
    column[free] = np.arange(free.size)
    rows = np.flatnonzero(column[rep] >= 0)
    reduce = sp.csr_matrix((np.ones(rows.size), (rows, column[rep[rows]])), shape=(n, free.size))
    return StripMesh(strip, region, theta, s, mesh, basis, order, reduce, locs[:, free].copy())
