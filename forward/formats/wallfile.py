"""Wall files, and the library's ``load_wall``: a wall from an expression or a file.

* ``.csv``: samples ``theta,b`` as people write them (:func:`read_sample_table`), read by
  :meth:`Wall.from_samples`;
* ``.json``: Fourier coefficients ``{"a0": …, "cos": […], "sin": […]}`` (``FOURIER_KEYS``), read by
  :meth:`Wall.from_fourier`, or samples ``{"theta": […], "b": […]}`` (``SAMPLE_KEYS``);
* anything else is an expression in ``t`` (alias ``theta``), parsed by :meth:`Wall.from_expression`.
"""

from __future__ import annotations

import math
import os
import re

from ..errors import InvalidArgument, InvalidWall
from ..validation import ASCII_BLANKS

__all__ = [
    "FOURIER_KEYS",
    "SAMPLE_KEYS",
    "WALL_FORMATS",
    "load_wall",
    "load_wall_file",
    "rounding_of",
]

WALL_FORMATS = (".csv", ".json")
#: the optional columns of a sample file, in the order they are read
_EXTRA = ("halfwidth_angle", "halfwidth_value", "sd_angle", "sd_value")
DRAWING_FORMATS = (".svg", ".dxf")
#: keys of a sample wall file (JSON): the angles (radians) and the wall values
SAMPLE_KEYS = ("theta", "b")
#: largest wall file read (64 MiB holds ~3·10⁶ rows, more than MAX_SAMPLES)
MAX_WALL_FILE_BYTES = 64 * 2**20
#: samples in a wall file at most (the library's bound, :data:`coinwall.forward.wall.MAX_SAMPLES`): ``critical``
#: on 10⁶ uniform samples from a file needs about 0.34 GB and seconds; 10⁷ rows would take minutes
MAX_SAMPLES = 1_000_000
#: keys of a Fourier wall file: constant term and the cosine and sine coefficients of orders 1, 2, …
FOURIER_KEYS = ("a0", "cos", "sin")


def load_wall(text: str, params=None, *, degrees: bool = False, b_halfwidth: float = 0.0, theta_halfwidth: float = 0.0,
              b_sd: float | None = None, theta_sd: float | None = None):
    """A wall from an expression in ``t`` or from a wall file (``.csv`` samples, ``.json`` Fourier or samples).

    Parameters
    ----------
    text : str
        The expression (``"sqrt((1+eps*cos(t)**2)/(1+eps))"``) or the name of a ``.csv``/``.json`` file.
    params : dict, optional
        Values of the expression's parameters; a file takes none.
    degrees : bool
        The angles of a sample file are in degrees (a header ``theta_deg`` or ``Theta (deg)`` says so too).
    b_halfwidth, theta_halfwidth : float
        Half-widths (bounds) of a sample file's values and angles (in the file's angle unit), where they exceed
        half a unit of the last digit written.
    b_sd, theta_sd : float, optional
        Standard deviations (statistics) of a sample file's values and angles (in the file's angle unit).

    Returns
    -------
    Wall

    Raises
    ------
    InvalidWall, InvalidExpression
        A bad file or expression, ``params`` given with a file, or a drawing (which has no wall yet).

    Examples
    --------
    A wall sampled at every degree, rounded to 6 decimals, as people write it: each sample is an interval
    of half a unit of its last digit, and the critical offset of ``1 + 0.1 cos 2θ`` (exactly −0.7, where
    ``b + b'' = 1 − 0.3 cos 2θ`` is smallest) is certified to lie in the interval printed.

    >>> import math
    >>> from coinwall import critical_offset
    >>> from coinwall.forward.formats import load_wall
    >>> with open("wall.csv", "w") as fh:
    ...     _ = fh.write("theta_deg,b\\n")
    ...     for degree in range(360):
    ...         _ = fh.write(f"{degree},{1 + 0.1 * math.cos(2 * math.radians(degree)):.6f}\\n")
    >>> wall = load_wall("wall.csv")
    >>> wall, f"{wall.sample_rounding[0]:.2g}"          # half a unit of the 6th decimal
    (Wall('uniform samples (n=360)'), '5e-07')
    >>> critical_offset(wall)
    CriticalOffset(b_c=-0.698797851192 in [-0.700865, -0.692739], angles=[0, 3.14159])
    >>> load_wall("1 + 0.1*cos(2*t)")
    Wall('1 + 0.1*cos(2*t)')
    """
    from ..wall import Wall

    if not isinstance(text, str):
        raise InvalidArgument(f"`text` must be a wall expression or a .csv/.json file name, got {text!r}")
    params = dict(params or {})
    lower = text.strip().lower()
    if lower.endswith(DRAWING_FORMATS):
        raise InvalidWall(f"{text!r} is a drawing, not a wall: run `coinwall wall {text} -o wall.csv` first "
                          "(its wall), then solve wall.csv")
    if lower.endswith(WALL_FORMATS):
        if params:
            raise InvalidWall(f"`params` apply to wall expressions, not to the wall file {text!r}")
        return load_wall_file(text.strip(), degrees=degrees, b_halfwidth=b_halfwidth, theta_halfwidth=theta_halfwidth,
                              b_sd=b_sd, theta_sd=theta_sd)
    stripped = text.strip()
    if os.sep not in stripped and "." in stripped and os.path.isfile(stripped) or _looks_like_file(stripped):
        # `wall.txt`, `data.xlsx`: a file name, not an expression (the parser would say "attribute access")
        suffix = os.path.splitext(stripped)[1]
        raise InvalidWall(f"{text!r} looks like a file with the extension {suffix!r}, which coinwall does not read as "
                          f"a wall: give a {' or '.join(WALL_FORMATS)} file (or an expression in t)")
    if os.sep in text and os.path.exists(text.strip()):
        # a path (``/dev/zero``, ``data/wall.txt``) read as an expression would only give a syntax error
        raise InvalidWall(f"{text!r} is a file, but not a wall file: coinwall reads walls from "
                          f"{' and '.join(WALL_FORMATS)} files (or give an expression in t)")
    if degrees:
        raise InvalidArgument("`degrees` applies to sample files, not to expressions (write the angle in radians)")
    if b_halfwidth or theta_halfwidth or b_sd is not None or theta_sd is not None:
        raise InvalidArgument("half-widths and standard deviations apply to sample files, not to expressions")
    return Wall.from_expression(text, params)


def _read_text(path: str) -> str:
    from .inputfile import read_text

    return read_text(path, what="wall file", error=InvalidWall, max_bytes=MAX_WALL_FILE_BYTES)


#: words that say "error" without saying which kind: a bound or a standard deviation
_AMBIGUOUS = ("sigma", "err", "error", "uncertainty", "unc", "tol", "tolerance", "eps")
#: prefixes and suffixes of a half-width column (a bound: certified) and of a standard-deviation one (statistics)
_HALFWIDTH = ("halfwidth", "half_width", "hw", "delta", "d", "δ", "±")
_SD = ("sd", "std", "stdev", "stddev")


def _column_kind(name: str, path: str = "?"):
    """``(kind, in_degrees)`` of a header cell: ``angle`` or ``value``; ``halfwidth_angle``/``halfwidth_value``
    (bounds: ``b_halfwidth``, ``halfwidth_b``, ``db``, ``delta_b``); ``sd_angle``/``sd_value`` (standard
    deviations: ``b_sd``, ``sd_b``, ``b_std``); or ``(None, None)``.  A column named with a word that does not
    say which (``sigma_b``, ``b_err``) is refused: the two meanings give different answers."""
    key = name.strip().lower()
    degrees = any(mark in key for mark in ("deg", "°"))
    parts = [p for p in key.replace("-", "_").replace(" ", "_").split("_") if p]
    base = _base_kind(key)
    if base is not None:
        return base, degrees if base == "angle" else None
    for words, kind in ((_HALFWIDTH, "halfwidth"), (_SD, "sd")):
        for word in words:
            for rest in (key[len(word):] if key.startswith(word) else None,
                         key[:-len(word)] if key.endswith(word) and len(key) > len(word) else None):
                if rest is None:
                    continue
                inner = _base_kind(rest.strip("_ ") or "?")
                if inner is not None:
                    return f"{kind}_{inner}", degrees if inner == "angle" else None
    if any(word in parts or (key.startswith(word) and _base_kind(key[len(word):].strip("_ ") or "?"))
           for word in _AMBIGUOUS):
        inner = next((_base_kind(p) for p in parts if _base_kind(p)), "value") or "value"
        what = "b" if inner == "value" else "theta"
        raise InvalidWall(f"wall file {path!r}: the column {name.strip()!r} does not say whether it is a bound or a "
                          f"standard deviation: name it {what}_halfwidth for a half-width (a bound: certified "
                          f"intervals) or {what}_sd for a standard deviation (statistics: estimates with confidence "
                          "intervals)")
    return None, None


def _base_kind(key):
    bare = "".join(ch for ch in key if ch.isalnum() or ch in "θ_").replace("_deg", "").replace("deg", "")
    bare = bare.replace("rad", "").strip("_")
    if bare in ("theta", "θ", "angle", "t", "phi", "φ"):
        return "angle"
    if bare in ("b", "h", "wall", "btheta", "bθ", "support", "value"):
        return "value"
    return None


def _angle_rounding(values, period):
    """``(rounding, grid)`` of angles as written (in the file's unit): half a unit of the last digit of each,
    or, where the angles are a uniform grid (0°, 1°, …; distinct, every step equal), a few ulps and the grid's
    step: the grid may be the design of the data, exact — which the samples' own scatter decides
    (:func:`coinwall.forward.sampledata.sample_intervals`)."""
    import numpy as np

    values = np.asarray(values, dtype=float)
    distinct = np.unique(values)
    if distinct.size == values.size and distinct.size >= 8:
        steps = np.diff(distinct)
        if np.all(np.abs(steps - steps[0]) <= 64 * np.finfo(float).eps * max(period, float(np.max(np.abs(values))))):
            return 4 * np.finfo(float).eps * np.maximum(np.abs(values), period), float(steps[0])
    return rounding_of(values), None


def _data_rows(text, most=None, skip=0):
    """``(line number, row)`` of the non-empty rows of ``text`` with ``#`` comments removed (the first
    ``most``; ``skip`` rows left out)."""
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.split("#", 1)[0].strip(ASCII_BLANKS)  # ASCII blanks only: a no-break space is no number
        if stripped:
            if skip:
                skip -= 1
                continue
            rows.append((number, stripped))
            if most is not None and len(rows) >= most:
                break
    return rows


class _LazyRows:
    """The data rows of a file, split only when asked for: the fast reader never needs them, and a message
    naming a sample by its line number needs them once."""

    def __init__(self, text, skip=0):
        self._text, self._skip, self._rows = text, skip, None

    def _all(self):
        if self._rows is None:
            self._rows = _data_rows(self._text, skip=self._skip)
        return self._rows

    def __iter__(self):
        return iter(self._all())

    def line_numbers(self):
        return _LineLabels(self)


class _LineLabels:
    """``labels[k]`` is ``"line N"`` of sample k, computed on first use."""

    def __init__(self, rows):
        self._rows = rows

    def __getitem__(self, k):
        return f"line {self._rows._all()[k][0]}"

    def __len__(self):
        return len(self._rows._all())


def _fast_columns(text, header_line, delimiter, decimal_comma, width, columns):
    """The numeric columns of the file's rows by numpy's C reader (10⁶ rows in about a second), or None where
    it cannot read them all (a bad row, decimal commas): the careful reader then names the row."""
    import io

    import numpy as np

    if decimal_comma or not text.split("\n", header_line)[-1].isascii():
        return None  # numpy's reader takes a no-break space as a blank: the careful reader refuses it, by line
    try:
        table = np.loadtxt(io.StringIO(text), delimiter=delimiter, dtype=float, ndmin=2, comments="#",
                           skiprows=header_line)
    except (ValueError, IndexError):
        return None
    if table.ndim != 2 or table.shape[1] != width or table.shape[0] == 0:
        return None
    return [np.ascontiguousarray(table[:, col]) for col in columns]


def _careful_columns(path, rows, cells, number, width, columns):
    """The numeric columns of ``rows``, row by row: the first bad row is an error naming its line."""
    import numpy as np

    data = [[] for _ in columns]
    for number_, line in rows:
        parts = cells(line)
        if (width is None and len(parts) != 2) or (width is not None and len(parts) != width):
            expected = "2 (theta, b; name the columns in a header row if there are more)" if width is None \
                else str(width)
            raise InvalidWall(f"wall file {path!r}, line {number_}: {len(parts)} columns, expected {expected}")
        try:
            for store, col in zip(data, columns):
                store.append(number(parts[col]))
        except ValueError:
            raise InvalidWall(f"wall file {path!r}, line {number_}: not a number in {line!r}") from None
    return [np.array(d) for d in data]


def read_sample_table(path: str, *, degrees: bool = False) -> dict:
    """Samples from a CSV as people write them: angles, values, their half-widths and line numbers.

    The delimiter is a comma, a semicolon, a tab or white space (decimal commas are read with a
    semicolon or tab delimiter).  A header row names the columns: ``theta``/``θ``/``angle`` for the
    angle (``theta_deg``, ``Theta (deg)``, ``angle [°]`` in degrees), ``b``/``h``/``wall`` for the
    wall, and optionally half-widths — bounds — ``b_halfwidth`` (or ``db``, ``delta_b``) and
    ``theta_halfwidth`` (``dtheta``; in the angle column's unit), and standard deviations — statistics —
    ``b_sd`` (``b_std``) and ``theta_sd``.  A column whose name does not say which (``sigma_b``, ``b_err``) is
    refused with a line naming both.  Without a header there must be exactly two
    columns, θ in radians (or ``degrees=True``) and b.  Radian angles spanning more than 2π are refused
    (they look like degrees).  Every row must be complete and numeric: a bad row is an error naming its
    line, never silently dropped.

    Returns
    -------
    dict
        ``theta`` (radians), ``b``, ``theta_rounding`` (radians) and ``b_rounding``: half a unit of the
        last digit written (or the file's half-width columns, whichever is larger; angles on a designed
        uniform grid are exact when the values agree), ``b_sd`` and ``theta_sd`` (radians; None without such a
        column), ``grid`` (the step of a uniform grid of angles, radians, or None) and ``labels``
        (``"line N"`` of each sample).
    """
    import numpy as np

    text = _read_text(path)
    from .kinds import WALL, csv_kind, refuse_kind

    refuse_kind(path, csv_kind(text), WALL, InvalidWall, "wall file")  # an outline's points are not a wall
    head = _data_rows(text, most=6)  # the first rows decide the delimiter and the header
    if not head:
        raise InvalidWall(f"wall file {path!r} has no rows")
    first = head[0][1]
    delimiter = next((d for d in (";", "\t", ",") if d in first), None)
    decimal_comma = delimiter in (";", "\t") and any("," in r for _, r in head)
    rows = _LazyRows(text)

    def cells(line):
        # ASCII blanks only, around and between cells: a no-break space is neither a blank nor a number
        parts = line.split(delimiter) if delimiter else re.split(r"[ \t\r\f\v]+", line.strip(ASCII_BLANKS))
        return [c.strip(ASCII_BLANKS) for c in parts]

    def number(cell):
        from ..validation import parse_number  # the one grammar of numbers (no 1_0, no other scripts' digits)

        return parse_number(cell.replace(",", ".") if decimal_comma else cell)

    header = cells(first)
    try:
        [number(c) for c in header]
        header = None
    except ValueError:
        rows = _LazyRows(text, skip=1)
    sigma_cols = {}
    if header is None:
        angle_col, value_col, width = 0, 1, None
        in_degrees = degrees
    else:
        kinds = [_column_kind(c, path) for c in header]
        angles = [i for i, (k, _) in enumerate(kinds) if k == "angle"]
        values = [i for i, (k, _) in enumerate(kinds) if k == "value"]
        if len(angles) != 1 or len(values) != 1:
            raise InvalidWall(f"wall file {path!r}: columns {header}: name one angle column (theta, θ, angle; "
                              "theta_deg for degrees) and one wall column (b, h, wall)")
        for kind in _EXTRA:
            found = [i for i, (k, _) in enumerate(kinds) if k == kind]
            if len(found) > 1:
                raise InvalidWall(f"wall file {path!r}: columns {header}: more than one {kind.replace('_', ' ')} "
                                  "column")
            if found:
                sigma_cols[kind] = found[0]
        angle_col, value_col, width = angles[0], values[0], len(header)
        in_degrees = degrees or bool(kinds[angle_col][1])
        for kind in ("halfwidth_angle", "sd_angle"):
            if kind in sigma_cols and kinds[sigma_cols[kind]][1] and not in_degrees:
                raise InvalidWall(f"wall file {path!r}: the column {header[sigma_cols[kind]]!r} is in degrees but "
                                  "the angles are not; give both in one unit")
    columns = [angle_col, value_col] + [sigma_cols[k] for k in _EXTRA if k in sigma_cols]
    arrays = _fast_columns(text, head[0][0] if header is not None else 0, delimiter, decimal_comma, width or 2,
                           columns)
    if arrays is None:  # the careful reader names the first bad row
        arrays = _careful_columns(path, rows, cells, number, width, columns)
    if arrays[0].size > MAX_SAMPLES:
        raise InvalidWall(f"wall file {path!r} has {arrays[0].size} rows; at most {MAX_SAMPLES} samples are read "
                          "(the solvers take minutes beyond): thin the data")
    lines = rows.line_numbers()
    theta, b = arrays[0], arrays[1]
    for arr in arrays:
        if not np.all(np.isfinite(arr)):
            bad = int(np.flatnonzero(~np.isfinite(arr))[0])
            raise InvalidWall(f"wall file {path!r}, {lines[bad]}: a value is not finite")
    sigma = dict(zip([k for k in _EXTRA if k in sigma_cols], arrays[2:]))
    for kind, arr in sigma.items():
        if np.any(arr < 0):
            bad = int(np.flatnonzero(arr < 0)[0])
            what = "half-width" if kind.startswith("halfwidth") else "standard deviation"
            raise InvalidWall(f"wall file {path!r}, {lines[bad]}: a {what} is negative")
    period = 360.0 if in_degrees else 2 * np.pi
    b_rounding = np.maximum(rounding_of(b), sigma.get("halfwidth_value", 0.0))
    theta_rounding, grid = _angle_rounding(theta, period)
    theta_rounding = np.maximum(theta_rounding, sigma.get("halfwidth_angle", 0.0))
    if in_degrees:
        theta, theta_rounding = np.radians(theta), np.radians(theta_rounding)
        grid = None if grid is None else math.radians(grid)
        if "sd_angle" in sigma:
            sigma["sd_angle"] = np.radians(sigma["sd_angle"])
    elif theta.size and np.ptp(theta) > 2 * np.pi * (1 + 1e-9) + 2 * float(np.max(theta_rounding)):
        # (an angle just below 2π written to 4 decimals is 6.2832: its rounding is allowed for)
        raise InvalidWall(f"wall file {path!r}: the angles span {np.ptp(theta):.6g}, more than 2π radians: are they "
                          "degrees? Name the column theta_deg, or pass --degrees")
    return {"theta": theta, "b": b, "theta_rounding": theta_rounding, "b_rounding": b_rounding,
            "b_sd": sigma.get("sd_value"), "theta_sd": sigma.get("sd_angle"), "grid": grid,
            "labels": lines, "degrees": in_degrees}


def _looks_like_file(text: str) -> bool:
    """A name with a file extension (``wall.txt``, ``scan.xlsx``): letters, digits, ``_-`` and one final
    ``.ext`` that is not a number — never a valid wall expression."""
    import re

    if not re.fullmatch(r"[\w\-]+(\.[\w\-]+)*\.[A-Za-z][A-Za-z0-9]{0,5}", text):
        return False
    return text.split(".", 1)[0].lower() not in ("t", "theta", "pi", "e")  # `t.real`: an attribute, not a file


#: keys of a sample wall file (JSON) besides the samples: one number for every sample
SAMPLE_OPTIONS = ("b_halfwidth", "theta_halfwidth", "b_sd", "theta_sd")


def load_wall_file(path: str, *, degrees: bool = False, b_halfwidth: float = 0.0, theta_halfwidth: float = 0.0,
                   b_sd: float | None = None, theta_sd: float | None = None, noisy: bool = False):
    """A wall from a file: ``.csv`` samples (:func:`read_sample_table`) or ``.json``: Fourier coefficients
    ``{"a0", "cos", "sin"}`` or samples ``{"theta": […], "b": […]}`` (``"degrees": true`` allowed, and one
    number for every sample under :data:`SAMPLE_OPTIONS`).

    Samples are intervals: half a unit of the last digit of each number, or ``b_halfwidth`` and
    ``theta_halfwidth`` (bounds; the angle's in the file's angle unit) where those are larger.  ``b_sd`` and
    ``theta_sd`` (or columns ``b_sd``, ``theta_sd``) are standard deviations: statistics, which the solvers
    turn into estimates with confidence intervals.  ``noisy``: measurements that scatter beyond their digits
    (``coinwall fit``): samples at one angle are averaged, not intersected.

    Parameters
    ----------
    path : str
        A ``.csv`` or ``.json`` wall file.
    degrees : bool
        The angles of the file are in degrees (a header ``theta_deg`` says so too).
    b_halfwidth, theta_halfwidth : float
        Half-widths (bounds) of the values and angles, where they exceed half a unit of the last digit.
    b_sd, theta_sd : float, optional
        Standard deviations of the values and angles.
    noisy : bool
        Samples at one angle are averaged, not intersected.

    Returns
    -------
    Wall

    Raises
    ------
    InvalidWall
        A missing, empty or damaged file, a file of another kind (a body, a drawing), samples that do not
        make a wall (too few, not finite, contradictory duplicates).
    InvalidArgument
        A bad half-width or standard deviation.

    Examples
    --------
    Fourier coefficients ``b = 1 + 0.1 cos 2θ`` in JSON:

    >>> import json
    >>> from coinwall.forward.formats import load_wall_file
    >>> with open("wall.json", "w") as fh:
    ...     json.dump({"a0": 1.0, "cos": [0.0, 0.1]}, fh)
    >>> wall = load_wall_file("wall.json")
    >>> wall, wall.kind, round(float(wall(0.0)), 12)
    (Wall('Fourier series (2 harmonics)'), 'fourier', 1.1)
    """
    import numpy as np

    from ..wall import Wall

    given = {"b_halfwidth": b_halfwidth, "theta_halfwidth": theta_halfwidth, "b_sd": b_sd, "theta_sd": theta_sd}
    for name, value in given.items():
        if value is not None and not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
            raise InvalidArgument(f"`{name}` must be a finite number ≥ 0, got {value!r}")

    if path.lower().endswith(".csv"):
        # numbers written as text carry their rounding in their digits
        table = read_sample_table(path, degrees=degrees)
        angle = math.radians if table.get("degrees") else float
        sd, theta_sd_ = _largest(table["b_sd"], b_sd), _largest(table["theta_sd"], None if theta_sd is None else
                                                                  angle(theta_sd))
        return Wall.from_samples(table["theta"], table["b"], rounding=np.maximum(table["b_rounding"], b_halfwidth),
                                 theta_rounding=np.maximum(table["theta_rounding"], angle(theta_halfwidth)),
                                 labels=table["labels"], merge="mean" if noisy else "intersect", sd=sd,
                                 theta_sd=theta_sd_, grid=table["grid"])
    from .inputfile import read_json

    doc = read_json(path, what="wall file", error=InvalidWall, max_bytes=MAX_WALL_FILE_BYTES)
    from .kinds import WALL, json_kind, refuse_kind

    refuse_kind(path, json_kind(doc), WALL, InvalidWall, "wall file")  # a body's outline is not a wall
    if not isinstance(doc, dict):
        raise InvalidWall(f"wall file {path!r}: expected an object with {', '.join(FOURIER_KEYS)} "
                          f"or with {', '.join(SAMPLE_KEYS)}")
    try:
        if set(doc) & set(SAMPLE_KEYS):
            for key in doc:
                if key not in SAMPLE_KEYS and key not in SAMPLE_OPTIONS and key not in ("degrees", "note"):
                    _column_kind(key, path)  # an ambiguous name ("sigma_b") is refused by name
            unknown = set(doc) - set(SAMPLE_KEYS) - set(SAMPLE_OPTIONS) - {"degrees", "note"}
            if unknown:
                raise InvalidWall(f"wall file {path!r}: unknown keys {sorted(unknown)}; "
                                  f"expected {', '.join(SAMPLE_KEYS)}")
            theta, b = (_numbers(doc.get(k), path, k) for k in SAMPLE_KEYS)
            if not isinstance(doc.get("degrees", False), bool):
                raise InvalidWall(f"wall file {path!r}: `degrees` must be true or false, got {doc['degrees']!r}")
            for key in SAMPLE_OPTIONS:  # one number for every sample (the file's own)
                if key in doc:
                    value = _numbers(doc[key], path, key)
                    if isinstance(value, list) or value < 0:
                        raise InvalidWall(f"wall file {path!r}: `{key}` must be one number ≥ 0")
                    given[key] = max(given[key] or 0.0, value)
            in_degrees = doc.get("degrees", False) is True or degrees
            period = 360.0 if in_degrees else 2 * np.pi
            b_rounding = np.maximum(rounding_of(b), given["b_halfwidth"])
            theta_rounding, grid = _angle_rounding(theta, period)
            theta_rounding = np.maximum(theta_rounding, given["theta_halfwidth"])
            angle = math.radians if in_degrees else float
            if in_degrees:
                theta, theta_rounding = np.radians(theta), np.radians(theta_rounding)
            elif len(theta) and np.ptp(theta) > 2 * np.pi * (1 + 1e-9) + 2 * float(np.max(theta_rounding)):
                # the same check as for a CSV file: radians spanning more than 2π are degrees
                raise InvalidWall(f"wall file {path!r}: the angles span {np.ptp(theta):.6g}, more than 2π radians: "
                                  "are they degrees? Add \"degrees\": true, or pass --degrees")
            return Wall.from_samples(theta, b, rounding=b_rounding, theta_rounding=theta_rounding,
                                     labels=[f"`theta`[{k}]" for k in range(len(theta))],
                                     merge="mean" if noisy else "intersect", sd=given["b_sd"],
                                     theta_sd=None if given["theta_sd"] is None else angle(given["theta_sd"]),
                                     grid=None if grid is None else angle(grid))
        unknown = set(doc) - set(FOURIER_KEYS)
        if unknown:
            raise InvalidWall(f"wall file {path!r}: unknown keys {sorted(unknown)}; expected "
                              f"{', '.join(FOURIER_KEYS)}")
        a0, cos, sin = FOURIER_KEYS
        return Wall.from_fourier(_numbers(doc.get(a0, 0.0), path, a0), _numbers(doc.get(cos, []), path, cos),
                                 _numbers(doc.get(sin, []), path, sin))
    except (ValueError, TypeError) as exc:
        if isinstance(exc, InvalidWall):
            raise
        raise InvalidWall(f"wall file {path!r} is not readable: {exc}") from None


def _largest(column, given):
    """A column of a file, or one number given for every sample, or the larger of the two; None if neither."""
    import numpy as np

    if column is None:
        return given
    return column if given is None else np.maximum(column, given)


def _numbers(value, path, key):
    """A finite number or a flat list of finite numbers (no strings, booleans, nested lists, NaN or Infinity),
    as floats; the message names the key and the index."""
    from .inputfile import json_number

    items = value if isinstance(value, list) else [value]
    if len(items) > MAX_SAMPLES:
        raise InvalidWall(f"wall file {path!r}: `{key}` holds {len(items)} values; at most {MAX_SAMPLES} are read")
    out = []
    for index, item in enumerate(items):
        where = f"`{key}`[{index}]" if isinstance(value, list) else f"`{key}`"
        out.append(json_number(item, where, f"wall file {path!r}: ", error=InvalidWall, what="values of a wall"))
    return out if isinstance(value, list) else out[0]


def rounding_of(values):
    """Half the last decimal place of each value: how far it may be from the number it stands for.

    Data come rounded to a number of decimals (``%.6f``) or of significant digits (``%.6g``); a
    value that needs no more than k decimals may have been rounded at the k-th.  The digits are read
    off the whole data set (a value that happens to be short, such as ``1.0``, is not taken as
    coarser than the rest): ``max(½·10^−K, ½·10^(m_i + 1 − S))`` with K the most decimals and S the
    most significant digits any value needs, m_i the decimal exponent of value i.  Values at full
    double precision give a few ulps.
    """
    import numpy as np

    v = np.asarray(values, dtype=float)
    a = np.abs(v)
    floor = 2.0 * np.finfo(float).eps * np.maximum(a, np.finfo(float).tiny)
    nonzero = a > 0
    if not nonzero.any():
        return floor
    decimals = np.full(v.size, 0)
    pending = nonzero.copy()
    for k in range(25):
        fits = pending & (np.abs(np.round(v, k) - v) <= 2.0 * np.finfo(float).eps * a)
        decimals[fits] = k
        pending &= ~fits
        if not pending.any():
            break
    decimals[pending] = 25
    exponent = np.floor(np.log10(np.where(nonzero, a, 1.0))).astype(int)
    significant = np.where(nonzero, decimals + exponent + 1, 0)
    most_decimals = int(decimals[nonzero].max())
    most_significant = int(significant[nonzero].max())
    fixed = 0.5 * 10.0 ** (-most_decimals)
    relative = 0.5 * 10.0 ** (exponent + 1 - most_significant)
    return np.maximum(floor, np.where(nonzero, np.maximum(fixed, relative), fixed))
