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
    """Root of every error coinwall raises for bad input."""


class InvalidExpression(CoinwallError):
    """A wall expression that cannot be parsed or uses something not allowed."""


class InvalidParameter(CoinwallError):
    """A named parameter that is unknown, missing, malformed or not finite."""


class InvalidWall(CoinwallError):
    """A wall function that is not finite, not 2π-periodic, too short, or negative."""


class InvalidOutline(CoinwallError):
    """A body outline that is empty, degenerate or not readable."""


class InvalidArgument(CoinwallError):
    """Any other argument outside its valid range (offset, resolution, method …)."""


class OutputError(CoinwallError):
    """An output file that cannot be written (unknown format, unwritable place)."""
