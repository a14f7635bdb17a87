"""Polyline approximation of a piecewise cubic Bézier outline within a tolerance, and its deviation.

Every node of the outline is kept as a vertex, so corners (Case III, the ends
of the stick) stay exact corners; each segment is split at uniform parameter
steps, doubled until its deviation is within the tolerance.  The deviation
of a piece is the largest distance from the curve to its chord: the signed
distance to the chord line is a cubic in the curve parameter, so its
maximum comes exactly from the roots of a quadratic; uniform samples guard
the (rare, strongly curved) case where the nearest point of the chord is an
end point rather than the foot of the perpendicular.
"""

from __future__ import annotations

import numpy as np

__all__ = ["flatten_outline", "polyline_deviation", "largest_diameter"]

_SAMPLES = 17
_MAX_DOUBLINGS = 14
# polyline size limit: beyond it the tolerance is reported as not reached (memory stays bounded)
_MAX_PIECES = 100_000


def _power_basis(p0, p1, p2, p3):
    """Coefficients a0..a3 of B(s) = a0 + a1 s + a2 s² + a3 s³ (each (n, 2))."""
    return p0, 3 * (p1 - p0), 3 * (p2 - 2 * p1 + p0), p3 - 3 * p2 + 3 * p1 - p0


def _evaluate(coef, s):
    a0, a1, a2, a3 = coef
    s = s[..., None]
    return a0 + s * (a1 + s * (a2 + s * a3))


def _piece_deviation(coef, sa, sb):
    """Largest distance from B(s), s ∈ [sa, sb], to the chord B(sa)B(sb); arrays of pieces."""
    a = _evaluate(coef, sa)
    b = _evaluate(coef, sb)
    chord = b - a
    length = np.hypot(chord[:, 0], chord[:, 1])
    safe = np.where(length > 0, length, 1.0)
    normal = np.stack([-chord[:, 1], chord[:, 0]], axis=1) / safe[:, None]
    # d(s) = (B(s) - a)·normal; d'(s) = c1 + 2 c2 s + 3 c3 s²
    c1 = np.einsum("ij,ij->i", coef[1], normal)
    c2 = np.einsum("ij,ij->i", coef[2], normal)
    c3 = np.einsum("ij,ij->i", coef[3], normal)
    qa, qb, qc = 3 * c3, 2 * c2, c1
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(np.maximum(qb * qb - 4 * qa * qc, 0.0))
        q = -0.5 * (qb + np.copysign(disc, qb))
        candidates = [q / qa, qc / q, -qc / qb]
    u = np.linspace(0.0, 1.0, _SAMPLES)
    params = [sa + (sb - sa) * t for t in u]
    for r in candidates:
        params.append(np.where(np.isfinite(r) & (r > sa) & (r < sb), r, sa))
    s = np.stack(params, axis=1)  # (pieces, m)
    coef_rep = [c[:, None, :] for c in coef]
    pts = coef_rep[0] + s[..., None] * (coef_rep[1] + s[..., None] * (coef_rep[2] + s[..., None] * coef_rep[3]))
    rel = pts - a[:, None, :]
    dirn = np.where(length[:, None] > 0, chord / safe[:, None], 0.0)
    t = np.clip(np.einsum("ijk,ik->ij", rel, dirn), 0.0, length[:, None])
    foot = a[:, None, :] + t[..., None] * dirn[:, None, :]
    return np.max(np.hypot(*(pts - foot).transpose(2, 0, 1)), axis=1)


def _pieces(coef, counts):
    seg = np.repeat(np.arange(len(counts)), counts)
    start = np.concatenate([np.arange(c) / c for c in counts])
    step = np.repeat(1.0 / counts, counts)
    return seg, start, start + step


def polyline_deviation(outline, counts, scale: float = 1.0):
    """Per-segment largest distance between the scaled outline and its polyline with ``counts`` pieces."""
    p = [scale * q for q in outline._segments]
    coef = _power_basis(*p)
    counts = np.asarray(counts, dtype=int)
    seg, sa, sb = _pieces(coef, counts)
    dev = _piece_deviation([c[seg] for c in coef], sa, sb)
    out = np.zeros(len(counts))
    np.maximum.at(out, seg, dev)
    return out


def flatten_outline(outline, tolerance: float, scale: float = 1.0):
    """Closed polyline within ``tolerance`` of ``scale`` × outline.

    Parameters
    ----------
    outline : forward.Outline
        The exact outline (body units).
    tolerance : float
        Largest allowed curve-to-polyline distance, in scaled units.
    scale : float
        Output length per body unit.

    Returns
    -------
    points : ndarray, shape (m, 2)
        Vertices (scaled), the outline's nodes among them, without repeating the first.
    deviation : float
        The largest curve-to-polyline distance achieved (scaled units); larger than
        ``tolerance`` when that would need more than ``_MAX_PIECES`` vertices.
    """
    n = len(outline.nodes)
    counts = np.ones(n, dtype=int)
    for _ in range(_MAX_DOUBLINGS):
        dev = polyline_deviation(outline, counts, scale)
        bad = dev > tolerance
        if not np.any(bad) or counts.sum() + counts[bad].sum() > _MAX_PIECES:
            break
        counts[bad] *= 2
    else:
        dev = polyline_deviation(outline, counts, scale)
    p = [scale * q for q in outline._segments]
    coef = _power_basis(*p)
    seg, sa, _ = _pieces(coef, counts)
    points = _evaluate([c[seg] for c in coef], sa)
    return points, float(dev.max())


def largest_diameter(outline, samples: int = 2048):
    """Largest diameter of the outline and its two end points (body units).

    The diameter of a convex body is its largest width ``h(θ) + h(θ + π)``;
    the maximum over a grid is refined with a bounded scalar search, and the
    end points are the outline points that project furthest along ±n(θ).
    """
    from scipy.optimize import minimize_scalar

    theta = np.linspace(0.0, np.pi, samples, endpoint=False)
    width = outline.support(theta) + outline.support(theta + np.pi)
    k = int(np.argmax(width))
    step = np.pi / samples
    best = minimize_scalar(lambda t: -(outline.support(t) + outline.support(t + np.pi)),
                           bounds=(theta[k] - step, theta[k] + step), method="bounded",
                           options={"xatol": 1e-12})
    angle = float(best.x) if -best.fun >= width[k] else float(theta[k])
    n = np.array([np.cos(angle), np.sin(angle)])
    dense = outline.polygon(16)
    proj = dense @ n
    return float(max(-best.fun, width[k])), dense[int(np.argmax(proj))], dense[int(np.argmin(proj))]
