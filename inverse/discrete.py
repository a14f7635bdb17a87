"""Walls given as samples: the exact geometry of their support lines.

A sample ``h_i = b0 + b(θ_i)`` says that the line ``x·n(θ_i) = h_i`` supports the body.  Nothing
more: between the samples the data are silent.  So for data the body is built from the lines
themselves, with no interpolant and no derivative (docs/theory.md, "Walls as data"):

* the **discrete radius of curvature** ``ρ_i`` (:func:`discrete_curvature`) is the length of the
  piece of line i between its neighbours, divided by ``tan(Δ₋/2) + tan(Δ₊/2)``.  It is what
  ``b + b''`` is for a smooth wall (the difference is ``Δ²(ρ'' )/12``) and adding ``b0`` to every
  ``h_i`` adds exactly ``b0`` to every ``ρ_i``: the data's critical offset is ``−min ρ_i``;
* the **largest body under the samples** is the intersection of the half-planes
  ``{x : x·n(θ_i) ≤ h_i}`` (:func:`support_polygon`), exact;
* a **vertex window** is a run of lines through one point (``ρ_i = 0``): a corner of the body, its
  point found by least squares over the lines; between two vertex windows with nothing in
  between, the body is the edge joining them (the wall has a kink at the edge's normal).

Every comparison with zero uses the tolerance that the data imply: the rounding of the values
propagated through the formulas.  Values read from a file carry their rounding in their digits
(:func:`rounding_of`; the file readers pass it on); arrays given to the API are taken at face value
(a few ulps) unless ``Wall.from_samples(..., rounding=)`` says otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.errors import InvalidWall
from coinwall.forward.formats.wallfile import rounding_of
from coinwall.forward.sampledata import curvature_coefficients, discrete_rho

from .support import interior_point

__all__ = ["rounding_of", "machine_rounding", "discrete_curvature", "DiscreteSupport", "discrete_support",
           "SampledBody", "support_polygon", "halfspace_polygon"]

_EPS = np.finfo(float).eps


def machine_rounding(values) -> np.ndarray:
    """A few ulps of each value: the rounding of numbers taken at face value."""
    v = np.abs(np.asarray(values, dtype=float))
    return 2.0 * _EPS * np.maximum(v, np.finfo(float).tiny)


def _gaps(theta):
    after = np.diff(np.append(theta, theta[0] + TWO_PI))
    return np.roll(after, 1), after


def discrete_curvature(theta, h, rounding=None):
    """The discrete radius of curvature of support samples, and its rounding tolerance.

    With ``Δ₋ = θ_i − θ_{i−1}`` and ``Δ₊ = θ_{i+1} − θ_i`` (cyclically), the lines i−1 and i+1 cut
    line i at distances ``(h_{i∓1} − h_i cos Δ∓)/sin Δ∓`` from its foot point, so the piece of
    line i between them has length ``ℓ_i`` and ``ρ_i = ℓ_i / (tan(Δ₋/2) + tan(Δ₊/2))``.  For a
    uniform step Δ this is ``(h_{i−1} + h_{i+1} − 2 cos Δ · h_i) / (2 (1 − cos Δ))`` (docs/theory.md).

    Parameters
    ----------
    theta : ndarray
        Sorted distinct angles in [0, 2π), every gap (cyclically) below π.
    h : ndarray
        Support values.
    rounding : ndarray, optional
        How far each ``h_i`` may be off (default: a few ulps).

    Returns
    -------
    rho, tolerance : ndarray
        ``ρ_i`` and the largest change of ``ρ_i`` the rounding of the three values can cause.
    """
    theta = np.asarray(theta, dtype=float)
    h = np.asarray(h, dtype=float)
    before, after = _gaps(theta)
    if np.max(np.maximum(before, after)) >= math.pi * (1 - 1e-9):
        raise InvalidWall("samples: two consecutive angles are π or more apart; the lines do not bound a body")
    delta = machine_rounding(h) if rounding is None else np.maximum(machine_rounding(h), rounding)
    a, c, d = curvature_coefficients(theta)
    rho = discrete_rho(theta, h)
    tolerance = np.abs(a) * np.roll(delta, 1) + np.abs(c) * delta + np.abs(d) * np.roll(delta, -1)
    return rho, tolerance


@dataclass(frozen=True, repr=False)
class DiscreteSupport:
    """Support samples of a wall (without the offset) and what they say about curvature.

    Attributes
    ----------
    theta, b : ndarray
        The samples, sorted, angles in [0, 2π).
    rounding : ndarray
        How far each ``b_i`` may be off (a few ulps, or what the maker of the samples said).
    rho, rho_tolerance : ndarray
        Discrete radius of curvature of ``b`` (offset 0) and its rounding tolerance.
    spacing_error : ndarray
        ``|ρ_{i−1} − 2ρ_i + ρ_{i+1}|/12``: how far ``ρ_i`` may stand from the radius of curvature of
        a smooth wall through the samples (``Δ²ρ''/12``, the leading error of the formula).
    """

    theta: np.ndarray
    b: np.ndarray
    rounding: np.ndarray
    rho: np.ndarray
    rho_tolerance: np.ndarray
    spacing_error: np.ndarray


def discrete_support(theta, b, rounding=None) -> DiscreteSupport:
    """:class:`DiscreteSupport` of samples (sorted, distinct, angles in [0, 2π)); ``rounding``: how far
    each value may be off (default: a few ulps: arrays are taken at face value)."""
    theta = np.asarray(theta, dtype=float)
    b = np.asarray(b, dtype=float)
    rounding = machine_rounding(b) if rounding is None else np.maximum(machine_rounding(b), rounding)
    rho, tol = discrete_curvature(theta, b, rounding)
    spacing = np.abs(np.roll(rho, 1) - 2 * rho + np.roll(rho, -1)) / 12.0
    return DiscreteSupport(theta, b, rounding, rho, tol, spacing)


@dataclass(frozen=True, repr=False)
class SampledBody:
    """The body under support samples: a convex polygon, its corners and what each one governs.

    Attributes
    ----------
    vertices : ndarray (m, 2)
        Counter-clockwise.
    cone_start, cone_end : ndarray (m,)
        The window of normal angles of each vertex (``cone_end ≥ cone_start``; unwrapped).
    corner : ndarray (m,) of bool
        Vertices that own at least one sample strictly inside their window: a vertex window of the
        data (lines through one point) or a cut (lines that miss the body, Case III).
    deficit, deficit_angle : ndarray (m,)
        Largest ``h_i − v·n_i`` over the samples in the window (0 within rounding) and where.
    rho : ndarray (m,)
        Discrete radius of curvature at the vertex (0 at corners).
    edges : int
        Vertex windows joined by an edge where the largest body would have a sliver.
    """

    vertices: np.ndarray
    cone_start: np.ndarray
    cone_end: np.ndarray
    corner: np.ndarray
    deficit: np.ndarray
    deficit_angle: np.ndarray
    rho: np.ndarray
    edges: int


def _intersections(theta_a, h_a, theta_b, h_b):
    det = np.sin(theta_b - theta_a)
    x = (h_a * np.sin(theta_b) - h_b * np.sin(theta_a)) / det
    y = (h_b * np.cos(theta_a) - h_a * np.cos(theta_b)) / det
    return np.column_stack([x, y])


def _least_squares_point(theta, h):
    """The point closest (in least squares) to lying on every line ``x·n(θ_k) = h_k``: the 2×2 normal
    equations (a thousand lines in microseconds), or an SVD where the lines are nearly parallel."""
    c, s = np.cos(theta), np.sin(theta)
    a, b, d = float(c @ c), float(c @ s), float(s @ s)
    det = a * d - b * b
    if det > 1e-6 * (a + d) ** 2:
        # normal equations square the condition number: two steps of iterative refinement on the residual
        # bring the point back to what an SVD gives (a vertex of exact data to ~1e-15)
        point = np.zeros(2)
        for _ in range(3):
            residual = h - c * point[0] - s * point[1]
            rc, rs = float(c @ residual), float(s @ residual)
            point = point + np.array([(d * rc - b * rs) / det, (a * rs - b * rc) / det])
        return point
    point, *_ = np.linalg.lstsq(np.column_stack([c, s]), h, rcond=None)
    return point


def _through_point(theta, h, tol):
    """A point within ``tol_k`` of every line ``x·n(θ_k) = h_k``, or None if there is none.

    The least-squares point first (microseconds); where it misses a line's tolerance, the region of all
    such points (:func:`_strip_region`) decides, and its centroid is checked here.
    """
    point = _least_squares_point(theta, h)
    c, s = np.cos(theta), np.sin(theta)
    if np.all(np.abs(h - c * point[0] - s * point[1]) <= tol):
        return point
    region = _strip_region(theta, h, tol)
    if region is None:
        return None
    candidate = region.mean(axis=0)
    if np.all(np.abs(h - c * candidate[0] - s * candidate[1]) <= tol):
        return candidate
    return None


def _strip_region(theta, h, tol):
    """The vertices of the convex region ``|x·n(θ_k) − h_k| ≤ tol_k`` for every k, or None if it is empty.

    Written by hand because the merges ask it for every candidate vertex (thousands of times for dense
    rounded data), and a general linear-programming call (~1 ms each in scipy's HiGHS) made solving 3,600
    rounded samples take 3 s: the strips of the first line and of the line least parallel to it make a
    parallelogram, which every other strip clips (Sutherland–Hodgman on a convex polygon of a few vertices).
    """
    a = 0
    b = int(np.argmax(np.abs(np.sin(theta - theta[a]))))
    polygon = _parallelogram(theta[a], h[a], tol[a], theta[b], h[b], tol[b])
    if polygon is None:
        return None  # all lines (nearly) parallel: no bounded region to speak of
    for k in range(theta.size):
        if k not in (a, b):
            polygon = _clip_strip(polygon, theta[k], h[k], tol[k])
            if not polygon:
                return None
    return np.array(polygon)


def _parallelogram(theta_a, h_a, tol_a, theta_b, h_b, tol_b):
    """The corners (a list, in order around it) of the intersection of two lines' strips, or None if the lines
    are (nearly) parallel."""
    if abs(math.sin(theta_b - theta_a)) < 1e-9:
        return None
    corners = []
    for sa, sb in ((-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (1.0, -1.0)):
        corners.append(tuple(_intersections(np.array([theta_a]), np.array([h_a + sa * tol_a]),
                                            np.array([theta_b]), np.array([h_b + sb * tol_b]))[0]))
    return corners


#: most vertices a strips' region keeps (see :func:`_clip_strip`)
MAX_REGION_VERTICES = 24


def _clip_strip(polygon, theta, h, tol):
    """The convex ``polygon`` cut by the strip ``|x·n(θ) − h| ≤ tol`` (its two half-planes).

    The strips of many lines of slowly turning angle cut a region of as many vertices, and clipping it again
    and again would be quadratic in the lines: beyond :data:`MAX_REGION_VERTICES` every other vertex is
    dropped.  Their hull lies inside the region (it is convex), so a point found in it is still within every
    strip; the price is only that a region too thin for the hull may be declared empty (a merge not made).
    """
    nx, ny = math.cos(theta), math.sin(theta)
    polygon = _clip(polygon, nx, ny, h + tol)  # x·n ≤ h + tol
    if polygon:
        polygon = _clip(polygon, -nx, -ny, tol - h)  # −x·n ≤ −(h − tol)
    if len(polygon) > MAX_REGION_VERTICES:
        polygon = polygon[::2]
    return polygon


def _clip(polygon, nx, ny, limit):
    """The convex ``polygon`` (a list of points) cut by the half-plane ``nx·x + ny·y ≤ limit``."""
    out = []
    count = len(polygon)
    for i in range(count):
        px, py = polygon[i]
        qx, qy = polygon[(i + 1) % count]
        dp = nx * px + ny * py - limit
        dq = nx * qx + ny * qy - limit
        if dp <= 0.0:
            out.append((px, py))
        if (dp < 0.0 < dq) or (dq < 0.0 < dp):
            f = dp / (dp - dq)
            out.append((px + f * (qx - px), py + f * (qy - py)))
    return out


def _concurrent(theta, h, rounding, scale) -> bool:
    """Whether the lines ``x·n(θ_k) = h_k`` pass through one point within their rounding: a point lies
    within each line's interval ``h_k ± rounding_k`` (so the merged vertex is a body the data allow)."""
    if theta.size <= 2:
        return True
    return _through_point(theta, h, rounding + 16.0 * _EPS * scale) is not None


def support_polygon(theta, h, rounding, rho, centre=None) -> SampledBody:
    """The body under the support lines ``x·n(θ_i) ≤ h_i`` (all ``h_i >= 0``).

    ``rounding`` is the half-width of each line's interval ``centre_i ± rounding_i`` (``centre`` defaults to
    ``h``; lines raised above their intervals' centres pass the centres here): vertices merge, and lines pass
    through a vertex, only where the point lies within every such interval.

    The active lines are the vertices of the convex hull of the dual points ``n_i / h_i`` (Qhull):
    a line is active iff its dual point is extreme.  Consecutive active lines meet at the vertices.
    Vertices closer than the rounding of their lines allows are one vertex; a vertex whose window
    holds further samples is a corner, its point fitted to every line through it; a vertex between
    two zero-deficit corners whose window holds no sample is an edge's sliver and is dropped.
    """
    from scipy.spatial import ConvexHull, QhullError

    theta = np.asarray(theta, dtype=float)
    h = np.asarray(h, dtype=float)
    mid = h if centre is None else np.asarray(centre, dtype=float)
    n = theta.size
    normals = np.column_stack([np.cos(theta), np.sin(theta)])
    scale = float(np.max(np.abs(h)))
    # the dual needs a point strictly inside: the centre of mass may be on the boundary (some h_i = 0)
    shifted = h - normals @ interior_point(normals, h)
    try:
        hull = ConvexHull(normals / shifted[:, None])
    except QhullError as exc:  # pragma: no cover - all h > 0 and the angles cover the circle
        raise InvalidWall(f"samples: the support lines do not bound a body ({str(exc).splitlines()[0]})") from None
    active = np.sort(hull.vertices)
    nxt = np.roll(active, -1)
    points = _intersections(theta[active], h[active], theta[nxt], h[nxt])
    start = theta[active]
    end = theta[nxt] + np.where(nxt <= active, TWO_PI, 0.0)
    # the rounding of two lines moves their intersection by about (δ_a + δ_b)/sin(gap)
    gap = end - start
    slack = (rounding[active] + rounding[nxt]) / np.maximum(np.sin(np.minimum(gap, np.pi / 2)), 1e-300)
    slack = 4.0 * slack + 16.0 * _EPS * scale

    # merge runs of vertices that are one point within rounding (a vertex window cut up by rounding): two
    # vertices closer than their lines resolve, and only while every line of the run passes within its
    # rounding of the run's common point (a chain of close vertices along an arc is not one vertex)
    m = len(points)
    same_as_next = np.hypot(*(np.roll(points, -1, axis=0) - points).T) <= np.maximum(slack, np.roll(slack, -1))
    if same_as_next.all() and _concurrent(theta[active], mid[active], rounding[active], scale):
        raise InvalidWall("samples: every support line passes through one point; the body would be a point")
    breaks = np.flatnonzero(~np.roll(same_as_next, 1))
    first = int(breaks[0]) if breaks.size else 0  # a vertex that does not continue a run
    # a run grows while the region of points within every interval of its lines is not empty: the region is
    # kept and clipped by each new line's strip (linear in the run's length; from scratch it was quadratic)
    merge_tol = rounding + 16.0 * _EPS * scale

    def start_region(j):
        return _parallelogram(theta[active[j]], mid[active[j]], merge_tol[active[j]],
                              theta[nxt[j]], mid[nxt[j]], merge_tol[nxt[j]])

    # only runs of close vertices need the region test; every other vertex is a group of its own
    order = (first + np.arange(m)) % m
    starts = np.flatnonzero(~same_as_next[(order - 1) % m])
    groups = []
    for seg in np.split(order, starts[1:]):
        if seg.size == 1:
            groups.append([int(seg[0])])
            continue
        current = [int(seg[0])]
        region = start_region(current[0])
        for j in seg[1:].tolist():
            if len(current) < m - 1:
                line = nxt[j]
                if region is not None:
                    grown = _clip_strip(region, theta[line], mid[line], merge_tol[line])
                    joins = bool(grown)
                else:  # the run's first two lines are parallel: decide from all its lines (rare)
                    lines = np.append(active[current], line)
                    grown, joins = None, _concurrent(theta[lines], mid[lines], rounding[lines], scale)
                if joins:
                    current.append(j)
                    region = grown
                    continue
            groups.append(current)
            current = [j]
            region = start_region(j)
        groups.append(current)

    group_first = np.array([g[0] for g in groups])
    group_last = np.array([g[-1] for g in groups])
    cone_start = start[group_first]
    cone_end = cone_start + np.mod(end[group_last] - cone_start, TWO_PI)
    cone_end = np.where(cone_end <= cone_start, cone_end + TWO_PI, cone_end)
    vertices = points[group_first].copy()
    for k in np.flatnonzero(group_last != group_first):
        vertices[k] = points[groups[k]].mean(axis=0)
    first_line, last_line = active[group_first], nxt[group_last]

    # the samples in each window: deficits, lines through the vertex, the fitted point
    count = len(vertices)
    corner = np.zeros(count, bool)
    deficit = np.zeros(count)
    deficit_angle = np.mod(cone_start, TWO_PI)
    rho_at = 0.5 * (rho[first_line] + rho[last_line])
    for k in np.flatnonzero(np.mod(last_line - first_line, n) > 1).tolist():
        i, j = first_line[k], last_line[k]
        idx = np.arange(i, j + (n if j <= i else 0) + 1) % n  # the lines from one active line to the next
        rho_at[k] = 0.0
        corner[k] = True
        # a line passes through the vertex if the vertex lies within the line's interval h ± rounding
        through_tol = rounding[idx] + 16.0 * _EPS * scale
        # the lines that made this vertex (merged within rounding) pass through it: a point within every
        # one's interval (it exists: the merge found it), then one within every line of the window that
        # passes through that point (a vertex window), where such a point exists
        made = np.unique(np.concatenate([active[groups[k]], nxt[groups[k]]]))
        meet = vertices[k].copy()  # where the window's lines meet: under every line of it, within rounding
        whole = _through_point(theta[idx], mid[idx], through_tol)  # every line of the window through one point
        if whole is not None:
            vertices[k] = whole
        elif made.size >= 2:
            fitted = _through_point(theta[made], mid[made], rounding[made] + 16.0 * _EPS * scale)
            vertices[k] = fitted if fitted is not None else _least_squares_point(theta[made], mid[made])
        for _ in range(0 if whole is not None else 2):
            standoff = mid[idx] - normals[idx] @ vertices[k]
            through = np.abs(standoff) <= through_tol
            if through.sum() < 2:
                break
            fitted = _through_point(theta[idx[through]], mid[idx[through]], through_tol[through])
            if fitted is None:
                break
            vertices[k] = fitted
        standoff = mid[idx] - normals[idx] @ vertices[k]
        crossed = standoff < -through_tol
        if crossed.any():
            # the fitted point lies beyond a line of the window (in a wide corner window many lines pass near
            # the vertex, and their least-squares point can cross the window's edge lines): move it back towards
            # where the lines meet, just far enough that no line of the window is crossed
            at_meet = mid[idx] - normals[idx] @ meet
            need = (-through_tol[crossed] - standoff[crossed]) / np.maximum(at_meet[crossed] - standoff[crossed],
                                                                              1e-300)
            s = min(1.0, float(np.max(need)))
            vertices[k] = vertices[k] + s * (meet - vertices[k])
            standoff = mid[idx] - normals[idx] @ vertices[k]
        standoff[np.abs(standoff) <= through_tol] = 0.0
        worst = int(np.argmax(standoff))
        deficit[k] = max(float(standoff[worst]), 0.0)
        deficit_angle[k] = theta[idx[worst]]

    # a sliver between two exact vertex windows is an edge of the body: drop it, and give each
    # neighbouring corner the window up to the edge's normal
    keep = np.ones(count, bool)
    if count > 3:
        exact = corner & (deficit == 0.0)
        for k in np.flatnonzero(~corner & np.roll(exact, 1) & np.roll(exact, -1)).tolist():
            before, after = (k - 1) % count, (k + 1) % count
            if not corner[k] and corner[before] and corner[after] and deficit[before] == 0.0 \
                    and deficit[after] == 0.0 and keep[before] and keep[after]:
                keep[k] = False
                dx, dy = vertices[after] - vertices[before]
                normal = math.atan2(-dx, dy)
                cone_end[before] = cone_start[before] + np.mod(normal - cone_start[before], TWO_PI)
                cone_start[after] = cone_end[after] - np.mod(cone_end[after] - normal, TWO_PI)
    edges = int(count - keep.sum())
    body = SampledBody(vertices[keep], cone_start[keep], cone_end[keep], corner[keep], deficit[keep],
                       deficit_angle[keep], rho_at[keep], edges)
    return _convex(body, 16.0 * _EPS * scale)


def _convex(body: SampledBody, tiny: float) -> SampledBody:
    """``body`` with every vertex that a merge or a least-squares fit left inside the hull of its neighbours
    (a reflex or straight turn, within rounding) dropped, its window given to the previous vertex."""
    v = body.vertices
    fields = [body.cone_start.copy(), body.cone_end.copy(), body.corner.copy(), body.deficit.copy(),
              body.deficit_angle.copy(), body.rho.copy()]
    while len(v) > 3:
        before, after = np.roll(v, 1, axis=0), np.roll(v, -1, axis=0)
        turn = (v[:, 0] - before[:, 0]) * (after[:, 1] - v[:, 1]) - (v[:, 1] - before[:, 1]) * (after[:, 0] - v[:, 0])
        reflex = np.flatnonzero(turn <= tiny * np.hypot(*(after - before).T))
        if reflex.size == 0:
            break
        k = int(reflex[np.argmin(turn[reflex])])
        previous = (k - 1) % len(v)
        start, end, corner, deficit, deficit_angle, rho = fields
        end[previous] = start[previous] + np.mod(end[k] - start[previous], TWO_PI)
        if end[previous] <= start[previous]:
            end[previous] += TWO_PI
        corner[previous] |= corner[k]
        if deficit[k] > deficit[previous]:
            deficit[previous], deficit_angle[previous] = deficit[k], deficit_angle[k]
        keep = np.arange(len(v)) != k
        v = v[keep]
        fields = [f[keep] for f in fields]
    if len(v) == len(body.vertices):
        return body
    return SampledBody(v, *fields, body.edges)


def halfspace_polygon(theta, h) -> np.ndarray:
    """The intersection of the half-planes ``x·n(θ_i) ≤ h_i`` by scipy's ``HalfspaceIntersection``
    (Qhull): an independent construction, used to cross-check :func:`support_polygon`.  Returns the
    vertices counter-clockwise."""
    from scipy.spatial import ConvexHull, HalfspaceIntersection

    h = np.asarray(h, dtype=float)
    normals = np.column_stack([np.cos(theta), np.sin(theta), -h])
    # Qhull needs a feasible point strictly inside; the centre of mass may lie on the boundary (some h_i = 0)
    inside = interior_point(normals[:, :2], h)
    points = HalfspaceIntersection(normals, inside).intersections
    hull = ConvexHull(points)
    return points[hull.vertices]


def simplest_inside(vertices, theta, lower, normals=None) -> tuple[np.ndarray, np.ndarray]:
    """The convex polygon ``vertices`` (counter-clockwise) with every vertex dropped whose removal keeps the
    support at each ``theta`` at least ``lower`` there — the fewest vertices, within rounding, that stay inside
    the intervals the polygon met (vertices are only removed, so the result lies inside the polygon).

    Each pass looks at vertices no two of them neighbours: first those standing out farthest from their
    neighbours' chord (taller than both), then, when none of those can go, the even and the odd ones in turn;
    removing vertex ``j`` replaces its support over its normal window by the larger of its neighbours', so a
    pass is one vectorised look at the samples in each candidate's window.  ``normals``: the normal angle of
    each edge ``j → j + 1`` where known exactly (the outer body's edges lie on sample lines); a new edge's
    normal is kept between those of the two it replaces, so tiny edges never disorder the windows.

    Examples
    --------
    The outer body of a pentagon's exact support at every 10° (its vertices and a roof over each edge) comes
    back as the pentagon:

    >>> theta = np.radians(np.arange(0, 360, 10.0))
    >>> corners = np.exp(1j * (0.3 + 2 * np.pi * np.arange(5) / 5))
    >>> h = np.max(np.outer(np.cos(theta), corners.real) + np.outer(np.sin(theta), corners.imag), axis=1)
    >>> outer = halfspace_polygon(theta, h)
    >>> len(outer), len(simplest_inside(outer, theta, h - 1e-12)[0])
    (10, 5)
    """
    v = np.asarray(vertices, float)
    theta = np.asarray(theta, float)
    lower = np.asarray(lower, float)
    if normals is None:
        edges = np.roll(v, -1, axis=0) - v
        normals = np.mod(np.arctan2(-edges[:, 0], edges[:, 1]), TWO_PI)
    normal = np.asarray(normals, float).copy()
    direction = np.column_stack([np.cos(theta), np.sin(theta)])
    stalled = parity = 0
    tallest = True
    while v.shape[0] > 3 and stalled < 3:
        m = v.shape[0]
        # the vertex whose normal window (from its incoming edge's normal to its outgoing one's) holds a sample
        owner = vertex_owner(normal, theta)
        if tallest:
            # the vertices standing farthest out from their neighbours' chord first (a roof over a flat edge
            # goes before the vertices on the curves beside it): those taller than both neighbours
            before, after = np.roll(v, 1, axis=0), np.roll(v, -1, axis=0)
            chord = after - before
            height = (chord[:, 1] * (v - before)[:, 0] - chord[:, 0] * (v - before)[:, 1]) / np.maximum(
                np.hypot(*chord.T), 1e-300)  # outward: to the right of the chord of a counter-clockwise polygon
            candidate = (height > np.roll(height, 1)) & (height >= np.roll(height, -1))
        else:
            candidate = (np.arange(m) % 2) == parity
            if m % 2:
                candidate[m - 1] = False  # it neighbours vertex 0
        pick = np.flatnonzero(candidate[owner])
        own = owner[pick]
        chord = np.maximum(np.einsum("ij,ij->i", v[(own - 1) % m], direction[pick]),
                           np.einsum("ij,ij->i", v[(own + 1) % m], direction[pick]))
        fails = np.zeros(m, bool)
        fails[own[chord < lower[pick]]] = True
        drop = candidate & ~fails
        excess = int(drop.sum()) - (m - 3)
        if excess > 0:
            drop[np.flatnonzero(drop)[-excess:]] = False
        if not tallest:
            parity ^= 1
        if not drop.any():
            stalled += 1
            tallest = False  # then every other vertex, both ways
            continue
        stalled = 0
        # the edge j − 1 → j + 1 replaces j − 1 → j and j → j + 1: its normal, kept between theirs
        j = np.flatnonzero(drop)
        before, after = v[(j - 1) % m], v[(j + 1) % m]
        chord_normal = np.arctan2(-(after - before)[:, 0], (after - before)[:, 1])
        low, span = normal[(j - 1) % m], np.mod(normal[j] - normal[(j - 1) % m], TWO_PI)
        offset = np.mod(chord_normal - low, TWO_PI)
        offset = np.where(offset <= span, offset, np.where(offset - span < TWO_PI - offset, span, 0.0))
        normal[(j - 1) % m] = np.mod(low + offset, TWO_PI)
        v, normal = v[~drop], normal[~drop]
    return v, normal


def vertex_owner(normals, theta) -> np.ndarray:
    """Index of the vertex of a convex polygon whose normal window holds each angle, from the normal angles
    of its edges (``normals[j]``: edge ``j → j + 1``; vertex ``j``'s window runs from ``normals[j − 1]`` to
    ``normals[j]``)."""
    m = normals.size
    order = np.argsort(normals, kind="stable")
    return (order[(np.searchsorted(normals[order], np.mod(theta, TWO_PI), side="left") - 1) % m] + 1) % m
