"""Level statistics: unfolded nearest-neighbour spacings per symmetry class, against Poisson and GOE.

Unfolding.  Levels of one class c of a group of order g are counted on average by
N̄_c(λ) = A λ/(4π g) + β_c √λ + γ_c: the area term is Weyl's (:mod:`.weyl`) divided by g; the √λ term
depends on the class (Dirichlet or Neumann on the symmetry lines), so β_c and γ_c are fitted by least
squares to the class's staircase.  The unfolded levels x_i = N̄_c(λ_i) have unit mean spacing; their
spacings s_i = x_{i+1} − x_i of all classes are pooled (each class is an independent spectrum; mixing the
classes before taking spacings would make any spectrum look Poissonian).

Reference distributions (cumulative): Poisson (integrable) 1 − e^(−s); GOE Wigner surmise (chaotic, time
reversal) 1 − e^(−πs²/4); Brody P_q(s) = (q + 1) a s^q e^(−a s^(q+1)), a = Γ((q + 2)/(q + 1))^(q+1), which
interpolates (q = 0 Poisson, q = 1 Wigner); q is fitted by maximum likelihood.  Berry–Robnik: a mixed phase
space with chaotic fraction ρ gives spacings between the two, which is what the ellipse family shows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..display import safe_repr

__all__ = [
    "SpacingStatistics",
    "brody_fit",
    "brody_pdf",
    "ks_distance",
    "level_statistics",
    "poisson_cdf",
    "unfold",
    "wigner_cdf",
]


def poisson_cdf(s):
    """Cumulative spacing distribution of uncorrelated levels, 1 − e^(−s)."""
    return 1.0 - np.exp(-np.asarray(s, dtype=float))


def wigner_cdf(s):
    """Cumulative GOE Wigner surmise, 1 − exp(−πs²/4)."""
    return 1.0 - np.exp(-0.25 * math.pi * np.asarray(s, dtype=float) ** 2)


def brody_pdf(s, q):
    """Brody's spacing density with parameter q (0: Poisson, 1: Wigner)."""
    a = math.gamma((q + 2.0) / (q + 1.0)) ** (q + 1.0)
    s = np.asarray(s, dtype=float)
    return (q + 1.0) * a * s**q * np.exp(-a * s ** (q + 1.0))


def ks_distance(spacings, cdf) -> float:
    """Kolmogorov–Smirnov distance sup |F_n − F| of the spacings from the cumulative ``cdf``."""
    s = np.sort(np.asarray(spacings, dtype=float))
    n = s.size
    if n == 0:
        return math.nan
    f = cdf(s)
    return float(max(np.max(np.arange(1, n + 1) / n - f), np.max(f - np.arange(n) / n)))


def brody_fit(spacings) -> float:
    """Maximum-likelihood Brody parameter q in [0, 1] of unit-mean spacings."""
    from scipy.optimize import minimize_scalar

    s = np.maximum(np.asarray(spacings, dtype=float), 1e-12)
    if s.size == 0:
        return math.nan
    result = minimize_scalar(lambda q: -float(np.sum(np.log(brody_pdf(s, q)))), bounds=(0.0, 1.0), method="bounded",
                             options={"xatol": 1e-6})
    return float(result.x)


def unfold(values, area, group_order):
    """Unfolded levels N̄_c(λ) of one class (module docstring): area term fixed, √λ and constant fitted."""
    values = np.sort(np.asarray(values, dtype=float))
    counts = np.arange(values.size) + 0.5
    leading = area * values / (4.0 * math.pi * group_order)
    if values.size < 3:
        return leading
    design = np.column_stack([np.sqrt(values), np.ones_like(values)])
    coefficients, *_ = np.linalg.lstsq(design, counts - leading, rcond=None)
    return leading + design @ coefficients


@dataclass(frozen=True, repr=False)
class SpacingStatistics:
    """Pooled unfolded nearest-neighbour spacings and their distances from Poisson and GOE.

    Attributes
    ----------
    spacings : ndarray
        Unfolded spacings of all classes (mean 1 up to the fit).
    classes : int
        How many classes were pooled.
    ks_poisson, ks_goe : float
        Kolmogorov–Smirnov distances from 1 − e^(−s) and from the Wigner surmise.
    brody : float
        Maximum-likelihood Brody parameter (0 Poisson, 1 Wigner).

    Examples
    --------
    >>> from coinwall import Wall, quantum_spectrum
    >>> from coinwall.forward.quantum import level_statistics
    >>> ellipse = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> level_statistics(quantum_spectrum(ellipse, H=3.0, levels=40, cells=6, order=2), skip=2)
    SpacingStatistics(14 spacings in 5 classes, KS Poisson 0.291, KS GOE 0.132, Brody q = 0.900)
    """

    spacings: np.ndarray
    classes: int
    ks_poisson: float
    ks_goe: float
    brody: float

    def to_dict(self) -> dict:
        """The fields as a JSON-ready dict."""
        return {"spacings": int(self.spacings.size), "classes": self.classes, "ks_poisson": self.ks_poisson,
                "ks_goe": self.ks_goe, "brody": self.brody}

    def plot(self, ax=None):
        """Histogram of the spacings with the Poisson, Wigner and fitted Brody densities."""
        from .figures import plot_spacings

        return plot_spacings(self, ax=ax)

    @safe_repr
    def __repr__(self) -> str:
        return (f"SpacingStatistics({self.spacings.size} spacings in {self.classes} classes, KS Poisson "
                f"{self.ks_poisson:.3f}, KS GOE {self.ks_goe:.3f}, Brody q = {self.brody:.3f})")


def level_statistics(spectrum, skip: int = 10) -> SpacingStatistics:
    """Spacing statistics of ``spectrum``, class by class, dropping each class's lowest ``skip`` levels
    (below them the smooth counting function is not yet a good unfolding).

    Parameters
    ----------
    spectrum : Spectrum
        A class-resolved spectrum (many levels: the statistics need hundreds).
    skip : int
        The lowest levels of each class left out.

    Returns
    -------
    SpacingStatistics

    Examples
    --------
    Far too few levels for a verdict, but the call is the same as for hundreds:

    >>> from coinwall import Wall
    >>> ellipse = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> from coinwall import quantum_spectrum
    >>> from coinwall.forward.quantum import level_statistics
    >>> spectrum = quantum_spectrum(ellipse, H=3.0, levels=40, cells=6, order=2)
    >>> stats = level_statistics(spectrum, skip=2)
    >>> stats.classes, stats.spacings.size
    (5, 14)
    """
    names = spectrum.classes
    # the classes of a strip that fell apart are its regions: equal areas (the swap maps one onto the other)
    group = 2 ** len(spectrum.symmetry_names) if spectrum.strip.periodic else len(spectrum.strip.regions)
    area = spectrum.strip.area
    pooled = []
    used = 0
    for name in sorted(set(names)):
        values = np.sort(spectrum.eigenvalues[np.array([c == name for c in names])])
        if values.size < skip + 3:
            continue
        x = unfold(values, area, group)[skip:]
        pooled.append(np.diff(x))
        used += 1
    spacings = np.concatenate(pooled) if pooled else np.empty(0)
    if spacings.size:
        spacings = spacings / np.mean(spacings)
    return SpacingStatistics(spacings, used, ks_distance(spacings, poisson_cdf), ks_distance(spacings, wigner_cdf),
                             brody_fit(spacings))
