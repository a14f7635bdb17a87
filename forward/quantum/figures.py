"""Pictures of the quantum coin: |ψ|² in the strip, the orientation probability, the counting function with
Weyl's curve, the spacing histogram and the doublet splitting on a log scale.  Each function returns a
matplotlib figure (Agg backend, :func:`coinwall.forward.formats.figure.new_figure`) or draws on ``ax``, in the house
style (:mod:`coinwall.forward.formats.style`), titled with the wall (``name`` as the user wrote it, else the wall's
description and parameters), H and the counts."""

from __future__ import annotations

import math

import numpy as np

from ..formats.figure import axes_or_new
from ..formats.style import plain_log_axis, styled, wall_label

__all__ = [
    "level_density",
    "level_grid",
    "orientation_probability",
    "plot_counting",
    "plot_density",
    "plot_orientation",
    "plot_spacings",
    "plot_splittings",
]


def level_grid(spectrum, level: int):
    """``(theta, eta, density, triangles)`` of |ψ|² at the mesh vertices of level ``level`` (physical coordinates)."""
    spectrum.require_vectors("|ψ|²")
    mesh = spectrum.meshes[int(spectrum.domain[level])]
    values = mesh.reduce @ spectrum.vectors[level]
    vertex = values[mesh.basis.nodal_dofs[0]]
    theta, s = mesh.mesh.p
    lo, _, width, _ = spectrum.strip.walls(theta)
    return theta, lo + s * width, vertex**2, mesh.mesh.t.T


def level_density(spectrum, level: int, columns: int = 721, rows: int = 97):
    """``(theta, eta, density)``: |ψ|² of level ``level`` on a regular grid of the strip, ``columns`` angles over
    the mesh's θ range by ``rows`` heights from wall to wall, each value the finite-element solution itself
    (its P2–P4 polynomial on the triangle that holds the point), not an interpolation between mesh vertices.

    Parameters
    ----------
    spectrum : Spectrum
        A spectrum with eigenvectors (``method="fem"``).
    level : int
        Which level (0 is the lowest).
    columns, rows : int
        Grid points along θ and across the strip.

    Returns
    -------
    theta, eta, density : ndarray, shape (columns, rows)
        Physical coordinates of the grid points (η = lower wall + s · width) and |ψ|² there.

    Raises
    ------
    InvalidArgument
        When the spectrum holds no eigenvectors.

    Examples
    --------
    >>> from coinwall import Wall, quantum_spectrum
    >>> spectrum = quantum_spectrum(Wall.from_expression("1"), H=3.0, levels=1, cells=2, order=2)
    >>> theta, eta, density = level_density(spectrum, 0, columns=9, rows=5)
    >>> density.shape, bool(density.min() >= 0)
    ((9, 5), True)
    """
    from matplotlib.tri import Triangulation

    spectrum.require_vectors("|ψ|²")
    mesh = spectrum.meshes[int(spectrum.domain[level])]
    values = mesh.reduce @ spectrum.vectors[level]
    grid_theta, grid_s = np.meshgrid(np.linspace(mesh.theta[0], mesh.theta[-1], columns), np.linspace(0.0, 1.0, rows),
                                     indexing="ij")
    points = np.array([grid_theta.ravel(), grid_s.ravel()])
    # the triangle of each point (matplotlib's trapezoid map: skfem's own finder tries every triangle for points
    # on an edge, seconds for a figure), then the element's basis there: skfem's CellBasis.probes, row by row
    cells = Triangulation(*mesh.mesh.p, mesh.mesh.t.T).get_trifinder()(*points)
    basis = mesh.basis
    local = basis.mapping.invF(points[:, :, np.newaxis], tind=cells)
    field = np.zeros(points.shape[1])
    for k in range(basis.Nbfun):
        phi = np.asarray(basis.elem.gbasis(basis.mapping, local, k, tind=cells)[0])[:, 0]
        field += phi * values[basis.element_dofs[k, cells]]
    lo, _, width, _ = spectrum.strip.walls(grid_theta.ravel())
    eta = (lo + grid_s.ravel() * width).reshape(grid_theta.shape)
    return grid_theta, eta, (field**2).reshape(grid_theta.shape)


def orientation_probability(spectrum, level: int):
    """``(theta, P)``: P(θ) = ∫|ψ|² dη at the mesh columns (trapezoid across; ∫P dθ ≈ 1)."""
    spectrum.require_vectors("P(θ)")
    mesh = spectrum.meshes[int(spectrum.domain[level])]
    values = mesh.reduce @ spectrum.vectors[level]
    vertex = values[mesh.basis.nodal_dofs[0]].reshape(mesh.theta.size, mesh.s.size)
    _, _, width, _ = spectrum.strip.walls(mesh.theta)
    ds = np.diff(mesh.s)
    across = np.sum(0.5 * (vertex[:, 1:] ** 2 + vertex[:, :-1] ** 2) * ds, axis=1)
    return mesh.theta, across * width


def _about(spectrum, name=None) -> str:
    """The wall, H and b0 of a spectrum's strip, for a title."""
    strip = spectrum.strip
    return f"{wall_label(strip.table.wall, name)}, H = {strip.H:g} κ"


def _angle_ticks(ax):
    ax.set_xlim(0.0, 2.0 * math.pi)
    ax.set_xticks([k * 0.5 * math.pi for k in range(5)], ["0", "π/2", "π", "3π/2", "2π"])


@styled
def plot_density(spectrum, level: int = 0, ax=None, name=None):
    """|ψ|² of level ``level`` in the (θ, η) strip, with both walls and a colour bar.

    The field is drawn from the finite-element solution on a fine regular grid of the strip
    (:func:`level_density`), so the picture shows the solution, not the mesh's triangles."""
    spectrum.require_vectors("|ψ|²")  # before a figure is made
    ax, created = axes_or_new(ax, (8, 3.2))
    theta, eta, density = level_density(spectrum, level)
    image = ax.pcolormesh(theta, eta, density, shading="gouraud", cmap="magma", rasterized=True)
    bar = ax.figure.colorbar(image, ax=ax, pad=0.015)
    bar.set_label("|ψ|² (1/(rad·κ); ∫|ψ|² dθ dη = 1)")
    grid = np.linspace(0.0, 2.0 * math.pi, 1000)
    strip = spectrum.strip
    ax.plot(grid, strip.lo(grid), "k", lw=0.8)
    ax.plot(grid, strip.hi(grid), "k", lw=0.8)
    ax.grid(False)
    _angle_ticks(ax)
    ax.set_xlabel("orientation θ (rad)")
    ax.set_ylabel("height of the centre η (κ)")
    ax.set_title(f"|ψ|² of level {level + 1} ({spectrum.classes[level]}), "
                 f"λ = {spectrum.eigenvalues[level]:.6g} /κ²\n"
                 f"{_about(spectrum, name)}")
    if created:
        ax.figure.tight_layout()
    return ax.figure


@styled
def plot_orientation(spectrum, levels=(0, 1), ax=None, name=None):
    """The probability density of the body's orientation θ for the given levels."""
    spectrum.require_vectors("P(θ)")  # before a figure is made
    ax, created = axes_or_new(ax, (6, 3.8))
    for level in levels:
        theta, density = orientation_probability(spectrum, level)
        ax.plot(theta, density, label=f"level {level + 1} ({spectrum.classes[level]})")
    _angle_ticks(ax)
    ax.set_xlabel("orientation θ (rad)")
    ax.set_ylabel("probability density P(θ) (1/rad)")
    ax.set_title(f"orientation of the quantum body\n{_about(spectrum, name)}")
    ax.legend()
    if created:
        ax.figure.tight_layout()
    return ax.figure


@styled
def plot_counting(spectrum, ax=None, name=None):
    """The staircase N(λ) of the computed levels and Weyl's N̄(λ) (:mod:`.weyl`)."""
    from .weyl import weyl_count

    ax, created = axes_or_new(ax, (6, 4))
    values = np.asarray(spectrum.eigenvalues)
    ax.step(values, np.arange(1, values.size + 1), where="post", lw=1.0, label="N(λ), computed")
    grid = np.linspace(0.0, values.max() if values.size else 1.0, 400)
    ax.plot(grid, weyl_count(spectrum.strip, grid), "--", label="Weyl Aλ/4π − L√λ/4π + C")
    ax.set_xlabel("eigenvalue λ (1/κ²)")
    ax.set_ylabel("number of levels N(λ) (count)")
    ax.set_title(f"{values.size} levels ({spectrum.method})\n{_about(spectrum, name)}")
    ax.legend()
    if created:
        ax.figure.tight_layout()
    return ax.figure


@styled
def plot_spacings(statistics, ax=None, name=None):
    """Histogram of unfolded spacings with the Poisson, Wigner and fitted Brody densities."""
    from .statistics import brody_pdf

    ax, created = axes_or_new(ax, (5.4, 3.8))
    ax.hist(statistics.spacings, bins=30, range=(0, 4), density=True, alpha=0.5, label="spacings")
    s = np.linspace(0.0, 4.0, 300)
    ax.plot(s, np.exp(-s), label="Poisson")
    ax.plot(s, 0.5 * math.pi * s * np.exp(-0.25 * math.pi * s**2), label="GOE (Wigner)")
    ax.plot(s, brody_pdf(s, statistics.brody), "k--", lw=0.8, label=f"Brody q = {statistics.brody:.2f}")
    ax.set_xlabel("unfolded spacing s (mean spacing = 1)")
    ax.set_ylabel("probability density P(s) (dimensionless)")
    what = f"{np.size(statistics.spacings)} unfolded spacings"
    ax.set_title(f"{what}: {name}" if name else what)
    ax.legend()
    if created:
        ax.figure.tight_layout()
    return ax.figure


@styled
def plot_splittings(splittings, ax=None, wall=None, name=None):
    """Δλ against H − D on a log scale: direct difference, flux formula and WKB exp(−S) (scaled to the flux
    at the widest trusted neck); the title names ``wall`` (or ``name``) and the levels and heights."""
    ax, created = axes_or_new(ax, (6.4, 4.2))
    gap = np.array([s.gap for s in splittings])
    direct = np.array([s.direct if s.direct_trusted else np.nan for s in splittings])
    flux = np.array([s.flux if s.flux_trusted else np.nan for s in splittings])
    wkb = np.exp(-np.array([s.action for s in splittings]))
    ax.semilogy(gap, flux, "o-", label="flux (Herring)")
    ax.semilogy(gap, direct, "x", ms=9, label="direct λ₋ − λ₊")
    trusted = np.flatnonzero(np.isfinite(flux))
    if trusted.size:
        k = trusted[np.argmax(gap[trusted])]
        ax.semilogy(gap, wkb * flux[k] / wkb[k], ":", label="WKB exp(−S), scaled")
    plain_log_axis(ax.yaxis)
    ax.set_xlabel("neck width H − D (κ)")
    ax.set_ylabel("doublet splitting Δλ (1/κ²)")
    heights = ", ".join(f"{s.H:g}" for s in splittings)
    about = wall_label(wall, name) if (wall is not None or name) else "the wall"
    ax.set_title(f"heads–tails tunnelling splitting of {about}\nH = {heights} κ")
    ax.legend()
    if created:
        ax.figure.tight_layout()
    return ax.figure
