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
    ``mean`` with ``sigma``, stopped at its n-th floor impact
    (:func:`coinwall.forward.dynamics.floor.fairness.fairness`), for every restitution e of ``restitutions``: the bias of heads at n = 1 (caught on landing, Keller's coin)
    in units of its standard error, and whether the bounces make the toss fair to 0.01 — resolved (2σ) at
    every bounce from some n to the last, and at the last :data:`FAIR_TAIL` bounces at least, not at the last
    bounce alone.

    Returns
    -------
    dict
        ``caught_bias``, ``caught_sigmas`` (|bias|/σ at n = 1, the same tosses for every e); ``fair_count`` and
        ``unfair_count`` (restitutions shown fair, and not), ``fair_list``, ``unfair_list`` (the same in words);
        ``per_e`` (e → (bias and standard error at the last
        bounce, the bounce from which it is fair or None, the share settled)); ``per_e_text`` (the same in
        words); ``samples``, ``bounces``, ``restitutions``.
    """
    from coinwall.forward.dynamics.floor.fairness import fairness
    from coinwall.forward.dynamics.floor.field import FieldTable
    from coinwall.forward.wall import Wall

    # 40,000 tosses resolve 0.01 at 2σ (σ ≈ 0.0025); fewer made the verdict of e = 0.6 depend on the seed
    samples, bounces = (40_000, 12) if resolution.fast else (100_000, 20)
    wall = Wall.from_expression(_COIN, {"eps": eps})
    rows = [fairness(FieldTable(wall, g=g, e=e), mean, sigma, height, bounces=bounces, samples=samples, seed=1)
            for e in restitutions]
    first = rows[0]
    per_e, words = {}, []
    for e, r in zip(restitutions, rows):
        fair = r.fair_after(0.01)
        if fair is not None and fair > bounces - FAIR_TAIL + 1:
            fair = None  # fair at the last bounce or two only: not shown
        per_e[float(e)] = (float(r.bias[-1]), float(r.stderr[-1]), fair, float(r.settled[-1]))
        if fair is not None:
            words.append(f"e = {e:g}: fair to 0.01 from bounce {fair} on (bias {r.bias[-1]:+.4f} ± {r.stderr[-1]:.4f} "
                         f"at bounce {bounces})")
        else:
            words.append(f"e = {e:g}: not fair, bias {r.bias[-1]:+.4f} ± {r.stderr[-1]:.4f} at bounce {bounces} "
                         f"({r.settled[-1]:.0%} settled)")
    fair_count = sum(v[2] is not None for v in per_e.values())
    listed = {True: [f"e = {e:g}" for e, v in per_e.items() if v[2] is not None],
              False: [f"e = {e:g}" for e, v in per_e.items() if v[2] is None]}
    return {"caught_bias": float(first.bias[0]), "caught_sigmas": abs(float(first.bias[0])) / float(first.stderr[0]),
            "fair_count": fair_count, "unfair_count": len(per_e) - fair_count, "per_e": per_e,
            "fair_list": ", ".join(listed[True]) or "none", "unfair_list": ", ".join(listed[False]) or "none",
            "per_e_text": "; ".join(words), "samples": samples, "bounces": bounces,
            "restitutions": ", ".join(f"{e:g}" for e in restitutions)}


#: a toss counts as made fair by its bounces only when it is fair at the last this many bounces computed
FAIR_TAIL = 3
