"""The Appendix family: the ε = 1 ellipse wall plus an offset b0, above, at and below b_c.

Paper Appendix, eq. 26–30.  With ``h = b0 + sqrt((1 + ε cos²θ)/(1 + ε))`` the
radius of curvature is ``ρ = h + h''``, smallest at θ = 0 (and π), where
``ρ(0) = b0 + 1/(1 + ε)``.  Hence

* ``K(0) = 1/ρ(0) = (1 + ε)/(1 + b0(1 + ε))`` (eq. 29) and ``b_c = −1/(1 + ε)``;
* near α = 0, with R'(0) = 0 and the polar curvature formula (eq. 28),
  ``R(α) = (b0 + 1) − ½ (1 + b0) ε/(1 + b0(1 + ε)) α² + …`` (eq. 27) — derived
  in :mod:`coinwall.cases.paper.checks_appendix` from ``K = (R² − R R'')/R³`` at R' = 0;
* Case I (b0 > b_c): convex, R − (b0+1) ~ α², R' ~ α;
* Case II (b0 = b_c = −1/2 for ε = 1, the paper's Fig. 4): ρ(0) = 0; with
  ρ ≈ c φ² one finds R − (b0+1) ~ α^(4/3) and R' ~ α^(1/3) (the paper's claim,
  checked by fitted exponents);
* Case III (b0 < b_c): no body has this wall; the largest body under it has
  corners on the major axis.  The paper calls the same shape "putative" and
  says R approaches b0 + 1 there — it does not: the corner lies *inside* the
  inactive support line x = b0 + 1 (see :mod:`coinwall.cases.paper.checks_appendix`).
"""

from .catalog import Case, Reference
from .ellipse import ELLIPSE_WALL, ellipse_wall

__all__ = ["APPENDIX_EPS", "appendix_curvature_at_zero", "CASES"]

APPENDIX_EPS = 1.0


def appendix_curvature_at_zero(eps: float, b0: float) -> float:
    """Eq. 29: ``K(0) = (1 + ε)/(1 + b0(1 + ε))``."""
    return (1 + eps) / (1 + b0 * (1 + eps))


def _case(name, b0, title, regime):
    eps = APPENDIX_EPS
    refs = [Reference("b_c", -1 / (1 + eps), "Appendix"),
            Reference("regime", regime, "Appendix Case I/II/III: b0 vs b_c")]
    if regime != "corner":
        refs.append(Reference("R0", b0 + 1, "Appendix: R(0) = b0 + 1 (R' = 0 there)"))
    if regime == "convex":
        refs.append(Reference("K0", appendix_curvature_at_zero(eps, b0), "eq. 29"))
    return Case(name, title, "paper Appendix, eq. 26–30", lambda: ellipse_wall(eps), b0, None, None, tuple(refs),
                ELLIPSE_WALL, {"eps": eps})


CASES = (
    _case("appendix-convex", -0.3, "Appendix Case I: ε = 1, b0 = −0.3 > b_c (convex)", "convex"),
    _case("appendix-critical", -0.5, "Appendix Case II: ε = 1, b0 = b_c = −1/2 (paper Fig. 4)", "critical"),
    _case("appendix-corner", -0.6, "Appendix Case III: ε = 1, b0 = −0.6 < b_c (corners)", "corner"),
)
