"""Beyond the paper: bodies designed for their odds (:mod:`coinwall.inverse.design`) against the literature's
closed forms and statements.

Pure functions ``check(resolution, **inputs) -> dict`` of measured numbers, as in :mod:`.checks`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["bounce_nickel", "bounce_nickel_friction", "drop_cylinder", "drop_rectangle", "flip_cylinder"]

_RECT = "a*abs(cos(t)) + c*abs(sin(t))"  # a 2a × 2c rectangle, edges (length 2c) at θ = 0, π


def drop_rectangle(resolution, *, ratios) -> dict:
    """The drop model of a planar d × h rectangle against P(edge) = (2/π) atan(h/d), and the design of
    P(edge) = 1/3 against h/d = 1/√3.

    Returns ``error`` (largest |P − closed form| over ``ratios``), ``design`` (h/d found) and
    ``design_error``."""
    from coinwall.forward.wall import Wall
    from coinwall.inverse.design import Drop, Family, design

    worst = 0.0
    for ratio in ratios:
        wall = Wall.from_expression(_RECT, {"a": 1.0, "c": ratio})
        worst = max(worst, abs(Drop().odds("planar", wall, ["edge"])["edge"] - 2 / math.pi * math.atan(ratio)))
    found = design(Family("planar", _RECT, {"c": (0.05, 3.0)}, {"a": 1.0}), {"edge": 1 / 3}, Drop())
    return {"error": worst, "design": float(found.x[0]), "design_error": abs(found.x[0] - 1 / math.sqrt(3)),
            "shown": ", ".join(f"{r:.4g}" for r in ratios)}


def drop_cylinder(resolution, *, ratios) -> dict:
    """The drop model of a cylinder (radius r = 1, thickness h = 2r × ratio) against the solid angle of its rim,
    P(edge) = (h/2)/√(r² + h²/4), and the design of P(edge) = 1/3 against h/(2r) = 1/(2√2)."""
    from coinwall.forward.revolution import coin
    from coinwall.inverse.design import Drop, Family, design

    worst = 0.0
    for ratio in ratios:
        h = 2.0 * ratio
        got = Drop().odds("cylinder", coin(1.0, h), ["edge"])["edge"]
        worst = max(worst, abs(got - (h / 2) / math.sqrt(1 + h * h / 4)))
    found = design(Family("cylinder", None, {"thickness": (0.05, 3.0)}), {"edge": 1 / 3}, Drop())
    ratio = float(found.x[0]) / 2
    return {"error": worst, "design": ratio, "design_error": abs(ratio - 1 / (2 * math.sqrt(2))),
            "shown": ", ".join(f"{r:.4g}" for r in ratios)}


def flip_cylinder(resolution) -> dict:
    """The vigorous flip of a cylinder about a diameter (its meridian section turning with a uniform phase): the
    thickness/diameter for P(edge) = 1/3 against Yong & Mahadevan's 1/√3; and the flip of an irregular
    quadrilateral against the drop, where the flip model differs (the faces beside the farthest corner)."""
    from coinwall.forward.wall import Wall
    from coinwall.inverse.design import Drop, Family, Flip, design

    found = design(Family("cylinder", None, {"thickness": (0.05, 3.0)}), {"edge": 1 / 3}, Flip())
    ratio = float(found.x[0]) / 2
    quad = Wall.from_expression("max(max(1.0*cos(t), 1.3*cos(t-1.4)), max(0.8*cos(t-3.1), 1.1*cos(t-4.6)))")
    flip = Flip().valley_odds("planar", quad)[1]
    drop = Drop().valley_odds("planar", quad)[1]
    return {"design": ratio, "design_error": abs(ratio - 1 / math.sqrt(3)),
            "irregular_difference": float(np.max(np.abs(flip - drop)))}


def bounce_nickel(resolution, *, diameter: float, thickness: float, restitutions, tosses: int) -> dict:
    """A US nickel (diameter, thickness in mm) flipped about a diameter and bounced on a frictionless floor:
    the planar bounce toss of its meridian section scaled by the coin's transverse radius of gyration κ₁ (the
    3-D coin without spin, coinwall.forward.dynamics.coin3d.rest), launch :class:`coinwall.inverse.design.Launch`'s
    defaults, per restitution; against the drop model's P(edge) and Murray & Teare's extrapolated 1/6000.

    Returns ``p_edge`` (the largest over ``restitutions``), ``p_edge_min``, ``per_e`` (e -> (p, standard error)),
    ``drop`` (the drop model's P(edge)), ``suppression`` (drop / largest p_edge), ``ratio_to_6000``
    (largest p_edge × 6000) and ``shown`` (per e, for the report)."""
    from coinwall.forward.revolution import coin
    from coinwall.inverse.design import Bounce, Drop, Family, odds

    r, h = diameter / 2, thickness
    body = coin(r, h)
    k1 = body.kappa1
    section = Family("planar", _RECT, {}, {"a": r / k1, "c": h / 2 / k1})
    n = tosses if not resolution.fast else tosses // 4
    es = restitutions if not resolution.fast else restitutions[1:2]
    per_e = {}
    for e in es:
        got = odds(section, Bounce(e=e), names=["edge"], tosses=n, seed=1)
        p, half = got["edge"]
        per_e[float(e)] = (p, half / 1.959963984540054)
    drop = Drop().odds("cylinder", body, ["edge"])["edge"]
    top = max(p for p, _ in per_e.values())
    return {"p_edge": top, "p_edge_min": min(p for p, _ in per_e.values()), "per_e": per_e, "drop": drop,
            "suppression": drop / top, "ratio_to_6000": top * 6000, "tosses": n,
            "shown": "; ".join(f"e = {e:g}: {p:.2g} ± {s:.1g}" for e, (p, s) in per_e.items())}


def bounce_nickel_friction(resolution, *, diameter: float, thickness: float, e: float, frictions,
                           tosses: int) -> dict:
    """The nickel of :func:`bounce_nickel` (the same section, scaling and launch) bounced on a floor with Coulomb
    friction μ (restitution ``e``), per μ: a coin that comes to rest on its rim stays there, one rocking on it
    is stopped or tipped by friction instead of sliding; against the drop model and Murray & Teare's 1/6000.

    Returns ``p_edge`` (the largest over ``frictions``), ``per_mu`` (μ -> (p, standard error)), ``undecided``
    (the largest undecided share), ``p_free`` and ``undecided_free`` (the same launches on a frictionless floor),
    ``drop``, ``suppression`` (drop / largest p_edge), ``ratio_to_6000`` and ``shown``."""
    from coinwall.forward.revolution import coin
    from coinwall.inverse.design import Bounce, Drop, Family, odds

    r, h = diameter / 2, thickness
    body = coin(r, h)
    k1 = body.kappa1
    section = Family("planar", _RECT, {}, {"a": r / k1, "c": h / 2 / k1})
    n = tosses if not resolution.fast else tosses // 4
    mus = frictions if not resolution.fast else frictions[1:2]
    per_mu, undecided = {}, 0.0
    for mu in mus:
        got = odds(section, Bounce(e=e, mu=mu), names=["edge"], tosses=n, seed=1)
        p, half = got["edge"]
        per_mu[float(mu)] = (p, half / 1.959963984540054)
        undecided = max(undecided, got["undecided"][0])
    free = odds(section, Bounce(e=e), names=["edge"], tosses=n, seed=1)
    drop = Drop().odds("cylinder", body, ["edge"])["edge"]
    top = max(p for p, _ in per_mu.values())
    return {"p_edge": top, "per_mu": per_mu, "undecided": undecided, "drop": drop, "suppression": drop / top,
            "ratio_to_6000": top * 6000, "tosses": n, "p_free": free["edge"][0],
            "undecided_free": free["undecided"][0],
            "shown": "; ".join(f"μ = {mu:g}: {p:.2g} ± {s:.1g}" for mu, (p, s) in per_mu.items())}
