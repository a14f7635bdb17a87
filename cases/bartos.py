"""350,757 real caught flips (Bartoš et al. 2023) against the precessing coin of Diaconis, Holmes & Montgomery.

The counts per tosser ship with coinwall (``cases/data/coin-flips-bartos2023.csv``, provenance in
``cases/data/README.md``).  :func:`bartos_fits` turns them into the angle ψ between the angular momentum and
the coin's normal that the DHM model needs to produce them (:func:`coinwall.forward.dynamics.coin3d.caught.fit_psi`:
one ψ, or a spread of ψ about 90° with its σ; 95 % likelihood-ratio intervals), overall and per tosser, and
tests whether the tossers share one proportion (the likelihood-ratio test of 48 binomials against one, χ²
with 47 degrees of freedom).  :func:`plot_bartos` draws the data against the model.
"""

from __future__ import annotations

import csv
import importlib.resources
import io
from dataclasses import dataclass

import numpy as np

from coinwall.forward.display import safe_repr
from coinwall.forward.dynamics.coin3d.caught import PsiFit, dhm_same_side, fit_psi, likelihood_interval

__all__ = ["BartosFits", "bartos_counts", "bartos_fits", "plot_bartos"]

DATA = "data/coin-flips-bartos2023.csv"


def bartos_counts() -> dict:
    """The shipped counts: ``{"tosser": [...], "same": array, "flips": array, ...}`` (one entry per column)."""
    text = importlib.resources.files("coinwall.cases").joinpath(DATA).read_text(encoding="utf-8")
    rows = list(csv.DictReader(io.StringIO(text)))
    out = {"tosser": [r["tosser"] for r in rows]}
    for key in ("heads_same", "heads_diff", "tails_same", "tails_diff", "same", "flips"):
        out[key] = np.array([int(r[key]) for r in rows], dtype=np.int64)
    return out


@dataclass(frozen=True, repr=False)
class BartosFits:
    """``overall`` (:class:`PsiFit` of all flips), ``tossers`` (name → PsiFit), and the homogeneity test:
    ``lr_statistic`` (2 Δ log-likelihood of one proportion per tosser against one for all), ``dof`` and
    ``p_value`` (χ²)."""

    overall: PsiFit
    tossers: dict
    lr_statistic: float
    dof: int
    p_value: float

    def to_dict(self) -> dict:
        return {"overall": self.overall.to_dict(), "tossers": {k: v.to_dict() for k, v in self.tossers.items()},
                "homogeneity": {"lr_statistic": self.lr_statistic, "dof": self.dof, "p_value": self.p_value}}

    @safe_repr
    def __repr__(self):
        return (f"BartosFits({self.overall!r}; {len(self.tossers)} tossers, homogeneity χ²={self.lr_statistic:.1f} "
                f"on {self.dof} dof, p={self.p_value:.3g})")


def _loglik(k, n):
    p = k / n
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(k > 0, k * np.log(p), 0.0) + np.where(n - k > 0, (n - k) * np.log1p(-p), 0.0)


def bartos_fits() -> BartosFits:
    """ψ overall and per tosser, and the homogeneity test (see the module docstring)."""
    from scipy.stats import chi2

    data = bartos_counts()
    same, flips = data["same"], data["flips"]
    overall = fit_psi(int(same.sum()), int(flips.sum()))
    tossers = {name: fit_psi(int(k), int(n)) for name, k, n in zip(data["tosser"], same, flips)}
    stat = float(2 * (np.sum(_loglik(same, flips)) - _loglik(np.array(same.sum()), np.array(flips.sum()))))
    dof = len(tossers) - 1
    return BartosFits(overall, tossers, stat, dof, float(chi2.sf(stat, dof)))


def plot_bartos(fits: BartosFits | None = None):
    """Two panels: each tosser's same-side proportion with its 95 % interval against the DHM value of the
    overall ψ (and its interval); and DHM's curve P(ψ) with the data's ψ marked."""
    from coinwall.forward.formats.figure import new_figure
    from coinwall.forward.formats.style import PALETTE, house_style

    fits = bartos_fits() if fits is None else fits
    with house_style():
        fig, (ax, bx) = new_figure(1, 2, figsize=(11, 4.2), constrained_layout=True)
        names = sorted(fits.tossers, key=lambda k: fits.tossers[k].flips)
        y = np.arange(len(names))
        p = np.array([fits.tossers[k].p for k in names])
        # the tossers' own intervals, unclipped at ½ (the data may fall below; the model cannot)
        lo, hi = np.array([likelihood_interval(fits.tossers[k].same, fits.tossers[k].flips) for k in names]).T
        ax.errorbar(p, y, xerr=[p - lo, hi - p], fmt="o", ms=3, color=PALETTE[0], lw=0.8,
                    label="tosser: same-side share, 95 % interval")
        o = fits.overall
        ax.axvspan(o.p_low, o.p_high, color=PALETTE[1], alpha=0.25,
                   label=f"all {o.flips:,} flips: {o.p:.4f} → ψ = {o.psi:.1f}° [{o.psi_low:.1f}, {o.psi_high:.1f}]")
        ax.axvline(0.5, color="k", lw=0.8, ls="--", label="fair coin")
        ax.set_yticks(y, [f"{k} ({fits.tossers[k].flips:,})" for k in names], fontsize=5)
        ax.set_xlabel("P(same side) (dimensionless)")
        ax.set_ylabel("tosser (flips), by number of flips")
        ax.set_title(f"Bartoš et al. (2023): 48 tossers, homogeneity p = {fits.p_value:.2g}")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1)
        psi = np.linspace(45, 90, 400)
        bx.plot(psi, dhm_same_side(np.radians(psi)), color=PALETTE[0], label="DHM: ½ + arcsin(cot²ψ)/π")
        bx.axhspan(o.p_low, o.p_high, color=PALETTE[1], alpha=0.25, label="all flips, 95 % interval")
        bx.axvspan(o.psi_low, o.psi_high, color=PALETTE[1], alpha=0.25)
        # wide enough for every tosser's P(same side) and its ψ on the curve (the most precessing is near 61°)
        top = max(0.62, float(np.max(p)) + 0.01)
        bx.set_ylim(0.49, top)
        curve = dhm_same_side(np.radians(psi))  # falls with ψ: the first ψ below the top of the axis
        bx.set_xlim(min(65.0, float(psi[np.argmax(curve <= top)]) - 1.0), 90)
        bx.set_xlabel("ψ, angle between angular momentum and normal (degrees)")
        bx.set_ylabel("P(same side) (dimensionless)")
        bx.set_title("the caught coin's precession (DHM 2007)")
        bx.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1)
    return fig

