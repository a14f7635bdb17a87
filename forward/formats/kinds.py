"""What a data file is, from its content: a wall (θ, b samples; Fourier coefficients) or a body (x, y points; an
outline), so that neither is ever read as the other.

A ``.csv`` or ``.json`` file can hold either kind, and both readers would take the other's file without a word: a
``theta,b`` wall given to ``coinwall wall`` gave the wall of the polygon with vertices (θ, b), and a headerless
file of an outline's points given to ``coinwall solve`` gave a wall b(θ = x) = y.  Each reader asks
:func:`csv_kind` or :func:`json_kind` first and refuses the other kind in one line that says what the file looks
like and which command reads it (:func:`refuse_kind`).  The signs, strongest first:

* **a header row** names the columns: an angle and a wall value (``theta``/``θ``/``angle``, ``theta_deg``;
  ``b``/``h``/``wall``: :func:`~.wallfile.read_sample_table`'s names) is a wall; ``x`` and ``y`` is a body
  (coinwall's body CSV starts with ``# coinwall body``);
* **JSON keys**: ``theta``/``b`` or ``a0``/``cos``/``sin`` is a wall, ``outline``/``points``/``controls`` a body;
* **a file without a header** (two numeric columns) is told by its first column.  A closed outline goes around:
  its x rises and falls again, so many steps go down (about half).  Wall samples are written by angle: the
  angles rise, with at most one wrap (180° … 359°, 0° … 179°).  At least 8 rows are needed to tell; a file
  whose first column never falls more than once is a wall, one where a quarter of the steps fall or more is a
  body.  A header row makes any file unambiguous (``x,y`` or ``theta,b``), and the messages say so.
"""

from __future__ import annotations

__all__ = ["BODY", "WALL", "csv_kind", "json_kind", "refuse_kind"]

WALL, BODY = "wall", "body"
#: which commands read each kind (named in the messages)
_READERS = {WALL: "`coinwall solve FILE` (and critical, fit, simulate, section, correlation, toss, quantum)",
            BODY: "`coinwall wall FILE` (and mass, export)"}
#: rows needed before a headerless file's kind is told from its first column
_ROWS = 8
#: a headerless file whose first column falls in this share of its steps or more goes around: an outline
_FALLING = 0.25


def _first_rows(text: str, most: int = 4096):
    rows = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            rows.append(line)
            if len(rows) >= most:
                break
    return rows


def _cells(line: str):
    delimiter = next((d for d in (";", "\t", ",") if d in line), None)
    return [c.strip() for c in (line.split(delimiter) if delimiter else line.split())]


def csv_kind(text: str):
    """``(kind, why)``: :data:`WALL`, :data:`BODY` or None (cannot tell), and the sign in words.

    Examples
    --------
    >>> csv_kind("theta_deg,b\\n0,1\\n10,1.1\\n")
    ('wall', 'columns theta_deg, b')
    >>> csv_kind("x,y\\n1,0\\n0,1\\n")
    ('body', 'columns x, y')
    >>> csv_kind("\\n".join(f"{k},{k % 3}" for k in range(12)))
    ('wall', 'a first column that rises row by row, like angles')
    """
    from .points import HEADER_PREFIX
    from .wallfile import _column_kind

    if text.lstrip().startswith(HEADER_PREFIX):
        return BODY, "coinwall's body CSV (x, y, alpha, R, K)"
    rows = _first_rows(text)
    if not rows:
        return None, ""
    header = _cells(rows[0])
    if not all(_is_number(c) for c in header):
        names = [c.strip().lower() for c in header]
        kinds = [_column_kind(c)[0] for c in header]
        shown = ", ".join(header[:4]) + (", ..." if len(header) > 4 else "")
        if "angle" in kinds and "value" in kinds:
            return WALL, f"columns {shown}"
        if "x" in names and "y" in names:
            return BODY, f"columns {shown}"
        return None, ""
    first = []
    for line in rows:
        cells = _cells(line)
        if len(cells) != 2 or not all(_is_number(c) for c in cells):
            return None, ""
        first.append(float(cells[0].replace(",", ".")))
    if len(first) < _ROWS:
        return None, ""
    falls = sum(b < a for a, b in zip(first, first[1:]))
    if falls <= 1:
        return WALL, "a first column that rises row by row, like angles"
    if falls >= _FALLING * (len(first) - 1):
        return BODY, "a first column that rises and falls, like the x of points around an outline"
    return None, ""


def _is_number(cell: str) -> bool:
    try:
        float(cell.replace(",", "."))
    except ValueError:
        return False
    return True


def json_kind(doc):
    """``(kind, why)`` of a JSON document (see :func:`csv_kind`).

    Examples
    --------
    >>> json_kind({"a0": 1, "cos": [0, 0.1]})
    ('wall', 'keys a0, cos')
    >>> json_kind({"outline": [[1, 0], [0, 1], [-1, 0]]})
    ('body', 'key outline')
    """
    if not isinstance(doc, dict):
        return None, ""
    keys = set(doc)
    for kind, names in ((BODY, ("outline", "points", "controls")), (WALL, ("theta", "b", "a0", "cos", "sin"))):
        found = [k for k in names if k in keys]
        if found:
            return kind, f"key{'s' if len(found) > 1 else ''} {', '.join(found)}"
    return None, ""


def refuse_kind(path: str, found, wanted: str, error, what: str = "") -> None:
    """Raise ``error`` when ``found`` (a :func:`csv_kind` or :func:`json_kind` answer) is not ``wanted``;
    ``what`` starts the message ("body file").

    Examples
    --------
    >>> from coinwall.forward.errors import InvalidOutline
    >>> refuse_kind("w.csv", ("wall", "columns theta, b"), "body", InvalidOutline, "body file")
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidOutline: body file 'w.csv' looks like a wall file (columns theta, b), not a body: \
`coinwall solve FILE` (and critical, fit, simulate, section, correlation, toss, quantum) reads it; \
if it is a body, name its columns x,y in a header row
    """
    kind, why = found
    if kind is None or kind == wanted:
        return
    header = "x,y" if wanted == BODY else "theta,b (or theta_deg,b)"
    hint = "" if str(path).lower().endswith(".json") else \
        f"; if it is a {wanted}, name its columns {header} in a header row"
    raise error(f"{(what + ' ') if what else ''}{path!r} looks like a {kind} file ({why}), not a {wanted}: "
                f"{_READERS[kind]} reads it{hint}")
