"""A formula whose floating-point evaluation has lost what it says: refused, with the operation to blame.

``2 + 0.1*cos(2*t + 1e20)`` is a wall in mathematics (b + b'' ≥ 1.7), but in floating point ``2t + 1e20``
is 1e20 rounded to a multiple of 16384 for every t, and ``cos`` of it is a constant: the computed wall no
longer depends on t, and every number derived from it (b_c = −1.77 "to 3e-14") would be silently wrong.
``(1e20 + cos(t)) - 1e20`` loses everything to cancellation the same way.

:func:`check_precision` evaluates b, b' and b'' on the check grid with certified ranges
(:class:`~coinwall.forward.affine.AffineProgram` on points: the width of each range bounds the rounding
error of evaluating that output in floating point) and refuses a wall where any of them is known to less
than :data:`RELATIVE_PRECISION` of its own size.  The message names the first operation of the formula
whose result lost that precision (an argument too large for its sine, terms that cancel), found by
replaying the formula with its ranges kept.  Below the threshold the rounding is small but not zero, and
the certified critical offset (:mod:`coinwall.inverse.criticalcells`) carries it into its tolerance.
"""

from __future__ import annotations

import numpy as np

from .errors import InvalidWall

__all__ = ["RELATIVE_PRECISION", "check_precision"]

#: How much of its size a quantity (b, b', b'') may lose to rounding, by the certified bound: 1e-4, as that bound
#: is pessimistic (it charges every operation its worst rounding: 2.5e-6 for ``1/(cos(t)+1.0000001)``, whose
#: b'' is good to ~1e-8) and a lost argument loses everything (0.05 for ``cos(2*t + 1e20)``).
RELATIVE_PRECISION = 1e-4

_NAMES = {"sin": "sin", "cos": "cos", "tan": "tan", "exp": "exp", "log": "log", "sqrt": "sqrt", "asin": "arcsin",
          "acos": "arccos", "atan": "arctan", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "pow": "a power",
          "sq": "a square", "inv": "a reciprocal"}


def check_precision(description: str, parsed, theta, scale: float = 1.0) -> None:
    """Refuse the wall of ``parsed`` (a :class:`~coinwall.forward.expression.ParsedExpression`) when b, b' or b''
    evaluated at the angles ``theta`` in floating point are known to less than :data:`RELATIVE_PRECISION` of
    their size (the larger of the wall's ``scale`` and their own largest value on ``theta``).

    Raises
    ------
    InvalidWall
        Naming the quantity, how well it is known, where, and the operation that lost the precision.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward.expression import parse_expression
    >>> theta = np.linspace(0, 2 * np.pi, 64)
    >>> check_precision("fine", parse_expression("2 + 0.1*cos(2*t + 1)"), theta)   # nothing to say
    >>> check_precision("bad", parse_expression("2 + 0.1*cos(2*t + 1e20)"), theta)
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidWall: wall 'bad' loses its precision in floating point: ...
    """
    import casadi as ca

    from .affine import AffineProgram

    t, b = parsed.symbol, parsed.expr
    d1 = ca.jacobian(b, t)
    d2 = ca.jacobian(d1, t)
    program = AffineProgram(ca.Function("wall", [t], [b, d1, d2], {"cse": True}), symbols=1)
    theta = np.asarray(theta, dtype=float)
    ranges = program.enclose(theta, theta, float_branches=True)
    for name, (lo, hi) in zip(("b", "b'", "b''"), ranges):
        with np.errstate(all="ignore"):
            width = hi - lo
            size = max(1.0, scale, float(np.max(np.abs(0.5 * lo + 0.5 * hi)[np.isfinite(width)], initial=0.0)))
        bad = ~(width <= RELATIVE_PRECISION * size)
        if not bad.any():
            continue
        worst = int(np.argmax(np.where(np.isfinite(width), width, np.inf)))
        known = "not at all" if not np.isfinite(width[worst]) else f"only to ±{0.5 * width[worst]:.2g}"
        raise InvalidWall(f"wall {description!r} loses its precision in floating point: {name} at θ = "
                          f"{theta[worst]:.6g} is known {known} (its size is {size:.3g}), because "
                          f"{_culprit(program, theta)}; write it so that floating point can follow t (reduce a "
                          "large argument modulo 2π, cancel large terms by hand)")


def _culprit(program, theta) -> str:
    """The first operation whose result, over the whole grid, is known to less than the threshold of its size."""
    _, steps = program.enclose(theta, theta, trace=True, float_branches=True)
    for name, inputs, (lo, hi) in steps:
        with np.errstate(all="ignore"):
            width = np.max(hi - lo)
            size = float(np.max(np.abs(0.5 * lo + 0.5 * hi)))
        if not (width <= RELATIVE_PRECISION * size) and width > 1e-300 and not np.isnan(width):
            return _describe(name, inputs, width, size)
    return "its operations add up their rounding"


def _describe(name, inputs, width, size) -> str:
    biggest = max(float(np.max(np.maximum(np.abs(lo), np.abs(hi)))) for lo, hi in inputs) if inputs else 0.0
    if name in ("add", "sub"):
        kind = "difference" if name == "sub" else "sum"
        return (f"a {kind} of terms as large as {biggest:.3g} comes to at most {size:.3g}, of which floating point "
                f"keeps only ±{0.5 * width:.2g}")
    if name in _NAMES and inputs:
        argument = float(np.max(inputs[0][1] - inputs[0][0]))
        return (f"{_NAMES[name]} is taken of an argument as large as {biggest:.3g}, known only to ±{0.5 * argument:.2g} "
                "in floating point")
    return f"an operation ({name}) on numbers as large as {biggest:.3g} keeps only ±{0.5 * width:.2g} of its result"
