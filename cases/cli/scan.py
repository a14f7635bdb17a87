"""``coinwall scan``: a quantity on a grid of wall parameters × H, on dask.distributed, into a Zarr store."""

from __future__ import annotations

import json
import os
import shlex
import sys

from .budget import add_allow_long, check_time
from .common import LibraryChoices, add_command, count, number, seed_argument, terminal_bar, written_lines

__all__ = ["register"]

DESCRIPTION = """\
Compute QUANTITY on every cell of a grid (wall parameters × H) with dask.distributed and write it,
cell by cell, into the Zarr store RESULT (read it with xarray.open_zarr; docs/scan.md).

QUANTITY: chaotic-fraction (share of Liouville-random orbits with λ/collision > 3 ln N/N), lyapunov
(mean λ over orbits), tau (decay time of P(n)), splitting (lowest heads–tails doublet of the quantum
coin), toss (the toss that lands on a floor: outcome shares, bias and bounces under a Gaussian hand;
scan --param restitution=LIST with --H as the launch height, i.e. the toss energy).
Axes: --param NAME=LIST|START:STOP:N[log] scans a parameter of the wall expression (--param
NAME=VALUE fixes one), --H LIST|START:STOP:N is required; e.g. eps=0.5:30:20log, H=2,3,4.
Each cell has its own seed, from --seed and the cell's coordinates: the arrays do not depend on
the number of workers.  Started again with the same command, a scan computes only the cells that
are missing (a killed scan loses only the cells it was computing); a store made with other options
is refused.  Default: a local cluster of one process per core (--workers N); --scheduler
tcp://HOST:PORT uses a running cluster whose workers have coinwall installed."""

EXAMPLE = """\
coinwall scan chaotic-fraction "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=0.5:30:16log --H 2:8:13 -o kam.zarr --figure kam.png
coinwall scan tau "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=99 --H 2.1:3:7 --bounces 100000 -o tau.zarr --figure tau.png
coinwall scan toss "sqrt((1+eps*cos(t)**2)/(1+eps))" --param eps=99 --param restitution=0.3:0.9:7 --H 1.2:6:9 -o toss.zarr --figure toss.png"""

#: quantity options: flag dest -> library option name (each applies to some quantities; others are refused)
_OPTIONS = ("orbits", "collisions", "every", "threshold", "bounces", "max_lag", "count", "pair", "cells", "order",
            "tosses", "g", "v0", "omega0", "spread", "impacts", "device")


def register(subparsers):
    """Add the ``scan`` subcommand."""
    scan = add_command(subparsers, "scan", help="a quantity on a grid of (parameter, H) on dask.distributed, "
                       "resumable, into a Zarr store", description=DESCRIPTION, example=EXAMPLE)
    scan.add_argument("quantity", choices=LibraryChoices("coinwall.cases.scan.quantities", "QUANTITIES"),
                      metavar="QUANTITY", help="%(choices)s")
    scan.add_argument("wall", help="wall b(θ): an expression in t, case:NAME, or a .csv/.json wall file "
                                   "(only an expression's parameters can be scanned)")
    scan.add_argument("--param", action="append", default=[], metavar="NAME=VALUES",
                      help="a parameter of the expression: one value (fixed) or LIST|START:STOP:N[log] (scanned; "
                           "repeatable)")
    scan.add_argument("--degrees", action="store_true", help="the angles of a sample file are in degrees")
    scan.add_argument("--H", required=True, metavar="LIST|START:STOP:N",
                      help="wall distances (units of κ, or of --kappa's length unit)")
    scan.add_argument("--b0", type=number, default=0.0, help="offset added to the wall (default 0)")
    scan.add_argument("--kappa", type=number, default=None, metavar="VALUE",
                      help="radius of gyration in the length unit of the wall, --H and --b0 (default: units of κ)")
    # quantity options (defaults: docs/scan.md); on the parser itself, not in an argument group, so that the
    # parser's flag table turns a library message about `max_lag` into --max-lag
    group = scan
    group.add_argument("--orbits", type=count, default=None, help="orbits per cell")
    group.add_argument("--collisions", type=count, default=None, help="collisions per orbit (exponents)")
    group.add_argument("--every", type=count, default=None, help="collisions between renormalisations (10)")
    group.add_argument("--threshold", type=number, default=None, help="chaos threshold per collision (3 ln N/N)")
    group.add_argument("--bounces", type=count, default=None, help="counted collisions per cell (tau)")
    group.add_argument("--max-lag", type=count, default=None, help="largest n of P(n) (tau)")
    group.add_argument("--count", choices=["bottom", "all"], default=None, help="n counts bottom or all (tau)")
    group.add_argument("--pair", type=count, default=None, help="doublet index, 0 = lowest (splitting)")
    group.add_argument("--cells", type=count, default=None, help="mesh rows across the strip (splitting)")
    group.add_argument("--order", type=count, default=None, help="element degree 2..4 (splitting)")
    group.add_argument("--tosses", type=count, default=None, help="tosses per cell (toss; default 2000)")
    group.add_argument("--g", type=number, default=None, help="field in κ/s² (toss; default 1)")
    group.add_argument("--v0", type=number, default=None, help="launch velocity, κ/s (toss; default 2)")
    group.add_argument("--omega0", type=number, default=None, help="launch spin, rad/s (toss; default 5)")
    group.add_argument("--spread", type=number, default=None,
                       help="relative standard deviation of the hand's v0 and ω0 (toss; default 0.02)")
    group.add_argument("--impacts", type=count, default=None, help="impacts per toss at most (toss; default 10000)")
    group.add_argument("--device", choices=["cpu", "gpu"], default=None,
                       help="where the orbits run (chaotic-fraction, lyapunov, tau, toss; default cpu): gpu "
                            "computes each cell's orbits on a CUDA GPU (coinwall[gpu]), one local worker by default")
    seed_argument(scan, "the scan (each cell's seed is drawn from it and the cell's coordinates)")
    scan.add_argument("--scheduler", default="local", metavar="local|synchronous|tcp://HOST:PORT",
                      help="'local' (default): a local cluster made for this scan; 'synchronous': every cell in this "
                           "process, one after the other; or a running scheduler")
    scan.add_argument("--workers", type=count, default=None,
                      help="local worker processes (default: one per core, at most what the memory holds); with "
                           "--scheduler, wait for N")
    scan.add_argument("-o", "--output", required=True, metavar="RESULT.zarr", help="the Zarr store (resumed if it "
                      "exists)")
    scan.add_argument("--figure", action="append", default=[], metavar="FILE",
                      help="figure of the result (.png, .svg, .pdf; repeatable): phase diagram or τ(H)")
    scan.add_argument("--json", action="store_true", help="print the summary as JSON (no progress bar)")
    add_allow_long(scan)
    scan.set_defaults(run=_cmd_scan)


def _table(args):
    """The TableSpec and the scanned axes' texts from WALL and --param."""
    from coinwall.cases.scan import TableSpec
    from coinwall.forward.errors import InvalidArgument, InvalidParameter

    from .common import load_wall, parse_params, wall_options

    fixed, grid = [], {}
    for text in args.param:
        name, sep, value = text.partition("=")
        name = name.strip()
        if sep and ("," in value or ":" in value):
            if name in grid:
                raise InvalidParameter(f"--param {name} given twice; give it once")
            grid[name] = value
        else:
            fixed.append(text)
    params = parse_params(fixed)
    both = sorted(set(params) & set(grid))
    if both:  # a fixed value and a scanned axis for one name: which would the wall use?
        raise InvalidParameter(f"--param {both[0]} given twice; give it once")
    if args.wall.startswith("case:") or args.wall.lower().endswith((".csv", ".json")):
        import pickle

        from coinwall.cases.scan.table import TOSS_AXES

        if set(grid) - set(TOSS_AXES):
            raise InvalidArgument(f"--param: {args.wall!r} is not an expression, its parameters cannot be scanned")
        toss_fixed = tuple((k, v) for k, v in params.items() if k in TOSS_AXES)  # the toss's, not the wall's
        wall_params = [f"{k}={v!r}" for k, v in params.items() if k not in TOSS_AXES]
        spec = TableSpec(load_wall(args.wall, wall_params, **wall_options(args)), toss_fixed, args.b0, args.kappa)
        if not isinstance(spec.wall, str):
            try:
                pickle.dumps(spec.wall)  # it travels to the workers as an object
            except Exception:  # noqa: BLE001 - whatever pickle raises, the answer is the same
                raise InvalidArgument(f"wall {args.wall!r} cannot be sent to workers; give it as an expression") \
                    from None
        return spec, grid
    return TableSpec(args.wall, tuple(params.items()), args.b0, args.kappa), grid


def _command(args) -> str:
    """The command line that made the store, rebuilt from the options that decide its numbers (an attribute)."""
    parts = ["coinwall", "scan", args.quantity, args.wall]
    for text in args.param:
        parts += ["--param", text]
    parts += ["--H", args.H, "--b0", repr(args.b0), "--seed", str(args.seed)]
    if args.kappa is not None:
        parts += ["--kappa", repr(args.kappa)]
    for name in _OPTIONS:
        if getattr(args, name) is not None:
            parts += [f"--{name.replace('_', '-')}", str(getattr(args, name))]
    return " ".join(shlex.quote(p) for p in parts)


def _check_work(args, table, grid, options) -> None:
    """The scan's time at 1 µs per collision over its workers (the whole grid: a resume is estimated as a new
    scan); refused past one hour without --allow-long.  The quantum splitting is bounded per cell by its mesh."""
    import math
    import os

    from coinwall.cases.scan.driver import make_axes
    from coinwall.cases.scan.quantities import check_options, work_of

    work = work_of(args.quantity, check_options(args.quantity, options))
    if not math.isfinite(work):
        return
    cells = math.prod(len(axis) for axis in make_axes(dict(grid), table))
    local = args.scheduler in (None, "local", "synchronous")
    workers = 1 if args.scheduler == "synchronous" else args.workers or (os.cpu_count() or 1 if local else 1)
    check_time(args, cells * work * 1e-6 / workers, f"{cells} cells of about {work:.3g} collisions each ({workers} "
               "worker(s), 1 µs per collision)", "fewer cells or less work per cell")


def _cmd_scan(args):
    from coinwall.cases.scan import scan
    from coinwall.forward.formats.figure import FIGURE_FORMATS, figure_bytes
    from coinwall.forward.formats.output import check_paths, write_all

    check_paths(args.figure, FIGURE_FORMATS)
    table, grid = _table(args)
    grid["H"] = args.H
    options = {name: getattr(args, name) for name in _OPTIONS if getattr(args, name) is not None}
    _check_work(args, table, grid, options)
    bar = None

    def progress(done, todo):
        nonlocal bar
        if bar is None:
            bar = terminal_bar(args, todo, "cell")
            if bar is None:
                return
        bar.update(done - bar.n)
        bar.set_postfix_str(f"{todo - done} left", refresh=False)

    def note(text):  # as it arises: a damaged cell computed again, fewer workers than asked
        print(f"coinwall: note: {text}", file=sys.stderr, flush=True)

    command = _command(args)
    try:
        result = scan(args.quantity, table, grid, output=args.output, options=options, seed=args.seed,
                      scheduler=args.scheduler, workers=args.workers, progress=progress, command=command, notes=note)
    finally:
        if bar is not None:
            bar.close()
    files = {}
    if args.figure:
        from coinwall.cases.scan.figures import plot_scan

        dataset = result.dataset()
        for path in args.figure:
            files[path] = figure_bytes(plot_scan(dataset).figure, path)
    written = write_all(files)
    # cells the library refused are stored as NaN with their status; like a body with warnings, the command
    # then exits 1 and says so on stderr, so a script cannot take a grid with holes for a complete one
    status = 1 if result.refused else 0
    if result.refused:
        print(f"coinwall: warning: {result.refused} of {result.cells} cells refused (NaN in the store; the reasons "
              f"are in {'the JSON' if args.json else 'the notes'})", file=sys.stderr)
    if args.json:
        # the fixed parameters as {name: value}, as every command gives them (the scanned ones are the grid's axes)
        print(json.dumps(dict(result.to_dict(), wall=args.wall, params=dict(table.params), seed=args.seed,
                              figures=list(args.figure)), indent=1, allow_nan=False))
        return status
    print(f"store      {os.path.abspath(result.path)}")
    print(f"cells      {result.cells}: {result.computed} computed now, {result.resumed} already in the store, "
          f"{result.refused} refused; seed {args.seed}")
    if result.computed:
        print(f"time       {result.seconds:.1f} s on {result.workers} workers "
              f"({result.computed / max(result.seconds, 1e-9):.3g} cells/s)")
    for message in result.messages:
        print(f"note       refused cell: {message}")
    for line in written_lines(written, written.replaced):
        print(line)
    return status
