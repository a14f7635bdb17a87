"""The on-disk result of a scan: an xarray Dataset in a Zarr directory store, written one cell at a time.

Layout (``xarray.open_zarr(path)`` reads it as it is):

* dimensions: the scanned wall parameters in the order given, then ``H``; coordinates with ``units``;
* one float64 array per variable of the quantity (:data:`.quantities.QUANTITIES`), NaN until computed,
  with ``units`` and ``long_name``;
* ``cell_seed`` (uint64): each cell's seed (:func:`.grid.cell_seed`), written when the store is made;
* ``cell_status`` (int8): 0 not computed, 1 computed, 2 refused by the library for that cell (its message
  is in the scan's report, not in the store);
* attributes: ``coinwall_version``, ``quantity``, ``seed``, ``options``, ``wall``, ``params``, ``b0``,
  ``kappa``, ``command`` and ``scan_identity`` (the JSON that a resumed scan must match).

Why it survives a kill: every array is chunked one chunk per cell, Zarr's local store writes each chunk
file atomically (a temporary, then a rename), and a cell's ``cell_status`` is written *after* its values.
A cell is either complete or still 0; a restarted scan reads ``cell_status`` and computes only the zeros.
The store itself is made in a temporary folder beside the target and renamed into place when complete.
One chunk per cell costs one small file per variable and cell (a 100 × 100 scan: 10⁴ files per variable),
which any filesystem holds; it keeps each write independent of its neighbours.
"""

from __future__ import annotations

import json
import os
import shutil
import uuid

import numpy as np

from ..errors import InvalidArgument

__all__ = ["STATUS_DONE", "STATUS_REFUSED", "STATUS_TODO", "CellWriter", "create_store", "open_store"]

STATUS_TODO, STATUS_DONE, STATUS_REFUSED = 0, 1, 2


def _identity_text(identity: dict) -> str:
    return json.dumps(identity, sort_keys=True, allow_nan=False)


def create_store(path: str, axes, variables: dict, seeds: np.ndarray, attrs: dict, identity: dict) -> None:
    """Make the empty store at ``path`` (must not exist): coordinates, NaN arrays, seeds and attributes."""
    import xarray as xr

    dims = tuple(a.name for a in axes)
    shape = tuple(len(a) for a in axes)
    coords = {a.name: (a.name, np.array(a.values), {"units": a.units, "grid": a.text}) for a in axes}
    import dask.array as da

    # the per-cell arrays as lazy dask arrays, never computed (to_zarr(compute=False) writes their metadata
    # only): zarr would otherwise check 10⁴ all-NaN chunks one by one (20 s for a 100 × 100 grid)
    data = {name: (dims, da.full(shape, np.nan, chunks=shape), {"units": units, "long_name": text})
            for name, (units, text) in variables.items()}
    data["cell_seed"] = (dims, seeds.astype(np.uint64), {"long_name": "the cell's seed (SeedSequence of the scan's "
                                                                       "seed and the coordinates)"})
    data["cell_status"] = (dims, da.zeros(shape, dtype=np.int8, chunks=shape),
                           {"long_name": "0 not computed, 1 computed, 2 refused by the library for this cell"})
    dataset = xr.Dataset(data, coords=coords, attrs={**attrs, "scan_identity": _identity_text(identity)})
    # one chunk per cell for what is written cell by cell; the seeds are written once, here, in one chunk
    # (10⁴ chunk files of seeds took 24 s to create for a 100 × 100 grid)
    encoding = {name: {"chunks": (1,) * len(dims)} for name in data}
    encoding["cell_seed"] = {"chunks": shape}
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidArgument(f"`output` {path!r}: the folder {folder!r} does not exist")
    partial = os.path.join(folder, f".{os.path.basename(path)}.{uuid.uuid4().hex}.partial")
    try:
        # Zarr format 2 with consolidated metadata: read by every Zarr implementation (format 3 warns that
        # consolidation is not part of its specification yet)
        dataset.to_zarr(partial, mode="w-", encoding=encoding, consolidated=True, zarr_format=2, compute=False)
        os.rename(partial, path)  # the store appears complete or not at all
    finally:
        if os.path.exists(partial):
            shutil.rmtree(partial, ignore_errors=True)


def open_store(path: str, identity: dict):
    """The ``cell_status`` array of an existing store made by the same scan; refuse any other store.

    Raises
    ------
    InvalidArgument
        ``path`` is not a scan store, or it was made with other options (the message names the first
        difference), or by another coinwall version (its numbers might differ).
    """
    import zarr

    try:
        group = zarr.open_group(path, mode="r")
        text = group.attrs["scan_identity"]
    except Exception:  # noqa: BLE001 - any unreadable or foreign folder is the same answer for the user
        raise InvalidArgument(f"`output` {path!r} exists and is not a coinwall scan store; choose another name") \
            from None
    stored = json.loads(text)
    if stored != json.loads(_identity_text(identity)):
        diffs = [k for k in sorted(set(stored) | set(identity)) if stored.get(k) != identity.get(k)]
        key = diffs[0] if diffs else "?"
        raise InvalidArgument(f"`output` {path!r} was made by a different scan ({key}: {stored.get(key)!r} there, "
                              f"{identity.get(key)!r} now); resume with the same command or choose another name")
    return np.asarray(group["cell_status"][...])


class CellWriter:
    """Writes finished cells into a store (the driver's only writer; the workers only compute).

    Parameters
    ----------
    path : str
    variables : iterable of str
        The quantity's variable names.
    """

    def __init__(self, path: str, variables):
        import zarr

        self.group = zarr.open_group(path, mode="r+")
        self.arrays = {name: self.group[name] for name in variables}
        self.status = self.group["cell_status"]

    def write(self, index: tuple, result: dict) -> None:
        """Write one cell: its values, then its status (so a kill in between leaves it to be computed again)."""
        status = int(result["status"])
        if status == STATUS_DONE:
            for name, array in self.arrays.items():
                array[index] = result.get(name, np.nan)
        self.status[index] = status
