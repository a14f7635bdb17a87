"""Parameter scans on dask.distributed: a quantity on a grid of wall parameters × H, one seeded task
per cell, written cell by cell into an xarray/Zarr store that a restarted scan resumes.

One module per step: :mod:`.grid` (axes, cells, per-cell seeds), :mod:`.table` (the table as data a worker
rebuilds), :mod:`.quantities` (the per-cell functions, calling the library), :mod:`.store` (the Zarr
store), :mod:`.driver` (the dask map) and :mod:`.figures` (with the closed-form ε*(H), ε**(H) of
:mod:`coinwall.forward.dynamics.islands`).  dask, xarray and
zarr are imported only when a scan runs (the ``scan`` extra).
"""

from .driver import ScanResult, make_axes, scan
from .grid import Axis, cell_seed, parse_axis
from .quantities import QUANTITIES, Quantity, check_options, compute_cell
from .table import TableSpec

__all__ = [
    "QUANTITIES",
    "Axis",
    "Quantity",
    "ScanResult",
    "TableSpec",
    "cell_seed",
    "check_options",
    "compute_cell",
    "make_axes",
    "parse_axis",
    "scan",
]
