"""Exception hierarchy shared by the whole project.

Bad input raises a subclass of :class:`CoinwallError`; a numerical *finding*
(no convex body exists, the body has a corner) is reported in a result object,
never raised.  Messages name the argument, the offending value and what would
have been valid, in one line, so the command-line tool can print them as is.
"""

__all__ = [
    "CoinwallError",
    "InvalidExpression",
    "InvalidParameter",
    "InvalidWall",
    "InvalidOutline",
    "InvalidArgument",
    "OutputError",
]


class CoinwallError(ValueError):
    """Root of every error coinwall raises for bad input.

    Every error below is one; it is itself a :class:`ValueError`, so code that catches ``ValueError`` keeps
    working. A numerical finding (no convex body, corners) is a field of the result, never an exception.

    Examples
    --------
    >>> from coinwall import CoinwallError, Wall
    >>> try:
    ...     Wall.from_expression("1/(1+cos(t))")
    ... except CoinwallError as error:
    ...     print(type(error).__name__, isinstance(error, ValueError))
    InvalidWall True
    """


class InvalidExpression(CoinwallError):
    """A wall expression that cannot be parsed or uses something not allowed.

    Examples
    --------
    An expression is parsed against a whitelist, never evaluated as Python:

    >>> from coinwall import Wall
    >>> Wall.from_expression("__import__('os')")
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidExpression: expression '__import__('os')': function '__import__' is not allowed (allowed: numbers, t/theta, pi, e, parameters, + - * / **, sin cos tan exp log sqrt abs arcsin arccos arctan sinh cosh tanh min max)
    """


class InvalidParameter(CoinwallError):
    """A named parameter that is unknown, missing, malformed or not finite.

    Examples
    --------
    >>> from coinwall import Wall
    >>> Wall.from_expression("1 + a*cos(t)", {"a": float("nan")})
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidParameter: parameter 'a' must be finite, got nan
    """


class InvalidWall(CoinwallError):
    """A wall function that is not finite, not 2π-periodic, too short, or negative.

    Examples
    --------
    >>> from coinwall import Wall
    >>> Wall.from_expression("1/(1+cos(t))")
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidWall: wall '1/(1+cos(t))': b(θ) is not finite at θ = 3.14159 (b = inf); the wall must be finite everywhere
    """


class InvalidOutline(CoinwallError):
    """A body outline that is empty, degenerate or not readable.

    Examples
    --------
    >>> from coinwall import load_outline
    >>> load_outline("nothing.csv")
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidOutline: body file 'nothing.csv' does not exist
    """


class InvalidArgument(CoinwallError):
    """Any other argument outside its valid range (offset, resolution, method …).

    Examples
    --------
    >>> from coinwall import Wall, solve_body
    >>> solve_body(Wall.from_expression("1"), 0.0, method="exact")
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidArgument: `method` must be one of ['envelope', 'polar'], got 'exact'
    """


class OutputError(CoinwallError):
    """An output file that cannot be written (unknown format, unwritable place).

    Examples
    --------
    >>> from coinwall import Wall, solve_body
    >>> from coinwall.inverse.export import write_outputs
    >>> disc = solve_body(Wall.from_expression("1"), 0.0, points=64)
    >>> write_outputs(disc, ["disc.xyz"])
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.OutputError: output 'disc.xyz': unknown extension '.xyz'; known: .csv, .dxf, .json, .pdf, .png, .svg
    """
