"""Record the frictionless field kernel's output on fixed launches, for the bit-for-bit test of μ = 0.

Run:  python tests/forward/dynamics/floor/record_frictionless.py

The recorded file (``data/frictionless_2385bd1.npz``) was written by this script from commit 2385bd1, the
field kernel before friction was added (Newton's restitution only).  ``test_friction.py`` runs the same
launches with μ = 0 and requires every number to be equal, bit for bit.  Re-running the script on a later
commit would only record that commit's output: the file is the record of the old code, keep it.
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"
EGG = "1 + 0.06*cos(2*t) + 0.04*sin(3*t) + 0.05*cos(t)"
TRIANGLE = "max(max(0.9*cos(t)+0.1*sin(t), -0.5*cos(t)+0.7*sin(t)), -0.4*cos(t)-0.8*sin(t))"
CORNERS = "1.5*abs(cos(t)) + 0.3*abs(sin(t))"

# (name, wall, params, g, e, H, start state [θ, η, θ̇, η̇], impacts)
RUNS = [
    ("coin-settle", COIN, {"eps": 99.0}, 1.0, 0.6, None, [0.3, 1.5, 3.7, 0.2], 400),
    ("coin-ceiling", COIN, {"eps": 99.0}, 1.0, 1.0, 3.0, [0.3, 1.5, 2.0, 1.5], 300),
    ("coin-edge", COIN, {"eps": 99.0}, 1.0, 0.5, None, [0.0, 1.5, 0.0, 0.0], 400),
    ("egg", EGG, {}, 1.0, 0.8, None, [1.0, 2.5, 4.0, 1.0], 400),
    ("triangle", TRIANGLE, {}, 3.0, 0.8, None, [2.0, 0.3 + 1.0, 0.8, 8.0], 400),
    ("corners-ceiling", CORNERS, {}, 1.0, 0.7, 5.0, [0.2, 3.0, 2.3, 0.4], 300),
]
# (name, wall, params, g, e, height, v0 grid, ω0 grid, impacts)
MAPS = [
    ("coin-map", COIN, {"eps": 99.0}, 1.0, 0.6, 1.2, (0.0, 3.0, 16), (0.0, 8.0, 16), 10_000),
    ("egg-map", EGG, {}, 1.0, 0.8, 2.5, (0.0, 3.0, 12), (0.0, 8.0, 12), 10_000),
    ("triangle-map", TRIANGLE, {}, 1.0, 0.7, 2.5, (0.0, 3.0, 10), (0.0, 8.0, 10), 10_000),
]


def launches(height, v, w, theta0):
    V, W = np.meshgrid(np.linspace(*v[:2], v[2]), np.linspace(*w[:2], w[2]))
    n = V.size
    return np.column_stack([np.full(n, theta0), np.full(n, height), W.ravel(), V.ravel()])


def main():
    from coinwall.forward import Wall
    from coinwall.forward.dynamics.floor.field import FieldTable, field_run, field_run_many

    out = {}
    for name, text, params, g, e, H, start, impacts in RUNS:
        table = FieldTable(Wall.from_expression(text, params), g=g, e=e, H=H)
        flight = field_run(table, start, impacts)
        out[f"{name}/columns"] = np.column_stack([flight.time, flight.theta, flight.eta, flight.v_theta,
                                                  flight.v_eta, flight.side.astype(float)])
        out[f"{name}/end"] = np.array([flight.valley, flight.floor_impacts])
        out[f"{name}/status"] = np.array(flight.status)
    for name, text, params, g, e, height, v, w, impacts in MAPS:
        table = FieldTable(Wall.from_expression(text, params), g=g, e=e)
        theta0 = float(table.landscape.minima[0])
        many = field_run_many(table, launches(height, v, w, theta0), impacts)
        out[f"{name}/codes"] = np.column_stack([many["status"], many["valley"], many["floor_impacts"],
                                                many["impacts"]])
        out[f"{name}/final"] = np.column_stack([many["time"], many["final"]])
        out[f"{name}/theta0"] = np.array(theta0)
    path = HERE / "data" / "frictionless_2385bd1.npz"
    np.savez_compressed(path, **out)
    print(f"wrote {path} ({len(out)} arrays)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
