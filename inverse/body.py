"""The solved body: outline, curvature, corners, regime and the closed loop back to the wall."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.display import json_number, safe_repr

__all__ = ["Body"]


@dataclass(frozen=True, repr=False)
class Body:
    """A body outline solved from a wall function and an offset.

    Coordinates are in units of the radius of gyration κ, with the centre of
    mass at the origin and the body axis along +x (see :mod:`forward.wall`
    for the angle convention).

    Attributes
    ----------
    wall : forward.Wall
        The prescribed wall b(θ).
    b0 : float
        The offset; the body's support function is ``b0 + b``.
    b_c : float
        Exact critical offset ``−min(b + b'')`` (``inf`` if no offset works).
    critical_angles : tuple of float
        Where the minimum of ``b + b''`` is attained (every angle where it is).
    critical_angle_errors : tuple of float
        For a formula wall, one per critical angle: every minimiser lies within it of one of them
        (:attr:`coinwall.inverse.critical.CriticalOffset.angle_errors`); empty for data.
    regime : str
        ``"convex"`` (Case I), ``"critical"`` (Case II) or ``"corner"`` (Case III).
    method : str
        The solver that produced the outline (``"envelope"`` or ``"polar"``).
    outline : forward.Outline
        Closed piecewise-cubic outline (exact support function, O(Δ⁴) shape).
    x, y, K : ndarray
        Outline nodes (Cartesian coordinates) and the curvature there (``inf`` at a corner).
        Their polar coordinates are the properties ``alpha`` and ``R``.
    phi_in, phi_out : ndarray
        Normal angles at every node (equal except at corners).
    corners : tuple of inverse.corners.Corner
        Corners of the body (Case III corners carry a wall deficit; corners
        of the prescribed wall itself, like the stick's ends, have none).
    folds : tuple of inverse.polar.Fold
        Folds of the map φ → α (cusps of the envelope), located exactly.
    max_wall_error : float
        Largest ``|wall(body) − (b0 + b)|`` over θ outside the corner windows,
        on a grid of angles different from the construction grid.
    cross_check : float or None
        Largest difference between the walls of the envelope and the polar
        solution (None when not computed).
    polar_residual : float or None
        Largest residual of the paper's equation F(α, R, R') = 0 (polar method).
    convex, valid : bool
        Convexity and validity of the outline polygon, checked with shapely.
    com_inside : bool
        Whether ``b0 + b > 0`` everywhere (centre of mass strictly inside).
    seconds : float
        Wall-clock time of the solve (including verification).
    notes : tuple of str
        What the solver did that a reader should know (a sampled wall, edges between vertex windows …).
    b_c_tolerance : float
        How well ``b_c`` is known: rounding for a formula wall; for samples, what their rounding and
        spacing allow.  The regime is ``critical`` when ``|b0 − b_c|`` is within it.
    accuracy : float
        The largest wall error and solver disagreement this body may have and still be the answer.
    warnings : tuple of str
        Everything that makes this body *not* the answer as asked: a wall error or a solver
        disagreement above :attr:`accuracy`, an outline that is not simple and convex.  Empty when
        all is well; the command line prints each as a ``warning:`` line and exits with status 1.
    b_c_lower, b_c_upper : float or None
        For a wall given as data: the certified interval of ``b_c`` over every wall consistent with
        the samples (the upper end under the assumption in the notes); None for a formula wall.
    regimes : tuple of str
        Every regime the data allow at ``b0`` (``("corner", "critical", "convex")`` where they cannot
        decide; :attr:`regime` is then ``"critical"``); for a formula wall, ``(regime,)``.
    outline_tolerance : float or None
        For a wall given as data (at an offset where some convex body is inside every sample's interval):
        certified bound on the Hausdorff distance between this outline and every convex body whose support
        function lies in the samples' intervals (the true body among them).  None otherwise.
    possible_corners : tuple of coinwall.inverse.certify.DataCorner
        For data: windows where the samples allow a corner that they do not force.
    band : coinwall.inverse.band.Band or None
        For data: the envelopes of every consistent body (what the figures draw).
    statistics : coinwall.inverse.noise.NoisyCritical or None
        For samples given with standard deviations: ``b_c`` as an estimate with a confidence interval (then
        :attr:`b_c_lower` and :attr:`b_c_upper`, which are certified bounds, are None).

    Examples
    --------
    >>> from coinwall import Wall, solve_body
    >>> wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> body = solve_body(wall, -0.6, points=256)       # below b_c = −1/2: Case III
    >>> body.regime, round(body.b_c, 12), len(body.corners), body.convex
    ('corner', -0.5, 2, True)
    >>> body.points.shape == (body.x.size, 2), body.to_dict()["regime"]
    (True, 'corner')
    """

    wall: object
    b0: float
    b_c: float
    critical_angles: tuple
    regime: str
    method: str
    outline: object
    x: np.ndarray
    y: np.ndarray
    K: np.ndarray
    phi_in: np.ndarray
    phi_out: np.ndarray
    corners: tuple
    folds: tuple
    max_wall_error: float
    cross_check: float | None
    polar_residual: float | None
    convex: bool
    valid: bool
    com_inside: bool
    seconds: float = 0.0
    notes: tuple = field(default=())
    b_c_tolerance: float = 0.0
    accuracy: float = 0.0
    warnings: tuple = field(default=())
    b_c_lower: float | None = None
    b_c_upper: float | None = None
    regimes: tuple = field(default=())
    critical_angle_errors: tuple = field(default=())
    outline_tolerance: float | None = None
    possible_corners: tuple = field(default=())
    band: object = field(default=None, repr=False, compare=False)
    statistics: object = field(default=None, repr=False, compare=False)

    @property
    def regime_decided(self) -> bool:
        """Whether the data (or the formula) decide the regime at ``b0``."""
        return len(self.regimes) <= 1

    def __post_init__(self):
        """Refuse a body with a non-finite number: it would be written to files and reported as an answer.

        ``K`` may be ``inf`` (a corner) and ``b_c`` may be ``inf`` (a concave kink), never ``nan``.
        """
        from coinwall.forward.errors import InvalidWall

        description = getattr(self.wall, "description", "?")
        with np.errstate(invalid="ignore"):
            bad = ~(np.isfinite(self.x) & np.isfinite(self.y) & np.isfinite(self.phi_in) & np.isfinite(self.phi_out)
                    & ~np.isnan(self.K))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            angle = self.phi_in[i] if np.isfinite(self.phi_in[i]) else float(i) * TWO_PI / max(1, bad.size)
            raise InvalidWall(f"wall {description!r} at b0 = {self.b0:g}: the body is not finite near the normal angle "
                              f"θ = {float(np.mod(angle, TWO_PI)):.6g} (x = {self.x[i]:.6g}, y = {self.y[i]:.6g}, "
                              f"curvature {self.K[i]:.6g}); no body is given for a wall that is not finite")
        outline_ok = all(np.all(np.isfinite(getattr(self.outline, name, 0.0))) for name in ("nodes", "controls"))
        numbers = {"b0": self.b0, "max_wall_error": self.max_wall_error}
        bad_number = next((name for name, value in numbers.items() if not math.isfinite(value)), None)
        if not outline_ok or bad_number or math.isnan(self.b_c):
            what = "its outline" if not outline_ok else f"`{bad_number or 'b_c'}`"
            raise InvalidWall(f"wall {description!r} at b0 = {self.b0:g}: {what} is not finite; no body is given for "
                              "a wall that is not finite")

    # What follows from the fields is derived, not stored: a Body keeps only what it cannot derive.
    @property
    def alpha(self) -> np.ndarray:
        """Polar angle of every node in [0, 2π)."""
        return np.mod(np.arctan2(self.y, self.x), TWO_PI)

    @property
    def R(self) -> np.ndarray:
        """Distance of every node from the centre of mass."""
        return np.hypot(self.x, self.y)

    @property
    def area(self) -> float:
        """Area of the outline (exact for the Bézier curve)."""
        return self.outline.area

    @property
    def perimeter(self) -> float:
        """Perimeter of the outline (exact for the Bézier curve)."""
        return self.outline.perimeter

    @property
    def points(self) -> np.ndarray:
        """Outline nodes as an (n, 2) array."""
        return np.column_stack([self.x, self.y])

    def wall_of_body(self, theta):
        """The forward wall of this body, ``h(θ) − b0`` (support function minus the offset)."""
        return self.outline.support(theta) - self.b0

    def to_dict(self) -> dict:
        """JSON-ready summary (without the outline)."""
        return {
            "wall": self.wall.description,
            "params": dict(self.wall.params),
            "b0": self.b0,
            "b_c": json_number(self.b_c),
            "b_c_infinite": bool(math.isinf(self.b_c)),
            "b_c_tolerance": json_number(self.b_c_tolerance),
            "critical_angles": list(self.critical_angles),
            "critical_angle_errors": list(self.critical_angle_errors),
            "regime": self.regime,
            "method": self.method,
            "regimes": list(self.regimes or (self.regime,)),
            "regime_decided": self.regime_decided,
            "b_c_lower": json_number(self.b_c_lower),
            "b_c_upper": json_number(self.b_c_upper),
            "outline_tolerance": json_number(self.outline_tolerance),
            "possible_corners": [c.to_dict() for c in self.possible_corners],
            "b_c_confidence": self.statistics.to_dict() if self.statistics is not None else None,
            "points": int(self.x.size),
            "max_wall_error": json_number(self.max_wall_error),
            "cross_check": json_number(self.cross_check),
            "polar_residual": json_number(self.polar_residual),
            "convex": self.convex,
            "valid": self.valid,
            "com_inside": self.com_inside,
            "area": self.area,
            "perimeter": self.perimeter,
            "corners": [c.to_dict() for c in self.corners],
            "folds": [f.to_dict() for f in self.folds],
            "kinks": [{"angle": k.angle, "jump": k.jump} for k in self.wall.kinks],
            "notes": list(self.notes),
            "accuracy": json_number(self.accuracy),
            "warnings": list(self.warnings),
            "seconds": self.seconds,
        }

    def plot(self, ax=None):
        """Draw the outline, its centre of mass and its corners (matplotlib, imported here, in the house style of
        :mod:`coinwall.forward.formats.style`); returns the axes."""
        from coinwall.forward.formats.figure import axes_or_new
        from coinwall.forward.formats.style import PALETTE, house_style

        with house_style():
            ax, _ = axes_or_new(ax, (5, 5))
            pts = self.outline.polygon(8)
            pts = np.vstack([pts, pts[:1]])
            ax.plot(pts[:, 0], pts[:, 1], "k-", lw=1.5, label="outline")
            ax.plot([0], [0], "+", color=PALETTE[1], ms=10, mew=1.5, label="centre of mass")
            for k, c in enumerate(self.corners):
                px, py = c.distance * math.cos(c.direction), c.distance * math.sin(c.direction)
                ax.plot([px], [py], "o", color=PALETTE[4], ms=5, label="corner" if k == 0 else None)
            ax.set_aspect("equal")
            ax.set_xlabel("x (κ)")
            ax.set_ylabel("y (κ)")
            ax.set_title(f"b0 = {self.b0:g} κ, {self.regime}")
        return ax

    def _repr_svg_(self) -> str:
        from .export.svg import svg_text

        return svg_text(self)

    @safe_repr
    def __repr__(self) -> str:
        return (f"Body(regime={self.regime!r}, b0={self.b0:g}, b_c={self.b_c:.6g}, method={self.method!r}, "
                f"points={self.x.size}, corners={len(self.corners)}, area={self.area:.6g}, "
                f"max_wall_error={self.max_wall_error:.2e})")
