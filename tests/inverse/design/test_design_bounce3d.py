"""The bounce3d toss: its launch in the reduced billiard is the tumbling body's (the 3-D angular momentum of
coin3d.rigid3d.from_reduced equals I ω of the drawn angular velocity), and its outcomes are heads, edge, tails."""

import numpy as np
import pytest

from coinwall.forward.dynamics.coin3d.rigid3d import Rigid3D, from_reduced
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.revolution import coin
from coinwall.inverse.design import Bounce3D, Family, Launch3D, odds
from coinwall.inverse.design.bounce3d import reduced_states


def test_launch_is_the_tumbling_body():
    body = coin(1.0, 0.7, 0.1)
    launch = Launch3D(g=9.81, height=0.5, v0=(1.0, 0.3), spin=4.0)
    draws = launch.draw(np.random.default_rng(4), 50)
    states, lz, l3 = reduced_states(body, launch, draws)
    system = Rigid3D(body, g=9.81)
    for d, state, a, b in zip(draws, states, lz, l3):
        theta = np.arccos(1 - 2 * d[0])
        axis = np.array([np.sin(theta), 0.0, np.cos(theta)])
        omega = launch.spin * d[2:5]
        along = omega @ axis
        L = body.I1 * (omega - along * axis) + body.I3 * along * axis  # I ω of the body of revolution
        _, v, _, got = from_reduced(system, state, a, b)
        assert np.allclose(got, L, rtol=0, atol=1e-12 * np.abs(L).max())
        assert abs(state[0] - theta) < 1e-12 and abs(v[2] - (1.0 + 0.3 * d[1])) < 1e-12
        assert abs(state[1] * body.kappa1 - (body.support(theta)[0] + 0.5)) < 1e-12


def test_bounce3d_odds_and_refusals():
    fam = Family("cylinder", None, {}, {"thickness": 0.8})
    got = odds(fam, Bounce3D(e=0.5), tosses=600, seed=2)
    assert set(got) == {"heads", "edge", "tails", "undecided"}
    assert abs(got["heads"][0] + got["edge"][0] + got["tails"][0] - 1) < 1e-12
    with pytest.raises(InvalidArgument, match="heads, edge and tails only"):
        odds(fam, Bounce3D(e=0.5), names=["face@90"], tosses=100)
    with pytest.raises(InvalidArgument, match="does not apply to a planar family"):
        odds(Family("planar", "1 + 0.2*cos(2*t)", {}), Bounce3D())
