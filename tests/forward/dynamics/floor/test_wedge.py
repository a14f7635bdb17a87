"""The wedge limit of the toss (Lehtihet & Miller, Physica D 21, 1986): integrable at 45°, chaotic between 45°
and 90°.

References that do not share the code under test: the plain-numpy wedge billiard ``wedge_flight`` (impacts as
roots of quadratics, the reflection written out) for the compiled field kernel; the linear growth of the
separation in an integrable system (a finite-time exponent of about log(N)/N, below 3·log(N)/N) for 45°.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coinwall.forward.dynamics.floor.field import FieldTable, field_run
from coinwall.forward.dynamics.floor.wedge import (
    WEDGE_CAP,
    wedge_flight,
    wedge_lyapunov,
    wedge_slope,
    wedge_wall,
)


def test_wedge_wall_is_the_exact_v():
    for phi in (45.0, 60.0, 80.0):
        wall = wedge_wall(phi)
        x = np.linspace(-WEDGE_CAP, WEDGE_CAP, 2001)
        assert np.max(np.abs(wall(0.5 * math.pi + x) - abs(x) / math.tan(math.radians(phi)))) < 1e-14
    assert wedge_slope(45.0) == pytest.approx(1.0, rel=1e-15)


@pytest.mark.parametrize("phi", [45.0, 60.0, 75.0])
def test_kernel_on_the_wedge_is_the_numpy_wedge_impact_by_impact(phi):
    """The field kernel on the wedge wall and the closed-form wedge billiard give the same impacts."""
    k = wedge_slope(phi)
    table = FieldTable(wedge_wall(phi), g=1.0, e=1.0, settle=False)
    start = [0.5 * math.pi + 0.05 * k, 0.2 * k, 0.13, -0.07]
    flight = field_run(table, start, 15)
    assert len(flight) == 15 and flight.status == "bounces"
    ref = wedge_flight(k, 1.0, start, 15)
    for name, col in zip(("time", "theta", "eta", "v_theta", "v_eta"), ref):
        # rounding (1e-16) and the contact tolerance (1e-13) grow by at most e^(0.62·15) ≈ 1e4 in 15 impacts
        assert np.allclose(getattr(flight, name), col, rtol=0, atol=1e-8), name


def test_lyapunov_integrable_at_45_and_chaotic_between_45_and_90():
    """45°: the separation grows linearly (finite-time exponent below 3·log(N)/N); 50°–85°: a positive exponent
    at least 10 times that (the numpy wedge, 4 orbits × 3000 impacts each; 85° is the smallest, 0.135)."""
    flat = wedge_lyapunov(45.0, orbits=4, impacts=3000, method="map")
    assert flat.exponent < flat.threshold and flat.discarded == 0
    # linear growth d ∝ n gives log(N)/N: the measured value is that, not merely small
    assert 0.3 < flat.exponent / (math.log(3000) / 3000) < 3.0
    for phi in (50.0, 60.0, 70.0, 80.0, 85.0):
        chaotic = wedge_lyapunov(phi, orbits=4, impacts=3000, method="map")
        assert chaotic.exponent > 10 * chaotic.threshold, (phi, chaotic)


@pytest.mark.parametrize("phi", [45.0, 60.0, 75.0])
def test_lyapunov_kernel_agrees_with_the_numpy_wedge(phi):
    kernel = wedge_lyapunov(phi, orbits=4, impacts=3000, method="kernel", seed=1)
    plain = wedge_lyapunov(phi, orbits=4, impacts=3000, method="map", seed=2)
    if phi == 45.0:
        assert kernel.exponent < kernel.threshold
    else:
        assert abs(kernel.exponent - plain.exponent) < 4 * math.hypot(kernel.stderr, plain.stderr), (kernel, plain)


@pytest.mark.slow
@pytest.mark.parametrize("phi", [45.0, 60.0])
def test_a_body_on_the_floor_near_its_valley_is_the_wedge(phi):
    """The wall c|cos θ| of a segment body (c = 1: the dumbbell, 45°) at a level 0.01 above its valley's bottom:
    the exponent is the wedge's (within 4 combined standard errors), 0 at 45°."""
    body = wedge_lyapunov(phi, orbits=8, impacts=10_000, method="dumbbell", level=1e-2, seed=3)
    plain = wedge_lyapunov(phi, orbits=8, impacts=10_000, method="map", seed=4)
    if phi == 45.0:
        assert body.exponent < body.threshold and plain.exponent < plain.threshold
    else:
        assert abs(body.exponent - plain.exponent) < 4 * math.hypot(body.stderr, plain.stderr), (body, plain)


def test_bad_wedges_are_refused():
    from coinwall.forward.errors import InvalidArgument

    for phi in (0.0, 90.0, -3.0, float("nan"), "x"):
        with pytest.raises(InvalidArgument, match="half_angle"):
            wedge_slope(phi)
    with pytest.raises(InvalidArgument, match="method"):
        wedge_lyapunov(60.0, method="bogus")
