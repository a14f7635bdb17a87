"""Validators of arguments, in one place, each named after what it checks (like scipy's ``_ivp/common.py``).

Each returns the value in its canonical type or raises :class:`~coinwall.forward.errors.InvalidArgument`
(or the error class passed as ``error``) with a message that names the argument, the value given and
what would be valid.  Library messages name *arguments* (``kappa``); the command line maps them to its
flags.
"""

from __future__ import annotations

import math
import numbers
import re

from .errors import InvalidArgument

__all__ = ["ASCII_BLANKS", "DECIMAL", "parse_number", "parse_number_list", "check_count", "check_finite", "check_positive",
           "check_choice", "check_range", "check_memory", "check_seed",
           "available_memory", "is_integer", "MEMORY_FRACTION"]

# a request may use at most this fraction of the memory available when it starts (the rest is for the
# interpreter, the libraries and the copies numpy makes on the way)
MEMORY_FRACTION = 0.5

#: The one grammar of numbers a user types or writes — flags, parameters, list items, sample files: ASCII
#: decimal digits with an optional sign, point and exponent (``-1e-3``, ``.5``), or inf/nan (left to the range
#: checks, which say why they are refused).  Python's ``float`` would also take ``1_0`` and other scripts'
#: digits (``１``, ``١``), which no flag takes.
DECIMAL = re.compile(r"[+-]?((\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|inf|infinity|nan)", re.IGNORECASE | re.ASCII)


#: The blanks a number may stand between: ASCII ones.  ``str.strip`` and ``float`` also drop a no-break space
#: (U+00A0) and the other Unicode spaces, which no message could show; a number is ASCII, blanks included.
ASCII_BLANKS = " \t\n\r\f\v"


def parse_number(text: str) -> float:
    """``text`` as a number of the one grammar (:data:`DECIMAL`) between ASCII blanks; ValueError else.

    >>> parse_number(" -2.5e-3 ")
    -0.0025
    >>> parse_number("\u00a0-0.3")
    Traceback (most recent call last):
    ...
    ValueError: not a decimal number: '\xa0-0.3' (character U+00A0 NO-BREAK SPACE at column 1: numbers are ASCII)
    """
    if not isinstance(text, str):
        raise ValueError(f"not a decimal number: {text!r}")
    stripped = text.strip(ASCII_BLANKS)
    if not DECIMAL.fullmatch(stripped):
        raise ValueError(f"not a decimal number: {text!r}{_foreign(text)}")
    return float(stripped)


def _foreign(text: str) -> str:
    """`` (character U+00A0 NO-BREAK SPACE at column 1: numbers are ASCII)`` for the first non-ASCII character."""
    import unicodedata

    for column, char in enumerate(text, start=1):
        if ord(char) > 127:
            return (f" (character U+{ord(char):04X} {unicodedata.name(char, 'unnamed')} at column {column}: numbers "
                    "are ASCII)")
    return ""


def parse_number_list(name: str, text: str, *, error=InvalidArgument) -> list[float]:
    """Comma-separated numbers of the one grammar, finite, no item empty (``3,,4`` is refused, not read as
    ``3,4``); one line naming ``name`` and the bad item otherwise."""
    items = str(text).split(",")
    values = []
    for index, item in enumerate(items, start=1):
        if not item.strip(ASCII_BLANKS):
            raise error(f"`{name}` must be comma-separated numbers; item {index} of {text!r} is empty")
        try:
            value = parse_number(item)
        except ValueError:
            raise error(f"`{name}` must be comma-separated numbers; item {index} ({item.strip(ASCII_BLANKS)!r}) of "
                        f"{text!r} is not a decimal number{_foreign(item)}") from None
        if not math.isfinite(value):
            raise error(f"`{name}` must be finite numbers; item {index} of {text!r} is {item.strip()}")
        values.append(value)
    return values


def is_integer(value) -> bool:
    """True for Python and NumPy integers, False for ``bool`` (an integer to Python, never a count to us)."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def check_count(name: str, value, *, minimum: int = 1, maximum: int | None = None, error=InvalidArgument) -> int:
    """``value`` as an ``int`` in ``[minimum, maximum]``; ``bool`` and non-integers are refused."""
    if not is_integer(value):
        raise error(f"`{name}` must be an integer, got {value!r}")
    value = int(value)
    if value < minimum or (maximum is not None and value > maximum):
        valid = f">= {minimum}" if maximum is None else f"from {minimum} to {maximum}"
        raise error(f"`{name}` must be an integer {valid}, got {value}")
    return value


def check_seed(value, name: str = "seed", *, error=InvalidArgument):
    """``value`` as a seed of NumPy's generators: ``None`` (fresh entropy) or an integer >= 0.

    Examples
    --------
    >>> check_seed(7), check_seed(None)
    (7, None)
    >>> check_seed(-1)
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidArgument: `seed` must be a non-negative integer, got -1
    """
    if value is not None and not (is_integer(value) and value >= 0):
        raise error(f"`{name}` must be a non-negative integer, got {value!r}")
    return None if value is None else int(value)


def check_finite(name: str, value, *, error=InvalidArgument) -> float:
    """``value`` as a finite ``float``; ``bool``, strings and non-finite numbers are refused."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise error(f"`{name}` must be a finite number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise error(f"`{name}` must be finite, got {value}")
    return value


def check_positive(name: str, value, *, error=InvalidArgument) -> float:
    """``value`` as a finite ``float`` > 0."""
    value = check_finite(name, value, error=error)
    if value <= 0:
        raise error(f"`{name}` must be positive, got {value:g}")
    return value


def check_choice(name: str, value, choices, *, error=InvalidArgument):
    """``value`` if it is one of ``choices``."""
    if value not in choices:
        raise error(f"`{name}` must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value


def check_range(name: str, value, low: float, high: float, *, why: str = "", error=InvalidArgument) -> float:
    """``value`` as a finite ``float`` in ``[low, high]``; ``why`` (e.g. "so the kernel keeps 1e-9 precision
    in θ") is added to the message."""
    value = check_finite(name, value, error=error)
    if not low <= value <= high:
        raise error(f"`{name}` must be between {low:g} and {high:g}{'; ' + why if why else ''}, got {value:g}")
    return value


def available_memory() -> int:
    """Bytes of memory this process can still use: ``MemAvailable`` of ``/proc/meminfo``, lowered to the
    address-space limit (``ulimit -v``) when one is set; 8 GiB where neither can be read."""
    available = None
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    available = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        pass
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
        if soft != resource.RLIM_INFINITY:
            available = soft if available is None else min(available, soft)
    except (ImportError, OSError, ValueError):
        pass
    return int(available) if available is not None else 8 * 2 ** 30


def _bytes(n: float) -> str:
    for unit, size in (("GiB", 2 ** 30), ("MiB", 2 ** 20), ("KiB", 2 ** 10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} bytes"


def check_memory(what: str, nbytes: float, *, error=InvalidArgument) -> float:
    """Refuse, before any work, a request whose estimated memory ``nbytes`` exceeds
    :data:`MEMORY_FRACTION` of :func:`available_memory`.

    ``what`` names the request in the words of the message, e.g. "`collisions` = 10000000000 (6 columns of
    8 bytes per collision)"; the message gives the estimate and the limit.
    """
    limit = MEMORY_FRACTION * available_memory()
    if not nbytes <= limit:  # also refuses nan
        raise error(f"{what} needs about {_bytes(nbytes)} of memory, more than the {_bytes(limit)} this machine "
                    f"can give it; ask for less")
    return nbytes
