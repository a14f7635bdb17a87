"""Families of bodies with free parameters, their rest faces (valleys), and the outcomes a toss can have.

A *family* is a body with named parameters, some of them free within a range:

* ``planar``: a wall expression ``b(θ)`` (units of κ, about the centre of mass; ``b0 + b`` is the support
  function, as everywhere in coinwall) with ``--param NAME=LO:HI`` for a free parameter;
* ``cylinder``: a body of revolution, a cylinder of ``radius`` and ``thickness`` with its edges rounded with
  radius ``rounding`` (:func:`coinwall.forward.revolution.coin`); lengths in any one unit.

Rest faces
----------
A body lying on a floor rests where the height of its centre of mass above the floor, the support function
``b(θ)`` of the downward direction θ (body frame), has a local minimum; tipped to any θ it rolls down ``b``
(gravity lowers the centre) into the *valley* that holds θ: the interval between the two local maxima of
``b`` around it.  For a polygon the valley of a face is the angle the face subtends at the centre of mass
(its maxima are the vertex directions).  :func:`planar_valleys` finds the maxima as sign changes of b'
(brentq to 1e-15 rad on b', so a smooth maximum and a corner are found alike); a valley narrower than
2π/16384 is not seen.  For a body of revolution θ ∈ [0, π] is the tilt of the axis from the upward vertical
and ``b`` is :meth:`~coinwall.forward.revolution.Revolution.support`.

Outcomes
--------
``heads`` is the valley that holds θ = 3π/2 (planar: the body direction −y, the convention of the toss,
:func:`coinwall.forward.dynamics.floor.field.landscape`) or θ = 0 (revolution: resting on its bottom face,
heads up); ``tails`` the valley that holds π/2 (planar) or π (revolution); ``edge`` every other valley
together.  ``face@DEG`` is the valley that holds the body direction DEG (degrees), for any body.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument, InvalidParameter, InvalidWall

__all__ = ["CYLINDER_PARAMETERS", "Family", "Valleys", "outcome_names", "outcome_sets", "planar_valleys",
           "revolution_valleys"]

#: the parameters of the cylinder family and their defaults (``None``: must be given)
CYLINDER_PARAMETERS = {"radius": 1.0, "thickness": None, "rounding": 0.0}
_FACE = re.compile(r"face@([+-]?(?:\d+\.?\d*|\.\d+))\Z")
_GRID = 16384  # angles at which b' is sampled for the valleys of a planar wall


@dataclass(frozen=True, repr=False)
class Family:
    """A body with named parameters, ``free`` ones within a range.

    Parameters
    ----------
    kind : {"planar", "cylinder"}
    expression : str or None
        The wall expression of a planar family (units of κ); ``None`` for a cylinder.
    free : dict
        ``name -> (lo, hi)``, in order: the parameters a design solves for (``lo < hi``).
    fixed : dict
        ``name -> value``: the other parameters.
    b0 : float
        Offset of a planar wall (``b0 + b`` is the support function).

    Raises
    ------
    InvalidParameter
        A range that is not finite ``LO < HI``, a parameter both free and fixed, an unknown or missing one.
    InvalidArgument
        An unknown kind, a planar family without an expression, ``b0`` for a cylinder.

    Examples
    --------
    >>> fam = Family("planar", "abs(cos(t)) + h*abs(sin(t))", {"h": (0.05, 3.0)})
    >>> fam.names
    ('h',)
    >>> float(fam.body([0.5])(np.array([0.0]))[0])
    1.0
    """

    kind: str
    expression: str | None
    free: dict
    fixed: dict = field(default_factory=dict)
    b0: float = 0.0

    def __post_init__(self):
        if self.kind not in ("planar", "cylinder"):
            raise InvalidArgument(f"`kind` must be 'planar' or 'cylinder', got {self.kind!r}")
        free = {}
        for name, bounds in dict(self.free).items():
            try:
                lo, hi = (float(b) for b in bounds)
            except (TypeError, ValueError):
                raise InvalidParameter(f"free parameter {name!r} needs a range (LO, HI), got {bounds!r}") from None
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise InvalidParameter(f"free parameter {name!r} needs finite LO < HI, got {lo:g}:{hi:g}")
            free[name] = (lo, hi)
        fixed = {name: float(value) for name, value in dict(self.fixed).items()}
        both = set(free) & set(fixed)
        if both:
            raise InvalidParameter(f"parameter {sorted(both)[0]!r} is given both free and fixed")
        if not math.isfinite(float(self.b0)):
            raise InvalidArgument(f"`b0` must be finite, got {self.b0!r}")
        if self.kind == "cylinder":
            unknown = (set(free) | set(fixed)) - set(CYLINDER_PARAMETERS)
            if unknown:
                raise InvalidParameter(f"a cylinder has the parameters {', '.join(CYLINDER_PARAMETERS)}; "
                                       f"{sorted(unknown)[0]!r} is not one of them")
            for name, default in CYLINDER_PARAMETERS.items():
                if name not in free and name not in fixed:
                    if default is None:
                        raise InvalidParameter(f"a cylinder needs its {name}: give --param {name}=VALUE or "
                                               f"{name}=LO:HI")
                    fixed[name] = default
            if self.b0 != 0.0:
                raise InvalidArgument("`b0` applies to a planar wall, not to a cylinder")
        elif not isinstance(self.expression, str):
            raise InvalidArgument("a planar family needs a wall expression")
        object.__setattr__(self, "free", free)
        object.__setattr__(self, "fixed", fixed)
        object.__setattr__(self, "b0", float(self.b0))
        if self.kind == "planar":  # every name is used by the expression, none is missing: checked once, here
            self.body([0.5 * (lo + hi) for lo, hi in free.values()])

    @property
    def names(self) -> tuple:
        """The free parameters, in order."""
        return tuple(self.free)

    @property
    def bounds(self) -> np.ndarray:
        """``(k, 2)``: the range of each free parameter."""
        return np.array(list(self.free.values()), dtype=float).reshape(-1, 2)

    def values(self, x) -> dict:
        """Every parameter's value for the free values ``x`` (in the order of :attr:`names`)."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        if x.shape != (len(self.free),):
            raise InvalidArgument(f"expected {len(self.free)} free values ({', '.join(self.free)}), got {x.tolist()}")
        return {**self.fixed, **dict(zip(self.free, (float(v) for v in x)))}

    def body(self, x):
        """The body at the free values ``x``: a :class:`~coinwall.forward.Wall` (planar, without b0) or a
        :class:`~coinwall.forward.revolution.Revolution` (cylinder)."""
        values = self.values(x)
        if self.kind == "planar":
            from coinwall.forward.wall import Wall

            return Wall.from_expression(self.expression, values)
        from coinwall.forward.revolution import coin

        return coin(values["radius"], values["thickness"], values["rounding"])

    def describe(self) -> str:
        """One line: the family and its parameters."""
        fixed = ", ".join(f"{k}={v:g}" for k, v in self.fixed.items())
        free = ", ".join(f"{k}={lo:g}:{hi:g}" for k, (lo, hi) in self.free.items())
        what = self.expression if self.kind == "planar" else "cylinder"
        return f"{what} [{', '.join(p for p in (free, fixed) if p)}]" + (f", b0={self.b0:g}" if self.b0 else "")

    def to_dict(self) -> dict:
        return {"kind": self.kind, "expression": self.expression, "free": {k: list(v) for k, v in self.free.items()},
                "fixed": dict(self.fixed), "b0": self.b0}

    @safe_repr
    def __repr__(self):
        return f"Family({self.describe()})"


@dataclass(frozen=True, repr=False)
class Valleys:
    """The rest faces of a body: valley ``i`` spans ``[left[i], right[i])`` and has its minimum at
    ``minima[i]`` (radians).  Planar valleys are cyclic (``right[i] = left[i + 1]``, the last one wraps past
    2π); a body of revolution's cover ``[0, π]``.

    Parameters
    ----------
    left, right, minima : ndarray (k,)
    period : float or None
        2π for planar valleys, None for the tilt of a body of revolution.

    Examples
    --------
    >>> v = Valleys(np.array([0.5, 2.0]), np.array([2.0, 0.5 + 2 * math.pi]), np.array([1.0, 4.0]), 2 * math.pi)
    >>> v.index(1.0), v.index(0.1)
    (0, 1)
    """

    left: np.ndarray
    right: np.ndarray
    minima: np.ndarray
    period: float | None

    def __len__(self) -> int:
        return int(self.left.size)

    def index(self, angle: float) -> int:
        """The valley that holds ``angle``."""
        if self.period is None:
            a = min(max(float(angle), 0.0), math.pi)
            return int(min(np.searchsorted(self.right, a, side="right"), self.left.size - 1))
        a = float(angle) % self.period
        k = int(np.searchsorted(self.left, a, side="right")) - 1
        return k % self.left.size

    @safe_repr
    def __repr__(self):
        parts = ", ".join(f"[{a:.6g}, {b:.6g})" for a, b in zip(self.left, self.right))
        return f"Valleys({parts})"


def planar_valleys(wall, points: int = _GRID) -> Valleys:
    """The valleys of a planar wall b(θ) (module docstring), maxima located to 1e-15 rad.

    Parameters
    ----------
    wall : Wall
        The support function about the centre of mass (b0 does not move the valleys).
    points : int
        Angles at which b' is sampled for sign changes (a valley narrower than 2π/points is not seen).

    Returns
    -------
    Valleys
        Cyclic, starting at the first maximum in [0, 2π).

    Raises
    ------
    InvalidWall
        The wall is not finite, or has no maximum (b constant: a disc rests at any angle).

    Examples
    --------
    >>> from coinwall.forward.wall import Wall
    >>> v = planar_valleys(Wall.from_expression("abs(cos(t)) + h*abs(sin(t))", {"h": 1 / 3 ** 0.5}))
    >>> len(v), round(float(v.right[0] - v.left[0]) / (2 * math.pi), 12)
    (4, 0.333333333333)
    """
    from scipy.optimize import brentq

    theta = np.arange(points) * (TWO_PI / points)
    b, d1, _ = wall.derivatives(theta)
    if not (np.all(np.isfinite(b)) and np.all(np.isfinite(d1))):
        raise InvalidWall(f"wall {wall.description!r} is not finite everywhere on [0, 2π)")
    flat = 1e-12 * max(1.0, float(np.max(np.abs(b))))
    if float(b.max() - b.min()) <= flat:
        raise InvalidWall(f"wall {wall.description!r} is constant (a disc): a body resting on it can rest at any "
                          "angle, so a toss has no outcome")

    def slope(x):
        return float(wall.derivatives(np.array([x]))[1][0])

    nxt = np.roll(d1, -1)
    maxima = []
    for i in np.flatnonzero((d1 > 0) & (nxt <= 0)):  # b' from + to −: a maximum (smooth or a corner) in the cell
        lo, hi = theta[i], theta[i] + TWO_PI / points
        maxima.append(brentq(slope, lo, hi, xtol=1e-15, rtol=8.9e-16) % TWO_PI if slope(hi) < 0 else hi % TWO_PI)
    maxima = np.sort(np.array(maxima))
    minima = theta[(d1 < 0) & (nxt >= 0)] + TWO_PI / points  # the face directions: to the grid step (names only)
    # a maximum less than `flat` above a minimum beside it is a rounding wiggle (a dimple that holds nothing)
    if minima.size:
        keep = []
        for a, v in zip(maxima, wall(maxima) if maxima.size else []):
            before = minima[minima < a]
            after = minima[minima > a]
            beside = [before[-1] if before.size else minima[-1], after[0] if after.size else minima[0]]
            if v - float(np.min(wall(np.array(beside)))) > flat:
                keep.append(a)
        maxima = np.array(keep)
    if maxima.size == 0:
        raise InvalidWall(f"wall {wall.description!r} has one valley only: the body rests on one face whatever "
                          "its orientation")
    left = maxima
    right = np.roll(maxima, -1)
    right[-1] += TWO_PI
    mins = np.empty(left.size)
    for i, (a, c) in enumerate(zip(left, right)):
        inside = minima[((minima > a) & (minima < c)) | ((minima + TWO_PI > a) & (minima + TWO_PI < c))]
        if inside.size:
            mins[i] = inside[np.argmin(wall(inside))]
        else:
            mins[i] = (0.5 * (a + c)) % TWO_PI
    return Valleys(left, right, mins % TWO_PI, TWO_PI)


def revolution_valleys(body) -> Valleys:
    """The valleys of a body of revolution over the tilt θ ∈ [0, π] (maxima of its support ``h``).

    Parameters
    ----------
    body : Revolution

    Returns
    -------
    Valleys
        From tilt 0 (heads) to π (tails); the face angles (``minima``) to π/256 of each valley's width.

    Examples
    --------
    >>> from coinwall.forward.revolution import coin
    >>> v = revolution_valleys(coin(1.0, 1.0))
    >>> [round(float(a), 12) for a in v.right[:-1]]
    [1.107148717794, 2.034443935796]
    """
    from scipy.optimize import brentq

    theta = np.linspace(0.0, math.pi, _GRID + 1)
    _, d1 = body.support(theta)

    def slope(x):
        return float(body.support(np.array([x]))[1][0])

    cells = np.flatnonzero((d1[:-1] > 0) & (d1[1:] <= 0))
    maxima = np.array([brentq(slope, theta[i], theta[i + 1], xtol=1e-15, rtol=8.9e-16)
                       if slope(theta[i + 1]) < 0 else theta[i + 1] for i in cells])
    maxima = maxima[(maxima > 0) & (maxima < math.pi)]
    left = np.concatenate([[0.0], maxima])
    right = np.concatenate([maxima, [math.pi]])
    h = lambda x: body.support(np.asarray(x, dtype=float))[0]  # noqa: E731
    mins = np.array([float(np.linspace(a, c, 257)[np.argmin(h(np.linspace(a, c, 257)))]) for a, c in zip(left, right)])
    return Valleys(left, right, mins, None)


def outcome_sets(valleys: Valleys, names, kind: str) -> dict:
    """``name -> tuple of valley indices`` for each outcome name (module docstring).

    Parameters
    ----------
    valleys : Valleys
    names : iterable of str
        ``heads``, ``tails``, ``edge`` or ``face@DEG``.
    kind : {"planar", "cylinder"}

    Returns
    -------
    dict

    Raises
    ------
    InvalidArgument
        An unknown name, or heads/tails/edge for a body on which they are not different faces.

    Examples
    --------
    >>> from coinwall.forward.wall import Wall
    >>> v = planar_valleys(Wall.from_expression("abs(cos(t)) + h*abs(sin(t))", {"h": 0.5}))
    >>> outcome_sets(v, ["heads", "edge"], "planar")
    {'heads': (2,), 'edge': (1, 3)}
    """
    planar = kind == "planar"
    heads = valleys.index(1.5 * math.pi if planar else 0.0)
    tails = valleys.index(0.5 * math.pi if planar else math.pi)
    sets = {}
    for name in names:
        match = _FACE.fullmatch(name)
        if match:
            deg = float(match.group(1))
            if not planar and not 0.0 <= deg <= 180.0:
                raise InvalidArgument(f"outcome {name!r}: a tilt of a body of revolution is between 0 and 180 degrees")
            sets[name] = (valleys.index(math.radians(deg)),)
        elif name in ("heads", "tails", "edge"):
            if heads == tails:
                where = "3π/2 and π/2" if planar else "0 and π"
                raise InvalidArgument(f"outcome {name!r}: the directions {where} are in the same valley, so this body "
                                      "has no heads and tails; name its faces by angle (face@DEG)")
            sets[name] = {"heads": (heads,), "tails": (tails,),
                          "edge": tuple(k for k in range(len(valleys)) if k not in (heads, tails))}[name]
        else:
            raise InvalidArgument(f"unknown outcome {name!r}: use heads, tails, edge or face@DEG (the face whose "
                                  "valley holds the body direction DEG, in degrees)")
    return sets


def outcome_names(valleys: Valleys, kind: str) -> list:
    """The names a result reports by default: heads, tails and edge where they are different faces (edge only
    when there is one), else every face as ``face@DEG`` by the angle of its minimum.

    Parameters
    ----------
    valleys : Valleys
    kind : {"planar", "cylinder"}

    Returns
    -------
    list of str

    Examples
    --------
    >>> from coinwall.forward.wall import Wall
    >>> outcome_names(planar_valleys(Wall.from_expression("abs(cos(t)) + 0.5*abs(sin(t))")), "planar")
    ['heads', 'tails', 'edge']
    """
    try:
        sets = outcome_sets(valleys, ("heads", "tails", "edge"), kind)
    except InvalidArgument:
        return [f"face@{math.degrees(m):.6g}" for m in valleys.minima]
    return [name for name in ("heads", "tails", "edge") if sets[name]]
