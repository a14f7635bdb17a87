"""Weyl's law for the strip: the smooth counting function and the residual of a computed spectrum.

For the Dirichlet Laplacian on a plane domain of area A and boundary length L (Weyl; Kac; Stewartson
and Waechter), the number of eigenvalues below λ is on average

    N̄(λ) = A λ/(4π) − L √λ/(4π) + C,

with A and L measured in the (θ, η) metric (the billiard's Euclidean one).  The periodic strip is an
annulus with two smooth walls: C = 0 (χ/6 with Euler characteristic 0) plus, for walls with kinks, the
corner terms (π² − γ²)/(24πγ) of each corner of interior angle γ.  A kink of b at θ_k with one-sided
slopes s⁻, s⁺ is a corner of the lower wall at θ_k with γ = π − (atan s⁺ − atan s⁻) and a corner of the
upper wall at θ_k − π with the same γ (the upper wall is the lower one turned by the swap symmetry).
The stick (b = |cos θ|, slopes ∓1) has four corners of γ = π/2, C = 4·(1/16) = 1/4.
A strip that fell apart has a further corner at each tip where the walls meet, of interior angle
γ = atan hi' − atan lo' (left tip) or atan lo' − atan hi' (right tip).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..angles import TWO_PI
from ..display import safe_repr

__all__ = ["WeylCheck", "corner_constant", "weyl_check", "weyl_count"]


def _inside(strip, angle) -> bool:
    if strip.periodic:
        return True
    return any(a < t < b for a, b in strip.regions for t in (np.mod(angle, TWO_PI), np.mod(angle, TWO_PI) + TWO_PI))


def corner_constant(strip) -> float:
    """The constant term C of N̄(λ): the corner terms (module docstring) of the walls' kinks inside the
    strip and, for a strip that fell apart, of the tips where the two walls meet."""
    def term(gamma):
        return (math.pi**2 - gamma**2) / (24.0 * math.pi * gamma)

    total = 0.0
    for kink in strip.table.wall.kinks:
        gamma = math.pi - (math.atan(kink.slope_right) - math.atan(kink.slope_left))
        total += term(gamma) * (_inside(strip, kink.angle) + _inside(strip, kink.angle - math.pi))
    for a, b in strip.regions:
        _, slope_lo, _, slope_width = strip.walls(np.array([a, b]))
        slope_hi = slope_lo + slope_width
        total += term(math.atan(slope_hi[0]) - math.atan(slope_lo[0]))
        total += term(math.atan(slope_lo[1]) - math.atan(slope_hi[1]))
    return total


def weyl_count(strip, lam):
    """The smooth counting function N̄(λ) = Aλ/(4π) − L√λ/(4π) + C (0 for λ ≤ 0).

    Parameters
    ----------
    strip : Strip
    lam : float or ndarray
        λ (1/κ²).

    Returns
    -------
    float or ndarray
        N̄(λ), with A the strip's area, L the length of its walls and C its corner term.

    Examples
    --------
    The flat strip of width 1: A = 2π, L = 4π, so N̄(100) = 200π/(4π) − 40π/(4π) = 40.

    >>> from coinwall import Wall, make_strip
    >>> from coinwall.forward.quantum import weyl_count
    >>> round(float(weyl_count(make_strip(Wall.from_expression("1"), 3.0), 100.0)), 12)
    40.0
    """
    lam = np.maximum(np.asarray(lam, dtype=float), 0.0)
    return (strip.area * lam - strip.wall_length * np.sqrt(lam)) / (4.0 * math.pi) + corner_constant(strip)


@dataclass(frozen=True, repr=False)
class WeylCheck:
    """A spectrum's counting function against Weyl's.

    Attributes
    ----------
    area, wall_length, constant : float
        A, L and C of :func:`weyl_count`.
    eigenvalues : ndarray
    counts : ndarray
        N at each eigenvalue, counted at the middle of its step (i + 1/2 for the i-th level, 0-based).
    smooth : ndarray
        N̄ at each eigenvalue.
    residual : ndarray
        ``counts − smooth``.
    mean_residual, rms_residual, max_residual : float
        Mean, root mean square and largest absolute residual over the upper half of the levels (the lower
        half is where the asymptotic law is least expected to hold).

    Examples
    --------
    >>> from coinwall import Wall, quantum_spectrum
    >>> spectrum = quantum_spectrum(Wall.from_expression("1"), H=3.0, levels=4, cells=4, order=2)
    >>> from coinwall.forward.quantum import weyl_check
    >>> check = weyl_check(spectrum)
    >>> check.counts.tolist()                  # i + 1/2 at the i-th level
    [0.5, 1.5, 2.5, 3.5]
    """

    area: float
    wall_length: float
    constant: float
    eigenvalues: np.ndarray
    counts: np.ndarray
    smooth: np.ndarray
    residual: np.ndarray
    mean_residual: float
    rms_residual: float
    max_residual: float

    def to_dict(self) -> dict:
        """The fields as a JSON-ready dict."""
        return {"area": self.area, "wall_length": self.wall_length, "constant": self.constant,
                "mean_residual": self.mean_residual, "rms_residual": self.rms_residual,
                "max_residual": self.max_residual, "residual": [float(r) for r in self.residual]}

    def plot(self, ax=None):
        """The residual N − N̄ against λ."""
        from ..formats.figure import axes_or_new
        from ..formats.style import house_style

        with house_style():
            ax, created = axes_or_new(ax, (6, 3.5))
            ax.plot(self.eigenvalues, self.residual, ".", ms=3)
            ax.axhline(0.0, color="k", lw=0.6)
            ax.set_xlabel("eigenvalue λ (1/κ²)")
            ax.set_ylabel("N(λ) − N̄(λ) (levels)")
            ax.set_title(f"Weyl's law: residual of {np.size(self.eigenvalues)} levels (A = {self.area:.4g} κ², "
                         f"L = {self.wall_length:.4g} κ), rms {self.rms_residual:.3g}")
            if created:
                ax.figure.tight_layout()
        return ax.figure

    @safe_repr
    def __repr__(self) -> str:
        return (f"WeylCheck(A={self.area:.6g}, L={self.wall_length:.6g}, C={self.constant:.4g}, "
                f"residual mean {self.mean_residual:.3g}, rms {self.rms_residual:.3g}, max {self.max_residual:.3g})")


def weyl_check(spectrum) -> WeylCheck:
    """Compare the counting function of ``spectrum`` with N̄(λ) of its strip.

    Parameters
    ----------
    spectrum : Spectrum

    Returns
    -------
    WeylCheck

    Examples
    --------
    >>> from coinwall import Wall, quantum_spectrum
    >>> spectrum = quantum_spectrum(Wall.from_expression("1"), H=3.0, levels=4, cells=4, order=2)
    >>> from coinwall.forward.quantum import weyl_check
    >>> weyl_check(spectrum)
    WeylCheck(A=6.28319, L=12.5664, C=0, residual mean 0.321, rms 0.323, max 0.359)
    """
    strip = spectrum.strip
    values = np.asarray(spectrum.eigenvalues, dtype=float)
    counts = np.arange(values.size) + 0.5
    smooth = weyl_count(strip, values)
    residual = counts - smooth
    upper = residual[values.size // 2:] if values.size > 1 else residual
    return WeylCheck(strip.area, strip.wall_length, corner_constant(strip), values, counts, smooth, residual,
                     float(np.mean(upper)) if upper.size else math.nan,
                     float(np.sqrt(np.mean(upper**2))) if upper.size else math.nan,
                     float(np.max(np.abs(upper))) if upper.size else math.nan)
