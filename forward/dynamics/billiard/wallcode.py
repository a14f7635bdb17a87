"""A :class:`~coinwall.forward.wall.Wall` as plain Python source that numba can compile.

casadi functions cannot be called from numba, so the billiard kernel needs the
wall as ordinary code.  This module writes that code:

* expression walls: casadi's own algorithm for ``(b, b')`` (the instruction
  list of a ``casadi.Function``: ``n_instructions``, ``instruction_id``,
  ``instruction_input``, ``instruction_output``, ``instruction_constant``) is
  translated instruction by instruction into Python with :mod:`math`.  The
  translation is literal, so it computes the same floating-point operations
  as casadi (same derivative rules, including ``sign(0) = 0`` for ``abs``).
  Numeric constants are not written into the source but read from an array
  ``c``, so walls that differ only in parameter values (ε = 0.55 and ε = 99)
  share one compiled function.
* Fourier walls (and sample walls, which are Fourier walls internally): one
  fixed source, the trigonometric sum by the angle-addition recurrence, with
  the coefficients in ``c``.

The source defines ``wall_b1(phi, c) -> (b, db)`` and ``wall_b2(phi, c) -> (b, db, d2b)``
(the kernel's last evaluation before a contact needs b'', see :mod:`coinwall.forward.dynamics.billiard._kernel`);
it runs as plain Python too
(tests compare it with :meth:`Wall.derivatives` without compiling anything).

The second half of the module is the on-disk cache of compiled kernels (:func:`cache_dir`,
:func:`load_module`, :func:`seal`): used only in a folder the user alone can write, modules executed only
from verified bytes, numba's files loaded only when their checksums match; otherwise the kernel is
compiled in memory (the comment above :func:`cache_dir` says why).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import re
import stat
import sys
import tempfile
import types

import numpy as np

from ...errors import InvalidWall

__all__ = ["cache_dir", "discard", "load_module", "python_wall", "seal", "wall_source"]

FOURIER_SOURCE = '''
{decorator}def wall_b2(phi, c):
    # c = [a0, n, cos_1..cos_n, sin_1..sin_n]; cos kφ, sin kφ by the angle-addition
    # recurrence (one cos and one sin call instead of 2n; error grows like n·1e-16)
    n = int(c[1])
    c1 = math.cos(phi)
    s1 = math.sin(phi)
    ck = c1
    sk = s1
    b = c[0]
    db = 0.0
    d2b = 0.0
    for k in range(1, n + 1):
        a = c[1 + k]
        s = c[1 + n + k]
        term = a * ck + s * sk
        b += term
        db += k * (s * ck - a * sk)
        d2b -= k * k * term
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
    return b, db, d2b


{decorator}def wall_b1(phi, c):
    # b and b' only (the compiler drops the unused b'' sum)
    b, db, d2b = wall_b2(phi, c)
    return b, db
'''


def _op_table():
    import casadi as ca

    unary = {ca.OP_ASSIGN: "{x}", ca.OP_NEG: "-{x}", ca.OP_EXP: "math.exp({x})", ca.OP_LOG: "math.log({x})",
             ca.OP_SQRT: "math.sqrt({x})", ca.OP_SQ: "{x} * {x}", ca.OP_TWICE: "2.0 * {x}",
             ca.OP_SIN: "math.sin({x})", ca.OP_COS: "math.cos({x})", ca.OP_TAN: "math.tan({x})",
             ca.OP_ASIN: "math.asin({x})", ca.OP_ACOS: "math.acos({x})", ca.OP_ATAN: "math.atan({x})",
             ca.OP_SINH: "math.sinh({x})", ca.OP_COSH: "math.cosh({x})", ca.OP_TANH: "math.tanh({x})",
             ca.OP_ASINH: "math.asinh({x})", ca.OP_ACOSH: "math.acosh({x})", ca.OP_ATANH: "math.atanh({x})",
             ca.OP_FABS: "abs({x})", ca.OP_INV: "1.0 / {x}", ca.OP_FLOOR: "float(math.floor({x}))",
             ca.OP_CEIL: "float(math.ceil({x}))", ca.OP_ERF: "math.erf({x})", ca.OP_LOG1P: "math.log1p({x})",
             ca.OP_EXPM1: "math.expm1({x})", ca.OP_NOT: "(1.0 if {x} == 0.0 else 0.0)",
             # casadi's sign: 0 at 0 (so d|x|/dx = 0 there, as in Wall.derivatives)
             ca.OP_SIGN: "(1.0 if {x} > 0.0 else (-1.0 if {x} < 0.0 else 0.0))"}
    binary = {ca.OP_ADD: "{x} + {y}", ca.OP_SUB: "{x} - {y}", ca.OP_MUL: "{x} * {y}", ca.OP_DIV: "{x} / {y}",
              ca.OP_POW: "{x} ** {y}", ca.OP_CONSTPOW: "{x} ** {y}", ca.OP_LT: "(1.0 if {x} < {y} else 0.0)",
              ca.OP_LE: "(1.0 if {x} <= {y} else 0.0)", ca.OP_EQ: "(1.0 if {x} == {y} else 0.0)",
              ca.OP_NE: "(1.0 if {x} != {y} else 0.0)",
              ca.OP_AND: "(1.0 if ({x} != 0.0 and {y} != 0.0) else 0.0)",
              ca.OP_OR: "(1.0 if ({x} != 0.0 or {y} != 0.0) else 0.0)",
              ca.OP_IF_ELSE_ZERO: "({y} if {x} != 0.0 else 0.0)", ca.OP_FMIN: "min({x}, {y})",
              ca.OP_FMAX: "max({x}, {y})", ca.OP_COPYSIGN: "math.copysign({x}, {y})",
              ca.OP_ATAN2: "math.atan2({x}, {y})", ca.OP_FMOD: "math.fmod({x}, {y})",
              ca.OP_HYPOT: "math.hypot({x}, {y})"}
    return unary, binary


def _translate(func, name, unary, binary, constants, text):
    """Python source of one casadi Function of one input (its instruction list, translated literally)."""
    import casadi as ca

    outputs = func.n_out()
    lines = [f"def {name}(phi, c):"] + [f"    o{k} = 0.0" for k in range(outputs)]
    for k in range(func.n_instructions()):
        op = func.instruction_id(k)
        ins = func.instruction_input(k)
        outs = func.instruction_output(k)
        if op == ca.OP_CONST:
            constants.append(float(func.instruction_constant(k)))
            lines.append(f"    w{outs[0]} = c[{len(constants) - 1}]")
        elif op == ca.OP_INPUT:
            lines.append(f"    w{outs[0]} = phi")
        elif op == ca.OP_OUTPUT:
            lines.append(f"    o{outs[0]} = w{ins[0]}")
        elif op in unary:
            lines.append(f"    w{outs[0]} = " + unary[op].format(x=f"w{ins[0]}"))
        elif op in binary:
            lines.append(f"    w{outs[0]} = " + binary[op].format(x=f"w{ins[0]}", y=f"w{ins[1]}"))
        else:
            raise InvalidWall(f"wall {text!r}: casadi operation {op} has no numba translation; "
                              f"give the wall as samples or a Fourier series instead")
    lines.append("    return " + ", ".join(f"o{k}" for k in range(outputs)))
    return "\n".join(lines) + "\n"


def _expression_source(parsed, decorator):
    """Translate casadi's algorithms for ``(b, b')`` and ``(b, b', b'')`` into Python source + constants."""
    import casadi as ca

    t = parsed.symbol
    d1 = ca.jacobian(parsed.expr, t)
    unary, binary = _op_table()
    constants = []  # both functions read one array (their constants one after the other)
    sources = [_translate(ca.Function(name, [t], outputs), name, unary, binary, constants, parsed.text)
               for name, outputs in (("wall_b1", [parsed.expr, d1]),
                                     ("wall_b2", [parsed.expr, d1, ca.jacobian(d1, t)]))]
    return "\n\n".join(decorator + src for src in sources), np.array(constants or [0.0])


def wall_source(wall, decorator: str = ""):
    """Python source of ``wall_b1(phi, c) -> (b, b')`` and ``wall_b2(phi, c) -> (b, b', b'')``.

    Parameters
    ----------
    wall : Wall
    decorator : str
        A line put before each ``def`` (e.g. ``"@njit(cache=True)\\n"``); empty for plain Python.

    Returns
    -------
    source : str
        Two function definitions using only :mod:`math` (no imports inside).
    constants : numpy.ndarray
        The array to pass as ``c`` (to either function).
    """
    backend = wall._backend
    if hasattr(backend, "parsed"):
        return _expression_source(backend.parsed, decorator)
    if hasattr(backend, "cos") and hasattr(backend, "sin"):
        n = backend.cos.size
        constants = np.concatenate([[backend.a0, float(n)], backend.cos, backend.sin])
        return FOURIER_SOURCE.format(decorator=decorator), constants
    raise InvalidWall(f"wall {wall.description!r} is built from exact {wall.kind}; the compiled billiard takes walls "
                      "given as an expression, Fourier coefficients or samples (a CSV of b(θ) at many angles works)")


def python_wall(wall, order: int = 1):
    """The generated ``wall_b1`` (``order=1``) or ``wall_b2`` (``order=2``) as a plain Python function of one angle.

    Uncompiled, for checks against :meth:`Wall.derivatives`.
    """
    source, constants = wall_source(wall)
    namespace = {"math": math}
    exec(compile(source, "<coinwall wall code>", "exec"), namespace)  # noqa: S102 -- our own generated source
    func = namespace["wall_b1" if order == 1 else "wall_b2"]
    return lambda phi: func(float(phi), constants)


# ---------------------------------------------------------------------------------------------------- the cache
# Trust.  Generated modules are executed and numba's cache files are pickles (and machine code): whoever
# can write into the cache folder can run code as the user.  So the cache is used only in a folder the
# user owns and nobody else can write (checked on the folder and on the one that holds it, every level
# coinwall creates is made 0700), a module is executed only from bytes equal to the source we generated
# (its name is the hash of that source), and numba's files are loaded only when their SHA-256 matches the
# manifest written after they were made (a truncated, emptied or garbled file, e.g. from a full disk or an
# interrupted write, is discarded and rebuilt: garbled machine code would otherwise crash with SIGILL,
# which no exception handler can catch).  Otherwise the kernel is compiled in memory (numba cache=False):
# nothing is read from or written to disk, at the price of compiling in every process.

_NOTED: set = set()


def _note(text: str) -> None:
    """One ``coinwall: note: ...`` line on stderr, once per process and text (the CLI's style of notice)."""
    if text not in _NOTED:
        _NOTED.add(text)
        print(f"coinwall: note: {text}", file=sys.stderr)


def _untrusted(path: str) -> str:
    """Why ``path`` cannot hold the cache ('' when it can): a directory of ours that no one else can write."""
    try:
        info = os.stat(path)
    except OSError as exc:
        return f"cannot use it ({exc.strerror or exc})"
    if not stat.S_ISDIR(info.st_mode):
        return "it is not a folder"
    if hasattr(os, "getuid") and info.st_uid != os.getuid():
        return f"it belongs to user id {info.st_uid}, not to this user ({os.getuid()})"
    if info.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        return f"others can write to it (mode {stat.S_IMODE(info.st_mode):o}; fix: chmod go-w {path})"
    if not os.access(path, os.W_OK | os.X_OK):
        return "it is not writable"
    return ""


def _private_folder(path: str) -> None:
    """Create ``path`` and each missing level above it with mode 0700 (existing levels are left as they are)."""
    missing = []
    while not os.path.lexists(path):
        missing.append(path)
        parent = os.path.dirname(path)
        if parent == path:
            break
        path = parent
    for level in reversed(missing):
        try:
            os.mkdir(level, 0o700)
        except FileExistsError:  # another process made it a moment ago: checked like any other folder
            pass


def _trusted(base: str) -> tuple:
    """``(folder, '')`` for the versioned cache folder under ``base`` if it and ``base`` can be trusted,
    else ``(folder, why not)``.  Nothing is created inside a ``base`` that fails the checks."""
    import numba

    folder = os.path.join(base, f"billiard-numba{numba.__version__}-py{sys.version_info[0]}{sys.version_info[1]}")
    levels = (base, folder, os.path.join(folder, "__pycache__"))  # numba's own folder too, before numba makes it
    for level in levels:
        try:
            _private_folder(level)
        except OSError as exc:
            return folder, f"cannot create {level} ({exc.strerror or exc})"
        why = _untrusted(level)
        if why:
            return folder, f"{level}: {why}"
    return folder, ""


def cache_dir():
    """Folder for generated modules and numba's on-disk cache, or ``None`` when no trusted folder is available.

    ``$COINWALL_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/coinwall`` (``~/.cache/coinwall``), each with a
    subfolder per numba and Python version.  Trusted only if this user owns it and the folder above it and
    neither is writable by group or others (levels coinwall creates are made 0700).  When the default
    folder cannot be used, ``<temp>/coinwall-<uid>`` is tried under the same checks (never for an explicit
    ``$COINWALL_CACHE_DIR``: the user chose that place).  ``None`` (after one ``coinwall: note:`` line on
    stderr) means: compile in memory.
    """
    chosen = os.environ.get("COINWALL_CACHE_DIR")
    default = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
                           "coinwall")
    candidates = [chosen] if chosen else [default, os.path.join(
        tempfile.gettempdir(), f"coinwall-{os.getuid() if hasattr(os, 'getuid') else 0}")]
    reasons = []
    for base in candidates:
        folder, why = _trusted(os.path.abspath(base))
        if not why:
            return folder
        reasons.append(why)
    _note(f"not using the kernel cache ({'; '.join(reasons)}); compiling in memory (slower start, nothing "
          f"read from or written to disk)")
    return None


def _write_atomic(folder: str, name: str, data: bytes) -> None:
    """Write ``data`` to ``folder/name`` through a temporary file and a rename: readers (other processes
    compiling the same wall) see the old file or the whole new one, never a part.  The temporary has a
    marked name (:func:`coinwall.forward.formats.output.marked_name`), so that only temporaries this program
    made are ever swept (:func:`_sweep_temporaries`)."""
    from ...formats.output import marked_name

    _clear_name(os.path.join(folder, name))
    temp = marked_name(folder, "part")
    fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o600)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(temp, os.path.join(folder, name))
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temp)
        raise


def _numba_files(folder: str, name: str) -> list:
    """numba's index and data files of module ``name`` (``__pycache__/<name>.<function>-<line>.pyXY[.k].nb?``)."""
    pycache = os.path.join(folder, "__pycache__")
    try:
        entries = os.listdir(pycache)
    except OSError:
        return []
    return sorted(os.path.join(pycache, e) for e in entries
                  if e.startswith(name + ".") and e.endswith((".nbi", ".nbc")))


def _digest(path: str) -> str:
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


def _check_numba_files(folder: str, name: str) -> None:
    """Delete numba's files of ``name`` unless every one is listed, with its SHA-256, in ``<name>.sums``."""
    for path in [os.path.join(folder, name + ".sums"), *_numba_files(folder, name)]:
        _clear_name(path)
    files = _numba_files(folder, name)
    if not files:
        return
    try:
        with open(os.path.join(folder, name + ".sums"), encoding="utf-8") as fh:
            sums = json.load(fh)
        if not isinstance(sums, dict):
            sums = {}
    except (OSError, ValueError):
        sums = {}
    if all(sums.get(os.path.basename(f)) == _digest(f) for f in files):
        return
    discard(folder, name, keep_source=True)
    _note(f"discarded damaged or unverified compiled-kernel cache files of {name} in {folder}; compiling again")


def seal(module) -> None:
    """Record the SHA-256 of numba's cache files of ``module`` (call after its functions were compiled).

    Only these recorded files are loaded later (:func:`load_module`); a file numba writes afterwards,
    or one that changed, is discarded and rebuilt.  Does nothing for a module compiled in memory.
    """
    folder = getattr(module, "COINWALL_CACHE_FOLDER", None)
    if folder is None:
        return
    name = module.__name__
    try:
        _clear_name(os.path.join(folder, name + ".sums"))
        sums = json.dumps({os.path.basename(f): _digest(f) for f in _numba_files(folder, name)}, indent=0,
                          sort_keys=True).encode()
        path = os.path.join(folder, name + ".sums")
        try:
            with open(path, "rb") as fh:
                unchanged = fh.read() == sums
        except FileNotFoundError:
            unchanged = False
        if not unchanged:  # (a process that only loaded the kernel has nothing new to record)
            _write_atomic(folder, name + ".sums", sums)
    except OSError:
        pass  # unsealed files are simply rebuilt by the next process


def discard(folder: str, name: str, keep_source: bool = False) -> None:
    """Delete module ``name``'s numba files and manifest (and its source unless ``keep_source``)."""
    paths = _numba_files(folder, name) + [os.path.join(folder, name + ".sums")]
    if not keep_source:
        paths.append(os.path.join(folder, name + ".py"))
    for path in paths:
        _clear_name(path)
        with contextlib.suppress(FileNotFoundError):
            os.unlink(path)


# numba's own temporaries (numba.core.caching._CacheImpl: "<file>.tmp.<16 hex>"), of our modules only
_NUMBA_TEMP = re.compile(r"coinwall_[a-z_]+_[0-9a-f]{20}\..+\.nb[ic]\.tmp\.[0-9a-f]{16}")
# the temporaries of coinwall before marked names (tempfile.mkstemp(prefix=".tmp-", suffix=".part")): made in the
# cache folder, which only coinwall writes (owner-only, checked), so this exact form is taken as ours there
_LEGACY_TEMP = re.compile(r"\.tmp-[a-z0-9_]{8}\.part")
_SWEPT: set = set()


def _sweep_temporaries(folder: str, age: float = 3600.0) -> int:
    """Remove the temporaries left in the cache folder by killed processes, older than ``age`` seconds (or whose
    process is gone), once per process and folder; returns how many.  Only ours: marked names
    (:func:`coinwall.forward.formats.output.sweep_stale`), numba's temporaries of our generated modules in
    ``__pycache__``, and the exact form of coinwall's earlier temporaries; regular files owned by this user."""
    import time

    from ...formats.output import sweep_stale

    if folder in _SWEPT:
        return 0
    _SWEPT.add(folder)
    removed = len(sweep_stale(folder, age))
    now = time.time()
    uid = os.getuid() if hasattr(os, "getuid") else None
    for place, pattern in ((folder, _LEGACY_TEMP), (os.path.join(folder, "__pycache__"), _NUMBA_TEMP)):
        with contextlib.suppress(OSError):
            for entry in os.scandir(place):
                if not pattern.fullmatch(entry.name):
                    continue
                with contextlib.suppress(OSError):
                    info = entry.stat(follow_symlinks=False)
                    if stat.S_ISREG(info.st_mode) and (uid is None or info.st_uid == uid) \
                            and now - info.st_mtime > age:
                        os.unlink(entry.path)
                        removed += 1
    return removed


def _clear_name(path: str) -> None:
    """Make room for a file of ours at ``path`` in the cache folder: something there that is not a regular file
    (a folder, however deep, a link, a FIFO) is not ours to delete, so it is moved aside, with a note, to
    ``<name>.not-a-file-<random>``; a cache that could never write its manifest again would never heal."""
    import secrets

    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return
    if stat.S_ISREG(info.st_mode):
        return
    aside = f"{path}.not-a-file-{secrets.token_hex(4)}"
    os.rename(path, aside)
    _note(f"moved {path} aside to {aside}: the kernel cache keeps a file of its own there, and it was not a file")


def _stored(folder: str, name: str, data: bytes) -> str:
    """Path of ``folder/name.py`` holding exactly ``data``: a file with other content (damaged, or planted by
    someone) is replaced, with its numba files, before anything of it is used."""
    path = os.path.join(folder, name + ".py")
    _clear_name(path)
    try:
        with open(path, "rb") as fh:
            stored = fh.read(len(data) + 1)
    except FileNotFoundError:
        stored = None
    if stored != data:  # equal bytes ⇔ equal SHA-256, which is the module's name: the file is what we made
        if stored is not None:
            _note(f"discarded {path}: its content does not match its name (damaged or foreign); writing it again")
        discard(folder, name, keep_source=True)
        _write_atomic(folder, name + ".py", data)
    return path


def _confine(module, folder) -> None:
    """Turn off numba's disk cache for any function of ``module`` whose cache would live outside ``folder``
    (``NUMBA_CACHE_DIR`` or a fallback locator would put it elsewhere, where we cannot vouch for it)."""
    from numba.core.caching import NullCache

    inside = os.path.realpath(os.path.join(folder, "__pycache__")) if folder else None
    for value in list(vars(module).values()):
        cache = getattr(value, "_cache", None)
        path = getattr(cache, "cache_path", None)
        if path is not None and (inside is None or os.path.realpath(path) != inside):
            value._cache = NullCache()
            if folder is not None:
                _note(f"numba would cache compiled code in {path} (NUMBA_CACHE_DIR?), outside the trusted folder "
                      f"{folder}; compiling without a disk cache")


_MODULES: dict = {}


def load_module(source: str, prefix: str = "coinwall_gen"):
    """Execute generated ``source`` as a module, from a file in the trusted cache folder when there is one.

    The module's name is ``<prefix>_<first 20 hex digits of the SHA-256 of source>``.  In the cache folder
    its file is checked to hold exactly ``source`` (else rewritten) and the *verified bytes* are compiled
    with the file's path as their file name (so numba's ``cache=True`` finds its machine code again in the
    next process); the file is never imported by path, so nothing written between the check and the
    execution can run.  The source reads a global ``CACHE``: True with a trusted folder, False in memory
    (:func:`cache_dir` returned None, or the folder could not be written), where nothing touches the disk.
    """
    data = source.encode()
    name = f"{prefix}_{hashlib.sha256(data).hexdigest()[:20]}"
    if name in _MODULES:
        return _MODULES[name]
    folder = cache_dir()
    filename = f"<coinwall generated {name}>"
    if folder is not None:
        _sweep_temporaries(folder)
        try:
            filename = _stored(folder, name, data)
            _check_numba_files(folder, name)
        except OSError as exc:
            _note(f"cannot write the kernel cache in {folder} ({exc.strerror or exc}); compiling in memory")
            folder, filename = None, f"<coinwall generated {name}>"
    module = types.ModuleType(name)
    module.__file__ = filename
    module.CACHE = folder is not None
    module.COINWALL_CACHE_FOLDER = folder
    sys.modules[name] = module  # numba's cache locates functions through their module
    exec(compile(data, filename, "exec"), module.__dict__)  # noqa: S102 -- our own generated source, verified above
    _confine(module, folder)
    _MODULES[name] = module
    return module
