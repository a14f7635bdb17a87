"""The compiled kernel: its source joined to a wall's generated code, compiled once per wall, and run.

The kernel itself is the real module :mod:`._kernel` (read it for the algorithm).  numba cannot call
casadi, so each wall is written out as plain Python (:mod:`.wallcode`); the text of ``_search.py``
below its marker line (:data:`SEARCH_SOURCE`, the certified search the field kernel shares) and the text
of ``_kernel.py`` below its marker line (:data:`KERNEL_SOURCE`) are appended to that code and the whole is
loaded as a module named after its hash (:func:`.wallcode.load_module`), whose functions keep their machine
code in numba's cache in coinwall's private folder (or are compiled in memory when there is none), so that
the next process reuses it.  Walls that differ only in parameter values share one source, hence one compiled
kernel.
"""

from __future__ import annotations

import importlib.resources
import weakref

import numpy as np

from ...wall import Wall
from .cellbounds import cell_bounds, cell_table

__all__ = ["HEADER", "KERNEL_SOURCE", "NOTES", "SEARCH_SOURCE", "CompiledKernel", "compiled", "kernel_module",
           "run", "run_many", "source_after_marker"]

_MARKER = "# ---- kernel: the text from the line after this one to the end of the file is joined to the wall code ----\n"  # noqa: E501 -- matched byte for byte in _kernel.py
_SEARCH_MARKER = "# ---- search: the text from the line after this one to the end of the file is joined to the wall code ----\n"  # noqa: E501 -- matched byte for byte in _search.py


def source_after_marker(package: str, filename: str, marker: str) -> str:
    """The part of the kernel source file ``filename`` in ``package`` that is compiled: all after ``marker``.

    Parameters
    ----------
    package : str
        The package that holds the file (a module's ``__package__``).
    filename : str
        ``"_kernel.py"``, ``"_search.py"`` or ``"_field_kernel.py"``.
    marker : str
        The marker line, matched byte for byte.

    Returns
    -------
    str
        The text after the marker line.
    """
    text = importlib.resources.files(package).joinpath(filename).read_text(encoding="utf-8")
    _head, found, kernel = text.partition(marker)
    if not found:  # a guard for whoever edits the file: without the marker the join is undefined
        raise RuntimeError(f"{filename} has lost its marker line; the kernel's text cannot be found")
    return kernel


KERNEL_SOURCE = source_after_marker(__package__, "_kernel.py", _MARKER)
SEARCH_SOURCE = source_after_marker(__package__, "_search.py", _SEARCH_MARKER)
# the imports and options the kernel's text expects (_kernel.py has the same lines above its marker);
# CACHE is set False by wallcode.load_module before the text runs: it gives each function coinwall's cache itself
HEADER = ("import math\nimport numpy as np\nfrom numba import carray, njit, prange, types\n"
          "from numba.extending import intrinsic\n\n"
          "OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}\n\n")


def kernel_module(wall: Wall, kernel_source: str, prefix: str):
    """Load (or compile) the module of one kernel for ``wall``: header, wall code, the search, the kernel.

    Parameters
    ----------
    wall : Wall
        The wall whose generated code (:func:`.wallcode.wall_source`) is placed first.
    kernel_source : str
        The kernel's own text (:data:`KERNEL_SOURCE` or the field kernel's).
    prefix : str
        The module name's prefix (:func:`.wallcode.load_module`).

    Returns
    -------
    module, ndarray
        The loaded module and the wall's constants.
    """
    from .wallcode import load_module, wall_source

    source, constants = wall_source(wall, "@njit(**OPTIONS)\n")
    return load_module(HEADER + source + SEARCH_SOURCE + kernel_source, prefix), constants


# why an orbit stopped early, by the kernel's status code (0: all collisions computed)
NOTES = {1: "free flight: the particle moves parallel to the walls in an open channel and never collides again",
         2: "the kernel's root search did not converge (a near-tangent graze?)",
         3: "the wall evaluated to nan or infinity where the particle met it (a pole or a domain error of the "
            "expression between the angles it was checked on)",
         4: "a flight carried θ beyond 1.8e13 rad, where float64 no longer resolves the contact angle (a ray "
            "almost parallel to the walls); the orbit stops there",
         5: "the search for the next collision walked more than 2^27 cells (about 10^6 turns of θ) without "
            "deciding (a ray almost parallel to the walls); the orbit stops there"}


class CompiledKernel:
    """The kernel for one wall: the generated module plus the wall's constants and cell bounds.

    Attributes
    ----------
    module : module
        The loaded module: the wall's ``wall_b1``/``wall_b2`` and the kernel's ``_run``/``_run_many``.
    constants : ndarray
        The wall's constants (the array ``c`` of the generated code).
    bounds : dict
        :func:`.cellbounds.cell_bounds` of the wall.
    cells : ndarray (m, 21)
        :func:`.cellbounds.cell_table` of the bounds.
    """

    def __init__(self, wall: Wall):
        self.module, constants = kernel_module(wall, KERNEL_SOURCE, "coinwall_billiard")
        self.constants = np.ascontiguousarray(constants, dtype=float)
        self.bounds = cell_bounds(wall)
        self.cells = cell_table(self.bounds)
        if not np.all(np.isfinite(self.constants)) or np.any(np.isinf(self.cells)):
            # (NaN in the table marks "no kink at this edge"; cellbounds refuses NaN bounds of a wall)
            from ...errors import InvalidWall

            raise InvalidWall(f"wall {wall.description!r}: its constants or cell bounds are not finite numbers")

    def call(self, name, *args):
        """Call the kernel function ``name`` (compiled, or loaded from the cache, on its first call)."""
        return getattr(self.module, name)(*args)

    def args(self, table):
        """The run-time arguments after the state: H, b0, constants, cell table, lookup, band, tol."""
        bd = self.bounds
        return (float(table.H), float(table.b0), self.constants, self.cells, bd["lookup"], bd["wmin"], bd["wmax"],
                float(table.tol))


_KERNELS: weakref.WeakKeyDictionary[Wall, CompiledKernel] = weakref.WeakKeyDictionary()


def compiled(table) -> CompiledKernel:
    """The :class:`CompiledKernel` of ``table``'s wall (made on first use, then kept while the wall lives)."""
    # bounds depend on the wall only (H and b0 are run-time arguments): one entry per wall object
    comp = _KERNELS.get(table.wall)
    if comp is None:
        comp = _KERNELS[table.wall] = CompiledKernel(table.wall)
    return comp


def run(comp: CompiledKernel, table, state, leaving: int, collisions: int, turns: int = 0):
    """One orbit of unit speed from ``state`` (θ in [0, 2π), ``turns`` whole turns on top); returns the six
    columns (time, θ, η, v_θ, v_η, side), a note and ``(θ mod 2π, turns)`` after the last collision."""
    out = [np.empty(collisions) for _ in range(5)] + [np.empty(collisions, dtype=np.int8)]
    last = np.empty(2)
    done, status = comp.call("_run", np.ascontiguousarray(state, dtype=float), int(turns), int(leaving), collisions,
                             *comp.args(table), *out, last)
    return [o[:done] for o in out], NOTES.get(int(status), ""), (float(last[0]), int(last[1]))


def run_many(comp: CompiledKernel, table, states, leaving, collisions: int, workers=None, turns=None, device="cpu"):
    """Many orbits of unit speed in parallel; returns per orbit its columns, note and end angle.

    ``device="cpu"``: numba threads, ``workers`` of them (a positive int, at most numba's thread count;
    default: numba's default, all cores).  ``device="gpu"``: one orbit per GPU thread (:func:`.gpu.run_into`,
    the same kernel text compiled for CUDA; ``workers`` does not apply).  Each orbit runs the same sequential
    code, so the result does not depend on ``workers``.
    """
    m = states.shape[0]
    out = [np.empty((m, collisions)) for _ in range(5)] + [np.empty((m, collisions), dtype=np.int8)]
    done = np.zeros(m, dtype=np.int64)
    status = np.zeros(m, dtype=np.int64)
    last = np.empty((m, 2))
    turns = np.zeros(m, dtype=np.int64) if turns is None else np.ascontiguousarray(turns, dtype=np.int64)
    if device == "gpu":
        from .gpu import run_into

        run_into(table, states, turns, np.ascontiguousarray(leaving, dtype=np.int64), collisions, out, done,
                 status, last)
    else:
        _run_threads(comp, table, states, turns, leaving, collisions, workers, out, done, status, last)
    return [([o[k, :done[k]] for o in out], NOTES.get(int(status[k]), ""), (float(last[k, 0]), int(last[k, 1])))
            for k in range(m)]


def _run_threads(comp, table, states, turns, leaving, collisions, workers, out, done, status, last):
    """``_run_many`` on ``workers`` numba threads (None: numba's default), into ``out``, ``done``, ``status`` and
    ``last``."""
    import numba

    if workers is not None:
        workers = min(int(workers), numba.config.NUMBA_NUM_THREADS)
    previous = numba.get_num_threads()
    try:
        if workers is not None:
            numba.set_num_threads(workers)
        comp.call("_run_many", states, turns, leaving, collisions, *comp.args(table), *out, done, status, last)
    finally:
        numba.set_num_threads(previous)
