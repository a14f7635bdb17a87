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

    The paper's remark is about any rigid body.  What makes the reduction work — a frictionless horizontal wall
    keeps ``L₃ = L·a`` — is measured for a general body too: the angular impulse per unit impulse of a floor
    touching the lowest point q is ``q × ẑ``, and its component along a body axis is the change of that axis's
    angular momentum (:func:`_impact_axis_torque`): zero to rounding for a body of revolution, not for a
    triaxial ellipsoid, whose orientation does not reduce to the tilt θ (no 2-D billiard; nothing is computed
    for it here).

    Returns ``error`` (largest state difference, ``inf`` if a wall differs), ``impacts`` compared,
    ``momentum_drift`` (largest change of ℓz, ℓ3 in the 3-D simulation), ``revolution_axis_torque`` and
    ``general_axis_torque`` (largest |(q × ẑ)·a|/|q| over random orientations, for the coin's body of
    revolution and for an ellipsoid with semi-axes 1, 0.7, 0.3)."""
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
    return {"error": worst, "impacts": count, "momentum_drift": drift,
            "revolution_axis_torque": _impact_axis_torque((1.0, 1.0, 0.3), 500, rng),
            "general_axis_torque": _impact_axis_torque((1.0, 0.7, 0.3), 500, rng)}


def _impact_axis_torque(semi_axes, orientations: int, rng) -> float:
    """The largest |(q × ẑ)·a| / |q| over random orientations of an ellipsoid with these semi-axes: the change
    of the angular momentum about its third axis ``a`` per unit impulse of a frictionless floor at its lowest
    point q (relative to the lever arm |q|).

    For ``x·Mx = 1`` (lab frame, ``M = R diag(1/s²) Rᵀ``) the support point in the direction −ẑ is
    ``q = −M⁻¹ẑ / sqrt(ẑ·M⁻¹ẑ)``; for a body of revolution about ``a``, q lies in the plane of a and ẑ."""
    from scipy.spatial.transform import Rotation

    inverse_shape = np.diag(np.asarray(semi_axes, dtype=float) ** 2)
    z = np.array([0.0, 0.0, 1.0])
    worst = 0.0
    for rotation in Rotation.random(orientations, random_state=rng).as_matrix():
        m_inv = rotation @ inverse_shape @ rotation.T
        q = -m_inv @ z / math.sqrt(z @ m_inv @ z)
        worst = max(worst, abs(float(np.cross(q, z) @ rotation[:, 2])) / float(np.linalg.norm(q)))
    return worst


def caught_coin_against_flips(resolution, *, samples: int) -> dict:
    """Beyond the paper: DHM's caught coin, simulated (the precessing coin of coinwall.forward.dynamics.coin3d.top),
    against the 350,757 flips of Bartoš et al. (2023), out of sample: ψ is fitted to one half of the tossers
    (odd- or even-numbered) and the coin simulated at that ψ must land on its start side as often as the other
    half's coins did, within the spread between tossers (the quasi-binomial dispersion of all 48); both ways
    round.  Comparing a ψ fitted to all flips with the same flips would test the simulation against DHM's
    formula only (``dhm_error`` does that).

    Returns ``psi``, ``psi_low``, ``psi_high`` (all flips, binomial interval, degrees), ``psi_spread_low``,
    ``psi_spread_high`` (with the spread between tossers), ``p_data``; per half ``a`` (odd-numbered tossers)
    and ``b``: ``psi_a``, ``n_a``, ``p_a`` (their share), ``p_sim_a`` (simulated at ``psi_a``), ``z_a`` (against
    the other half's share, with the spread), ``z_binomial_a`` (binomial errors only), likewise for ``b``; ``z``
    and ``z_binomial`` (the larger in size), ``samples`` and ``dhm_error`` (largest |simulation − DHM's
    formula| in standard errors)."""
    from coinwall.cases.bartos import bartos_counts, bartos_fits
    from coinwall.forward.dynamics.coin3d.caught import dhm_same_side, fit_psi, simulate_caught

    n = samples if resolution.fast else 10 * samples
    fits = bartos_fits()
    data = bartos_counts()
    same, flips = data["same"], data["flips"]
    halves = {"a": np.arange(0, same.size, 2), "b": np.arange(1, same.size, 2)}  # T01, T03, … and T02, T04, …
    shares = {h: (int(same[i].sum()), int(flips[i].sum())) for h, i in halves.items()}
    out = {"psi": fits.overall.psi, "psi_low": fits.overall.psi_low, "psi_high": fits.overall.psi_high,
           "psi_spread_low": fits.overall_overdispersed.psi_low, "psi_spread_high": fits.overall_overdispersed.psi_high,
           "p_data": fits.overall.p, "samples": n, "dhm_error": 0.0}
    for h, other in (("a", "b"), ("b", "a")):
        fit = fit_psi(*shares[h])
        p_sim, se_sim = simulate_caught(math.radians(fit.psi), n, seed=11)
        k_other, n_other = shares[other]
        p_other = k_other / n_other
        variance = p_other * (1 - p_other) * (1 / shares[h][1] + 1 / n_other)  # both halves' sampling
        out.update({f"psi_{h}": fit.psi, f"n_{h}": shares[h][1], f"p_{h}": fit.p, f"p_sim_{h}": p_sim,
                    f"z_{h}": (p_sim - p_other) / math.sqrt(se_sim ** 2 + fits.dispersion * variance),
                    f"z_binomial_{h}": (p_sim - p_other) / math.sqrt(se_sim ** 2 + variance)})
        out["dhm_error"] = max(out["dhm_error"], abs(p_sim - float(dhm_same_side(math.radians(fit.psi)))) / se_sim)
    out["z"] = max(out["z_a"], out["z_b"], key=abs)
    out["z_binomial"] = max(out["z_binomial_a"], out["z_binomial_b"], key=abs)
    return out
