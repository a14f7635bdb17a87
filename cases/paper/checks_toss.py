"""The paper's "external fields" (sec. V) and the casinos' remark (sec. III, end), computed for the toss that
lands: gravity, a floor and restitution.

Pure functions ``check(resolution, **inputs) -> dict`` of measured numbers, as in :mod:`.checks`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["casino_bounces", "external_fields"]

_COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"


def external_fields(resolution, *, eps: float, H: float, g: float, e: float) -> dict:
    """Sec. V: the equivalence extends to a field.  The rigid body (an ellipse x² + (1+ε)y² = 1, κ = 1) in the
    field g between a floor and a ceiling, with restitution e at its contact point, against the field billiard
    from each of its states: the next impact of the billiard is the body's next collision.

    Returns
    -------
    dict
        ``error``: the largest state or time difference (``inf`` if a wall differs); ``impacts`` compared.
    """
    from coinwall.forward.dynamics.billiard.rigidbody import EllipseShape, RigidBody, simulate_rigid_body
    from coinwall.forward.dynamics.floor.field import FieldTable, field_run
    from coinwall.forward.wall import Wall

    impacts = 60 if resolution.fast else 300
    body = RigidBody(EllipseShape(1.0, 1.0 / math.sqrt(1.0 + eps)), H=H, g=g, e=e)
    table = FieldTable(Wall.from_expression(_COIN, {"eps": eps}), g=g, e=e, H=H)
    rigid = simulate_rigid_body(body, [1.4, 0.3, 0.7, 2.1], impacts)
    states = rigid.billiard
    worst, count = 0.0, 0
    for i in range(len(rigid) - 1):
        one = field_run(table, states[i], 1)
        if len(one) != 1 or one.side[0] != rigid.side[i + 1]:
            worst = math.inf
            break
        got = np.array([one.theta[0], one.eta[0], one.v_theta[0], one.v_eta[0]])
        worst = max(worst, float(np.max(np.abs(got - states[i + 1]))),
                    abs(one.time[0] - (rigid.time[i + 1] - rigid.time[i])))
        count += 1
    return {"error": worst, "impacts": count}


def casino_bounces(resolution, *, eps: float, g: float, height: float, mean, sigma, restitutions) -> dict:
    """Sec. III (end): bounces randomise the outcome.  The coin (ε) launched by a hand, (v0, ω0) Gaussian about
    ``mean`` with ``sigma``, stopped at its n-th floor impact (:func:`coinwall.forward.dynamics.floor.fairness.fairness`):
    the bias of heads at n = 1 (caught on landing, Keller's coin) and after the last bounce, in units of their
    standard errors, and the bounce from which the toss is fair to 0.01 (2σ resolved), per restitution e.

    Returns
    -------
    dict
        ``caught_bias``, ``caught_sigmas`` (|bias|/σ at n = 1); per e (the last of ``restitutions`` first in
        the thresholds): ``bounced_bias``, ``bounced_sigmas`` (after the last bounce), ``fair_bounce`` (None
        if not shown), ``fair_found``, ``samples``, ``bounces``.
    """
    from coinwall.forward.dynamics.floor.fairness import fairness
    from coinwall.forward.dynamics.floor.field import FieldTable
    from coinwall.forward.wall import Wall

    samples, bounces = (20_000, 15) if resolution.fast else (100_000, 20)
    wall = Wall.from_expression(_COIN, {"eps": eps})
    es = restitutions[-1:] if resolution.fast else restitutions
    rows = [fairness(FieldTable(wall, g=g, e=e), mean, sigma, height, bounces=bounces, samples=samples, seed=1)
            for e in es]
    last = rows[-1]
    fair = last.fair_after(0.01)
    return {"caught_bias": float(last.bias[0]), "caught_sigmas": abs(float(last.bias[0])) / float(last.stderr[0]),
            "bounced_bias": float(last.bias[-1]), "bounced_stderr": float(last.stderr[-1]),
            "bounced_sigmas": abs(float(last.bias[-1])) / float(last.stderr[-1]), "fair_bounce": fair,
            "fair_found": fair is not None, "samples": samples, "bounces": bounces, "e_last": es[-1],
            "per_e": {float(e): (float(r.bias[-1]), float(r.stderr[-1]), r.fair_after(0.01)) for e, r in zip(es, rows)}}
