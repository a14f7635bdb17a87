"""Nothing of the user's is lost, and nothing of ours is left: hostile cases found by an independent probe, each a
test that gets one clear line and exit status 2 (or the right answer), with the folder listing compared before
and after.

1. A write touches nothing but its outputs: a user's ``.coinwall-settings.json`` survives it; folders made for a
   failed command are removed; an output that names an input is refused.
2. A scan store knows itself: with any single chunk damaged, a resumed scan ends with the arrays of an undamaged
   run; a store whose identity, coordinates or layout changed is refused in one line.
3. Ctrl-C during a scan is one line.
"""

import errno
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward.formats import output

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def listing(folder):
    """Every path under ``folder`` with the SHA-256 of each file (a folder maps to None)."""
    found = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs:
            found[os.path.relpath(os.path.join(root, name), folder)] = None
        for name in files:
            path = os.path.join(root, name)
            with open(path, "rb") as fh:
                found[os.path.relpath(path, folder)] = hashlib.sha256(fh.read()).hexdigest()
    return found


def one_error(capsys, *needles):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:"), err
    for needle in needles:
        assert needle in err, (needle, err)
    return err


# ------------------------------------------------------------------------------------- 1. outputs and temporaries
def test_users_own_files_of_the_old_pattern_survive_a_write(tmp_path, monkeypatch, capsys):
    """`.coinwall-settings.json` and `.coinwall-my_notes.csv`, two days old, used to vanish on the next write."""
    monkeypatch.chdir(tmp_path)
    old = time.time() - 2 * 86400
    for name in (".coinwall-settings.json", ".coinwall-my_notes.csv", ".coinwall-abcd_123.svg", ".coinwall-x1y2z3w4.tmp",
                 ".coinwall-tmp.00000000.1.0123456789abcdef.0123456789abcdef.part"):
        (tmp_path / name).write_text("mine")
        os.utime(tmp_path / name, (old, old))
    before = listing(tmp_path)
    assert main(["solve", "1+0.1*cos(2*t)", "--no-cross-check", "-o", "a.csv"]) == 0
    after = listing(tmp_path)
    assert set(after) - set(before) == {"a.csv"} and all(after[k] == v for k, v in before.items())


def test_ctrl_c_while_writing_leaves_nothing(tmp_path, monkeypatch):
    """Ctrl-C while the second of three outputs is written (one of them in a folder still to be made): the old
    file untouched, no temporary, no folder."""
    (tmp_path / "a.csv").write_text("old")
    before = listing(tmp_path)
    real = os.fdopen
    calls = []

    def fdopen(fd, mode="r", *args, **kwargs):
        calls.append(fd)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(fd, mode, *args, **kwargs)

    monkeypatch.setattr(os, "fdopen", fdopen)
    with pytest.raises(KeyboardInterrupt):
        output.write_all({str(tmp_path / "a.csv"): b"new", str(tmp_path / "new" / "b.csv"): b"b",
                          str(tmp_path / "c.csv"): b"c"})
    assert listing(tmp_path) == before


def test_an_output_path_too_long_is_refused_before_any_folder(tmp_path, monkeypatch, capsys):
    """`-o d/d/…/x.csv` (2100 levels) used to make some 2000 folders, then fail."""
    monkeypatch.chdir(tmp_path)
    deep = "d/" * 2100 + "x.csv"
    assert main(["solve", "1+0.1*cos(2*t)", "--no-cross-check", "-o", deep]) == 2
    one_error(capsys, "bytes long", "choose a shorter one")
    assert main(["solve", "1", "-o", "n" * 300 + ".csv"]) == 2
    one_error(capsys, "this filesystem allows")
    assert os.listdir(tmp_path) == []


def _disk_full(monkeypatch):
    """Every write of an output's temporary fails as on a full disk."""
    real = os.fdopen

    def fdopen(fd, mode="r", *args, **kwargs):
        if "w" in mode:
            os.close(fd)
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(fd, mode, *args, **kwargs)

    monkeypatch.setattr(os, "fdopen", fdopen)


def test_a_failed_command_removes_the_folders_it_made(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "keep").mkdir()
    before = listing(tmp_path)
    _disk_full(monkeypatch)
    assert main(["solve", "1+0.1*cos(2*t)", "--no-cross-check", "-o", "keep/a/b/c/x.csv", "-o", "y/z.json"]) == 2
    one_error(capsys, "No space left on device")
    assert listing(tmp_path) == before


def test_verify_out_on_a_full_disk_leaves_no_folder(tmp_path, monkeypatch, capsys):
    """`coinwall verify --out r/a/b` on a full disk: one line, no empty folders (it used to leave r/a/b/figures)."""
    from coinwall.cases.paper import figures, verify

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(verify, "evaluate", lambda claims, resolution, progress=False: ())  # the work is not tested
    monkeypatch.setattr(figures, "figure_files", lambda folder, points, ext: {os.path.join(folder, "f" + ext): b"x"})
    _disk_full(monkeypatch)
    assert main(["verify", "--fast", "--json", "--out", "r/a/b"]) == 2
    one_error(capsys, "No space left on device")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("command", [
    ["solve", "wall.csv", "--no-cross-check", "-o", "wall.csv"],
    ["solve", "wall.csv", "--no-cross-check", "-o", "body.json", "-o", "./wall.csv"],
    ["solve", "wall.csv", "--no-cross-check", "-o", "hard.csv"],
    ["fit", "wall.csv", "-o", "wall.csv"],
    ["wall", "body.json", "-o", "body.json"],
])
def test_an_output_that_is_an_input_is_refused(tmp_path, monkeypatch, capsys, command):
    monkeypatch.chdir(tmp_path)
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    np.savetxt("wall.csv", np.column_stack([theta, 1 + 0.05 * np.cos(2 * theta)]), delimiter=",", header="theta,b",
               comments="")
    os.link("wall.csv", "hard.csv")
    assert main(["solve", "1+0.05*cos(2*t)", "--no-cross-check", "-o", "body.json"]) == 0
    capsys.readouterr()
    before = listing(tmp_path)
    assert main(command) == 2
    one_error(capsys, "is an input file of this command", "choose another name")
    assert listing(tmp_path) == before


# ------------------------------------------------------------------------------------------------ 2. the scan store
pytest.importorskip("zarr")
pytest.importorskip("xarray")
pytest.importorskip("distributed")

GRID = {"eps": "2,8", "H": "0.4,3"}   # H = 0.4: refused cells (status 2) in the store as well
OPTIONS = {"orbits": 4, "collisions": 40}
NAMES = ["chaotic_fraction", "chaotic_fraction_stderr", "regular_orbits", "orbits_used", "cell_seed", "cell_status",
         "cell_checksum"]


def _scan(path, **kwargs):
    from coinwall.cases.scan import TableSpec, scan

    return scan("chaotic-fraction", TableSpec(ELLIPSE), GRID, output=str(path), options=OPTIONS, seed=3,
                scheduler="synchronous", **kwargs)


def _arrays(path):
    import xarray as xr

    with xr.open_zarr(str(path)) as ds:
        return {name: ds[name].values.copy() for name in NAMES}


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    path = tmp_path_factory.mktemp("store") / "ref.zarr"
    result = _scan(path)
    assert result.computed == 4 and result.refused == 2
    return path, _arrays(path)


def _damage(chunk, how, path):
    data = open(chunk, "rb").read()
    if how == "truncate":
        data = data[: len(data) // 2]
    elif how == "flip":
        k = len(data) - 1  # the last byte: the cell's own data (blosc keeps small chunks uncompressed)
        data = data[:k] + bytes([data[k] ^ 0xFF])
    elif how == "foreign":  # a chunk of another array: another dtype (or, for the seeds, another shape)
        other = os.path.join(path, "chaotic_fraction", "1.1") if "cell_seed" not in chunk \
            else os.path.join(path, "cell_status", "1.1")
        data = open(other, "rb").read()
    if how == "delete":
        os.unlink(chunk)
    else:
        with open(chunk, "wb") as fh:
            fh.write(data)


@pytest.mark.parametrize("how", ["truncate", "delete", "flip", "foreign"])
@pytest.mark.parametrize("chunk", ["chaotic_fraction/1.1", "orbits_used/0.1", "cell_status/1.1", "cell_status/0.0",
                                   "cell_checksum/1.1", "cell_seed/0.0"])
def test_a_store_with_any_single_chunk_damaged_resumes_to_the_same_arrays(reference, tmp_path, chunk, how):
    ref_path, ref = reference
    path = tmp_path / "s.zarr"
    shutil.copytree(ref_path, path)
    _damage(os.path.join(path, chunk), how, str(path))
    said = []
    result = _scan(path, notes=said.append)
    got = _arrays(path)
    assert all(np.array_equal(got[k], ref[k], equal_nan=got[k].dtype.kind == "f") for k in NAMES)
    assert result.computed <= 1 and list(result.notes) == said
    if chunk.startswith("cell_seed"):
        assert said and "cell_seed" in said[0]
    elif result.computed:
        assert "failed their checksum" in said[0]
    again = _scan(path)
    assert (again.computed, again.notes) == (0, ())


def test_a_damaged_consolidated_metadata_is_rewritten(reference, tmp_path):
    path = tmp_path / "s.zarr"
    shutil.copytree(reference[0], path)
    (path / ".zmetadata").write_text("garbage")
    assert _scan(path).computed == 0
    got = _arrays(path)
    assert all(np.array_equal(got[k], reference[1][k], equal_nan=got[k].dtype.kind == "f") for k in NAMES)


def _edit_attr(path, edit):
    for name in (".zattrs", ".zmetadata"):
        doc = json.loads((path / name).read_text())
        edit(doc if name == ".zattrs" else doc["metadata"][".zattrs"])
        (path / name).write_text(json.dumps(doc))


def _set_coordinate(path):
    import zarr

    zarr.open_group(str(path), mode="r+")["H"][1] = 72.0


def _status_dtype(path):
    meta = json.loads((path / "cell_status" / ".zarray").read_text())
    meta["dtype"] = "<f8"
    (path / "cell_status" / ".zarray").write_text(json.dumps(meta))


@pytest.mark.parametrize("change,needle", [
    (_set_coordinate, "its coordinate H was changed on disk (72 at position 2, 3 when it was made)"),
    (lambda p: _edit_attr(p, lambda a: a.update(scan_identity=a["scan_identity"][:-3])), "scan_identity"),
    (lambda p: _edit_attr(p, lambda a: a.update(scan_identity=a["scan_identity"].replace('"seed": 3', '"seed": 4'))),
     "does not match its checksum"),
    (_status_dtype, "the array cell_status is float64"),
    (lambda p: shutil.rmtree(p / "cell_checksum"), "the array cell_checksum is missing"),
    (lambda p: (p / ".zattrs").write_text("{"), "damaged scan store"),
])
def test_a_store_changed_on_disk_is_refused_in_one_line(reference, tmp_path, monkeypatch, capsys, change, needle):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(reference[0], tmp_path / "s.zarr")
    change(tmp_path / "s.zarr")
    before = listing(tmp_path)
    args = ["scan", "chaotic-fraction", ELLIPSE, "--param", "eps=2,8", "--H", "0.4,3", "--orbits", "4",
            "--collisions", "40", "--seed", "3", "--scheduler", "synchronous", "-o", "s.zarr"]
    assert main(args) == 2
    one_error(capsys, needle)
    assert listing(tmp_path) == before


@pytest.mark.parametrize("address", ["tcp://[::1", "tcp://host:notaport", "http://x:1", "tcp://"])
def test_a_bad_scheduler_address_is_one_line(tmp_path, monkeypatch, capsys, address):
    monkeypatch.chdir(tmp_path)
    assert main(["scan", "chaotic-fraction", ELLIPSE, "--param", "eps=2", "--H", "3", "--scheduler", address,
                 "-o", "s.zarr"]) == 2
    one_error(capsys, "--scheduler")
    assert os.listdir(tmp_path) == []


def test_workers_are_bounded_by_the_machine(monkeypatch):
    """`--workers 300` on 2 cores reached 9.9 GB: the local cluster gets what cores and memory hold, with a note."""
    import distributed

    from coinwall.cases.scan import driver

    # Ctrl-C as in a terminal (a shell starts background jobs with SIGINT ignored, and the driver rightly
    # restores "ignored" there)
    original = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        _workers_are_bounded(monkeypatch, distributed, driver)
    finally:
        signal.signal(signal.SIGINT, original)


def _workers_are_bounded(monkeypatch, distributed, driver):
    made = {}

    class Cluster:
        def __init__(self, n_workers, **kwargs):
            made["n"] = n_workers
            made["ignored"] = signal.getsignal(signal.SIGINT) is signal.SIG_IGN

    monkeypatch.setattr(distributed, "LocalCluster", Cluster)
    monkeypatch.setattr(distributed, "Client", lambda cluster: "client")
    monkeypatch.setattr(driver, "worker_limit", lambda: (2, "2 core(s), 1 GiB"))
    notes = []
    assert driver._client("local", 300, notes)[0] == "client"
    assert made == {"n": 2, "ignored": True} and notes == ["asked for 300 workers; this machine can hold 2 "
                                                           "(2 core(s), 1 GiB): using 2"]
    assert signal.getsignal(signal.SIGINT) is not signal.SIG_IGN
    driver._client("local", 1, notes)
    assert made["n"] == 1 and len(notes) == 1
    limit, why = driver.worker_limit()
    assert 1 <= limit <= (os.cpu_count() or 1) and "core" in why
    os.environ.pop(driver.WORKER_ENVIRONMENT, None)


def test_ctrl_c_during_a_scan_is_one_line(tmp_path):
    """Ctrl-C goes to the whole process group; it used to print 67-76 lines of dask and tornado tracebacks."""
    command = [sys.executable, "-m", "coinwall", "scan", "chaotic-fraction", ELLIPSE, "--param", "eps=2:8:20",
               "--H", "2,3", "--orbits", "40", "--collisions", "3000", "--workers", "2", "-o", str(tmp_path / "c.zarr")]
    # the child gets Ctrl-C as in a terminal, even when the tests run as a background job (SIGINT ignored)
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            cwd=tmp_path, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.time() + 60
        while not os.path.exists(tmp_path / "c.zarr" / "cell_status") and time.time() < deadline:
            time.sleep(0.1)  # the store is made once the cluster is up: the cells are running
        time.sleep(1.0)
        os.killpg(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130 and err == "coinwall: interrupted\n", err
