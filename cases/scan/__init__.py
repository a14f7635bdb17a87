"""Parameter scans on dask.distributed: a quantity on a grid of wall parameters × H, one seeded task
per cell, written cell by cell into an xarray/Zarr store that a restarted scan resumes.

One module per step: :mod:`.grid` (axes, cells, per-cell seeds), :mod:`.table` (the table as data a worker
rebuilds), :mod:`.quantities` (the per-cell functions, calling the library), :mod:`.store` (the Zarr
store), :mod:`.driver` (the dask map) and :mod:`.figures` (with the closed-form ε*(H), ε**(H) of
:mod:`coinwall.forward.dynamics.analysis.islands`).  dask, xarray and
zarr are imported only when a scan runs (the ``scan`` extra).
"""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
