"""The paper's claims as a registry: what the paper says, where, how coinwall checks it, and the verdict.

Each :class:`Claim` names the claim (``key``), where the paper makes it (``source``, equations and
sections counted in its LaTeX source), what the paper states (``paper``), the check to call (a pure
function of :mod:`.checks`, :mod:`.checks_appendix` or :mod:`.checks_dynamics`) with its ``inputs``,
the ``thresholds`` a measured number must meet for the paper to be right, and the verdict recorded
when the claim was written (``expected``).  The text columns are templates filled with the check's
measured numbers and the claim's inputs (:meth:`str.format`).

The verdict is ``yes`` if every condition in ``thresholds`` holds; otherwise ``partly`` if the claim
has a ``partly`` mapping and all of its conditions hold (an empty mapping: the paper claims no more
than an estimate), else ``no``.  ``coinwall verify`` is ``ok`` when every verdict is the recorded one.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

from coinwall.forward.display import safe_repr

from . import checks, checks_appendix, checks_coin3d, checks_design, checks_dynamics, checks_quantum, checks_toss

__all__ = ["Below", "Above", "Within", "Equals", "Claim", "REGISTRY", "CLAIMS", "judge", "render"]


# ----------------------------------------------------------------------------- conditions

@dataclass(frozen=True)
class Below:
    """The measured value is below ``limit``."""

    limit: float

    def holds(self, value) -> bool:
        return float(value) < self.limit


@dataclass(frozen=True)
class Above:
    """The measured value is above ``limit``."""

    limit: float

    def holds(self, value) -> bool:
        return float(value) > self.limit


@dataclass(frozen=True)
class Within:
    """The measured value is within ``tolerance`` of ``target``."""

    target: float
    tolerance: float

    def holds(self, value) -> bool:
        return abs(float(value) - self.target) < self.tolerance


@dataclass(frozen=True)
class Equals:
    """The measured value (a count or a yes/no finding) equals ``value``."""

    value: object

    def holds(self, value) -> bool:
        return value == self.value


# ----------------------------------------------------------------------------- the claim

@dataclass(frozen=True)
class Claim:
    """One claim of the paper and how it is checked.

    Attributes
    ----------
    key : str
        Short unique name (the report's rows and the tests refer to it).
    claim : str
        The claim in one line.
    source : str
        Where the paper makes it (equation, section).
    paper : str
        What the paper states (template).
    check : callable
        ``check(resolution, **inputs) -> dict`` of measured numbers.
    inputs : mapping
        The check's keyword arguments (the bodies, walls, parameters it uses).
    thresholds : mapping
        ``{measured name: condition}``: the paper is right (``yes``) if all hold.
    expected : str
        The verdict recorded when the claim was written.
    computed : str
        What coinwall finds (template).
    detail : str
        Explanation for the report's Details section (template; "" for none).
    partly : mapping or None
        ``{measured name: condition}`` for ``partly`` when the thresholds fail; None: ``no`` then.
    """

    key: str
    claim: str
    source: str
    paper: str
    check: Callable[..., dict]
    inputs: Mapping = field(default_factory=dict)
    thresholds: Mapping = field(default_factory=dict)
    expected: str = ""
    computed: str = ""
    detail: str = ""
    partly: Mapping | None = None

    @safe_repr
    def __repr__(self) -> str:
        return f"Claim({self.key!r}, {self.source}, check={self.check.__name__}, expected={self.expected!r})"


def judge(claim: Claim, measured: Mapping) -> str:
    """The verdict (``yes``, ``partly`` or ``no``) of ``claim`` on its check's ``measured`` numbers."""
    if all(condition.holds(measured[name]) for name, condition in claim.thresholds.items()):
        return "yes"
    if claim.partly is not None and all(condition.holds(measured[name])
                                        for name, condition in claim.partly.items()):
        return "partly"
    return "no"


def render(template: str, claim: Claim, measured: Mapping) -> str:
    """``template`` filled with the claim's inputs and the measured numbers (these take precedence)."""
    return template.format(**{**claim.inputs, **measured})


# ----------------------------------------------------------------------------- the registry

#: The ellipse parameters of section IV's checks.
_EPS = [0.3, 1.0, 3.0, 99.0]
#: One seeded sample of collision states for the stick, the ellipse and the egg (eq. 2–14).
_IMPULSES = {"seed": 20261121, "samples": 2000, "stick_length": 1.7, "ellipse_eps": 2.5}
#: The Case III wall of the Appendix: ellipse ε = 1 below its critical offset −1/2.
_CASE_THREE = {"b0": -0.6, "eps": 1.0}
_LIMITS = {"small_eps": [1e-2, 3e-3, 1e-3, 3e-4], "large_eps": [1e2, 1e3, 1e4, 1e5]}

_CLAIMS = (
    # ------------------------------------------------------------------ section II: collisions
    Claim("stick-specular", "Stick collisions are specular reflections", "eq. 2–8",
          "δv ⟂ tangent T; normal component flips", checks.collision_impulses, _IMPULSES,
          {"stick_error": Below(1e-12)}, "yes",
          "max |Δv_rigid − Δv_specular| = {stick_error:.1e} ({states} states)",
          "Impulse from eq. 2 with energy conservation (eq. 4) equals the specular reflection at "
          "b = (L/κ)|cos θ|. Valid as written for cos θ > 0 (the +L end is the lower one); for cos θ < 0 the "
          "other end touches and the lever arm changes sign — the paper does not say."),
    # as printed (L/R read as 1) eq. 3 fails; with L/κ, as eq. 2 and 4 give, it holds: partly
    Claim("eq3-typo", "Eq. 3: δθ̇ = (L/R) sin θ δη̇", "eq. 3", "ratio L/R", checks.collision_impulses, _IMPULSES,
          {"printed_error": Below(1e-12)}, "partly", "ratio is L/κ (eq. 2 and 4)",
          "Eq. 3 as printed has L/R; it follows from eq. 2 only with L/κ (R is not defined for the stick). "
          "Reading L/R as 1 would be off by up to {printed_error:.2f} in δθ̇ on the test states.",
          partly={"stick_error": Below(1e-12)}),
    Claim("general-specular", "Any body: collisions are specular (eq. 13–14)", "eq. 11–14",
          "equivalent billiard for every shape", checks.collision_impulses, _IMPULSES,
          {"general_error": Below(1e-12)}, "yes",
          "max |Δv_rigid − Δv_specular| = {general_error:.1e} (ellipse ε = {ellipse_eps}, asymmetric egg)",
          "Rigid-body impulse computed from the contact point in the lab frame (lever arm, I = Mκ²) "
          "versus specular reflection at the wall b(θ) with exact b'(θ). Asymmetric body: upper wall "
          "H − b(θ + π), see tests/inverse/test_conventions.py."),
    # ------------------------------------------------------------------ section IV: the ellipse
    Claim("eq18", "Ellipse wall b(θ) (eq. 18) from its body (eq. 15)", "eq. 15, 18",
          "b = sqrt((1 + ε cos²θ)/(1 + ε))", checks.ellipse_wall_from_body, {"eps_values": _EPS},
          {"error": Below(1e-9)}, "yes", "max |support(outline) − eq. 18| = {error:.1e}, ε ∈ {eps_values}",
          "Forward construction: exact support function of the ellipse outline."),
    Claim("eq16-17", "Contact angle α_c of the ellipse (eq. 16, 17)", "eq. 16, 17", "closed forms",
          checks.contact_angle, {"eps_values": _EPS},
          {"eq16_error": Below(1e-12), "eq17_error": Below(1e-12)}, "yes",
          "max error eq. 16: {eq16_error:.1e}, eq. 17: {eq17_error:.1e}",
          "α_c from the contact point geometry; the paper's θ is clockwise, i.e. θ_paper = −θ_coinwall "
          "(both formulas are even in θ except through α_c + θ)."),
    Claim("limits", "ε → 0 gives the circle, ε → ∞ the stick", "after eq. 18", "b → 1; b → |cos θ|",
          checks.ellipse_limits, _LIMITS,
          {"circle_exponent": Within(1.0, 0.05), "stick_exponent": Within(-0.5, 0.05)}, "yes",
          "max|b − 1| ∝ ε^{circle_exponent:.2f}; max|b − |cos θ|| ∝ ε^{stick_exponent:.2f}",
          "Rates fitted over ε ∈ [3e-4, 1e-2] and [1e2, 1e5]; expected 1 and −1/2 (at θ = π/2 the difference "
          "is 1/sqrt(1 + ε))."),
    Claim("eq19", "Small-ε expansion b ≈ 1 − (ε/2) sin²θ", "eq. 19", "first order in ε",
          checks.ellipse_limits, _LIMITS, {"eq19_exponent": Within(2.0, 0.05)}, "yes",
          "error ∝ ε^{eq19_exponent:.2f} (error {eq19_error:.1e} at ε = 3e-4)"),
    Claim("eq22", "Quadratic for R'/R is solved by eq. 15 with a double root", "eq. 22 (sec. IV)",
          "consistent with eq. 15; two degenerate solutions", checks.quadratic_22, {"eps_values": _EPS},
          {"discriminant": Below(1e-12), "root_error": Below(1e-8)}, "yes",
          "discriminant ≤ {discriminant:.1e}, root error {root_error:.1e}",
          "At R of eq. 15 the square root in eq. 22 vanishes identically: the body is the singular solution "
          "(Clairaut). The text says the wall is 'given by equation (17)' — it is eq. (18)."),
    Claim("eq23-sign", "Eq. 23: b0 + b(α + atan(R'/R)) = R²/sqrt(R² + R'²)", "eq. 23 (sec. IV)", "plus sign",
          checks.eq23_sign, {"eps_values": _EPS}, {"plus_residual": Below(1e-9)}, "partly",
          "on eq. 15 (b0 = 0): residual {plus_residual:.2f} with +, {minus_residual:.1e} with −",
          "Eq. 12 gives θ = atan(R'/R) − α (θ clockwise); for a wall even in θ, as the ellipse's, that is "
          "b(α − atan(R'/R)). The printed plus sign fails on the paper's own ellipse; the minus sign holds to "
          "rounding. coinwall's polar solver uses θ = α − atan(R'/R) (inverse/polar.py).",
          partly={"minus_residual": Below(1e-9)}),
    # ------------------------------------------------------------------ Appendix
    Claim("bc", "Critical offset b_c = −1/(1 + ε)", "Appendix, eq. 29", "b_c = −1/(1 + ε)",
          checks_appendix.critical_offsets, {"eps_values": [0.3, 1, 2, 99]}, {"error": Below(1e-12)}, "yes",
          "exact −min(b + b''): max error {error:.1e} for ε ∈ {eps_values}"),
    Claim("bc-extremum", "Negative curvature first appears at an extremum of b (estimate)",
          "Appendix, last paragraph", "not demonstrated; suggested as an estimate",
          checks_appendix.extremum_estimate, {"expression": "1 + 0.05*cos(2*t) + 0.03*sin(5*t)"},
          {"estimate_error": Below(1e-9)}, "partly",
          "wall 1 + 0.05 cos 2θ + 0.03 sin 5θ: exact b_c = {b_c:.6f} at θ = {angle:.4f} (b' = {slope:.3f}); "
          "estimate from extrema {estimate:.6f}",
          "The paper only claims an estimate. The minimum of b + b'' need not sit at an extremum of b; "
          "there the estimate is too low, so an offset between the two values would be wrongly called physical.",
          partly={}),
    Claim("K0", "Curvature K(0) = (1 + ε)/(1 + b0(1 + ε))", "eq. 28–29", "closed form",
          checks_appendix.curvature_at_zero, {"cases": [(0.5, 0.0), (1.0, -0.3), (3.0, -0.1), (1.0, 0.4)]},
          {"error": Below(1e-8)}, "yes", "max relative error {error:.1e} over {count} (ε, b0)"),
    Claim("eq27", "R(α) ≈ (b0 + 1) − ½(1 + b0)ε/(1 + b0(1 + ε)) α²", "eq. 27", "coefficient {paper_coefficient:.6f}",
          checks_appendix.coefficient_27, {"b0": -0.3, "eps": 1.0}, {"relative_error": Within(0.0, 1e-3)}, "yes",
          "fitted {fitted:.6f} (ε = 1, b0 = −0.3)",
          "Follows from eq. 28–29 with R'(0) = 0 (derivation in cases/paper/checks_appendix.py)."),
    Claim("case1", "Case I: R − (b0+1) ~ α², R' ~ α", "Appendix Case I", "quadratic, linear",
          checks_appendix.exponents_near_zero, {"b0": -0.3, "eps": 1.0, "lo": 1e-3, "hi": 3e-2},
          {"radius_exponent": Within(2.0, 0.02), "slope_exponent": Within(1.0, 0.02)}, "yes",
          "fitted exponents {radius_exponent:.3f}, {slope_exponent:.3f}"),
    Claim("case2", "Case II: R − (b0+1) ~ α^(4/3), R' ~ α^(1/3)", "Appendix Case II", "4/3, 1/3",
          checks_appendix.exponents_near_zero, {"b0": -0.5, "eps": 1.0, "lo": 1e-6, "hi": 1e-3},
          {"radius_exponent": Within(4 / 3, 0.02), "slope_exponent": Within(1 / 3, 0.02)}, "yes",
          "fitted exponents {radius_exponent:.3f}, {slope_exponent:.3f}",
          "Fitted on the solved body's nodes for α ∈ [1e-6, 1e-3]; with ρ ≈ cφ² near φ = 0 the map "
          "α(φ) is cubic, which gives the exponents 4/3 and 1/3 (the paper's statement)."),
    Claim("case3-corner", "Case III: R' tends to a non-zero R'_0 (a corner)", "Appendix Case III",
          "discontinuous derivative at α = 0, π", checks_appendix.case_three, _CASE_THREE,
          {"corner_slope": Above(1e-3), "corners": Equals(2)}, "yes",
          "R'(0±) = ±{corner_slope:.6f}; {corners} corners",
          "The largest convex body under the wall (half-plane intersection) has corners exactly there; "
          "it is the paper's 'putative shape'."),
    Claim("case3-R0", "Case III: R approaches b0 + 1", "Appendix Case III", "R(0) = b0 + 1 = {paper_distance:.4f}",
          checks_appendix.case_three, _CASE_THREE, {"distance_gap": Within(0.0, 1e-6)}, "no",
          "corner at R_c = {corner_distance:.6f}",
          "The support line x = b0 + 1 is inactive in Case III (that is what the deficit means), so the corner "
          "lies inside it: R_c = {corner_distance:.6f} < {paper_distance:.4f} (difference {distance_gap:.4f}). "
          "R does approach R_c linearly."),
    Claim("case3-thetac", "Case III: θ_c = atan(R'_0/(b0 + 1))", "eq. 30", "{paper_theta_c:.6f} rad",
          checks_appendix.case_three, _CASE_THREE, {"paper_theta_c_error": Below(1e-6)}, "partly",
          "exact window half-width {half_width:.6f} rad = atan(|R'_0|/R_c) = {exact_theta_c:.6f}",
          "Eq. 30 is exact with the corner's true distance R_c in place of b0 + 1; as printed it is off by "
          "{paper_theta_c_error:.4f} rad.",
          partly={"exact_theta_c_error": Below(1e-9)}),
    Claim("case3-deficit", "Case III: the body fails to reproduce the wall for |θ| < θ_c", "Appendix Case III",
          "wall not reproduced in the window", checks_appendix.case_three, _CASE_THREE,
          {"max_deficit": Above(1e-6)}, "yes",
          "largest deficit {max_deficit:.3e} at θ = {deficit_angle:.3g}",
          "Everywhere else the body's wall equals the prescribed one "
          "(max_wall_error = {max_wall_error:.1e} outside the windows)."),
    Claim("case3-positive", "b0 + b stays positive down to b0 = −1/sqrt(1 + ε)", "Appendix, end of Case III",
          "−1/sqrt(1+ε) < b_c", checks_appendix.offset_positivity, {"eps": 1.0}, {"margin": Above(0.0)}, "yes",
          "min b = {min_wall:.6f} for ε = {eps:g}: the bound is −{min_wall:.6f} < b_c = −{minus_b_c:g}"),
    Claim("case1-realizable", "Case I bodies are physical shapes", "Appendix Case I",
          "a physical shape", checks_appendix.realizable_body, {"b0": -0.25, "eps": 1.0},
          {"realizable": Equals(True)}, "no",
          "b0 = {b0:g} ({regime}): κ_max = {kappa_max:.4f} κ, uniform κ = {kappa_uniform:.4f} κ",
          "Convex, yes; a rigid body, not for every b0 > b_c. The wall is in units of κ, so the body must be "
          "able to have κ = 1; the largest κ any mass distribution inside it gives (centre of mass at the origin) "
          "is its largest distance from the centre, b0 + 1 for this wall: only b0 ≥ 0 is realizable."),
    Claim("case2-realizable", "The critical body of Fig. 4 is a completely physical shape", "Appendix Case II, Fig. 4",
          "completely physical", checks_appendix.realizable_body, {"b0": -0.5, "eps": 1.0},
          {"realizable": Equals(True)}, "no",
          "b0 = {b0:g} ({regime}): κ_max = {kappa_max:.4f} κ, uniform κ = {kappa_uniform:.4f} κ",
          "The Fig. 4 body is convex, but no mass distribution inside it has κ = 1: with κ_max = 0.5 κ it "
          "cannot be the rigid body whose billiard has this wall. Scaled to be realizable it has another wall."),
    # ------------------------------------------------------------------ section IV: general walls
    Claim("large-b0", "Large b0: R(α) ≈ b0 + b(α), α ≈ θ", "eq. 23–25", "leading order", checks.large_offset,
          {"eps": 1.0, "offsets": [50.0, 100.0, 200.0, 400.0], "points": 512},
          {"exponent": Within(-1.0, 0.02)}, "yes",
          "max|R − (b0 + b)| ∝ b0^{exponent:.3f} ({first_error:.1e} at b0 = {offsets[0]:g})",
          "The error is −b'(α)²/(2 b0) + O(b0⁻²) (cases/large_offset.py). The text says 'expand equation (28)'; "
          "eq. (23) is meant."),
    Claim("extrema", "Extrema of b and R coincide, with α = θ and R = b0 + b there", "sec. IV",
          "coincide; R(α) = b(θ)", checks.extrema_coincide, {"b0": 0.0},
          {"extrema_match": Equals(True), "error": Below(1e-6)}, "yes",
          "egg wall: {wall_extrema} extrema of b, {radius_extrema} of R; |R − (b0 + b)| ≤ {error:.1e}",
          "True for convex bodies: d(R²)/dφ = 2h'ρ vanishes only where h' = 0 when ρ > 0. The paper's "
          "'R(α) = b(θ)' omits the offset: it is R = b0 + b."),
    # the paper is right only if no wall with two extrema has a convex body
    Claim("four-extrema", "A wall needs at least four extrema", "sec. IV", "four-extremum requirement",
          checks.two_extremum_wall, {"c": 0.3, "points": 512}, {"convex": Equals(False)}, "no",
          "b = 1 + {c:g} cos θ (2 extrema) is the unit disc about ({c:g}, 0): radius spread {radius_spread:.1e}, "
          "{shape}",
          "The four-vertex theorem is about extrema of the curvature, not of the support function. A wall with "
          "two extrema is a disc whose centre of mass is off-centre (a non-uniform density)."),
    Claim("theta-half", "Map θ → θ/2 to meet the requirement", "sec. IV", "b(θ/2) is a wall",
          checks.half_angle_wall, {"expression": "1 + 0.3*cos(t/2)"}, {"refused": Equals(False)}, "no",
          "b(θ/2) is 4π-periodic: {outcome}",
          "b(2θ) (π-periodic, doubled number of extrema) is presumably what is meant."),
    # ------------------------------------------------------------------ section II, simulated
    Claim("equivalence-simulated", "Rigid body and billiard are the same dynamics (simulated)", "sec. II (theorem)",
          "equivalent billiard", checks_dynamics.simulated_equivalence, {"H": 3.0, "ellipse_eps": 0.3},
          {"error": Below(1e-9)}, "yes",
          "max state difference {error:.1e} over {collisions} collisions "
          "(stick, restarted every collision; ellipse ε = {ellipse_eps}, one run)",
          "Direct rigid-body simulation (flat walls, impulse from the contact point of the rotated outline) "
          "versus the billiard kernel, from corresponding states: same wall sequence and states. The stick is "
          "chaotic, so it is compared map by map (rounding grows ≈3× per collision); see docs/equivalence.md. "
          "Section III's statistics (Poincaré sections, KAM boundary eq. 20, the coin's P(n) and τ(H)) are "
          "computed by `coinwall section|kam|correlation` and tests/benchmarks/reproduce_coin.py; their "
          "numbers and verdicts are in docs/dynamics.md (too slow for this report)."),
    # ------------------------------------------------------------------ external fields: the toss that lands
    Claim("external-fields", "The results extend to external fields", "sec. V",
          "can be extended to include external fields", checks_toss.external_fields,
          {"eps": 0.3, "H": 5.0, "g": 1.0, "e": 0.97}, {"error": Below(1e-9)}, "yes",
          "rigid body in the field g = {g:g} with restitution e = {e:g} (ellipse ε = {eps}, floor and ceiling H = "
          "{H:g}) against the field billiard: max state difference {error:.1e} over {impacts} impacts",
          "The field is a linear potential in η: the body is a point on parabolas in the (θ, η) strip, and "
          "Newton's restitution at the contact point is restitution of the normal velocity in the billiard "
          "metric (docs/toss.md). The direct rigid-body simulation in gravity agrees with the field kernel "
          "impact by impact (restarted from the body's state at each impact: the orbit is chaotic)."),
    # bounces randomise at e = 0.6 and 0.9, not at e = 0.3, where the coin settles with a larger bias: partly
    Claim("casino", "Bounces randomise the outcome (the casinos' house rule)", "sec. III (end)",
          "the bounce plays a significant role in randomizing the outcome", checks_toss.casino_bounces,
          {"eps": 99.0, "g": 1.0, "height": 1.2, "mean": (2.0, 5.0), "sigma": (0.05, 0.2),
           "restitutions": (0.3, 0.6, 0.9)},
          {"caught_sigmas": Above(4.0), "unfair_count": Equals(0)}, "partly",
          "coin ε = {eps:g} on a floor, hand (v0, ω0) = {mean} ± {sigma}, {samples} tosses per e: caught on landing "
          "the heads bias is {caught_bias:+.4f} ({caught_sigmas:.1f}σ); stopped at the n-th floor bounce, "
          "{per_e_text}",
          "The toss that lands (`coinwall toss`, docs/toss.md): a croupier stops the coin at its n-th floor impact "
          "and reads the face down; a toss settled before keeps its outcome. The claim holds where the coin keeps "
          "bouncing (of e = {restitutions}: fair at {fair_list}; not at {unfair_list}): \"fair\" means within "
          "0.01 of ½ by two standard errors at every bounce from some n to the last computed, and at the last 3 at "
          "least. With small e the "
          "coin settles after a few bounces and the outcome keeps — and here grows — the bias it had then. "
          "Fairness to 0.001 needs about 10⁶ tosses to resolve; the curve against e is on docs/toss.md. This is "
          "the planar coin, the paper's model; a precessing coin on a frictionless floor keeps L_z and L₃ and is "
          "not randomised by its bounces (docs/coin3d.md).",
          partly={"caught_sigmas": Above(4.0), "fair_count": Above(0.5)}),
    # ------------------------------------------------------------------ section V: the announced next step
    Claim("quantum-tunnelling", "The quantum body tunnels from heads to tails", "sec. V (last paragraph)",
          "announced as a current focus; nothing computed", checks_quantum.tunnelling_doublets,
          {"expression": "sqrt((1+eps*cos(t)**2)/(1+eps))", "eps": 0.55, "heights": (2.3, 2.2, 2.15)},
          {"agreement": Below(1e-5), "wkb_slope": Within(1.0, 0.1), "all_trusted": Equals(True)}, "yes",
          "lowest doublet of the ε = {eps} ellipse at H = 2.3, 2.2, 2.15 (diameter 2): Δλ = {splittings[0]:.3g}, "
          "{splittings[1]:.3g}, {splittings[2]:.3g}; direct and flux agree to {agreement:.1e} where Δλ > 1e-7 λ; "
          "ln Δλ falls {wkb_slope:.3f} × the WKB action",
          "coinwall computes the quantum problem the paper announces (`coinwall quantum`, docs/quantum.md): the "
          "Dirichlet Laplacian on the billiard strip by finite elements. Just above the diameter the levels pair "
          "into heads–tails doublets; the splitting by Herring's flux formula (no subtraction of nearly equal "
          "eigenvalues) agrees with the direct difference and follows exp(−S) through the necks."),
    # computed for bodies of revolution; the paper's remark is about any rigid body: partly
    Claim("three-d-billiard", "A rigid body in 3-D is a new type of billiard", "sec. V (last paragraph)",
          "conjectured for rigid bodies in 3-D (\"a new type of billiard motion\"); nothing computed",
          checks_coin3d.three_d_billiard, {"impacts": 12, "restitution": 0.8},
          {"error": Below(1e-9), "momentum_drift": Below(1e-12), "general_axis_torque": Below(1e-12)}, "partly",
          "bodies of revolution: the (θ, η) billiard with the top's potential (ℓz − ℓ3 cos θ)²/(2 sin²θ); the "
          "direct 3-D simulation restarted at each of {impacts} impacts (coin on a floor, ellipsoid between walls, "
          "e = {restitution}) meets the reduced billiard's next state to {error:.1e}; Lz, L3 kept to "
          "{momentum_drift:.1e}. A general body is not reduced: a floor's impulse turns a triaxial ellipsoid "
          "about its own axis by up to {general_axis_torque:.2f} × lever arm (a body of revolution: "
          "{revolution_axis_torque:.0e})",
          "For a body of revolution the conjecture holds exactly: a frictionless horizontal wall conserves L_z "
          "and L_3, and the motion is a 2-D billiard in (θ, η) whose new ingredient is the symmetric top's "
          "potential (docs/coin3d.md). The paper speaks of rigid bodies in general; for a body without an axis of "
          "symmetry the impulse of the wall changes the angular momentum about the body's axes (measured on a "
          "triaxial ellipsoid at random orientations) and the orientation needs all three angles: whatever "
          "billiard it is, it is not this one, and coinwall computes none. The potential breaks the heads/tails "
          "symmetry when L_3 ≠ 0, so, unlike the planar paper's coin, bounces on a frictionless floor do not make "
          "a precessing coin fair.",
          partly={"error": Below(1e-9), "momentum_drift": Below(1e-12), "revolution_axis_torque": Below(1e-12)}),
    Claim("caught-coin-flips", "A caught coin keeps its side (DHM 2007; Bartoš et al. 2023)",
          "beyond the paper", "not in the paper (the planar coin has no precession)",
          checks_coin3d.caught_coin_against_flips, {"samples": 20000},
          {"z_a": Within(0.0, 3.0), "z_b": Within(0.0, 3.0), "dhm_error": Below(3.5)}, "yes",
          "out of sample: ψ fitted to the odd-numbered tossers ({n_a:,} flips) is {psi_a:.2f}°, where the simulated "
          "caught coin ({samples} tosses) keeps its side {p_sim_a:.4f} of the time; the even-numbered tossers' "
          "coins did {p_b:.4f} ({z_a:+.1f} σ with the spread between tossers, {z_binomial_a:+.1f} σ binomial). "
          "The other way round: {psi_b:.2f}° → {p_sim_b:.4f} against {p_a:.4f} ({z_b:+.1f} σ, "
          "{z_binomial_b:+.1f} σ binomial). All 350,757 flips: ψ = {psi:.2f}°, [{psi_low:.2f}, {psi_high:.2f}] "
          "as one binomial, [{psi_spread_low:.2f}, {psi_spread_high:.2f}] with the spread between tossers",
          "The precessing coin of the reduced billiard, caught after a free flight, reproduces Diaconis, Holmes "
          "& Montgomery's ½ + arcsin(cot²ψ)/π (to {dhm_error:.1f} standard errors of the simulation). Against the "
          "data the check holds data out: ψ fitted to all the flips and compared with the same flips would agree "
          "by construction. The 48 tossers differ beyond binomial noise (Pearson χ² 265 on 47 dof), so the "
          "comparison allows for that spread (quasi-binomial, dispersion 5.6); the real flips need ψ ≈ 81° "
          "(docs/coin3d.md)."),
    # ------------------------------------------------------------------ beyond the paper: bodies designed for odds
    Claim("design-drop-rectangle", "A dropped planar d × h rectangle lands on an edge with P = (2/π) atan(h/d)",
          "beyond the paper", "not in the paper; the angle each face subtends at the centre of mass",
          checks_design.drop_rectangle, {"ratios": (0.05, 0.3, 1 / 3 ** 0.5, 1.0, 2.7)},
          {"error": Below(1e-9), "design_error": Below(1e-9)}, "yes",
          "drop model at h/d = {shown}: largest |P − (2/π) atan(h/d)| = {error:.1e}; `coinwall design` for "
          "P(edge) = 1/3 finds h/d = {design:.12f} (1/√3 to {design_error:.1e})",
          "The drop model (`coinwall design --model drop`, docs/design.md): a uniform random orientation, no "
          "bounce, the face below the centre of mass; exact from the valleys of the wall b(θ)."),
    Claim("design-drop-cylinder", "A dropped cylinder lands on its rim with P = (h/2)/√(r² + h²/4)",
          "beyond the paper", "Yong & Mahadevan (2011): thickness/diameter 1/(2√2) ≈ 0.354 for a third on the edge",
          checks_design.drop_cylinder, {"ratios": (0.05, 0.2, 1 / 8 ** 0.5, 0.6, 1.5)},
          {"error": Below(1e-9), "design_error": Below(1e-9)}, "yes",
          "solid angle of the rim band at h/(2r) = {shown}: largest error {error:.1e}; the design for P(edge) = "
          "1/3 has h/(2r) = {design:.12f} (1/(2√2) to {design_error:.1e})",
          "A body of revolution's tilt is uniform on the sphere (density sin θ/2); a valley [a, c] of its support "
          "function has P = (cos a − cos c)/2 (docs/design.md)."),
    Claim("design-flip-cylinder", "A cylinder flipped vigorously about a diameter is fair at thickness/diameter "
          "1/√3", "beyond the paper", "Yong & Mahadevan (2011): 1/√3 ≈ 0.577 for a coin flipped about a "
          "horizontal axis", checks_design.flip_cylinder, {}, {"design_error": Below(1e-9)}, "yes",
          "the planar flip of the meridian section (first contact at a uniform phase, no bounce) gives "
          "thickness/diameter {design:.12f} (1/√3 to {design_error:.1e}); for an irregular quadrilateral the flip "
          "and the drop differ by up to {irregular_difference:.3f} in a face's probability",
          "The flip model's first contact is the first passage of b(u) + k u over a uniform level (docs/design.md). "
          "Where every corner is equally far from the centre of mass (a rectangle, a cylinder's section) it gives "
          "the drop's angle measure for every fall-to-spin ratio k, hence Yong & Mahadevan's 1/√3; for a body "
          "whose corners differ, a vigorous flip lands beside the farthest corner."),
    Claim("design-bounce-nickel", "A bouncing US nickel lands on its edge about once in 6000 tosses",
          "beyond the paper", "Murray & Teare (1993, abstract): ≈ 1 in 6000, extrapolated from their dynamical "
          "model of coins dropped onto a surface", checks_design.bounce_nickel,
          {"diameter": 21.21, "thickness": 1.95, "restitutions": (0.3, 0.5, 0.7), "tosses": 400_000},
          {"ratio_to_6000": Within(1.0, 0.5)}, "partly",
          "frictionless planar bounce of the nickel's section (flipped about a diameter, {tosses} tosses per e): "
          "P(edge) {shown}; the largest is {ratio_to_6000:.1f} × 1/6000 and {suppression:.0f}× below the drop "
          "model's {drop:.4f}",
          "Compared with the abstract only (Murray & Teare, Phys. Rev. E 48, 2547; its text was not read here): the "
          "bounces make the edge rare, tens of times rarer than the geometric drop estimate, as they report, but "
          "the frictionless floor and the launch of `coinwall design` are not their model (friction, their launch "
          "and restitution are not known here), and the number differs by the factor above. Hernández-Navarro & "
          "Piñero (arXiv:2103.10927) were not compared: only their abstract was available.",
          partly={"suppression": Above(10.0)}),
    Claim("design-bounce-nickel-friction", "A US nickel bouncing on a floor with friction lands on its edge about "
          "once in 6000 tosses", "beyond the paper", "Murray & Teare (1993, abstract): ≈ 1 in 6000, extrapolated "
          "from their dynamical model of coins dropped onto a surface", checks_design.bounce_nickel_friction,
          {"diameter": 21.21, "thickness": 1.95, "e": 0.5, "frictions": (0.1, 0.3, 0.6), "tosses": 400_000},
          {"ratio_to_6000": Within(1.0, 0.5), "undecided": Below(1e-3)}, "partly",
          "planar bounce of the nickel's section (as in the row above) on a floor with Coulomb friction, e = {e:g}, "
          "{tosses} tosses per μ: P(edge) {shown} (frictionless, the same launches: {p_free:.2g}, {undecided_free:.1%} "
          "undecided); undecided with friction {undecided:.1e}; the largest is {ratio_to_6000:.1f} × 1/6000 and "
          "{suppression:.0f}× below the drop model's {drop:.4f}",
          "With friction the tosses settle that slide on their rim for ever on a frictionless floor, and the edge "
          "odds are compared with the frictionless ones above. Murray & Teare's launch, restitution and friction are "
          "not known here (only their abstract was read), and the planar toss of the section has no precession, so "
          "the verdict is partly when the bounces make the edge at least ten times rarer than the drop model, as "
          "they report, without reaching their number (yes within a factor 1.5 of 1/6000).",
          partly={"suppression": Above(10.0), "undecided": Below(1e-3)}),
)

#: Every claim by key, in the report's order.
REGISTRY: dict = {claim.key: claim for claim in _CLAIMS}

#: The keys of every claim, in order.
CLAIMS: tuple = tuple(REGISTRY)
