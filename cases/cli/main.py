"""The ``coinwall`` command line: parse, call the library, print or write.

Bad input (any :class:`coinwall.forward.CoinwallError`) becomes one line on stderr and exit status 2;
outputs are written all-or-nothing.  The subcommands are listed in :mod:`.parser`, one module each.
"""

from __future__ import annotations

import os
import re
import sys

__all__ = ["main", "flag_message"]

# a library message names an argument in backticks: "`max_lag` must be ..."
_ARGUMENT = re.compile(r"`([A-Za-z_][A-Za-z0-9_]*)`")


def flag_message(message: str, flags: dict) -> str:
    """``message`` in the words of the command line: every argument name in backticks that is a flag of
    the command (``flags``: ``dest -> flag``) becomes that flag, so "`max_lag` must be ..." reads
    "--max-lag must be ..."; other backticked names stay as they are."""
    return _ARGUMENT.sub(lambda match: flags.get(match.group(1), match.group(0)), message)


def main(argv=None) -> int:
    """Entry point of the ``coinwall`` command; returns the exit status.

    Without a subcommand it prints the help and returns 0 (a request for help, not an error).
    """
    from coinwall.forward.errors import CoinwallError

    from .parser import build_parser

    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    try:
        return args.run(args)
    except CoinwallError as exc:
        message = flag_message(str(exc), parser.commands[args.command].flags)
        print(f"coinwall: error: {message}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader went away (`coinwall cases --json | head`): not an error of ours
        # Python would report the pipe again when it flushes stdout at exit; point stdout at nothing
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
