"""The coinwall body JSON: the reader, and the field names the writer shares with it.

``coinwall solve -o body.json`` (:mod:`coinwall.inverse.export.jsonfile`) writes the body's summary
(:meth:`Body.to_dict`) plus the outline nodes (``OUTLINE_KEY``) and the two Bézier control points of
every segment (``CONTROLS_KEY``), in units of κ with the centre of mass at the origin.  Read back, nodes
and controls give the exact outline again.  Any other JSON object with an ``"outline"`` or ``"points"``
list of ``[x, y]`` is read as points.
"""

from __future__ import annotations

import json
from typing import NamedTuple

import numpy as np

from ..errors import InvalidOutline

__all__ = ["OUTLINE_KEY", "POINTS_KEY", "CONTROLS_KEY", "UNITS_KEY", "UNITS_VALUE", "B0_KEY", "REGIME_KEY",
           "BodyJson", "read_body_json"]

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


def read_body_json(path: str) -> BodyJson:
    """Read a body JSON file.

    Raises
    ------
    InvalidOutline
        No ``outline`` or ``points`` list.
    OSError, ValueError, TypeError
        Unreadable file, invalid JSON or numbers (the caller names the file).
    """
    with open(path, encoding="utf-8") as fh:
        doc = json.load(fh)
    key = OUTLINE_KEY if isinstance(doc, dict) and OUTLINE_KEY in doc else POINTS_KEY
    if not isinstance(doc, dict) or key not in doc:
        raise InvalidOutline(f"body file {path!r}: no {OUTLINE_KEY!r} or {POINTS_KEY!r} list of [x, y] points")
    points = np.asarray(doc[key], dtype=float)
    controls = doc.get(CONTROLS_KEY)
    recorded = {"com": (0.0, 0.0)} if controls is not None else {}
    if controls is not None:
        controls = np.asarray(controls, dtype=float)
        valid = controls.shape == (len(points), 2, 2) and np.all(np.isfinite(controls)) \
            and np.all(np.isfinite(points))
        controls = controls if valid else None
    return BodyJson(points, controls, recorded, "JSON points")
