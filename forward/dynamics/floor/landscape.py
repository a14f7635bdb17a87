"""The floor's wall as a potential landscape: its valleys, their barriers, and the names of the rest states.

With gravity the floor's wall is a potential landscape: ``λ = E/g = η + (θ̇² + η̇²)/(2g) ≥ b0 + b(θ)``.  The
*valleys* are the intervals between consecutive local maxima of b; a body whose level ``λ − b0`` is below the
lower of its valley's two maxima (the valley's *barrier*, at least the lowest saddle of all) can never leave
it: the outcome is decided.  With friction the horizontal motion's energy ``½ ξ̇²`` counts too (friction can
turn it into rotation); the total never increases, so the rule stays exact.

Each valley holds one rest state: the body comes to rest at its minimum, on a flat face of the body where b
has a kink there, else on a smooth part.  The names are those a user would give: for a *coin* (a body with a
centre of symmetry, ``b(θ + π) = b(θ)``, whose two deepest valleys are a pair of opposite faces) ``heads``
(the minimum with ``sin θ < 0``, the convention of :func:`.correlation.heads`) and ``tails``, and ``edge``
for any other valley; otherwise each rest state by the angle of the floor's normal in the body frame,
``face 90°`` (a flat face) or ``rest 94.8°`` (a smooth part).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...angles import TWO_PI
from ...display import safe_repr
from ...errors import InvalidWall
from ...wall import Wall

__all__ = ["Landscape", "landscape"]


@dataclass(frozen=True, repr=False)
class Landscape:
    """The valleys of the floor's wall b(θ) (b0 not included; the valleys do not depend on it).

    Attributes
    ----------
    minima : ndarray (k,)
        The angle of each valley's minimum (its rest state), in [0, 2π), in the order of the valleys.
    maxima : ndarray (k,)
        The left maximum of each valley (valley i spans ``[maxima[i], maxima[i+1])``, cyclically).
    barriers : ndarray (k,)
        The lower of each valley's two maxima (b's value; ``inf`` for a wall with a single valley).
    names : list of str
        ``heads``/``tails``/``edge`` for a coin, else ``face θ°`` or ``rest θ°`` by the angle of the minimum
        (module docstring).
    table : ndarray (k, 3)
        ``[left maximum, barrier, minimum]`` per valley, sorted by the left maximum: the kernel's input.
    coin : bool
        Whether the body is a coin (the names are heads and tails).
    faces : ndarray of bool (k,)
        Whether each rest state is a flat face (b has a kink at the minimum).
    """

    minima: np.ndarray
    maxima: np.ndarray
    barriers: np.ndarray
    names: list
    table: np.ndarray
    coin: bool = False
    faces: np.ndarray = None

    def valley(self, theta):
        """Index of the valley holding each angle (the kernel's rule).

        Parameters
        ----------
        theta : float or array_like
            Angles (radians, any range).

        Returns
        -------
        ndarray of int
            Valley indices into :attr:`names`.

        Examples
        --------
        >>> from coinwall.forward import Wall
        >>> coin = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})
        >>> land = landscape(coin)
        >>> [land.names[k] for k in land.valley([1.0, 4.0])]
        ['tails', 'heads']
        """
        x = np.mod(np.asarray(theta, dtype=float), TWO_PI)
        if self.maxima.size <= 1:
            return np.zeros(x.shape, dtype=np.int64)
        k = np.searchsorted(self.maxima, x, side="right") - 1
        return np.where(k < 0, self.maxima.size - 1, k)

    @safe_repr
    def __repr__(self):
        parts = [f"{n} (min θ={m:.4g}, barrier {b:.4g})" for n, m, b in zip(self.names, self.minima, self.barriers)]
        return f"Landscape({'; '.join(parts)})"


def _is_face(wall: Wall, angle: float) -> bool:
    """Whether b has a kink at ``angle`` (a flat face of the body rests there)."""
    return any(abs(math.remainder(k.angle - angle, TWO_PI)) < 1e-7 for k in wall.kinks)


def _names(wall: Wall, mins: np.ndarray, values: np.ndarray, faces: np.ndarray) -> tuple:
    """The names of the rest states and whether the body is a coin (module docstring)."""
    theta = np.arange(1024) * (TWO_PI / 1024)
    k = mins.size
    symmetric = bool(np.max(np.abs(wall(theta + math.pi) - wall(theta))) <= 1e-9 * max(1.0, wall.scale))
    order = np.argsort(values, kind="stable")
    coin = symmetric and k in (2, 4)
    if coin and k == 4:  # the deepest pair must be deeper than the other (a square is no coin)
        coin = values[order[2]] - values[order[1]] > 1e-9 * max(1.0, wall.scale)
    if coin:
        a, b = order[0], order[1]
        coin = abs(abs(math.remainder(mins[a] - mins[b], TWO_PI)) - math.pi) < 1e-6
    if coin:
        side = [math.sin(m) if abs(math.sin(m)) > 1e-9 else math.cos(m) for m in mins]
        names = ["edge"] * k
        names[a], names[b] = ("heads", "tails") if side[a] < 0 else ("tails", "heads")
        return names, True
    names = []
    for m, face in zip(mins, faces):
        degrees = math.degrees(m) % 360.0
        names.append(f"{'face' if face else 'rest'} {degrees:.4g}°")
    for i, name in enumerate(names):  # more digits where two rest states round to one name
        if names.count(name) > 1:
            names[i] = f"{name[:-1].split()[0]} {math.degrees(mins[i]) % 360.0:.10g}°"
    return names, False


def landscape(wall: Wall, points: int = 16384) -> Landscape:
    """The valleys of ``wall``: local maxima and minima of b, refined on the exact wall, and their names.

    Extrema are found on a grid of ``points`` angles (strict local extrema of the sampled b, cyclic) and
    refined by a bounded scalar search on b within one grid step (b is continuous, kinks included; the value
    at an extremum is accurate to rounding even where the angle is known only to ~1e-8).  Extrema closer in
    b than 1e-12·scale to both neighbours are ignored (flat or rounding wiggles).

    Parameters
    ----------
    wall : Wall
        The floor's wall b(θ).
    points : int
        Grid of the first search.

    Returns
    -------
    Landscape

    Raises
    ------
    InvalidWall
        If b is not finite everywhere on the grid.

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> landscape(Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0})).names
    ['tails', 'heads']
    >>> landscape(Wall.from_expression("1 + 0.06*cos(2*t) + 0.04*sin(3*t) + 0.05*cos(t)")).names
    ['rest 94.8°', 'rest 225°']
    """
    from scipy.optimize import minimize_scalar

    theta = np.arange(points) * (TWO_PI / points)
    b = wall(theta)
    if not np.all(np.isfinite(b)):
        raise InvalidWall(f"wall {wall.description!r} is not finite everywhere on [0, 2π)")
    h = TWO_PI / points
    prev, nxt = np.roll(b, 1), np.roll(b, -1)
    flat = 1e-12 * wall.scale
    is_max = (b > prev) & (b >= nxt) & ((b - np.minimum(prev, nxt)) > 0)
    is_min = (b < prev) & (b <= nxt)

    def refine(i, sign):
        res = minimize_scalar(lambda x: sign * float(wall(np.array([x]))[0]), bounds=(theta[i] - h, theta[i] + h),
                              method="bounded", options={"xatol": 1e-12})
        x = float(res.x) % TWO_PI
        return x, float(wall(np.array([x]))[0])

    maxima = [refine(i, -1.0) for i in np.flatnonzero(is_max)]
    minima = [refine(i, 1.0) for i in np.flatnonzero(is_min)]
    # drop pairs that are rounding wiggles: a maximum less than `flat` above the minima next to it
    if maxima and minima and max(v for _, v in maxima) - min(v for _, v in minima) <= flat:
        maxima, minima = [], []
    if len(maxima) <= 1:
        lo = min(minima, key=lambda m: m[1]) if minima else (float(theta[int(np.argmin(b))]), float(b.min()))
        left = maxima[0][0] if maxima else 0.0
        table = np.array([[left, math.inf, lo[0]]])
        face = np.array([_is_face(wall, lo[0])])
        names, _ = _names(wall, np.array([lo[0]]), np.array([lo[1]]), face)
        return Landscape(np.array([lo[0]]), np.array([left]), np.array([math.inf]), names, table, False, face)
    maxima.sort()
    mx = np.array([a for a, _ in maxima])
    mv = np.array([v for _, v in maxima])
    k = mx.size
    mins = np.empty(k)
    values = np.empty(k)
    barriers = np.empty(k)
    for i in range(k):
        left, right = mx[i], mx[(i + 1) % k] + (TWO_PI if i == k - 1 else 0.0)
        inside = [(v, a) for a, v in minima if left < a < right or left < a + TWO_PI < right]
        if inside:
            values[i], mins[i] = min(inside)
        else:  # no sampled minimum between two maxima (cannot happen for strict extrema): the midpoint
            mins[i] = (0.5 * (left + right)) % TWO_PI
            values[i] = float(wall(np.array([mins[i]]))[0])
        barriers[i] = min(mv[i], mv[(i + 1) % k])
    faces = np.array([_is_face(wall, m) for m in mins])
    names, coin = _names(wall, mins, values, faces)
    table = np.column_stack([mx, barriers, mins])
    return Landscape(mins, mx, barriers, names, np.ascontiguousarray(table), coin, faces)
