"""The bound on work every long command keeps: an estimate before it starts, and a refusal past one hour.

A command that follows orbits, tosses or collisions (``simulate``, ``section``, ``correlation``, ``toss``,
``coin3d bounce``, ``quantum``) estimates its run time from the work asked for and a measured cost per unit of
work (with a margin: the costs below are upper bounds on two shared cores), *before* any of it is done.  Past
:data:`MAX_SECONDS` it refuses in one line that gives the estimate and the largest request that fits, unless
``--allow-long`` is given: nothing long starts by accident, and nothing bounded is refused.

A command adds the flag with :func:`add_allow_long` and calls :func:`check_time` with its estimate.
"""

from __future__ import annotations

__all__ = ["MAX_SECONDS", "add_allow_long", "check_time", "duration"]

#: The longest run started without --allow-long: one hour by the command's estimate.
MAX_SECONDS = 3600.0


def add_allow_long(parser) -> None:
    """Add ``--allow-long`` to a subcommand parser."""
    parser.add_argument("--allow-long", action="store_true",
                        help="run even when the estimated time exceeds one hour (the estimate is in the refusal)")


def duration(seconds: float) -> str:
    """A run time in words ("one hour", "2.5 days", "40 s").

    Examples
    --------
    >>> duration(3600.0), duration(1.8e5), duration(42.0)
    ('one hour', '2.08 days', '42 s')
    """
    if seconds == MAX_SECONDS:
        return "one hour"
    if not seconds < float("inf"):
        return "longer than any run"
    for unit, size in (("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def check_time(args, seconds: float, what: str, fits: str = "") -> float:
    """Refuse a request estimated at more than :data:`MAX_SECONDS` unless ``args.allow_long``; returns ``seconds``.

    Parameters
    ----------
    args : argparse.Namespace
        The command's arguments (``allow_long`` read when present).
    seconds : float
        The estimate (may be ``inf``: refused too).
    what : str
        What was asked for and what it costs, e.g. "--impacts 1e9 for 14400 elastic tosses (2 µs per impact)".
    fits : str
        The largest request that fits, in the command's flags (added as "ask for ...").

    Returns
    -------
    float

    Raises
    ------
    coinwall.forward.errors.InvalidArgument
        The estimate exceeds one hour and ``--allow-long`` was not given.

    Examples
    --------
    >>> import argparse
    >>> check_time(argparse.Namespace(allow_long=False), 10.0, "ten seconds of work")
    10.0
    """
    from coinwall.forward.errors import InvalidArgument

    if seconds > MAX_SECONDS and not getattr(args, "allow_long", False):
        advice = f"ask for {fits} or add --allow-long" if fits else "ask for less or add --allow-long"
        raise InvalidArgument(f"{what} would take about {duration(seconds)}, more than the {duration(MAX_SECONDS)} "
                              f"allowed without --allow-long; {advice}")
    return seconds
