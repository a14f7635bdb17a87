"""Whole-array evaluation of a casadi function of one angle, with numpy.

casadi evaluates an ``SX`` function point by point: each call costs ~10 µs of Python and casadi
overhead, each point ~0.4 µs, and its result comes back as a ``DM`` whose conversion to numpy goes
through a Python list (~0.1 ms per 2048 values).  A wall of 10⁵ angles (the solvers' grids, the
polar cross-check's Newton iterations) spent seconds there.

:class:`ArrayProgram` reads the function's own algorithm (its instruction list: ``n_instructions``,
``instruction_id``, ``instruction_input``, ``instruction_output``, ``instruction_constant``, the
interface :mod:`coinwall.forward.dynamics.billiard.wallcode` translates for numba) and replays it with one
numpy call per instruction on the whole array of angles.  The operations are casadi's (same
derivative rules, ``sign(0) = 0``, ``fmin``/``fmax`` ignoring a NaN, ``if_else_zero`` giving 0
even where its value is not finite); only the elementary functions are numpy's instead of the C
library's, which may differ in the last bit.  No code is generated or compiled, so there is no
start-up cost: hand-written on purpose, as neither casadi nor numpy offers this replay.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ArrayProgram", "array_program", "instructions"]


def instructions(func):
    """The algorithm of a casadi ``SX`` function: ``(op, inputs, outputs, constant)`` per instruction.

    ``op`` is casadi's operation code (``casadi.OP_ADD`` …), ``inputs``/``outputs`` the work-vector slots it
    reads and writes (for ``OP_OUTPUT``: the output's index first), ``constant`` the value of an
    ``OP_CONST`` (None otherwise).  :class:`ArrayProgram` replays it with numpy,
    :class:`coinwall.forward.affine.AffineProgram` with certified ranges.
    """
    import casadi as ca

    for k in range(func.n_instructions()):
        op = func.instruction_id(k)
        constant = float(func.instruction_constant(k)) if op == ca.OP_CONST else None
        yield op, func.instruction_input(k), func.instruction_output(k), constant


# module-level operations (not lambdas), so that a program, and the wall holding it, pickles
def _flag(values):
    return values.astype(float)


def _same(x):
    return x


def _square(x):
    return x * x


def _twice(x):
    return 2.0 * x


def _inverse(x):
    return 1.0 / x


def _not(x):
    return _flag(np.equal(x, 0.0))


def _lt(x, y):
    return _flag(np.less(x, y))


def _le(x, y):
    return _flag(np.less_equal(x, y))


def _eq(x, y):
    return _flag(np.equal(x, y))


def _ne(x, y):
    return _flag(np.not_equal(x, y))


def _and(x, y):
    return _flag(np.logical_and(np.not_equal(x, 0.0), np.not_equal(y, 0.0)))


def _or(x, y):
    return _flag(np.logical_or(np.not_equal(x, 0.0), np.not_equal(y, 0.0)))


def _if_else_zero(x, y):
    return np.where(np.not_equal(x, 0.0), y, 0.0)


def _op_tables():
    import casadi as ca

    unary = {ca.OP_ASSIGN: _same, ca.OP_NEG: np.negative, ca.OP_EXP: np.exp, ca.OP_LOG: np.log,
             ca.OP_SQRT: np.sqrt, ca.OP_SQ: _square, ca.OP_TWICE: _twice,
             ca.OP_SIN: np.sin, ca.OP_COS: np.cos, ca.OP_TAN: np.tan, ca.OP_ASIN: np.arcsin,
             ca.OP_ACOS: np.arccos, ca.OP_ATAN: np.arctan, ca.OP_SINH: np.sinh, ca.OP_COSH: np.cosh,
             ca.OP_TANH: np.tanh, ca.OP_ASINH: np.arcsinh, ca.OP_ACOSH: np.arccosh, ca.OP_ATANH: np.arctanh,
             ca.OP_FABS: np.abs, ca.OP_INV: _inverse, ca.OP_FLOOR: np.floor, ca.OP_CEIL: np.ceil,
             ca.OP_LOG1P: np.log1p, ca.OP_EXPM1: np.expm1, ca.OP_NOT: _not,
             ca.OP_SIGN: np.sign}  # numpy's sign is casadi's: 0 at 0
    binary = {ca.OP_ADD: np.add, ca.OP_SUB: np.subtract, ca.OP_MUL: np.multiply, ca.OP_DIV: np.divide,
              ca.OP_POW: np.power, ca.OP_CONSTPOW: np.power, ca.OP_LT: _lt, ca.OP_LE: _le, ca.OP_EQ: _eq,
              ca.OP_NE: _ne, ca.OP_AND: _and, ca.OP_OR: _or, ca.OP_IF_ELSE_ZERO: _if_else_zero,
              ca.OP_FMIN: np.fmin, ca.OP_FMAX: np.fmax, ca.OP_COPYSIGN: np.copysign,
              ca.OP_ATAN2: np.arctan2, ca.OP_FMOD: np.fmod, ca.OP_HYPOT: np.hypot}
    return unary, binary


class ArrayProgram:
    """A casadi ``SX`` function of one scalar input, evaluated on whole numpy arrays.

    Parameters
    ----------
    func : casadi.Function
        An ``SX`` function with one scalar input and scalar outputs.

    Raises
    ------
    ValueError
        If the function uses an operation with no numpy counterpart here (the caller keeps casadi).
    """

    def __init__(self, func):
        import casadi as ca

        unary, binary = _op_tables()
        steps = []  # (kind, target, a, b): kind 0 constant, 1 input, 2 output, 3 unary, 4 binary
        for op, ins, outs, constant in instructions(func):
            if op == ca.OP_CONST:
                steps.append((0, outs[0], constant, None))
            elif op == ca.OP_INPUT:
                steps.append((1, outs[0], None, None))
            elif op == ca.OP_OUTPUT:
                steps.append((2, outs[0], ins[0], None))
            elif op in unary:
                steps.append((3, outs[0], unary[op], ins[0]))
            elif op in binary:
                steps.append((4, outs[0], binary[op], (ins[0], ins[1])))
            else:
                raise ValueError(f"casadi operation {op} has no numpy counterpart")
        self._steps = tuple(steps)
        self._n_out = func.n_out()
        self._n_work = 1 + max([s[1] for s in steps if s[0] != 2] + [0])

    @property
    def n_out(self) -> int:
        """Number of outputs."""
        return self._n_out

    def __call__(self, theta):
        """The outputs at the angles ``theta`` (a 1-D float array), each an array of the same length."""
        work = [None] * self._n_work
        out = [0.0] * self._n_out  # a structurally zero output (b' of a constant) has no instruction
        with np.errstate(all="ignore"):  # casadi gives inf/nan silently too; the callers judge them
            for kind, target, a, b in self._steps:
                if kind == 4:
                    work[target] = a(work[b[0]], work[b[1]])
                elif kind == 3:
                    work[target] = a(work[b])
                elif kind == 0:
                    work[target] = a
                elif kind == 1:
                    work[target] = theta
                else:
                    out[target] = work[a]
        shape = np.shape(theta)
        # an output that does not depend on t (a constant, or b'' of a linear wall) is a scalar here
        return [np.array(np.broadcast_to(np.asarray(o, dtype=float), shape)) for o in out]


def array_program(func):
    """:class:`ArrayProgram` of ``func``, or ``None`` when an operation has no numpy counterpart."""
    try:
        return ArrayProgram(func)
    except ValueError:
        return None
