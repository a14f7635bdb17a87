"""The ``drop`` toss: a uniformly random orientation, landing without a bounce on the face below the centre.

Assumptions.  The body reaches the floor with its orientation uniformly distributed (planar: the angle θ of
the downward body direction uniform on the circle; a body of revolution: its axis uniform on the sphere),
does not bounce (a perfectly inelastic floor), and rolls without slipping or overshooting into the rest face
whose valley holds its orientation at contact (:mod:`.family`).  No length, mass, speed or field enters:
the odds are a property of the outline alone.

* Planar: ``P(face) = (width of its valley)/(2π)``, the angle the face subtends at the centre of mass for a
  polygon.  A d × h rectangle (edges of length h): ``P(edge) = (2/π) atan(h/d)``, 1/3 at h/d = 1/√3.
* Body of revolution (tilt θ ∈ [0, π] of the axis, density sin θ / 2 on the sphere): a valley [a, c] has
  ``P = (cos a − cos c)/2``, its solid angle over 4π.  A cylinder of radius r and thickness h has its edge
  valley between the rim directions tan a = 2r/h and π − a:
  ``P(edge) = cos a = (h/2)/√(r² + h²/4)``, 1/3 at h/(2r) = 1/(2√2) (Yong & Mahadevan's dropped coin).

:meth:`Drop.simulate` draws the same toss at random (the independent re-simulation of an exact design).
"""

from __future__ import annotations

import math

import numpy as np

from coinwall.forward.display import safe_repr

from .family import outcome_sets, planar_valleys, revolution_valleys

__all__ = ["Drop", "valley_hits"]


def valley_hits(index, sets) -> dict:
    """``name -> bool array``: which draws (valley ``index``, −1 undecided) fall on each outcome of ``sets``."""
    index = np.asarray(index)
    return {name: np.isin(index, np.array(members, dtype=np.int64)) for name, members in sets.items()}


class Drop:
    """The drop toss (module docstring): exact odds, and the same toss drawn at random.

    It has no parameters: ``odds(kind, body, names)`` is exact, ``simulate`` draws the toss (one uniform number
    per toss), for the independent re-simulation of a design.

    Examples
    --------
    >>> from coinwall.forward.wall import Wall
    >>> wall = Wall.from_expression("abs(cos(t)) + h*abs(sin(t))", {"h": 0.5})
    >>> p = Drop().odds("planar", wall, ["edge"])["edge"]
    >>> abs(p - 2 / math.pi * math.atan(0.5)) < 1e-12
    True
    """

    name = "drop"
    exact = True
    dimensions = 1  # random numbers per toss

    def valleys(self, kind, body):
        return planar_valleys(body) if kind == "planar" else revolution_valleys(body)

    def valley_odds(self, kind, body) -> tuple:
        """``(valleys, probability of each)`` of ``body`` (planar: a Wall; else a Revolution)."""
        valleys = self.valleys(kind, body)
        if kind == "planar":
            return valleys, (valleys.right - valleys.left) / (2.0 * math.pi)
        return valleys, 0.5 * (np.cos(valleys.left) - np.cos(valleys.right))

    def odds(self, kind, body, names) -> dict:
        """``name -> probability`` of each outcome name (:func:`.family.outcome_sets`); raises InvalidArgument for
        an unknown name, InvalidWall for a body without two valleys."""
        valleys, p = self.valley_odds(kind, body)
        sets = outcome_sets(valleys, names, kind)
        return {name: float(np.sum(p[list(members)])) for name, members in sets.items()}

    def draw(self, rng, n: int) -> np.ndarray:
        """``(n, 1)`` uniform numbers in [0, 1): the orientations of ``n`` random drops."""
        return rng.random((n, 1))

    def simulate(self, kind, body, draws, names, b0=0.0) -> tuple:
        """The toss at random: ``draws`` (n, 1) uniform numbers in [0, 1) give the orientations.  Returns
        ``(hits, undecided)``: ``name -> bool array`` and an all-False array (every drop lands)."""
        u = np.asarray(draws, dtype=float)[:, 0]
        valleys = self.valleys(kind, body)
        if kind == "planar":
            theta = 2.0 * math.pi * u
            index = np.searchsorted(valleys.left, theta % (2 * math.pi), side="right") - 1
            index = np.where(index < 0, len(valleys) - 1, index)
        else:
            theta = np.arccos(1.0 - 2.0 * u)
            index = np.minimum(np.searchsorted(valleys.right, theta, side="right"), len(valleys) - 1)
        return valley_hits(index, outcome_sets(valleys, names, kind)), np.zeros(u.size, dtype=bool)

    def to_dict(self) -> dict:
        return {"model": self.name}

    @safe_repr
    def __repr__(self):
        return "Drop()"
