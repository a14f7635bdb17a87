"""Side-up correlation of a body of revolution between two walls: the 3-D coin's P(n) and its decay.

The observable is the side up at each floor impact, ``s = sign(cos θ)`` (heads: the symmetry axis, the coin's
normal, points up).  For the planar coin of the paper this is its "heads" (the arrow along the coin's
diameter pointing right ⇔ the normal, the arrow turned by 90°, pointing up), so with ℓz = ℓ3 = 0 the 3-D P(n)
is the paper's planar P(n) of the meridian section (``tests/test_coin3d.py`` holds them together).

``P(n)`` is the probability that the side recurs n floor impacts later, averaged over independent orbits (each
orbit one block: the error is the spread over orbits over √orbits).  With ℓ3 ≠ 0 the top's potential favours
one side (the heads share ``h`` is not ½), so P(n) decays to ``P∞ = h² + (1 − h)²``, not to ½; the decay time τ
is fitted to ``P(n) − P∞ = A exp(−n/τ)`` (:func:`.correlation.fit_decay` applied to ``P − P∞ + ½``), with P∞
from each orbit's own heads share.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InvalidArgument
from ...validation import check_count

__all__ = ["side_correlation"]


def side_correlation(table, states, lz, l3, impacts: int, max_lag: int = 10, burn: int = 20) -> dict:
    """P(n) of the side up at floor impacts over the orbits from ``states`` (m, 4) with ``lz``, ``l3``.

    Returns a dict: ``P`` and ``P_stderr`` (lags 1 … max_lag), ``heads`` (mean heads share) and its standard
    error, ``P_inf`` (mean of the orbits' h² + (1 − h)²), ``tau`` and ``tau_stderr`` (a jackknife over groups of
    orbits; nan when a fit fails), ``orbits``,
    ``floor_impacts`` (counted in all).

    Parameters
    ----------
    table : TopTable
        A body of revolution between two walls.
    states : array_like (m, 4)
        ``(θ, η, θ̇, η̇)`` of each orbit's start (m ≥ 2).
    lz, l3 : float
        ``ℓ_z`` and ``ℓ₃`` (rad/s).
    impacts : int
        Impacts of each orbit.
    max_lag : int
        Largest lag n.
    burn : int
        Impacts dropped at the start of each orbit.

    Returns
    -------
    dict
        The keys above.

    Raises
    ------
    InvalidArgument
        For a table without a ceiling, fewer than two orbits, or an orbit with too few floor impacts.

    Examples
    --------
    >>> import numpy as np
    >>> from coinwall.forward.revolution import coin
    >>> from coinwall.forward.dynamics import TopTable, side_correlation
    >>> table = TopTable(coin(1.0, 0.2), H=6.0)
    >>> starts = np.array([[0.3, 3.0, 0.5, 0.3], [1.0, 3.0, -0.5, 0.4]])
    >>> result = side_correlation(table, starts, 0.0, 0.0, 400, max_lag=3, burn=5)
    >>> result["P"].shape, result["orbits"]
    ((3,), 2)
    """
    from ..analysis.correlation import fit_decay
    from .top import TopTable, top_run

    if not isinstance(table, TopTable) or table.H is None:
        raise InvalidArgument("`table` must be a TopTable with a ceiling (two walls)")
    impacts = check_count("impacts", impacts, maximum=100_000_000)
    max_lag = check_count("max_lag", max_lag)
    arr = np.asarray(states, dtype=float).reshape(-1, 4)
    if arr.shape[0] < 2:
        raise InvalidArgument("`states` must hold at least two orbits (the error is their spread)")
    agree, heads, plateau, counted = [], [], [], 0
    for state in arr:
        flight = top_run(table, state, lz, l3, impacts)
        side = np.sign(np.cos(flight.theta[flight.wall == 0][burn:]))
        if side.size <= 10 * max_lag:
            raise InvalidArgument(f"an orbit had only {side.size} floor impacts after the burn-in: give more "
                                  "`impacts`")
        counted += side.size
        agree.append([np.mean(side[n:] == side[:-n]) for n in range(1, max_lag + 1)])
        h = float(np.mean(side > 0))
        heads.append(h)
        plateau.append(h * h + (1 - h) * (1 - h))
    agree = np.array(agree)
    m = agree.shape[0]
    P = agree.mean(axis=0)
    se = agree.std(axis=0, ddof=1) / math.sqrt(m)
    p_inf = float(np.mean(plateau))
    lags = np.arange(1, max_lag + 1)
    sigma = np.maximum(se, 1e-12)
    tau = fit_decay(P - p_inf + 0.5, sigma, lags)[1]
    # the error of τ: a delete-one-group jackknife over (up to) 10 groups of orbits, as in .correlation
    groups = np.array_split(np.arange(m), min(10, m))
    taus = []
    for g in groups:
        keep = np.setdiff1d(np.arange(m), g)
        taus.append(fit_decay(agree[keep].mean(axis=0) - np.mean(np.array(plateau)[keep]) + 0.5, sigma, lags)[1])
    taus = np.array(taus)
    k = len(groups)
    tau_se = math.nan
    if np.all(np.isfinite(taus)):
        tau_se = float(math.sqrt((k - 1) / k * np.sum((taus - taus.mean()) ** 2)))
    return {"P": P, "P_stderr": se, "heads": float(np.mean(heads)),
            "heads_stderr": float(np.std(heads, ddof=1) / math.sqrt(m)), "P_inf": p_inf, "tau": tau,
            "tau_stderr": tau_se, "orbits": m, "floor_impacts": counted}
