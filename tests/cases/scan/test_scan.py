"""Parameter scans on dask.distributed (issue 15): grid, seeds, the batched exponents, the store, the driver on
local clusters (1 vs 2 workers, resume after an interruption, a killed worker), the CLI.

Reference values and where they come from are stated in each test.  The cluster tests use grids of a few
cells with small samples; they need dask.distributed, xarray and zarr (the ``scan`` extra).
"""

import json
import os
import signal

import numpy as np
import pytest

pytest.importorskip("distributed")
pytest.importorskip("xarray")
pytest.importorskip("zarr")

from benettin_loop import lyapunov_loop

from coinwall.cases.scan import (
    QUANTITIES,
    TableSpec,
    cell_seed,
    check_options,
    compute_cell,
    parse_axis,
    scan,
)
from coinwall.forward import Wall
from coinwall.forward.dynamics.analysis.islands import ELLIPSE_WALL, eps_star, eps_star_star
from coinwall.forward.dynamics.analysis.lyapunov import chaotic_fraction, lyapunov_many
from coinwall.forward.dynamics.billiard.table import Billiard, random_states
from coinwall.forward.errors import InvalidArgument

TABLE = TableSpec(ELLIPSE_WALL)
GRID = {"eps": "1:20:3log", "H": "0.4,2,3"}   # H = 0.4 < 2/√(1+ε) for ε ≤ 20: the strip is closed, refused cells
OPTIONS = {"orbits": 24, "collisions": 300}
VARIABLES = list(QUANTITIES["chaotic-fraction"].variables)


def arrays(path):
    import xarray as xr

    with xr.open_zarr(path) as ds:
        return {name: ds[name].values.copy() for name in [*VARIABLES, "cell_seed", "cell_status"]}


def same_arrays(a, b):
    return all(np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f") for k in a)


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=50)
    with Client(cluster) as c:
        yield c
    cluster.close()


@pytest.fixture(scope="module")
def reference(tmp_path_factory, client):
    """The whole GRID scanned on the 2-worker cluster."""
    path = str(tmp_path_factory.mktemp("scan") / "ref.zarr")
    result = scan("chaotic-fraction", TABLE, GRID, output=path, options=OPTIONS, seed=7, client=client)
    return path, result


# ---------------------------------------------------------------------------------------------------- grid
def test_parse_axis_forms():
    """LIST, START:STOP:N (ends included) and START:STOP:Nlog (geometric) (module docstring of grid.py)."""
    assert parse_axis("H", "2, 3,4.5").values == (2.0, 3.0, 4.5)
    assert parse_axis("H", "2:4:5").values == (2.0, 2.5, 3.0, 3.5, 4.0)
    assert np.allclose(parse_axis("eps", "0.1:10:3log").values, [0.1, 1.0, 10.0], rtol=1e-14)
    assert parse_axis("H", "3").values == (3.0,)


@pytest.mark.parametrize("text", ["", "a,b", "1:2", "1:2:0", "1:2:x", "0:10:3log", "1:2:3:4", "2,2", "1,nan"])
def test_parse_axis_refuses(text):
    with pytest.raises(InvalidArgument):
        parse_axis("H", text)


def test_cell_seed_depends_on_coordinates_only():
    """Same (seed, coordinates) → same seed, in any grid; another coordinate or scan seed → another seed."""
    a = cell_seed(7, (2.0, 3.0))
    assert a == cell_seed(7, (2.0, 3.0)) and 0 <= a < 2**63
    assert len({a, cell_seed(7, (3.0, 2.0)), cell_seed(8, (2.0, 3.0)), cell_seed(7, (2.0, 3.0000000000000004))}) == 4


def test_check_options():
    assert check_options("chaotic-fraction", {}) == QUANTITIES["chaotic-fraction"].defaults
    with pytest.raises(InvalidArgument, match="`bounces` is not an option"):
        check_options("chaotic-fraction", {"bounces": 10})
    with pytest.raises(InvalidArgument, match="max_lag"):
        check_options("tau", {"bounces": 100, "orbits": 10, "max_lag": 10})
    with pytest.raises(InvalidArgument):
        check_options("no-such-quantity", {})


# ---------------------------------------------------------------------------------------------------- cells
def test_lyapunov_many_reproduces_the_per_orbit_loop():
    """The array bookkeeping is the same method with the same arithmetic as a loop over the orbits on the
    public API (tests/benettin_loop.py): identical exponents, times and counts (to the bit)."""
    table = Billiard(Wall.from_expression(ELLIPSE_WALL, {"eps": 3.0}), 3.0)
    states = random_states(table, 12, 5)
    result = lyapunov_many(table, states, 200, seed=5, workers=1)
    per_collision, per_time, used, time, notes = lyapunov_loop(table, states, 200, seed=5, workers=1)
    assert np.array_equal(result.per_collision, per_collision)
    assert np.array_equal(result.per_time, per_time)
    assert np.array_equal(result.collisions, used)
    assert np.array_equal(result.time, time)
    assert result.notes == notes == ()


def test_lyapunov_many_notes_orbits_that_stop_as_the_loop_does():
    """A stick (flat walls) in an open channel: orbits that fly parallel to the walls stop early; the notes
    name them and why, as the per-orbit loop's do, and their exponents are NaN."""
    table = Billiard(Wall.from_expression("1 + 0*t"), 3.0)
    states = np.array([[0.1, 1.5, 1.0, 0.3], [0.2, 1.5, 1.0, 0.0], [0.3, 1.4, 0.2, 1.0]])
    result = lyapunov_many(table, states, 40, seed=1, workers=1)
    per_collision, _, used, _, notes = lyapunov_loop(table, states, 40, seed=1, workers=1)
    assert result.notes == notes and len(notes) >= 1 and notes[0].startswith("orbit 1: free flight")
    assert np.array_equal(np.isnan(result.per_collision), np.isnan(per_collision))
    assert np.isnan(result.per_collision[1]) and np.array_equal(result.collisions, used)


def test_chaotic_fraction_cell_equals_library():
    """A cell is chaotic_fraction(table, orbits, collisions, seed=cell seed): same counts."""
    seed = cell_seed(7, (3.0, 3.0))
    cell = compute_cell("chaotic-fraction", TABLE, {"eps": 3.0}, 3.0, seed, check_options("chaotic-fraction", OPTIONS))
    lib = chaotic_fraction(Billiard(Wall.from_expression(ELLIPSE_WALL, {"eps": 3.0}), 3.0), 24, 300, seed=seed,
                           workers=1)
    assert cell["status"] == 1
    assert cell["chaotic_fraction"] == lib.fraction and cell["regular_orbits"] == lib.regular


def test_refused_cell_is_a_finding():
    """H = 0.5 < 2/√(1+ε) leaves no room for motion: status 2 with the library's message, not an exception."""
    cell = compute_cell("chaotic-fraction", TABLE, {"eps": 1.0}, 0.5, 1, check_options("chaotic-fraction", {}))
    assert cell["status"] == 2 and "no room for motion" in cell["error"]


def test_tau_and_splitting_cells():
    """tau: P(1) in (½, 1) at H/D = 1.2 (docs/dynamics.md: 0.8184 with 10⁶ bounces); splitting: the lowest
    doublet at ε = 0.55, H = 2.3 is a small positive Δλ, tunnelling (docs/quantum.md)."""
    tau = compute_cell("tau", TableSpec(ELLIPSE_WALL, (("eps", 99.0),)), {}, 2.4, 3,
                       check_options("tau", {"bounces": 4000, "orbits": 4, "max_lag": 5}))
    assert tau["status"] == 1 and 0.75 < tau["P1"] < 0.9 and tau["tau"] > 0
    split = compute_cell("splitting", TABLE, {"eps": 0.55}, 2.3, 0, check_options("splitting", {"cells": 4}))
    assert split["status"] == 1 and 0 < split["splitting"] < 1e-2 and split["neck_width"] == pytest.approx(0.3)


def test_islands_closed_form_matches_docs_table():
    """ε*(H), ε**(H) of docs/dynamics.md ("The islands come from two period-2 orbits", closed form)."""
    for H, star, star2 in [(2, 4.049, 21.84), (3, 1.861, 6.011), (8, 0.372, 0.689), (16, 0.152, 0.255)]:
        assert eps_star(H) == pytest.approx(star, abs=6e-4)
        assert eps_star_star(H) == pytest.approx(star2, rel=6e-4)


# ---------------------------------------------------------------------------------------------------- driver
def test_scan_store_layout(reference):
    """Coordinates with units, attributes (seed, version, options), statuses: 1 computed, 2 refused (H = 0.4)."""
    import xarray as xr

    from coinwall import __version__

    path, result = reference
    assert result.cells == 9 and result.computed == 9 and result.refused == 3 and result.workers == 2
    with xr.open_zarr(path) as ds:
        assert ds.chaotic_fraction.dims == ("eps", "H")
        assert ds.H.attrs["units"] == "kappa" and ds.chaotic_fraction.attrs["units"] == "1"
        assert ds.attrs["seed"] == 7 and ds.attrs["coinwall_version"] == __version__
        assert ds.attrs["quantity"] == "chaotic-fraction" and "orbits" in ds.attrs["options"]
        status = ds.cell_status.values
        assert (status[:, 0] == 2).all() and (status[:, 1:] == 1).all()
        assert np.isnan(ds.chaotic_fraction.values[:, 0]).all()
        fraction = ds.chaotic_fraction.values[:, 1:]
        assert np.all((fraction > 0) & (fraction <= 1))
        # ε = 1 is below ε*(2) = 4.05: the vertical orbit's island is large; ε = 20 is far above ε*(3) = 1.86
        assert fraction[0, 0] < 0.7 and fraction[2, 1] > 0.95


def test_one_worker_gives_the_same_arrays(reference, tmp_path):
    """Seeds follow the coordinates, not the worker or the order: 1 worker == 2 workers, bit for bit."""
    path, _ = reference
    one = str(tmp_path / "one.zarr")
    result = scan("chaotic-fraction", TABLE, GRID, output=one, options=OPTIONS, seed=7, workers=1)
    assert result.workers == 1
    assert same_arrays(arrays(one), arrays(path))


def test_interrupted_scan_resumes_missing_cells_only(reference, client, tmp_path):
    """Stop after 3 cells (as Ctrl-C would), run again: only the other 6 are computed; same arrays."""
    path = str(tmp_path / "part.zarr")

    def stop(done, todo):
        if done == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        scan("chaotic-fraction", TABLE, GRID, output=path, options=OPTIONS, seed=7, client=client, progress=stop)
    assert np.count_nonzero(arrays(path)["cell_status"]) == 3
    again = scan("chaotic-fraction", TABLE, GRID, output=path, options=OPTIONS, seed=7, client=client)
    assert (again.resumed, again.computed) == (3, 6)
    assert same_arrays(arrays(path), arrays(reference[0]))
    done = scan("chaotic-fraction", TABLE, GRID, output=path, options=OPTIONS, seed=7, client=client)
    assert (done.resumed, done.computed) == (9, 0)


def test_resume_with_other_options_is_refused(reference, client):
    path, _ = reference
    for change in ({"seed": 8}, {"options": {"orbits": 25, "collisions": 300}}):
        kwargs = {"options": OPTIONS, "seed": 7, **change}
        with pytest.raises(InvalidArgument, match="different scan"):
            scan("chaotic-fraction", TABLE, GRID, output=path, client=client, **kwargs)
    with pytest.raises(InvalidArgument, match="different scan"):
        scan("chaotic-fraction", TABLE, {"eps": "1:20:4log", "H": "0.4,2,3"}, output=path, options=OPTIONS, seed=7,
             client=client)


def test_bad_grids_are_refused_before_any_work(tmp_path):
    out = str(tmp_path / "x.zarr")
    for grid, match in [({"eps": "1:2:3"}, "'H' axis"), ({"epsx": "1,2", "H": "2"}, "eps"),
                        ({"eps": "1:2:0", "H": "2"}, "N in START:STOP:N")]:
        with pytest.raises(Exception, match=match):
            scan("chaotic-fraction", TABLE, grid, output=out)
    with pytest.raises(InvalidArgument, match="scheduler"):
        scan("chaotic-fraction", TABLE, {"eps": "1", "H": "2"}, output=out, scheduler="http://nowhere")
    assert not os.path.exists(out) or os.path.isdir(out)


def test_killed_worker_does_not_lose_the_scan(reference, tmp_path):
    """SIGKILL one worker process as the first cell arrives: its tasks run elsewhere, every cell is written,
    and the arrays equal the undisturbed scan's."""
    from distributed import Client, LocalCluster

    path = str(tmp_path / "killed.zarr")
    options = {"orbits": 40, "collisions": 1000}  # cells of ~0.1 s, so tasks are running when the kill comes
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=50)
    killed = []
    with Client(cluster) as c:
        # warm both workers first (imports, kernel load: seconds), so the kill lands while cells are running
        warm = check_options("chaotic-fraction", {"orbits": 2, "collisions": 20})
        c.run(compute_cell, "chaotic-fraction", TABLE, {"eps": 2.0}, 2.0, 0, warm)
        pids = list(c.run(os.getpid).values())

        def kill(done, todo):
            if not killed:
                os.kill(pids[0], signal.SIGKILL)
                killed.append(pids[0])

        grid = {"eps": "2:8:4", "H": "2,3"}
        result = scan("chaotic-fraction", TABLE, grid, output=path, options=options, seed=1, client=c, progress=kill)
        assert killed and result.computed == 8
        reference_path = str(tmp_path / "quiet.zarr")
        scan("chaotic-fraction", TABLE, grid, output=reference_path, options=options, seed=1, client=c)
    cluster.close()
    assert (arrays(path)["cell_status"] == 1).all()
    assert same_arrays(arrays(path), arrays(reference_path))


# ---------------------------------------------------------------------------------------------------- CLI
@pytest.fixture()
def cli():
    """``main`` of the command line (``scan`` is one of its SUBCOMMANDS)."""
    from coinwall.cases.cli import parser
    from coinwall.cases.cli.main import main

    assert "scan" in parser.SUBCOMMANDS
    return main


def test_cli_quantity_choices_are_the_library_table():
    """QUANTITY offers the library's QUANTITIES, read from the library when the command runs."""
    from coinwall.cases.cli.parser import build_parser

    action = next(a for a in build_parser().commands["scan"]._actions if a.dest == "quantity")
    assert list(action.choices) == list(QUANTITIES) and "tau" in action.choices and "magic" not in action.choices


def test_cli_scan_json_figure_and_refusals(cli, tmp_path, capsys):
    """A 2 × 2 phase diagram with a figure; then one-line refusals with exit status 2."""
    store, figure = str(tmp_path / "k.zarr"), str(tmp_path / "k.png")
    args = ["scan", "chaotic-fraction", ELLIPSE_WALL, "--param", "eps=2,8", "--H", "2,3", "--orbits", "10",
            "--collisions", "200", "--workers", "1", "-o", store]
    assert cli([*args, "--figure", figure, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["cells"] == 4 and doc["computed"] == 4 and os.path.getsize(figure) > 1000
    assert cli([*args[:-4], "--workers", "1", "-o", store, "--seed", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("coinwall: error: --output") and "different scan" in err and err.count("\n") == 1
    for bad, text in [(["--bounces", "5"], "--bounces is not an option"), (["--H", "2:3:0"], "N in START"),
                      (["--H", "1,1"], "twice"), (["--param", "eps=3"], "--param eps given twice")]:
        assert cli([*args[:-2], "-o", str(tmp_path / "b.zarr"), *bad]) == 2
        assert text in capsys.readouterr().err
    assert not os.path.exists(tmp_path / "b.zarr")


def test_cli_refused_cells_exit_1_with_a_warning(cli, tmp_path, capsys):
    """H = 0.4 leaves the ellipse no room for motion: the cell is refused, stored as NaN with status 2, and the
    command says so on stderr and exits 1 (a grid with holes is not a complete result)."""
    store = str(tmp_path / "r.zarr")
    args = ["scan", "chaotic-fraction", ELLIPSE_WALL, "--param", "eps=2", "--H", "0.4,3", "--orbits", "10",
            "--collisions", "200", "--workers", "1", "-o", store]
    assert cli(args) == 1
    captured = capsys.readouterr()
    assert captured.err.startswith("coinwall: warning: 1 of 2 cells refused") and captured.err.count("\n") == 1
    assert "note       refused cell:" in captured.out
    status = arrays(store)["cell_status"]
    assert sorted(status.ravel().tolist()) == [1, 2]


def test_workers_that_keep_dying_stop_the_scan_in_one_line(monkeypatch):
    """After its retries a cell whose workers died raises distributed's KilledWorker; the scan turns it into one
    line that names the cell and says how to resume (not an internal error).  A fake client and futures stand in
    for a cluster whose workers die (the real kill-and-retry path is test_killed_worker_does_not_lose_the_scan)."""
    import distributed
    from distributed import KilledWorker

    from coinwall.cases.scan import driver

    class DyingFuture:
        def result(self):
            raise KilledWorker("coinwall-cell", "tcp://127.0.0.1:1", 3)

        def done(self):
            return True

    class Client:
        def submit(self, *args, **kwargs):
            return DyingFuture()

    monkeypatch.setattr(distributed, "as_completed", lambda futures: iter(list(futures)))
    todo = [((0, 0), (2.0, 3.0, 0.0))]
    with pytest.raises(driver.ScanError, match=r"cell eps = 2, H = 3 died 4 times .* run the same command again"):
        driver._run(Client(), "chaotic-fraction", None, ["eps", "H"], todo, 0, {}, 3, None, None)


@pytest.mark.parametrize("options,text", [({"orbits": 10 ** 19}, r"collisions, more than the 1e\+10"),
                                          ({"collisions": 10 ** 9}, r"collisions, more than the 1e\+10")])
def test_cells_too_large_are_refused_before_any_work(options, text):
    """Found by tests/benchmarks/fuzz_cli.py: `--orbits 1e19` used to start the cluster and refuse every cell."""
    from coinwall.cases.scan.quantities import check_options
    from coinwall.forward.errors import InvalidArgument

    with pytest.raises(InvalidArgument, match=text):
        check_options("chaotic-fraction", options)


def test_a_small_phase_diagram_is_ticked_at_its_cells():
    """A 4 × 4 grid is labelled at the values computed, not at round numbers past the last one (restitution
    1.0 on a grid that ends at 0.9 read as a value that was never computed); a fine grid keeps round ticks."""
    import matplotlib.pyplot as plt
    import xarray as xr

    from coinwall.cases.scan.figures import plot_phase_diagram

    def dataset(rows):
        e, H = np.linspace(0.3, 0.9, rows), np.linspace(2.5, 6.0, 4)
        shape = (e.size, H.size)
        return xr.Dataset({"heads": (("restitution", "H"), np.full(shape, 0.5)),
                           "cell_status": (("restitution", "H"), np.ones(shape, int))},
                          coords={"restitution": e, "H": H}, attrs={"quantity": "toss", "wall": "1"})

    ax = plot_phase_diagram(dataset(4))
    np.testing.assert_allclose(ax.get_yticks(), np.linspace(0.3, 0.9, 4))
    np.testing.assert_allclose(ax.get_xticks(), np.linspace(2.5, 6.0, 4))
    assert [t.get_text() for t in ax.get_yticklabels()] == ["0.3", "0.5", "0.7", "0.9"]
    plt.close(ax.figure)
    ax = plot_phase_diagram(dataset(40))
    assert len(ax.get_yticks()) < 40
    plt.close(ax.figure)
