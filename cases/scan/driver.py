"""The scan driver: a map of pure, seeded cell tasks on dask.distributed; the driver alone writes the store.

:func:`scan` checks everything it can before any work (the quantity's options, the grid, the wall at the
first cell, the memory of the bookkeeping), makes or reopens the store (:mod:`.store`), submits one task
per cell that is not yet computed (``client.map`` of :func:`.quantities.compute_cell`) and writes each
result as it arrives (``as_completed``).  A cell's numbers depend only on its coordinates, the options and
the scan's seed, never on the worker or the order, so any number of workers gives the same arrays.

Workers.  The billiard kernel holds the GIL (numba functions compiled without ``nogil``), so threads in one
process would run the cells one at a time: the default cluster is :class:`distributed.LocalCluster` with
one single-threaded *process* per core (measured in tests/benchmarks/bench_scan.py), and each cell runs the
kernel with one numba thread.  ``scheduler="tcp://HOST:PORT"`` uses a running cluster instead; its workers
need coinwall installed, and should also run one thread each (``dask worker --nthreads 1 --nworkers N``).

Losing a worker.  Tasks of a worker that dies are run again elsewhere by the scheduler (a worker death
counts toward ``distributed.scheduler.allowed-failures``, 3 by default); a task that raises is retried
``retries`` times.  Cells already written stay written: a scan that stops for any reason (a kill, Ctrl-C,
the driver's machine) is resumed by running it again with the same arguments.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import time
from dataclasses import dataclass

import numpy as np

from coinwall.forward.display import safe_repr
from coinwall.forward.errors import CoinwallError, InvalidArgument
from coinwall.forward.validation import check_count, check_memory

from .grid import cell_seed, cells, parse_axis
from .quantities import QUANTITIES, check_options, compute_cell
from .store import STATUS_REFUSED, STATUS_TODO, CellWriter, create_store, open_store
from .table import TableSpec


class ScanError(CoinwallError):
    """A scan stopped before its last cell for a reason outside the input (workers that kept dying); the
    cells finished are in the store and the same command resumes."""


__all__ = ["WORKER_BYTES", "ScanError", "ScanResult", "make_axes", "scan", "worker_limit"]

_BYTES_PER_CELL = 4000.0  # the driver's bookkeeping per submitted cell (a future, its key, its arguments)
#: memory one local worker process holds while it computes a cell: the interpreter, numpy, numba and the compiled
#: kernel, casadi, dask's worker (0.25-0.35 GB resident after a chaotic-fraction cell; rounded up)
WORKER_BYTES = 512 * 2**20
_QUIET_LOGGERS = ("distributed", "tornado", "asyncio", "bokeh")


@dataclass(frozen=True, repr=False)
class ScanResult:
    """What one run of :func:`scan` did.

    Attributes
    ----------
    path : str
        The store (``xarray.open_zarr(path)`` reads it).
    quantity : str
    cells : int
        Cells in the grid.
    computed : int
        Cells computed by this run.
    resumed : int
        Cells found already computed in the store.
    refused : int
        Cells the library refused (status 2 in the store), over all runs.
    messages : tuple of str
        The distinct refusal messages of this run (at most 5).
    seconds : float
        Wall-clock time of this run.
    workers : int
        Workers of the cluster.
    notes : tuple of str
        What the run repaired or changed (damaged cells computed again, fewer workers than asked), in words.

    Examples
    --------
    >>> from coinwall.cases.scan import TableSpec, scan
    >>> ellipse = TableSpec("sqrt((1+eps*cos(t)**2)/(1+eps))")
    >>> result = scan("splitting", ellipse, {"eps": "1", "H": "2.3,2.5"}, output="result.zarr",
    ...               options={"cells": 4}, scheduler="synchronous")
    >>> result.quantity, result.cells, result.resumed, result.path
    ('splitting', 2, 0, 'result.zarr')
    """

    path: str
    quantity: str
    cells: int
    computed: int
    resumed: int
    refused: int
    messages: tuple
    seconds: float
    workers: int
    notes: tuple = ()

    def dataset(self):
        """The store as an :class:`xarray.Dataset` (lazy)."""
        import xarray as xr

        return xr.open_zarr(self.path)

    def to_dict(self) -> dict:
        """JSON-ready dictionary."""
        return {"path": self.path, "quantity": self.quantity, "cells": self.cells, "computed": self.computed,
                "resumed": self.resumed, "refused": self.refused, "messages": list(self.messages),
                "seconds": self.seconds, "workers": self.workers, "notes": list(self.notes)}

    @safe_repr
    def __repr__(self) -> str:
        return (f"ScanResult({self.quantity}: {self.computed} of {self.cells} cells computed in "
                f"{self.seconds:.1f} s on {self.workers} workers, {self.resumed} resumed, {self.refused} refused; "
                f"{self.path})")


def make_axes(grid: dict, table: TableSpec) -> list:
    """The axes of ``grid`` (name → ``LIST | START:STOP:N[log]`` text or a sequence of numbers): the wall
    parameters in the order given, then ``H`` (required).

    Parameters
    ----------
    grid : dict
        Axis name → text or numbers; ``"H"`` is required.
    table : TableSpec
        The wall whose parameters the other axes name.

    Returns
    -------
    list of Axis

    Raises
    ------
    InvalidArgument
        For a grid that is not a dict with an ``H`` axis, an axis that names no parameter of the wall, or
        a bad axis text.

    Examples
    --------
    >>> from coinwall.cases.scan import TableSpec, make_axes
    >>> axes = make_axes({"eps": "0.5,1", "H": "3:4:2"}, TableSpec("sqrt((1+eps*cos(t)**2)/(1+eps))"))
    >>> [(axis.name, axis.values, axis.units) for axis in axes]
    [('eps', (0.5, 1.0), '1'), ('H', (3.0, 4.0), 'kappa')]
    """
    if not isinstance(grid, dict) or "H" not in grid:
        raise InvalidArgument(f"`grid` must be a dict with an 'H' axis (and wall parameters), got {grid!r}")
    h_units = "kappa" if table.kappa is None else f"length unit of the wall (kappa = {table.kappa:g})"
    axes = []
    for name, spec in [*((k, v) for k, v in grid.items() if k != "H"), ("H", grid["H"])]:
        text = spec if isinstance(spec, str) else ",".join(repr(float(v)) for v in np.atleast_1d(spec))
        axes.append(parse_axis(name, text, h_units if name == "H" else "1"))
    fixed = {k for k, _ in table.params}
    clash = sorted(fixed & set(grid))
    if clash:
        raise InvalidArgument(f"`{clash[0]}` is both a fixed parameter and a scanned axis; give it once")
    return axes


def _require():
    """Refuse in one line when the optional dependencies of a scan are missing."""
    import importlib.util

    missing = [name for name in ("distributed", "xarray", "zarr") if importlib.util.find_spec(name) is None]
    if missing:
        raise InvalidArgument(f"`scheduler`: scans need dask.distributed, xarray and zarr ({', '.join(missing)} "
                              f"missing): pip install 'coinwall[scan]'")


def worker_limit() -> tuple:
    """``(workers, why)``: how many local worker processes this machine can hold, one per core and
    :data:`WORKER_BYTES` each within :data:`~coinwall.forward.validation.MEMORY_FRACTION` of the available memory."""
    from coinwall.forward.validation import MEMORY_FRACTION, available_memory

    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    memory = MEMORY_FRACTION * available_memory()
    by_memory = int(memory // WORKER_BYTES)
    why = (f"{cores} core(s), {memory / 2**30:.3g} GiB of memory for workers at about {WORKER_BYTES / 2**30:.2g} GiB "
           "each")
    return max(1, min(cores, by_memory)), why


def _quiet_logs():
    """Silence the loggers of dask.distributed, tornado and asyncio (closing a cluster after Ctrl-C makes them
    report every cancelled task and closed connection); returns what to restore."""
    import logging

    saved = {}
    for name in _QUIET_LOGGERS:
        logger = logging.getLogger(name)
        saved[name] = (logger.level, logger.disabled)
        logger.disabled = True
    return saved


def _restore_logs(saved) -> None:
    import logging

    for name, (level, disabled) in saved.items():
        logger = logging.getLogger(name)
        logger.setLevel(level)
        logger.disabled = disabled


#: set in the environment of the local cluster's worker processes: :mod:`coinwall.cases.cli.main`, which
#: multiprocessing runs first in every worker it spawns from the command line, then ignores SIGINT there
WORKER_ENVIRONMENT = "COINWALL_SCAN_WORKER"


@contextlib.contextmanager
def _workers_ignore_sigint():
    """Ctrl-C in a terminal goes to the whole process group: the worker processes would each print a
    traceback.  While the cluster starts, SIGINT is ignored here, so that the worker processes start with it
    ignored (a Python started so keeps it so) and their interpreter start-up cannot be cut short; their
    environment (:data:`WORKER_ENVIRONMENT`) makes a worker the cluster restarts later ignore it too.  The
    driver alone stops, and closes the cluster.  (The cost: a Ctrl-C in the second or two the cluster takes
    to start is not seen; the next one is.)"""
    import threading

    os.environ[WORKER_ENVIRONMENT] = "1"  # for the cluster's life: removed by _close
    main = threading.current_thread() is threading.main_thread()
    handler = signal.getsignal(signal.SIGINT) if main else None
    if main:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        if main:
            signal.signal(signal.SIGINT, handler if handler is not None else signal.SIG_DFL)


def _check_address(scheduler) -> None:
    """Refuse, in one line, a scheduler address that is not ``PROTOCOL://HOST:PORT``."""
    from distributed.comm.addressing import parse_address, parse_host_port

    if not (isinstance(scheduler, str) and scheduler.startswith(("tcp://", "tls://", "ucx://", "inproc://"))):
        raise InvalidArgument(f"`scheduler` must be 'local', 'synchronous' or an address tcp://HOST:PORT, "
                              f"got {scheduler!r}")
    try:
        protocol, location = parse_address(scheduler)
        if protocol != "inproc":
            parse_host_port(location)
    except Exception:  # noqa: BLE001 - whatever the parser says, the address is not one
        raise InvalidArgument(f"`scheduler` {scheduler!r} is not an address PROTOCOL://HOST:PORT (an IPv6 host is "
                              "written in brackets: tcp://[::1]:8786)") from None


def _client(scheduler, workers, notes):
    """A connected :class:`distributed.Client` and the LocalCluster we made for it (or None)."""
    from distributed import Client, LocalCluster

    if scheduler in (None, "local"):
        limit, why = worker_limit()
        n = min(workers or limit, limit)
        if workers and workers > limit:
            notes.append(f"asked for {workers} workers; this machine can hold {limit} ({why}): using {limit}")
        # ":0": any free port for the scheduler's HTTP endpoints (8787 may be taken by another cluster, and
        # the warning that says so would reach the user)
        # the workers' own log lines (a heartbeat to a scheduler that is closing) are not the user's business:
        # a cell that fails reaches the driver as an exception
        try:
            with _workers_ignore_sigint():
                cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                                       silence_logs=logging.CRITICAL)
        except BaseException:
            os.environ.pop(WORKER_ENVIRONMENT, None)
            raise
        return Client(cluster), cluster
    _check_address(scheduler)
    try:
        client = Client(scheduler, timeout="20s")
    except Exception as exc:  # noqa: BLE001 - OSError, TimeoutError, ValueError of a host that does not resolve ...
        raise InvalidArgument(f"`scheduler` {scheduler!r}: cannot connect ({type(exc).__name__}: {exc})") from None
    if workers:
        try:
            client.wait_for_workers(workers, timeout=120)
        except TimeoutError:
            have = len(client.scheduler_info(n_workers=-1)["workers"])
            client.close()
            raise InvalidArgument(f"`workers`: only {have} of {workers} workers joined {scheduler} within 120 s") \
                from None
    return client, None


def _close(client, cluster, interrupted) -> None:
    """Close the client and the cluster we made; after an interruption quietly (no log lines, no traceback)."""
    saved = _quiet_logs() if interrupted else None
    try:
        with contextlib.suppress(Exception):
            client.close(timeout=10)
        if cluster is not None:
            with contextlib.suppress(Exception):
                cluster.close(timeout=10)
            os.environ.pop(WORKER_ENVIRONMENT, None)
    finally:
        if saved is not None:
            _restore_logs(saved)


def _check_toss_grid(table, axes, options) -> None:
    """Refuse, before any store is made, the toss cells that could only fail: a restitution outside (0, 1] and a
    launch height H the body does not clear (checked on the first wall of the grid)."""
    from coinwall.forward.dynamics.floor.toss import launch_states

    from .table import DEFAULT_RESTITUTION

    scanned = {a.name: a.values for a in axes}
    values = scanned.get("restitution", [dict(table.params).get("restitution", DEFAULT_RESTITUTION)])
    for value in values:
        if not 0.0 < float(value) <= 1.0:
            raise InvalidArgument(f"restitution must be in (0, 1], got {value!r}")
    first = {a.name: a.values[0] for a in axes[:-1]}
    field = table.field_table_at(first, float(options["g"]))
    kappa = 1.0 if table.kappa is None else float(table.kappa)
    for H in axes[-1].values:
        try:
            launch_states(field, 0.0, 0.0, float(H) / kappa)
        except InvalidArgument as exc:
            raise InvalidArgument(f"--H {H:g} (the launch height of the toss scan): {exc}") from None


def scan(quantity: str, table: TableSpec, grid: dict, *, output: str, options: dict | None = None, seed: int = 0,
         scheduler: str = "local", workers: int | None = None, client=None, retries: int = 3, progress=None,
         command: str = "", notes=None) -> ScanResult:
    """Compute ``quantity`` on every cell of ``grid`` and store it at ``output`` (resuming what is there).

    Parameters
    ----------
    quantity : {"chaotic-fraction", "lyapunov", "tau", "splitting"}
    table : TableSpec
        The wall (an expression, so its parameters can be scanned), fixed parameters, b0, κ.
    grid : dict
        Axis name → ``"a,b,c"``, ``"START:STOP:N"``, ``"START:STOP:Nlog"`` or a sequence of numbers; ``"H"``
        is required, the other names are wall parameters (e.g. ``{"eps": "0.5:30:20log", "H": "2:8:13"}``).
    output : str
        The Zarr directory store.  If it exists it must come from the same scan (same quantity, options,
        wall, grid, seed and coinwall version); only its missing cells are computed.
    options : dict, optional
        The quantity's options (:data:`.quantities.QUANTITIES` defaults).
    seed : int
        The scan's seed; each cell's comes from it and the cell's coordinates (:func:`.grid.cell_seed`).
    scheduler : str
        ``"local"`` (a :class:`~distributed.LocalCluster` made and closed here), ``"synchronous"`` (every cell
        in this process, one after the other: small scans, tests, debugging) or ``"tcp://HOST:PORT"``.
    workers : int, optional
        Local worker processes (default: one per core; with the option ``device="gpu"`` one, which computes
        whole cells on the GPU); at most what the machine can hold (cores, and
        memory at :data:`WORKER_BYTES` each: :func:`worker_limit`), with a note.  With an address, wait for
        that many.
    client : distributed.Client, optional
        Use this client instead (``scheduler`` and ``workers`` are then ignored).
    retries : int
        Times a task that raised is run again.
    progress : callable, optional
        ``progress(done, todo)`` after each cell written by this run.
    command : str
        Recorded in the store's attributes (the CLI passes its command line).
    notes : callable, optional
        ``notes(text)`` for each note as it arises (a damaged cell computed again, fewer workers); they are
        also in :attr:`ScanResult.notes`.

    Returns
    -------
    ScanResult

    Raises
    ------
    InvalidArgument
        For an unknown quantity or option, a grid without ``H`` or with a bad axis, a store made by a
        different scan, or a scheduler that cannot be reached.

    Examples
    --------
    The ellipse's tunnelling splitting at two wall distances, every cell in this process (a real scan uses
    a dask cluster); the store is read back with xarray:

    >>> from coinwall.cases.scan import TableSpec, scan
    >>> ellipse = TableSpec("sqrt((1+eps*cos(t)**2)/(1+eps))")
    >>> result = scan("splitting", ellipse, {"eps": "1", "H": "2.3,2.5"}, output="splitting.zarr",
    ...               options={"cells": 4}, scheduler="synchronous")
    >>> result.computed, result.refused
    (2, 0)
    >>> import xarray
    >>> [f"{value:.3e}" for value in xarray.open_zarr("splitting.zarr").splitting.values.ravel()]
    ['2.068e-05', '3.844e-03']
    """
    from coinwall import __version__

    _require()
    if not isinstance(table, TableSpec):
        raise InvalidArgument(f"`table` must be a TableSpec, got {type(table).__name__}")
    options = check_options(quantity, options)
    seed = check_count("seed", seed, minimum=0)
    if options.get("device") == "gpu" and client is None and scheduler in (None, "local", "synchronous"):
        from coinwall.forward.dynamics.billiard.gpu import check_device

        check_device("gpu")  # here, before the store is made: the local workers are this machine
        if workers is None:
            workers = 1  # one process drives the GPU, a whole cell (all its orbits) per launch
    retries = check_count("retries", retries, minimum=0)
    if workers is not None:
        workers = check_count("workers", workers, maximum=4096)
    if not isinstance(output, str) or not output.strip():
        raise InvalidArgument(f"`output` must be a path for the store, got {output!r}")
    axes = make_axes(grid, table)
    from .table import TOSS_AXES

    misplaced = sorted(set(TOSS_AXES) & ({a.name for a in axes} | {k for k, _ in table.params}))
    if misplaced and quantity != "toss":
        raise InvalidArgument(f"`{misplaced[0]}` is a parameter of the toss quantity, not of {quantity!r}")
    if quantity == "toss":
        _check_toss_grid(table, axes, options)
    shape = tuple(len(a) for a in axes)
    total = int(np.prod(shape))
    check_memory(f"a grid of {total} cells ({_BYTES_PER_CELL:g} bytes of bookkeeping per cell)",
                 total * _BYTES_PER_CELL)
    names = [a.name for a in axes[:-1]]
    first = {n: a.values[0] for n, a in zip(names, axes)}
    table.wall_at(first)  # a wrong parameter name or expression fails here, once, not in every cell
    identity = {"quantity": quantity, "options": options, **table.identity(), "seed": seed,
                "axes": {a.name: list(a.values) for a in axes}, "coinwall_version": __version__}
    if quantity == "toss" and "restitution" not in {a.name for a in axes} | {k for k, _ in table.params}:
        from .table import DEFAULT_RESTITUTION

        identity["restitution"] = DEFAULT_RESTITUTION  # the store says which e its cells were tossed with
    if client is None and scheduler not in (None, "local", "synchronous"):
        _check_address(scheduler)  # before the store is read or made
    said = []

    def note(text):
        said.append(text)
        if notes is not None:
            notes(text)

    variables = list(QUANTITIES[quantity].variables)
    exists = os.path.lexists(output)
    seeds = np.array([cell_seed(seed, c) for _, c in cells(axes)], dtype=np.uint64).reshape(shape)
    if exists:
        verified = open_store(output, identity, axes, variables, seeds)
        status = verified.status
        for text in verified.notes:
            note(text)
    else:
        status = np.zeros(shape, dtype=np.int8)
    todo = [(index, coords) for index, coords in cells(axes) if status[index] == STATUS_TODO]
    resumed = total - len(todo)
    start = time.perf_counter()
    messages, computed, n_workers = [], 0, 0
    inline = client is None and scheduler == "synchronous"
    own = client is None and bool(todo) and not inline
    cluster, interrupted = None, False
    if own:  # connect before the store is made: a scheduler that cannot be reached leaves no file behind
        told = []
        with _quiet_on_interrupt():
            client, cluster = _client(scheduler, workers, told)
        for text in told:
            note(text)
    try:
        if not exists:
            attrs = {"coinwall_version": __version__, "quantity": quantity, "seed": seed,
                     "options": repr(options), "wall": table.description, "params": repr(dict(table.params)),
                     "b0": float(table.b0), "kappa": "none" if table.kappa is None else float(table.kappa),
                     "command": command, "title": f"coinwall scan {quantity}"}
            create_store(output, axes, QUANTITIES[quantity].variables, seeds, attrs, identity)
        if todo:
            writer = CellWriter(output, variables, identity)
            if inline:
                n_workers = 1
                computed, messages = _run_inline(quantity, table, names, todo, seed, options, writer, status,
                                                 progress)
            else:
                n_workers = len(client.scheduler_info(n_workers=-1)["workers"])
                computed, messages = _run(client, quantity, table, names, todo, seed, options, retries, writer,
                                          progress, status)
    except KeyboardInterrupt:
        interrupted = True
        raise
    finally:
        if own:
            _close(client, cluster, interrupted)
    refused = int(np.count_nonzero(status == STATUS_REFUSED))
    return ScanResult(path=output, quantity=quantity, cells=total, computed=computed, resumed=resumed,
                      refused=refused, messages=tuple(messages), seconds=time.perf_counter() - start,
                      workers=n_workers, notes=tuple(said))


@contextlib.contextmanager
def _quiet_on_interrupt():
    """Ctrl-C while the cluster starts: its loggers are silenced before the interruption goes on."""
    try:
        yield
    except KeyboardInterrupt:
        _quiet_logs()
        raise


def _run_inline(quantity, table, names, todo, seed, options, writer, status, progress):
    """Every cell in this process, one after the other (``scheduler="synchronous"``)."""
    messages, done = [], 0
    for index, coords in todo:
        result = compute_cell(quantity, table, dict(zip(names, coords[:-1])), coords[-1], cell_seed(seed, coords),
                              options)
        writer.write(index, result)
        status[index] = result["status"]
        done += 1
        if result["status"] == STATUS_REFUSED and result["error"] not in messages and len(messages) < 5:
            messages.append(result["error"])
        if progress is not None:
            progress(done, len(todo))
    return done, messages


def _run(client, quantity, table, names, todo, seed, options, retries, writer, progress, status=None):
    """Submit the cells, write each result as it arrives; returns (cells written, refusal messages)."""
    from distributed import as_completed

    token = f"{os.getpid()}-{time.time_ns()}"
    futures, coords_of = {}, {}
    for index, coords in todo:
        values = dict(zip(names, coords[:-1]))
        key = f"coinwall-cell-{'-'.join(map(str, index))}-{token}"
        future = client.submit(compute_cell, quantity, table, values, coords[-1], cell_seed(seed, coords), options,
                               key=key, retries=retries, pure=False)
        futures[future] = index
        coords_of[future] = coords[:-1]
    messages, done = [], 0
    try:
        for future in as_completed(futures):
            try:
                result = future.result()  # a task that failed after its retries raises here: the scan stops
            except Exception as exc:  # noqa: BLE001 - any failure of a task, said in one line with how to go on
                from distributed import KilledWorker

                if not isinstance(exc, KilledWorker):
                    raise
                # workers died on this cell more often than the retries allow (memory? a signal?): not a bug
                # of ours, and nothing is lost — the cells done are in the store and the same command resumes
                cell = ", ".join(f"{name} = {value:g}" for name, value in zip(names, coords_of[future]))
                raise ScanError(f"the workers running the cell {cell} died {retries + 1} times (out of memory? "
                                f"killed?); the {done} cells finished are in the store: run the same command again "
                                "to compute the rest") from None
            writer.write(futures[future], result)
            if status is not None:
                status[futures[future]] = result["status"]
            done += 1
            if result["status"] == STATUS_REFUSED and result["error"] not in messages and len(messages) < 5:
                messages.append(result["error"])
            if progress is not None:
                progress(done, len(todo))
    finally:
        for future in futures:
            if not future.done():
                future.cancel()
    return done, messages
