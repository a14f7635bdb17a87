"""Safe parsing of a wall expression in ``t`` into a casadi SX expression.

The text is parsed with :func:`ast.parse` and translated node by node against
a whitelist; it is never evaluated as Python, so nothing outside the
whitelist (attribute access, imports, arbitrary calls …) can run.  Every
rejection is an :class:`InvalidExpression` or :class:`InvalidParameter`
whose one-line message names the offending token.
"""

from __future__ import annotations

import ast
import difflib
import math
import operator
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .errors import InvalidExpression, InvalidParameter

if TYPE_CHECKING:
    import casadi
from .display import safe_repr

__all__ = ["ParsedExpression", "check_ascii", "check_one_line", "parse_expression", "parse_param", "parse_params"]

MAX_LENGTH = 2000
#: Most levels of nesting: parentheses, calls, signs and powers inside one another.  A chain of one
#: operator (``a + b − c + …``, ``a * b / c …``) is one level however long: nesting counts nesting, and the
#: length of an expression is bounded by :data:`MAX_LENGTH` alone (each node takes at least one character).
MAX_DEPTH = 200

_VARIABLES = ("t", "theta")
_CONSTANTS = {"pi": math.pi, "e": math.e}
_UNARY_FUNCS = {"sin": "sin", "cos": "cos", "tan": "tan", "exp": "exp", "log": "log",
                "sqrt": "sqrt", "abs": "fabs", "arcsin": "asin", "arccos": "acos",
                "arctan": "atan", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh"}
_FOLD_FUNCS = {"min": "fmin", "max": "fmax"}
_RESERVED = frozenset(_VARIABLES) | frozenset(_CONSTANTS) | frozenset(_UNARY_FUNCS) | frozenset(_FOLD_FUNCS)
_ALLOWED = ("allowed: numbers, t/theta, pi, e, parameters, + - * / **, "
            + " ".join(_UNARY_FUNCS) + " " + " ".join(_FOLD_FUNCS))
_BINOPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow}
_NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
# a plain decimal literal: no underscores, hex, nan/inf words or expressions
# (ASCII digits only: Python's float() and re's \d also take "１" and other Unicode digits)
_FLOAT_RE = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?\Z")
# a number literal in an expression: the same grammar, unsigned (the sign is an operator there)
_LITERAL_RE = re.compile(r"([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?\Z")
_FORBIDDEN_OPS = {ast.FloorDiv: "//", ast.Mod: "%", ast.MatMult: "@", ast.LShift: "<<", ast.RShift: ">>",
                  ast.BitOr: "|", ast.BitXor: "^", ast.BitAnd: "&", ast.Not: "not", ast.Invert: "~",
                  ast.And: "and", ast.Or: "or"}
_COMPARE_OPS = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!=",
                ast.In: "in", ast.NotIn: "not in", ast.Is: "is", ast.IsNot: "is not"}


def _show(text: str, limit: int = 80) -> str:
    """Quote ``text`` on one line: non-printable characters escaped, long text shortened."""
    text = str(text)
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return "'" + "".join(c if c.isprintable() else repr(c)[1:-1] for c in text) + "'"


@dataclass(frozen=True, eq=False, repr=False)  # casadi's == is symbolic, so equality stays identity
class ParsedExpression:
    """A wall expression translated to casadi.

    Attributes
    ----------
    text : str
        The original text.
    params : tuple of (str, float)
        The parameters, sorted by name.
    symbol : casadi.SX
        The scalar symbol standing for ``t``.
    expr : casadi.SX
        The expression in ``symbol``, parameters substituted as numbers.
    switching : tuple of casadi.SX
        Switching functions of ``abs``/``min``/``max``: the result may have a
        kink only where one of them is zero.  Those that do not depend on
        ``t`` are left out, since they cannot produce a kink in ``t``.
    """

    text: str
    params: tuple[tuple[str, float], ...]
    symbol: casadi.SX
    expr: casadi.SX
    switching: tuple

    @safe_repr
    def __repr__(self) -> str:
        extra = "".join(f", {k}={v:g}" for k, v in self.params)
        return f"ParsedExpression({_show(self.text, 60)}{extra}, switching={len(self.switching)})"


def _check_name(name) -> str:
    """Validate a parameter name: an ASCII identifier that is not reserved."""
    if not isinstance(name, str) or not _NAME_RE.match(name):
        raise InvalidParameter(f"parameter name {_show(name)} is not valid; use letters, digits and '_', "
                               f"not starting with a digit")
    if name.startswith("__"):
        raise InvalidParameter(f"parameter name {_show(name)} must not start with '__'")
    if name in _RESERVED:
        raise InvalidParameter(f"parameter name {_show(name)} is reserved (t, theta, pi, e and the "
                               f"function names cannot be parameters)")
    return name


def _check_value(name: str, value) -> float:
    """Validate a parameter value: a finite real number."""
    if isinstance(value, (bool, str, bytes)):
        raise InvalidParameter(f"parameter {_show(name)} must be a real number, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InvalidParameter(f"parameter {_show(name)} must be a real number, got {value!r}") from None
    if not math.isfinite(number):
        raise InvalidParameter(f"parameter {_show(name)} must be finite, got {number}")
    return number


def parse_param(text: str) -> tuple[str, float]:
    """Parse a command-line ``NAME=VALUE`` parameter.

    Parameters
    ----------
    text : str
        For example ``"eps=0.5"``; blanks around name and value are ignored.
        The value is a plain decimal number, not an expression.

    Returns
    -------
    tuple of (str, float)

    Raises
    ------
    InvalidParameter
        Missing ``=``, invalid or reserved name, value not a finite number.
    """
    if not isinstance(text, str) or "=" not in text:
        raise InvalidParameter(f"parameter {_show(text)} must have the form NAME=VALUE, e.g. eps=0.5")
    name, _, raw = (part.strip(" \t") for part in text.partition("="))
    if not name:
        raise InvalidParameter(f"parameter {_show(text)} has no name; use NAME=VALUE, e.g. eps=0.5")
    _check_name(name)
    if raw.lower().lstrip("+-") in ("inf", "infinity", "nan"):
        raise InvalidParameter(f"parameter {_show(name)} must be finite, got {raw}")
    if not _FLOAT_RE.match(raw):
        # the grammar of numbers in expressions too: no hexadecimal, underscores, complex or Unicode digits
        raise InvalidParameter(f"parameter {_show(name)} must be a plain decimal number such as 0.5 or -1e-3, "
                               f"got {_show(raw)}")
    value = float(raw)
    if not math.isfinite(value):
        raise InvalidParameter(f"parameter {_show(name)} must be finite, got {raw}")
    return name, value


def parse_params(texts, what: str = "parameter") -> dict[str, float]:
    """Parse command-line ``NAME=VALUE`` parameters (:func:`parse_param`) into a dict.

    ``what`` names them in the message (the command line passes ``"--param"``).

    Raises
    ------
    InvalidParameter
        As :func:`parse_param`, and for a name given twice (the last value would silently win).
    """
    params: dict[str, float] = {}
    for text in texts:
        name, value = parse_param(text)
        if name in params:
            raise InvalidParameter(f"{what} {name} given twice ({params[name]:g} and {value:g}); give it once")
        params[name] = value
    return params


def check_ascii(text: str, what: str = "expression") -> str:
    """Refuse any character outside ASCII, naming it and its column.

    Python's parser folds lookalike letters (``ｓｉｎ``, mathematical bold ``𝐭``) to ASCII by NFKC
    normalisation, so ``ｓｉｎ(𝐭)`` would silently read as ``sin(t)``; a wall is a number to be
    manufactured, and what the user typed should be what is computed.  So nothing outside ASCII is
    accepted (a Unicode minus sign or a non-breaking space included): the message says which
    character and where, so it can be retyped.
    """
    import unicodedata

    for column, char in enumerate(text, start=1):
        if ord(char) > 127:
            name = unicodedata.name(char, "unnamed character")
            raise InvalidExpression(f"{what} {_show(text)}: character {char!r} (U+{ord(char):04X} {name}) at "
                                    f"column {column} is not allowed; use plain ASCII (e.g. '-' for a minus, "
                                    "'t' for the angle)")
    return text


class _Translator:
    """Walks a checked AST and builds the casadi expression."""

    def __init__(self, ca, source: str, symbol, params: dict[str, float]):
        self.ca, self.source, self.symbol, self.params = ca, source, symbol, params
        self.used: set[str] = set()
        self.switching: list = []

    def fail(self, problem: str, allowed: bool = False):
        suffix = f" ({_ALLOWED})" if allowed else ""
        raise InvalidExpression(f"expression {_show(self.source)}: {problem}{suffix}")

    def segment(self, node) -> str:
        return _show(ast.get_source_segment(self.source, node) or type(node).__name__, 40)

    def switch(self, s):
        if self.ca.depends_on(s, self.symbol):
            self.switching.append(s)

    def visit(self, node):
        ca = self.ca
        if isinstance(node, ast.Constant):
            value = node.value
            if type(value) not in (int, float):
                if isinstance(value, str):
                    self.fail(f"string {_show(value, 40)} is not allowed", allowed=True)
                kind = {bool: "boolean", complex: "complex number"}.get(type(value), "literal")
                self.fail(f"{kind} {self.segment(node)} is not allowed", allowed=True)
            segment = ast.get_source_segment(self.source, node)
            if segment is not None and not _LITERAL_RE.match(segment):
                # hexadecimal, octal, binary and 1_000: --param takes plain decimals only, so do expressions
                self.fail(f"number {_show(segment, 40)} is not a plain decimal number (write e.g. 16, 0.5 or 1e-3)")
            try:
                number = float(value)
            except OverflowError:
                number = math.inf
            if not math.isfinite(number):
                self.fail(f"number {self.segment(node)} is not finite")
            return ca.SX(number)
        if isinstance(node, ast.Name):
            return self.name(node.id)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
            operand = self.visit(node.operand)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            chain = [node]  # a + b − c + …: walked as a loop, not one recursion per term
            while _chained(chain[-1], chain[-1].left) and type(chain[-1].left.op) in _BINOPS:
                chain.append(chain[-1].left)
            value = self.visit(chain[-1].left)
            for link in reversed(chain):
                value = _BINOPS[type(link.op)](value, self.visit(link.right))
            return value
        if isinstance(node, ast.Call):
            return self.call(node)
        self.reject(node)

    def name(self, ident: str):
        if ident in _VARIABLES:
            return self.symbol
        if ident in _CONSTANTS:
            return self.ca.SX(_CONSTANTS[ident])
        if ident in self.params:
            self.used.add(ident)
            return self.ca.SX(self.params[ident])
        if ident in _UNARY_FUNCS or ident in _FOLD_FUNCS:
            self.fail(f"function {_show(ident)} must be called, e.g. {ident}(t)")
        if ident.startswith("__"):
            self.fail(f"name {_show(ident)} is not allowed", allowed=True)
        close = difflib.get_close_matches(ident, list(self.params) + list(_CONSTANTS) + list(_VARIABLES), 1)
        hint = f" (did you mean {_show(close[0])}?)" if close else ""
        if not _NAME_RE.match(ident):  # could never be declared, so do not suggest --param
            self.fail(f"unknown name {_show(ident)}{hint}", allowed=True)
        self.fail(f"unknown name {_show(ident)}{hint}; declare it with --param {ident}=VALUE")

    def call(self, node: ast.Call):
        if not isinstance(node.func, ast.Name):
            self.fail(f"call of {self.segment(node.func)} is not allowed; call functions by bare name",
                      allowed=True)
        fname = node.func.id
        if fname not in _UNARY_FUNCS and fname not in _FOLD_FUNCS:
            self.fail(f"function {_show(fname)} is not allowed", allowed=True)
        if node.keywords:
            self.fail(f"keyword argument {self.segment(node.keywords[0])} in call to {_show(fname)} "
                      f"is not allowed; pass arguments by position")
        for arg in node.args:
            if isinstance(arg, ast.Starred):
                self.fail(f"starred argument {self.segment(arg)} in call to {_show(fname)} is not allowed")
        n = len(node.args)
        if fname in _UNARY_FUNCS and n != 1:
            self.fail(f"function {_show(fname)} takes 1 argument, got {n}")
        if fname in _FOLD_FUNCS and n < 2:
            self.fail(f"function {_show(fname)} takes 2 or more arguments, got {n}")
        args = [self.visit(arg) for arg in node.args]
        if fname in _UNARY_FUNCS:
            if fname == "abs":
                self.switch(args[0])
            return getattr(self.ca, _UNARY_FUNCS[fname])(args[0])
        fold = getattr(self.ca, _FOLD_FUNCS[fname])
        result = args[0]
        for arg in args[1:]:
            self.switch(result - arg)
            result = fold(result, arg)
        return result

    def reject(self, node):
        op = getattr(node, "op", None)
        if type(op) in _FORBIDDEN_OPS:
            self.fail(f"operator {_show(_FORBIDDEN_OPS[type(op)])} is not allowed", allowed=True)
        if isinstance(node, ast.Attribute):
            self.fail(f"attribute access {_show('.' + node.attr)} is not allowed", allowed=True)
        if isinstance(node, ast.Compare):
            token = _COMPARE_OPS.get(type(node.ops[0]), "?")
            self.fail(f"comparison {_show(token)} is not allowed", allowed=True)
        kinds = {ast.Subscript: "subscript", ast.Lambda: "lambda", ast.IfExp: "conditional expression",
                 ast.JoinedStr: "f-string", ast.NamedExpr: "assignment expression",
                 ast.Tuple: "tuple", ast.List: "list", ast.Dict: "dict", ast.Set: "set"}
        kind = kinds.get(type(node), f"construct {type(node).__name__}")
        self.fail(f"{kind} {self.segment(node)} is not allowed", allowed=True)


_TRAILING_COMMA = re.compile(r",\s*\)")


def check_one_line(source: str, what: str = "expression") -> str:
    """Refuse what Python's parser would take but the expression grammar does not: an expression is one line.

    No line breaks or other control characters (a tab is a blank), no comment (``#`` would silently drop
    the rest of the line: ``1 + 0.1*cos(t) # + 0.2*cos(3*t)``), no backslash continuation, and no empty item
    in an argument list (``max(t, 1,)``): list items are never empty, as in every list coinwall reads.
    """
    for column, char in enumerate(source, start=1):
        if (ord(char) < 32 and char != "\t") or ord(char) == 127:
            kind = "a line break" if char in "\n\r" else f"control character {char!r}"
            raise InvalidExpression(f"{what} {_show(source)}: {kind} at column {column}; an expression is one line")
        if char == "#":
            raise InvalidExpression(f"{what} {_show(source)}: '#' at column {column} is not allowed (no comments in "
                                    "an expression: the rest of the line would be ignored)")
        if char == "\\":
            raise InvalidExpression(f"{what} {_show(source)}: '\\' at column {column} is not allowed (no line "
                                    "continuations: an expression is one line)")
    match = _TRAILING_COMMA.search(source)
    if match:
        raise InvalidExpression(f"{what} {_show(source)}: empty argument after ',' at column {match.start() + 1}")
    return source


def _parse_tree(text: str, source: str) -> ast.Expression:
    """Parse ``source`` and refuse pathological size or nesting before the recursive walk."""
    try:
        with warnings.catch_warnings():  # e.g. "invalid decimal literal": the error that follows says it
            warnings.simplefilter("ignore", SyntaxWarning)
            tree = ast.parse(source, mode="eval")
    except SyntaxError as exc:
        if exc.lineno is None:
            where = ""
        elif not exc.offset or exc.offset < 1:  # the parser reports 0 when the text ends too early
            where = f" at column {len(source.splitlines()[-1]) + 1} (end of expression)"
        else:
            where = f" at column {exc.offset}" if exc.lineno == 1 else f" at line {exc.lineno}, column {exc.offset}"
        raise InvalidExpression(f"expression {_show(source)}: syntax error{where}: {exc.msg}") from None
    except ValueError as exc:  # e.g. null bytes (3.11 raises ValueError, not SyntaxError)
        raise InvalidExpression(f"expression {_show(text)}: {exc}") from None
    except (RecursionError, MemoryError):
        raise InvalidExpression(f"expression {_show(text)} is too deeply nested "
                                f"(at most {MAX_DEPTH} levels)") from None
    stack = [(tree.body, 1)]
    while stack:  # iterative, so the check itself cannot hit the recursion limit
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise InvalidExpression(f"expression {_show(source)} is too complex (more than {MAX_DEPTH} levels of "
                                    "nesting)")
        stack.extend((child, depth + (0 if _chained(node, child) else 1))
                     for child in ast.iter_child_nodes(node) if isinstance(child, ast.expr))
    return tree


_GROUPS = {ast.Add: "+", ast.Sub: "+", ast.Mult: "*", ast.Div: "*"}


def _chained(parent, child) -> bool:
    """Whether ``child`` continues the chain of ``parent`` (``a + b − c``: the left operand of the same kind of
    operator), so that it adds no level of nesting."""
    return (isinstance(parent, ast.BinOp) and isinstance(child, ast.BinOp) and child is parent.left
            and _GROUPS.get(type(parent.op), "?") == _GROUPS.get(type(child.op), "!"))


def parse_expression(text: str, params: Mapping[str, float] | None = None) -> ParsedExpression:
    """Parse a wall expression in ``t`` (alias ``theta``) with named parameters.

    Parameters
    ----------
    text : str
        For example ``"sqrt((1+eps*cos(t)**2)/(1+eps))"``.  Allowed: numbers,
        ``t``/``theta``, ``pi``, ``e``, the parameters, ``+ - * / **``, and the
        functions ``sin cos tan exp log sqrt abs arcsin arccos arctan sinh
        cosh tanh`` (one argument) and ``min max`` (two or more).
    params : mapping of str to float, optional
        Parameter values; every one must be used in ``text``.

    Returns
    -------
    ParsedExpression

    Raises
    ------
    InvalidExpression
        Syntax errors, anything outside the whitelist, unknown names, too long or too nested.
    InvalidParameter
        Invalid, reserved, non-finite or unused parameters.
    """
    import casadi as ca

    if not isinstance(text, str):
        raise InvalidExpression(f"expression must be a string, got {type(text).__name__}")
    if params is None:
        params = {}
    if not isinstance(params, Mapping):
        raise InvalidParameter(f"parameters must be a mapping name -> value, got {type(params).__name__}")
    values = {_check_name(name): _check_value(name, value) for name, value in params.items()}
    source = text.strip(" \t\n\r\f\v")  # a leading blank would be an IndentationError; ASCII ones only
    check_ascii(source)
    check_one_line(source)
    if not source:
        raise InvalidExpression(f"expression {_show(text)} is empty; give a wall such as '1 + 0.1*cos(2*t)'")
    if len(source) > MAX_LENGTH:
        raise InvalidExpression(f"expression {_show(source, 40)} is too long "
                                f"({len(source)} characters, at most {MAX_LENGTH})")
    tree = _parse_tree(text, source)
    symbol = ca.SX.sym("t")
    walker = _Translator(ca, source, symbol, values)
    expr = walker.visit(tree.body)
    unused = sorted(set(values) - walker.used)
    if unused:
        raise InvalidParameter(f"parameter {_show(unused[0])} is not used in the expression {_show(source)}")
    return ParsedExpression(text, tuple(sorted(values.items())), symbol, expr, tuple(walker.switching))
