"""Certified ranges of a formula on whole arrays of cells: affine arithmetic on casadi's instruction list.

:class:`AffineProgram` replays the algorithm of a casadi ``SX`` function of one angle
(:func:`~coinwall.forward.wallvector.instructions`, the list :class:`~coinwall.forward.wallvector.ArrayProgram`
replays with plain numpy) on cells ``[lo, hi]`` of angles, carrying for every intermediate value an
*affine form* ``c + Σ_k a_k ε_k + r η`` with unknowns ``ε_k, η ∈ [−1, 1]``: ``ε_0`` is the position in the
cell, each non-linear operation adds an unknown of its own for what its linearisation leaves out, and ``r``
gathers the rounding errors.  A value that a formula uses twice carries the same unknowns both times, so
``|cos t| − |cos t|`` (the stick's ``b + b''``) comes out as 0 on every cell where ``cos t`` keeps its sign,
and a smooth function's range on a cell of width ``w`` is overestimated by ``O(w²)``, not ``O(w)`` as plain
interval arithmetic would.

Every operation is rounded outward (:mod:`.intervalmath` says what is trusted of numpy's elementary
functions), so the range of an output on a cell contains every value the exact formula takes there; on a
cell of width 0 (a point) the width of the range bounds the rounding error of evaluating the formula in
floating point (:mod:`coinwall.forward.precision`).  Operations whose branch a cell does not decide
(``abs``, ``min``/``max`` and the comparisons of their derivatives, where the argument's range holds 0)
give the range of all their branches.  Written by hand, like :mod:`.wallvector`: no library offers
affine arithmetic on arrays (see :mod:`.intervalmath`).
"""

from __future__ import annotations

import math

import numpy as np

from .intervalmath import EPS, UNARY, down, power_range, up

__all__ = ["AffineProgram", "affine_program"]

#: Unknowns per form at most (ε_0 and one per non-linear operation); later operations put what their
#: linearisation leaves out into the rounding term ``r``, which stays correct but does not cancel.
MAX_SYMBOLS = 40
#: Relative error charged to every computed centre and coefficient (libm within 4 ulps, products of two).
_ROUND = 8.0 * EPS


def _codes():
    import casadi as ca

    unary = {ca.OP_EXP: "exp", ca.OP_LOG: "log", ca.OP_SQRT: "sqrt", ca.OP_SIN: "sin", ca.OP_COS: "cos",
             ca.OP_TAN: "tan", ca.OP_ASIN: "asin", ca.OP_ACOS: "acos", ca.OP_ATAN: "atan", ca.OP_SINH: "sinh",
             ca.OP_COSH: "cosh", ca.OP_TANH: "tanh", ca.OP_ASINH: "asinh", ca.OP_ACOSH: "acosh",
             ca.OP_ATANH: "atanh", ca.OP_INV: "inv", ca.OP_LOG1P: "log1p", ca.OP_EXPM1: "expm1"}
    names = {ca.OP_ASSIGN: "assign", ca.OP_NEG: "neg", ca.OP_TWICE: "twice", ca.OP_ADD: "add", ca.OP_SUB: "sub",
             ca.OP_MUL: "mul", ca.OP_DIV: "div", ca.OP_SQ: "sq", ca.OP_POW: "pow", ca.OP_CONSTPOW: "pow",
             ca.OP_FABS: "fabs", ca.OP_SIGN: "sign", ca.OP_FMIN: "fmin", ca.OP_FMAX: "fmax", ca.OP_LT: "lt",
             ca.OP_LE: "le", ca.OP_EQ: "eq", ca.OP_NE: "ne", ca.OP_NOT: "not", ca.OP_AND: "and", ca.OP_OR: "or",
             ca.OP_IF_ELSE_ZERO: "if_else_zero", ca.OP_FLOOR: "floor", ca.OP_CEIL: "ceil", ca.OP_FMOD: "fmod",
             ca.OP_COPYSIGN: "copysign", ca.OP_ATAN2: "atan2", ca.OP_HYPOT: "hypot", ca.OP_ERF: "erf"}
    names.update(unary)
    return names, ca.OP_CONST, ca.OP_INPUT, ca.OP_OUTPUT


# operations exact in their centre and coefficients up to rounding: no unknown of their own
_LINEAR = frozenset({"assign", "neg", "twice", "add", "sub"})
# how many unknowns an operation may add (division: the reciprocal's and the product's; a general power:
# logarithm, product and exponential)
_NEEDS = {"div": 2, "pow": 3}


def _nonzero(lo, hi):
    return (lo > 0) | (hi < 0)


def _zero(lo, hi):
    return (lo == 0) & (hi == 0)


def _equal(x, y):
    return (x[0] == x[1]) & (y[0] == y[1]) & (x[0] == y[0])


def _apart(x, y):
    return (x[1] < y[0]) | (x[0] > y[1])


# per operation, from the ranges of its arguments: where its first branch is certain, where its second is
# (abs: x or −x; sign: 1 or −1; min/max: x or y; comparisons and logic: true or false; if_else_zero: y or 0)
_BRANCHES = {
    "fabs": lambda x: (x[0] >= 0, x[1] <= 0),
    "sign": lambda x: (x[0] > 0, x[1] < 0),
    "fmin": lambda x, y: (x[1] <= y[0], y[1] <= x[0]),
    "fmax": lambda x, y: (x[0] >= y[1], y[0] >= x[1]),
    "lt": lambda x, y: (x[1] < y[0], x[0] >= y[1]),
    "le": lambda x, y: (x[1] <= y[0], x[0] > y[1]),
    "eq": lambda x, y: (_equal(x, y), _apart(x, y)),
    "ne": lambda x, y: (_apart(x, y), _equal(x, y)),
    "not": lambda x: (_zero(*x), _nonzero(*x)),
    "and": lambda x, y: (_nonzero(*x) & _nonzero(*y), _zero(*x) | _zero(*y)),
    "or": lambda x, y: (_nonzero(*x) | _nonzero(*y), _zero(*x) & _zero(*y)),
    "if_else_zero": lambda x, y: (_nonzero(*x), _zero(*x)),
}


# the same choices made the way floating point makes them, from the computed values (the forms' centres): for
# bounding the rounding of a point's evaluation, which takes one branch even where the ranges leave both open
_FLOAT_BRANCHES = {
    "fabs": lambda x: (x >= 0, x < 0),
    "sign": lambda x: (x > 0, x < 0),
    "fmin": lambda x, y: (x <= y, y < x),
    "fmax": lambda x, y: (x >= y, y > x),
    "lt": lambda x, y: (x < y, x >= y),
    "le": lambda x, y: (x <= y, x > y),
    "eq": lambda x, y: (x == y, x != y),
    "ne": lambda x, y: (x != y, x == y),
    "not": lambda x: (x == 0, x != 0),
    "and": lambda x, y: ((x != 0) & (y != 0), (x == 0) | (y == 0)),
    "or": lambda x, y: ((x != 0) | (y != 0), (x == 0) & (y == 0)),
    "if_else_zero": lambda x, y: (x != 0, x == 0),
}


class AffineProgram:
    """A casadi ``SX`` function of one angle, evaluated with certified ranges on arrays of cells.

    Parameters
    ----------
    func : casadi.Function
        An ``SX`` function with one scalar input and scalar outputs.
    symbols : int
        Unknowns per affine form at most (at least 1: the position in the cell).

    Raises
    ------
    ValueError
        If the function uses an operation this replay does not know.

    Examples
    --------
    >>> import casadi as ca
    >>> t = ca.SX.sym("t")
    >>> program = AffineProgram(ca.Function("f", [t], [ca.fabs(ca.cos(t)) - ca.fabs(ca.cos(t))], {"cse": True}))
    >>> (lo, hi), = program.enclose(np.array([0.1]), np.array([0.2]))
    >>> bool(abs(lo[0]) < 1e-15 and abs(hi[0]) < 1e-15)
    True
    """

    def __init__(self, func, symbols: int = MAX_SYMBOLS):
        from .wallvector import instructions

        names, op_const, op_input, op_output = _codes()
        steps, free = [], 1
        written = {}  # work slot -> the step that last wrote it (the values, as the algorithm's data flow)
        compared, pairs = {}, {}
        for op, ins, outs, constant in instructions(func):
            if op == op_const:
                step = ("const", outs[0], constant, ())
            elif op == op_input:
                step = ("input", outs[0], None, ())
            elif op == op_output:
                steps.append(("output", outs[0], None, (ins[0],)))
                continue
            elif op in names:
                name = names[op]
                need = 0 if name in _LINEAR else _NEEDS.get(name, 1)
                cols = []
                for _ in range(need):
                    cols.append(free if free < symbols else -1)
                    free += 1
                sources = tuple(written.get(i) for i in ins)
                if name in ("le", "lt"):
                    compared[len(steps)] = sources
                elif name == "add" and all(x in compared for x in sources) \
                        and compared[sources[0]] == compared[sources[1]][::-1]:
                    # (a ≤ b) + (b ≤ a): the denominator of min/max's derivative weights, at least 1 everywhere
                    pairs[len(steps)] = (sources, free if free < symbols else -1)
                    free += 1
                elif name == "div" and sources[1] in pairs and sources[0] in pairs[sources[1]][0]:
                    pair, col = pairs[sources[1]]
                    name = "weight"
                    cols = (col, 1.0 if sources[0] == pair[0] else -1.0)
                step = (name, outs[0], tuple(cols), tuple(ins))
            else:
                raise ValueError(f"casadi operation {op} has no certified counterpart")
            written[outs[0]] = len(steps)
            steps.append(step)
        self._steps = tuple(steps)
        self._symbols = max(1, min(symbols, free))
        self._n_out = func.n_out()
        self._n_work = 1 + max([s[1] for s in steps if s[0] != "output"] + [0])

    @property
    def n_out(self) -> int:
        """Number of outputs."""
        return self._n_out

    def enclose(self, lo, hi, *, decide=None, trace: bool = False, float_branches: bool = False):
        """Certified ranges of every output on the cells ``[lo[i], hi[i]]`` (``lo == hi``: points).

        Parameters
        ----------
        lo, hi : ndarray
            The cells' ends (1-D, the same length; ``lo ≤ hi``).
        decide : ndarray, optional
            Per cell an angle (NaN for none): where the cell's ranges leave a branch of ``abs``, ``min``,
            ``max`` or a comparison open, the branch taken at that angle is used.  For a cell beside a kink,
            with the angle inside it: the formula of the kink's side is then followed up to the kink itself
            (the one-sided limit), not the hull of both sides.  Correct only where no branch changes inside
            the cell.
        trace : bool
            Also return, per instruction, ``(name, input ranges, output range)`` (for naming the
            operation that loses precision).
        float_branches : bool
            For points: where the ranges leave a branch open, take the one floating point takes (from the
            computed values), so that the ranges bound the rounding of the floating-point evaluation itself.

        Returns
        -------
        list of (ndarray, ndarray)
            Per output, the lower and upper ends of its range on each cell; ``(−inf, inf)`` where the
            formula may not be finite on the cell.  With ``trace``, ``(ranges, steps)``.
        """
        lo = np.ascontiguousarray(lo, dtype=float).ravel()
        hi = np.ascontiguousarray(hi, dtype=float).ravel()
        ops = _Ops(self._symbols, lo.size, "float" if float_branches else "")
        if decide is not None:
            decide = np.asarray(decide, dtype=float).ravel()
            forced = np.isfinite(decide)
            if forced.any():
                at = np.where(forced, decide, lo)
                record = _Ops(1, lo.size, "record")
                self._run(record, at, at, False)
                ops = _Ops(self._symbols, lo.size, "force", record.log, forced)
        return self._run(ops, lo, hi, trace)

    def _run(self, ops, lo, hi, trace):
        work = [None] * self._n_work
        out = [ops.constant(0.0)] * self._n_out
        steps = []
        with np.errstate(all="ignore"):
            for name, target, arg, ins in self._steps:
                if name == "const":
                    work[target] = ops.constant(arg)
                elif name == "input":
                    work[target] = ops.cell(lo, hi)
                elif name == "output":
                    out[target] = work[ins[0]]
                else:
                    args = [work[i] for i in ins]
                    work[target] = ops.apply(name, args, arg)
                    if trace:
                        steps.append((name, [ops.range(x) for x in args], ops.range(work[target])))
        ranges = [tuple(np.broadcast_to(v, lo.shape).copy() for v in ops.range(form)) for form in out]
        return (ranges, steps) if trace else ranges


def affine_program(func, symbols: int = MAX_SYMBOLS):
    """:class:`AffineProgram` of ``func``, or ``None`` when an operation has no certified counterpart."""
    try:
        return AffineProgram(func, symbols)
    except ValueError:
        return None


class _Ops:
    """The operations on affine forms ``(c, a, r)``: centre (m,), coefficients (m, K), rounding term (m,),
    with m the number of cells or 1 (a constant, broadcast)."""

    def __init__(self, symbols: int, n: int, mode: str = "", log=None, forced=None):
        self.k = symbols
        self.n = n
        # "record": keep each branch choice; "force": settle undecided ones of `forced` cells; "float": settle
        # undecided ones as floating point does
        self.mode = mode
        self.log = [] if log is None else log
        self.used = []
        self.forced = forced

    # ---------------------------------------------------------------- forms
    def constant(self, value):
        value = np.atleast_1d(np.asarray(value, dtype=float))
        return value, np.zeros((value.size, self.k)), np.zeros(value.size)

    def cell(self, lo, hi):
        c = 0.5 * lo + 0.5 * hi
        a = np.zeros((lo.size, self.k))
        a[:, 0] = up(np.maximum(hi - c, c - lo))
        return c, a, np.zeros(lo.size)

    def radius(self, form):
        _, a, r = form
        return (np.abs(a).sum(axis=1) + r) * (1.0 + (self.k + 2) * EPS)

    def range(self, form):
        c, _, _ = form
        rad = self.radius(form)
        lo, hi = down(c - rad), up(c + rad)
        bad = ~np.isfinite(rad) | ~np.isfinite(c)
        return np.where(bad, -np.inf, lo), np.where(bad, np.inf, hi)

    def finish(self, c, a, r):
        """The form with the rounding of its centre and coefficients charged; non-finite → unbounded."""
        r = r + _ROUND * (np.abs(c) + np.abs(a).sum(axis=1))
        bad = ~(np.isfinite(c) & np.isfinite(r) & np.isfinite(a).all(axis=1))
        if bad.any():
            c = np.where(bad, 0.0, c)
            a = np.where(bad[:, None], 0.0, a)
            r = np.where(bad, np.inf, r)
        return c, a, r

    def fresh(self, lo, hi, col):
        """A form for the range ``[lo, hi]`` with no tie to the others (one new unknown)."""
        lo, hi = np.broadcast_arrays(np.asarray(lo, float), np.asarray(hi, float))
        c = 0.5 * lo + 0.5 * hi
        half = up(0.5 * hi - 0.5 * lo) + 2.0 * EPS * np.abs(c)
        bad = ~(np.isfinite(c) & np.isfinite(half))
        c = np.where(bad, 0.0, c)
        half = np.where(bad, np.inf, half)
        a = np.zeros((c.size, self.k))
        if 0 <= col < self.k and not bad.any():
            a[:, col] = half
            return c, a, np.zeros(c.size)
        return c, a, half

    def _add_symbol(self, a, r, col, amount):
        if 0 <= col < self.k:
            a = np.array(np.broadcast_to(a, (np.broadcast(a[:, 0], amount).size, self.k)))
            a[:, col] += amount
            return a, r
        return a, r + amount

    @staticmethod
    def select(mask, first, second):
        """Per cell the form ``first`` where ``mask``, else ``second``."""
        return (np.where(mask, first[0], second[0]), np.where(mask[:, None], first[1], second[1]),
                np.where(mask, first[2], second[2]))

    # ---------------------------------------------------------------- dispatch
    def apply(self, name, args, cols):
        col = cols[0] if cols else -1
        if name in UNARY:
            return self.unary(name, args[0], col)
        if name == "assign":
            return args[0]
        if name == "neg":
            c, a, r = args[0]
            return -c, -a, r
        if name == "twice":
            c, a, r = args[0]
            return 2.0 * c, 2.0 * a, 2.0 * r
        if name in ("add", "sub"):
            (cx, ax, rx), (cy, ay, ry) = args
            if name == "sub":
                cy, ay = -cy, -ay
            return self.finish(cx + cy, ax + ay, rx + ry)
        if name == "mul":
            return self.mul(args[0], args[1], col)
        if name == "div":
            return self.div(args[0], args[1], cols)
        if name == "weight":
            return self.weight(args[0], args[1], *cols)
        if name == "sq":
            return self.sq(args[0], col)
        if name == "pow":
            return self.power(args[0], args[1], cols)
        return self.piecewise(name, args, col)

    # ---------------------------------------------------------------- arithmetic
    def mul(self, x, y, col):
        (cx, ax, rx), (cy, ay, ry) = x, y
        c = cx * cy
        a = cx[:, None] * ay + cy[:, None] * ax
        r = np.abs(cx) * ry + np.abs(cy) * rx
        a, r = self._add_symbol(a, r, col, self.radius(x) * self.radius(y))
        product = self.finish(c, a, r)
        # an exact 0 times anything is 0: the other factor's values are finite (the wall is), however wide
        # its range (the derivative of a min whose branches this cell leaves open, multiplied by the 0
        # weight of the branch an outer min does not take)
        zero = (self._is_zero(x) | self._is_zero(y)) * np.ones(product[0].shape, dtype=bool)
        return self.select(zero, self.constant(0.0), product) if zero.any() else product

    @staticmethod
    def _is_zero(form):
        c, a, r = form
        return (c == 0) & ~np.any(a, axis=1) & (r == 0)

    def sq(self, x, col):
        cx, ax, rx = x
        rad = self.radius(x)
        half = up(0.5 * rad * rad)
        a, r = self._add_symbol(2.0 * cx[:, None] * ax, 2.0 * np.abs(cx) * rx, col, half)
        return self.finish(cx * cx + half, a, r)

    def div(self, x, y, cols):
        cy, ay, ry = y
        if not np.any(ay) and not np.any(ry):  # by a constant: a scaling
            cx, ax, rx = x
            return self.finish(cx / cy, ax / cy[:, None], rx / np.abs(cy))
        return self.mul(x, self.unary("inv", y, cols[0]), cols[1])

    def weight(self, x, y, col, sign):
        """``(a ≤ b) / ((a ≤ b) + (b ≤ a))`` (``sign`` +1) or its partner (−1), the weights casadi gives the two
        branches of min/max in their derivatives: 1 and 0, or ½ and ½ at a tie.  Where the cell leaves the
        comparison open they are ``½ ± ½ ε`` with one unknown ε for both, so they still add up to 1 (the
        derivative of a min of two equal branches is their common derivative, not a range around it)."""
        plain = self.div(x, y, (-1, -1))
        open_ = self.radius(y) > 0.25  # an open comparison adds ½ (0 or 1); decided ones add rounding
        if not np.any(open_):
            return plain
        half = np.full(1, 0.5)
        a = np.zeros((1, self.k))
        r = np.zeros(1)
        a, r = self._add_symbol(a, r, int(col), half)
        if 0 <= col < self.k:
            a[:, int(col)] *= sign
        shape = np.ones(np.broadcast(open_, plain[0]).shape, dtype=bool)
        return self.select(open_ * shape, (half, a, r), plain)

    def power(self, x, y, cols):
        cy, ay, ry = y
        if not np.any(ay) and not np.any(ry) and np.all(cy == cy[0]):
            return self.constant_power(x, float(cy[0]), cols[0])
        # x**y = exp(y log x) for a varying exponent
        return self.unary("exp", self.mul(y, self.unary("log", x, cols[0]), cols[1]), cols[2])

    def constant_power(self, x, p, col):
        if p == 0:
            return self.constant(1.0)
        if p == 1:
            return x
        if p == 2:
            return self.sq(x, col)
        factor = p * (p - 1.0)

        def second(lo, hi):
            a, b = power_range(lo, hi, p - 2.0)
            return (factor * a, factor * b) if factor >= 0 else (factor * b, factor * a)

        funcs = (lambda v: np.power(v, p), lambda v: p * np.power(v, p - 1.0),
                 lambda lo, hi: power_range(lo, hi, p), second)
        return self.taylor(funcs, x, col)

    def unary(self, name, x, col):
        return self.taylor(UNARY[name], x, col)

    def taylor(self, funcs, x, col):
        """``φ(x)`` as ``φ(c) + φ'(c)(x − c) + R`` with ``R ∈ ½ φ''(X) (x − c)²`` (a new unknown), or the
        range of φ on X with no tie when that is narrower by half (a coarse cell, a domain's end)."""
        value, slope, image, second = funcs
        cx, ax, rx = x
        lo, hi = self.range(x)
        rad = self.radius(x)
        v, d = value(cx), slope(cx)
        s_lo, s_hi = second(lo, hi)
        q = 0.5 * rad * rad
        rem_lo = np.minimum(s_lo, 0.0) * q
        rem_hi = np.maximum(s_hi, 0.0) * q
        shift = 0.5 * rem_lo + 0.5 * rem_hi
        a, r = self._add_symbol(d[:, None] * ax, np.abs(d) * rx, col, up(0.5 * rem_hi - 0.5 * rem_lo))
        form = self.finish(v + shift, a, r)
        i_lo, i_hi = image(lo, hi)
        plain = self.fresh(i_lo, i_hi, col)
        with np.errstate(invalid="ignore"):
            keep = self.radius(form) <= 1.5 * self.radius(plain)
        keep = np.broadcast_to(keep, np.broadcast(cx, i_lo).shape)
        if keep.all():
            return form
        return self.select(keep, form, plain)

    # ---------------------------------------------------------------- branches
    def piecewise(self, name, args, col):
        """``abs``, ``sign``, ``min``/``max``, comparisons and ``if_else_zero``: per cell the branch its
        ranges decide (1 or 2), or (0) the range of every branch; :meth:`AffineProgram.enclose`'s ``decide``
        settles the undecided ones of some cells by the branch taken at a point of their own."""
        ranges = [self.range(x) for x in args]
        (xl, xh) = ranges[0]
        if name in ("floor", "ceil"):
            func = np.floor if name == "floor" else np.ceil
            a, b = func(xl) * np.ones(self.n), func(xh) * np.ones(self.n)
            return self.select(a == b, self.constant(a), self.fresh(a, b, col))
        if name not in _BRANCHES:
            return self.fresh(*self._loose(name, ranges), col)
        first, second = _BRANCHES[name](*ranges)
        choice = np.where(first, 1, np.where(second, 2, 0)) * np.ones(self.n, dtype=int)
        if self.mode == "float":
            first, second = _FLOAT_BRANCHES[name](*(x[0] for x in args))
            choice = np.where(choice == 0, np.where(first, 1, np.where(second, 2, 0)), choice)
        if self.mode == "record":
            self.log.append(choice)
        elif self.mode == "force":
            recorded = self.log[len(self.used)]
            self.used.append(name)
            choice = np.where((choice == 0) & self.forced, recorded, choice)
        one, zero = self.constant(1.0), self.constant(0.0)
        if name == "fabs":
            x = args[0]
            top = np.maximum(np.abs(xl), np.abs(xh))
            branches = (x, (-x[0], -x[1], x[2]), (0.0 * top, top))
        elif name == "sign":
            branches = (one, self.constant(-1.0), (np.sign(xl), np.sign(xh)))
        elif name in ("fmin", "fmax"):
            # undecided: max(x, y) = (x + y)/2 + |x − y|/2 (min: −), which keeps the ties of two equal branches
            x, y = args
            half_sum = self.finish(0.5 * x[0] + 0.5 * y[0], 0.5 * x[1] + 0.5 * y[1], 0.5 * x[2] + 0.5 * y[2])
            dl, dh = self.range(self.finish(x[0] - y[0], x[1] - y[1], x[2] + y[2]))
            gap = 0.5 * np.maximum(np.abs(dl), np.abs(dh))
            gap = self.fresh(0.0 * gap, gap, col)
            if name == "fmin":
                gap = (-gap[0], -gap[1], gap[2])
            both = self.finish(half_sum[0] + gap[0], half_sum[1] + gap[1], half_sum[2] + gap[2])
            return self.select(choice == 1, x, self.select(choice == 2, y, both))
        elif name == "if_else_zero":
            (yl, yh) = ranges[1]
            branches = (args[1], zero, (np.minimum(yl, 0.0), np.maximum(yh, 0.0)))
        else:  # comparisons and logic: 1 or 0
            branches = (one, zero, (0.0, 1.0))
        undecided = self.fresh(*branches[2], col)
        if self.mode == "float" and name == "sign":  # floating point's sign(0) is 0
            undecided = self.select((args[0][0] == 0) * np.ones(self.n, dtype=bool), zero, undecided)
        return self.select(choice == 1, branches[0], self.select(choice == 2, branches[1], undecided))

    @staticmethod
    def _loose(name, ranges):
        """Ranges of the rarely used operations (casadi may emit them; the parser does not): enough to be
        correct, not tight."""
        (xl, xh) = ranges[0]
        big_x = np.maximum(np.abs(xl), np.abs(xh))
        if name == "erf":
            return -1.0 + 0.0 * xl, 1.0 + 0.0 * xh
        (yl, yh) = ranges[1]
        big_y = np.maximum(np.abs(yl), np.abs(yh))
        if name == "atan2":
            return -math.pi - 1e-15 + 0.0 * xl, math.pi + 1e-15 + 0.0 * xh
        if name == "hypot":
            small_x = np.where((xl <= 0) & (xh >= 0), 0.0, np.minimum(np.abs(xl), np.abs(xh)))
            small_y = np.where((yl <= 0) & (yh >= 0), 0.0, np.minimum(np.abs(yl), np.abs(yh)))
            return down(np.hypot(small_x, small_y)), up(np.hypot(big_x, big_y))
        if name == "fmod":
            return -big_y, big_y
        return -big_x, big_x  # copysign
