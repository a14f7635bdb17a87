"""The spectrum of the quantum coin: the result object and the entry point :func:`quantum_spectrum`.

The eigenvalues λ of −Δ (Dirichlet on both walls, periodic in θ) on the strip of :mod:`.strip`, in units
of 1/κ²; the energy is E = ħ²λ/(2Mκ²).  Methods (:data:`METHODS`): ``"fem"``, Lagrange finite elements
on the mapped mesh (:mod:`.mesh`, :mod:`.fem`), solved class by class (:mod:`.symmetry`); ``"spectral"``,
Fourier × sine modes on the mapped cylinder for smooth walls (:mod:`.spectral`; eigenvalues and classes only).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..display import safe_repr
from ..errors import CoinwallError, InvalidArgument
from ..validation import check_choice, check_count
from ..wall import Wall
from .strip import Strip, make_strip

__all__ = ["BYTES_PER_DOF", "MAX_DOFS", "METHODS", "Spectrum", "check_mesh", "default_cells", "estimated_seconds",
           "fem_dofs", "quantum_spectrum"]

#: The largest finite-element problem (degrees of freedom, estimated from the mesh before it is built) and its
#: memory per degree of freedom.  Measured (`quantum 1 --H h --levels 4`, P2, peak RSS, 2 shared cores under
#: load): 15,120 dofs 0.5 s / 134 MB (h = 2.1), 150,840 dofs 56 s / 446 MB (h = 2.01): about 2.3 kB per dof,
#: counted as 4 kB; the time grows faster than the size, so the bound is set by time near 400,000 dofs.
#: The columns follow the strip's width (Δθ = w/cells), so their number grows like 1/(H − H_min) for a circle
#: and 1/√(H − H_min) at a smooth neck: H = 2.0000001 on a circle wanted 5·10^8 columns (1.5·10^10 dofs).
MAX_DOFS = 400_000
BYTES_PER_DOF = 4096


@dataclass(frozen=True, repr=False)
class Spectrum:
    """The lowest levels of the quantum billiard.

    Attributes
    ----------
    eigenvalues : ndarray
        Ascending λ (units 1/κ²).
    classes : tuple of str
        The symmetry class of each level (``"swap+ mirror-"``, :mod:`.symmetry`); for a strip that fell
        apart, ``"region k"`` (the regions are separate domains).
    characters : ndarray (levels, r) of int
        The class as ±1 per symmetry in ``symmetry_names`` (empty columns for a strip that fell apart).
    symmetry_names : tuple of str
    domain : ndarray of int
        Index into ``meshes`` of each level's domain (0 for the periodic strip).
    strip : Strip
    meshes : tuple of StripMesh
    method : str
    cells, order : int
        Rows of cells across the strip and element degree.
    dofs : int
        Free degrees of freedom (all domains).
    seconds : float
        Wall-clock time of mesh, assembly and solve.
    vectors : tuple of ndarray
        Each level's eigenvector on the free dofs of its mesh (M-normalised: ∫ψ² dθ dη = 1).

    Examples
    --------
    >>> from coinwall import Wall, quantum_spectrum
    >>> spectrum = quantum_spectrum(Wall.from_expression("1"), H=3.0, levels=4, cells=4, order=2)
    >>> spectrum.method, spectrum.order, len(spectrum.eigenvalues)
    ('fem', 2, 4)
    """

    eigenvalues: np.ndarray
    classes: tuple
    characters: np.ndarray
    symmetry_names: tuple
    domain: np.ndarray
    strip: Strip
    meshes: tuple
    method: str
    cells: int
    order: int
    dofs: int
    seconds: float
    vectors: tuple = field(default=(), compare=False)

    def __len__(self) -> int:
        return int(self.eigenvalues.size)

    def require_vectors(self, what: str) -> None:
        """Raise :class:`InvalidArgument` naming ``what`` needed them if this spectrum has no eigenvectors."""
        if len(self.vectors) < len(self):
            raise InvalidArgument(f"{what} needs eigenvectors, and the {self.method} solver gives none: "
                                  "solve with method=\"fem\"")

    def weyl(self):
        """The :class:`.weyl.WeylCheck` of these levels."""
        from .weyl import weyl_check

        return weyl_check(self)

    def statistics(self, skip: int = 10):
        """Nearest-neighbour spacing statistics per class (:func:`.statistics.level_statistics`)."""
        from .statistics import level_statistics

        return level_statistics(self, skip=skip)

    def plot(self, ax=None):
        """The spectrum's counting function with Weyl's curve (:func:`.figures.plot_counting`)."""
        from .figures import plot_counting

        return plot_counting(self, ax=ax)

    def to_dict(self) -> dict:
        """The levels, classes, solver, strip and Weyl check as a JSON-ready dict (no eigenvectors)."""
        weyl = self.weyl()
        return {"eigenvalues": [float(v) for v in self.eigenvalues], "classes": list(self.classes),
                "symmetries": list(self.symmetry_names), "method": self.method, "cells": self.cells,
                "order": self.order, "dofs": self.dofs, "seconds": self.seconds, "strip": self.strip.to_dict(),
                "weyl": weyl.to_dict()}

    @safe_repr
    def __repr__(self) -> str:
        low = ", ".join(f"{v:.6g}" for v in self.eigenvalues[:4])
        more = ", …" if self.eigenvalues.size > 4 else ""
        solver = f"fem P{self.order}" if self.method == "fem" else self.method
        return (f"Spectrum({self.eigenvalues.size} levels [{low}{more}], {solver}, "
                f"{self.dofs} dofs, {self.seconds:.3g} s)")


def default_cells(strip: Strip, levels: int, order: int = 2) -> int:
    """Rows across the strip for relative errors of about 1e-4 at the ``levels``-th level.

    Weyl's law with its boundary term puts the ``levels``-th level near λ ≈ 1.5·4π·levels/A.  On flat
    walls (exact values; tests/forward/quantum/test_quantum.py) the largest relative error of degree p with
    cells of side h is about c_p·(h√λ)^(2p), measured: 2.6e-4 at h√λ = 0.62 (P2), 4.3e-5 at 1.24 (P3),
    3.4e-7 at 1.24 (P4); h√λ = 0.5, 1.4, 2.5 for p = 2, 3, 4 gives ~1e-4.

    Parameters
    ----------
    strip : Strip
    levels : int
        The highest level wanted.
    order : int
        The element degree (2, 3 or 4).

    Returns
    -------
    int
        Rows of cells across the strip.

    Examples
    --------
    >>> from coinwall import Wall, make_strip
    >>> from coinwall.forward.quantum import default_cells
    >>> default_cells(make_strip(Wall.from_expression("1"), 3.0), levels=10)
    13
    """
    lam = 1.5 * 4.0 * math.pi * levels / max(strip.area, 1e-12) + (math.pi / strip.width_max) ** 2
    target = {2: 0.5, 3: 1.4, 4: 2.5}.get(order, 0.5)
    return max(4, math.ceil(strip.width_max * math.sqrt(lam) / target))


def fem_dofs(strip: Strip, cells: int, order: int = 2) -> float:
    """The number of degrees of freedom of the finite-element problem, from the column count alone (nothing
    the size of the mesh is built): about order·columns × order·cells per domain."""
    from .mesh import column_count

    cells += cells % 2
    domains = [None] if strip.periodic else list(strip.regions)
    return float(sum(order * column_count(strip, cells, region) * order * cells for region in domains))


def estimated_seconds(strip: Strip, levels: int, method: str, cells: int, order: int = 4) -> float:
    """The time one solve should take, on one idle core, from the size of the problem alone (before anything
    is built); ``method`` is ``"fem"`` or ``"spectral"`` (the spectral time includes the coarser second solve
    that estimates its error).

    Measured (``quantum 1 --H h --levels n``, one thread; under load the ratios held, the times grew alike):

    * fem: 15,120 dofs took 0.5 s and 150,840 dofs 56 s on a thin strip (4 rows of P4 cells, 16 dofs across):
      time ∝ dofs^2.05.  A wide strip is slower per dof, by (dofs across / 16)^1.4: 3,824 dofs 240 across took
      40 times the thin strip's rate, 8,944 dofs 560 across 135 times (ARPACK needs more iterations as the
      levels crowd at the bottom of a wide strip).  ``0.5 s · (dofs/15,120)^2.05 · max(1, across/16)^1.4``.
    * spectral: dense generalized eigenproblems, one per symmetry class of ``n = modes/classes``: 1,000 levels
      of the ε = 0.55 ellipse (9,367 modes, eight classes) took 18 s, so ``2 · 1.4e-9 s · classes · n³``.
    """
    if method == "spectral":
        from .spectral import spectral_modes

        M, N = spectral_modes(strip, cells)
        classes = 2 ** len(strip.symmetries) if strip.periodic else 1
        n = (2 * M + 1) * N / classes
        return 2.0 * 1.4e-9 * classes * n**3
    across = order * (cells + cells % 2)
    return 0.5 * (fem_dofs(strip, cells, order) / 15_120) ** 2.05 * max(1.0, across / 16) ** 1.4


def _fits(strip, levels, cells, order, max_seconds=None):
    cells = default_cells(strip, levels, order) if cells is None else cells
    count = fem_dofs(strip, cells, order)
    quick = max_seconds is None or estimated_seconds(strip, levels, "fem", cells, order) <= max_seconds
    return count <= MAX_DOFS and count * BYTES_PER_DOF <= _memory_limit() and quick, count


def _memory_limit():
    from ..validation import MEMORY_FRACTION, available_memory

    return MEMORY_FRACTION * available_memory()


def check_mesh(strip: Strip, levels: int, cells=None, order: int = 2, max_seconds=None) -> float:
    """Refuse, before the mesh is built, a finite-element problem above :data:`MAX_DOFS` degrees of freedom,
    the memory this machine can give it (:data:`BYTES_PER_DOF` each) or ``max_seconds`` of
    :func:`estimated_seconds`; the message names the smallest H that fits all of them (same wall, offset,
    levels and cells), so that the H it suggests runs.  Returns the estimated number of dofs."""
    ok, count = _fits(strip, levels, cells, order, max_seconds)
    if ok:
        return count
    table = strip.table
    h_min = table.H - strip.width_min
    hint = ""
    try:
        gap, good = strip.width_min, None
        for _ in range(60):
            gap *= 2.0
            if _fits(make_strip(table.wall, h_min + gap, table.b0), levels, cells, order, max_seconds)[0]:
                good = gap
                break
        if good is not None:
            bad = strip.width_min
            for _ in range(30):
                mid = math.sqrt(bad * good)
                if _fits(make_strip(table.wall, h_min + mid, table.b0), levels, cells, order, max_seconds)[0]:
                    good = mid
                else:
                    bad = mid
                if good / bad < 1.01:
                    break
            hint = f"; H ≥ {h_min + good:.6g} fits"
    except (CoinwallError, ArithmeticError, ValueError):  # the hint is a courtesy: no hint, not a second error
        hint = ""
    limit = min(MAX_DOFS, _memory_limit() / BYTES_PER_DOF)
    cells = default_cells(strip, levels, order) if cells is None else cells
    seconds = estimated_seconds(strip, levels, "fem", cells, order)
    if count <= limit:  # the size fits, the time does not
        raise InvalidArgument(f"H = {table.H:.10g}: the finite elements ({count:.3g} degrees of freedom, "
                              f"{order * (cells + cells % 2)} across) would take about {_duration(seconds)}, more "
                              f"than {_duration(max_seconds)} (`max_seconds`){hint}, or ask for fewer levels or "
                              "cells")
    raise InvalidArgument(f"H = {table.H:.10g} leaves a neck of width {strip.width_min:.3g}: the mesh would have "
                          f"about {count:.3g} degrees of freedom ({BYTES_PER_DOF} bytes each), more than the "
                          f"{limit:.3g} allowed (time and memory){hint}, or ask for fewer --levels / --cells")


def _duration(seconds: float) -> str:
    for unit, size in (("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def default_modes(strip: Strip, levels: int) -> int:
    """Sine modes across for the spectral method: those of the ``levels``-th level (λ as in
    :func:`default_cells`, n ≈ w_max√λ/π) and 8 more, for ~1e-8 relative on an analytic wall."""
    lam = 1.5 * 4.0 * math.pi * levels / max(strip.area, 1e-12) + (math.pi / strip.width_max) ** 2
    return max(4, math.ceil(strip.width_max * math.sqrt(lam) / math.pi) + 10)


def _fem(strip, levels, cells, order, symmetry, progress):
    import scipy.sparse as sp

    from .fem import assemble, solve_classes
    from .mesh import strip_mesh
    from .symmetry import class_bases, class_labels, dof_permutation, label_text

    if strip.periodic:
        mesh = strip_mesh(strip, cells, order)
        stiffness, mass = assemble(mesh)
        names = strip.symmetries if symmetry else ()
        perms = [dof_permutation(mesh.free_locations, n) for n in names]
        bases = class_bases(perms, mesh.dofs) if names else [sp.identity(mesh.dofs, format="csc")]
        values, labels, vectors = solve_classes(stiffness, mass, bases, levels, progress)
        characters = np.array(class_labels(names), dtype=int).reshape(len(bases), len(names))[labels]
        classes = tuple(label_text(names, c) for c in characters)
        return values, classes, characters, tuple(names), np.zeros(values.size, dtype=int), (mesh,), vectors, mesh.dofs
    parts = []
    meshes = []
    for k, region in enumerate(strip.regions):
        mesh = strip_mesh(strip, cells, order, region=region)
        stiffness, mass = assemble(mesh)
        values, _, vectors = solve_classes(stiffness, mass, [sp.identity(mesh.dofs, format="csc")], levels, progress)
        parts.append((values, np.full(values.size, k), vectors))
        meshes.append(mesh)
    values = np.concatenate([p[0] for p in parts])
    domain = np.concatenate([p[1] for p in parts])
    vectors = [v for p in parts for v in p[2]]
    order_ = np.argsort(values, kind="stable")[:levels]
    classes = tuple(f"region {domain[k]}" for k in order_)
    return (values[order_], classes, np.zeros((order_.size, 0), dtype=int), (), domain[order_], tuple(meshes),
            [vectors[k] for k in order_], sum(m.dofs for m in meshes))


def _spectral(strip, levels, cells, order, symmetry, progress):
    from .spectral import spectral_levels
    from .symmetry import label_text

    values, characters, names, modes, across = spectral_levels(strip, levels, cells, symmetry, progress)
    classes = tuple(label_text(names, c) for c in characters)
    return values, classes, characters, names, np.zeros(values.size, dtype=int), (), (), (2 * modes + 1) * across


#: method name -> function(strip, levels, cells, order, symmetry, progress) returning (values, classes,
#: characters, names, domain, meshes, vectors, dofs); "spectral" has no mesh and no eigenvectors
METHODS = {"fem": _fem, "spectral": _spectral}


def quantum_spectrum(wall, H=None, b0: float = 0.0, levels: int = 10, *, method: str = "auto", cells=None,
                     order: int | None = None, eigenvectors: bool = False, symmetry: bool = True,
                     progress=None, max_seconds: float | None = None) -> Spectrum:
    """The lowest ``levels`` eigenvalues of the Dirichlet Laplacian on the strip of ``wall`` at distance ``H``.

    Parameters
    ----------
    wall : Wall or Strip
        The wall function b(θ) (then ``H`` is required), or a :class:`Strip` already made.
    H, b0 : float
        Distance between the walls and the offset (units of κ).
    levels : int
        How many levels (the lowest; per region when the strip fell apart, then merged).
    method : str
        A key of :data:`METHODS`, or ``"auto"`` (default): the fastest accurate solver for the strip, as the
        command line picks it (:func:`.choice.default_solver`): the spectral method for a smooth wall on a
        strip open at every angle, degree-4 elements otherwise.  The spectral method gives no eigenvectors:
        for ``|ψ|²`` or splittings pass ``eigenvectors=True`` or ``method="fem"`` (``"auto"`` with ``cells`` or
        ``order`` given is ``"fem"`` too).
    cells : int, optional
        FEM: rows of cells across the strip (even), default :func:`default_cells`; spectral: sine modes
        across (the Fourier modes follow, :func:`.spectral.spectral_modes`), default :func:`default_modes`.
    order : int, optional
        Element degree, 2 to 4; default 4 (at the default mesh faster and more accurate than 2 or 3).
    eigenvectors : bool
        With ``method="auto"``: the eigenvectors are needed (``|ψ|²``, P(θ), splittings), so the finite
        elements, which give them, are chosen.
    symmetry : bool
        Solve class by class (default) — False solves the whole problem at once (for checks).
    progress : callable, optional
        Called with 1 after each class (or region) is solved.
    max_seconds : float, optional
        Refuse (InvalidArgument, before anything is built) a problem whose :func:`estimated_seconds` exceed
        this; None (default): no time bound (the size and memory bounds hold always).

    Returns
    -------
    Spectrum

    Raises
    ------
    InvalidArgument
        For a Wall without ``H``, something that is neither a Wall nor a Strip, an unknown method, or a
        spectral run estimated to take longer than ``max_seconds``.

    Examples
    --------
    The flat wall ``b = 1`` at ``H = 3`` is a strip of width 1 around the cylinder θ ∈ [0, 2π): its levels
    are ``π² n² + m²`` exactly; the lowest, π² = 9.8696, to 5e-4 with this coarse mesh.

    >>> from coinwall import Wall, quantum_spectrum
    >>> spectrum = quantum_spectrum(Wall.from_expression("1"), H=3.0, levels=4, cells=4, order=2)
    >>> spectrum.eigenvalues.round(2).tolist()
    [9.87, 10.87, 10.88, 13.89]
    >>> spectrum.classes[0]
    'swap+ mirror+ half_turn+'
    """
    check_choice("method", method, ("auto", *METHODS))
    levels = check_count("levels", levels, minimum=1, maximum=100_000)
    elements = cells is not None or order is not None  # element parameters given: the elements (as the CLI)
    order = 4 if order is None else check_count("order", order, minimum=2, maximum=4)
    if isinstance(wall, Strip):
        strip = wall
    elif isinstance(wall, Wall):
        if H is None:
            raise InvalidArgument("`H` is required with a Wall (or pass a Strip)")
        strip = make_strip(wall, H, b0)
    else:
        raise InvalidArgument(f"`wall` must be a Wall or a Strip, got {type(wall).__name__}")
    if method == "auto":
        from .choice import default_solver

        method = "fem" if elements else default_solver(strip, levels, eigenvectors=eigenvectors).method
    if cells is None:
        cells = default_modes(strip, levels) if method == "spectral" else default_cells(strip, levels, order)
    cells = check_count("cells", cells, minimum=2, maximum=4096)
    if method == "fem":
        check_mesh(strip, levels, cells, order, max_seconds)
    elif max_seconds is not None and estimated_seconds(strip, levels, method, cells) > max_seconds:
        seconds = estimated_seconds(strip, levels, method, cells)
        raise InvalidArgument(f"the spectral method at {cells} modes across would take about {_duration(seconds)} "
                              f"(dense blocks: the time grows like the cube of the modes), more than "
                              f"{_duration(max_seconds)} (`max_seconds`); ask for fewer levels or a smaller H")
    start = time.perf_counter()
    values, classes, characters, names, domain, meshes, vectors, dofs = METHODS[method](
        strip, levels, cells, order, symmetry, progress)
    seconds = time.perf_counter() - start
    cells = cells + cells % 2 if method == "fem" else cells
    return Spectrum(np.asarray(values), classes, characters, names, domain, strip, meshes, method,
                    cells, order, int(dofs), seconds, tuple(vectors))
