"""The coinwall body JSON: the reader, and the field names the writer shares with it.

``coinwall solve -o body.json`` (:mod:`coinwall.inverse.export.jsonfile`) writes the body's summary
(:meth:`Body.to_dict`) plus the outline nodes (``OUTLINE_KEY``) and the two Bézier control points of
every segment (``CONTROLS_KEY``), in units of κ with the centre of mass at the origin.  Read back, nodes
and controls give the exact outline again.  Any other JSON object with an ``"outline"`` or ``"points"``
list of ``[x, y]`` is read as points.

A file with ``controls`` is verified before it is used (:func:`verify_controls`), because a wall, a
drawing or mass properties made from damaged controls look as good as the real ones: the control
polygon (every node followed by its segment's two control points) must be convex and turn once,
counter-clockwise.  By the variation-diminishing property of Bézier curves the outline is then simple,
convex and counter-clockwise, and at every node the end tangents of the two segments that meet there
turn left by less than π (a smooth node: by nothing).  A clockwise file is refused, not reversed: coinwall
writes counter-clockwise outlines, so it was edited.  The ``area`` and ``perimeter`` the file records
(when it does) must be those of its nodes and controls, to rounding.
"""

from __future__ import annotations

import math
import reprlib
from typing import NamedTuple

import numpy as np

from ..angles import TWO_PI
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
    "verify_controls",
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


#: a vertex of the control polygon may sit this far (relative to the outline's size) on the wrong side of the
#: line through its neighbours: rounding of coordinates ~1 written with 17 digits is ~1e-16; the solvers'
#: own outlines stay below 1e-12 (a cusp of Case II included)
_TURN_TOLERANCE = 1e-9
#: edges of the control polygon shorter than this (relative to the size) have no direction: a Bézier arm of
#: length zero at a corner of the body, two coincident control points
_SHORT_EDGE = 1e-12
#: recorded area and perimeter agree with the outline's to this (relative to the size², size)
_RECORD_TOLERANCE = 1e-9


def _where(vertex: int) -> str:
    """The place in the file of vertex ``vertex`` of the control polygon (node, control, control, node, …)."""
    segment, part = divmod(vertex, 3)
    return f"node {segment}" if part == 0 else f"control point {part} of segment {segment}"


def verify_controls(nodes: np.ndarray, controls: np.ndarray, recorded: dict | None = None) -> str | None:
    """What is wrong with a Bézier outline read from a file, or None when it is a coinwall outline.

    Parameters
    ----------
    nodes : ndarray, shape (n, 2)
        Segment end points (segment ``i`` from node ``i`` to node ``i+1``: its end points are nodes by
        construction).
    controls : ndarray, shape (n, 2, 2)
        The two inner control points of every segment.
    recorded : dict, optional
        The file's other fields: ``area`` and ``perimeter``, when numbers, must be the outline's.

    Returns
    -------
    str or None
        One line naming the fault (the first place where it shows), or None.
    """
    n = len(nodes)
    if n < 2:
        return f"an outline needs at least 2 nodes, got {n}"
    polygon = np.concatenate([nodes[:, None, :], controls], axis=1).reshape(-1, 2)
    size = float(np.ptp(polygon, axis=0).max())
    if not size > 0:
        return "every node and control point is the same point"
    edges = np.roll(polygon, -1, axis=0) - polygon
    lengths = np.hypot(*edges.T)
    kept = np.flatnonzero(lengths > _SHORT_EDGE * size)
    if len(kept) < 2:
        return "the control polygon has fewer than two edges of non-zero length"
    first, second = edges[kept], np.roll(edges[kept], -1, axis=0)
    cross = first[:, 0] * second[:, 1] - first[:, 1] * second[:, 0]
    dot = np.einsum("ij,ij->i", first, second)
    turn = np.arctan2(cross, dot)
    # a turn of exactly π (the two sides of a body of zero width, a stick) is a left turn
    turn = np.where(turn < -np.pi + 1e-9, turn + TWO_PI, turn)
    # the vertex between an edge and the next kept one, and how far it lies on the wrong side of their line
    vertex = (np.roll(kept, -1)) % len(polygon)
    slack = _TURN_TOLERANCE * size * (lengths[kept] + np.roll(lengths[kept], -1))
    winding = float(np.sum(turn)) / TWO_PI
    if np.all(cross <= slack) and round(winding) == -1:
        return ("the outline runs clockwise; coinwall writes counter-clockwise outlines, so the file was edited "
                "(write it again with 'coinwall solve -o')")
    right = np.flatnonzero(cross < -slack)
    if len(right):
        return (f"the Bézier controls do not fit the nodes: the control polygon turns clockwise at "
                f"{_where(int(vertex[right[0]]))} (a convex counter-clockwise outline never does)")
    if round(winding) != 1 or abs(winding - 1) > 1e-6:
        return (f"the Bézier controls do not fit the nodes: the control polygon winds {winding:.4g} times around "
                "the inside instead of once, so the outline crosses itself")
    from ..outline import Outline

    outline = Outline(nodes, controls)
    for key, value, unit in (("area", outline.area, size * size), ("perimeter", outline.perimeter, size)):
        stored = (recorded or {}).get(key)
        if isinstance(stored, (int, float)) and not isinstance(stored, bool) \
                and not abs(stored - value) <= _RECORD_TOLERANCE * unit:
            return (f"records {key} {stored!r} but its nodes and controls give {value:.12g}: the outline is not the "
                    "one that was solved")
    return None


def read_body_json(path: str) -> BodyJson:
    """Read a body JSON file (through :mod:`.inputfile`: a regular file of at most 64 MiB, nested at most
    :data:`~.inputfile.MAX_NESTING` deep).

    Raises
    ------
    InvalidOutline
        No ``outline`` or ``points`` list; a point that is not two finite numbers (the message names its
        index); ``controls`` that do not match the outline (:func:`verify_controls`); more than
        :data:`~.geometry.MAX_POINTS` points.
    """
    from .geometry import MAX_POINTS
    from .inputfile import read_json

    doc = read_json(path, what="body file", error=InvalidOutline)
    from .kinds import BODY, json_kind, refuse_kind

    refuse_kind(path, json_kind(doc), BODY, InvalidOutline, "body file")  # a wall's samples are not an outline
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
        fault = verify_controls(points, controls, doc)
        if fault is not None:
            raise InvalidOutline(f"body file {path!r}: {fault}")
    if KAPPA_KEY in doc:
        # the scale, κ in the file's units, as SVG and DXF drawings record it: a wrong one is refused, never used
        kappa = doc[KAPPA_KEY]
        if isinstance(kappa, bool) or not isinstance(kappa, (int, float)) or not 0 < kappa < math.inf:
            raise InvalidOutline(f"body file {path!r} records \"{KAPPA_KEY}\": {reprlib.repr(kappa)}; it must be a "
                                 "positive finite number (pass --kappa to override)")
        recorded["kappa"] = float(kappa)
    return BodyJson(points, controls, recorded, "JSON points")
