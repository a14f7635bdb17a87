"""The grid of a scan: axes parsed from ``LIST | START:STOP:N[log]``, the cells, and each cell's own seed.

A cell's seed depends only on the scan's seed and the cell's *coordinate values* (not on its index,
the grid's shape, the number of workers or the order of completion): the same (ε, H) gets the same
random orbits in any scan with the same seed, so a finer grid reproduces the coarse grid's cells.
"""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass

import numpy as np

from coinwall.forward.errors import InvalidArgument
from coinwall.forward.validation import check_count

__all__ = ["AXIS_POINTS_MAX", "Axis", "cell_seed", "cells", "parse_axis"]

AXIS_POINTS_MAX = 10_000  # points on one axis; a 10⁴ × 10⁴ grid would be 10⁸ cells, far past any cluster run
_RANGE = re.compile(r"^\s*([^:]+):([^:]+):([^:]+?)\s*(log)?\s*$")


@dataclass(frozen=True)
class Axis:
    """One axis of the grid.

    Attributes
    ----------
    name : str
        The coordinate name (a wall parameter, or ``"H"``).
    values : tuple of float
        The coordinate values, in the order given.
    units : str
        Units of the values (``"kappa"`` for H, ``"1"`` for a dimensionless parameter).
    text : str
        What the user wrote (kept in the store's attributes).

    Examples
    --------
    >>> from coinwall.cases.scan import parse_axis
    >>> parse_axis("H", "2:8:4", units="kappa")
    Axis(name='H', values=(2.0, 4.0, 6.0, 8.0), units='kappa', text='2:8:4')
    """

    name: str
    values: tuple
    units: str
    text: str

    def __len__(self) -> int:
        return len(self.values)


def _number(name, text):
    try:
        value = float(text)
    except ValueError:
        raise InvalidArgument(f"`{name}` must be a list of numbers or START:STOP:N[log], got {text!r}") from None
    if not math.isfinite(value):
        raise InvalidArgument(f"`{name}` values must be finite, got {text!r}")
    return value


def parse_axis(name: str, text: str, units: str = "1") -> Axis:
    """An :class:`Axis` from ``"a,b,c"`` or ``"START:STOP:N"`` (linear, both ends included) or
    ``"START:STOP:Nlog"`` (geometric; both ends > 0).

    Parameters
    ----------
    name : str
        The coordinate name.
    text : str
        The values, as above.
    units : str
        Their units.

    Returns
    -------
    Axis

    Raises
    ------
    InvalidArgument
        Not numbers, N not a whole number in [1, AXIS_POINTS_MAX], a log range with an end ≤ 0, or a
        value given twice (two cells with the same coordinates would share a seed and a store row).

    Examples
    --------
    >>> from coinwall.cases.scan import parse_axis
    >>> [round(value, 6) for value in parse_axis("eps", "0.5:30:3log").values]
    [0.5, 3.872983, 30.0]
    >>> parse_axis("eps", "1,2,1")
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidArgument: ...
    """
    if not isinstance(text, str) or not text.strip():
        raise InvalidArgument(f"`{name}` must be a list of numbers or START:STOP:N[log], got {text!r}")
    match = _RANGE.match(text)
    if match:
        start, stop = _number(name, match.group(1)), _number(name, match.group(2))
        try:
            points = int(match.group(3))
        except ValueError:
            raise InvalidArgument(f"`{name}`: N in START:STOP:N must be a whole number, got {match.group(3)!r}") \
                from None
        if not 1 <= points <= AXIS_POINTS_MAX:
            raise InvalidArgument(f"`{name}`: N in START:STOP:N must be from 1 to {AXIS_POINTS_MAX}, got {points}")
        if match.group(4):
            if not (start > 0 and stop > 0):
                raise InvalidArgument(f"`{name}`: a log range needs START and STOP > 0, got {text!r}")
            values = np.geomspace(start, stop, points)
        else:
            values = np.linspace(start, stop, points)
    else:
        values = np.array([_number(name, part) for part in text.split(",") if part.strip()])
        if values.size == 0:
            raise InvalidArgument(f"`{name}` must be a list of numbers or START:STOP:N[log], got {text!r}")
        if values.size > AXIS_POINTS_MAX:
            raise InvalidArgument(f"`{name}` has {values.size} values, more than {AXIS_POINTS_MAX}")
    if np.unique(values).size != values.size:
        raise InvalidArgument(f"`{name}` has a value twice in {text!r}; every cell needs its own coordinates")
    return Axis(name=name, values=tuple(float(v) for v in values), units=units, text=text.strip())


def cells(axes):
    """Every cell of the grid as ``(index tuple, coordinate tuple)``, in C order."""
    for index in itertools.product(*(range(len(a)) for a in axes)):
        yield index, tuple(a.values[i] for a, i in zip(axes, index))


def cell_seed(seed: int, coordinates) -> int:
    """The seed of the cell at ``coordinates`` (floats) in a scan with ``seed``: 63 bits from
    ``numpy.random.SeedSequence(seed, spawn_key=<the float64 bit patterns of the coordinates>)``.

    The bit patterns make it exact (no rounding of a printed value) and independent of the grid.

    Parameters
    ----------
    seed : int
        The scan's seed.
    coordinates : sequence of float
        The cell's coordinates, in axis order.

    Returns
    -------
    int
        A seed in [0, 2⁶³).

    Examples
    --------
    The same cell gets the same seed in any scan with the same seed, whatever else its grid holds:

    >>> from coinwall.cases.scan import cell_seed
    >>> cell_seed(0, (1.0, 3.0)) == cell_seed(0, (1.0, 3.0)), cell_seed(0, (1.0, 3.0)) == cell_seed(1, (1.0, 3.0))
    (True, False)
    """
    seed = check_count("seed", seed, minimum=0)
    key = tuple(int(np.float64(c).view(np.uint64)) for c in coordinates)
    state = np.random.SeedSequence(seed, spawn_key=key).generate_state(2, np.uint32)
    return int(state[0]) << 31 | int(state[1]) >> 1
