"""Wall files, and the library's ``load_wall``: a wall from an expression or a file.

* ``.csv``: samples ``theta,b`` as people write them (:func:`read_samples_csv`), read by
  :meth:`Wall.from_samples`;
* ``.json``: Fourier coefficients ``{"a0": …, "cos": […], "sin": […]}`` (``FOURIER_KEYS``), read by
  :meth:`Wall.from_fourier`, or samples ``{"theta": […], "b": […]}`` (``SAMPLE_KEYS``);
* anything else is an expression in ``t`` (alias ``theta``), parsed by :meth:`Wall.from_expression`.
"""

from __future__ import annotations

import os

from ..errors import InvalidArgument, InvalidWall

__all__ = [
    "FOURIER_KEYS",
    "SAMPLE_KEYS",
    "WALL_FORMATS",
    "load_wall",
    "load_wall_file",
    "read_samples_csv",
    "rounding_of",
]

WALL_FORMATS = (".csv", ".json")
DRAWING_FORMATS = (".svg", ".dxf")
#: keys of a sample wall file (JSON): the angles (radians) and the wall values
SAMPLE_KEYS = ("theta", "b")
#: largest wall file read (64 MiB holds ~3·10⁶ rows, more than MAX_SAMPLES)
MAX_WALL_FILE_BYTES = 64 * 2**20
#: samples in a wall file at most: ``critical`` on 10⁶ uniform samples takes 9.5 s and 0.34 GB (measured on
#: 2 shared cores); 10⁷ rows (issue 12) ran for over 300 s
MAX_SAMPLES = 1_000_000
#: keys of a Fourier wall file: constant term and the cosine and sine coefficients of orders 1, 2, …
FOURIER_KEYS = ("a0", "cos", "sin")


def load_wall(text: str, params=None, *, degrees: bool = False):
    """A wall from an expression in ``t`` or from a wall file (``.csv`` samples, ``.json`` Fourier or samples).

    Parameters
    ----------
    text : str
        The expression (``"sqrt((1+eps*cos(t)**2)/(1+eps))"``) or the name of a ``.csv``/``.json`` file.
    params : dict, optional
        Values of the expression's parameters; a file takes none.
    degrees : bool
        The angles of a sample file are in degrees (a header ``theta_deg`` or ``Theta (deg)`` says so too).

    Returns
    -------
    Wall

    Raises
    ------
    InvalidWall, InvalidExpression
        A bad file or expression, ``params`` given with a file, or a drawing (which has no wall yet).
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
        return load_wall_file(text.strip(), degrees=degrees)
    if os.sep in text and os.path.exists(text.strip()):
        # a path (``/dev/zero``, ``data/wall.txt``) read as an expression would only give a syntax error
        raise InvalidWall(f"{text!r} is a file, but not a wall file: coinwall reads walls from "
                          f"{' and '.join(WALL_FORMATS)} files (or give an expression in t)")
    if degrees:
        raise InvalidArgument("`degrees` applies to sample files, not to expressions (write the angle in radians)")
    return Wall.from_expression(text, params)


def _read_text(path: str) -> str:
    from .inputfile import read_text

    return read_text(path, what="wall file", error=InvalidWall, max_bytes=MAX_WALL_FILE_BYTES)


def _column_kind(name: str):
    """('angle', in_degrees) or ('value', None) or (None, None) for a header cell."""
    key = name.strip().lower()
    degrees = any(mark in key for mark in ("deg", "°"))
    bare = "".join(ch for ch in key if ch.isalnum() or ch in "θ_").replace("_deg", "").replace("deg", "")
    bare = bare.replace("rad", "").rstrip("_")
    if bare in ("theta", "θ", "angle", "t", "phi", "φ"):
        return "angle", degrees
    if bare in ("b", "h", "wall", "btheta", "bθ", "support", "value"):
        return "value", None
    return None, None


def read_samples_csv(path: str, *, degrees: bool = False):
    """``(theta, b)`` in radians from a CSV of samples, as people write them.

    The delimiter is a comma, a semicolon, a tab or white space (decimal commas are read with a
    semicolon or tab delimiter).  A header row names the columns: ``theta``/``θ``/``angle`` for the
    angle (``theta_deg``, ``Theta (deg)``, ``angle [°]`` in degrees) and ``b``/``h``/``wall`` for the
    wall; without a header there must be exactly two columns, θ in radians (or ``degrees=True``) and b.
    Radian angles spanning more than 2π are refused (they look like degrees).  Every row must be
    complete and numeric: a bad row is an error naming its line, never silently dropped.
    """
    import numpy as np

    text = _read_text(path)
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.split("#", 1)[0].strip()
        if stripped:
            rows.append((number, stripped))
    if not rows:
        raise InvalidWall(f"wall file {path!r} has no rows")
    first = rows[0][1]
    delimiter = next((d for d in (";", "\t", ",") if d in first), None)
    decimal_comma = delimiter in (";", "\t") and any("," in r for _, r in rows[1:6] + rows[:1])

    def cells(line):
        parts = line.split(delimiter) if delimiter else line.split()
        return [c.strip() for c in parts]

    def number(cell):
        return float(cell.replace(",", ".") if decimal_comma else cell)

    header = cells(first)
    try:
        [number(c) for c in header]
        header = None
    except ValueError:
        rows = rows[1:]
    if header is None:
        angle_col, value_col, width = 0, 1, None
        in_degrees = degrees
    else:
        kinds = [_column_kind(c) for c in header]
        angles = [i for i, (k, _) in enumerate(kinds) if k == "angle"]
        values = [i for i, (k, _) in enumerate(kinds) if k == "value"]
        if len(angles) != 1 or len(values) != 1:
            raise InvalidWall(f"wall file {path!r}: columns {header}: name one angle column (theta, θ, angle; "
                              "theta_deg for degrees) and one wall column (b, h, wall)")
        angle_col, value_col, width = angles[0], values[0], len(header)
        in_degrees = degrees or bool(kinds[angle_col][1])
    if len(rows) > MAX_SAMPLES:
        raise InvalidWall(f"wall file {path!r} has {len(rows)} rows; at most {MAX_SAMPLES} samples are read "
                          "(the solvers take minutes beyond): thin the data")
    theta, b = [], []
    for number_, line in rows:
        parts = cells(line)
        if (width is None and len(parts) != 2) or (width is not None and len(parts) != width):
            expected = "2 (theta, b; name the columns in a header row if there are more)" if width is None \
                else str(width)
            raise InvalidWall(f"wall file {path!r}, line {number_}: {len(parts)} columns, expected {expected}")
        try:
            theta.append(number(parts[angle_col]))
            b.append(number(parts[value_col]))
        except ValueError:
            raise InvalidWall(f"wall file {path!r}, line {number_}: not a number in {line!r}") from None
    theta, b = np.array(theta), np.array(b)
    if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(b))):
        bad = int(np.flatnonzero(~(np.isfinite(theta) & np.isfinite(b)))[0])
        raise InvalidWall(f"wall file {path!r}: sample {bad + 1} is not finite")
    if in_degrees:
        theta = np.radians(theta)
    elif theta.size and np.ptp(theta) > 2 * np.pi * (1 + 1e-9):
        raise InvalidWall(f"wall file {path!r}: the angles span {np.ptp(theta):.6g}, more than 2π radians: are they "
                          "degrees? Name the column theta_deg, or pass --degrees")
    return theta, b


def load_wall_file(path: str, *, degrees: bool = False):
    """A wall from a file: ``.csv`` samples (:func:`read_samples_csv`) or ``.json``: Fourier coefficients
    ``{"a0", "cos", "sin"}`` or samples ``{"theta": […], "b": […]}`` (``"degrees": true`` allowed)."""
    from ..wall import Wall

    if path.lower().endswith(".csv"):
        theta, b = read_samples_csv(path, degrees=degrees)
        # numbers written as text carry their rounding in their digits
        return Wall.from_samples(theta, b, rounding=rounding_of(b))
    from .inputfile import read_json

    doc = read_json(path, what="wall file", error=InvalidWall, max_bytes=MAX_WALL_FILE_BYTES)
    if not isinstance(doc, dict):
        raise InvalidWall(f"wall file {path!r}: expected an object with {', '.join(FOURIER_KEYS)} "
                          f"or with {', '.join(SAMPLE_KEYS)}")
    try:
        if set(doc) & set(SAMPLE_KEYS):
            unknown = set(doc) - set(SAMPLE_KEYS) - {"degrees", "note"}
            if unknown:
                raise InvalidWall(f"wall file {path!r}: unknown keys {sorted(unknown)}; "
                                  f"expected {', '.join(SAMPLE_KEYS)}")
            theta, b = (_numbers(doc.get(k), path, k) for k in SAMPLE_KEYS)
            if not isinstance(doc.get("degrees", False), bool):
                raise InvalidWall(f"wall file {path!r}: `degrees` must be true or false, got {doc['degrees']!r}")
            if doc.get("degrees", False) is True or degrees:
                import numpy as np

                theta = np.radians(theta)
            return Wall.from_samples(theta, b, rounding=rounding_of(b))
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
