"""The check of the paper's announced next step, the quantum problem (sec. V, last paragraph).

The paper computes nothing quantum: it announces "the analogous quantum mechanical problem … the
tunneling from heads to tails".  coinwall computes it (:mod:`coinwall.forward.quantum`, docs/quantum.md);
this check measures what the announcement implies: just above the diameter the lowest levels pair into
heads–tails doublets whose splitting falls like the WKB factor exp(−S) through the necks.
"""

from __future__ import annotations

import math

__all__ = ["tunnelling_doublets"]


def tunnelling_doublets(resolution, *, expression: str, eps: float, heights) -> dict:
    """The lowest doublet of the ellipse wall ``expression`` (parameter ``eps``) at each of ``heights``.

    Returns the splittings (Herring's flux formula, which subtracts no nearly equal eigenvalues), the
    largest relative difference between it and the direct difference λ₋ − λ₊ where that is above
    1e-7 λ (``agreement``), and the slope of ln Δλ against the WKB action S between consecutive heights
    (``wkb_slope``, 1 when Δλ ∝ exp(−S)).
    """
    from coinwall.forward.quantum import doublet_splitting
    from coinwall.forward.wall import Wall

    wall = Wall.from_expression(expression, {"eps": eps})
    splittings = [doublet_splitting(wall, H, cells=8) for H in heights]
    # compare where the difference is far above the eigenvalues' rounding (~1e-13 λ with shift-invert
    # ARPACK here): at 1e-7 λ the direct difference keeps about six digits on any BLAS
    both = [s for s in splittings if s.flux_trusted and s.direct > 1e-7 * s.lower]
    agreement = max(abs(s.direct - s.flux) / s.flux for s in both) if both else math.inf
    slopes = [math.log(a.flux / b.flux) / (b.action - a.action) for a, b in zip(splittings, splittings[1:])]
    return {"splittings": [s.flux for s in splittings], "agreement": agreement, "compared": len(both),
            "wkb_slope": sum(slopes) / len(slopes), "smallest": min(s.flux for s in splittings),
            "all_trusted": all(s.flux_trusted for s in splittings)}
