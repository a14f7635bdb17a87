"""A closed convex outline as a piecewise cubic Bézier curve, and its support function.

The forward construction (body → wall) needs the support function
``h(θ) = max_{x ∈ body} x·n(θ)`` of an outline at *arbitrary* θ, exactly.
Taking the maximum over the vertices of a polygon would be exact for a polygon
but only O(Δ²) accurate for a sampled smooth curve; a cubic Hermite/Bézier
interpolant of the curve is accurate to O(Δ⁴) and its support function is
still exact to rounding, because the projection of a cubic Bézier onto a
direction is a cubic polynomial whose maximum comes from a quadratic.

Segment ``i`` runs from ``nodes[i]`` to ``nodes[(i+1) % n]`` with inner
control points ``controls[i, 0]`` and ``controls[i, 1]``.  A polygon is the
special case of straight segments.  Outlines are counter-clockwise with the
centre of mass at the origin.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .angles import TWO_PI
from .display import safe_repr
from .errors import InvalidOutline

__all__ = ["Outline", "support_function"]

# Gauss–Legendre nodes on [0, 1]: 3 points integrate the degree-5 area integrand exactly
_GL3 = np.polynomial.legendre.leggauss(3)
_GL8 = np.polynomial.legendre.leggauss(8)


def _chord_directions(p0, p1, p2, p3):
    """Direction of every segment's chord (control polygon as fallback for a closed segment).

    For a convex curve the chord of a segment is parallel to the tangent at
    some interior point, so chord normals are monotone along the outline and
    each lies inside its segment's range of normals; unlike the end tangents
    they stay well defined where the curvature radius vanishes.
    """
    chord = p3 - p0
    size = np.hypot(*chord.T)
    small = size <= 1e-14 * (1 + np.hypot(*p0.T))
    chord[small] = (p2 - p1)[small]
    return chord


@dataclass(frozen=True, repr=False)
class Outline:
    """Closed counter-clockwise piecewise cubic Bézier curve.

    Attributes
    ----------
    nodes : ndarray, shape (n, 2)
        Segment end points; segment ``i`` goes from ``nodes[i]`` to ``nodes[i+1]``.
    controls : ndarray, shape (n, 2, 2)
        The two inner control points of every segment.

    Examples
    --------
    >>> from coinwall import Outline
    >>> square = Outline.from_polygon([[1, 1], [-1, 1], [-1, -1], [1, -1]])
    >>> square
    Outline(4 segments, area=4, perimeter=8)
    >>> square.support([0.0]).tolist()          # the support function: the half-width 1 along +x
    [1.0]
    """

    nodes: np.ndarray
    controls: np.ndarray

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_polygon(cls, points) -> "Outline":
        """Straight segments through ``points`` (any orientation; made counter-clockwise)."""
        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
            raise InvalidOutline(f"an outline needs at least 2 points as (x, y) pairs, got shape {pts.shape}")
        if not np.all(np.isfinite(pts)):
            raise InvalidOutline("outline points must be finite")
        if len(pts) > 2 and np.allclose(pts[0], pts[-1]):
            pts = pts[:-1]
        if _signed_area(pts) < 0:
            pts = pts[::-1]
        nxt = np.roll(pts, -1, axis=0)
        controls = np.stack([pts + (nxt - pts) / 3, pts + 2 * (nxt - pts) / 3], axis=1)
        return cls(pts, controls)

    @classmethod
    def from_hermite(cls, points, d_out, d_in, steps) -> "Outline":
        """Cubic Hermite interpolant: ``d_out[i]`` leaves node i, ``d_in[i]`` arrives at node i.

        ``steps[i]`` is the parameter length of segment i (node i → i+1), the
        derivatives being with respect to that parameter.
        """
        pts = np.asarray(points, dtype=float)
        d_out = np.asarray(d_out, dtype=float)
        d_in = np.asarray(d_in, dtype=float)
        steps = np.asarray(steps, dtype=float)[:, None]
        c1 = pts + d_out * steps / 3
        c2 = np.roll(pts, -1, axis=0) - np.roll(d_in, -1, axis=0) * steps / 3
        return cls(pts, np.stack([c1, c2], axis=1))

    # ------------------------------------------------------------------ geometry
    @property
    def _segments(self):
        return self.nodes, self.controls[:, 0], self.controls[:, 1], np.roll(self.nodes, -1, axis=0)

    def point(self, s):
        """Points at the local parameters ``s`` (shape (n,) or (n, m)) of every segment."""
        p0, p1, p2, p3 = self._segments
        s = np.asarray(s, dtype=float)
        if s.ndim == 1:
            s = s[None, :].repeat(len(p0), 0)
        u = 1 - s
        w = [u**3, 3 * u**2 * s, 3 * u * s**2, s**3]
        return sum(wk[..., None] * pk[:, None, :] for wk, pk in zip(w, (p0, p1, p2, p3)))

    def _derivative(self, s):
        """B'(s) at the same local parameters ``s`` (shape (m,)) of every segment: shape (n, m, 2)."""
        p0, p1, p2, p3 = self._segments
        s = np.asarray(s, dtype=float)
        u = 1 - s
        weights = np.stack([3 * u**2, 6 * u * s, 3 * s**2])  # (3, m): Bernstein basis of degree 2
        deltas = np.stack([p1 - p0, p2 - p1, p3 - p2])  # (3, n, 2)
        # a matrix product: einsum with this signature is several times slower
        out = weights.T @ deltas.reshape(3, -1)  # (m, n*2)
        return out.reshape(s.size, -1, 2).transpose(1, 0, 2)

    def polygon(self, per_segment: int = 1) -> np.ndarray:
        """Points along the curve, ``per_segment`` per segment (``1``: the nodes)."""
        if per_segment == 1:
            return self.nodes.copy()
        s = np.arange(per_segment) / per_segment
        return self.point(s).reshape(-1, 2)

    @property
    def area(self) -> float:
        """Enclosed area, exact for the cubic Bézier curve.

        Green's theorem, ``A = ½∮(x dy − y dx)``; for one cubic segment the
        integral is the bilinear form of its control points
        ``(6 P0×P1 + 3 P0×P2 + P0×P3 + 3 P1×P2 + 3 P1×P3 + 6 P2×P3)/10``
        (integrate the Bernstein products; checked against Gauss–Legendre in the tests).
        """
        p0, p1, p2, p3 = self._segments

        def cross(a, b):
            return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]

        twice = (6 * cross(p0, p1) + 3 * cross(p0, p2) + cross(p0, p3) + 3 * cross(p1, p2)
                 + 3 * cross(p1, p3) + 6 * cross(p2, p3)) / 10
        return float(0.5 * np.sum(twice))

    @property
    def perimeter(self) -> float:
        """Arc length (8-point Gauss–Legendre on every segment)."""
        x, w = _GL8
        s, w = (x + 1) / 2, w / 2
        der = self._derivative(s)
        return float(np.sum(np.hypot(der[..., 0], der[..., 1]) * w))

    def support(self, theta):
        """Support function ``max_{x on curve} x·(cos θ, sin θ)``; see :func:`support_function`."""
        return support_function(self, theta)

    # ------------------------------------------------------------------ pictures
    def plot(self, ax=None):
        """Draw the outline and the centre of mass (the origin), matplotlib imported here; returns the axes."""
        from .formats.figure import axes_or_new
        from .formats.style import house_style

        with house_style():
            return self._plot(axes_or_new(ax, (5, 5))[0])

    def _plot(self, ax):
        # a few points per segment show the curve; a finely sampled outline is drawn through its nodes
        pts = self.polygon(4) if len(self.nodes) < 4096 else self.nodes
        pts = np.vstack([pts, pts[:1]])
        ax.plot(pts[:, 0], pts[:, 1], "k-")
        ax.plot([0], [0], "+", color="#D55E00", ms=10, mew=1.5, label="centre of mass")
        ax.set_aspect("equal")
        ax.set_xlabel("x (κ)")
        ax.set_ylabel("y (κ)")
        ax.set_title(f"body ({len(self.nodes)} segments), + centre of mass")
        return ax

    def plot_wall(self, ax=None, *, theta=None, H=None):
        """Draw the wall function ``b(θ) = h(θ)`` and, given the wall distance ``H``, the upper wall
        ``t(θ) = H − h(θ + π)`` at the angles ``theta`` (default 720 uniform); returns the axes."""
        from .formats.figure import axes_or_new
        from .formats.style import house_style

        with house_style():
            return self._plot_wall(axes_or_new(ax, (6, 4))[0], theta, H)

    def _plot_wall(self, ax, theta, H):
        theta = np.linspace(0.0, TWO_PI, 720, endpoint=False) if theta is None else np.asarray(theta, float)
        ax.plot(theta, self.support(theta), label="b(θ)")
        if H is not None:
            ax.plot(theta, H - self.support(theta + np.pi), label=f"t(θ) = H − b(θ+π), H = {H:g}")
        ax.set_xlim(0.0, TWO_PI)
        ax.set_xlabel("wall angle θ (rad)")
        ax.set_ylabel("wall height in the frame of the centre of mass (κ)")
        # above the axes, so the legend never hides a curve
        ax.legend(loc="lower left", bbox_to_anchor=(0, 1.02), ncol=2)
        return ax

    def __len__(self) -> int:
        return len(self.nodes)

    @safe_repr
    def __repr__(self) -> str:
        return f"Outline({len(self.nodes)} segments, area={self.area:.6g}, perimeter={self.perimeter:.6g})"


def _signed_area(pts):
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _dot(p, n):
    """Row-wise dot products of (k, 2) arrays."""
    return p[:, 0] * n[:, 0] + p[:, 1] * n[:, 1]


def _segment_max(p0, p1, p2, p3, n):
    """max over s ∈ [0, 1] of B(s)·n for matching rows of segments and directions."""
    q0, q1, q2, q3 = (_dot(p, n) for p in (p0, p1, p2, p3))
    d0, d1, d2 = q1 - q0, q2 - q1, q3 - q2
    # derivative of the projected cubic is 3(A s² + B s + C)
    a = d0 - 2 * d1 + d2
    b = 2 * (d1 - d0)
    c = d0
    best = np.maximum(q0, q3)
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(np.maximum(b * b - 4 * a * c, 0.0))
        q = -0.5 * (b + np.copysign(disc, b))
        roots = [np.where(np.abs(a) > 1e-300, q / a, np.nan), np.where(np.abs(q) > 1e-300, c / q, np.nan)]
        linear = np.abs(a) <= 1e-14 * (np.abs(b) + np.abs(c) + 1e-300)
        roots.append(np.where(linear & (np.abs(b) > 1e-300), -c / b, np.nan))
    for r in roots:
        ok = np.isfinite(r) & (r > 0) & (r < 1)
        if np.any(ok):
            s = r[ok]
            u = 1 - s
            # the projection of the cubic is the cubic of the projections
            value = u**3 * q0[ok] + 3 * u * u * s * q1[ok] + 3 * u * s * s * q2[ok] + s**3 * q3[ok]
            best[ok] = np.maximum(best[ok], value)
    return best


def support_function(outline: Outline, theta):
    """Support function of a convex counter-clockwise outline at the angles ``theta``.

    For every θ the segment whose chord normal is the last one not exceeding θ
    is located by a binary search on the (monotone) chord normals; the contact
    point then lies on that segment or the next, and the maximum of the
    projection is taken over that segment and its two neighbours, in closed
    form.  For a convex outline this is exact to rounding; for a
    polygon it equals ``max_i x_i·n(θ)``.

    Parameters
    ----------
    outline : Outline
        A convex counter-clockwise outline (e.g. a convex hull or a solved body).
    theta : array_like
        Directions in the body frame (radians).

    Returns
    -------
    ndarray
        ``h(θ)``, same shape as ``theta``.

    Examples
    --------
    A square of side 2: ``h(0) = 1`` (a side), ``h(π/4) = √2`` (a corner).

    >>> import numpy as np
    >>> from coinwall import Outline, support_function
    >>> square = Outline.from_polygon([[1, 1], [-1, 1], [-1, -1], [1, -1]])
    >>> support_function(square, np.array([0.0, np.pi / 4])).round(12).tolist()
    [1.0, 1.414213562373]
    """
    theta = np.asarray(theta, dtype=float)
    shape = theta.shape
    theta = theta.ravel()
    p0, p1, p2, p3 = outline._segments
    nseg = len(p0)
    chord = _chord_directions(p0, p1, p2, p3)
    # outward normal of a counter-clockwise curve: the tangent turned clockwise
    normal_angle = np.arctan2(-chord[:, 0], chord[:, 1])
    slack = 1e-9  # normals equal to the first one up to rounding must not wrap around to +2π
    unwrapped = normal_angle[0] + np.mod(normal_angle - normal_angle[0] + slack, TWO_PI) - slack
    # pieces of one straight edge share a normal up to rounding: give them exactly the normal of
    # the run's first piece, so the stable sort below keeps them in index (geometric) order
    step = np.abs(np.diff(unwrapped)) > 1e-12
    run = np.concatenate([[0], np.cumsum(step)])
    unwrapped = unwrapped[np.flatnonzero(np.concatenate([[True], step]))][run]
    # Segments sorted by chord normal are in geometric order for a convex curve, whatever
    # rounding does to ties on a straight edge or to the chords of tiny segments at a corner;
    # the contact segment for θ is then the last one with chord normal ≤ θ or the next one
    # *in sorted order* (its neighbour by index may be another piece of the same straight edge).
    order = np.argsort(unwrapped, kind="stable")
    rel = normal_angle[0] + np.mod(theta - normal_angle[0], TWO_PI)
    pos = np.searchsorted(unwrapped[order], rel, side="right") - 1
    n = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    best = np.full(theta.size, -np.inf)
    for shift in (-1, 0, 1):
        k = order[np.mod(pos + shift, nseg)]
        best = np.maximum(best, _segment_max(p0[k], p1[k], p2[k], p3[k], n))
    return best.reshape(shape)
