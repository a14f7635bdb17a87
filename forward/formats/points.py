"""CSV points: ``x,y`` columns (a header row and ``#`` comments are skipped), and coinwall's body CSV.

Every row has the same number of comma-separated columns, at least two; the first two are x and y,
finite numbers.  A row that is not (text, a missing value, a column too many or too few) is an error
naming its line, never dropped.  The file is read through :mod:`.inputfile` (a regular file of at most
64 MiB), and holds at most :data:`~.geometry.MAX_POINTS` rows.

``coinwall solve -o body.csv`` (:mod:`coinwall.inverse.export.csvfile`) writes a comment line starting
with ``HEADER_PREFIX``, then the columns ``COLUMNS``, one row per outline node, in units of κ with the
centre of mass at the origin; the reader recognises that line and keeps the origin as centre of mass.
"""

from __future__ import annotations

import numpy as np

from ..errors import InvalidOutline

__all__ = ["COLUMNS", "HEADER_PREFIX", "read_points_csv"]

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
        Fewer than two columns, no rows, a row that is not numbers (naming its line), too many rows.
    """
    import math

    from ..validation import ASCII_BLANKS, parse_number  # the one grammar of numbers: ASCII, no 1_0
    from .geometry import MAX_POINTS
    from .inputfile import read_text

    text = read_text(path, what="body file", error=InvalidOutline)
    from .kinds import BODY, csv_kind, refuse_kind

    refuse_kind(path, csv_kind(text), BODY, InvalidOutline, "body file")  # a wall's samples are not an outline
    lines = text.splitlines()
    coinwall = bool(lines) and lines[0].startswith(HEADER_PREFIX)
    rows = [(number, line.split("#", 1)[0].strip(ASCII_BLANKS)) for number, line in enumerate(lines, start=1)]
    rows = [(number, line) for number, line in rows if line]
    if len(rows) > MAX_POINTS + 1:
        raise InvalidOutline(f"body file {path!r} has {len(rows)} rows; at most {MAX_POINTS} points are read")

    def numbers(line):
        try:
            return [parse_number(cell) for cell in line.split(",")]
        except ValueError:
            return None

    if rows and numbers(rows[0][1]) is None:  # a header row names the columns
        width = len(rows[0][1].split(","))
        rows = rows[1:]
    else:
        width = len(rows[0][1].split(",")) if rows else 0
    if not rows:
        raise InvalidOutline(f"body file {path!r}: no x,y points")
    if width < 2:
        raise InvalidOutline(f"body file {path!r}: {width} column; expected 2 columns x,y (or more, x and y first)")
    points = []
    for number, line in rows:
        cells = [cell.strip(ASCII_BLANKS) for cell in line.split(",")]
        if len(cells) != width:
            raise InvalidOutline(f"body file {path!r}, line {number}: {len(cells)} columns, expected {width} "
                                 f"(x, y first)")
        try:
            x, y = parse_number(cells[0]), parse_number(cells[1])
        except ValueError:
            raise InvalidOutline(f"body file {path!r}, line {number}: x, y must be ASCII decimal numbers, got "
                                 f"{line[:60]!r}") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InvalidOutline(f"body file {path!r}, line {number}: x, y must be finite, got {line[:60]!r}")
        points.append((x, y))
    return np.array(points, dtype=float).reshape(-1, 2), coinwall
