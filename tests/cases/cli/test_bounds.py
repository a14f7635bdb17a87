"""Bounds that hold: each valid-but-large request runs within its stated bound or is refused up front in one line.

The checks of a run that must fit in memory run in a subprocess under a small RLIMIT_AS (and a timeout), so nothing
here can take the machine down; a refusal before any work runs in this process.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys

import pytest

from coinwall.forward import validation

GIB = 2 ** 30


def _run(args, limit_bytes, timeout=60, cwd=None):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, limit_bytes))

    env = {k: v for k, v in os.environ.items() if k != "COINWALL_DEBUG"}
    return subprocess.run([sys.executable, "-m", "coinwall", *args], check=False, preexec_fn=limit, capture_output=True, text=True,
                          timeout=timeout, cwd=cwd, env=env)


def _one_error_line(result):
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("coinwall: error: "), result.stderr
    return lines[0]


def test_solve_points_at_the_bound_runs_under_the_limit_and_above_it_is_refused(tmp_path):
    from coinwall.inverse.support import BYTES_PER_POINT

    # the estimate covers every stage (envelope, cross-check, checks, κ_max): the largest --points the check
    # allows under a 1 GiB address-space limit runs to the end under that limit (margin: 1 / MEMORY_FRACTION)
    limit = 1 * GIB
    allowed = min(limit, validation.available_memory())
    largest = int(validation.MEMORY_FRACTION * allowed // BYTES_PER_POINT)
    ok = _run(["solve", "--points", str(largest), "-o", "body.json"], limit, timeout=120, cwd=tmp_path)
    assert ok.returncode == 0, ok.stderr
    assert (tmp_path / "body.json").exists()
    refused = _run(["solve", "--points", str(largest + 1), "-o", "other.json"], limit, cwd=tmp_path)
    line = _one_error_line(refused)
    assert f"{BYTES_PER_POINT} bytes per point" in line
    assert not (tmp_path / "other.json").exists()


def _refused_in_process(args, capsys):
    """A request refused before any work, run in this process (the refusal, not a memory limit, is tested)."""
    from coinwall.cases.cli.main import main

    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error: "), err
    return err


def test_quantum_near_the_critical_height_is_refused_with_the_height_that_fits(capsys):
    line = _refused_in_process(["quantum", "1", "--H", "2.0000001", "--levels", "4"], capsys)
    assert "degrees of freedom" in line and "H ≥ 2.00" in line


def test_quantum_estimate_counts_the_mesh_before_building_it():
    from coinwall.forward import Wall
    from coinwall.forward.quantum import make_strip
    from coinwall.forward.quantum.mesh import column_angles, column_count
    from coinwall.forward.quantum.spectrum import MAX_DOFS, check_mesh

    wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", params={"eps": 0.55})
    for H in (2.5, 2.1):
        strip = make_strip(wall, H, 0.0)
        assert column_count(strip, 8) == column_angles(strip, 8)[0].size
        assert check_mesh(strip, 4) <= MAX_DOFS
    strip = make_strip(wall, 1.9, 0.0)  # fell apart: one mesh per region
    for region in strip.regions:
        assert column_count(strip, 8, region) == column_angles(strip, 8, region)[0].size


def test_fourier_wall_is_bounded_in_harmonics(tmp_path, capsys, monkeypatch):
    from coinwall.forward import Wall
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.wallbackends import MAX_HARMONICS

    with pytest.raises(InvalidWall, match=f"more than the {MAX_HARMONICS} allowed"):
        Wall.from_fourier(2.0, [0.0] * (MAX_HARMONICS + 1))
    Wall.from_fourier(2.0, [0.0] * MAX_HARMONICS)
    (tmp_path / "f.json").write_text(json.dumps({"a0": 2.0, "cos": [0.0] * 100_000}))
    monkeypatch.chdir(tmp_path)
    assert "harmonics" in _refused_in_process(["critical", "f.json"], capsys)


def test_simulate_refuses_work_above_an_hour_and_reports_the_estimate(capsys):
    from coinwall.cases.cli.main import main

    line = _refused_in_process(["simulate", "1", "--H", "3", "--collisions", "1e12"], capsys)
    assert "days" in line and "--allow-long" in line
    assert "--allow-long" in _refused_in_process(["simulate", "1", "--H", "3", "--collisions", "1e4", "--method",
                                                  "reference", "--collisions", "1e7"], capsys)
    assert main(["simulate", "1", "--H", "3", "--collisions", "1000", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["estimated_seconds"] == pytest.approx(1000 * 1e-6)
