"""Options checked for meaning and for conflicts, in one place, before a command runs.

argparse checks each option's type; what a value *means* and which options mean nothing together is checked
here, from two tables, by :func:`check_options` (called by :func:`.main.main` after parsing, before any work):

* :data:`CONFLICTS` — options that cannot be given together: each entry names them and says why (``--cut``
  draws one contour and nothing else, so ``--dimension`` with it would be silently dropped);
* :data:`ANGLES` — options that are angles in radians: finite and at most :data:`MAX_ANGLE` in size (an angle
  of 1e300 keeps no digit of its direction once reduced to [0, 2π)).

An option counts as given when its value differs from the parser's default.  Checks that need the input
itself (``wall --H`` against the body's width) stay with their command.
"""

from __future__ import annotations

import math

__all__ = ["ANGLES", "CONFLICTS", "MAX_ANGLE", "check_options"]

#: the largest angle in radians an option takes: reduced mod 2π it still keeps 10 of its 16 digits
MAX_ANGLE = 1e6

#: command -> [(options, why)]: the options (``--flag`` given, or ``--flag=value`` given with that value) that mean
#: nothing together
CONFLICTS = {
    "export": [(("--cut", "--dimension"), "--cut draws one closed contour and nothing else (no dimension line); "
                                          "drop one of them")],
    "quantum": [(("--method=spectral", "--order"), "--order is the degree of the finite elements (--method fem, or "
                                                   "auto); the spectral method has none: drop --order")],
}

#: command -> options that are angles in radians
ANGLES = {"toss": ("--theta0",)}


def _dest(parser, flag: str):
    for action in parser._actions:
        if flag in action.option_strings:
            return action
    raise KeyError(f"no option {flag} in `coinwall {parser.prog}`")


def _given(parser, args, spec: str) -> bool:
    flag, _, wanted = spec.partition("=")
    action = _dest(parser, flag)
    value = getattr(args, action.dest, action.default)
    if wanted:
        return value is not None and str(value) == wanted
    return value != action.default and value not in (None, [], False)


def check_options(command: str, parser, args) -> None:
    """Refuse options that conflict (:data:`CONFLICTS`) or angles that mean nothing (:data:`ANGLES`).

    Parameters
    ----------
    command : str
        The subcommand.
    parser : argparse.ArgumentParser
        Its parser (for the options' defaults).
    args : argparse.Namespace
        The parsed arguments.

    Raises
    ------
    coinwall.forward.errors.InvalidArgument
        One line naming the options and why.

    Examples
    --------
    >>> from coinwall.cases.cli.parser import build_parser
    >>> parser = build_parser()
    >>> args = parser.parse_args(["export", "body.json", "-o", "b.svg", "--cut", "--dimension"])
    >>> check_options("export", parser.commands["export"], args)
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidArgument: --cut and --dimension: --cut draws one closed contour and nothing \
else (no dimension line); drop one of them
    """
    from coinwall.forward.errors import InvalidArgument

    for specs, why in CONFLICTS.get(command, ()):
        if all(_given(parser, args, spec) for spec in specs):
            raise InvalidArgument(f"{' and '.join(spec.replace('=', ' ') for spec in specs)}: {why}")
    for flag in ANGLES.get(command, ()):
        value = getattr(args, _dest(parser, flag).dest)
        if value is not None and not (math.isfinite(value) and abs(value) <= MAX_ANGLE):
            raise InvalidArgument(f"{flag} must be an angle in radians of at most {MAX_ANGLE:g} in size (reduced to "
                                  f"[0, 2π) a larger one keeps too few digits of its direction), got {value:g}")
