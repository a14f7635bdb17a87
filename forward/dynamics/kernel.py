"""The compiled kernel: its source joined to a wall's generated code, compiled once per wall, and run.

The kernel itself is the real module :mod:`._kernel` (read it for the algorithm).  numba cannot call
casadi, so each wall is written out as plain Python (:mod:`.wallcode`); the text of ``_kernel.py``
below its marker line (:data:`KERNEL_SOURCE`) is appended to that code and the whole is loaded as a
module from a file named after its hash (:func:`.wallcode.load_module`), which lets numba's
``cache=True`` reuse the machine code in the next process.  Walls that differ only in parameter
values share one source, hence one compiled kernel.
"""

from __future__ import annotations

import importlib.resources
import weakref

import numpy as np

from ..wall import Wall
from .cellbounds import cell_bounds, cell_table

__all__ = ["KERNEL_SOURCE", "HEADER", "NOTES", "CompiledKernel", "compiled", "run", "run_many"]

_MARKER = "# ---- kernel: the text from the line after this one to the end of the file is joined to the wall code ----\n"


def _kernel_text() -> str:
    """The part of ``_kernel.py`` that is compiled: everything after the marker line."""
    text = importlib.resources.files(__package__).joinpath("_kernel.py").read_text(encoding="utf-8")
    head, marker, kernel = text.partition(_MARKER)
    if not marker:  # a guard for whoever edits _kernel.py: without the marker the join is undefined
        raise RuntimeError("_kernel.py has lost its marker line; kernel.py cannot find the kernel's text")
    return kernel


KERNEL_SOURCE = _kernel_text()
# the imports and options the kernel's text expects (_kernel.py has the same lines above its marker)
HEADER = ("import math\nimport numpy as np\nfrom numba import carray, njit, prange, types\n"
          "from numba.extending import intrinsic\n\n"
          "OPTIONS = dict(cache=True, error_model='numpy')\n\n")
# why an orbit stopped early, by the kernel's status code (0: all collisions computed)
NOTES = {1: "free flight: the particle moves parallel to the walls in an open channel and never collides again",
         2: "the kernel's root search did not converge (a near-tangent graze?)",
         3: "the wall evaluated to nan or infinity where the particle met it (a pole or a domain error of the "
            "expression between the angles it was checked on)"}


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
    cells : ndarray (m, 16)
        :func:`.cellbounds.cell_table` of the bounds.
    """

    def __init__(self, wall: Wall):
        from .wallcode import load_module, wall_source

        source, constants = wall_source(wall, "@njit(**OPTIONS)\n")
        self.module = load_module(HEADER + source + KERNEL_SOURCE, "coinwall_billiard")
        self.constants = np.ascontiguousarray(constants, dtype=float)
        self.bounds = cell_bounds(wall)
        self.cells = cell_table(self.bounds)

    def args(self, table):
        """The run-time arguments after the state: H, b0, constants, cell table, lookup, band, tol."""
        bd = self.bounds
        return (float(table.H), float(table.b0), self.constants, self.cells, bd["lookup"], bd["wmin"], bd["wmax"],
                float(table.tol))


_KERNELS: "weakref.WeakKeyDictionary[Wall, CompiledKernel]" = weakref.WeakKeyDictionary()


def compiled(table) -> CompiledKernel:
    """The :class:`CompiledKernel` of ``table``'s wall (made on first use, then kept while the wall lives)."""
    # bounds depend on the wall only (H and b0 are run-time arguments): one entry per wall object
    comp = _KERNELS.get(table.wall)
    if comp is None:
        comp = _KERNELS[table.wall] = CompiledKernel(table.wall)
    return comp


def run(comp: CompiledKernel, table, state, leaving: int, collisions: int):
    """One orbit of unit speed from ``state``; returns the six columns (time, θ, η, v_θ, v_η, side) and a note."""
    out = [np.empty(collisions) for _ in range(5)] + [np.empty(collisions, dtype=np.int8)]
    done, status = comp.module._run(np.ascontiguousarray(state, dtype=float), int(leaving), collisions,
                                    *comp.args(table), *out)
    return [o[:done] for o in out], NOTES.get(int(status), "")


def run_many(comp: CompiledKernel, table, states, leaving, collisions: int, workers=None):
    """Many orbits of unit speed in parallel (numba threads); returns per orbit its columns and note.

    ``workers`` threads (a positive int, at most numba's thread count; default: numba's default, all
    cores); each orbit runs the same sequential code, so the result does not depend on it.
    """
    import numba

    if workers is not None:
        workers = min(int(workers), numba.config.NUMBA_NUM_THREADS)
    m = states.shape[0]
    out = [np.empty((m, collisions)) for _ in range(5)] + [np.empty((m, collisions), dtype=np.int8)]
    done = np.zeros(m, dtype=np.int64)
    status = np.zeros(m, dtype=np.int64)
    previous = numba.get_num_threads()
    try:
        if workers is not None:
            numba.set_num_threads(workers)
        comp.module._run_many(states, leaving, collisions, *comp.args(table), *out, done, status)
    finally:
        numba.set_num_threads(previous)
    return [([o[k, :done[k]] for o in out], NOTES.get(int(status[k]), "")) for k in range(m)]
