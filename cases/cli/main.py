"""The ``coinwall`` command line: parse, call the library, print or write.

Bad input (any :class:`coinwall.forward.CoinwallError`) becomes one line on stderr and exit status 2;
outputs are written all-or-nothing.  The subcommands are listed in :mod:`.parser`, one module each.

:func:`main` is also the last line of defence: whatever escapes a subcommand ends as at most two lines
on stderr (the line below and at most one ``note:`` line), never a traceback (``COINWALL_DEBUG=1``
re-raises everything, bad input included, and leaves warnings to Python, for a developer):

========================== ======================================================== ======
what escaped               stderr                                                   status
========================== ======================================================== ======
CoinwallError (bad input)  ``coinwall: error: MESSAGE``                             2
OSError (a file, the disk) ``coinwall: error: cannot read or write 'PATH': REASON`` 2
MemoryError                ``coinwall: error: not enough memory: ...; ask for less`` 2
RecursionError             ``coinwall: error: the input is nested too deeply ...``  2
KeyboardInterrupt          ``coinwall: interrupted``                                130
SIGTERM, SIGHUP, ...       ``coinwall: stopped by SIGTERM``                         128 + n
any other exception        ``coinwall: internal error: TYPE: MESSAGE -- this is a   70
                           bug ...`` (asks for a report; EX_SOFTWARE of sysexits.h)
========================== ======================================================== ======

Terminals that cannot show every character: the command line writes θ, κ, ±, ≤ and friends.  On a stream whose
encoding lacks one (``LANG=C`` without Python's UTF-8 mode, ``PYTHONIOENCODING=ascii``, a latin-1 terminal, a
Windows console in cp1252) :func:`main` writes it through the error handler :data:`ASCII_FALLBACK` instead of
failing: a symbol becomes its ASCII name (θ → theta, ε → eps, κ → kappa, ± → +/-, ≤ → <=, θ₀ → theta0), any
other character a Python escape (``w\\xe4nde.csv``; a byte of a file name the locale could not decode,
``\\xc3``), so a file name stays unambiguous.  A character the stream can encode is written as it is.

A signal that would end the process (SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGXCPU, where the
process does not ignore it) is turned into an exception, like Ctrl-C: every ``finally`` clause runs, so
the temporaries of an output being written are removed (:mod:`coinwall.forward.formats.output`) and the
status is the one a shell shows for the signal.  A closed standard output is refused before any work
(the report would be lost), and one that cannot be written (a full disk) is an error, not a lost report.

Warnings (NumPy's RuntimeWarnings such as "invalid value encountered in divide", a library's
UserWarning) never reach the terminal as raw warning text: they are recorded while the command runs
and summarised in *one* ``coinwall: note:`` line at the end, with how many there were.  They are not
silenced: such a warning means a step produced a NaN or an infinity that the library did not check
for; the results themselves are checked (no file is ever written with a non-finite number, see
:func:`coinwall.forward.formats.output.refuse_non_finite`), so the note reports an unexpected event,
and asks for a report, rather than a wrong result.  The exit status is not changed by it.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import sys

# numba marks up its messages with colorama when that is installed, and colorama then writes a terminal reset
# (ESC[0m) at exit: after a --json document on a terminal, which is no longer JSON.  The command line wants plain
# text; numba's own switch for that is this variable (set before numba is imported; a user's value is kept).
os.environ.setdefault("NUMBA_DISABLE_ERROR_MESSAGE_HIGHLIGHTING", "1")

from coinwall.forward.display import one_line  # noqa: E402 - after the variable above (display imports no numba)

__all__ = ["ASCII_FALLBACK", "EX_INTERRUPTED", "EX_SOFTWARE", "ascii_fallback", "flag_message", "main",
           "restore_streams"]

#: exit status for a bug in coinwall (sysexits.h: "an internal software error has been detected")
EX_SOFTWARE = 70
#: exit status after Ctrl-C: 128 + SIGINT, what a shell reports for a program killed by it
EX_INTERRUPTED = 130


def _quiet_scan_worker() -> None:
    """In a worker process of ``coinwall scan``'s local cluster (spawned by multiprocessing, which runs this
    module first): ignore SIGINT, so that Ctrl-C stops the driver alone, which closes the cluster, instead
    of every worker printing a traceback (coinwall.cases.scan.driver.WORKER_ENVIRONMENT)."""
    # (multiprocessing.parent_process() is set only after this module ran; spawn_main has been imported by then)
    if os.environ.get("COINWALL_SCAN_WORKER") == "1" and "multiprocessing.spawn" in sys.modules:
        import signal

        signal.signal(signal.SIGINT, signal.SIG_IGN)


_quiet_scan_worker()

# the signals that end a process by default, turned into an exception by main() (module docstring)
_STOPS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP", "SIGQUIT", "SIGUSR1", "SIGUSR2", "SIGALRM",
                                                  "SIGXCPU") if hasattr(signal, name))


class _Stopped(BaseException):
    """A signal in :data:`_STOPS` arrived (``args[0]``: its number); a BaseException, as KeyboardInterrupt is."""


def _stop(number, frame):
    raise _Stopped(number)


@contextlib.contextmanager
def _signals_as_exceptions():
    """While a command runs in the main thread: the signals of :data:`_STOPS` that have their default action
    raise :class:`_Stopped` instead of killing the process (ignored ones, e.g. under ``nohup``, stay ignored)."""
    import threading

    previous = {}
    if threading.current_thread() is threading.main_thread():
        for number in _STOPS:
            if signal.getsignal(number) is signal.SIG_DFL:
                previous[number] = signal.signal(number, _stop)
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


# a library message names an argument in backticks: "`max_lag` must be ..."
_ARGUMENT = re.compile(r"`([A-Za-z_][A-Za-z0-9_]*)`")
# warnings meant for developers (hidden by Python's default filters too)
_DEVELOPER_WARNINGS = (DeprecationWarning, PendingDeprecationWarning, ImportWarning)


#: the name of the codec error handler that writes what a terminal cannot show in ASCII (module docstring)
ASCII_FALLBACK = "coinwall-ascii"
_GREEK = ("alpha beta gamma delta eps zeta eta theta iota kappa lambda mu nu xi omicron pi rho sigma sigma "
          "tau upsilon phi chi psi omega").split()
#: symbols by their ASCII names (Greek letters: lower case U+03B1..U+03C9, upper case U+0391..U+03A9)
_NAMES = {**{chr(0x3B1 + k): name for k, name in enumerate(_GREEK)},
          **{chr(0x391 + k): name.capitalize() for k, name in enumerate(_GREEK) if k != 17},
          "\u03d5": "phi", "\u03f5": "eps", "\u2113": "l", "\u0127": "hbar", "\u00b5": "u",
          "\u00b0": " deg", "\u00b1": "+/-", "\u2213": "-/+", "\u00d7": "x", "\u00b7": "*", "\u2212": "-",
          "\u2013": "-", "\u2014": "--", "\u2026": "...", "\u2032": "'", "\u2033": "''", "\u2192": "->",
          "\u21a6": "|->", "\u21d2": "=>", "\u21d4": "<=>", "\u2264": "<=", "\u2265": ">=", "\u2248": "~",
          "\u2260": "!=", "\u2261": "==", "\u226a": "<<", "\u226b": ">>", "\u2272": "<~", "\u221e": "inf",
          "\u221a": "sqrt", "\u2202": "d", "\u2207": "grad", "\u2208": " in ", "\u221d": "~", "\u222b": "int",
          "\u22a5": "perp", "\u27c2": "perp", "\u27e8": "<", "\u27e9": ">", "\u2016": "||", "\u00bd": "1/2",
          "\u00bc": "1/4", "\u00be": "3/4", "\u2153": "1/3", "\u00a7": "S", "\u00a0": " ", "\u2019": "'",
          "\u2018": "'", "\u201c": '"', "\u201d": '"', "\u2022": "*", "\u0307": "dot", "\u0308": "ddot",
          "\u0302": "hat", "\u0304": "bar", "\u1e8b": "xdot", "\u1e8f": "ydot", "\u1e91": "zhat",
          "\u2096": "n", "\u1d62": "i", "\u208a": "+", "\u208b": "-", "\u207a": "^+", "\u207b": "^-",
          "\u207d": "^(", "\u207e": "^)", "\u1d40": "^T",
          **{chr(0x2080 + k): str(k) for k in range(10)},  # subscripts: θ₀ -> theta0
          **{ch: f"^{k}" for k, ch in enumerate("\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")}}


def _ascii_names(error: UnicodeEncodeError):
    """The codec error handler :data:`ASCII_FALLBACK`: what the stream cannot encode, in ASCII (module docstring)."""
    if not isinstance(error, UnicodeEncodeError):
        raise error
    out = []
    for char in error.object[error.start:error.end]:
        if char in _NAMES:
            out.append(_NAMES[char])
        elif 0xDC80 <= ord(char) <= 0xDCFF:  # a byte of a file name the locale did not decode (surrogateescape)
            out.append(f"\\x{ord(char) - 0xDC00:02x}")
        else:
            out.append(char.encode("ascii", "backslashreplace").decode("ascii"))
    return "".join(out), error.end


def ascii_fallback(streams=None) -> list:
    """Let ``streams`` write what their encoding lacks through :data:`ASCII_FALLBACK` (module docstring).

    Parameters
    ----------
    streams : iterable of io.TextIOWrapper, optional
        Default: ``sys.stdout`` and ``sys.stderr``.  A stream that cannot be reconfigured (a test's capture) is
        left as it is.

    Returns
    -------
    list
        ``[(stream, its error handler before)]``, for :func:`restore_streams`.

    Examples
    --------
    >>> import io
    >>> stream = io.TextIOWrapper(io.BytesIO(), encoding="ascii")
    >>> changed = ascii_fallback([stream])
    >>> _ = stream.write("θ₀ ± 0.1 rad"); stream.flush()
    >>> stream.buffer.getvalue()
    b'theta0 +/- 0.1 rad'
    >>> restore_streams(changed)
    """
    import codecs

    try:
        codecs.lookup_error(ASCII_FALLBACK)
    except LookupError:
        codecs.register_error(ASCII_FALLBACK, _ascii_names)
    changed = []
    for stream in (sys.stdout, sys.stderr) if streams is None else streams:
        errors = getattr(stream, "errors", None)
        try:
            stream.reconfigure(errors=ASCII_FALLBACK)
        except (AttributeError, ValueError, OSError):
            continue
        changed.append((stream, errors))
    return changed


def restore_streams(changed) -> None:
    """Undo :func:`ascii_fallback` (for a caller that runs :func:`main` in its own process).

    Parameters
    ----------
    changed : list
        What :func:`ascii_fallback` returned.
    """
    for stream, errors in changed:
        try:
            stream.reconfigure(errors=errors)
        except (AttributeError, ValueError, OSError):
            pass


def flag_message(message: str, flags: dict) -> str:
    """``message`` in the words of the command line: every argument name in backticks that is a flag of
    the command (``flags``: ``dest -> flag``) becomes that flag, so "`max_lag` must be ..." reads
    "--max-lag must be ..."; other backticked names stay as they are."""
    return _ARGUMENT.sub(lambda match: flags.get(match.group(1), match.group(0)), message)


def _debug() -> bool:
    return os.environ.get("COINWALL_DEBUG", "").strip() not in ("", "0")


def _error(message: str) -> None:
    print(f"coinwall: error: {one_line(message, 1000)}", file=sys.stderr)


def _note_warnings(caught) -> None:
    """At most one line for the warnings recorded while the command ran (module docstring)."""
    caught = [w for w in caught if not issubclass(w.category, _DEVELOPER_WARNINGS)]
    if not caught:
        return
    counts = {}
    for w in caught:
        text = f"{w.category.__name__}: {one_line(w.message, 120)}"
        counts[text] = counts.get(text, 0) + 1
    shown = [text + (f" (x{n})" if n > 1 else "") for text, n in counts.items()]
    more = f"; and {len(shown) - 2} other kind(s)" if len(shown) > 2 else ""
    print(f"coinwall: note: unexpected warning from a library: {'; '.join(shown[:2])}{more}. No file is written "
          "with a NaN or an infinity, but please report this (COINWALL_DEBUG=1 shows where)", file=sys.stderr)


def main(argv=None) -> int:
    """Entry point of the ``coinwall`` command; returns the exit status.

    Without a subcommand it prints the help and returns 0 (a request for help, not an error).
    Usage errors of the argument parser raise ``SystemExit(2)`` after one line, as argparse does.
    """
    import warnings

    streams = ascii_fallback()
    try:
        with _signals_as_exceptions():
            if _debug():  # the developer's view: warnings and tracebacks as Python shows them
                return _run(argv)
            with warnings.catch_warnings(record=True) as caught:
                try:
                    return _guarded(argv)
                finally:
                    _note_warnings(caught)
    finally:
        restore_streams(streams)


def _guarded(argv) -> int:
    """:func:`_run`, with whatever escapes it turned into an exit status and a line (module docstring)."""
    try:
        return _run(argv)
    except MemoryError as exc:
        detail = f" ({one_line(exc, 200)})" if str(exc) else ""
        _error(f"not enough memory for this request{detail}; ask for less (fewer points, samples or collisions)")
        return 2
    except RecursionError:
        _error("the input is nested too deeply to process (Python's recursion limit was reached); "
               "simplify the expression or the file")
        return 2
    except KeyboardInterrupt:
        print("coinwall: interrupted", file=sys.stderr)
        return EX_INTERRUPTED
    except _Stopped as exc:
        print(f"coinwall: stopped by {signal.Signals(exc.args[0]).name}", file=sys.stderr)
        return 128 + exc.args[0]
    except OSError as exc:  # an input or output the library did not map: a file, a folder, the disk
        where = f" {exc.filename!r}" if getattr(exc, "filename", None) else ""
        _error(f"cannot read or write{where}: {exc.strerror or exc}")
        return 2
    except Exception as exc:  # noqa: BLE001 - the last line of defence: a bug, reported in one line
        print(f"coinwall: internal error: {type(exc).__name__}: {one_line(exc)} -- this is a bug in coinwall; "
              "please report it, with the command and the traceback that COINWALL_DEBUG=1 prints", file=sys.stderr)
        return EX_SOFTWARE


def _run(argv) -> int:
    """Parse and run the subcommand; bad input (CoinwallError) is one line and status 2."""
    from coinwall.forward.errors import CoinwallError

    from .parser import build_parser

    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    if sys.stdout is None:  # started with its standard output closed (`coinwall solve >&-`)
        _error("standard output is closed, and the command's report would be lost; redirect it to a file "
               "(or to /dev/null to discard it)")
        return 2
    from coinwall.forward.formats.output import command_scope

    from .options import check_options

    try:
        check_options(args.command, parser.commands[args.command], args)  # meaning and conflicts, before any work
        # the files named as positional arguments, and every input file read, cannot be outputs of the command
        with command_scope(_file_arguments(parser.commands[args.command], args)):
            status = args.run(args)
        try:
            sys.stdout.flush()  # a report that cannot be written (a full disk) is an error, not exit status 0
        except BrokenPipeError:
            raise
        except OSError as exc:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # Python flushes it again at exit
            _error(f"cannot write the report to standard output: {exc.strerror or exc}")
            return 2
        return status
    except CoinwallError as exc:
        if _debug():
            raise
        _error(flag_message(str(exc), parser.commands[args.command].flags))
        return 2
    except BrokenPipeError:  # the reader went away (`coinwall cases --json | head`): not an error of ours
        # Python would report the pipe again when it flushes stdout at exit; point stdout at nothing
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def _file_arguments(parser, args) -> list:
    """The positional arguments of ``args`` that name an existing regular file (the command's inputs)."""
    names = []
    for action in parser._actions:
        if action.option_strings:
            continue
        values = getattr(args, action.dest, None)
        for value in values if isinstance(values, (list, tuple)) else [values]:
            if isinstance(value, str) and value and os.path.isfile(value):
                names.append(value)
    return names


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
