"""350,757 real caught flips (Bartoš et al. 2023) against the precessing coin of Diaconis, Holmes & Montgomery.

The counts per tosser ship with coinwall (``cases/data/coin-flips-bartos2023.csv``, provenance in
``cases/data/README.md``).  :func:`bartos_fits` turns them into the angle ψ between the angular momentum and
the coin's normal that the DHM model needs to produce them (:func:`coinwall.forward.dynamics.coin3d.caught.fit_psi`:
one ψ, or a spread of ψ about 90° with its σ; 95 % likelihood-ratio intervals), overall and per tosser, and
tests whether the tossers share one proportion (the likelihood-ratio test of 48 binomials against one, χ²
with 47 degrees of freedom).  They do not (χ² ≈ 266, p ≈ 1e-32): the 350,757 flips are 48 people's, each
with a proportion of his own, so the binomial interval of all the flips pooled is too narrow for "the" ψ of
a toss.  Beside it the overall fit is given with the spread between tossers allowed for
(``overall_overdispersed``: the quasi-binomial interval, its dispersion φ = Pearson's χ²/47 ≈ 5.6,
:func:`coinwall.forward.dynamics.coin3d.caught.overdispersion`), about 2.5 times wider in ψ.
:func:`plot_bartos` draws the data against the model.
"""

from __future__ import annotations

import csv
import importlib.resources
import io
from dataclasses import dataclass

import numpy as np

from coinwall.forward.display import safe_repr
from coinwall.forward.dynamics.coin3d.caught import PsiFit, dhm_same_side, fit_psi, likelihood_interval, overdispersion

__all__ = ["BartosFits", "bartos_counts", "bartos_fits", "plot_bartos"]

DATA = "data/coin-flips-bartos2023.csv"


def bartos_counts() -> dict:
    """The shipped counts: ``{"tosser": [...], "same": array, "flips": array, ...}`` (one entry per column).

    Returns
    -------
    dict
        Tosser names and, per tosser, the counts of same-side landings, flips, and heads/tails by start side.

    Examples
    --------
    >>> from coinwall.cases import bartos_counts
    >>> counts = bartos_counts()
    >>> len(counts["tosser"]), int(counts["same"].sum()), int(counts["flips"].sum())
    (48, 178078, 350757)
    """
    text = importlib.resources.files("coinwall.cases").joinpath(DATA).read_text(encoding="utf-8")
    rows = list(csv.DictReader(io.StringIO(text)))
    out = {"tosser": [r["tosser"] for r in rows]}
    for key in ("heads_same", "heads_diff", "tails_same", "tails_diff", "same", "flips"):
        out[key] = np.array([int(r[key]) for r in rows], dtype=np.int64)
    return out


@dataclass(frozen=True, repr=False)
class BartosFits:
    """The flips against the DHM model.

    Attributes
    ----------
    overall : PsiFit
        All flips as one binomial (the interval of a single tosser who made them all).
    overall_overdispersed : PsiFit
        All flips with the spread between tossers allowed for (quasi-binomial, ``dispersion``): the interval
        for the ψ of a toss by people like these.
    tossers : dict
        Tosser name → :class:`PsiFit` of his flips.
    lr_statistic, dof, p_value : float, int, float
        The homogeneity test: 2 Δ log-likelihood of one proportion per tosser against one for all, on ``dof``
        degrees of freedom, and its χ² p-value.
    pearson_statistic, dispersion : float
        Pearson's χ² of the tossers against the pooled proportion and φ = ``pearson_statistic / dof``.

    Examples
    --------
    >>> from coinwall.cases import bartos_fits
    >>> fits = bartos_fits()
    >>> len(fits.tossers), fits.dof, fits.p_value < 1e-6        # the tossers differ
    (48, 47, True)
    """

    overall: PsiFit
    tossers: dict
    lr_statistic: float
    dof: int
    p_value: float
    overall_overdispersed: PsiFit
    pearson_statistic: float
    dispersion: float

    def to_dict(self) -> dict:
        """The fits and tests as a JSON-ready dict."""
        return {"overall": self.overall.to_dict(), "overall_overdispersed": self.overall_overdispersed.to_dict(),
                "tossers": {k: v.to_dict() for k, v in self.tossers.items()},
                "homogeneity": {"lr_statistic": self.lr_statistic, "dof": self.dof, "p_value": self.p_value,
                                "pearson_statistic": self.pearson_statistic, "dispersion": self.dispersion}}

    @safe_repr
    def __repr__(self):
        wide = self.overall_overdispersed
        return (f"BartosFits({self.overall!r}; with the spread between tossers ψ in [{wide.psi_low:.2f}, "
                f"{wide.psi_high:.2f}]; {len(self.tossers)} tossers, homogeneity χ²={self.lr_statistic:.1f} "
                f"on {self.dof} dof, p={self.p_value:.3g}, dispersion {self.dispersion:.2f})")


def _loglik(k, n):
    p = k / n
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(k > 0, k * np.log(p), 0.0) + np.where(n - k > 0, (n - k) * np.log1p(-p), 0.0)


def bartos_fits() -> BartosFits:
    """ψ overall (binomial, and with the spread between tossers) and per tosser, and the homogeneity test.

    Returns
    -------
    BartosFits

    Examples
    --------
    >>> fits = bartos_fits()
    >>> round(fits.overall.psi, 2), fits.dof
    (81.16, 47)
    >>> binomial, spread = fits.overall, fits.overall_overdispersed
    >>> round((spread.psi_high - spread.psi_low) / (binomial.psi_high - binomial.psi_low), 1)
    2.5
    """
    from scipy.stats import chi2

    data = bartos_counts()
    same, flips = data["same"], data["flips"]
    overall = fit_psi(int(same.sum()), int(flips.sum()))
    tossers = {name: fit_psi(int(k), int(n)) for name, k, n in zip(data["tosser"], same, flips)}
    stat = float(2 * (np.sum(_loglik(same, flips)) - _loglik(np.array(same.sum()), np.array(flips.sum()))))
    dispersion, pearson, dof = overdispersion(same, flips)
    spread = fit_psi(int(same.sum()), int(flips.sum()), dispersion=dispersion, dof=dof)
    return BartosFits(overall, tossers, stat, dof, float(chi2.sf(stat, dof)), spread, pearson, dispersion)


def plot_bartos(fits: BartosFits | None = None):
    """Two panels: each tosser's same-side proportion with its 95 % interval against the DHM value of the
    overall ψ, with the interval of all flips as one binomial and with the spread between tossers; and DHM's
    curve P(ψ) with both intervals of the data's ψ marked.

    Parameters
    ----------
    fits : BartosFits, optional
        Default :func:`bartos_fits`.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> fig = plot_bartos()
    >>> [ax.get_xlabel().split(" (")[0] for ax in fig.axes]
    ['P(same side)', 'ψ, angle between angular momentum and normal']
    """
    from coinwall.forward.formats.figure import new_figure
    from coinwall.forward.formats.style import PALETTE, house_style, legend_below

    fits = bartos_fits() if fits is None else fits
    with house_style():
        fig, (ax, bx) = new_figure(1, 2, figsize=(12, 5.2), constrained_layout=True)
        names = sorted(fits.tossers, key=lambda k: fits.tossers[k].flips)
        y = np.arange(len(names))
        p = np.array([fits.tossers[k].p for k in names])
        # the tossers' own intervals, unclipped at ½ (the data may fall below; the model cannot)
        lo, hi = np.array([likelihood_interval(fits.tossers[k].same, fits.tossers[k].flips) for k in names]).T
        ax.errorbar(p, y, xerr=[p - lo, hi - p], fmt="o", ms=3, color=PALETTE[0], lw=0.8,
                    label="tosser: same-side share, 95 % interval")
        o, w = fits.overall, fits.overall_overdispersed
        ax.axvspan(w.p_low, w.p_high, color=PALETTE[4], alpha=0.22,
                   label=f"with the spread between tossers (φ = {fits.dispersion:.2f}): ψ in [{w.psi_low:.1f}°, "
                         f"{w.psi_high:.1f}°]")
        ax.axvspan(o.p_low, o.p_high, color=PALETTE[1], alpha=0.35,
                   label=f"all {o.flips:,} flips as one binomial: {o.p:.4f} → ψ = {o.psi:.1f}° "
                         f"[{o.psi_low:.1f}°, {o.psi_high:.1f}°]")
        ax.axvline(0.5, color="k", lw=0.8, ls="--", label="fair coin")
        ax.set_yticks(y, [f"{k} ({fits.tossers[k].flips:,})" for k in names], fontsize=5)
        ax.set_xlabel("P(same side) (dimensionless)")
        ax.set_ylabel("tosser (flips), by number of flips")
        ax.set_title(f"Bartoš et al. (2023): 48 tossers, homogeneity χ² = {fits.lr_statistic:.0f} on {fits.dof} "
                     f"dof (p = {fits.p_value:.2g})")
        legend_below(ax, ncol=1)
        psi = np.linspace(45, 90, 400)
        bx.plot(psi, dhm_same_side(np.radians(psi)), color=PALETTE[0], label="DHM: ½ + arcsin(cot²ψ)/π")
        bx.axhspan(w.p_low, w.p_high, color=PALETTE[4], alpha=0.22, label="all flips, with the spread between tossers")
        bx.axvspan(w.psi_low, w.psi_high, color=PALETTE[4], alpha=0.22)
        bx.axhspan(o.p_low, o.p_high, color=PALETTE[1], alpha=0.35, label="all flips as one binomial, 95 %")
        bx.axvspan(o.psi_low, o.psi_high, color=PALETTE[1], alpha=0.35)
        # wide enough for every tosser's P(same side) and its ψ on the curve (the most precessing is near 61°)
        top = max(0.62, float(np.max(p)) + 0.01)
        bx.set_ylim(0.49, top)
        curve = dhm_same_side(np.radians(psi))  # falls with ψ: the first ψ below the top of the axis
        bx.set_xlim(min(65.0, float(psi[np.argmax(curve <= top)]) - 1.0), 90)
        bx.set_xlabel("ψ, angle between angular momentum and normal (degrees)")
        bx.set_ylabel("P(same side) (dimensionless)")
        bx.set_title("the caught coin's precession (DHM 2007)")
        legend_below(bx, ncol=1)
    return fig
