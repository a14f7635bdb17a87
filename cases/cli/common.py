"""What several subcommands share: the subcommand parser, the WALL and table arguments, loading them,
the progress bar, ``--com``, numbers as a reader sees them, and the lines that report written files."""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import sys
from collections.abc import Sequence

__all__ = [
    "LibraryChoices",
    "add_command",
    "check_body_finite",
    "count",
    "describe_written",
    "device_argument",
    "format_angles",
    "load_table",
    "load_wall",
    "number",
    "parse_com",
    "parse_params",
    "progress_bar",
    "seed_argument",
    "table_arguments",
    "terminal_bar",
    "wall_arguments",
    "wall_params",
    "written_lines",
]

#: the seed of every command that draws at random when no ``--seed`` is given: a command run twice prints the same
#: numbers, and the seed it used is printed (text and JSON) so that a run can be repeated or varied
DEFAULT_SEED = 0

# what a number flag accepts: ASCII decimal notation as in --param (not 0x10, 1_000 or Arabic-Indic digits, which
# float() takes), and inf/nan, so that the check that follows refuses them with its reason instead of argparse
_INTEGER = re.compile(r"[+-]?[0-9]+")
from coinwall.forward.validation import DECIMAL as _DECIMAL  # noqa: E402 (the one number grammar)

#: How far from the true angle ``critical_offset`` may report the minimum of b + b'' (read as 0)
from coinwall.inverse.tolerances import ANGLE_TOLERANCE  # noqa: E402


class LibraryChoices(Sequence):
    """The names of a table of the library (``QUANTITIES``, ``METHODS``), read on first use.

    argparse checks a value against ``choices`` and lists them in a usage error, but ``coinwall --help``
    builds every subcommand's parser and reads none of them: the table's module (and numpy, which it
    imports) is loaded only when a command that has the option runs or shows its own help.  Give the
    argument a ``metavar``: argparse would otherwise list the choices while the parser is built.

    Parameters
    ----------
    module : str
        The module that defines the table, e.g. ``"coinwall.cases.scan.quantities"``.
    table : str
        The table's name in it (its keys are the choices, in its order).
    first : tuple of str, optional
        Choices of the command line's own, offered before the table's (e.g. ``("auto",)``).
    """

    def __init__(self, module: str, table: str, first: tuple = ()):
        self.module, self.table, self.first = module, table, tuple(first)
        self._names = None

    def _load(self) -> tuple:
        if self._names is None:
            import importlib

            self._names = self.first + tuple(getattr(importlib.import_module(self.module), self.table))
        return self._names

    def __getitem__(self, index):
        return self._load()[index]

    def __len__(self) -> int:
        return len(self._load())

    def __contains__(self, value) -> bool:
        return value in self._load()


def add_command(subparsers, name, *, help, description, example):
    """A subcommand parser whose ``--help`` starts with what it computes and ends with an example.

    Parameters
    ----------
    subparsers
        The object ``add_subparsers`` returned.
    name, help : str
        The subcommand and its one line in ``coinwall --help``.
    description : str
        A paragraph (or a few): what the subcommand computes.
    example : str
        One or more command lines, without the ``$ `` prompt.
    """
    lines = "\n".join(f"  $ {line}" for line in example.strip().splitlines())
    return subparsers.add_parser(name, help=help, description=description, epilog=f"example:\n{lines}",
                                 formatter_class=argparse.RawDescriptionHelpFormatter)


def format_angles(angles, tolerance=ANGLE_TOLERANCE):
    """Angles in [0, 2π) for reading: within ``tolerance`` of 0 or of 2π (the same direction) they are 0."""
    from coinwall.forward.angles import TWO_PI
    from coinwall.forward.display import format_number

    shown = [format_number(0.0 if abs(a - TWO_PI) <= tolerance else a, tolerance) for a in angles]
    return ", ".join(shown) or "—"


def number(text: str) -> float:
    """The ``type`` of the number flags: a decimal number (``-1e-3``, ``.5``; ``inf`` and ``nan`` are left
    to the range checks, which say why they are refused).  argparse reports "invalid number value"."""
    from coinwall.forward.validation import parse_number

    return parse_number(text)


def count(text: str) -> int:
    """The ``type`` of the integer flags: an ASCII decimal whole number with an optional sign, in plain or
    exponent notation (``100000``, ``1e8``, ``2.5e3``; ``int()`` would also take ``1_000`` and other scripts'
    digits, ``١``, and would refuse ``1e8``, the way the docs write large counts).  A value that is not a
    whole number (``1.5``, ``1e-3``) is refused; the range is the subcommand's check.  argparse reports
    "invalid count value"."""
    import decimal

    from coinwall.forward.validation import ASCII_BLANKS

    text = text.strip(ASCII_BLANKS)
    if _INTEGER.fullmatch(text):
        return int(text)
    if not _DECIMAL.fullmatch(text) or not any(c.isdigit() for c in text):  # no inf/nan
        raise ValueError(text)
    value = decimal.Decimal(text)
    # a count beyond 10^30 is refused by every range; Decimal keeps "1e400" exact, so cap before int()
    if abs(value) > decimal.Decimal("1e30") or value != value.to_integral_value():
        raise ValueError(text)
    return int(value)


def parse_params(params) -> dict:
    """``--param NAME=VALUE`` options as ``{name: value}``; a name given twice is refused (the last one
    would win silently, hiding a typo in a long command line)."""
    from coinwall.forward.expression import parse_params as parse

    return parse(params, what="--param")


def check_body_finite(body, what="the body") -> None:
    """Before writing a solved body: its nodes and Bézier controls are finite numbers, and so is ``b_c``
    unless it is ``inf`` (a concave kink, which the files record as such).  A NaN body must never reach
    a file (forward.formats.output.refuse_non_finite)."""
    from coinwall.forward.formats.output import refuse_non_finite

    refuse_non_finite(what, nodes=body.outline.nodes, controls=body.outline.controls, x=body.x, y=body.y,
                      b0=body.b0, b_c=0.0 if math.isinf(body.b_c) else body.b_c)


def wall_arguments(parser, optional=False, intervals=True):
    """Add the positional WALL argument, ``--param`` and ``--degrees`` to a subcommand parser, and with
    ``intervals`` the errors of a sample file (:func:`sample_arguments`: only the commands that treat samples as
    intervals or estimates, the solver's and the critical offset's, use them)."""
    parser.add_argument("wall", nargs="?" if optional else None,
                        help="wall b(θ): an expression in t (alias theta), e.g. \"sqrt((1+eps*cos(t)**2)/(1+eps))\", "
                             "or a file: .csv (theta,b samples; header theta_deg for degrees) or .json (Fourier: "
                             "{\"a0\", \"cos\", \"sin\"}, or samples {\"theta\", \"b\"})")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="value of a parameter of the expression (repeatable)")
    if intervals:
        sample_arguments(parser)
    else:
        parser.add_argument("--degrees", action="store_true", help="the angles of a sample file are in degrees")


def sample_arguments(parser, halfwidths=True):
    """Add ``--degrees`` and the two kinds of error of a sample file: half-widths (bounds: certified intervals)
    and standard deviations (statistics: estimates with confidence intervals), named so that one is never taken
    for the other; the old ambiguous ``--sigma-b``/``--sigma-theta`` are refused by :func:`wall_options`."""
    import argparse

    parser.add_argument("--degrees", action="store_true", help="the angles of a sample file are in degrees")
    if halfwidths:
        parser.add_argument("--b-halfwidth", type=number, default=0.0, metavar="W",
                            help="a bound: every wall value of a sample file is within ±W of the truth, where larger "
                                 "than half its last digit (a column b_halfwidth does the same per sample)")
        parser.add_argument("--theta-halfwidth", type=number, default=0.0, metavar="W",
                            help="a bound on the angles' error, in the file's angle unit, where larger than half their "
                                 "last digit (a column theta_halfwidth does the same per sample)")
    parser.add_argument("--b-sd", type=number, default=None, metavar="S",
                        help="a statistic: the standard deviation of a sample file's wall values (noise; a column b_sd "
                             "does the same per sample); b_c becomes an estimate with a confidence interval")
    parser.add_argument("--theta-sd", type=number, default=None, metavar="S",
                        help="the standard deviation of the angles, in the file's angle unit (a column theta_sd)")
    for old in ("--sigma-b", "--sigma-theta"):
        parser.add_argument(old, default=None, help=argparse.SUPPRESS)


def table_arguments(parser):
    """Add WALL, ``--param``, ``--degrees``, ``--H``, ``--b0`` and ``--kappa``: the billiard table of the dynamics
    subcommands."""
    wall_arguments(parser, intervals=False)
    parser.add_argument("--H", type=number, required=True,
                        help="distance between the walls (units of κ, or of --kappa's length unit)")
    parser.add_argument("--b0", type=number, default=0.0, help="offset added to the wall (default 0)")
    parser.add_argument("--kappa", type=number, default=None, metavar="VALUE",
                        help="radius of gyration of a physical body, in the length unit of the wall, --H and --b0 "
                             "(all three are divided by it; results are in units of κ). Default: they already are "
                             "in units of κ")


def load_table(args):
    """The wall and the :class:`forward.billiard.Billiard` of a dynamics subcommand (``table_arguments``).

    With ``--kappa`` the wall, ``--H`` and ``--b0`` are lengths in the unit of κ's value and are
    divided by it: the billiard is always in units of κ (η = y/κ, paper eq. 8).
    """
    from coinwall.forward.dynamics.billiard.table import Billiard
    from coinwall.forward.errors import InvalidArgument

    kappa = args.kappa
    if kappa is not None and not (math.isfinite(kappa) and kappa > 0):
        raise InvalidArgument(f"--kappa must be a positive length, got {kappa}")
    wall = load_wall(args.wall, args.param, **wall_options(args))
    if kappa is None:
        return wall, Billiard(wall, args.H, args.b0)
    return wall, Billiard(wall.scaled(1.0 / kappa), args.H / kappa, args.b0 / kappa)


def wall_options(args) -> dict:
    """The sample-file options of :func:`sample_arguments` (degrees, half-widths, standard deviations) as keywords
    of :func:`load_wall`; the ambiguous ``--sigma-b``/``--sigma-theta`` are refused with a line naming both kinds."""
    from coinwall.forward.errors import InvalidArgument

    for old, what in (("sigma_b", "b"), ("sigma_theta", "theta")):
        if getattr(args, old, None) is not None:
            raise InvalidArgument(f"--{old.replace('_', '-')} is ambiguous: give --{what}-halfwidth for a bound (every "
                                  f"error within it: certified intervals) or --{what}-sd for a standard deviation "
                                  "(statistics: estimates with confidence intervals)")
    return {"degrees": getattr(args, "degrees", False), "b_halfwidth": getattr(args, "b_halfwidth", 0.0),
            "theta_halfwidth": getattr(args, "theta_halfwidth", 0.0), "b_sd": getattr(args, "b_sd", None),
            "theta_sd": getattr(args, "theta_sd", None)}


def load_wall(text, params, degrees=False, b_halfwidth=0.0, theta_halfwidth=0.0, b_sd=None, theta_sd=None):
    """The :class:`forward.Wall` named on the command line: ``case:NAME``, or what
    :func:`coinwall.forward.formats.load_wall` reads (expression, .csv samples, .json Fourier)."""
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.formats import load_wall as load_wall_text

    values = parse_params(params)
    if text.startswith("case:"):
        from ..catalog import get_case

        if values:
            raise InvalidWall(f"--param does not apply to {text!r}: a case fixes its own parameters")
        if b_halfwidth or theta_halfwidth or b_sd is not None or theta_sd is not None:
            raise InvalidWall(f"half-widths and standard deviations apply to sample files, not to {text!r}")
        return get_case(text).wall()
    return load_wall_text(text, values, degrees=degrees, b_halfwidth=b_halfwidth, theta_halfwidth=theta_halfwidth,
                          b_sd=b_sd, theta_sd=theta_sd)


@contextlib.contextmanager
def progress_bar(args, total, unit, show=True):
    """``with progress_bar(args, total, unit) as bar:`` :func:`terminal_bar` (None where there is none, or where
    ``show`` is false), closed on the way out however the block ends."""
    bar = terminal_bar(args, total, unit) if show else None
    try:
        yield bar
    finally:
        if bar is not None:
            bar.close()


def terminal_bar(args, total, unit):
    """A tqdm progress bar on stderr when stderr is a terminal and the output is not JSON, else None."""
    if args.json or not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    try:
        columns, lines = os.get_terminal_size(sys.stderr.fileno())
    except OSError:
        columns = lines = 0
    # a terminal that reports no size (0 × 0: some containers, CI and editor pseudo-terminals) makes
    # tqdm take −1 rows and silently hide the bar; give it a standard size instead
    size = {} if columns > 0 and lines > 0 else {"ncols": 80, "nrows": 24}
    # unit_scale=False: counts are whole numbers ("7/45 toss"), not SI-scaled floats ("7.00/45.0")
    return tqdm(total=total, unit=unit, unit_scale=False, file=sys.stderr, leave=False, **size)


def seed_argument(parser, what: str):
    """``--seed N``, the one seed flag of the commands that draw at random (default :data:`DEFAULT_SEED`).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The subcommand's parser.
    what : str
        What is drawn, for the help ("the random start states").

    Returns
    -------
    None
        The flag is added to ``parser`` (``args.seed``, an ``int``).

    Examples
    --------
    >>> import argparse
    >>> parser = argparse.ArgumentParser()
    >>> seed_argument(parser, "the draws")
    >>> parser.parse_args([]).seed, parser.parse_args(["--seed", "7"]).seed
    (0, 7)
    """
    parser.add_argument("--seed", type=count, default=DEFAULT_SEED, metavar="N",
                        help=f"seed of {what} (default {DEFAULT_SEED}: a run repeats; printed with the results)")


def wall_params(wall) -> dict:
    """The parameters of a wall as every command's JSON gives them: ``{name: value}`` (empty for a file or a
    formula without parameters; a ``case:NAME`` gives the case's own).

    Parameters
    ----------
    wall : coinwall.forward.Wall
        The wall a command read.

    Returns
    -------
    dict
        ``{name: float}``.

    Examples
    --------
    >>> from coinwall import Wall
    >>> wall_params(Wall.from_expression("1 + a*cos(2*t)", {"a": 0.1}))
    {'a': 0.1}
    >>> wall_params(load_wall("case:coin", []))
    {'eps': 99.0}
    """
    return {str(name): float(value) for name, value in dict(getattr(wall, "params", None) or {}).items()}


def device_argument(parser):
    """``--device cpu|gpu``: where the kernel follows the orbits (all CPU cores, or one CUDA GPU with numba-cuda,
    ``pip install 'coinwall[gpu]'``); ``gpu`` without a usable GPU is refused with one line before any work."""
    parser.add_argument("--device", choices=["cpu", "gpu"], default="cpu",
                        help="where the kernel runs: all CPU cores (default) or a CUDA GPU (coinwall[gpu]; "
                             "one orbit per GPU thread, worth it from ~10^4 orbits)")


def parse_com(text):
    """The ``--com X,Y`` option as a pair of floats (``None`` when not given); the one place it is parsed."""
    from coinwall.forward.errors import InvalidArgument

    if text is None:
        return None
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) != 2 or not all(math.isfinite(v) for v in values):
        raise InvalidArgument(f"--com must be two numbers X,Y, got {text!r}")
    return tuple(values)


def _replaced(path, replaced):
    return f"{path} (replaced)" if path in replaced else path


def written_lines(paths, replaced=()):
    """One ``wrote`` line per path, marking the files that replaced an existing one."""
    return [f"wrote      {_replaced(path, replaced)}" for path in paths]


def describe_written(result, replaced=()):
    """One line per written file, with the deviation the exporter achieved (used by solve and export).

    ``replaced`` names the paths that existed before (:func:`coinwall.forward.formats.output.existing_files`).
    """
    lines = []
    for path in result.paths:
        report = result.reports.get(path, {})
        name = _replaced(path, replaced)
        if "polyline" in report:
            spline = f"SPLINE exact (deviation {report['spline']:.1e}), " if "spline" in report else "cut-ready, "
            lines.append(f"wrote      {name}: {spline}LWPOLYLINE "
                         f"{report['polyline_vertices']} vertices, deviation {report['polyline']:.3g} "
                         f"<= tolerance {report['tolerance']:.3g} {report['units']}")
        elif "path" in report:
            lines.append(f"wrote      {name}: exact Bézier path (rounding {report['path']:.1e} {report['units']}), "
                         f"largest diameter {report['diameter']:.6g} {report['units']}")
        else:
            lines.append(f"wrote      {name}")
    return lines
