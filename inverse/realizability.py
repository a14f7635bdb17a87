"""Is a solved body physical?  Uniform-density κ and centroid, the self-consistent offset, the κ range.

The wall is measured in units of the body's radius of gyration κ, with the
centre of mass at the origin.  A body reconstructed in those units is a
*uniform* lamina with this wall only if its own radius of gyration (about
its centroid) is 1 and its centroid is at the origin.

Self-consistent offset
----------------------
For the wall ``b0 + b`` the uniform κ grows with ``b0`` (for large b0 the
body is nearly the disc of radius b0, κ ≈ b0/√2).  :func:`self_consistent_offset`
finds every ``b0`` with ``κ_uniform(b0) = 1`` (bracketing on a grid of
offsets, then Brent's method, each step a full solve) and reports the
centroid offset there; the body is self-consistent at such a b0 only if that
offset also vanishes (to ``tol``).  For a centrally symmetric wall the
centroid is always at the origin; in general the two conditions are three
equations in one unknown and no such b0 exists.

Range of κ reachable by some mass distribution
----------------------------------------------
Let K be the (convex) outline region with the origin inside.  Over all
probability measures μ on K with centre of mass ``∫x dμ = 0``, which values
of ``κ² = ∫|x|² dμ`` occur?

* Lower end: a mass concentrated ever closer to the origin has κ → 0, and
  κ = 0 itself is not a lamina, so the infimum is 0 (not attained).
* Upper end: maximise the linear functional ``∫|x|² dμ`` under the linear
  constraints ``∫dμ = 1``, ``∫x dμ = 0``.  Lagrange duality for this moment
  problem (strong duality holds: K is compact and 0 is an interior point, a
  Slater point) gives

      κ_max² = min over λ ∈ R² of max over x ∈ K of (|x|² − λ·x)
             = min over c ∈ R² of [ max_{x ∈ K} |x − c|² − |c|² ]        (c = λ/2).

  The inner maximum is attained at an extreme point of K, so a dense
  polygon of the outline gives it to the polygon's accuracy, and the whole
  problem is the linear programme ``min t`` subject to
  ``t ≥ |x_i|² − λ·x_i`` for every polygon vertex x_i (HiGHS, through casadi).  The
  optimal μ sits on at most three boundary points (the active constraints).
  Checks: a centred disc or ellipse with semi-axes a ≥ b gives κ_max = a
  (mass at the ends of the major axis); an equilateral triangle with
  circumradius R gives κ_max = R (mass on the vertices).
* Every value in between is reached: the set of admissible measures is
  convex and κ² is linear in μ.

So a body is realizable by *some* mass distribution with the prescribed wall
iff the origin is inside it and ``κ_max ≥ 1``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.massprops import outline_moments

from .tolerances import REALIZABLE_TOLERANCE

__all__ = ["Realizability", "SelfConsistency", "realizability", "kappa_max", "self_consistent_offset"]


def kappa_max(outline, per_segment: int = 8):
    """Largest radius of gyration of a mass distribution inside ``outline`` with centre of mass at the origin.

    Returns ``(kappa_max, support)`` where ``support`` (k, 3) lists the points
    and weights of an optimal distribution; ``(nan, empty)`` if the origin is not
    strictly inside.  See the module docstring for the derivation.

    Parameters
    ----------
    outline : Outline
        A convex outline in units of κ, the centre of mass at the origin.
    per_segment : int
        Candidate support points per outline segment.

    Returns
    -------
    kappa_max : float
        The largest radius of gyration (``nan`` if the origin is not strictly inside).
    support : ndarray (k, 3)
        Points ``x, y`` and weights of an optimal mass distribution.

    Examples
    --------
    All the mass on the rim of the unit disc, balanced about its centre: κ = 1.

    >>> from coinwall import Wall, kappa_max, solve_body
    >>> value, support = kappa_max(solve_body(Wall.from_expression("1"), 0.0, points=64).outline)
    >>> round(value, 6), support.shape[1]
    (1.0, 3)
    """
    pts = outline.polygon(per_segment) if per_segment > 1 else outline.nodes
    # centre of mass strictly inside: every support value positive
    theta = np.linspace(0, 2 * math.pi, 720, endpoint=False)
    if np.min(outline.support(theta)) <= 0:
        return float("nan"), np.empty((0, 3))
    sq = np.einsum("ij,ij->i", pts, pts)
    # variables (λx, λy, t); minimise t subject to |x_i|² − λ·x_i − t ≤ 0.  Constraint generation: the
    # programme on a subset of the points, then the points whose row it violates added, until none is (the
    # optimum has at most three active rows; the full programme of 10⁵ rows took seconds, this takes
    # milliseconds and gives the same optimum, since a solution feasible for every row is optimal for all)
    subset = np.unique(np.concatenate([np.linspace(0, len(pts) - 1, min(len(pts), 256)).astype(int),
                                       [int(np.argmax(sq))]]))
    for _ in range(50):
        a_ub = np.column_stack([-pts[subset, 0], -pts[subset, 1], -np.ones(subset.size)])
        solution = _min_t(a_ub, -sq[subset])
        if solution is None:
            return float("nan"), np.empty((0, 3))
        x, weights = solution
        lam, t = x[:2], x[2]
        excess = sq - pts @ lam - t
        violated = np.flatnonzero(excess > 1e-12 * max(1.0, float(np.max(sq))))
        if violated.size == 0:
            break
        worst = violated[np.argsort(excess[violated])[::-1][:64]]
        grown = np.union1d(subset, worst)
        if grown.size == subset.size:  # rows violated within HiGHS's tolerance, all in already: the same
            break  # programme again would give the same solution (it ran all 50 rounds at 10⁵ nodes)
        subset = grown
    active = weights > 1e-12 * max(weights.max(), 1e-300)
    points = pts[subset]
    support = np.column_stack([points[active], weights[active] / weights[active].sum()])
    # the objective at the solver's λ, evaluated over every point (not the solver's own rounding of it)
    return math.sqrt(max(float(np.max(sq - pts @ lam)), 0.0)), support


def _min_t(a_ub, b_ub):
    """``(x, weights)`` minimising ``x[2]`` subject to ``a_ub @ x <= b_ub`` (x free), or None if not solved.

    HiGHS through casadi's ``conic`` plugin (casadi is loaded for every formula wall already), not
    ``scipy.optimize.linprog``: importing ``scipy.optimize`` costs 0.3–0.7 s, a third of a ``coinwall
    solve`` of the built-in example.  ``weights`` are the rows' multipliers (≥ 0): an optimal mass
    distribution's weights on the active points.
    """
    import casadi as ca

    rows = a_ub.shape[0]
    try:
        solver = ca.conic("kappa_max", "highs", {"a": ca.Sparsity.dense(rows, 3), "h": ca.Sparsity(3, 3)},
                          {"highs": {"output_flag": False}, "verbose": False, "error_on_fail": False})
    except RuntimeError:  # a casadi built without its HiGHS plugin: scipy's HiGHS, the same programme
        from scipy.optimize import linprog

        res = linprog([0.0, 0.0, 1.0], A_ub=a_ub, b_ub=b_ub, bounds=[(None, None)] * 3, method="highs")
        return (res.x, -np.asarray(res.ineqlin.marginals)) if res.status == 0 else None
    result = solver(g=[0.0, 0.0, 1.0], a=ca.DM(a_ub), lba=-np.inf, uba=b_ub, lbx=-np.inf, ubx=np.inf)
    if not solver.stats().get("success", False):
        return None
    return np.asarray(result["x"]).ravel(), np.asarray(result["lam_a"]).ravel()


@dataclass(frozen=True, repr=False)
class Realizability:
    """Physical readings of a solved body.

    Attributes
    ----------
    b0 : float
        The body's offset.
    kappa_uniform : float
        Radius of gyration of the uniform lamina about its own centroid (body units;
        1 for a self-consistent uniform body).
    centroid : tuple of float
        Centroid of the uniform lamina (should be the origin).
    centroid_offset : float
        Its distance from the origin.
    kappa_max : float
        Largest κ of a mass distribution inside the outline with centre of mass at the
        origin (nan if the origin is not inside); reachable κ: ``(0, kappa_max]``.
    realizable : bool
        Some mass distribution gives this wall: origin inside and ``kappa_max ≥ 1``.
    uniform_consistent : bool
        The uniform lamina itself gives this wall (κ = 1 and centroid at the origin, to ``tol``).
    tol : float

    Examples
    --------
    >>> from coinwall import Wall, realizability, solve_body
    >>> reading = realizability(solve_body(Wall.from_expression("1"), 0.0, points=64))
    >>> round(reading.kappa_uniform ** 2, 6), reading.realizable
    (0.5, True)
    """

    b0: float
    kappa_uniform: float
    centroid: tuple
    centroid_offset: float
    kappa_max: float
    realizable: bool
    uniform_consistent: bool
    tol: float

    def to_dict(self) -> dict:
        return {"b0": self.b0, "kappa_uniform": self.kappa_uniform, "centroid": list(self.centroid),
                "centroid_offset": self.centroid_offset,
                "kappa_max": self.kappa_max if math.isfinite(self.kappa_max) else None,
                "kappa_range": [0.0, self.kappa_max] if math.isfinite(self.kappa_max) else None,
                "realizable": self.realizable, "uniform_consistent": self.uniform_consistent}

    @safe_repr
    def __repr__(self) -> str:
        return (f"Realizability(kappa_uniform={self.kappa_uniform:.6g}, centroid_offset={self.centroid_offset:.3g}, "
                f"kappa_max={self.kappa_max:.6g}, realizable={self.realizable}, "
                f"uniform_consistent={self.uniform_consistent})")


def realizability(body, tol: float = 1e-6) -> Realizability:
    """Uniform κ and centroid of ``body`` (an :class:`inverse.Body`), and the reachable κ range.

    Parameters
    ----------
    body : Body
        A solved body.
    tol : float
        Tolerance of the self-consistency checks (κ = 1, centroid at the origin).

    Returns
    -------
    Realizability

    Examples
    --------
    The wall ``b = 1`` is a disc of radius κ: a uniform disc has κ = 1/√2 (not self-consistent), but a
    ring of mass at the rim reaches κ = 1, so some mass distribution has this wall.

    >>> from coinwall import Wall, realizability, solve_body
    >>> realizability(solve_body(Wall.from_expression("1"), 0.0, points=64))
    Realizability(kappa_uniform=0.707107, centroid_offset=0, kappa_max=1, realizable=True, uniform_consistent=False)
    """
    size = float(np.max(np.hypot(body.x, body.y))) if body.x.size else 0.0
    if body.area <= 1e-12 * max(1.0, size) ** 2:
        # a segment (the stick): the uniform rod, κ = length/√12 about its midpoint (a lamina has no mass)
        points = body.outline.polygon(4)
        end = points[np.argmax(np.hypot(*points.T))]  # one end of the segment: the point farthest out
        far = points[np.argmax(np.hypot(*(points - end).T))]  # the other end: the point farthest from it
        kappa_u = float(np.hypot(*(far - end)) / math.sqrt(12.0))
        centroid = tuple(0.5 * (far + end))
    else:
        props = outline_moments(body.outline)
        kappa_u, centroid = props.kappa, props.centre
    kmax, _ = kappa_max(body.outline)
    offset = float(math.hypot(*centroid))
    realizable = bool(math.isfinite(kmax) and kmax >= 1.0 - REALIZABLE_TOLERANCE)
    uniform = bool(abs(kappa_u - 1) <= tol and offset <= tol)
    return Realizability(float(body.b0), float(kappa_u), tuple(float(c) for c in centroid), offset, float(kmax),
                         realizable, uniform, float(tol))


@dataclass(frozen=True, repr=False)
class SelfConsistency:
    """Offsets at which the uniform lamina has κ = 1.

    Attributes
    ----------
    offsets : tuple of float
        Every b0 (in the searched range) with ``kappa_uniform(b0) = 1``.
    centroid_offsets : tuple of float
        Distance of the uniform centroid from the origin at each of them.
    consistent : tuple of bool
        Whether that distance is within ``tol`` (a fully self-consistent uniform body).
    searched : tuple of float
        The b0 range searched.

    Examples
    --------
    >>> from coinwall import Wall, self_consistent_offset
    >>> result = self_consistent_offset(Wall.from_expression("0.1*cos(2*t)"), points=128, grid=8)
    >>> len(result.offsets), len(result.consistent) == len(result.offsets)
    (1, True)
    """

    offsets: tuple
    centroid_offsets: tuple
    consistent: tuple
    searched: tuple

    @property
    def b0(self):
        """The first fully self-consistent offset, or None."""
        for b0, ok in zip(self.offsets, self.consistent):
            if ok:
                return b0
        return None

    def to_dict(self) -> dict:
        return {"offsets": list(self.offsets), "centroid_offsets": list(self.centroid_offsets),
                "consistent": list(self.consistent), "searched": list(self.searched), "b0": self.b0}

    @safe_repr
    def __repr__(self) -> str:
        return f"SelfConsistency(b0={self.b0}, offsets={[round(b, 6) for b in self.offsets]})"


def self_consistent_offset(wall, *, points: int = 512, grid: int = 24, tol: float = 1e-6,
                           xtol: float = 1e-12) -> SelfConsistency:
    """Offsets b0 for which the uniform body with wall ``b0 + b`` has κ = 1 (see the module docstring).

    Parameters
    ----------
    wall : Wall
        The wall function b(θ).
    points : int
        Outline nodes of each body solved.
    grid : int
        Offsets tried before the roots are bracketed (≥ 4).
    tol : float
        Tolerance of the centroid check.
    xtol : float
        Tolerance of the root finder on b0.

    Returns
    -------
    SelfConsistency

    Raises
    ------
    InvalidArgument
        For a ``grid`` that is not an integer of at least 4.

    Examples
    --------
    >>> from coinwall import Wall, self_consistent_offset
    >>> result = self_consistent_offset(Wall.from_expression("0.1*cos(2*t)"), points=128, grid=8)
    >>> [round(b0, 4) for b0 in result.offsets]
    [1.4125]
    """
    from scipy.optimize import brentq

    from .solve import solve_body

    if not isinstance(grid, int) or grid < 4:
        raise InvalidArgument(f"grid must be an integer >= 4, got {grid!r}")
    theta = np.linspace(0, 2 * math.pi, 2048, endpoint=False)
    values = wall(theta)
    scale = max(float(np.max(np.abs(values))), 1.0)
    lo = -float(np.min(values)) + 1e-6 * scale  # below this the origin is outside the body

    def body_at(b0):
        return solve_body(wall, b0, points=points)

    def excess(b0):
        body = body_at(b0)
        return (outline_moments(body.outline).kappa if body.area > 0 else 0.0) - 1.0

    hi = lo + 2.0
    while excess(hi) < 0:  # κ ≈ b0/√2 for large b0: doubling terminates
        hi = lo + 2 * (hi - lo)
    offsets = np.linspace(lo, hi, grid)
    vals = [excess(b) for b in offsets]
    roots = []
    for a, b, fa, fb in zip(offsets[:-1], offsets[1:], vals[:-1], vals[1:]):
        if fa == 0:
            roots.append(float(a))
        elif fa * fb < 0:
            roots.append(float(brentq(excess, a, b, xtol=xtol)))
    cents = []
    for r in roots:
        props = outline_moments(body_at(r).outline)
        cents.append(float(math.hypot(*props.centre)))
    return SelfConsistency(tuple(roots), tuple(cents), tuple(c <= tol for c in cents), (lo, float(hi)))
