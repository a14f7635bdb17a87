"""Hardening of the billiard: a kernel cache that is private and heals, long runs in
pieces, bounds that keep the kernel's float64 arithmetic meaningful, and requests refused before they
exhaust memory or time.

Reference values and where they come from:

* the numbers a kernel loaded from a (rebuilt, or no) cache gives are compared with the same kernel freshly
  compiled: they must be identical (the same source and compiler);
* Santaló's mean free time ``π·Area/Perimeter`` (exact for an ergodic table; the coin at H = 3) for the
  statistics of a run in many pieces;
* a flat wall (b = 1): v_θ is conserved and every flight has the same length, so a run in pieces must
  equal one long run bit for bit apart from the summed time;
* the refusal messages: the bounds stated in the Billiard, correlation and kam docstrings.
"""

import hashlib
import json
import math
import os
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward import Wall
from coinwall.forward.dynamics.analysis import orbitstats
from coinwall.forward.dynamics.billiard import wallcode
from coinwall.forward.dynamics.billiard.kernel import NOTES, compiled, run
from coinwall.forward.dynamics.billiard.table import Billiard, random_states, simulate
from coinwall.forward.errors import InvalidArgument

COIN = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99})
FOURIER = Wall.from_fourier(1.0, [0.1, 0.02, 0.003], [0.05, 0.0, 0.01])   # shares test_billiard's kernel
TINY = "from numba import njit\n\n\n@njit(cache=CACHE)\ndef shift(x):\n    return x + 1.5\n"


# ---------------------------------------------------------------------------------------------- the cache
@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh COINWALL_CACHE_DIR and fresh module/notice registries (nothing from other tests)."""
    base = tmp_path / "cache"
    monkeypatch.setenv("COINWALL_CACHE_DIR", str(base))
    monkeypatch.setattr(wallcode, "_MODULES", {})
    monkeypatch.setattr(wallcode, "_NOTED", set())
    return base


def _tiny(prefix="coinwall_test_tiny"):
    """Load and run the tiny module (as kernel.CompiledKernel.call does); forget it afterwards.  Returns the
    module and its function's numba statistics (cache hits and misses)."""
    module = wallcode.load_module(TINY, prefix)
    assert module.shift(1.0) == 2.5
    wallcode._MODULES.clear()
    sys.modules.pop(module.__name__, None)
    return module, module.shift.stats


def _notes(capsys):
    err = capsys.readouterr().err
    return [line for line in err.splitlines() if line]


def _cache_files(base):
    return sorted(p for p in Path(base).rglob("*") if p.is_file())


def test_cache_folders_are_private_and_reused(cache, capsys):
    module, stats = _tiny()
    assert module.CACHED and sum(stats.cache_misses.values()) == 1
    folder = Path(stats.cache_path)
    assert folder.parent == cache
    for level in (cache, folder):
        assert stat.S_IMODE(os.stat(level).st_mode) == 0o700
    files = _cache_files(cache)
    assert [f.suffix for f in files] == [".nbc", ".nbi"] and all(f.parent == folder for f in files)  # numba's two
    assert not any(f.suffix == ".py" for f in files)   # the module is executed from memory, never from a file
    assert _notes(capsys) == []
    _, stats = _tiny()                                  # loaded from the cache: a hit, no notice
    assert sum(stats.cache_hits.values()) == 1 and sum(stats.cache_misses.values()) == 0
    assert _notes(capsys) == []


@pytest.mark.parametrize("target", [".nbi", ".nbc"])
@pytest.mark.parametrize("damage", ["truncate", "empty", "garble", "foreign"])
def test_damaged_cache_file_is_a_miss_and_rebuilt(cache, capsys, target, damage):
    """A damaged file (or numba's own unchecked format) is never loaded: the function is compiled again, gives the
    same result (asserted in _tiny), and the file is written again, so the next process loads it (a hit)."""
    first, _ = _tiny()
    path = next(f for f in _cache_files(cache) if f.suffix == target)
    data = path.read_bytes()
    if damage == "truncate":
        data = data[: len(data) // 2]
    elif damage == "empty":
        data = b""
    elif damage == "garble":  # bytes in the middle replaced (machine code, for .nbc: loading it would crash)
        middle = len(data) // 2
        data = data[:middle] + bytes((b + 97) % 256 for b in data[middle:middle + 64]) + data[middle + 64:]
    else:  # a valid pickle without coinwall's checksum: what numba itself writes
        data = data[32:]
    path.write_bytes(data)
    _, stats = _tiny()
    assert sum(stats.cache_misses.values()) == 1 and sum(stats.cache_hits.values()) == 0
    assert path.read_bytes() != data
    _, stats = _tiny()                                  # healed
    assert sum(stats.cache_hits.values()) == 1
    assert _notes(capsys) == []


def test_a_folder_in_place_of_a_cache_file_is_one_note(cache, capsys):
    """Something that is not a file where numba's index goes: the kernel runs (compiled in memory), one note."""
    _tiny()
    index = next(f for f in _cache_files(cache) if f.suffix == ".nbi")
    index.unlink()
    (index / "d" / "d").mkdir(parents=True)
    _, stats = _tiny()
    assert sum(stats.cache_misses.values()) == 1
    notes = _notes(capsys)
    assert len(notes) == 1 and "could not write the kernel cache" in notes[0] and "is a folder" in notes[0]


@pytest.mark.parametrize("mode", [0o777, 0o755])
def test_untrusted_folders_are_not_used(tmp_path, monkeypatch, capsys, mode):
    """A cache folder others can write (or, for the versioned folder, enter) is not used: compiled in memory."""
    monkeypatch.setattr(wallcode, "_MODULES", {})
    monkeypatch.setattr(wallcode, "_NOTED", set())
    base = tmp_path / "shared"
    base.mkdir()
    if mode == 0o777:
        base.chmod(mode)
    else:  # the base is fine; the folder of the kernels is readable by others
        from numba import __version__

        (base / f"kernels-numba{__version__}-py{sys.version_info[0]}{sys.version_info[1]}").mkdir(mode=mode)
    monkeypatch.setenv("COINWALL_CACHE_DIR", str(base))
    before = sorted(base.rglob("*"))
    module, stats = _tiny("coinwall_test_shared")        # works, compiled in memory
    assert not module.CACHED and stats.cache_path is None
    assert sorted(base.rglob("*")) == before             # nothing created, read or written there
    notes = _notes(capsys)
    assert len(notes) == 1 and "open to others" in notes[0] and "compiling in memory" in notes[0]
    if hasattr(os, "geteuid") and os.geteuid() == 0 and mode == 0o777:  # a private folder of another user
        other = tmp_path / "other"
        other.mkdir(mode=0o700)
        os.chown(other, 4242, 4242)
        monkeypatch.setenv("COINWALL_CACHE_DIR", str(other))
        monkeypatch.setattr(wallcode, "_NOTED", set())
        assert not _tiny("coinwall_test_other")[0].CACHED
        assert "belongs to user id 4242" in _notes(capsys)[0] and os.listdir(other) == []


def test_numba_cache_dir_does_not_move_the_cache(cache, monkeypatch, tmp_path):
    """NUMBA_CACHE_DIR moves numba's caches of other code; coinwall's stay in its private folder."""
    import numba

    elsewhere = tmp_path / "numba-elsewhere"
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(elsewhere))
    _, stats = _tiny("coinwall_test_elsewhere")
    assert Path(stats.cache_path).parent == cache
    assert not elsewhere.exists()


def test_the_package_kernels_cache_in_the_private_folder_too(cache, monkeypatch):
    """The 3-D coin's kernel is a module of the package: its functions get the same folder, stamped with the
    hash of its sources (numba's own cache would go beside the file, or to numba's folder, unchecked)."""
    from numba.core.dispatcher import Dispatcher

    from coinwall.forward.dynamics.coin3d import _top_kernel

    functions = [f for f in vars(_top_kernel).values() if isinstance(f, Dispatcher)]
    for f in functions:  # put back what the rest of the session uses
        monkeypatch.setattr(f, "_cache", f._cache)
    monkeypatch.delattr(_top_kernel, "CACHED", raising=False)  # attached again, to this test's folder
    assert wallcode.cache_module(_top_kernel) and len(functions) > 5
    folder = wallcode.cache_dir()
    digest = wallcode._package_stamp(_top_kernel.__file__, _top_kernel.__name__)
    assert Path(folder).parent == cache
    assert all(f._cache.cache_path == folder and f._cache._cache_file._source_stamp == digest for f in functions)


def test_package_kernels_are_keyed_by_their_sources_and_what_they_import(tmp_path, monkeypatch):
    """A package module's compiled code is keyed by its source and by the sources of the package's modules it
    imports (numba compiles a called kernel into its caller: the 3-D coin's rest kernel calls the top's), not by
    where the package lies: two clones with the same sources share it, a changed imported module changes it."""
    import importlib
    import shutil

    package = tmp_path / "one" / "cwstamp"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "inner.py").write_text("def f(x):\n    return x\n")
    (package / "outer.py").write_text("import math\n\nfrom .inner import f\n\n\ndef g(x):\n    return f(x) + math.pi\n")
    monkeypatch.syspath_prepend(str(tmp_path / "one"))
    for name in ("cwstamp", "cwstamp.inner", "cwstamp.outer"):
        monkeypatch.delitem(sys.modules, name, raising=False)
    outer = importlib.import_module("cwstamp.outer")
    stamp = wallcode._package_stamp.__wrapped__
    before = stamp(outer.__file__, "cwstamp.outer")
    assert before != hashlib.sha256((package / "outer.py").read_bytes()).hexdigest()
    clone = tmp_path / "two" / "cwstamp"
    shutil.copytree(package, clone)
    assert stamp(str(clone / "outer.py"), "cwstamp.outer") == before  # another place, the same sources
    (package / "inner.py").write_text("def f(x):\n    return 2 * x\n")
    assert stamp(outer.__file__, "cwstamp.outer") != before  # the imported module changed
    (package / "inner.py").write_text("def f(x):\n    return x\n")
    assert stamp(outer.__file__, "cwstamp.outer") == before
    for name in ("cwstamp", "cwstamp.inner", "cwstamp.outer"):
        sys.modules.pop(name, None)


@pytest.mark.slow
def test_kernel_in_memory_gives_the_same_numbers(tmp_path, monkeypatch, capsys):
    """The real kernel compiled in memory (untrusted cache folder) gives the numbers of the cached one.

    In the slow tier: it compiles the whole billiard kernel once more (about 6 s of CPU alone, 25 s on a loaded
    machine).  The default run checks the in-memory path itself with a small module
    (``test_untrusted_folders_are_not_used``: compiled in memory, nothing written, the one note)."""
    table = Billiard(FOURIER, 3.0)
    state = random_states(table, 1, seed=11)[0]
    cached = simulate(table, state, 300)
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    monkeypatch.setenv("COINWALL_CACHE_DIR", str(shared))
    monkeypatch.setattr(wallcode, "_MODULES", {})
    monkeypatch.setattr(wallcode, "_NOTED", set())
    fresh_wall = Wall.from_fourier(1.0, [0.1, 0.02, 0.003], [0.05, 0.0, 0.01])  # a new object: a new kernel entry
    memory = simulate(Billiard(fresh_wall, 3.0), state, 300)
    assert not compiled(Billiard(fresh_wall, 3.0)).module.CACHED
    for field in ("time", "theta", "eta", "v_theta", "v_eta", "side"):
        np.testing.assert_array_equal(getattr(memory, field), getattr(cached, field))
    assert os.listdir(shared) == [] and "compiling in memory" in capsys.readouterr().err


_LOAD_TINY = """
import sys
from coinwall.forward.dynamics.billiard import wallcode
module = wallcode.load_module(sys.argv[1], "coinwall_test_race")
print(module.shift(1.0), sum(module.shift.stats.cache_hits.values()))
"""


def test_two_processes_compile_at_once(tmp_path):
    """Two processes compile the same module into an empty cache at once: all work, none complains, and the
    cache they leave is complete (the next load is a silent hit)."""
    env = dict(os.environ, COINWALL_CACHE_DIR=str(tmp_path / "cache"))
    runs = [subprocess.Popen([sys.executable, "-c", _LOAD_TINY, TINY], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=env) for _ in range(2)]
    outs = [p.communicate(timeout=300) for p in runs]
    assert [p.returncode for p in runs] == [0] * 2, outs
    assert [out.split()[0] for out, _ in outs] == ["2.5"] * 2 and all(err == "" for _, err in outs)
    again = subprocess.run([sys.executable, "-c", _LOAD_TINY, TINY], capture_output=True, text=True, env=env,
                           timeout=300, check=False)
    assert (again.returncode, again.stdout, again.stderr) == (0, "2.5 1\n", "")


@pytest.mark.slow
def test_two_kernels_compile_at_once_then_heal(tmp_path):
    """Two `coinwall simulate` compile the same wall into an empty cache at once; then a garbled numba data
    file of the kernel (machine code: loading it would die with SIGILL) is a miss, compiled again, with the
    same numbers.  (~40 s on a loaded 2-core machine: three kernel compilations.)"""
    wall = tmp_path / "wall.json"
    wall.write_text(json.dumps({"a0": 1.0, "cos": [0.1, 0.03], "sin": [0.02, 0.0]}))
    env = dict(os.environ, COINWALL_CACHE_DIR=str(tmp_path / "cache"))
    argv = [sys.executable, "-m", "coinwall", "simulate", str(wall), "--H", "3", "--collisions", "500", "--seed",
            "4", "--json"]
    runs = [subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
            for _ in range(2)]
    outs = [p.communicate(timeout=300) for p in runs]
    assert [p.returncode for p in runs] == [0, 0], outs
    docs = [json.loads(out) for out, _ in outs]
    assert docs[0]["final_state"] == docs[1]["final_state"] and docs[0]["collisions"] == 500
    assert all(err == "" for _, err in outs)
    data = next(f for f in _cache_files(tmp_path / "cache") if "._run-" in f.name and f.suffix == ".nbc")
    raw = bytearray(data.read_bytes())
    raw[len(raw) // 2: len(raw) // 2 + 256] = bytes(256)
    data.write_bytes(bytes(raw))
    again = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=300, check=False)
    assert again.returncode == 0 and again.stderr == "", again.stderr
    assert json.loads(again.stdout)["final_state"] == docs[0]["final_state"]
    assert data.read_bytes() != bytes(raw)  # written again


# ---------------------------------------------------------------------------------------------- long runs
def test_many_pieces_equal_one_run_on_a_flat_wall(monkeypatch):
    """Flat wall b = 1 (v_θ conserved): 40 pieces of 250 collisions are the long run, and θ stays continuous
    past 10^5 rad, where the unwrapped angle alone would no longer place the particle on the wall."""
    table = Billiard(Wall.from_fourier(1.0, [0.0]), 3.0)
    state = [1.0, 1.5, 0.9995, math.sqrt(1 - 0.9995 ** 2)]
    whole = simulate(table, state, 10_000)
    monkeypatch.setattr(orbitstats, "CHUNK", 250)
    pieces = orbitstats.orbit_statistics(table, state, 10_000)
    assert pieces.collisions == 10_000 and pieces.note == ""
    assert whole.theta[-1] > 1e5
    np.testing.assert_array_equal(pieces.final_state, whole.final_state)
    assert pieces.bottom == int(np.count_nonzero(whole.side == 0))
    assert pieces.total_time == pytest.approx(whole.time[-1], rel=1e-12)
    assert (pieces.final_angle, pieces.final_turns) == (whole.end_angle, whole.end_turns)


def test_many_pieces_far_from_zero_on_the_coin(monkeypatch):
    """The issue's failure: the coin continued from θ ~ 6e6 rad (one ulp 9e-10) was refused as "outside the
    strip" by the 3e-12 check at the unwrapped angle.  In pieces of 7 it now runs; its statistics match a
    single long run from the same start (Santaló's mean free time within the spread of 3000 collisions)."""
    table = Billiard(COIN, 3.0)
    start = random_states(table, 1, seed=2)[0]
    start[0] += 2 * math.pi * 1_000_000
    monkeypatch.setattr(orbitstats, "CHUNK", 7)
    pieces = orbitstats.orbit_statistics(table, start, 3000)
    assert pieces.collisions == 3000 and pieces.note == ""
    assert abs(pieces.final_state[0] - start[0]) < 1e5                 # continuous, not reduced
    assert 0 <= pieces.final_angle < 2 * math.pi
    santalo = pieces.santalo_mean_free_time
    assert pieces.mean_free_time == pytest.approx(santalo, rel=0.1)
    assert 0.4 < pieces.bottom_fraction < 0.6
    # the unwrapped final_state still continues (its rounding is within the widened tolerance)
    again = simulate(table, pieces.final_state, 10)
    assert len(again) == 10 and again.note == ""


def test_long_run_statistics_in_pieces(monkeypatch):
    """60000 coin collisions in 30 pieces against the same start in one run: the same statistics."""
    table = Billiard(COIN, 3.0)
    start = random_states(table, 1, seed=7)[0]
    whole = simulate(table, start, 60_000)
    monkeypatch.setattr(orbitstats, "CHUNK", 2000)
    pieces = orbitstats.orbit_statistics(table, start, 60_000)
    assert pieces.collisions == len(whole) == 60_000
    santalo = pieces.santalo_mean_free_time
    assert pieces.mean_free_time == pytest.approx(santalo, rel=0.03)
    assert whole.time[-1] / 60_000 == pytest.approx(santalo, rel=0.03)
    assert pieces.bottom_fraction == pytest.approx(np.mean(whole.side == 0), abs=0.02)


@pytest.mark.slow
def test_hundred_million_collisions_on_the_coin():
    """The issue's command, which died after 2-3e7 collisions: it must finish (measured: see the notes)."""
    done = subprocess.run([sys.executable, "-m", "coinwall", "simulate", "case:coin", "--H", "3", "--collisions",
                           "100000000", "--seed", "1", "--json"], capture_output=True, text=True, timeout=3600,
                          check=False)
    assert done.returncode == 0, done.stderr
    doc = json.loads(done.stdout)
    assert doc["collisions"] == 100_000_000 and doc["note"] == ""
    assert doc["mean_free_time"] == pytest.approx(doc["santalo_mean_free_time"], rel=1e-3)


# ---------------------------------------------------------------------------------------------- bounds
def test_kernel_guards_stop_instead_of_looping_or_crashing():
    """Past the Billiard's checks (called directly): θ beyond float64's reach ends the orbit with status 4,
    a ray that never leaves the band of a flat wall with status 5 — never a segfault or a hang."""
    from types import SimpleNamespace

    table = Billiard(Wall.from_fourier(1.0, [0.0]), 3.0)
    comp = compiled(table)
    huge = SimpleNamespace(H=1e50, b0=0.0, tol=1e-13 * 1e50)        # H = 1e50 as it used to reach the kernel
    rows, note, _ = run(comp, huge, np.array([1.0, 5e49, 0.6, 0.8]), -1, 1000)
    assert len(rows[0]) <= 1 and note == NOTES[4]
    rows, note, _ = run(comp, table, np.array([1e300, 1.5, 0.8, 0.6]), -1, 10)
    assert len(rows[0]) == 0 and note == NOTES[4]                    # θ = 1e300: no cell index from it
    grazing = np.array([1.0, 1.0 + 5e-13, 1.0, -1e-30])              # inside the band, almost horizontal
    rows, note, _ = run(comp, table, grazing, -1, 3)
    assert len(rows[0]) == 0 and note == NOTES[5]


@pytest.mark.parametrize("H,b0,needle", [
    (1e100, 0.0, "between -4e+06 and 4e+06"),
    (1e50, 0.0, "between -4e+06 and 4e+06"),
    (3.0, 1e300, "`b0` must be between -1e+06 and 1e+06"),
    (0.2000000000001, 0.0, "use H >= 0.200000001"),
])
def test_billiard_refuses_heights_outside_the_float64_range(H, b0, needle):
    with pytest.raises(InvalidArgument, match=needle.replace("+", r"\+").replace("(", r"\(")):
        Billiard(COIN, H, b0)


def test_random_states_has_a_budget(monkeypatch):
    """A strip open only on a sliver narrower than the sampling grid (the grid's estimate of the inside,
    2e-4 of the box, is 100 times the truth): a message naming an H that works, not an endless loop."""
    from coinwall.forward.dynamics.billiard import table as billiard

    monkeypatch.setattr(billiard, "_DRAW_BUDGET_MIN", 1e4)
    table = Billiard(COIN, 0.2 + 2e-9)
    with pytest.raises(InvalidArgument, match=r"cannot draw enough start states: .* random draws.* H >= 0\.20"):
        random_states(table, 1, seed=0)
    far = Billiard(COIN, 0.2 + 1e-6)
    far_states = random_states(far, 3, seed=0)                     # a wider opening: drawn within the budget
    assert np.all(far_states[:, 1] > far.lower(far_states[:, 0]))


@pytest.mark.parametrize("argv,needle", [
    (["simulate", "case:coin", "--collisions", "1000", "--H", "1e100"], "--H must be between"),
    (["simulate", "case:coin", "--collisions", "1000", "--H", "1e50"], "--H must be between"),
    (["simulate", "case:coin", "--collisions", "1000", "--H", "0.2000000000001"], "contact tolerances"),
    (["section", "case:coin", "--H", "1e100"], "--H must be between"),
    (["simulate", "case:coin", "--H", "3e9", "--kappa", "1e-9"], "max |b| <= 1e+06"),
    (["section", "case:coin", "--H", "3", "--collisions", "10000000000"], "of memory"),
    (["section", "case:coin", "--H", "3", "--orbits", "1000000000"], "of memory"),
    # (their time, 23 days and 2.3 days, is refused first: the one-hour bound without --allow-long)
    (["correlation", "case:coin", "--H", "3", "--bounces", "1000000000000"], "--allow-long"),
    (["correlation", "case:coin", "--H", "3", "--bounces", "10000000", "--max-lag", "90000"], "comparisons"),
    (["correlation", "case:coin", "--H", "3", "--bounces", "100000000000", "--max-lag", "1", "--orbits", "2"],
     "--allow-long"),
    (["kam", "--H", "3", "--collisions", "10000000000", "--orbits", "2"], "collisions of work"),
    (["kam", "--H", "1e100"], "--H must be between"),
])
def test_reproducers_exit_2_with_one_line(argv, needle, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:") and needle in err
    assert os.listdir(tmp_path) == []
