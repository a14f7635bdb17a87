"""Which solver a spectrum gets by default: the fastest accurate one for the strip, and the digits it earns.

On the ε = 0.55 ellipse at H = 2.5 (``tests/benchmarks/bench_quantum_default.py``; its figures are in
docs/performance.md):

* The spectral method (:mod:`.spectral`) converges exponentially for a smooth wall on a strip open at
  every angle: 100 levels to ~1e-12 relative, against P2 elements' ~5e-5 in twice the time.  Solved class
  by class, it is faster than P4 elements from 10 to 1,000 levels, by a factor of about 4 at 1,000.  Its
  blocks are dense, so its cost grows like the cube of the number of modes: beyond
  :data:`SPECTRAL_MAX_MODES` the elements take over.
* Finite elements of degree 4 reach a given accuracy with far fewer unknowns than degree 2 (error
  ∝ h^8 instead of h^4): at the default mesh (:func:`.spectrum.default_cells`, ~1e-4 relative at the top
  level for every degree) P4 is both faster and more accurate than P2.
* A strip with a narrow neck (the walls nearly touch) needs many Fourier modes to follow the mapping
  there, and a wall with a kink or a jump in curvature gives Fourier modes only algebraic convergence:
  both go to P4 (which also refuses, with the height that fits, a neck too narrow to mesh).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["SPECTRAL_MAX_MODES", "SPECTRAL_MIN_NECK", "SolverChoice", "default_solver", "earned_digits",
           "spectral_error"]

#: Most modes (basis size) the default gives to the spectral method: 1,000 levels of the ε = 0.55 ellipse
#: need 9,367 at H = 2.5 and 12,069 at H = 2.2; a strip whose widest place is tiny (H just above the
#: body's diameter) would need millions, and goes to the elements, which refuse it with the height that fits.
SPECTRAL_MAX_MODES = 12_000
#: Narrowest neck, as a fraction of the widest place, that the default gives to the spectral method.
SPECTRAL_MIN_NECK = 0.25


@dataclass(frozen=True)
class SolverChoice:
    """The solver picked for a spectrum.

    Attributes
    ----------
    method : str
        ``"spectral"`` or ``"fem"``.
    order : int
        Element degree (4 for the finite elements; unused by the spectral method).
    accuracy : float
        The relative error its default resolution aims at for the highest level asked for (1e-8 for the
        spectral method's :func:`.spectrum.default_modes`, 1e-4 for :func:`.spectrum.default_cells`).
    why : str
        One line saying why, for the command line's report.
    """

    method: str
    order: int
    accuracy: float
    why: str


def default_solver(strip, levels: int, *, eigenvectors: bool = False) -> SolverChoice:
    """The fastest accurate solver for ``levels`` levels on ``strip``.

    Parameters
    ----------
    strip : Strip
        The billiard strip (:func:`.strip.make_strip`).
    levels : int
        How many levels are asked for.
    eigenvectors : bool
        Whether eigenvectors are needed (splittings, |ψ|²): only the finite elements give them.

    Returns
    -------
    SolverChoice
    """
    from .spectral import spectral_modes
    from .spectrum import default_modes

    wall = strip.table.wall
    if eigenvectors:
        why = "eigenvectors needed"
    elif wall.kinks or wall.breaks:
        why = "the wall has kinks or curvature jumps"
    elif not strip.periodic:
        why = "the strip falls apart"
    elif strip.width_min < SPECTRAL_MIN_NECK * strip.width_max:
        why = f"narrow neck (width {strip.width_min:.3g} of {strip.width_max:.3g})"
    elif _modes(strip, levels, spectral_modes, default_modes) > SPECTRAL_MAX_MODES:
        why = f"more than {SPECTRAL_MAX_MODES} modes"
    else:
        return SolverChoice("spectral", 4, 1e-8, "smooth wall, open strip")
    return SolverChoice("fem", 4, 1e-4, why)


def _modes(strip, levels, spectral_modes, default_modes):
    """Size of the spectral basis at the default resolution for ``levels`` levels."""
    M, N = spectral_modes(strip, default_modes(strip, levels))
    return (2 * M + 1) * N


def spectral_error(strip, values, cells: int, fewer: int = 4):
    """Relative error estimate of each of ``values``, the spectral method's levels at ``cells`` modes across.

    The same levels are solved again with ``fewer`` modes across (and the Fourier modes that follow, about
    40 % of the time at the default resolution); the relative difference estimates the coarser solve's
    error, hence bounds the finer one's for a method that converges exponentially.  On the ε = 0.55 ellipse
    at H = 2.5, 1,000 levels at the default 29 modes differ from 36 modes by 8.4e-6 at the top level and
    4e-14 in the median, which the default's ``accuracy`` line must say, not 1e-8.

    Parameters
    ----------
    strip : Strip
    values : ndarray
        The levels found with ``cells`` modes across (ascending).
    cells : int
        Their modes across.
    fewer : int
        How many fewer modes across the check uses.

    Returns
    -------
    ndarray
        ``|λ − λ_coarse| / |λ|`` per level.
    """
    import numpy as np

    from .spectrum import quantum_spectrum

    coarse = quantum_spectrum(strip, levels=len(values), method="spectral", cells=max(2, cells - fewer))
    values = np.asarray(values, dtype=float)
    count = min(values.size, coarse.eigenvalues.size)
    error = np.full(values.size, np.inf)
    error[:count] = np.abs(values[:count] - coarse.eigenvalues[:count]) / np.abs(values[:count])
    return error


def earned_digits(error: float) -> int:
    """Significant digits a value with relative error ``error`` carries (3 to 12)."""
    import math

    if not error > 0 or not math.isfinite(error):
        return 12 if error == 0 else 3
    return max(3, min(12, math.floor(-math.log10(error)) + 1))
