"""The one place that opens a user's input file: regular files only, a size limit, decoding errors in one line.

Every reader of :mod:`coinwall.forward.formats` (wall samples CSV/JSON, SVG, DXF, body JSON, points CSV)
reads its file through :func:`read_bytes` or :func:`read_text`, so that

* a FIFO, a device (``/dev/zero``, ``/dev/urandom``), a folder or a socket is refused by
  :func:`os.stat` *before* it is opened, and checked again with :func:`os.fstat` on the open
  descriptor, which is opened with ``O_NONBLOCK`` so that a FIFO swapped in between cannot block;
* a file larger than the limit of its format (:data:`MAX_BYTES`) is refused before it is read, and at
  most one byte more than the limit is ever read (a file that grows while it is read is refused too);
* text that is not in its encoding is one line naming the file and the offset of the first bad byte.

The limits (:data:`MAX_BYTES`) follow from what the parsers hold in memory and time, measured on this
project's readers (docs/cli-limits.md has the numbers): the readers keep the file, its parse tree and the
points of every curve in memory, a few times the file's size; the counts that bound the work once the
file is parsed (rows, path segments, DXF entities, flattened points) are checked by the readers.
"""

from __future__ import annotations

import errno
import os
import stat

from ..errors import InvalidOutline
from .output import note_input

__all__ = ["MAX_BYTES", "MAX_NESTING", "check_regular", "file_kind", "json_nesting", "json_number", "read_bytes",
           "read_json", "read_text"]

#: largest file read, by format, in bytes.  CSV and JSON samples: 64 MiB is ~3·10⁶ rows, beyond the rows
#: the solver takes in reasonable time (the readers bound rows separately).  SVG: 32 MiB holds 10⁶ path
#: segments, more than the readers accept, and Python's XML tree takes ~10× the file.  DXF: ezdxf keeps
#: ~1.2 kB per entity, ~25× the text (2·10⁵ circles, 9 MB: 0.24 GB, 28 s); 64 MiB of DXF is ~10⁶ short
#: entities, and the entity count is bounded separately (before parsing).  Body JSON: as wall JSON.
MAX_BYTES = {".csv": 64 * 2**20, ".json": 64 * 2**20, ".svg": 32 * 2**20, ".dxf": 64 * 2**20}
#: deepest nesting of JSON arrays/objects or XML elements a reader accepts (Python's parsers recurse;
#: coinwall's files nest 3 deep, drawings a few dozen)
MAX_NESTING = 200

_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def file_kind(mode: int) -> str:
    """What a file of ``st_mode`` ``mode`` is, in words ("a FIFO (named pipe)", "a folder" …)."""
    for test, words in _KINDS:
        if test(mode):
            return words
    return "not a regular file"


def _limit(path: str, max_bytes: int | None) -> int:
    if max_bytes is not None:
        return int(max_bytes)
    return MAX_BYTES.get(os.path.splitext(path)[1].lower(), min(MAX_BYTES.values()))


def _size(n: int) -> str:
    return f"{n / 2**20:.3g} MiB" if n >= 2**20 else f"{n} bytes"


def check_regular(path, *, what: str = "input file", error=InvalidOutline, max_bytes: int | None = None) -> int:
    """Refuse ``path`` unless it names an existing regular file (symbolic links followed) of at most
    ``max_bytes`` (default: :data:`MAX_BYTES` of its extension); returns its size.

    Raises
    ------
    error
        "<what> 'path' does not exist", "... is not a regular file (a FIFO ...)", "... is too large".
    """
    if not isinstance(path, (str, os.PathLike)):
        raise error(f"{what} must be a file name, got {path!r}")
    path = os.fspath(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise error(f"{what} {path!r} does not exist") from None
    except OSError as exc:
        raise error(f"{what} {path!r} is not readable: {exc.strerror or exc}") from None
    except ValueError:  # a NUL byte in the name
        raise error(f"{what} {path!r} is not a valid file name") from None
    _check_info(path, info, what, error, _limit(path, max_bytes))
    return int(info.st_size)


def _check_info(path, info, what, error, limit):
    if not stat.S_ISREG(info.st_mode):
        raise error(f"{what} {path!r} is not a regular file (it is {file_kind(info.st_mode)}); "
                    "give the name of a file on disk")
    if info.st_size > limit:
        raise error(f"{what} {path!r} is too large: {_size(info.st_size)}, at most {_size(limit)} are read "
                    f"for {os.path.splitext(path)[1] or 'this format'} files")


def read_bytes(path, *, what: str = "input file", error=InvalidOutline, max_bytes: int | None = None) -> bytes:
    """The content of the regular file ``path``, at most ``max_bytes`` (default :data:`MAX_BYTES` of its
    extension).

    The file is checked with :func:`os.stat` before it is opened, opened without blocking (a FIFO
    swapped in after the check cannot block) and checked again on the open descriptor.

    Raises
    ------
    error
        Missing, not a regular file, larger than the limit, or unreadable; one line naming the file.
    """
    check_regular(path, what=what, error=error, max_bytes=max_bytes)
    path = os.fspath(path)
    limit = _limit(path, max_bytes)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        descriptor = os.open(path, flags)
    except FileNotFoundError:
        raise error(f"{what} {path!r} does not exist") from None
    except OSError as exc:
        if exc.errno == errno.ENXIO:  # a FIFO without a writer, swapped in after the check
            raise error(f"{what} {path!r} is not a regular file (it is a FIFO (named pipe))") from None
        raise error(f"{what} {path!r} is not readable: {exc.strerror or exc}") from None
    try:
        _check_info(path, os.fstat(descriptor), what, error, limit)
        note_input(path)  # a command's input is never one of its outputs (output.command_scope)
        chunks, total = [], 0
        while total <= limit:
            chunk = os.read(descriptor, min(1 << 20, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
    except OSError as exc:
        raise error(f"{what} {path!r} is not readable: {exc.strerror or exc}") from None
    finally:
        os.close(descriptor)
    if total > limit:  # the file grew after it was measured
        raise error(f"{what} {path!r} is too large: more than {_size(limit)}")
    return b"".join(chunks)


def read_text(path, *, what: str = "input file", error=InvalidOutline, max_bytes: int | None = None,
              encoding: str = "utf-8-sig") -> str:
    """The content of the regular file ``path`` (see :func:`read_bytes`) decoded as ``encoding`` (UTF-8,
    a byte-order mark skipped); a byte that is not in the encoding is one line with its offset."""
    data = read_bytes(path, what=what, error=error, max_bytes=max_bytes)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise error(f"{what} {os.fspath(path)!r} is not {_encoding_name(encoding)} text: byte "
                    f"0x{data[exc.start]:02x} at offset {exc.start}") from None


_JSON_STRING = None


def json_nesting(text: str) -> int:
    """Deepest nesting of arrays and objects in the JSON ``text`` (brackets inside strings do not count).

    Linear in the text and without recursion, so that it can be asked before :func:`json.loads`
    (which recurses once per level).
    """
    import re

    import numpy as np

    global _JSON_STRING
    if _JSON_STRING is None:
        _JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')
    brackets = _JSON_STRING.sub("", text).encode("utf-8", "surrogatepass")
    codes = np.frombuffer(brackets, dtype=np.uint8)
    step = (np.isin(codes, (ord("["), ord("{"))).astype(np.int64)
            - np.isin(codes, (ord("]"), ord("}"))).astype(np.int64))
    return int(np.cumsum(step).max(initial=0))


def read_json(path, *, what: str = "input file", error=InvalidOutline, max_bytes: int | None = None):
    """The JSON document in the regular file ``path`` (see :func:`read_bytes`), nested at most
    :data:`MAX_NESTING` deep.  The literals ``NaN``, ``Infinity`` and ``-Infinity`` (which Python's
    :mod:`json` accepts) are read as floats, so that the caller can name the key that holds one."""
    import json

    text = read_text(path, what=what, error=error, max_bytes=max_bytes)
    name = os.fspath(path)
    depth = json_nesting(text)
    if depth > MAX_NESTING:
        raise error(f"{what} {name!r} is nested {depth} levels deep; coinwall reads JSON nested at most "
                    f"{MAX_NESTING} deep")
    try:
        return json.loads(text)
    except (ValueError, RecursionError) as exc:
        detail = str(exc).splitlines()[0][:160] if str(exc) else type(exc).__name__
        raise error(f"{what} {name!r} is not valid JSON: {detail}") from None


def _encoding_name(encoding: str) -> str:
    return "UTF-8" if encoding.lower().replace("_", "-").startswith("utf-8") else encoding


def json_number(item, where: str, prefix: str, *, error=InvalidOutline, what: str = "numbers") -> float:
    """``item`` from a JSON document as a finite float, or ``error`` naming ``where`` (a key and index).

    Strings, booleans and ``null`` are not numbers (Python's ``float`` would take ``"1"`` and ``True``);
    NaN and Infinity (which Python's :mod:`json` reads) and integers too large for a float are refused.
    ``prefix`` starts every message (e.g. "body file 'b.json': "), ``what`` says what the numbers are.
    """
    import math
    import numbers
    import reprlib

    if isinstance(item, bool) or not isinstance(item, numbers.Real):
        raise error(f"{prefix}{where} must be a number, got {reprlib.repr(item)}")
    try:
        number = float(item)
    except OverflowError:
        number = math.inf
    if not math.isfinite(number):
        if not isinstance(item, float):
            raise error(f"{prefix}{where} is an integer of {len(str(item))} digits, too large for a floating-point "
                        "number")
        raise error(f"{prefix}{where} must be a finite number, got {item!r:.30} (NaN and Infinity are not {what})")
    return number
