"""Bodies whose truth is known in closed form, for the tests of walls given as data.

Numpy only, never coinwall: a test that compares coinwall's answer with these compares two independent
computations.  Every body is a convex set with the centre of mass convention of ``docs/theory.md``: its
support function ``h(θ) = max_{x ∈ K} x·n(θ)`` is the wall at ``b0 = 0``.  Each :class:`Truth` carries

* ``h(theta)``: the support function, in closed form (derived in each constructor's docstring);
* ``b_c``: ``−min(h + h'')`` over the absolutely continuous part (edges are positive masses);
* ``vertices``: the true corners (points whose normal window has positive width) and their windows.

Helpers: :func:`write_csv` writes samples as a person would (digits, degrees, shuffled rows, duplicates);
:func:`outline_support` evaluates a coinwall outline's support from its own Bézier control points (numpy);
:func:`distance` is the Hausdorff distance of two convex bodies (the largest difference of their support
functions) on a dense grid of directions.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

TWO_PI = 2.0 * np.pi


@dataclasses.dataclass(frozen=True)
class Truth:
    """A convex body known in closed form."""

    name: str
    h: Callable[[np.ndarray], np.ndarray]
    b_c: float
    vertices: np.ndarray  # (m, 2), the corners
    windows: np.ndarray  # (m, 2) the normal window [start, end] (unwrapped) of each corner

    def corners_seen(self, theta, least=2):
        """The corners whose window holds at least ``least`` of the angles ``theta`` strictly inside."""
        theta = np.asarray(theta, float)
        count = np.array([np.sum((np.mod(theta - a, TWO_PI) > 1e-12) & (np.mod(theta - a, TWO_PI) < b - a - 1e-12))
                          for a, b in self.windows])
        return self.vertices[count >= least], count


def _unit(theta):
    return np.cos(theta), np.sin(theta)


def polygon(vertices, name="polygon", rounding=0.0) -> Truth:
    """A convex polygon (counter-clockwise vertices), or the polygon ⊕ a disc of radius ``rounding``: ``h(θ) =
    max_k v_k·n(θ) + r`` (the support of a Minkowski sum is the sum of supports).  Corners: the vertices when
    ``r = 0`` (window of vertex k: between the normals of its two edges), none otherwise.  ``b_c``: 0 for the
    polygon (h + h'' = 0 on every window), −r for the rounded one (h + h'' = r on the arcs)."""
    v = np.asarray(vertices, float)
    edges = np.roll(v, -1, axis=0) - v
    normals = np.mod(np.arctan2(-edges[:, 0], edges[:, 1]), TWO_PI)  # of edge k → k + 1
    start = np.roll(normals, 1)
    end = start + np.mod(normals - start, TWO_PI)

    def h(theta):
        c, s = _unit(np.asarray(theta, float).ravel())
        return (np.max(v[:, :1] * c + v[:, 1:] * s, axis=0) + rounding).reshape(np.shape(theta))

    if rounding > 0:
        return Truth(f"{name} ⊕ disc {rounding:g}", h, -rounding, np.zeros((0, 2)), np.zeros((0, 2)))
    return Truth(name, h, 0.0, v, np.column_stack([start, end]))


def regular_polygon(n, radius=1.0, phase=0.3, rounding=0.0) -> Truth:
    k = np.arange(n)
    v = radius * np.column_stack([np.cos(phase + TWO_PI * k / n), np.sin(phase + TWO_PI * k / n)])
    return polygon(v, f"regular {n}-gon", rounding)


def random_polygon(count, rng) -> Truth:
    """A random convex polygon with ``count`` vertices, made from its edges: outward normals whose gaps (the
    vertices' windows) are uniform in [1, 3] times a common factor (so between 1/3 and 3 times each other), at
    distances in [0.85, 1.15] from the origin; vertex k is where edges k and k + 1 meet (a 2×2 solve).  Redrawn
    until every edge is longer than 0.05 with every turn positive, so every point is a vertex."""
    for _ in range(100000):
        gaps = rng.uniform(1.0, 3.0, count)
        phi = rng.uniform(0, TWO_PI) + np.cumsum(gaps / gaps.sum() * TWO_PI)
        d = rng.uniform(0.85, 1.15, count)
        a, b = phi, np.roll(phi, -1)
        det = np.sin(b - a)
        v = np.column_stack([(d * np.sin(b) - np.roll(d, -1) * np.sin(a)) / det,
                             (np.roll(d, -1) * np.cos(a) - d * np.cos(b)) / det])
        e = np.roll(v, -1, axis=0) - v
        turn = e[:, 0] * np.roll(e, -1, axis=0)[:, 1] - e[:, 1] * np.roll(e, -1, axis=0)[:, 0]
        if np.all(turn > 1e-3) and np.all(np.hypot(*e.T) > 0.05):
            return polygon(v, f"random {count}-gon")
    raise RuntimeError("no polygon")  # pragma: no cover


def ellipse(a=1.0, c=0.65, shift=(0.0, 0.0)) -> Truth:
    """The ellipse with semi-axes ``a`` (along x) and ``c``, shifted: ``h = sqrt(a² cos² + c² sin²) + s·n``
    (the support of a linear image of the disc; a translation adds ``s·n``).  ``h + h''`` is the radius of
    curvature ``a²c²/(a² cos² + c² sin²)^{3/2}``, least at the ends of the major axis: ``b_c = −c²/a`` for a ≥ c."""
    sx, sy = shift

    def h(theta):
        c_, s_ = _unit(theta)
        return np.sqrt(a * a * c_ * c_ + c * c * s_ * s_) + sx * c_ + sy * s_

    return Truth(f"ellipse {a:g}×{c:g}", h, -min(a, c) ** 2 / max(a, c), np.zeros((0, 2)), np.zeros((0, 2)))


def superellipse(p=4.0, scale=1.0) -> Truth:
    """``|x|^p + |y|^p ≤ 1`` (scaled), p > 2: ``h(θ) = (|cos θ|^q + |sin θ|^q)^{1/q}`` with ``1/p + 1/q = 1``
    (Hölder: the dual norm).  Its least radius of curvature is at the diagonals, where ``x = y = 2^{−1/p}``
    (the curve is flat where it meets the axes): with ``F = x^p + y^p`` the curvature of a level set is
    ``κ = (F_xx F_y² − 2F_xy F_x F_y + F_yy F_x²) / |∇F|³`` (``F_xy = 0``), and ``b_c = −1/κ`` there."""
    q = p / (p - 1.0)
    x = 2.0 ** (-1.0 / p)
    fx = fy = p * x ** (p - 1)
    fxx = fyy = p * (p - 1) * x ** (p - 2)
    kappa = (fxx * fy**2 + fyy * fx**2) / (fx**2 + fy**2) ** 1.5
    b_c = -scale / kappa

    def h(theta):
        c_, s_ = _unit(theta)
        return scale * (np.abs(c_) ** q + np.abs(s_) ** q) ** (1.0 / q)

    return Truth(f"superellipse p={p:g}", h, b_c, np.zeros((0, 2)), np.zeros((0, 2)))


def lens(R=1.0, d=0.6) -> Truth:
    """The lens ``disc((−d, 0), R) ∩ disc((d, 0), R)``: two arcs of radius R meeting at the corners
    ``(0, ±c)``, ``c = √(R² − d²)``.  The arc on the right belongs to the disc centred at (−d, 0): for
    ``|θ| ≤ α = atan2(c, d)``, ``h = R − d cos θ``; symmetrically ``h = R + d cos θ`` for ``|θ − π| ≤ α``; the other
    normals belong to the corners, ``h = c |sin θ|`` (windows ``[α, π − α]`` and ``[π + α, 2π − α]``).  ``b_c = 0``
    (ρ = 0 on the corner windows, R on the arcs)."""
    c = np.sqrt(R * R - d * d)
    alpha = np.arctan2(c, d)

    def h(theta):
        t = np.mod(np.asarray(theta, float), TWO_PI)
        cos, sin = np.cos(t), np.sin(t)
        right = (t <= alpha) | (t >= TWO_PI - alpha)
        left = np.abs(t - np.pi) <= alpha
        return np.where(right, R - d * cos, np.where(left, R + d * cos, c * np.abs(sin)))

    vertices = np.array([[0.0, c], [0.0, -c]])
    windows = np.array([[alpha, np.pi - alpha], [np.pi + alpha, TWO_PI - alpha]])
    return Truth(f"lens R={R:g} d={d:g}", h, 0.0, vertices, windows)


def d_shape(R=1.0) -> Truth:
    """The half disc ``{|x| ≤ R, x ≥ 0}``: one flat edge of length 2R (normal π) between the corners (0, ±R).
    ``h = R`` for ``cos θ ≥ 0`` (the arc), ``R |sin θ|`` otherwise (the corner windows [π/2, π] and [π, 3π/2]);
    ``b_c = 0``."""

    def h(theta):
        c_, s_ = _unit(theta)
        return np.where(c_ >= 0, R, R * np.abs(s_))

    vertices = np.array([[0.0, R], [0.0, -R]])
    windows = np.array([[np.pi / 2, np.pi], [np.pi, 1.5 * np.pi]])
    return Truth(f"half disc R={R:g}", h, 0.0, vertices, windows)


def egg() -> Truth:
    """``h = 1 + 0.04 cos 2θ + 0.03 cos 3θ``: ``h + h'' = 1 − 0.12 cos 2θ − 0.24 cos 3θ`` (``(cos kθ)'' = −k² cos kθ``),
    positive, so a convex egg-like body with no corner; ``b_c = −min(h + h'')``, found here on a grid of 10⁶ angles
    refined by a parabola (the function is a trigonometric polynomial of degree 3)."""
    t = np.linspace(0, TWO_PI, 1_000_000, endpoint=False)
    rho = 1 - 0.12 * np.cos(2 * t) - 0.24 * np.cos(3 * t)
    i = int(np.argmin(rho))
    left, mid, right = rho[i - 1], rho[i], rho[(i + 1) % t.size]
    least = mid - (left - right) ** 2 / (8 * (left - 2 * mid + right))

    def h(theta):
        theta = np.asarray(theta, float)
        return 1 + 0.04 * np.cos(2 * theta) + 0.03 * np.cos(3 * theta)

    return Truth("egg", h, -float(least), np.zeros((0, 2)), np.zeros((0, 2)))


def paper_wall(eps=1.0) -> Truth:
    """The paper's ellipse wall ``sqrt((1 + ε cos²θ)/(1 + ε))``: an ellipse with semi-axes 1 and 1/√(1+ε), so
    ``b_c = −1/(1 + ε)`` (``ellipse`` with ``a = 1``, ``c² = 1/(1 + ε)``)."""
    truth = ellipse(1.0, 1.0 / np.sqrt(1.0 + eps))
    return dataclasses.replace(truth, name=f"paper wall ε={eps:g}")


# ---------------------------------------------------------------------------------------------------- data
def write_csv(path, theta, b, *, digits=8, degrees=False, theta_digits=None, shuffle=None, duplicate=0.0,
              rng=None, sd=None, header=True):
    """Samples as a person writes them: ``digits`` decimals of the values (angles to ``theta_digits``, default
    the same), in degrees or radians, rows shuffled (``shuffle=True``), a fraction ``duplicate`` of rows written
    twice, a ``b_sd`` column when ``sd`` is given."""
    rng = rng or np.random.default_rng(0)
    angle = np.degrees(theta) if degrees else np.asarray(theta, float)
    td = digits if theta_digits is None else theta_digits
    rows = [f"{a:.{td}f},{v:.{digits}f}" + (f",{sd:g}" if sd is not None else "") for a, v in zip(angle, b)]
    if duplicate:
        extra = rng.choice(len(rows), int(duplicate * len(rows)), replace=False)
        rows += [rows[k] for k in extra]
    if shuffle:
        rng.shuffle(rows)
    head = ("theta_deg" if degrees else "theta") + ",b" + (",b_sd" if sd is not None else "")
    with open(path, "w") as stream:
        stream.write((head + "\n" if header else "") + "\n".join(rows) + "\n")
    return path


def outline_support(nodes, controls, theta, per_segment=16):
    """The support function of a closed cubic Bézier outline at ``theta``, from its own points: the largest
    projection over ``per_segment`` points of every segment (exact for a polygon's straight segments, whose
    largest projection is at an end; for curved ones short by at most the sag of a chord of one part in per_segment)."""
    p0 = np.asarray(nodes, float)
    p1, p2 = np.asarray(controls, float)[:, 0], np.asarray(controls, float)[:, 1]
    p3 = np.roll(p0, -1, axis=0)
    s = np.arange(per_segment)[None, :, None] / per_segment
    u = 1 - s
    points = (u**3 * p0[:, None] + 3 * u * u * s * p1[:, None] + 3 * u * s * s * p2[:, None]
              + s**3 * p3[:, None]).reshape(-1, 2)
    theta = np.asarray(theta, float)
    out = np.empty(theta.size)
    block = max(1, 2_000_000 // points.shape[0])
    for start in range(0, theta.size, block):
        t = theta[start:start + block]
        out[start:start + block] = np.max(np.cos(t)[:, None] * points[:, 0] + np.sin(t)[:, None] * points[:, 1],
                                          axis=1)
    return out


def distance(body, truth, count=None):
    """The Hausdorff distance between a coinwall body's outline and the true body: the largest difference of
    their support functions over ``count`` directions (default 50,000 for a polygon, seen from its vertices,
    exactly; 20,000 for a curved outline, seen from 16 points a segment), plus the body's ``b0``."""
    per_segment = 1 if body.method == "halfplanes" else 16
    count = count or (50_000 if per_segment == 1 else 20_000)
    theta = np.linspace(0, TWO_PI, count, endpoint=False)
    return float(np.max(np.abs(outline_support(body.outline.nodes, body.outline.controls, theta, per_segment)
                               - (body.b0 + truth.h(theta)))))
