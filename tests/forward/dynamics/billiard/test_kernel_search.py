"""The shared certified search: the curving-away runs, the skip after a reflection and the split windows.

References that do not share the code under test: a brute-force walk over the cells for the runs, and the
plain-numpy twins (``method="reference"``) for every contact the compiled search finds after skipping.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.angles import TWO_PI
from coinwall.forward.dynamics.billiard.cellbounds import cell_bounds, concave_runs
from coinwall.forward.dynamics.billiard.table import Billiard, simulate
from coinwall.forward.dynamics.floor.field import FieldTable, field_run

COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"
CORNERS = "1.5*abs(cos(t)) + 0.3*abs(sin(t))"


def _brute_runs(bd):
    """The runs by walking cell by cell from every cell (quadratic time, no shared code with concave_runs)."""
    edges, cmax = bd["edges"], bd["cmax"]
    m = edges.size - 1
    kink = [not (math.isnan(bd["slope_left"][i]) and math.isnan(bd["slope_right"][i])) for i in range(m + 1)]
    kink[0] = kink[m] = kink[0] or kink[m]
    rows = []
    for j in range(m):
        fwd, k = 0, j  # cells added going forward
        while cmax[j] <= 0 and fwd < m - 2 and cmax[(k + 1) % m] <= 0 and not kink[(k + 1) % m]:
            k += 1
            fwd += 1
        end_angle = edges[k % m + 1] + TWO_PI * (k // m)
        bwd, k = 0, j
        while cmax[j] <= 0 and bwd < m - 2 and cmax[(k - 1) % m] <= 0 and not kink[k % m]:
            k -= 1
            bwd += 1
        begin_angle = edges[k % m] - (TWO_PI if k < 0 else 0.0)
        rows.append((end_angle, (j + fwd + 1) % m, begin_angle, (j - bwd - 1) % m))
    return np.array(rows)


@pytest.mark.parametrize("expression", [COIN, CORNERS, "1 + 0.3*cos(t) + 0.05*sin(3*t)"])
def test_concave_runs_match_a_brute_force_walk(expression):
    wall = Wall.from_expression(expression, {"eps": 99.0} if "eps" in expression else None)
    bd = cell_bounds(wall)
    got = concave_runs(bd["edges"], bd["cmax"], bd["slope_left"], bd["slope_right"])
    want = _brute_runs(bd)
    assert np.array_equal(got[:, [1, 3]], want[:, [1, 3]])
    np.testing.assert_allclose(got[:, [0, 2]], want[:, [0, 2]], rtol=0, atol=1e-12)
    concave = bd["cmax"] <= 0
    m = concave.size
    lengths = (got[:, 1].astype(int) - np.arange(m)) % m  # cells in the forward run from each cell
    assert concave.any() and lengths.max() > 1 and lengths.min() < m - 1  # runs to skip, and ends (cells, kinks)
    # a run never contains a cell whose b'' may be positive: the skip's premise, on the wall's own b''
    theta = np.linspace(0, TWO_PI, 20001)
    d2 = wall.derivatives(theta)[2]
    cell = np.searchsorted(bd["edges"], theta, side="right") - 1
    inside = (cell < concave.size) & (theta > bd["edges"][np.minimum(cell, concave.size - 1)] + 1e-9)
    assert np.all(d2[inside & concave[np.minimum(cell, concave.size - 1)]] <= 1e-12)


def _leaving_states(wall, upper, angles=9, signs=(1.0, -1.0), lifts=(0.02, 0.4), H=3.0):
    # states on a wall leaving it at a small angle to its tangent, from points spread over the period (the runs
    # across the seam at θ = 0 included), both directions of rotation
    out = []
    for th in np.linspace(-0.3, 2 * math.pi - 0.3, angles):
        phi = th + (math.pi if upper else 0.0)
        b, d1, _ = (float(x[0]) for x in wall.derivatives(np.array([phi])))
        for sign in signs:
            for lift in lifts:
                if upper:  # ceiling η = H − b(θ + π), its slope −b'(θ + π); leaving it means moving down
                    v = np.array([sign, -sign * d1 - lift])
                    eta = H - b
                else:
                    v = np.array([sign, sign * d1 + lift])
                    eta = b
                v /= np.hypot(*v)
                out.append([th % TWO_PI, eta, v[0], v[1]])
    return out


def _check_next_contacts(upper, **kwargs):
    wall = Wall.from_expression(COIN, {"eps": 99.0})
    table = Billiard(wall, 3.0)
    for state in _leaving_states(wall, upper, **kwargs):
        kern = simulate(table, state, 1)
        ref = simulate(table, state, 1, method="reference")
        assert kern.side[0] == ref.side[0], state
        assert abs(kern.time[0] - ref.time[0]) < 1e-9 * max(1.0, ref.time[0]), state
        assert abs(kern.theta[0] - ref.theta[0]) < 1e-9, state


@pytest.mark.parametrize("upper", [False, True])
def test_billiard_next_contact_after_the_skip_is_the_references(upper):
    """From states leaving the coin's arches (where the walk skips the curving-away run at once) the kernel's
    next collision is the reference stepper's: the same wall or the other, the same time and angle."""
    _check_next_contacts(upper)


@pytest.mark.slow
@pytest.mark.parametrize("upper", [False, True])
def test_billiard_next_contact_after_the_skip_is_the_references_dense(upper):
    """The same from 23 angles and grazing departures (1e-3 off the tangent: long, shallow flights)."""
    _check_next_contacts(upper, angles=23, lifts=(1e-3, 0.05, 0.4))


@pytest.mark.parametrize("g, H, start", [
    (1.0, 3.0, [0.3, 1.5, 2.0, 1.5]),     # the toss set-up of bench_toss: above the floor's band between bounces
    (1.0, None, [0.3, 1.5, 1.1, 2.5]),    # floor only: high bounces, each flight leaves the band and comes back
    (0.5, 3.0, [2.0, 1.2, -2.7, 0.9]),    # ceiling hits under gravity (the skip applies there: Q < 0)
])
def test_field_kernel_with_split_windows_matches_reference(g, H, start):
    wall = Wall.from_expression(COIN, {"eps": 99.0})
    table = FieldTable(wall, g=g, e=1.0, H=H)
    kernel = field_run(table, start, 12)
    assert len(kernel) == 12
    # step by step (chaos amplifies the contact tolerance ~5-10x an impact, so whole orbits agree only briefly):
    # the reference twin restarts from every impact of the kernel and must find the kernel's next impact
    for k in range(11):
        state = [kernel.theta[k], kernel.eta[k], kernel.v_theta[k], kernel.v_eta[k]]
        ref = field_run(table, state, 1, method="reference")
        assert ref.side[0] == kernel.side[k + 1], k
        assert abs(ref.time[0] - (kernel.time[k + 1] - kernel.time[k])) < 1e-9, k
        for name in ("theta", "eta", "v_theta", "v_eta"):
            assert abs(getattr(ref, name)[0] - getattr(kernel, name)[k + 1]) < 1e-9, (k, name)
