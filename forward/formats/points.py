"""CSV points: ``x,y`` columns (a header row and ``#`` comments are skipped), and coinwall's body CSV.

``coinwall solve -o body.csv`` (:mod:`coinwall.inverse.export.csvfile`) writes a comment line starting
with ``HEADER_PREFIX``, then the columns ``COLUMNS``, one row per outline node, in units of κ with the
centre of mass at the origin; the reader recognises that line and keeps the origin as centre of mass.
"""

from __future__ import annotations

import numpy as np

from ..errors import InvalidOutline

__all__ = ["HEADER_PREFIX", "COLUMNS", "read_points_csv"]

#: first line of a body CSV written by coinwall
HEADER_PREFIX = "# coinwall body"
#: columns of coinwall's body CSV: node, polar angle and radius, curvature (inf at corners)
COLUMNS = ("x", "y", "alpha", "R", "K")


def read_points_csv(path: str):
    """The ``x, y`` points of a CSV file and whether coinwall wrote it.

    Returns
    -------
    points : ndarray, shape (n, 2)
    coinwall : bool
        True if the first line starts with ``HEADER_PREFIX`` (the origin is the centre of mass).

    Raises
    ------
    InvalidOutline
        Fewer than two columns, or no rows.
    """
    with open(path, encoding="utf-8") as fh:
        first = fh.readline()
    coinwall = first.startswith(HEADER_PREFIX)
    data = np.genfromtxt(path, delimiter=",", comments="#", ndmin=2)
    data = data[~np.all(np.isnan(data), axis=1)]
    if data.size == 0 or data.shape[1] < 2:
        raise InvalidOutline(f"body file {path!r}: no x,y points")
    return data[:, :2], coinwall
