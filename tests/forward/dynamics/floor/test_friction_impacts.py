"""Impacts with Coulomb friction: closed forms by hand, energy over random bodies, and the rigid body.

The field kernel's impact (``_friction_impact``: Stronge's energetic restitution, Routh's integration in
closed form, billiard units M = κ = 1) is held to

* impulses derived here by hand for a uniform rod and a dumbbell striking the floor at an angle, in lab units
  (mass m, half-length L), for sliding throughout, sticking throughout, slip then stick, and slip reversal;
* the energy law: over random bodies and states, μ ∈ [0, 2], e ∈ (0, 1], no impact creates energy;
* the direct rigid-body simulation (``rigidbody.py``: its own contact point, its own lab-frame event loop over
  the impulse), impact by impact along whole tosses.

The rod and the dumbbell (the closed forms).  A body of mass m and moment of inertia I = m κ² touches the floor
at r = (r_x, r_y) from its centre of mass.  An impulse P = (P_t, P_n) there changes the contact point's
velocity u = (ẋ − ω r_y, ẏ + ω r_x) by W P with

    W = (1/m) 1 + (1/I) [[r_y², −r_x r_y], [−r_x r_y, r_x²]].

For a rod of half-length L (κ² = L²/3) whose lower end is at the angle α below the horizontal, r = (L cos α,
−L sin α) and m W = [[1 + 3 sin²α, 3 sin α cos α], [3 sin α cos α, 1 + 3 cos²α]]; for a dumbbell (two masses
m/2 at ±L, κ = L) the 3 is a 1.  With the normal impulse as the clock, u is linear in P_n on each phase:

1. *Sliding throughout* (σ = sign u_t⁻ kept to the end): dP_t = −μσ dP_n, u_n rises at the rate
   a = W_nn − μσ W_tn, compression ends at P_c = −u_n⁻/a and Stronge's e (restitution work = e² × compression
   work, both ½ a x²) gives P_n = (1 + e) P_c = −(1 + e) u_n⁻/(W_nn − μσW_tn), P_t = −μσ P_n.
2. *Sticking throughout* (u_t⁻ = 0, |W_tn| ≤ μ W_tt): u_t stays 0, dP_t = −(W_tn/W_tt) dP_n, u_n rises at
   a_s = W_nn − W_tn²/W_tt: P_n = −(1 + e) u_n⁻/a_s, P_t = −(W_tn/W_tt) P_n, u⁺ = (0, −e u_n⁻).
3. *Slip, then stick* (the slip stops during compression, at P₁ = −u_t⁻/(W_tn − μσW_tt), where
   u_n = u₁ = u_n⁻ + a P₁ < 0): compression ends at P_c = P₁ − u₁/a_s, its work is
   w_c = ½ P₁ (u_n⁻ + u₁) + ½ u₁ (P_c − P₁); restitution sticks throughout: ½ a_s x² = e² |w_c|, so
   P_n = P_c + e √(2|w_c|/a_s), P_t = −μσ P₁ − (W_tn/W_tt)(P_n − P₁).
4. *Slip reversal* (|W_tn| > μ W_tt: the slip stops at P₁ and starts back with σ' = sign W_tn): as 3. with
   a_s → a' = W_nn − μσ'W_tn and W_tn/W_tt → μσ'.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.dynamics.floor.field import FieldTable
from coinwall.forward.dynamics.floor.fieldkernel import _kernel

COIN = "sqrt((1+eps*cos(t)**2)/(1+eps))"


@pytest.fixture(scope="module")
def impact():
    """The compiled kernel's impact function (any wall's module has it; the coin's is compiled anyway)."""
    table = FieldTable(Wall.from_expression(COIN, {"eps": 99.0}), g=1.0, e=0.5, mu=0.3)
    return _kernel(table).module._friction_impact


def _lab_W(m, kappa2, rx, ry):
    return np.array([[1 / m + ry * ry / (m * kappa2), -rx * ry / (m * kappa2)],
                     [-rx * ry / (m * kappa2), 1 / m + rx * rx / (m * kappa2)]])


def _hand_impulse(W, u, mu, e):
    """The four closed forms of the module docstring (lab units), with the case each applies to."""
    ut, un = u
    wtt, wtn, wnn = W[0, 0], W[0, 1], W[1, 1]
    if ut == 0.0:
        assert abs(wtn) <= mu * wtt
        a = wnn - wtn * wtn / wtt
        pn = -(1 + e) * un / a
        return np.array([-(wtn / wtt) * pn, pn]), "stick"
    sg = math.copysign(1.0, ut)
    a = wnn - mu * sg * wtn
    slope_t = wtn - mu * sg * wtt
    p1 = -ut / slope_t if sg * slope_t < 0 else math.inf
    pn = -(1 + e) * un / a
    if pn <= p1:
        return np.array([-mu * sg * pn, pn]), "slide"
    u1 = un + a * p1
    assert u1 < 0, "the slip stops after compression: not one of the cases by hand"
    if abs(wtn) <= mu * wtt:
        k2, a2, case = -wtn / wtt, wnn - wtn * wtn / wtt, "slip-stick"
    else:
        s2 = math.copysign(1.0, wtn)
        k2, a2, case = -mu * s2, wnn - mu * s2 * wtn, "reversal"
    pc = p1 - u1 / a2
    wc = 0.5 * p1 * (un + u1) + 0.5 * u1 * (pc - p1)
    pn = pc + e * math.sqrt(2 * abs(wc) / a2)
    return np.array([-mu * sg * p1 + k2 * (pn - p1), pn]), case


# (body, factor of the 3 in W: rod 3, dumbbell 1) × (α, ẋ, ẏ, ω, μ, e, expected case)
CASES = [
    ("rod", 0.6, 0.9, -2.0, 0.4, 0.3, 0.7, "slide"),
    ("rod", 0.6, None, -2.0, 0.4, 1.5, 0.7, "stick"),     # ẋ chosen so that u_t⁻ = 0
    ("rod", 0.9, 0.35, -2.0, 0.1, 0.8, 0.5, "slip-stick"),
    ("dumbbell", 0.7, -2.5, -1.5, 0.3, 0.25, 0.9, "slide"),
    ("dumbbell", 0.7, None, -1.5, 0.3, 0.6, 0.4, "stick"),
    ("dumbbell", 0.6, -0.35, -1.5, 0.3, 0.2, 0.6, "reversal"),
]


@pytest.mark.parametrize("body, alpha, xdot, ydot, omega, mu, e, case", CASES)
def test_rod_and_dumbbell_impacts_by_hand(impact, body, alpha, xdot, ydot, omega, mu, e, case):
    """The kernel's impulse (billiard units) is the closed form by hand (lab units, m = 0.37, L = 0.8) to 1e-12,
    and the case by hand is the one named (so every phase structure is exercised)."""
    m, L = 0.37, 0.8
    kappa2 = L * L / 3 if body == "rod" else L * L
    kappa = math.sqrt(kappa2)
    rx, ry = L * math.cos(alpha), -L * math.sin(alpha)
    if xdot is None:
        xdot = omega * ry  # u_t = ẋ − ω r_y = 0
    W = _lab_W(m, kappa2, rx, ry)
    u = (xdot - omega * ry, ydot + omega * rx)
    P, found = _hand_impulse(W, u, mu, e)
    assert found == case
    # the same impact in the billiard's units: s = r_x/κ, η = −r_y/κ, θ̇ = −ω, η̇ = ẏ/κ, ξ̇ = ẋ/κ; P/(m κ)
    vt, ve, vx, pn = impact(-omega, ydot / kappa, xdot / kappa, rx / kappa, -ry / kappa, e, mu)
    assert pn == pytest.approx(P[1] / (m * kappa), rel=1e-12)
    assert vx * kappa == pytest.approx(xdot + P[0] / m, rel=1e-12, abs=1e-12)
    assert ve * kappa == pytest.approx(ydot + P[1] / m, rel=1e-12)
    assert -vt == pytest.approx(omega + (rx * P[1] - ry * P[0]) / (m * kappa2), rel=1e-12, abs=1e-12)
    after = np.array(u) + W @ P
    if case == "stick":
        assert after[0] == pytest.approx(0.0, abs=1e-12) and after[1] == pytest.approx(-e * u[1], rel=1e-12)
    energy = [0.5 * m * (x * x + y * y) + 0.5 * m * kappa2 * w * w for x, y, w in
              ((xdot, ydot, omega), (xdot + P[0] / m, ydot + P[1] / m, omega + (rx * P[1] - ry * P[0]) / (m * kappa2)))]
    assert energy[1] <= energy[0]


def test_frictionless_limit_is_newton(impact):
    """μ = 0: Stronge's energetic coefficient is Newton's; the impulse is the field kernel's frictionless one."""
    for s, h, vt, ve, vx, e in [(0.3, 1.2, 1.5, -2.0, 0.4, 0.6), (-1.1, 0.4, -0.2, -0.7, 3.0, 1.0)]:
        nt, ne, nx, _ = impact(vt, ve, vx, s, h, e, 0.0)
        f = (1 + e) * (ve - s * vt) / (1 + s * s)
        assert (nt, ne, nx) == pytest.approx((vt + f * s, ve - f, vx), rel=1e-14, abs=1e-15)


def test_no_impact_creates_energy(impact):
    """A property over random bodies and states (numpy draws, seeded): contact points r = (s, −h) of convex
    bodies (h > 0 the centre's height, any lever s), approaching velocities, μ ∈ [0, 2], e ∈ (0, 1]: the energy
    ½(θ̇² + η̇² + ξ̇²) after the impact is never above the energy before (to rounding, 1e-13 relative), and the
    contact point leaves the floor (u_n⁺ ≥ 0) and never slides faster than it came (|u_t⁺| ≤ |u_t⁻| + rounding
    when it does not reverse)."""
    rng = np.random.default_rng(34)
    worst = -math.inf
    for _ in range(20000):
        s = rng.normal(0, 2.0)
        h = rng.uniform(0.05, 3.0)
        vt, vx = rng.normal(0, 3.0, 2)
        ve = s * vt - rng.exponential(2.0)          # u_n < 0: approaching
        mu = rng.uniform(0, 2.0) if rng.random() < 0.9 else 0.0
        e = rng.uniform(0, 1.0) if rng.random() < 0.9 else 1.0
        e = max(e, 1e-3)
        before = 0.5 * (vt * vt + ve * ve + vx * vx)
        nt, ne, nx, pn = impact(vt, ve, vx, s, h, e, mu)
        after = 0.5 * (nt * nt + ne * ne + nx * nx)
        worst = max(worst, (after - before) / before)
        assert after <= before * (1 + 1e-13), (s, h, vt, ve, vx, mu, e)
        assert ne - s * nt >= -1e-12 * (abs(ve) + abs(s * vt))
        assert pn > 0
    assert worst < 1e-13
