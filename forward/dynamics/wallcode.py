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
(the kernel's last evaluation before a contact needs b'', see :mod:`coinwall.forward.dynamics._kernel`);
it runs as plain Python too
(tests compare it with :meth:`Wall.derivatives` without compiling anything).
"""

from __future__ import annotations

import hashlib
import importlib.util
import math
import os
import sys
import tempfile

import numpy as np

from ..errors import InvalidWall

__all__ = ["wall_source", "python_wall", "load_module", "cache_dir"]

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
    raise InvalidWall(f"wall {wall!r}: unknown wall kind {wall.kind!r}; the billiard kernel handles "
                      f"expression, Fourier and sample walls")


def python_wall(wall, order: int = 1):
    """The generated ``wall_b1`` (``order=1``) or ``wall_b2`` (``order=2``) as a plain Python function of one angle.

    Uncompiled, for checks against :meth:`Wall.derivatives`.
    """
    source, constants = wall_source(wall)
    namespace = {"math": math}
    exec(compile(source, "<coinwall wall code>", "exec"), namespace)  # our own generated source, not user text
    func = namespace["wall_b1" if order == 1 else "wall_b2"]
    return lambda phi: func(float(phi), constants)


def cache_dir() -> str:
    """Folder for generated modules and numba's on-disk cache.

    ``$COINWALL_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/coinwall`` (``~/.cache/coinwall``);
    falls back to the system temporary folder when that is not writable.
    """
    import numba

    base = os.environ.get("COINWALL_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "coinwall")
    folder = os.path.join(base, f"billiard-numba{numba.__version__}-py{sys.version_info[0]}{sys.version_info[1]}")
    try:
        os.makedirs(folder, exist_ok=True)
        if os.access(folder, os.W_OK):
            return folder
    except OSError:
        pass
    folder = os.path.join(tempfile.gettempdir(), f"coinwall-{os.getuid() if hasattr(os, 'getuid') else 0}",
                          os.path.basename(folder))
    os.makedirs(folder, exist_ok=True)
    return folder


_MODULES: dict = {}


def load_module(source: str, prefix: str = "coinwall_gen"):
    """Import generated ``source`` as a module from a file (so numba's ``cache=True`` works).

    The file name is the hash of the source: the same source is written once and
    its compiled functions are reused across processes.
    """
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    name = f"{prefix}_{digest}"
    if name in _MODULES:
        return _MODULES[name]
    folder = cache_dir()
    path = os.path.join(folder, name + ".py")
    if not os.path.exists(path):
        fd, temp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=".py")
        with os.fdopen(fd, "w") as fh:
            fh.write(source)
        os.replace(temp, path)  # atomic: parallel processes never see half a file
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # numba's cache locates functions through their module
    spec.loader.exec_module(module)
    _MODULES[name] = module
    return module
