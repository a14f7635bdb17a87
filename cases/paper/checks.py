"""The computations behind the paper's claims, sections II and IV: collisions and the ellipse.

Every check is a pure function ``check(resolution, **inputs) -> dict`` returning *measured numbers*
under names the claim registry (:mod:`.claims`) refers to.  No prose and no verdicts live here: what
the paper says, the thresholds and the expected verdicts are in the registry.  The Appendix checks are
in :mod:`.checks_appendix`, the simulated equivalence in :mod:`.checks_dynamics`.

Derivations used below:

* Stick impulse (eq. 2–4).  With ``Mκ δη̇ = J`` and ``Mκ² δθ̇ = L sin θ J``,
  energy conservation ``(θ̇ + δθ̇)² + (η̇ + δη̇)² = θ̇² + η̇²`` gives
  ``δη̇ = −2(η̇ + (L/κ) θ̇ sin θ)/(1 + (L/κ)² sin²θ)`` (eq. 4) and
  ``δθ̇ = (L/κ) sin θ δη̇`` — eq. 3 prints ``L/R`` for ``L/κ``.  The lever arm
  ``L sin θ`` is that of the lower end for cos θ > 0; for cos θ < 0 the other
  end touches and the sign flips (the paper does not say).
* General body (eq. 13–14).  The rigid-body impulse is computed from the lab
  geometry: contact point ``c`` (body point with outward normal along the
  downward wall normal), horizontal lever arm ``d``; ``J`` from energy
  conservation with ``I = Mκ²``.  It is compared with the specular reflection
  of (θ̇, η̇) at the wall ``b(θ)`` — the paper's theorem.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import format_number, safe_repr

__all__ = ["Resolution", "Measured", "fit_exponent", "collision_impulses", "ellipse_wall_from_body",
           "contact_angle", "ellipse_limits", "quadratic_22", "eq23_sign", "large_offset", "extrema_coincide",
           "two_extremum_wall", "half_angle_wall"]


@dataclass(frozen=True)
class Resolution:
    """How finely a run resolves what it checks (``fast`` is what the test suite runs).

    Attributes
    ----------
    fast : bool
        The fast mode's fewer nodes and collisions.
    points : int
        Nodes of every solved body (checks and figures).
    stick_collisions, ellipse_collisions : int
        Collisions of the simulated stick and ellipse (:mod:`.checks_dynamics`).
    """

    fast: bool
    points: int
    stick_collisions: int
    ellipse_collisions: int

    @classmethod
    def of(cls, fast: bool) -> Resolution:
        """The fast or the full resolution."""
        return cls(True, 4096, 60, 100) if fast else cls(False, 20000, 300, 500)


@dataclass(frozen=True)
class Measured:
    """A number known only to ``tolerance``: formats as ``0`` at that level (a minimiser's 1.7e-08 for
    an exact 0), otherwise with the format spec it is given."""

    value: float
    tolerance: float

    def __float__(self) -> float:
        return float(self.value)

    def __format__(self, spec: str) -> str:
        if abs(self.value) <= self.tolerance:
            return format_number(self.value, self.tolerance)
        return format(self.value, spec)

    @safe_repr
    def __repr__(self) -> str:
        return f"Measured({self.value!r} ± {self.tolerance:g})"


def fit_exponent(x, y) -> float:
    """Slope of log|y| against log x (least squares), over the points where both are positive."""
    x, y = np.asarray(x, float), np.abs(np.asarray(y, float))
    keep = (x > 0) & (y > 0)
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def _reflect(velocity, slope):
    """Specular reflection of (θ̇, η̇) at a wall of slope b'(θ)."""
    normal = np.stack([-slope, np.ones(slope.size)], axis=1) / np.sqrt(1 + slope**2)[:, None]
    return velocity - 2 * np.einsum("ij,ij->i", velocity, normal)[:, None] * normal, normal


# ----------------------------------------------------------------------------- section II: collisions

def collision_impulses(resolution, *, seed: int, samples: int, stick_length: float, ellipse_eps: float) -> dict:
    """Eq. 2–14: rigid-body impulses against specular reflection, on one seeded sample of states.

    The stick (eq. 2–8, lever arm ``L sin θ``, ``L = stick_length`` in units of κ) is checked first,
    then an ellipse of eccentricity parameter ``ellipse_eps`` and the asymmetric egg (eq. 13–14, contact
    point in closed form / from the envelope), drawing from the same generator.

    Returns
    -------
    dict
        ``stick_error`` (largest |Δv_rigid − Δv_specular| for the stick), ``states`` (incoming stick
        states), ``printed_error`` (largest change of δθ̇ when eq. 3's ``L/R`` is read as 1) and
        ``general_error`` (the same as ``stick_error`` for the ellipse and the egg).
    """
    rng = np.random.default_rng(seed)
    stick_error, printed_error, states = _stick_impulse(rng, samples, stick_length)
    general_error = _general_impulse(rng, samples, ellipse_eps)
    return {"stick_error": stick_error, "printed_error": printed_error, "states": states,
            "general_error": general_error}


def _stick_impulse(rng, samples, L):
    theta = rng.uniform(-math.pi / 2 + 0.05, math.pi / 2 - 0.05, samples)  # cos θ > 0: the +L end is lower
    v = rng.normal(size=(samples, 2))
    slope = -L * np.sin(theta)  # b'(θ)
    normal = np.stack([-slope, np.ones(samples)], axis=1) / np.sqrt(1 + slope**2)[:, None]
    incoming = np.einsum("ij,ij->i", v, normal) < 0
    v, theta, normal = v[incoming], theta[incoming], normal[incoming]
    d_eta = -2 * (v[:, 1] + L * v[:, 0] * np.sin(theta)) / (1 + L**2 * np.sin(theta) ** 2)  # eq. 4
    d_theta = L * np.sin(theta) * d_eta  # eq. 3 with L/κ
    rigid = v + np.stack([d_theta, d_eta], axis=1)
    specular = v - 2 * np.einsum("ij,ij->i", v, normal)[:, None] * normal
    err = float(np.max(np.abs(rigid - specular)))
    # eq. 3 as printed has L/R; R is undefined for the stick, and read literally as R = L (the distance
    # of the contact point) the ratio would be sin θ, not (L/κ) sin θ
    printed = float(np.max(np.abs(np.sin(theta) * d_eta - d_theta)))
    return err, printed, int(incoming.sum())


def _general_impulse(rng, samples, eps):
    from ..asymmetric import egg_wall
    from ..ellipse import ellipse_wall

    a, bb = 1.0, 1 / math.sqrt(1 + eps)

    def ellipse_contact(phi):
        n = np.stack([np.cos(phi), np.sin(phi)], axis=1)
        h = np.sqrt((a * n[:, 0]) ** 2 + (bb * n[:, 1]) ** 2)
        return np.stack([a * a * n[:, 0], bb * bb * n[:, 1]], axis=1) / h[:, None]

    egg = egg_wall()

    def egg_contact(phi):
        h, h1, _ = egg.derivatives(phi)
        return np.stack([h * np.cos(phi) - h1 * np.sin(phi), h * np.sin(phi) + h1 * np.cos(phi)], axis=1)

    worst = 0.0
    for wall, contact in ((ellipse_wall(eps), ellipse_contact), (egg, egg_contact)):
        theta = rng.uniform(0, TWO_PI, samples)
        # lab orientation ψ of the body axis: the downward normal (0, −1) has body angle θ = −π/2 − ψ
        psi = -math.pi / 2 - theta
        c = contact(theta)  # body frame
        lab_x = np.cos(psi) * c[:, 0] - np.sin(psi) * c[:, 1]  # horizontal lever arm of the contact point
        omega = rng.normal(size=samples)  # dψ/dt
        vy = rng.normal(size=samples)  # dy/dt (κ = 1, M = 1)
        # velocity of the contact point along the wall normal (+y): v_y + ω × r  (z-cross in 2-D)
        vc = vy + omega * lab_x
        incoming = vc < 0
        J = -2 * vc / (1 + lab_x**2)  # elastic: contact normal velocity reverses, I = M κ² = 1
        vy2, omega2 = vy + J, omega + lab_x * J
        # billiard: θ̇ = −ω, η̇ = v_y; reflect at the wall b(θ)
        _, slope, _ = wall.derivatives(theta)
        specular, _ = _reflect(np.stack([-omega, vy], axis=1), slope)
        rigid = np.stack([-omega2, vy2], axis=1)
        worst = max(worst, float(np.max(np.abs(rigid - specular)[incoming])))
    return worst


# ----------------------------------------------------------------------------- section IV: the ellipse

def ellipse_wall_from_body(resolution, *, eps_values) -> dict:
    """Eq. 15, 18: largest |support(ellipse outline) − eq. 18| over θ, for every ε (``error``)."""
    from ..ellipse import ellipse_outline, ellipse_wall

    theta = np.linspace(0, TWO_PI, 997)
    error = max(float(np.max(np.abs(ellipse_outline(e).support(theta) - ellipse_wall(e)(theta))))
                for e in eps_values)
    return {"error": error}


def contact_angle(resolution, *, eps_values) -> dict:
    """Eq. 16, 17: the ellipse's contact angle α_c from geometry against both closed forms
    (``eq16_error``, ``eq17_error``); the paper's θ is clockwise, θ_paper = −θ."""
    worst16 = worst17 = 0.0
    for eps in eps_values:
        a, b = 1.0, 1 / math.sqrt(1 + eps)
        theta = np.linspace(0.01, TWO_PI - 0.01, 500)
        n = np.stack([np.cos(theta), np.sin(theta)], axis=1)
        h = np.hypot(a * n[:, 0], b * n[:, 1])
        c = np.stack([a * a * n[:, 0], b * b * n[:, 1]], axis=1) / h[:, None]
        alpha = np.arctan2(c[:, 1], c[:, 0])
        theta_paper = -theta
        s2 = np.sin(alpha) ** 2
        eq17 = np.sin(theta_paper) ** 2 / (1 + (eps**2 + 2 * eps) * np.cos(theta_paper) ** 2)
        eq16 = (1 + eps * s2) / np.sqrt(1 + (eps**2 + 2 * eps) * s2)
        worst17 = max(worst17, float(np.max(np.abs(s2 - eq17))))
        worst16 = max(worst16, float(np.max(np.abs(np.cos(alpha + theta_paper) - eq16))))
    return {"eq16_error": worst16, "eq17_error": worst17}


def ellipse_limits(resolution, *, small_eps, large_eps) -> dict:
    """After eq. 18 and eq. 19: fitted rates of max|b − 1| (``circle_exponent``), max|b − eq. 19|
    (``eq19_exponent``, and ``eq19_error`` at the smallest ε) and max|b − |cos θ|| (``stick_exponent``)."""
    from ..ellipse import ellipse_wall

    theta = np.linspace(0, TWO_PI, 721)
    small, large = np.array(small_eps), np.array(large_eps)
    err_circle = [np.max(np.abs(ellipse_wall(e)(theta) - 1)) for e in small]
    err_eq19 = [np.max(np.abs(ellipse_wall(e)(theta) - (1 - e / 2 * np.sin(theta) ** 2))) for e in small]
    err_stick = [np.max(np.abs(ellipse_wall(e)(theta) - np.abs(np.cos(theta)))) for e in large]
    return {"circle_exponent": fit_exponent(small, err_circle), "eq19_exponent": fit_exponent(small, err_eq19),
            "stick_exponent": fit_exponent(large, err_stick), "eq19_error": float(err_eq19[-1])}


def quadratic_22(resolution, *, eps_values) -> dict:
    """Eq. 22 at R of eq. 15: largest |discriminant| (``discriminant``) and largest error of the root
    against d log R/dα (by hand and by central differences; ``root_error``)."""
    worst_disc = worst_root = 0.0
    for eps in eps_values:
        alpha = np.linspace(0, TWO_PI, 721)
        s, c = np.sin(alpha), np.cos(alpha)
        R = 1 / np.sqrt(1 + eps * s * s)
        disc = -1 - eps + (1 + eps) * (1 + eps * s * s) * R * R
        root = -eps * s * c / (1 + eps * s * s)
        exact = -eps * s * c / (1 + eps * s * s)  # d log R/dα of eq. 15, by hand
        h = 1e-6
        numeric = (np.log(1 / np.sqrt(1 + eps * np.sin(alpha + h) ** 2))
                   - np.log(1 / np.sqrt(1 + eps * np.sin(alpha - h) ** 2))) / (2 * h)
        worst_disc = max(worst_disc, float(np.max(np.abs(disc))))
        worst_root = max(worst_root, float(np.max(np.abs(root - numeric))), float(np.max(np.abs(root - exact))))
    return {"discriminant": worst_disc, "root_error": worst_root}


def eq23_sign(resolution, *, eps_values) -> dict:
    """Eq. 23 on the exact ellipse R(α) of eq. 15 (b0 = 0): largest residual with the printed plus sign
    (``plus_residual``) and with the minus sign (``minus_residual``) in front of atan(R'/R)."""
    from ..ellipse import ellipse_wall

    worst = {+1: 0.0, -1: 0.0}
    for eps in eps_values:
        wall = ellipse_wall(eps)
        alpha = np.linspace(0, TWO_PI, 721)
        R = 1 / np.sqrt(1 + eps * np.sin(alpha) ** 2)
        Rp = R * (-eps * np.sin(alpha) * np.cos(alpha) / (1 + eps * np.sin(alpha) ** 2))
        rhs = R**2 / np.sqrt(R**2 + Rp**2)
        for sign in (+1, -1):
            worst[sign] = max(worst[sign], float(np.max(np.abs(wall(alpha + sign * np.arctan(Rp / R)) - rhs))))
    return {"plus_residual": worst[+1], "minus_residual": worst[-1]}


def large_offset(resolution, *, eps: float, offsets, points: int) -> dict:
    """Eq. 23–25: max|R − (b0 + b)| of the solved ellipse body for large b0 (``errors``) and its fitted
    power of b0 (``exponent``)."""
    from coinwall.inverse import solve_body

    from ..ellipse import ellipse_wall

    wall = ellipse_wall(eps)
    errors = []
    for b0 in offsets:
        body = solve_body(wall, b0, points=points)
        errors.append(float(np.max(np.abs(body.R - (b0 + wall(body.alpha))))))
    return {"exponent": fit_exponent(np.array(offsets), np.array(errors)), "errors": errors,
            "first_error": errors[0]}


def extrema_coincide(resolution, *, b0: float) -> dict:
    """Sec. IV on the asymmetric egg: extrema of b (``wall_extrema``) and of R (``radius_extrema``),
    whether they are as many (``extrema_match``), and the largest |R − (b0 + b)| at the extrema of b (``error``)."""
    from scipy.optimize import brentq

    from coinwall.inverse import solve_body

    from ..asymmetric import egg_wall

    wall = egg_wall()
    body = solve_body(wall, b0, points=resolution.points)
    theta = np.linspace(0, TWO_PI, 200000, endpoint=False)
    _, d1, _ = wall.derivatives(theta)
    n_b = int(np.sum(np.sign(d1) != np.sign(np.roll(d1, -1))))
    order = np.argsort(body.alpha)
    R = body.R[order]
    dR = np.roll(R, -1) - R
    n_R = int(np.sum(np.sign(dR) != np.sign(np.roll(dR, -1))))
    # at extrema of b (b' = 0): α = θ and R = b0 + b, from the solver's nodes (h' = 0 ⇒ R = h, α = φ)
    worst = 0.0
    for i in np.flatnonzero(np.sign(d1) != np.sign(np.roll(d1, -1))):
        t0, t1 = theta[i], theta[(i + 1) % theta.size] + (TWO_PI if i + 1 == theta.size else 0)
        root = brentq(lambda x: float(wall.derivatives(np.array([x]))[1][0]), t0, t1, xtol=1e-14)
        R_at = float(np.interp(np.mod(root, TWO_PI), np.sort(body.alpha), R))
        worst = max(worst, abs(R_at - (b0 + float(wall(np.array([root]))[0]))))
    return {"wall_extrema": n_b, "radius_extrema": n_R, "extrema_match": n_b == n_R, "error": worst}


def two_extremum_wall(resolution, *, c: float, points: int) -> dict:
    """Sec. IV, four extrema: the wall 1 + c cos θ (two extrema) solved at b0 = 0; the spread of the
    distance of its outline from (c, 0) (``radius_spread``) and whether it is a convex body (``convex``,
    ``shape``)."""
    from coinwall.inverse import solve_body

    from ..few_extrema import few_extrema_wall

    body = solve_body(few_extrema_wall(c), 0.0, points=points)
    convex = bool(body.convex and body.valid)
    return {"radius_spread": float(np.ptp(np.hypot(body.x - c, body.y))), "convex": convex,
            "shape": "convex" if convex else "not convex"}


def half_angle_wall(resolution, *, expression: str) -> dict:
    """Sec. IV, the remedy θ → θ/2: whether ``Wall.from_expression`` refuses the 4π-periodic
    ``expression`` (``refused``, ``outcome``)."""
    from coinwall.forward import Wall
    from coinwall.forward.errors import InvalidWall

    try:
        Wall.from_expression(expression, {})
        refused = False
    except InvalidWall:
        refused = True
    return {"refused": refused, "outcome": "refused as not 2π-periodic" if refused else "accepted"}
