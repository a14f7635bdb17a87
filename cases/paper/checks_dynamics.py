"""The computation behind the paper's theorem, simulated: the rigid body and the billiard, same starts.

A pure function ``check(resolution, **inputs) -> dict`` of measured numbers, as in :mod:`.checks`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["simulated_equivalence"]


def simulated_equivalence(resolution, *, H: float, ellipse_eps: float) -> dict:
    """Sec. II (theorem): the rigid body (collisions from the rotated outline) against the billiard
    kernel, from corresponding states.

    The stick is chaotic, so it is restarted from the billiard's state after every collision (rounding
    grows ≈3× per collision); the ellipse of parameter ``ellipse_eps`` runs in one piece.

    Returns
    -------
    dict
        ``error``: largest state difference (``inf`` if a wall sequence differs); ``collisions``: how
        many collisions were compared.
    """
    from coinwall.forward import Billiard, EllipseShape, PolygonShape, RigidBody, Wall, simulate, simulate_rigid_body
    from coinwall.forward.dynamics.billiard.rigidbody import billiard_to_body, body_to_billiard

    worst, count = 0.0, 0
    runs = [(PolygonShape.stick(1.0), "abs(cos(t))", {}, 1, resolution.stick_collisions),
            (EllipseShape(1.0, 1 / math.sqrt(1 + ellipse_eps)), "sqrt((1+eps*cos(t)**2)/(1+eps))",
             {"eps": ellipse_eps}, None, resolution.ellipse_collisions)]
    for shape, text, params, restart, collisions in runs:
        table = Billiard(Wall.from_expression(text, params), H)
        body = RigidBody(shape, H=H)
        start = body_to_billiard(np.array([1.5, math.pi + 0.1, math.sin(1.2), math.cos(1.2)]))
        traj = simulate(table, start, collisions)
        bill = np.stack([traj.theta, traj.eta, traj.v_theta, traj.v_eta], axis=1)
        step = restart or collisions
        for first in range(0, collisions, step):
            origin = start if first == 0 else bill[first - 1]
            n = min(step, collisions - first)
            rigid = simulate_rigid_body(body, billiard_to_body(origin), n)
            same = len(rigid) == n and np.array_equal(rigid.side, traj.side[first:first + n])
            err = float(np.max(np.abs(rigid.billiard - bill[first:first + n]))) if same else math.inf
            worst = max(worst, err)
            count += n
    return {"error": worst, "collisions": count}
