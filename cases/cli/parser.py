"""The ``coinwall`` argument parser: the explicit table of subcommands, one module each.

Every module in :data:`SUBCOMMANDS` has ``register(subparsers)``, which adds exactly its one
subcommand and sets ``run`` (the function called with the parsed arguments).  The table is the
order of ``coinwall --help``; adding a subcommand is adding a module and a line here.
"""

from __future__ import annotations

import argparse

# each module imports only argparse-level things at the top; the library is imported when a command runs
from . import cases, correlation, critical, export, fit, kam, mass, section, simulate, solve, verify, wall

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
    "kam": kam,
    "cases": cases,
    "verify": verify,
}


class CommandParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` that reports usage errors in one line and remembers its flags.

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
