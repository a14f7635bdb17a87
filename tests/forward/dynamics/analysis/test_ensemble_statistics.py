"""Statistics of many orbits (``simulate --orbits N``): the mean free time against Santaló's, pieces, devices.

Reference: Santaló's mean free time π·A/P of the strip (derived in tests/benchmarks/bench_gpu.py's docstring),
from ``Billiard.area_perimeter`` (trapezoid on 20,000 angles) and, independently here, from the closed forms of
a Fourier wall b = a0 + a1 cos θ: A = 2π(H − 2 a0) (the odd harmonic cancels in b(θ) + b(θ + π)) and
P = 2·∫ √(1 + a1² sin² θ) dθ = 8·E(−a1²) (the complete elliptic integral of the second kind, scipy's ellipe).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.dynamics.analysis.orbitstats import ensemble_statistics
from coinwall.forward.dynamics.billiard.table import Billiard, random_states


def _santalo_closed_form(a0, a1, H):
    from scipy.special import ellipe

    area = 2 * math.pi * (H - 2 * a0)
    perimeter = 2 * 4 * ellipe(-a1 * a1)
    return math.pi * area / perimeter


def test_mean_free_time_is_santalos_within_its_error():
    # 600 Liouville-random orbits of 40 collisions; the window estimator is unbiased on any table, so the estimate
    # must lie within 3 standard errors of π·A/P (a 0.3 % chance of a false alarm; the seed is fixed)
    table = Billiard(Wall.from_fourier(1.0, [0.3]), 3.2)
    want = _santalo_closed_form(1.0, 0.3, 3.2)
    area, perimeter = table.area_perimeter()
    assert math.isclose(math.pi * area / perimeter, want, rel_tol=1e-9)  # the two references agree
    stats = ensemble_statistics(table, random_states(table, 600, seed=3), 40)
    assert stats.orbits == 600 and stats.collisions == 600 * 40 and not stats.notes
    assert abs(stats.mean_free_time - want) <= 3 * stats.mean_free_time_stderr
    assert 0 < stats.mean_free_time_stderr < 0.05 * want
    assert math.isclose(stats.santalo_mean_free_time, want, rel_tol=1e-9)
    assert 0.4 < stats.bottom_fraction < 0.6
    json.dumps(stats.to_dict(), allow_nan=False)


def test_pieces_and_groups_do_not_change_the_counts(monkeypatch):
    # orbits longer than a group holds are followed in pieces continued with Trajectory.resume_state: the sums are
    # those of the same pieces computed by hand (to the order of summation); against one piece of 90 the collisions
    # and the bottom count agree and the total time to 1e-6 (each resumed start is renormalised to unit speed, a
    # rounding change that the chaotic orbits amplify over the next 60 collisions: ~1e-7 here)
    from coinwall.forward.dynamics.analysis import orbitstats
    from coinwall.forward.dynamics.billiard.table import ensemble

    table = Billiard(Wall.from_fourier(1.0, [0.2, 0.05]), 3.0)
    states = random_states(table, 7, seed=5)
    whole = ensemble_statistics(table, states, 90)
    monkeypatch.setattr(orbitstats, "CHUNK", 3)  # groups of 30 collisions: 1 orbit at a time, 3 pieces each
    pieces = ensemble_statistics(table, states, 90)
    total, bottom = 0.0, 0
    for start in states:
        state, turns, clock = start, 0, 0.0
        for _ in range(3):
            (traj,) = ensemble(table, state[None, :], 30, turns=turns)
            clock += traj.time[-1]
            bottom += int(np.count_nonzero(traj.side == 0))
            state, turns = traj.resume_state()
        total += clock
    assert pieces.collisions == whole.collisions == 7 * 90
    assert pieces.bottom == bottom and math.isclose(pieces.total_time, total, rel_tol=1e-14)  # (summation order)
    assert whole.bottom == bottom and math.isclose(pieces.total_time, whole.total_time, rel_tol=1e-6)


def test_on_the_gpu_the_same_statistics():
    pytest.importorskip("numba.cuda")
    table = Billiard(Wall.from_fourier(1.0, [0.2]), 3.0)
    states = random_states(table, 4, seed=2)
    cpu = ensemble_statistics(table, states, 15)
    gpu = ensemble_statistics(table, states, 15, device="gpu")
    assert gpu.collisions == cpu.collisions and gpu.bottom == cpu.bottom
    assert np.isclose(gpu.mean_free_time, cpu.mean_free_time, rtol=1e-9)


def test_simulate_orbits_from_the_command_line(capsys):
    from coinwall.cases.cli.main import main

    assert main(["simulate", "case:coin", "--H", "3", "--collisions", "30", "--orbits", "50", "--seed", "1",
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["orbits"] == 50 and doc["collisions"] == 1500 and doc["device"] == "cpu"
    assert abs(doc["mean_free_time"] - doc["santalo_mean_free_time"]) <= 4 * doc["mean_free_time_stderr"]
    assert main(["simulate", "case:coin", "--H", "3", "--collisions", "30", "--orbits", "2", "--method",
                 "reference"]) == 2
    assert "--method reference runs one orbit" in capsys.readouterr().err
