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
(the kernel's last evaluation before a contact needs b'', see :mod:`coinwall.forward.dynamics.billiard._kernel`),
and ``wall_b3(phi, c) -> d3b`` (for the contact phases on the floor; the billiard never calls it, so its compiled
code does not change); it runs as plain Python too
(tests compare it with :meth:`Wall.derivatives` without compiling anything).

The second half of the module loads generated source as a module (:func:`load_module`) and gives its
compiled functions numba's own cache, in one private folder (:func:`cache_dir`), or compiles them in
memory when there is none (the comment above :func:`cache_dir` says why).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import math
import os
import pickle
import stat
import sys
import types

import numpy as np

from ...errors import InvalidWall

__all__ = ["attach_cache", "cache_dir", "cache_module", "load_module", "python_wall", "wall_source"]

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


{decorator}def wall_b3(phi, c):
    # the third derivative alone (for the contact phases' rates of the contact force), by the same recurrence
    n = int(c[1])
    c1 = math.cos(phi)
    s1 = math.sin(phi)
    ck = c1
    sk = s1
    d3b = 0.0
    for k in range(1, n + 1):
        d3b += k * k * k * (c[1 + k] * sk - c[1 + n + k] * ck)
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
    return d3b
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
    d2 = ca.jacobian(d1, t)
    sources = [_translate(ca.Function(name, [t], outputs), name, unary, binary, constants, parsed.text)
               for name, outputs in (("wall_b1", [parsed.expr, d1]), ("wall_b2", [parsed.expr, d1, d2]))]
    # b''' after the others, so that their code and constants do not change: only the contact phases call it,
    # and NaN, where it has no translation, makes them take their first-order steps
    try:
        sources.append(_translate(ca.Function("wall_b3", [t], [ca.jacobian(d2, t)]), "wall_b3", unary, binary,
                                  constants, parsed.text))
    except InvalidWall:
        sources.append("def wall_b3(phi, c):\n    return math.nan\n")
    return "\n\n".join(decorator + src for src in sources), np.array(constants or [0.0])


def wall_source(wall, decorator: str = ""):
    """Python source of ``wall_b1(phi, c) -> (b, b')``, ``wall_b2(phi, c) -> (b, b', b'')`` and ``wall_b3``.

    ``wall_b3(phi, c) -> b'''`` returns NaN for an expression whose third derivative has an operation without a
    translation.

    Parameters
    ----------
    wall : Wall
    decorator : str
        A line put before each ``def`` (e.g. ``"@njit(cache=True)\\n"``); empty for plain Python.

    Returns
    -------
    source : str
        Three function definitions using only :mod:`math` (no imports inside).
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
    """The generated ``wall_b1``, ``wall_b2`` or ``wall_b3`` (``order`` 1 to 3) as a plain Python function of an angle.

    Uncompiled, for checks against :meth:`Wall.derivatives`.
    """
    source, constants = wall_source(wall)
    namespace = {"math": math}
    exec(compile(source, "<coinwall wall code>", "exec"), namespace)  # noqa: S102 -- our own generated source
    func = namespace[f"wall_b{order}"]
    return lambda phi: func(float(phi), constants)


# ---------------------------------------------------------------------------------------------------- the cache
# numba's cache files are pickles with machine code: whoever can write them can run code as the user, and a
# garbled file could crash with SIGILL, which no exception handler catches.  So they live in one folder that
# this user owns and nobody else can enter (mode 0700), under a name that is the hash of the module's source,
# and each file carries the SHA-256 of its content (CheckedFile): a file that is damaged, emptied or not
# numba's reads as a miss, and numba's next save writes it again, through coinwall's writer.  Where no such
# folder can be had, the kernels are compiled in memory (nothing read from or written to disk).

_NOTED: set = set()


def _note(text: str) -> None:
    """One ``coinwall: note: ...`` line on stderr, once per process and text (the CLI's style of notice)."""
    if text not in _NOTED:
        _NOTED.add(text)
        print(f"coinwall: note: {text}", file=sys.stderr)


def _not_private(path: str, mode: int) -> str:
    """Why the folder ``path`` cannot hold the cache ('' when it can): ours, a real folder, and none of the
    bits of ``mode`` (group and others' access) set."""
    try:
        info = os.lstat(path)
    except OSError as exc:
        return f"{path}: {exc.strerror or exc}"
    if not stat.S_ISDIR(info.st_mode):
        return f"{path} is not a folder"
    if hasattr(os, "getuid") and info.st_uid != os.getuid():
        return f"{path} belongs to user id {info.st_uid}, not to this user ({os.getuid()})"
    if info.st_mode & mode:
        return f"{path} is open to others (mode {stat.S_IMODE(info.st_mode):o}; fix: chmod 700 {path})"
    return ""


def cache_dir():
    """The private folder of numba's cache of the kernels, or ``None``: compile in memory.

    ``$COINWALL_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/coinwall`` (``~/.cache/coinwall``), made with mode
    0700 where missing; in it one folder per numba and Python version.  Used only when this user owns both and
    nobody else can write the first or enter the second; otherwise one ``coinwall: note:`` line on stderr and
    ``None``.

    Returns
    -------
    str or None
    """
    import numba

    base = os.path.abspath(os.environ.get("COINWALL_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "coinwall"))
    folder = os.path.join(base, f"kernels-numba{numba.__version__}-py{sys.version_info[0]}{sys.version_info[1]}")
    try:
        os.makedirs(base, mode=0o700, exist_ok=True)
        why = _not_private(base, stat.S_IWGRP | stat.S_IWOTH)
        if not why:
            os.makedirs(folder, mode=0o700, exist_ok=True)
            why = _not_private(folder, 0o077)
    except OSError as exc:
        why = f"cannot create it ({exc.strerror or exc})"
    if why:
        _note(f"not using the kernel cache in {base} ({why}); compiling in memory (slower start, nothing read from "
              "or written to disk)")
        return None
    return folder


@functools.cache
def _package_stamp(path: str, module: str) -> str:
    """The SHA-256 of the source of ``module`` (at ``path``) and of every module of the same package it imports,
    directly or through others (relative imports, and absolute ones under the package's top name): the cache
    key of a package module's compiled functions.  The imported modules are found in ``sys.modules`` (a
    module is compiled after it was imported, and so were its imports)."""
    import ast

    top = module.split(".")[0]
    digest, todo, seen = hashlib.sha256(), [(module, path)], set()
    while todo:
        name, file = todo.pop()
        if file in seen:
            continue
        seen.add(file)
        with open(file, "rb") as fh:
            source = fh.read()
        digest.update(name.encode() + b"\0" + hashlib.sha256(source).digest())
        package = name if os.path.basename(file) == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.ImportFrom):
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([node.module] if node.module else [])) \
                    if node.level else node.module
                targets = [base, *(f"{base}.{alias.name}" for alias in node.names)]  # submodules imported by name
            elif isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            else:
                continue
            for target in targets:
                imported = sys.modules.get(target) if target.split(".")[0] == top else None
                if getattr(imported, "__file__", None):
                    todo.append((target, imported.__file__))
    return digest.hexdigest()


@functools.cache
def _cache_class(base=None):
    """numba's ``FunctionCache`` (or ``base``, e.g. a CUDA dispatcher's cache class) kept in the folder of the
    function's file name, with checked files.  Made on first use: numba is imported only where it runs."""
    from numba.core.caching import FunctionCache, IndexDataCacheFile, _CacheLocator

    from ...formats.output import write_all

    base = base or FunctionCache

    class Locator(_CacheLocator):
        """Every function in coinwall's folder.  A generated module's (its file name, never written, is in the
        folder) is stamped with that name, the hash of its source, so that one name never stands for two
        sources; a module of the package with :func:`_package_stamp`, the SHA-256 of its file and of every
        module of the package it imports (numba compiles a called function into its caller: a change in an
        imported kernel must reach the caller's cache), so that two copies of the package with the same sources
        (two clones) share the compiled code."""

        def __init__(self, folder, stamp, disambiguator):
            self._folder, self._stamp, self._disambiguator = folder, stamp, disambiguator

        def ensure_cache_path(self):
            pass  # made private by cache_dir()

        def get_cache_path(self):
            return self._folder

        def get_source_stamp(self):
            return self._stamp

        def get_disambiguator(self):
            return self._disambiguator

        @classmethod
        def from_function(cls, py_func, py_file):
            folder = cache_dir()
            if folder is None:
                return None
            if os.path.dirname(py_file) == folder:
                return cls(folder, os.path.basename(py_file), "")
            try:
                stamp = _package_stamp(os.path.abspath(py_file), py_func.__module__)
            except (OSError, SyntaxError, ValueError):  # no source file (a zip): compiled in memory
                return None
            return cls(folder, stamp, hashlib.sha256(py_func.__module__.encode()).hexdigest()[:8])  # not the path

    class CheckedFile(IndexDataCacheFile):
        """numba's index and data files, each the SHA-256 of its pickle, then the pickle: anything else reads
        as a miss (and is written again by the next save), never as code."""

        def _dump(self, obj):
            data = super()._dump(obj)
            return hashlib.sha256(data).digest() + data

        def _read(self, path):
            """The pickle at ``path`` if it verifies, else None; a missing file raises (numba's miss)."""
            with open(path, "rb") as fh:
                blob = fh.read()
            with contextlib.suppress(Exception):  # noqa: BLE001 - not unpickled: a miss
                if hashlib.sha256(blob[32:]).digest() == blob[:32]:
                    return pickle.loads(blob[32:])  # noqa: S301 -- verified, in a folder only this user can enter
            return None

        def _load_index(self):
            with contextlib.suppress(Exception):  # noqa: BLE001 - missing, damaged or not ours: a miss
                version, stamp, overloads = self._read(self._index_path)
                if (version, stamp) == (self._version, self._source_stamp) and isinstance(overloads, dict):
                    return overloads
            return {}

        def _save_index(self, overloads):
            write_all({self._index_path: self._dump((self._version, self._source_stamp, overloads))})

        def _load_data(self, name):
            return self._read(self._data_path(name))

        def _save_data(self, name, data):
            write_all({self._data_path(name): self._dump(data)})

        def save(self, key, data):
            from ...errors import OutputError

            try:
                super().save(key, data)
            except (OSError, OutputError) as exc:  # a full disk: the next process compiles again
                _note(f"could not write the kernel cache ({exc}); it is compiled again next time")

    class Impl(base._impl_class):
        _locator_classes = [Locator]

    class Cache(base):
        _impl_class = Impl

        def __init__(self, py_func):
            super().__init__(py_func)
            self._cache_file = CheckedFile(self._cache_path, self._impl.filename_base,
                                           self._impl.locator.get_source_stamp())

    return Cache


def attach_cache(dispatcher, base=None) -> bool:
    """Give one numba function coinwall's cache (in :func:`cache_dir`, with checked files); returns whether it
    has one (False: it compiles in memory, as with ``cache=False``).

    Parameters
    ----------
    dispatcher : numba dispatcher
        A function made with ``cache=False`` (a module made by :func:`load_module`, or one of the package,
        :func:`cache_module`), not yet compiled.
    base : type, optional
        The cache class that ``cache=True`` would give it (numba's ``FunctionCache`` by default; a CUDA
        dispatcher's cache class for a CUDA kernel).

    Returns
    -------
    bool
    """
    folder = cache_dir()
    if folder is None:
        return False
    try:
        cache = _cache_class(base)(dispatcher.py_func)
    except RuntimeError:  # no locator placed it (no source file; NUMBA_CACHE_LOCATOR_CLASSES chose others)
        return False
    if cache.cache_path != folder:  # a cache only in coinwall's folder
        return False
    dispatcher._cache = cache
    return True


def cache_module(module) -> bool:
    """:func:`attach_cache` for every numba function of ``module``, once per module; returns whether all of them
    have the cache (kept as ``module.CACHED``)."""
    from numba.core.dispatcher import Dispatcher

    if not hasattr(module, "CACHED"):
        functions = [value for value in vars(module).values() if isinstance(value, Dispatcher)]
        module.CACHED = all([attach_cache(f) for f in functions])
    return module.CACHED


_MODULES: dict = {}


def load_module(source: str, prefix: str = "coinwall_gen"):
    """Execute generated ``source`` as a module whose numba functions keep their machine code in coinwall's cache.

    The module's name is ``<prefix>_<first 20 hex digits of the SHA-256 of source>``; it is executed from
    memory (nothing but numba's own files is on disk).  The source reads a global ``CACHE``, which is False:
    the decorators make no cache of their own, and every numba function of the module then gets coinwall's
    (:func:`attach_cache`; none when :func:`cache_dir` is None: compiled in memory).

    Parameters
    ----------
    source : str
        Python source that defines numba functions.
    prefix : str
        The start of the module's name.

    Returns
    -------
    module
        Loaded once per process and source; ``module.CACHED`` says whether its functions use the disk cache.

    Examples
    --------
    >>> module = load_module("from numba import njit\\n@njit(cache=CACHE)\\ndef twice(x):\\n    return 2 * x\\n",
    ...                      "coinwall_example")
    >>> module.twice(1.5)
    3.0
    """
    data = source.encode()
    name = f"{prefix}_{hashlib.sha256(data).hexdigest()[:20]}"
    if name in _MODULES:
        return _MODULES[name]
    folder = cache_dir()
    module = types.ModuleType(name)
    module.__file__ = os.path.join(folder or "<memory>", name + ".py")  # a name only: numba's cache is keyed by it
    module.CACHE = False
    sys.modules[name] = module  # numba finds a function's globals through its module
    exec(compile(data, module.__file__, "exec"), module.__dict__)  # noqa: S102 -- our own generated source
    if folder is None:
        module.CACHED = False
    cache_module(module)
    _MODULES[name] = module
    return module
