"""Heads–tails tunnelling: the splitting of the lowest doublet just above H = D, three ways.

Just above the diameter D the strip's heads and tails halves are joined by two necks of width H − D
around θ_n and θ_n + π (:attr:`.strip.Strip.neck`); the low levels come in pairs ψ₊, ψ₋ (different
symmetry classes) whose splitting Δλ = λ₋ − λ₊ is exponentially small.

* **direct**: the difference of the two eigenvalues, each from its own class problem.  Each carries a
  rounding error of about ε·λ (ε = 2.2e-16, times the solver's few digits): trusted only where
  Δλ > :data:`DIRECT_FLOOR`·λ.
* **flux** (Herring's formula, exact for the discrete problem, no subtraction of nearly equal numbers).
  With A the half of the strip θ_n < θ < θ_n + π and K_A, M_A the stiffness and mass matrices of its
  elements only, for the two eigenvectors

      ψ₊ᵀ(K_A − λ₋M_A)ψ₋ − ψ₋ᵀ(K_A − λ₊M_A)ψ₊ = (λ₊ − λ₋) ψ₊ᵀM_Aψ₋.

  A row of (K_A − λM_A)ψ vanishes inside A (ψ is an eigenvector) and outside A (no element), so the
  left side is a sum over the degrees of freedom on the two cut lines θ_n, θ_n + π only: the discrete
  flux ∮(ψ₊∂ₙψ₋ − ψ₋∂ₙψ₊) through the necks.  Every term is a product of the small values of the states
  in the necks, so its rounding is relative to them, not to λ:

      Δλ = −Σ_{i on the cuts} [ψ₊ᵢ ((K_A − λ₋M_A)ψ₋)ᵢ − ψ₋ᵢ ((K_A − λ₊M_A)ψ₊)ᵢ] / ψ₊ᵀM_Aψ₋.

  It is as accurate as the eigenvectors' values in the necks (absolute error ~1e-16 of their maximum),
  so it reaches splittings near 1e-26·λ where the direct difference stops near 1e-12·λ.
* **WKB**: the adiabatic transverse mode sin(π(η − lo)/w) gives the state a local decay rate
  √((π/w(θ))² − λ) where (π/w)² > λ; through one neck the amplitude falls by exp(−S/2) on each side, so
  Δλ ∝ exp(−S) with S = ∫ √((π/w)² − λ) dθ over the forbidden interval around the neck.  It holds when
  the neck is long compared with its width (the adiabatic condition |w'| ≪ 1 there), i.e. as H → D⁺.

The physical tunnelling time is ħ/ΔE with ΔE = ħ²Δλ/(2Mκ²): t = 2Mκ²/(ħ Δλ) (:func:`tunnelling_time`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..angles import TWO_PI
from ..display import safe_repr
from ..errors import InvalidArgument

__all__ = ["DIRECT_FLOOR", "FLUX_FLOOR", "HBAR", "Splitting", "doublet_splitting", "splitting_of", "tunnelling_time",
           "wkb_action"]

#: reduced Planck constant, J·s (CODATA 2018, exact)
HBAR = 1.054571817e-34
#: the direct difference is trusted where Δλ > DIRECT_FLOOR·λ (the class solves' eigenvalues differ by up to
#: ~1e-12·λ from rounding alone: 2.9e-11 at λ = 50 on the ε = 0.55 ellipse at H = 2.1)
DIRECT_FLOOR = 1e-11
#: the flux is trusted where the states' largest value on the cuts exceeds FLUX_FLOOR times their maximum
#: (the eigenvectors' absolute rounding is ~1e-16 of the maximum; at 1e-14 the neck values keep 2 digits)
FLUX_FLOOR = 1e-14


@dataclass(frozen=True, repr=False)
class Splitting:
    """The splitting of one low doublet.

    Attributes
    ----------
    H, gap : float
        Wall distance and H − D (the neck's width).
    lower, upper : float
        λ₊ and λ₋.
    classes : tuple of str
        Their symmetry classes.
    direct, flux : float
        λ₋ − λ₊ as a difference and by Herring's flux formula (module docstring); the flux is nan (and not
        trusted) when the two levels are of one class, as the formula needs a pair of different classes.
    direct_trusted : bool
        Whether ``direct`` is above :data:`DIRECT_FLOOR`·λ.
    flux_trusted : bool
        Whether the states' values in the necks are above :data:`FLUX_FLOOR` of their maximum.
    neck_amplitude : float
        Largest ``|ψ|`` on the cuts and their neighbouring dofs over the largest ``|ψ|`` anywhere (the smaller
        of the two states').
    action : float
        The WKB action S through one neck at λ₊ (Δλ ∝ exp(−S)).
    dofs, cells : int

    Examples
    --------
    >>> from coinwall import Wall
    >>> ellipse = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> from coinwall import doublet_splitting
    >>> split = doublet_splitting(ellipse, 2.3, cells=4, order=2)
    >>> round(split.gap, 12), split.classes[0] != split.classes[1]
    (0.3, True)
    """

    H: float
    gap: float
    lower: float
    upper: float
    classes: tuple
    direct: float
    flux: float
    direct_trusted: bool
    flux_trusted: bool
    neck_amplitude: float
    action: float
    dofs: int
    cells: int

    def to_dict(self) -> dict:
        """The fields as a JSON-ready dict."""
        return {"H": self.H, "gap": self.gap, "lower": self.lower, "upper": self.upper, "classes": list(self.classes),
                "direct": self.direct, "flux": self.flux if math.isfinite(self.flux) else None,
                "direct_trusted": self.direct_trusted,
                "flux_trusted": self.flux_trusted, "neck_amplitude": self.neck_amplitude,
                "wkb_action": self.action, "dofs": self.dofs, "cells": self.cells}

    @safe_repr
    def __repr__(self) -> str:
        return (f"Splitting(H={self.H:.6g}, gap {self.gap:.3g}: λ {self.lower:.8g}, direct {self.direct:.4g}"
                f"{'' if self.direct_trusted else ' (rounding)'}, flux {self.flux:.4g}"
                f"{'' if self.flux_trusted else ' (rounding)'}, WKB exp(−S) {math.exp(-self.action):.3g})")


def wkb_action(strip, lam, points: int = 20001) -> float:
    """S = ∫ √((π/w)² − λ) dθ over the forbidden interval (π/w)² > λ containing the neck (0 if there is none).

    Parameters
    ----------
    strip : Strip
    lam : float
        The level λ (1/κ²).
    points : int
        Quadrature points over the period.

    Returns
    -------
    float
        S, so that the splitting goes as ``exp(−S)``.

    Examples
    --------
    >>> from coinwall import Wall
    >>> ellipse = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> from coinwall import make_strip
    >>> from coinwall.forward.quantum import wkb_action
    >>> round(wkb_action(make_strip(ellipse, 2.3), 17.71455), 3)
    12.449
    """
    theta = strip.neck + np.linspace(-0.5 * math.pi, 0.5 * math.pi, points)
    width = strip.width(theta)
    rate2 = np.where(width > 0, (math.pi / np.maximum(width, 1e-300)) ** 2 - lam, np.inf)
    centre = points // 2
    if rate2[centre] <= 0:
        return 0.0
    left = centre
    while left > 0 and rate2[left - 1] > 0:
        left -= 1
    right = centre
    while right < points - 1 and rate2[right + 1] > 0:
        right += 1
    rate = np.sqrt(np.maximum(rate2[left:right + 1], 0.0))
    return float(np.sum(0.5 * (rate[1:] + rate[:-1]) * np.diff(theta[left:right + 1])))


def tunnelling_time(delta_lambda, mass, kappa):
    """ħ/ΔE in seconds for a splitting ``delta_lambda`` (1/κ²), ``mass`` in kg and ``kappa`` in m.

    Parameters
    ----------
    delta_lambda : float
        The splitting Δλ (1/κ²).
    mass : float
        The body's mass (kg).
    kappa : float
        Its radius of gyration (m).

    Returns
    -------
    float
        ħ/ΔE in seconds, with ``ΔE = ħ² Δλ / (2 m κ²)``.

    Examples
    --------
    A 1 g body with κ = 1 cm and a splitting of 10⁻³/κ² would tunnel between heads and tails once in
    about 10³⁰ s:

    >>> from coinwall.forward.quantum import tunnelling_time
    >>> f"{tunnelling_time(1e-3, 1e-3, 1e-2):.2e}"
    '1.90e+30'
    """
    return 2.0 * mass * kappa**2 / (HBAR * np.asarray(delta_lambda, dtype=float))


def _half_matrices(mesh, cut):
    """Stiffness and mass matrices of the elements of the half θ_cut < θ < θ_cut + π (free dofs)."""
    from dataclasses import replace

    from skfem import Basis

    from .fem import assemble

    centres = mesh.mesh.p[0, mesh.mesh.t].mean(axis=0)
    inside = np.flatnonzero(np.mod(centres - cut, TWO_PI) < math.pi)
    # the same element and quadrature as the whole mesh (mesh.strip_mesh), on the elements of the half only
    half = Basis(mesh.mesh, mesh.basis.elem, intorder=2 * mesh.order + 2, elements=inside)
    return assemble(replace(mesh, basis=half))


def doublet_splitting(wall, H, b0: float = 0.0, *, pair: int = 0, cells: int = 8, order: int = 2) -> Splitting:
    """The splitting of the ``pair``-th lowest doublet (levels 2·pair, 2·pair + 1) at wall distance ``H``.

    Parameters
    ----------
    wall : Wall
    H, b0 : float
        The table; H must exceed the diameter (the strip must be open at the necks).
    pair : int
        0 for the lowest doublet.
    cells, order : int
        Mesh rows across and element degree (:func:`.mesh.strip_mesh`); the columns follow the neck's
        width, so its decay is resolved at every H.

    Returns
    -------
    Splitting

    Raises
    ------
    InvalidArgument
        When ``H`` is not above the body's diameter (the strip fell apart at its necks).

    Examples
    --------
    The ellipse's lowest heads–tails doublet at ``H = 2.3`` (necks 0.3 wide): the direct difference and
    Herring's flux formula agree.

    >>> from coinwall import Wall
    >>> ellipse = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> from coinwall import doublet_splitting
    >>> split = doublet_splitting(ellipse, 2.3, cells=4, order=2)
    >>> f"{split.direct:.3e} {split.flux:.3e}"
    '2.068e-05 2.068e-05'
    """
    from .spectrum import quantum_spectrum
    from .strip import make_strip

    strip = make_strip(wall, H, b0)
    if not strip.periodic:
        raise InvalidArgument(f"`H` = {H:g} is not above the diameter {strip.diameter:.12g}: the strip fell apart, "
                              "and there is no tunnelling between separate regions")
    return splitting_of(quantum_spectrum(strip, levels=2 * pair + 2, method="fem", cells=cells, order=order), pair)


def splitting_of(spectrum, pair: int = 0) -> Splitting:
    """The :class:`Splitting` of levels 2·pair and 2·pair + 1 of a periodic, class-resolved ``spectrum``.

    Parameters
    ----------
    spectrum : Spectrum
        A class-resolved spectrum of a periodic strip.
    pair : int
        0 for the lowest doublet.

    Returns
    -------
    Splitting

    Raises
    ------
    InvalidArgument
        When the spectrum has too few class-resolved levels for that pair.

    Examples
    --------
    >>> from coinwall import Wall
    >>> ellipse = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> from coinwall import quantum_spectrum
    >>> from coinwall.forward.quantum import splitting_of
    >>> split = splitting_of(quantum_spectrum(ellipse, H=2.3, levels=4, cells=4, order=2))
    >>> f"{split.direct:.3e}"
    '2.068e-05'
    """
    strip = spectrum.strip
    k = 2 * pair
    spectrum.require_vectors("the splitting of a pair")
    if not strip.periodic or len(spectrum) < k + 2 or not spectrum.symmetry_names:
        raise InvalidArgument(f"`pair` = {pair}: needs {k + 2} class-resolved levels of a periodic strip")
    lower, upper = (float(v) for v in spectrum.eigenvalues[k:k + 2])
    plus, minus = spectrum.vectors[k], spectrum.vectors[k + 1]
    mesh = spectrum.meshes[0]
    cut = float(mesh.theta[np.argmin(np.abs(mesh.theta - strip.neck))])
    stiffness, mass = _half_matrices(mesh, cut)
    x = mesh.free_locations[0]
    on_cut = np.flatnonzero((np.abs(x - cut) < 1e-9) | (np.abs(x - np.mod(cut + math.pi, TWO_PI)) < 1e-9)
                            | (np.abs(x - cut - TWO_PI) < 1e-9))
    rows_k, rows_m = stiffness[on_cut], mass[on_cut]
    residual_minus = rows_k @ minus - upper * (rows_m @ minus)
    residual_plus = rows_k @ plus - lower * (rows_m @ plus)
    flux = float(plus[on_cut] @ residual_minus - minus[on_cut] @ residual_plus)
    overlap = float(plus @ (mass @ minus))
    classes = tuple(spectrum.classes[k:k + 2])
    # two levels of one class are M-orthogonal on A as well, to rounding: the identity then says nothing
    delta = -flux / overlap if classes[0] != classes[1] and overlap != 0 else math.nan
    if delta < 0:  # below rounding the solver may order the pair either way: the flux says which is lower
        lower, upper, delta, classes = upper, lower, -delta, classes[::-1]
    near = np.unique(rows_k.indices)  # the cuts and their neighbours: a state odd about a cut vanishes on it
    amplitude = min(float(np.max(np.abs(v[near])) / np.max(np.abs(v))) for v in (plus, minus))
    if not math.isfinite(delta):
        amplitude = 0.0
    return Splitting(strip.H, float(strip.width_min), lower, upper, classes, upper - lower, delta,
                     abs(upper - lower) > DIRECT_FLOOR * upper, amplitude > FLUX_FLOOR, amplitude,
                     wkb_action(strip, lower), spectrum.dofs, spectrum.cells)
