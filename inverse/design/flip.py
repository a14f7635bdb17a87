"""The ``flip`` toss: a body turning about a horizontal axis with a uniformly random phase (planar).

Derivation.  The body turns at a constant rate ω about a horizontal axis (perpendicular to its plane) while
its centre of mass comes down at the speed v; at some moment its phase is uniform (the flip is long compared
with a turn).  With u the downward body direction (radians; u = φ + ω t) and the centre at the height
η(t) = η0 − v t, the lowest point first touches the floor at the first u with

    F(u) = b(u) + k u  ≥  c,        k = v/ω  (lengths per radian),  c = η0 + k φ,

and c is uniform over an interval of length 2πk because φ is.  So the contact direction u* is the first
passage of F over a uniform level: with M(u) = max over s ≤ u of F(s) (the running maximum; it grows by
exactly 2πk per turn), ``P(u* in (l, r]) = (M(r) − M(l))/(2πk)``.  The body then rests as in the drop
(no bounce, the turn stopped at contact): in the valley that holds u*.  Both senses of turning are equally
likely (the mirror image u → −u).

Limits.  k → ∞ (no turn) is the drop: ``P = width/(2π)``.  k → 0 (a *vigorous* flip, the default) touches
only at the global maxima of b, the points of the body farthest from its centre of mass: each valley whose
far end (in the sense of the turn) is a global maximum gets the angle back to the previous global maximum,
the other valleys nothing.  Where every maximum of b is equally high, as for a rectangle (a cylinder
flipped about a diameter), this is the drop's angle measure for every k: P(edge) = (2/π) atan(h/d), 1/3 at
thickness/diameter = 1/√3 ≈ 0.577, the value Yong and Mahadevan give for a cylinder flipped vigorously
about a horizontal axis.  For a body whose corners are at different distances the flip favours the faces
beside its farthest corner.  Maxima within 1e-12 × the body's size of the highest count as equal.

A body of revolution is flipped about a diameter: its meridian section is the planar body, with the
direction in the plane of the axis folded onto the tilt (b(u) = h(|u|)); heads is the valley of u = 0.
"""

from __future__ import annotations

import math

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument

from .family import Valleys, outcome_sets, planar_valleys, revolution_valleys

__all__ = ["Flip", "first_contact_odds"]

_PER_VALLEY = 2048  # samples of b' per valley for the interior maxima of F (k > 0)


def _one_sense(b, db, left, right, k, scale):
    """P(valley) for a turn that increases u (module docstring); ``left``/``right`` sorted, cyclic."""
    from scipy.optimize import brentq

    n = left.size
    if k == 0.0:
        peaks = b(right)
        top = float(np.max(peaks))
        record = peaks >= top - 1e-12 * scale
        p = np.zeros(n)
        ends = np.flatnonzero(record)
        for j, i in enumerate(ends):
            previous = right[ends[j - 1]] - (TWO_PI if j == 0 else 0.0)
            p[i] = (right[i] - previous) / TWO_PI
        return p
    fmax = np.empty(n)
    for i in range(n):
        best = max(b(np.array([left[i]]))[0] + k * left[i], b(np.array([right[i]]))[0] + k * right[i])
        u = np.linspace(left[i], right[i], _PER_VALLEY + 1)
        g = db(u) + k
        for j in np.flatnonzero((g[:-1] > 0) & (g[1:] <= 0)):
            a, c = u[j], u[j + 1]
            if (db(np.array([c]))[0] + k) < 0:
                a = brentq(lambda x: float(db(np.array([x]))[0]) + k, a, c, xtol=1e-15, rtol=8.9e-16)
            else:
                a = c
            best = max(best, float(b(np.array([a]))[0]) + k * a)
        fmax[i] = best
    running = -math.inf
    p = np.zeros(n)
    for turn in range(2):  # the second turn's increments: the running maximum has seen a whole turn before
        for i in range(n):
            new = max(running, fmax[i] + turn * TWO_PI * k)
            if turn == 1:
                p[i] = (new - running) / (TWO_PI * k)
            running = new
    return p


def first_contact_odds(b, db, valleys: Valleys, ratio: float, scale: float) -> np.ndarray:
    """P(valley) of the flip with ``ratio`` k = v/ω, averaged over both senses of turning.

    ``b``, ``db``: the planar support function and its derivative (vectorised, 2π-periodic); ``valleys``:
    its cyclic valleys; ``scale``: the body's size (for the tie tolerance of the vigorous limit).
    """
    left, right = valleys.left, valleys.right
    plus = _one_sense(b, db, left, right, ratio, scale)
    minus = _one_sense(lambda u: b(-u), lambda u: -db(-u), -right[::-1], -left[::-1], ratio, scale)[::-1]
    return 0.5 * (plus + minus)


def _section(body):
    """The planar support function of a body of revolution's meridian section and its valleys on the circle."""
    def b(u):
        return body.support(np.abs(np.angle(np.exp(1j * np.asarray(u, dtype=float)))))[0]

    def db(u):
        w = np.angle(np.exp(1j * np.asarray(u, dtype=float)))
        return np.sign(w) * body.support(np.abs(w))[1]

    tilt = revolution_valleys(body)
    inner = tilt.right[:-1]  # the maxima in (0, π)
    bounds = np.sort(np.concatenate([inner, TWO_PI - inner]))
    left = bounds
    right = np.roll(bounds, -1)
    right[-1] += TWO_PI
    return b, db, Valleys(left, right, 0.5 * (left + right) % TWO_PI, TWO_PI)


class Flip:
    """The flip toss (module docstring).

    Parameters
    ----------
    ratio : float
        The fall speed over the spin, k = v/ω, in lengths per radian of the body's own unit (κ for a planar wall);
        0, the default, is the vigorous flip.  Negative or non-finite: InvalidArgument.

    Examples
    --------
    >>> from coinwall.forward.wall import Wall
    >>> wall = Wall.from_expression("abs(cos(t)) + h*abs(sin(t))", {"h": 0.5})
    >>> p = Flip().odds("planar", wall, ["edge"])["edge"]
    >>> abs(p - 2 / math.pi * math.atan(0.5)) < 1e-12
    True
    """

    name = "flip"
    exact = True

    def __init__(self, ratio: float = 0.0):
        ratio = float(ratio)
        if not (math.isfinite(ratio) and ratio >= 0.0):
            raise InvalidArgument(f"`ratio` (fall speed over spin, v/ω) must be >= 0, got {ratio!r}")
        self.ratio = ratio

    def valley_odds(self, kind, body):
        """``(valleys, probabilities)``: planar valleys on the circle for a planar body, the tilt valleys of a
        body of revolution (the section's valleys folded back onto the tilt)."""
        if kind == "planar":
            valleys = planar_valleys(body)
            scale = max(1.0, body.scale)
            p = first_contact_odds(body, lambda u: body.derivatives(np.asarray(u, dtype=float))[1], valleys,
                                   self.ratio, scale)
            return valleys, p
        b, db, circle = _section(body)
        p = first_contact_odds(b, db, circle, self.ratio, max(1.0, body.reach))
        tilt = revolution_valleys(body)
        folded = np.zeros(len(tilt))
        for i, (a, c) in enumerate(zip(circle.left, circle.right)):
            folded[tilt.index(abs(np.angle(np.exp(0.5j * (a + c)))))] += p[i]
        return tilt, folded

    def odds(self, kind, body, names) -> dict:
        valleys, p = self.valley_odds(kind, body)
        sets = outcome_sets(valleys, names, kind)
        return {name: float(np.sum(p[list(members)])) for name, members in sets.items()}

    def to_dict(self) -> dict:
        return {"model": self.name, "ratio": self.ratio}

    @safe_repr
    def __repr__(self):
        return f"Flip(ratio={self.ratio:g})"
