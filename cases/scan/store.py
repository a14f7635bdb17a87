"""The on-disk result of a scan: an xarray Dataset in a Zarr directory store, written one cell at a time,
that knows itself: every cell carries a checksum, and a resumed scan trusts only what verifies.

Layout (``xarray.open_zarr(path)`` reads it as it is):

* dimensions: the scanned wall parameters in the order given, then ``H``; coordinates with ``units``;
* one float64 array per variable of the quantity (:data:`.quantities.QUANTITIES`), NaN until computed,
  with ``units`` and ``long_name``;
* ``cell_seed`` (uint64): each cell's seed (:func:`.grid.cell_seed`), written when the store is made;
* ``cell_status`` (int8): 0 not computed, 1 computed, 2 refused by the library for that cell (its message
  is in the scan's report, not in the store);
* ``cell_checksum`` (uint64): the first 8 bytes of a SHA-256 over the scan's identity, the cell's index,
  its values (float64, in the order of the variables) and its status (:func:`cell_checksum`); 0 until the
  cell is written;
* attributes: ``coinwall_version``, ``quantity``, ``seed``, ``options``, ``wall``, ``params``, ``b0``,
  ``kappa``, ``command``, ``scan_identity`` (the JSON that a resumed scan must match) and
  ``scan_identity_sha256`` (its SHA-256, so that a damaged or edited identity is seen).

Why it survives a kill: every array is chunked one chunk per cell, Zarr's local store writes each chunk
file atomically (a temporary, then a rename), and a cell is written values first, then its checksum, then
its status.  The store itself is made in a temporary folder beside the target and renamed into place when complete
(:func:`coinwall.forward.formats.output.new_folder`).

Why it survives damage (a chunk truncated, deleted, rewritten or with a flipped byte; a disk error):
:func:`open_store` reads the store's own metadata (not the consolidated copy), refuses a store whose
identity, coordinates or array layout are not what they were made as (one line, exit status 2: its cells
cannot be told apart from another scan's), and verifies every stored cell: a cell whose chunks cannot be
read, whose status is not 0, 1 or 2, or whose checksum does not match its values and status is computed
again, with a note.  Seeds that do not match the coordinates are written again; the consolidated
metadata is rewritten from the arrays' own.  So a resumed store always ends equal to an undamaged run.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import warnings

import numpy as np

from coinwall.forward.errors import InvalidArgument

__all__ = ["STATUS_DONE", "STATUS_REFUSED", "STATUS_TODO", "CellWriter", "Verified", "cell_checksum", "create_store",
           "open_store"]

STATUS_TODO, STATUS_DONE, STATUS_REFUSED = 0, 1, 2
_PER_CELL = ("cell_status", "cell_checksum")


def _identity_text(identity: dict) -> str:
    return json.dumps(identity, sort_keys=True, allow_nan=False)


def identity_digest(identity: dict) -> bytes:
    """SHA-256 of the canonical identity text (bound into every cell's checksum)."""
    return hashlib.sha256(_identity_text(identity).encode()).digest()


def cell_checksum(digest: bytes, index, values, status: int) -> int:
    """The checksum of one cell: the first 8 bytes (little-endian, never 0) of a SHA-256 over ``digest`` (the
    scan's identity), the cell's ``index``, its ``values`` as float64 (NaN written as one bit pattern) and
    its ``status``."""
    numbers = np.array(values, dtype="<f8")
    numbers[np.isnan(numbers)] = np.nan
    h = hashlib.sha256(digest)
    h.update(np.array(index, dtype="<i8").tobytes())
    h.update(numbers.tobytes())
    h.update(int(status).to_bytes(2, "little", signed=True))
    return int.from_bytes(h.digest()[:8], "little") or 1


def create_store(path: str, axes, variables: dict, seeds: np.ndarray, attrs: dict, identity: dict) -> None:
    """Make the empty store at ``path`` (must not exist): coordinates, NaN arrays, seeds and attributes."""
    import dask.array as da
    import xarray as xr

    from coinwall.forward.formats.output import new_folder

    dims = tuple(a.name for a in axes)
    shape = tuple(len(a) for a in axes)
    coords = {a.name: (a.name, np.array(a.values), {"units": a.units, "grid": a.text}) for a in axes}
    # the per-cell arrays as lazy dask arrays, never computed (to_zarr(compute=False) writes their metadata
    # only): zarr would otherwise check 10⁴ all-NaN chunks one by one (20 s for a 100 × 100 grid)
    data = {name: (dims, da.full(shape, np.nan, chunks=shape), {"units": units, "long_name": text})
            for name, (units, text) in variables.items()}
    data["cell_seed"] = (dims, seeds.astype(np.uint64), {"long_name": "the cell's seed (SeedSequence of the scan's "
                                                                       "seed and the coordinates)"})
    data["cell_status"] = (dims, da.zeros(shape, dtype=np.int8, chunks=shape),
                           {"long_name": "0 not computed, 1 computed, 2 refused by the library for this cell"})
    data["cell_checksum"] = (dims, da.zeros(shape, dtype=np.uint64, chunks=shape),
                             {"long_name": "SHA-256 (first 8 bytes) of the scan's identity, the cell's index, values "
                                           "and status; 0 until the cell is written"})
    text = _identity_text(identity)
    dataset = xr.Dataset(data, coords=coords, attrs={**attrs, "scan_identity": text,
                                                     "scan_identity_sha256": hashlib.sha256(text.encode()).hexdigest()})
    # one chunk per cell for what is written cell by cell; the seeds are written once, here, in one chunk
    # (10⁴ chunk files of seeds took 24 s to create for a 100 × 100 grid)
    encoding = {name: {"chunks": (1,) * len(dims)} for name in data}
    encoding["cell_seed"] = {"chunks": shape}
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InvalidArgument(f"`output` {path!r}: the folder {folder!r} does not exist")
    with new_folder(path) as partial:  # the store appears complete or not at all
        # Zarr format 2 with consolidated metadata: read by every Zarr implementation (format 3 warns that
        # consolidation is not part of its specification yet)
        dataset.to_zarr(partial, mode="w-", encoding=encoding, consolidated=True, zarr_format=2, compute=False)


class Verified:
    """What :func:`open_store` found.

    Attributes
    ----------
    status : numpy.ndarray
        The status of every cell as trusted: a cell that failed its verification is 0 (to compute).
    damaged : int
        Cells that were stored but failed their verification.
    notes : list of str
        What was repaired or will be computed again, in words.
    """

    def __init__(self, status, damaged, notes):
        self.status, self.damaged, self.notes = status, damaged, notes


def _damaged(path, why):
    return InvalidArgument(f"`output` {path!r} is a damaged scan store ({why}); delete it or choose another name")


def _read(array, shape):
    """``(values, readable)``: every cell of ``array``; ``readable`` is False where its chunk cannot be read."""
    with contextlib.suppress(Exception):  # a damaged chunk: read the cells one by one to find it
        values = np.asarray(array[...])
        if values.shape == shape:
            return values, np.ones(shape, dtype=bool)
    values = np.zeros(shape, dtype=array.dtype)
    readable = np.zeros(shape, dtype=bool)
    for index in np.ndindex(*shape):
        with contextlib.suppress(Exception):  # this cell's chunk is damaged
            values[index] = array[index]
            readable[index] = True
    return values, readable


def _check_layout(path, group, axes, variables):
    """Refuse a store whose arrays are not the ones it was made with (names, dtypes, shapes, chunks)."""
    shape = tuple(len(a) for a in axes)
    expected = {name: (np.dtype("float64"), (1,) * len(shape)) for name in variables}
    expected.update({"cell_status": (np.dtype("int8"), (1,) * len(shape)),
                     "cell_checksum": (np.dtype("uint64"), (1,) * len(shape)), "cell_seed": (np.dtype("uint64"), None)})
    arrays = {}
    for name, (dtype, chunks) in expected.items():
        try:
            array = group[name]
        except Exception:  # noqa: BLE001 - missing or unreadable metadata
            raise _damaged(path, f"the array {name} is missing or unreadable") from None
        if array.dtype != dtype or tuple(array.shape) != shape or (chunks and tuple(array.chunks) != chunks):
            raise _damaged(path, f"the array {name} is {array.dtype} {tuple(array.shape)} in chunks "
                                 f"{tuple(array.chunks)}; it was made {dtype} {shape}")
        arrays[name] = array
    for axis in axes:
        try:
            stored = np.asarray(group[axis.name][...], dtype=float)
        except Exception:  # noqa: BLE001 - a damaged coordinate chunk: the cells can no longer be placed
            raise _damaged(path, f"its coordinate {axis.name} cannot be read") from None
        want = np.array(axis.values, dtype=float)
        if stored.shape != want.shape:
            raise _damaged(path, f"its coordinate {axis.name} has {stored.size} values, {want.size} expected")
        differ = np.flatnonzero(~((stored == want) | (np.isnan(stored) & np.isnan(want))))
        if differ.size:
            k = int(differ[0])
            raise InvalidArgument(f"`output` {path!r}: its coordinate {axis.name} was changed on disk ({stored[k]:g} "
                                  f"at position {k + 1}, {want[k]:g} when it was made); its cells no longer match "
                                  "their coordinates: delete it or choose another name")
    return arrays


def open_store(path: str, identity: dict, axes, variables, seeds=None) -> Verified:
    """Open an existing store made by the same scan, verify it and say which cells to (re)compute.

    Parameters
    ----------
    path : str
    identity : dict
        The scan's identity (quantity, options, wall, axes, seed, version): the store must record the same.
    axes : list of Axis
    variables : iterable of str
        The quantity's variables, in the store's order.
    seeds : numpy.ndarray, optional
        The cells' seeds; a store whose ``cell_seed`` differs has it written again.

    Raises
    ------
    InvalidArgument
        ``path`` is not a scan store; or it was made by another scan (the message names the first
        difference); or its identity, coordinates or arrays were changed or cannot be read.
    """
    import zarr

    variables = list(variables)
    shape = tuple(len(a) for a in axes)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zarr's remarks about formats are not the user's business
        try:
            group = zarr.open_group(path, mode="r", use_consolidated=False)
            attrs = dict(group.attrs)
        except Exception:  # noqa: BLE001 - any unreadable or foreign folder is the same answer for the user
            if os.path.isfile(os.path.join(path, ".zgroup")):
                raise _damaged(path, "its group metadata cannot be read") from None
            raise InvalidArgument(f"`output` {path!r} exists and is not a coinwall scan store; choose another name") \
                from None
        if "scan_identity" not in attrs:
            raise InvalidArgument(f"`output` {path!r} exists and is not a coinwall scan store; choose another name")
        text = attrs["scan_identity"]
        try:
            stored = json.loads(text)
        except (TypeError, ValueError):
            stored = None
        if not isinstance(stored, dict):
            raise _damaged(path, "its record of the scan, scan_identity, is not readable")
        if attrs.get("scan_identity_sha256") != hashlib.sha256(str(text).encode()).hexdigest():
            raise _damaged(path, "its record of the scan, scan_identity, does not match its checksum")
        if stored != json.loads(_identity_text(identity)):
            diffs = [k for k in sorted(set(stored) | set(identity)) if stored.get(k) != identity.get(k)]
            key = diffs[0] if diffs else "?"
            raise InvalidArgument(f"`output` {path!r} was made by a different scan ({key}: {stored.get(key)!r} "
                                  f"there, {identity.get(key)!r} now); resume with the same command or choose another "
                                  "name")
        arrays = _check_layout(path, group, axes, variables)
        status, ok = _read(arrays["cell_status"], shape)
        checksum, ok_sum = _read(arrays["cell_checksum"], shape)
        ok &= ok_sum
        values = np.empty(shape + (len(variables),))
        for k, name in enumerate(variables):
            values[..., k], ok_values = _read(arrays[name], shape)
            ok &= ok_values
        digest = identity_digest(identity)
        status = status.astype(np.int64)
        trusted = np.zeros(shape, dtype=bool)
        for index in np.ndindex(*shape):
            s = int(status[index])
            if ok[index] and s in (STATUS_DONE, STATUS_REFUSED):
                trusted[index] = int(checksum[index]) == cell_checksum(digest, index, values[index], s)
        written = (status != STATUS_TODO) | (checksum != 0) | ~ok
        damaged = int(np.count_nonzero(written & ~trusted))
        notes = []
        if damaged:
            notes.append(f"{damaged} cell(s) of the store failed their checksum (damaged or cut off while being "
                         "written); computing them again")
        repair_seeds = False
        if seeds is not None:
            stored_seeds, ok_seeds = _read(arrays["cell_seed"], shape)
            repair_seeds = not (ok_seeds.all() and np.array_equal(stored_seeds, seeds))
    _repair(path, seeds if repair_seeds else None, notes)
    return Verified(np.where(trusted, status, STATUS_TODO).astype(np.int8), damaged, notes)


def _repair(path, seeds, notes) -> None:
    """Write the seeds again (when given) and the consolidated metadata from the arrays' own (a damaged or
    edited ``.zmetadata`` would otherwise mislead xarray; the arrays' own metadata were verified)."""
    import zarr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            group = zarr.open_group(path, mode="r+", use_consolidated=False)
            if seeds is not None:
                group["cell_seed"][...] = seeds
                notes.append("the store's cell_seed did not match the cells' coordinates; written again")
            zarr.consolidate_metadata(group.store, zarr_format=2)
        except OSError as exc:
            if seeds is None:  # only the copy of the metadata: a read-only complete store is still fine
                return
            raise InvalidArgument(f"`output` {path!r} cannot be written ({exc.strerror or exc})") from None


class CellWriter:
    """Writes finished cells into a store (the driver's only writer; the workers only compute).

    Parameters
    ----------
    path : str
    variables : iterable of str
        The quantity's variable names.
    identity : dict
        The scan's identity (bound into every cell's checksum).
    """

    def __init__(self, path: str, variables, identity: dict):
        import zarr

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.group = zarr.open_group(path, mode="r+", use_consolidated=False)
        self.arrays = {name: self.group[name] for name in variables}
        self.status = self.group["cell_status"]
        self.checksum = self.group["cell_checksum"]
        self.digest = identity_digest(identity)

    def write(self, index: tuple, result: dict) -> None:
        """Write one cell: its values (NaN where it has none), its checksum, then its status (so a kill in
        between leaves it to be computed again)."""
        status = int(result["status"])
        values = [float(result[name]) if status == STATUS_DONE and result.get(name) is not None else np.nan
                  for name in self.arrays]
        for value, array in zip(values, self.arrays.values()):
            array[index] = value
        self.checksum[index] = np.uint64(cell_checksum(self.digest, index, values, status))
        self.status[index] = status
