"""The coinwall body JSON: the reader, and the field names the writer shares with it.

``coinwall solve -o body.json`` (:mod:`coinwall.inverse.export.jsonfile`) writes the body's summary
(:meth:`Body.to_dict`) plus the outline nodes (``OUTLINE_KEY``) and the two Bézier control points of
every segment (``CONTROLS_KEY``), in units of κ with the centre of mass at the origin.  Read back, nodes
and controls give the exact outline again.  Any other JSON object with an ``"outline"`` or ``"points"``
list of ``[x, y]`` is read as points.
"""

from __future__ import annotations

import math
import reprlib
from typing import NamedTuple

import numpy as np

from ..errors import InvalidOutline

__all__ = [
    "B0_KEY",
    "CONTROLS_KEY",
    "OUTLINE_KEY",
    "POINTS_KEY",
    "REGIME_KEY",
    "UNITS_KEY",
    "UNITS_VALUE",
    "BodyJson",
    "read_body_json",
]

#: outline nodes ``[[x, y], …]``
OUTLINE_KEY = "outline"
#: a plain list of points ``[[x, y], …]`` (files not written by coinwall)
POINTS_KEY = "points"
#: Bézier control points ``[[[x1, y1], [x2, y2]], …]``, one pair per segment (segment i from node i)
CONTROLS_KEY = "controls"
#: the unit of every length in the file, and the one value coinwall writes there
UNITS_KEY = "units"
UNITS_VALUE = "radius of gyration (kappa)"
#: the offset and the regime of the solved body (``coinwall export`` reads them back)
B0_KEY = "b0"
#: the scale of a points file: κ in the units of its coordinates (optional; coinwall's bodies are in units of κ)
KAPPA_KEY = "kappa"
REGIME_KEY = "regime"


class BodyJson(NamedTuple):
    """What a body JSON holds.

    Attributes
    ----------
    points : ndarray
        The outline nodes or points, (n, 2) for a valid file.
    controls : ndarray or None
        The Bézier control points, (n, 2, 2) and finite, when the file has valid ones.
    recorded : dict
        ``{"com": (0, 0)}`` for a coinwall body (it has ``controls``): the origin is its centre of mass.
    what : str
        A note saying what was read.
    """

    points: np.ndarray
    controls: np.ndarray | None
    recorded: dict
    what: str


def _pairs(value, path, key, shape):
    """``value`` as a finite float array of ``shape`` (None: any count), refusing strings, booleans, NaN and
    ragged lists with a message naming ``key`` and the index."""
    from .inputfile import json_number

    def check(item, where, depth):
        if depth == len(shape):
            json_number(item, where, f"body file {path!r}: ", what="coordinates")
            return
        size = shape[depth]
        if not isinstance(item, list) or (size is not None and len(item) != size):
            wanted = f"a list of {size}" if size is not None else "a list"
            raise InvalidOutline(f"body file {path!r}: {where} must be {wanted}, got {reprlib.repr(item)}")
        for index, inner in enumerate(item):
            check(inner, f"{where}[{index}]", depth + 1)

    check(value, f"`{key}`", 0)
    return np.asarray(value, dtype=float).reshape((-1,) + tuple(s for s in shape[1:]))


def read_body_json(path: str) -> BodyJson:
    """Read a body JSON file (through :mod:`.inputfile`: a regular file of at most 64 MiB, nested at most
    :data:`~.inputfile.MAX_NESTING` deep).

    Raises
    ------
    InvalidOutline
        No ``outline`` or ``points`` list; a point that is not two finite numbers (the message names its
        index); ``controls`` that do not match the outline; more than :data:`~.geometry.MAX_POINTS` points.
    """
    from .geometry import MAX_POINTS
    from .inputfile import read_json

    doc = read_json(path, what="body file", error=InvalidOutline)
    key = OUTLINE_KEY if isinstance(doc, dict) and OUTLINE_KEY in doc else POINTS_KEY
    if not isinstance(doc, dict) or key not in doc or not isinstance(doc[key], list):
        raise InvalidOutline(f"body file {path!r}: no {OUTLINE_KEY!r} or {POINTS_KEY!r} list of [x, y] points")
    if len(doc[key]) > MAX_POINTS:
        raise InvalidOutline(f"body file {path!r}: `{key}` holds {len(doc[key])} points; at most {MAX_POINTS} are read")
    points = _pairs(doc[key], path, key, (None, 2))
    controls = doc.get(CONTROLS_KEY)
    recorded = {"com": (0.0, 0.0)} if controls is not None else {}
    if controls is not None:
        # a coinwall body: the controls must be those of this outline, else the file was damaged
        controls = _pairs(controls, path, CONTROLS_KEY, (len(points), 2, 2))
    if KAPPA_KEY in doc:
        # the scale, κ in the file's units, as SVG and DXF drawings record it: a wrong one is refused, never used
        kappa = doc[KAPPA_KEY]
        if isinstance(kappa, bool) or not isinstance(kappa, (int, float)) or not 0 < kappa < math.inf:
            raise InvalidOutline(f"body file {path!r} records \"{KAPPA_KEY}\": {reprlib.repr(kappa)}; it must be a "
                                 "positive finite number (pass --kappa to override)")
        recorded["kappa"] = float(kappa)
    return BodyJson(points, controls, recorded, "JSON points")
