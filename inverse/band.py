"""The outline of a sampled wall as a certified band: where every body consistent with the samples lies.

A body is *consistent* with the samples when its support function at every sample's angle lies in the
sample's interval ``[l_i, u_i]`` (``b0 + b_i ± w_i``).  Between samples the data are silent, but convexity
is not (docs/theory.md, "The outline as a band"):

* **outer envelope.**  Every consistent body lies under every upper line ``x·n_i ≤ u_i``, so inside their
  intersection ``O`` (the *outer body*); in a gap between two samples its support is that of the vertex of
  ``O`` whose normal window holds the gap: ``U(θ) = [u_a sin(θ_b − θ) + u_b sin(θ − θ_a)] / sin(θ_b − θ_a)``
  for the active lines ``a ≤ i < i + 1 ≤ b`` around it;
* **inner envelope.**  A consistent body touches line ``i`` at a point ``p`` with ``p·n_i ≥ l_i``, and ``p``
  lies under the line ``k`` samples back, ``p·n_{i−k} ≤ u_{i−k}``.  For ``θ`` ahead of ``θ_i`` the least
  value of ``p·n(θ)`` over that wedge is the support of its apex, the meeting point of the lower line ``i``
  and the upper line ``i − k``: ``L_{i,k}(θ) = [l_i sin(θ − θ_{i−k}) − u_{i−k} sin(θ − θ_i)] / sin(θ_i − θ_{i−k})``;
  the same from the other side for ``θ`` behind ``θ_{i+1}``.  The body's support is at least the largest of
  these (``k = 1, 2``, both sides of the gap).

For convex bodies the Hausdorff distance is the largest difference of support functions, so any two
consistent bodies are within ``max_θ (U − L)`` of each other: the **outline tolerance**.  In a gap it is the
maximum of the least of a few sinusoids, found exactly from their peaks and crossings.  For exact data it is
the distance from the outer body to the true one: ``ρΔ²/2`` on an arc, the roof ``E·Δ/4`` over a flat edge
of length ``E``, with ``Δ`` the gap.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.sampledata import discrete_rho

__all__ = ["Band", "band_of"]

#: how many samples back (and ahead) the inner envelope looks
_BACK = 2


def _meet(pa, ca, sa, pb, cb, sb):
    """The point where the line ``x·(ca, sa) = pa`` meets ``x·(cb, sb) = pb``, as an (n, 2) array."""
    s = sb * ca - cb * sa  # sin(θb − θa)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.column_stack([(pa * sb - pb * sa) / s, (pb * ca - pa * cb) / s])


@dataclass(frozen=True, repr=False)
class Band:
    """The envelopes of every body consistent with interval samples (module docstring).

    Attributes
    ----------
    theta, lower, upper : ndarray
        The samples' angles (sorted, in [0, 2π)) and intervals ``[l_i, u_i]`` of the support function.
    vertex : ndarray (n, 2)
        For each gap (``i`` to ``i + 1``), the vertex of the outer body over it.
    apexes : ndarray (n, 2k, 2)
        For each gap, the apexes whose support bounds the inner envelope there.
    width : ndarray (n,)
        The largest ``U − L`` over each gap (exact for the envelopes).
    outer : ndarray (m, 2)
        The outer body's vertices, counter-clockwise.
    outer_normals : ndarray (m,)
        The normal angle of each of its edges (vertex k to k + 1): the angle of the sample line it lies on.

    Examples
    --------
    A hexagon's exact support values at 12 angles: every consistent body lies within the band, whose
    tolerance is the hexagon's corner height ``1 − cos 30°`` over its gaps.

    >>> import numpy as np
    >>> from coinwall.inverse.band import band_of
    >>> theta = np.arange(12) * np.pi / 6 + np.pi / 12
    >>> corners = np.exp(1j * np.pi * np.arange(6) / 3)
    >>> h = np.max(np.outer(np.cos(theta), corners.real) + np.outer(np.sin(theta), corners.imag), axis=1)
    >>> band = band_of(theta, h, h)
    >>> band.outer.shape, band.width.shape
    ((12, 2), (12,))
    """

    theta: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    vertex: np.ndarray
    apexes: np.ndarray
    width: np.ndarray
    outer: np.ndarray
    outer_normals: np.ndarray

    @property
    def tolerance(self) -> float:
        """The outline tolerance: every two consistent bodies are within this (Hausdorff) of each other."""
        return float(np.max(self.width))

    def _gap(self, angles):
        angles = np.mod(np.asarray(angles, float), TWO_PI)
        return (np.searchsorted(self.theta, angles, side="right") - 1) % self.theta.size, angles

    def outer_support(self, angles) -> np.ndarray:
        """``U(θ)``: the support of the outer body, at least every consistent body's."""
        gap, angles = self._gap(angles)
        v = self.vertex[gap]
        return v[:, 0] * np.cos(angles) + v[:, 1] * np.sin(angles)

    def inner_support(self, angles) -> np.ndarray:
        """``L(θ)``: at most every consistent body's support."""
        gap, angles = self._gap(angles)
        p = self.apexes[gap]
        return np.max(p[..., 0] * np.cos(angles)[:, None] + p[..., 1] * np.sin(angles)[:, None], axis=1)

    def __repr__(self) -> str:
        return f"Band({self.theta.size} samples, outline tolerance {self.tolerance:.3g})"


def band_of(theta, lower, upper) -> Band:
    """The band of every convex body whose support at ``theta`` lies in ``[lower, upper]`` (module docstring).

    Parameters
    ----------
    theta : ndarray
        Distinct sorted angles in [0, 2π), every gap below π.
    lower, upper : ndarray
        The intervals of the support function (the offset included).

    Returns
    -------
    Band

    Examples
    --------
    A regular hexagon (vertices at distance 1) seen at 12 exact samples, two in each vertex window: over each
    edge the two sample lines meet at distance 1 from the centre, where the edge is at ``cos(π/6)``, so the
    band is that roof, ``1 − cos(π/6)`` high (and 0 inside the vertex windows).

    >>> import numpy as np
    >>> theta = np.arange(12) * np.pi / 6 + np.pi / 12
    >>> corners = np.exp(1j * np.pi * np.arange(6) / 3)
    >>> h = np.max(np.outer(np.cos(theta), corners.real) + np.outer(np.sin(theta), corners.imag), axis=1)
    >>> band = band_of(theta, h, h)
    >>> round(band.tolerance, 6), round(float(1 - np.cos(np.pi / 6)), 6)
    (0.133975, 0.133975)
    """
    from scipy.spatial import ConvexHull

    from .support import interior_point

    theta = np.asarray(theta, float)
    lo = np.asarray(lower, float)
    up = np.asarray(upper, float)
    n = theta.size
    gaps = np.diff(np.append(theta, theta[0] + TWO_PI))
    # the outer body: its active lines are the hull vertices of the dual points n_i / (u_i − n_i·p)
    normals = np.column_stack([np.cos(theta), np.sin(theta)])
    if np.all(discrete_rho(theta, up) >= 0):
        active = np.arange(n)  # every piece of every upper line is there (a convex polygon): no hull needed
    else:
        centre = interior_point(normals, up)
        shifted = up - normals @ centre
        active = np.sort(ConvexHull(normals / shifted[:, None]).vertices)
    # the active lines around each gap: a = last active ≤ g, b = first active ≥ g + 1 (cyclically)
    position = np.searchsorted(active, np.arange(n), side="right") - 1
    a = active[position % active.size]
    b = active[(position + 1) % active.size]
    cos, sin = normals[:, 0], normals[:, 1]
    vertex = _meet(up[a], cos[a], sin[a], up[b], cos[b], sin[b])
    outer = vertex[active]
    # the apexes: lower line g with the upper line k back; lower line g + 1 with the upper line k ahead
    index = np.arange(n)
    nxt = (index + 1) % n
    apexes = []
    for k in range(1, min(_BACK, n - 2) + 1):
        back, ahead = (index - k) % n, (index + 1 + k) % n
        apexes.append(_meet(up[back], cos[back], sin[back], lo, cos, sin))
        apexes.append(_meet(lo[nxt], cos[nxt], sin[nxt], up[ahead], cos[ahead], sin[ahead]))
    apexes = np.stack(apexes, axis=1)  # (n, 2k, 2)
    width = _largest_gap_difference(theta, gaps, vertex, apexes)
    return Band(theta, lo, up, vertex, apexes, width, outer, theta[np.roll(active, -1)])


def _largest_gap_difference(theta, gaps, vertex, apexes):
    """``max over δ in [0, gap] of min_k (V_g − P_{g,k})·n(θ_g + δ)`` for every gap g, exactly.

    In the gap's own frame each term is ``A_k cos δ + B_k sin δ``.  The least of them is largest at an end of
    the gap, at a term's peak (``δ = atan2(B, A)``, value ``hypot(A, B)``) or where two terms cross
    (``(A_i − A_j) cos δ + (B_i − B_j) sin δ = 0``); each such direction is known by its cosine and sine, so
    only the test of whether it lies inside the gap needs an angle.
    """
    m = apexes.shape[1]
    c0, s0 = np.cos(theta), np.sin(theta)
    # rows k of (m, n) arrays: contiguous, so the least over k is m − 1 elementwise minima
    dx = np.ascontiguousarray((vertex[:, None, 0] - apexes[..., 0]).T)
    dy = np.ascontiguousarray((vertex[:, None, 1] - apexes[..., 1]).T)
    A, B = dx * c0 + dy * s0, dy * c0 - dx * s0

    def least(cos, sin):
        out = A[0] * cos + B[0] * sin
        for j in range(1, m):
            np.minimum(out, A[j] * cos + B[j] * sin, out=out)
        return out

    best = np.maximum(least(1.0, 0.0), least(np.cos(gaps), np.sin(gaps)))
    directions = [(A[j], B[j]) for j in range(m)]
    for i in range(m):
        for j in range(i + 1, m):
            dB, dA = B[i] - B[j], A[i] - A[j]
            directions += [(dB, -dA), (-dB, dA)]
    for x, y in directions:
        r = np.hypot(x, y)
        inside = (r > 0) & (np.mod(np.arctan2(y, x), TWO_PI) <= gaps)
        with np.errstate(invalid="ignore", divide="ignore"):
            value = least(x / r, y / r)
        np.maximum(best, np.where(inside, value, -np.inf), out=best)
    return np.maximum(best, 0.0)
