"""The ``coinwall`` argument parser: the explicit table of subcommands, one module each.

Every module in :data:`SUBCOMMANDS` has ``register(subparsers)``, which adds exactly its one
subcommand and sets ``run`` (the function called with the parsed arguments).  The table is the
order of ``coinwall --help``; adding a subcommand is adding a module and a line here.
"""

from __future__ import annotations

import argparse
import re

# each module imports only argparse-level things at the top; the library is imported when a command runs
from . import (
    cases,
    coin3d,
    correlation,
    critical,
    design,
    explore,
    export,
    fit,
    kam,
    mass,
    quantum,
    scan,
    section,
    simulate,
    solve,
    toss,
    verify,
    wall,
)

__all__ = ["SUBCOMMANDS", "CommandParser", "build_parser"]

#: subcommand -> the module that registers it, in the order of ``coinwall --help``
SUBCOMMANDS = {
    "solve": solve,
    "critical": critical,
    "fit": fit,
    "wall": wall,
    "export": export,
    "mass": mass,
    "simulate": simulate,
    "section": section,
    "correlation": correlation,
    "toss": toss,
    "design": design,
    "coin3d": coin3d,
    "kam": kam,
    "quantum": quantum,
    "scan": scan,
    "cases": cases,
    "verify": verify,
    "explore": explore,
}


#: a negative number in any notation float() reads: -1e-3, -.5, -1., -inf, -Infinity, -nan
_NEGATIVE_NUMBER = re.compile(r"-(\d+\.?\d*(e[+-]?\d+)?|\.\d+(e[+-]?\d+)?|inf|infinity|nan)",
                              re.IGNORECASE | re.ASCII)
#: what an option name can consist of; an argument with anything else before its '=' is not an option
_OPTION_NAME = re.compile(r"-{1,2}[A-Za-z0-9_][A-Za-z0-9_-]*")


class CommandParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` that reports usage errors in one line, remembers its flags and reads a
    leading minus sign the way a user means it.

    argparse takes every argument that starts with '-' for an option unless it matches its narrow
    negative-number pattern (``-1``, ``-.5``), so ``--b0 -1e-3``, ``--H -inf`` and the wall
    ``"-cos(t)+2"`` were refused ("expected one argument").  :meth:`_parse_optional` reads as a value
    (for the option before it, or as the positional) an argument that is not one of the parser's
    options and either is a negative number in any notation or contains a character no option name
    has (parentheses, operators, spaces, '.', ...).  Everything else is left to argparse: ``--help``,
    abbreviations (``--poin`` for ``--points``), ``-ofile.svg`` (an attached value), ``--b0=-1`` and
    the error for an unknown option (``--bogus``, ``-x``).  A wall that starts with ``-o`` or ``-h``
    followed by letters reads as that short option; write it after ``--`` (``-- "-omega*cos(t)"``).

    Attributes
    ----------
    flags : dict
        ``dest -> option string`` (the long one) of every optional argument, so that an error
        naming a library argument (```max_lag```) can be told in the flag's words (``--max-lag``).
    """

    def __init__(self, *args, **kwargs):
        self.flags = {}  # before __init__, which adds --help
        super().__init__(*args, **kwargs)

    def add_argument(self, *args, **kwargs):
        action = super().add_argument(*args, **kwargs)
        if action.option_strings:
            longest = max(action.option_strings, key=len)
            self.flags.setdefault(action.dest, longest)
        return action

    def _parse_optional(self, arg_string):
        # argparse's only hook for "is this an option?": narrowed for negative numbers and expressions
        if self._reads_as_value(arg_string):
            return None
        return super()._parse_optional(arg_string)

    def _reads_as_value(self, text: str) -> bool:
        """True for an argument starting with '-' that cannot be one of this parser's options."""
        if not text.startswith("-") or text == "--" or text in self._option_string_actions:
            return False
        if _NEGATIVE_NUMBER.fullmatch(text):
            return not self._has_negative_number_optionals  # no option of ours looks like a number
        head = text.split("=", 1)[0]
        if head in self._option_string_actions:  # --b0=-1e-3
            return False
        if text[1:2] != "-" and text[:2] in self._option_string_actions:  # -ofile.svg: a short option's value
            return False
        return not _OPTION_NAME.fullmatch(head)

    def _get_values(self, action, arg_strings):
        # Python 3.11's argparse removes a '--' even when it is an option's own value (`--H=--`) and then
        # hands the option an empty list (a TypeError later, in our code): a '--' attached with '=' is the
        # value given, checked like any other ("invalid number value: '--'")
        if arg_strings == ["--"] and action.nargs in (None, argparse.OPTIONAL):
            value = self._get_value(action, "--")
            self._check_value(action, value)
            return value
        return super()._get_values(action, arg_strings)

    def error(self, message):  # one line, exit status 2, as for every bad input
        self.exit(2, f"coinwall: error: {message}\n")


def build_parser() -> CommandParser:
    """The ``coinwall`` parser with every subcommand of :data:`SUBCOMMANDS`.

    ``parser.commands`` maps each subcommand name to its parser.
    """
    from coinwall import __version__

    parser = CommandParser(prog="coinwall", description="Rigid bodies between parallel walls as billiards "
                           "(Balazs, Chatterjee, Jackson, \"Coin Tossing as a Billiard Problem\"): wall function "
                           "-> body outline, and back; the billiard's dynamics.",
                           epilog="`coinwall COMMAND --help` describes a command, with an example.")
    parser.add_argument("--version", action="version", version=f"coinwall {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=CommandParser)
    for name, module in SUBCOMMANDS.items():
        module.register(subparsers)
        if name not in subparsers.choices:
            raise RuntimeError(f"{module.__name__}.register did not add the {name!r} subcommand")
    parser.commands = dict(subparsers.choices)
    return parser
