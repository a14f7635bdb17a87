"""The corner tests of :func:`coinwall.inverse.fit.fit_convex`: the least-squares projection's vertex windows,
merged while the edge between them is not supported, each tested by a likelihood ratio against the window
rounded off, and the body with exactly the supported corners (the method is described in :mod:`.fit`).

Each test is a local least-squares problem (the window and up to 40 lines either side move, the rest stays at
the projection), solved exactly by Lawson & Hanson's least-distance reduction to one NNLS (:func:`_lsi`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI

__all__ = ["Cluster", "Structure", "cluster_runs", "stencil"]


def stencil(theta):
    """The three diagonals of ρ = A p (coefficients of p_{j−1}, p_j, p_{j+1}) and ``tan(Δ₋/2) + tan(Δ₊/2)``
    (the length of the piece of line j is ``ρ_j`` times it)."""
    after = np.diff(np.append(theta, theta[0] + TWO_PI))
    before = np.roll(after, 1)
    norm = np.tan(before / 2) + np.tan(after / 2)
    return (1 / np.sin(before) / norm, -(np.cos(before) / np.sin(before) + np.cos(after) / np.sin(after)) / norm,
            1 / np.sin(after) / norm, norm)


def _lsi(E, f, G, h):
    """``min ‖E x − f‖`` subject to ``G x ≥ h`` (E of full column rank, or a 1-d array: a diagonal), by
    Lawson & Hanson's reduction to a least-distance programme whose dual is one non-negative least squares
    problem (Solving Least Squares Problems, 1974, ch. 23).  Returns x, or None when no x meets the
    constraints."""
    from scipy.linalg import cholesky, solve_triangular
    from scipy.optimize import nnls

    if E.ndim == 1:  # z = E x − f
        g = G / E[None, :]
        base = f
    else:  # z = R x − R⁻ᵀEᵀf with RᵀR = EᵀE
        r = cholesky(E.T @ E)
        base = solve_triangular(r, E.T @ f, trans="T")
        g = solve_triangular(r, G.T, trans="T").T
    hh = h - g @ base
    m = g.shape[1]
    matrix = np.vstack([g.T, hh[None, :]])
    rhs = np.zeros(m + 1)
    rhs[-1] = 1.0
    u, _ = nnls(matrix, rhs, maxiter=50 * max(10, matrix.shape[1]))
    residual = matrix @ u - rhs
    if abs(residual[-1]) < 1e-12:  # pragma: no cover - the constraints here always have a solution
        return None
    z = -residual[:m] / residual[-1] + base
    return z / E if E.ndim == 1 else solve_triangular(r, z)


def cluster_runs(mask):
    """Cyclic runs of True: (start, length) pairs, the start in [0, n)."""
    n = mask.size
    if mask.all():
        return [(0, n)]
    if not mask.any():
        return []
    shift = int(np.flatnonzero(~mask)[0])
    rolled = np.roll(mask, -shift)
    edges = np.diff(np.concatenate([[0], rolled.astype(int), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(int((s + shift) % n), int(e - s)) for s, e in zip(starts, stops)]


@dataclass
class Cluster:
    """Lines ``first .. last`` (unwrapped indices) through one candidate vertex; the lines strictly
    between them are its window's interior."""

    first: int
    last: int
    radius: float = 0.0
    statistic: float = 0.0
    corner: bool = False


def _margin(span):
    """Lines either side of a window that a local fit moves: its own width, at least 8, at most 40."""
    return int(min(max(8, span), 40))


class Structure:
    """The least-squares projection's vertex windows, merged and tested (see the module docstring)."""

    def __init__(self, theta, weights, target, support, sigma):
        self.theta, self.weights, self.target, self.support, self.sigma = theta, weights, target, support, sigma
        self.n = theta.size
        self.lo, self.mid, self.hi, self.norm = stencil(theta)
        self.rho = self.curvature(support)
        self.length = np.maximum(self.rho, 0.0) * self.norm  # the edges of the projection
        self.normals = np.column_stack([np.cos(theta), np.sin(theta)])

    def curvature(self, p):
        return self.lo * np.roll(p, 1) + self.mid * p + self.hi * np.roll(p, -1)

    def angle(self, k):
        """Unwrapped angle of line index k (any integer)."""
        k = np.asarray(k)
        return self.theta[k % self.n] + TWO_PI * (k // self.n)

    def lines(self, first, last):
        return np.arange(first, last + 1) % self.n

    def width(self, cluster):
        return float(self.angle(cluster.last) - self.angle(cluster.first))

    # ------------------------------------------------------------------------------------------ merging
    def merge_cost(self, left, right):
        """χ² increase when the two candidate vertices are made one: ρ = 0 on every line between them."""
        last = right.last if right.first >= left.last else right.last + self.n
        if self.angle(last) - self.angle(left.first) >= 0.9 * math.pi:
            return math.inf
        first = left.first
        if self.resolved(left, right, last):
            return math.inf

        def bounds(j):
            k = first + ((j - first) % self.n)
            return 0.0, first < k < last

        change, _, _ = self.local_fit(first, last, bounds, _margin(last - first))
        return max(change, 0.0) / self.sigma**2

    def resolved(self, left, right, last):
        """Whether the two vertices are plainly apart: the edges between them longer than 6 standard
        deviations of the difference of their positions (each fitted to its own lines, noise σ)."""
        stop = right.first if right.first >= left.last else right.first + self.n
        idx = self.lines(left.last, stop)
        d = self.length[idx] @ np.column_stack([-np.sin(self.theta[idx]), np.cos(self.theta[idx])])
        size = float(np.hypot(*d))
        if size == 0.0:
            return False
        spread = 0.0
        for first, end in ((left.first, left.last), (stop, last)):
            idx = self.lines(first, end)
            moment = (self.normals[idx] * self.weights[idx, None]).T @ self.normals[idx]
            if abs(np.linalg.det(moment)) < 1e-12 * np.trace(moment) ** 2:
                return False
            spread += float(d @ np.linalg.solve(moment, d)) / size**2
        return size > 6.0 * self.sigma * math.sqrt(spread)

    def merge(self, clusters, threshold):
        """Join neighbouring candidate vertices while the cheapest join costs at most ``threshold`` in χ²
        (the edge between them is not supported by the data); costs are counted from the projection, so a
        chain of cheap joins cannot add up to an expensive one."""
        clusters = list(clusters)
        m = len(clusters)
        costs = [self.merge_cost(clusters[k], clusters[(k + 1) % m]) if m > 1 else math.inf for k in range(m)]
        while len(clusters) > 1:
            k = int(np.argmin(costs))
            if costs[k] > threshold:
                break
            j = (k + 1) % len(clusters)
            if j == 0:  # the last joins the first across 2π: indices stay unwrapped from the last
                clusters[k] = Cluster(clusters[k].first, clusters[0].last + self.n)
                del clusters[0], costs[0]
                k -= 1
            else:
                clusters[k] = Cluster(clusters[k].first, clusters[j].last)
                del clusters[j], costs[j]
            m = len(clusters)
            for i in ((k - 1) % m, k % m):
                costs[i] = self.merge_cost(clusters[i], clusters[(i + 1) % m]) if m > 1 else math.inf
        return clusters

    # ------------------------------------------------------------------------------------------ testing
    def neighbourhood_radius(self, cluster, length):
        """Radius of curvature of the projection next to the window: its boundary length within one
        window-width of either side (the bounding edges included), divided by that width, on the less
        curved side."""
        w = self.width(cluster)
        if w >= math.pi:
            return float(length.sum() / TWO_PI)
        ks = np.arange(cluster.first - self.n, cluster.last + self.n + 1)
        angles = self.angle(ks)
        slack = 1e-12 * TWO_PI
        a, b = self.angle(cluster.first), self.angle(cluster.last)
        left = (angles >= a - w - slack) & (ks <= cluster.first)
        right = (ks >= cluster.last) & (angles <= b + w + slack)
        return float(min(length[ks[left] % self.n].sum(), length[ks[right] % self.n].sum()) / w)

    def local_fit(self, first, last, bounds, margin):
        """Least squares over the lines near first..last, the rest held at the projection, subject to
        ``ρ_j ≥ lower`` (``= 0`` where equality) for ``lower, equality = bounds(j)``; returns (the change
        of the weighted residual sum, indices, new values)."""
        n = self.n
        span = last - first + 1 + 2 * margin
        if span >= n - 2:
            region = np.arange(n)
            rows = region
        else:
            region = np.arange(first - margin, last + margin + 1) % n
            rows = np.arange(first - margin - 1, last + margin + 2) % n
        position = np.full(n, -1)
        position[region] = np.arange(region.size)
        G = np.zeros((rows.size, region.size))
        spec = [bounds(j) for j in rows]
        h = np.array([s[0] for s in spec], dtype=float)
        for offset, coef in ((-1, self.lo), (0, self.mid), (1, self.hi)):
            cols = (rows + offset) % n
            at = position[cols]
            free = at >= 0
            G[np.flatnonzero(free), at[free]] += coef[rows[free]]
            h[~free] -= coef[rows[~free]] * self.support[cols[~free]]
        equal = np.array([s[1] for s in spec], bool)
        if equal.any():  # ρ_j ≤ 0 as well: −ρ_j ≥ 0
            G = np.vstack([G, -G[equal]])
            h = np.concatenate([h, -h[equal]])
        sw = np.sqrt(self.weights[region])
        x = _lsi(sw, sw * self.target[region], G, h)
        if x is None:  # pragma: no cover
            return math.inf, region, self.support[region]
        before = float(np.sum(self.weights[region] * (self.support[region] - self.target[region]) ** 2))
        after = float(np.sum(self.weights[region] * (x - self.target[region]) ** 2))
        return after - before, region, x

    def rounding_test(self, cluster, fraction):
        """The likelihood ratio of the window rounded off against the corner: the change of χ² from the fit
        with ρ = 0 over the window (the corner, its lines through one point) to the fit with ρ ≥ ``fraction``
        × the radius of curvature next to it (measured on the corner's fit, where the edges that noise split
        across nearby directions are whole again), everything nearby free to follow."""
        first, last = cluster.first, cluster.last
        margin = _margin(last - first)

        def inside(j):
            k = first + ((j - first) % self.n)
            return first < k < last

        corner, region, values = self.local_fit(first, last, lambda j: (0.0, inside(j)), margin)
        support = self.support.copy()
        support[region] = values
        length = np.maximum(self.curvature(support), 0.0) * self.norm
        radius = fraction * self.neighbourhood_radius(cluster, length)
        rounded, _, _ = self.local_fit(first, last, lambda j: ((radius if inside(j) else 0.0), False), margin)
        return radius, max(rounded - corner, 0.0) / self.sigma**2

    # ------------------------------------------------------------------------------------------ the body
    def floors(self, clusters):
        """Smallest ρ_j of the simplest body: 0 on the lines of a corner, elsewhere the radius its
        (rejected) candidate was tested with, or that of the neighbouring candidates."""
        n = self.n
        floor = np.full(n, np.nan)
        owner = np.full(n, -1)
        for k, c in enumerate(clusters):
            inner = self.lines(c.first + 1, c.last - 1)
            floor[inner] = 0.0 if c.corner else c.radius
            owner[inner] = k
        for k, c in enumerate(clusters):
            if c.corner:
                floor[c.first % n] = 0.0
                floor[c.last % n] = 0.0
        m = len(clusters)
        for k in range(m):
            left, right = clusters[k], clusters[(k + 1) % m]
            stop = right.first if right.first >= left.last else right.first + n
            idx = [j % n for j in range(left.last, stop + 1) if np.isnan(floor[j % n])]
            if not idx:
                continue
            radii = [c.radius for c in (left, right) if not c.corner]
            if radii:
                value = min(radii)
            else:
                span = max(float(self.angle(stop) - self.angle(left.last)), float(np.max(self.norm)))
                value = float(self.length[self.lines(left.last, stop)].sum()) / span
            floor[idx] = value
        return floor

    def body_fit(self, clusters, factor):
        """Least squares with ρ = 0 exactly inside each corner window (its lines through one point: the
        support values there follow from the two bounding lines) and ρ ≥ the floors elsewhere."""
        from scipy import sparse

        n = self.n
        floor = self.floors(clusters)
        forced = np.zeros(n, bool)
        rows, cols, vals = [], [], []
        for c in clusters:
            if not c.corner:
                continue
            a, b = self.angle(c.first), self.angle(c.last)
            for j in range(c.first + 1, c.last):
                t = self.angle(j)
                forced[j % n] = True
                s = math.sin(b - a)
                rows += [j % n, j % n]
                cols += [c.first % n, c.last % n]
                vals += [math.sin(b - t) / s, math.sin(t - a) / s]
        free = np.flatnonzero(~forced)
        index = np.full(n, -1)
        index[free] = np.arange(free.size)
        rows += free.tolist()
        cols += free.tolist()
        vals += [1.0] * free.size
        B = sparse.csr_matrix((vals, (rows, index[np.array(cols)])), shape=(n, free.size))
        A = sparse.diags([self.lo[1:], self.mid, self.hi[:-1]], [-1, 0, 1], shape=(n, n)).tolil()
        A[0, n - 1] = self.lo[0]
        A[n - 1, 0] = self.hi[n - 1]
        constrained = free  # the forced lines meet their constraint exactly
        G = (A.tocsr()[constrained] @ B).toarray()
        h = factor * floor[constrained]
        sw = np.sqrt(self.weights)
        E = (sparse.diags(sw) @ B).toarray()
        x = _lsi(E, sw * self.target, G, h)
        if x is None:  # pragma: no cover
            return None
        return B @ x
