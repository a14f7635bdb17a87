"""A scan store trusts nothing it says of itself that it cannot verify (cases/scan/store.py).

Each example of a store changed on disk is either refused in one line (exit status 2, the folder unchanged) or
resumed to the arrays an undamaged run gives: the wall file's content changed under the same name, dimension
names swapped on a square grid, attributes rewritten, an extra array with conflicting sizes, a chunk that is a
FIFO or a symbolic link to /dev/zero (or to a file of the user's, which must survive).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("zarr")
pytest.importorskip("xarray")

from coinwall.cases.cli.main import main  # noqa: E402

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
#: a square grid: arrays read with swapped dimensions would be the transposed values, of the right shape
GRID = {"eps": "2,8", "H": "2.5,3"}
OPTIONS = {"orbits": 4, "collisions": 40}
NAMES = ["chaotic_fraction", "chaotic_fraction_stderr", "regular_orbits", "orbits_used", "cell_seed", "cell_status",
         "cell_checksum"]
ARGS = ["scan", "chaotic-fraction", ELLIPSE, "--param", "eps=2,8", "--H", "2.5,3", "--orbits", "4", "--collisions",
        "40", "--seed", "3", "--scheduler", "synchronous", "-o", "s.zarr"]


def _scan(path, **kwargs):
    from coinwall.cases.scan import TableSpec, scan

    return scan("chaotic-fraction", TableSpec(ELLIPSE), GRID, output=str(path), options=OPTIONS, seed=3,
                scheduler="synchronous", command="coinwall scan ...", **kwargs)


def _arrays(path):
    import xarray as xr

    with xr.open_zarr(str(path)) as ds:
        return {name: ds[name].values.copy() for name in NAMES}


def _listing(folder):
    found = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = os.path.join(root, name)
            if os.path.islink(path) or not os.path.isfile(path):
                found[os.path.relpath(path, folder)] = os.readlink(path) if os.path.islink(path) else None
            else:
                with open(path, "rb") as fh:
                    found[os.path.relpath(path, folder)] = hashlib.sha256(fh.read()).hexdigest()
    return found


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    path = tmp_path_factory.mktemp("store") / "ref.zarr"
    result = _scan(path)
    assert result.computed == 4
    return path, _arrays(path)


def _edit_json(path, member, edit):
    """Edit a metadata file and its copy in the consolidated metadata, as a careful hand would."""
    doc = json.loads((path / member).read_text())
    edit(doc)
    (path / member).write_text(json.dumps(doc))
    meta = json.loads((path / ".zmetadata").read_text())
    edit(meta["metadata"][member])
    (path / ".zmetadata").write_text(json.dumps(meta))


def _swap_dimensions(path):
    for name in ("chaotic_fraction", "chaotic_fraction_stderr", "regular_orbits", "orbits_used"):
        _edit_json(path, f"{name}/.zattrs", lambda a: a.update(_ARRAY_DIMENSIONS=a["_ARRAY_DIMENSIONS"][::-1]))


def _extra_array(path):
    import zarr

    group = zarr.open_group(str(path), mode="r+", zarr_format=2)
    junk = group.create_array("junk", shape=(5,), dtype="f8")
    junk.attrs["_ARRAY_DIMENSIONS"] = ["H"]  # 5 values along H, which has 2: xarray cannot open the store
    zarr.consolidate_metadata(group.store, zarr_format=2)


@pytest.mark.parametrize("change,needle", [
    (_swap_dimensions, "the array chaotic_fraction has the dimensions ['H', 'eps']"),
    (lambda p: _edit_json(p, ".zattrs", lambda a: a.update(seed=4)), "its attributes (.zattrs) were changed"),
    (lambda p: _edit_json(p, ".zattrs", lambda a: a.update(wall="1+0.1*cos(t)")), "its attributes (.zattrs)"),
    (lambda p: _edit_json(p, ".zattrs", lambda a: a.update(command="coinwall scan lyapunov")), "attributes"),
    (lambda p: _edit_json(p, "chaotic_fraction/.zattrs", lambda a: a.update(units="m")),
     "the metadata of chaotic_fraction were changed"),
    (_extra_array, "it holds an array 'junk' it was not made with"),
    (lambda p: _edit_json(p, ".zattrs", lambda a: a.pop("scan_metadata_sha256")), "no record of its metadata"),
])
def test_a_store_whose_labels_changed_is_refused(reference, tmp_path, monkeypatch, capsys, change, needle):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(reference[0], tmp_path / "s.zarr")
    change(tmp_path / "s.zarr")
    before = _listing(tmp_path)
    assert main(ARGS) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:") and needle in err, err
    assert _listing(tmp_path) == before


def test_a_users_own_attribute_is_kept(reference, tmp_path):
    """Only the store's own record is checked: a note added by the user neither refuses the store nor is lost."""
    path = tmp_path / "s.zarr"
    shutil.copytree(reference[0], path)
    _edit_json(path, ".zattrs", lambda a: a.update(my_note="run on the lab machine"))
    assert _scan(path).computed == 0
    assert json.loads((path / ".zattrs").read_text())["my_note"] == "run on the lab machine"


def test_the_wall_files_content_is_the_identity(tmp_path, monkeypatch, capsys):
    """The same file name with other data is another scan; the same data again resumes."""
    monkeypatch.chdir(tmp_path)
    theta = np.arange(64) * 2 * np.pi / 64

    def write(eps):
        with open("w.csv", "w") as fh:
            fh.write("theta,b\n" + "".join(f"{t:.17g},{1 + eps * np.cos(2 * t):.17g}\n" for t in theta))

    args = ["scan", "chaotic-fraction", "w.csv", "--H", "3,4", "--orbits", "4", "--collisions", "40",
            "--scheduler", "synchronous", "-o", "w.zarr"]
    write(0.1)
    assert main(args) == 0
    capsys.readouterr()
    write(0.2)
    before = _listing(tmp_path)
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "was made from another wall" in err and err.count("\n") == 1, err
    assert _listing(tmp_path) == before
    write(0.1)
    assert main(args + ["--json"]) == 0
    assert json.loads(capsys.readouterr().out)["resumed"] == 2


def _resume_in_a_subprocess(path, timeout=120):
    """The resume in a process of its own, under 2 GiB of address space and a time limit: a FIFO that blocks or a
    link to /dev/zero that is read whole fails the test instead of hanging it or taking the machine."""
    code = (
        "import resource, sys; resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30)); "
        "sys.path.insert(0, sys.argv[2]); import test_store_trust as t; r = t._scan(sys.argv[1]); "
        "print(r.computed); print(r.notes)")
    return subprocess.run([sys.executable, "-c", code, str(path), os.path.dirname(__file__)], capture_output=True,
                          text=True, timeout=timeout, check=False)


def test_chunks_that_are_not_regular_files_are_computed_again(reference, tmp_path):
    """A FIFO, a link to /dev/zero, a link to the user's own file and a sparse file of 6 GB in place of four
    chunks: each is removed (a link, never what it points to) and its cell computed again."""
    ref_path, ref = reference
    path = tmp_path / "s.zarr"
    shutil.copytree(ref_path, path)
    mine = tmp_path / "mine.bin"
    mine.write_bytes(b"the user's own data")
    chunks = {kind: path / "chaotic_fraction" / name for kind, name in
              (("fifo", "0.0"), ("devzero", "0.1"), ("users-file", "1.0"), ("huge", "1.1"))}
    for chunk in chunks.values():
        os.unlink(chunk)
    os.mkfifo(chunks["fifo"])
    os.symlink("/dev/zero", chunks["devzero"])
    os.symlink(mine, chunks["users-file"])
    with open(chunks["huge"], "wb") as fh:
        fh.truncate(6 << 30)  # 6 GB (sparse)
    result = _resume_in_a_subprocess(path)
    assert result.returncode == 0, result.stderr[-2000:]
    computed, notes = result.stdout.splitlines()[-2:]
    assert int(computed) == 4 and "4 chunk(s) of the store were not regular files of a chunk's size" in notes
    got = _arrays(path)
    assert all(np.array_equal(got[k], ref[k], equal_nan=got[k].dtype.kind == "f") for k in NAMES)
    assert all(chunk.is_file() and not chunk.is_symlink() for chunk in chunks.values())
    assert mine.read_bytes() == b"the user's own data"


def test_metadata_that_is_a_fifo_is_refused(reference, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(reference[0], tmp_path / "s.zarr")
    os.unlink(tmp_path / "s.zarr" / "cell_status" / ".zarray")
    os.mkfifo(tmp_path / "s.zarr" / "cell_status" / ".zarray")
    assert main(ARGS) == 2
    err = capsys.readouterr().err
    assert "cell_status/.zarray is a FIFO" in err, err


def test_doctests():
    import doctest
    import importlib

    assert doctest.testmod(importlib.import_module("coinwall.cases.scan.table")).failed == 0
