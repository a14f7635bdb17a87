"""
The rigid body is the billiard: a direct cross-check
====================================================

The paper's theorem: a body bouncing between flat walls *is* a point particle in the (θ, η) strip
between :math:`b(\\theta)` and :math:`H - b(\\theta+\\pi)`, reflected specularly. coinwall checks it with
a simulator that knows nothing of wall functions: :func:`coinwall.simulate_rigid_body` rotates the
ellipse itself, finds each contact of its lowest (highest) point with the floor (ceiling) and applies
the impulse with its lever arm. Started from the corresponding state
(:func:`~coinwall.forward.dynamics.body_to_billiard`), :func:`coinwall.simulate` on the billiard gives
the same collisions, to rounding.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from coinwall import Billiard, RigidBody, Wall, simulate, simulate_rigid_body
from coinwall.forward.dynamics import EllipseShape, body_to_billiard

eps, H, collisions = 0.3, 3.0, 200
shape = EllipseShape(1.0, 1.0 / math.sqrt(1.0 + eps))  # x² + (1+ε)y² = 1, κ = 1 (paper eq. 15)
rigid_body = RigidBody(shape, H=H)
start = np.array([1.5, math.pi + 0.1, math.sin(1.2), math.cos(1.2)])  # (y, ψ, ẏ, ω)
rigid = simulate_rigid_body(rigid_body, start, collisions)

table = Billiard(Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": eps}), H)
point = simulate(table, body_to_billiard(start), collisions)
print(rigid)
print(point)

billiard_states = np.stack([point.theta, point.eta, point.v_theta, point.v_eta], axis=1)
state_error = np.max(np.abs(rigid.billiard - billiard_states), axis=1)
time_error = np.abs(rigid.time - point.time)

fig, (ax_lab, ax_theta, ax_err) = plt.subplots(
    1, 3, figsize=(13, 3.9), width_ratios=[1.4, 1, 1]
)
# the lab frame: the horizontal motion decouples, so give it any drift to spread the snapshots out
a, c = 1.0, 1.0 / math.sqrt(1.0 + eps)
s = np.linspace(0.0, 2 * np.pi, 100)
for k in range(8):
    x0, y0, psi = 1.2 * rigid.time[k], rigid.y[k], rigid.psi[k]
    xs = x0 + a * np.cos(s) * np.cos(psi) - c * np.sin(s) * np.sin(psi)
    ys = y0 + a * np.cos(s) * np.sin(psi) + c * np.sin(s) * np.cos(psi)
    ax_lab.plot(xs, ys, color=plt.cm.viridis(k / 8), lw=1)
    ax_lab.plot(
        [x0, x0 + a * np.cos(psi)],
        [y0, y0 + a * np.sin(psi)],
        color=plt.cm.viridis(k / 8),
        lw=1,
    )
ax_lab.axhline(0.0, color="k", lw=2)
ax_lab.axhline(H, color="k", lw=2)
ax_lab.set_aspect("equal")
ax_lab.set(
    xlabel="x / κ (drift added for display)",
    ylabel="y / κ",
    title="the body at its first 8 collisions",
)

n = np.arange(1, collisions + 1)
ax_theta.plot(n, np.mod(point.theta, 2 * np.pi), "o", ms=5, mfc="none", label="billiard")
ax_theta.plot(
    n, np.mod(rigid.billiard[:, 0], 2 * np.pi), ".", ms=3, color="tab:red", label="rigid body"
)
ax_theta.set_yticks(np.arange(5) * np.pi / 2, ["0", "π/2", "π", "3π/2", "2π"])
ax_theta.set(
    xlabel="collision number", ylabel="contact angle θ_c (rad)", title="same collisions"
)
ax_theta.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False
)

ax_err.semilogy(n, np.maximum(state_error, 1e-17), label="largest |Δ state (θ, η, θ̇, η̇)|")
ax_err.semilogy(n, np.maximum(time_error, 1e-17), label="|Δ collision time| (κ/speed)")
ax_err.set(
    xlabel="collision number",
    ylabel="difference (dimensionless)",
    title="rigid body − billiard",
)
ax_err.legend(
    fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=1, frameon=False
)
fig.suptitle(f"Ellipse x² + (1+ε)y² = 1, ε = {eps:g}, between walls H = {H:g} κ apart")
fig.tight_layout()
