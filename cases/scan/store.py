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
  ``kappa``, ``command``, ``scan_identity`` (the JSON that a resumed scan must match: a wall that is not an
  expression is in it by the SHA-256 of its data, :func:`.table.wall_digest`), ``scan_identity_sha256`` (its
  SHA-256, so that a damaged or edited identity is seen) and ``scan_metadata_sha256``: the SHA-256 of the
  metadata of every member as made (``{".": of the attributes above, NAME: of the array's .zarray and .zattrs:
  dtype, shape, chunks, fill value, dimensions, units}``), so that an attribute rewritten (``seed``, ``wall``,
  ``command``), dimension names swapped or an array's metadata edited are seen, not resumed and shown to
  readers.

Why it survives a kill: every array is chunked one chunk per cell, Zarr's local store writes each chunk
file atomically (a temporary, then a rename), and a cell is written values first, then its checksum, then
its status.  The store itself is made in a temporary folder beside the target and renamed into place when complete
(:func:`coinwall.forward.formats.output.new_folder`).

Why it survives damage (a chunk truncated, deleted, rewritten or with a flipped byte; a disk error):
:func:`open_store` first looks at every member without opening it (:func:`_check_members`): each file it will
read must be a regular file inside the store (no symbolic link, FIFO or device) of at most
:func:`_member_limit` bytes; a chunk of a per-cell array that is not is removed (its cell is computed again),
anything else makes the store damaged, and a folder holding an array the scan did not make (which would make
the store unreadable for xarray: "conflicting sizes") too.  It then reads the store's own metadata (not the
consolidated copy), refuses a store whose identity, metadata, coordinates or array layout are not what they
were made as (one line, exit status 2: its cells cannot be told apart from another scan's), and verifies
every stored cell: a cell whose chunks cannot be
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
#: the store's own attributes (a user may add others: they are not the store's record and are not checked)
OWN_ATTRIBUTES = ("coinwall_version", "quantity", "seed", "options", "wall", "params", "b0", "kappa", "command",
                  "title", "scan_identity", "scan_identity_sha256")
_METADATA_DIGEST = "scan_metadata_sha256"
_METADATA_FILES = (".zarray", ".zattrs", ".zgroup")


def _member_limit(cells: int) -> int:
    """The largest file a store of ``cells`` cells holds, in bytes: the one chunk of every cell's seed (8 bytes a
    cell, compressed or not) with room to spare, and 64 KiB for metadata and one-cell chunks (a few dozen
    bytes each)."""
    return 16 * int(cells) + 2 ** 16


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


def _json_member(path: str, limit: int):
    """The JSON document of a metadata file, or None where it is missing; an error where it is not a regular file
    of at most ``limit`` bytes or not JSON (the caller says "damaged")."""
    import stat

    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return None
    if not stat.S_ISREG(info.st_mode) or info.st_size > limit:
        raise ValueError(f"{os.path.basename(path)} is not a small regular file")
    with open(path, "rb") as fh:
        return json.loads(fh.read(limit + 1).decode("utf-8"))


def _metadata_digests(path: str, members, limit: int = 2 ** 16) -> dict:
    """``{".": SHA-256 of the store's own attributes, NAME: of the member's .zarray and .zattrs}`` for ``members``
    (the arrays and coordinates), read from the files themselves (canonical JSON: key order and spacing do not
    count)."""
    def digest(doc):
        return hashlib.sha256(json.dumps(doc, sort_keys=True, allow_nan=True).encode()).hexdigest()

    attrs = _json_member(os.path.join(path, ".zattrs"), limit) or {}
    own = {key: attrs.get(key) for key in OWN_ATTRIBUTES}
    digests = {".": digest(own)}
    for name in members:
        digests[name] = digest({f: _json_member(os.path.join(path, name, f), limit) for f in (".zarray", ".zattrs")})
    return digests


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
        _seal(partial, list(data) + list(dims))


def _seal(path: str, members) -> None:
    """Record the digests of the metadata as made (``scan_metadata_sha256``) and consolidate them again."""
    import zarr

    digests = _metadata_digests(path, members)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        group = zarr.open_group(path, mode="r+", use_consolidated=False)
        group.attrs[_METADATA_DIGEST] = digests
        zarr.consolidate_metadata(group.store, zarr_format=2)


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


def _check_members(path: str, members, per_cell, cells: int) -> int:
    """Look at every file of the store without opening it: the store's own files must be regular files (no link,
    FIFO, device or folder in their place) of at most :func:`_member_limit` bytes.  A chunk of a ``per_cell`` array
    that is not is removed (the link, never what it points to) and its cell computed again; anything else, and a
    folder holding an array or group the store was not made with, is a damaged store.  Returns the chunks
    removed."""
    import stat

    from coinwall.forward.formats.inputfile import file_kind

    limit = _member_limit(cells)
    removed = 0

    def look(full, name):
        info = os.lstat(full)
        if stat.S_ISLNK(info.st_mode):
            return "a symbolic link"
        if not stat.S_ISREG(info.st_mode):
            return file_kind(info.st_mode)
        if info.st_size > limit:
            return f"a file of {info.st_size} bytes (a store of {cells} cells holds none over {limit})"
        return None

    if os.path.islink(path):
        raise _damaged(path, "it is a symbolic link, not the folder coinwall made")
    for name in sorted(os.listdir(path)):
        full = os.path.join(path, name)
        if os.path.isdir(full) and not os.path.islink(full):
            if name not in members:
                if any(os.path.lexists(os.path.join(full, f)) for f in _METADATA_FILES):
                    raise _damaged(path, f"it holds an array {name!r} it was not made with")
                continue  # a folder of the user's own: zarr and xarray never read it
            for entry in sorted(os.listdir(full)):
                why = look(os.path.join(full, entry), entry)
                if why is None:
                    continue
                if name in per_cell and entry not in _METADATA_FILES:
                    os.unlink(os.path.join(full, entry))
                    removed += 1
                    continue
                raise _damaged(path, f"{name}/{entry} is {why}")
        elif name in _METADATA_FILES or name in members:
            why = look(full, name)
            if why is not None:
                raise _damaged(path, f"{name} is {why}")
        elif name == ".zmetadata" and look(full, name) is not None:
            os.unlink(full)  # the consolidated copy: written again from the arrays' own (_repair)
    return removed


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
        dims = array.attrs.get("_ARRAY_DIMENSIONS")
        if dims != [a.name for a in axes]:  # swapped names: a square grid would be read transposed
            raise _damaged(path, f"the array {name} has the dimensions {dims}; it was made with "
                                 f"{[a.name for a in axes]}")
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
    per_cell = variables + ["cell_status", "cell_checksum", "cell_seed"]
    members = per_cell + [a.name for a in axes]
    cells = int(np.prod(shape))
    if os.path.isdir(path) and os.path.lexists(os.path.join(path, ".zgroup")):
        removed = _check_members(path, members, per_cell, cells)
    else:
        removed = 0
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
            if key == "wall_sha256":
                raise InvalidArgument(f"`output` {path!r} was made from another wall: the data of the wall "
                                      f"{identity.get('wall')!r} (a file's content) are not those its cells were "
                                      "computed for; delete it or choose another name")
            raise InvalidArgument(f"`output` {path!r} was made by a different scan ({key}: {stored.get(key)!r} "
                                  f"there, {identity.get(key)!r} now); resume with the same command or choose another "
                                  "name")
        arrays = _check_layout(path, group, axes, variables)
        recorded = attrs.get(_METADATA_DIGEST)
        if not isinstance(recorded, dict):
            raise _damaged(path, f"it has no record of its metadata ({_METADATA_DIGEST}): it was made by an earlier "
                                 "coinwall or edited")
        try:
            now = _metadata_digests(path, members, _member_limit(cells))
        except (OSError, ValueError):
            raise _damaged(path, "its metadata cannot be read") from None
        changed = [name for name in now if recorded.get(name) != now[name]]
        if changed or set(recorded) != set(now):
            what = "its attributes (.zattrs)" if "." in changed else \
                f"the metadata of {(changed or sorted(set(recorded) ^ set(now)))[0]}"
            raise InvalidArgument(f"`output` {path!r}: {what} were changed on disk since it was made; what it says of "
                                  "its cells can no longer be trusted: delete it or choose another name")
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
        if removed:
            notes.append(f"{removed} chunk(s) of the store were not regular files of a chunk's size (a link, a FIFO, "
                         "a device, a huge file): removed, their cells computed again")
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
