"""The coin in three dimensions: the paper's closing conjecture and the caught coin against real flips.

Pure functions ``check(resolution, **inputs) -> dict`` of measured numbers, as in :mod:`.checks`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["caught_coin_against_flips", "three_d_billiard"]


def three_d_billiard(resolution, *, impacts: int, restitution: float) -> dict:
    """Sec. V: "the motion of a rigid body in three dimensions ... a new type of billiard motion".  For a body
    of revolution it is the (θ, η) billiard with the top's potential (coinwall.forward.dynamics.coin3d.top): the
    direct 3-D simulation (quaternions, impulse at the 3-D contact point) is restarted from every impact of
    the reduced billiard and must reach the next one in the same state; a coin on a floor with gravity and
    restitution, and an ellipsoid between two walls.

    Returns ``error`` (largest state difference, ``inf`` if a wall differs), ``impacts`` compared, and
    ``momentum_drift`` (largest change of ℓz, ℓ3 in the 3-D simulation)."""
    from coinwall.forward.dynamics.coin3d.rigid3d import Rigid3D, from_reduced, simulate_3d
    from coinwall.forward.dynamics.coin3d.top import TopTable, top_run
    from coinwall.forward.revolution import coin, ellipsoid

    n = impacts if resolution.fast else 4 * impacts
    worst, drift, count = 0.0, 0.0, 0
    rng = np.random.default_rng(5)
    for body, g, H, lz, l3 in ((coin(1.0, 0.3), 1.0, None, 0.4, 0.9), (ellipsoid(1.0, 0.4), 0.0, 6.0, 0.9, 0.9)):
        k1 = body.kappa1
        table = TopTable(body, g=g, e=restitution, H=H)
        system = Rigid3D(body, g=g * k1, e=restitution, H=None if H is None else H * k1)
        start = [1.0, 3.0, 0.7, 0.3]
        flight = top_run(table, start, lz, l3, n)
        states = np.vstack([start, flight.states()])
        for i in range(flight.impacts):
            traj = simulate_3d(system, from_reduced(system, states[i], lz, l3, spin_angle=rng.uniform(0, 6),
                                                    azimuth=rng.uniform(0, 6)), 1)
            got = traj.reduced()[0]
            if traj.wall[0] != flight.wall[i]:
                return {"error": math.inf, "impacts": count, "momentum_drift": math.inf}
            worst = max(worst, float(np.max(np.abs(got[:4] - states[i + 1]))))
            drift = max(drift, float(abs(got[4] - lz)), float(abs(got[5] - l3)))
            count += 1
    return {"error": worst, "impacts": count, "momentum_drift": drift}


def caught_coin_against_flips(resolution, *, samples: int) -> dict:
    """Beyond the paper: DHM's caught coin, simulated (the precessing coin of coinwall.forward.dynamics.coin3d.top) at
    the ψ fitted to the 350,757 flips of Bartoš et al. (2023); the simulated share must match the data's.

    Returns ``psi`` (degrees, fitted), ``p_data``, ``p_sim``, ``z`` (difference over the combined standard
    error) and ``dhm_error`` (|simulation − DHM's formula| in standard errors)."""
    from coinwall.cases.bartos import bartos_fits
    from coinwall.forward.dynamics.coin3d.caught import dhm_same_side, simulate_caught

    n = samples if resolution.fast else 10 * samples
    fit = bartos_fits().overall
    p, se = simulate_caught(math.radians(fit.psi), n, seed=11)
    se_data = math.sqrt(fit.p * (1 - fit.p) / fit.flips)
    return {"psi": fit.psi, "psi_low": fit.psi_low, "psi_high": fit.psi_high, "p_data": fit.p, "p_sim": p,
            "samples": n, "z": (p - fit.p) / math.hypot(se, se_data),
            "dhm_error": abs(p - float(dhm_same_side(math.radians(fit.psi)))) / se}
