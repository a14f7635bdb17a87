"""The wall function b(θ): the object the forward and the inverse side share.

Convention (pinned by tests/inverse/test_conventions.py with a triangle, which has no symmetry axis):
``b0 + b(θ)`` is the support function ``h`` of the body evaluated at the
body-frame polar angle ``θ``, measured counter-clockwise from the body axis.
Physically, θ is the angle measured *clockwise* from the outward normal of the
bottom wall (pointing down, away from the body) to the body axis, as in the
paper's section II.  The upper wall of the billiard is ``H − b(θ + π)``.

A wall is 2π-periodic and finite.  Where it has a corner (a *kink*: ``b'``
jumps), ``b''`` is a measure with a point mass ``jump = b'(θ+) − b'(θ−)``;
kinks are located exactly and reported in :attr:`Wall.kinks`, never smoothed.
A positive jump is an edge of the body (a straight piece of length ``jump``);
a negative jump cannot belong to any convex body.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from .angles import TWO_PI
from .display import safe_repr
from .errors import InvalidWall
from .validation import check_memory
from .wallbackends import MAX_HARMONICS, MS_PER_HARMONIC, _ArcsBackend, _FourierBackend, _SampledBackend

__all__ = ["BYTES_PER_SAMPLE", "MAX_MAGNITUDE", "MAX_SAMPLES", "Kink", "Wall", "check_magnitude"]

_MIN_SAMPLES = 8
#: Largest |b| and |b'| of a wall.  The body's area ``½∫(h² − h'²)`` and polar moment
#: ``¼∫(h² + h'²) h (h + h'') dφ`` are fourth powers of the wall: (1.8e308)^(1/4) ≈ 1e77 is where they
#: overflow; 1e60 leaves room for the sums and the offset.
MAX_MAGNITUDE = 1e60
#: Most distinct sample angles a wall takes: the critical offset of 10⁶ samples is the data's own geometry,
#: O(n log n), and a solve of them takes seconds (tests/benchmarks/bench_dense_data.py); peaks of 166–540
#: bytes per sample (tracemalloc), counted as :data:`BYTES_PER_SAMPLE`.  Non-uniform samples are further bounded for their least-squares
#: interpolant (:data:`~.wallbackends.MAX_LSQ_SAMPLES`).  The wall-file readers read at most as many rows.
MAX_SAMPLES = 1_000_000
BYTES_PER_SAMPLE = 600
_CHECK_POINTS = 4096
# least squares costs n·k²: beyond a few hundred harmonics a smooth wall gains nothing and a large
# non-uniform data set would take minutes (the data themselves are solved exactly: inverse/discrete.py)
_MAX_LSQ_HARMONICS = 256
_BLOCK = 2048  # casadi evaluates point by point; a mapped block amortises the call overhead


@dataclass(frozen=True)
class Kink:
    """A corner of the wall at ``angle`` where ``b'`` jumps by ``jump``.

    ``slope_left``/``slope_right`` are the one-sided first derivatives and
    ``curvature_left``/``curvature_right`` the one-sided second derivatives.

    Attributes
    ----------
    angle : float
        Where the kink is, in [0, 2π).
    jump : float
        ``b'(angle⁺) − b'(angle⁻)``: a positive jump is a straight edge of the body of that length; a negative
        one belongs to no convex body.
    slope_left, slope_right : float
        The one-sided first derivatives.
    curvature_left, curvature_right : float
        The one-sided second derivatives.

    Examples
    --------
    The stick's wall ``L |cos θ|`` (the paper's eq. 5) has kinks at π/2 and 3π/2, each a jump of 2L: the
    stick is a segment of length 2L.

    >>> from coinwall import Wall
    >>> stick = Wall.from_expression("L*abs(cos(t))", {"L": 1.0})
    >>> [(round(k.angle, 12), round(k.jump, 12)) for k in stick.kinks]
    [(1.570796326795, 2.0), (4.712388980385, 2.0)]
    """

    angle: float
    jump: float
    slope_left: float
    slope_right: float
    curvature_left: float
    curvature_right: float


class _ExpressionBackend:
    """Exact derivatives by casadi's symbolic differentiation of the parsed expression."""

    def __init__(self, parsed):
        import casadi as ca

        t = parsed.symbol
        b = parsed.expr
        d1 = ca.jacobian(b, t)
        d2 = ca.jacobian(d1, t)
        single = ca.Function("wall", [t], [b, d1, d2])
        single0 = ca.Function("wall0", [t], [b])
        # each function three ways: casadi for one angle, casadi mapped over blocks, and casadi's own
        # algorithm replayed by numpy on whole arrays (forward/wallvector.py: no per-block call and no
        # conversion of casadi's results; None where casadi uses an operation numpy lacks)
        self._f012 = self._three(single)
        self._f0 = self._three(single0)
        self._switching = [self._three(ca.Function(f"s{k}", [t], [s])) for k, s in enumerate(parsed.switching)]
        self.parsed = parsed

    @staticmethod
    def _three(func):
        from .wallvector import array_program

        return func, func.map(_BLOCK), array_program(func)

    @staticmethod
    def _blocks(funcs, theta, n_out):
        theta = np.ascontiguousarray(theta, dtype=float).ravel()
        n = theta.size
        single, func, program = funcs
        if program is not None and n > 1:  # one angle (root finders): casadi's own call is cheaper
            return program(theta)
        if n <= 8:  # root finders call with one or two points: skip the padded block
            res = [single(x) for x in theta]
            res = [r if n_out > 1 else (r,) for r in res]
            return [np.array([float(r[k]) for r in res]) for k in range(n_out)]
        out = [np.empty(n) for _ in range(n_out)]
        for start in range(0, n, _BLOCK):
            chunk = theta[start:start + _BLOCK]
            m = chunk.size
            if m < _BLOCK:
                chunk = np.concatenate([chunk, np.zeros(_BLOCK - m)])
            res = func(chunk.reshape(1, -1))
            if n_out == 1:
                res = (res,)
            for k in range(n_out):
                out[k][start:start + m] = np.asarray(res[k]).ravel()[:m]
        return out

    def values(self, theta):
        return self._blocks(self._f0, theta, 1)[0]

    def derivatives(self, theta):
        return tuple(self._blocks(self._f012, theta, 3))

    def switching(self, theta):
        return [self._blocks(s, theta, 1)[0] for s in self._switching]


def check_magnitude(description: str, theta, b, slope=None) -> None:
    """Refuse a wall whose values or slopes exceed :data:`MAX_MAGNITUDE` (on the check angles ``theta``)."""
    for name, values in (("b", b), ("b'", slope)):
        if values is None or not values.size:
            continue
        worst = int(np.argmax(np.abs(values)))
        if abs(values[worst]) > MAX_MAGNITUDE:
            raise InvalidWall(f"wall {description!r}: |{name}| = {abs(values[worst]):.3g} at θ = {theta[worst]:.6g} "
                              f"is more than {MAX_MAGNITUDE:g}; the body's area (∝ b²) and moment of inertia (∝ b⁴) "
                              "would overflow: measure the wall in a larger unit")


class Wall:
    """A 2π-periodic wall function b(θ) with exact first and second derivatives.

    Build one with :meth:`from_expression`, :meth:`from_samples` or
    :meth:`from_fourier`; do not call the constructor directly.

    Attributes
    ----------
    description : str
        What the wall was made from (the expression, "samples (n=…)", …).
    kind : str
        ``"expression"``, ``"fourier"`` or ``"samples"``.
    params : Mapping[str, float]
        The named parameters of an expression (read-only).
    kinks : tuple of Kink
        Corners of the wall, sorted by angle in [0, 2π).
    breaks : tuple of float
        Angles where b' is continuous but b'' jumps (the end of a vertex window on an arc: the radius of
        curvature of the body jumps there); solvers put a node on each, as on a kink.
    samples : tuple of ndarray or None
        For a wall made from samples: the distinct angles in [0, 2π), sorted, and their values.
    sample_rounding : ndarray or None
        How far the wall at each sample's angle may be from its value (aligned with ``samples``): the
        values' and the angles' rounding (the digits a file carried, a measurement's accuracy, a
        solver's tolerance) and merged duplicates; a few ulps for values at face value.
    sample_data : coinwall.forward.sampledata.SampleData or None
        The samples as intervals, with the half-widths of values and angles they came from.

    A wall is immutable, like every result: it is shared by the forward and the inverse side, and
    caches (its scale, its check grid) are only valid for the function it was made with.

    Examples
    --------
    The paper's ellipse wall (eq. 18) with ε = 1, its exact derivatives, and the same wall sampled:

    >>> import numpy as np
    >>> from coinwall import Wall
    >>> wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> wall
    Wall('sqrt((1+eps*cos(t)**2)/(1+eps))' [eps=1])
    >>> float(wall(0.0)), round(float(wall(np.pi / 2)), 12)     # 1 and 1/√2
    (1.0, 0.707106781187)
    >>> b, slope, curvature = wall.derivatives(np.array([0.0]))
    >>> float(curvature[0])                # b + b'' = 1/(1+ε) at θ = 0 (eq. 18), so b''(0) = −1/2
    -0.5
    >>> grid = np.linspace(0.0, 2 * np.pi, 64, endpoint=False)
    >>> sampled = Wall.from_samples(grid, wall(grid))
    >>> sampled.kind, bool(abs(sampled(0.3) - wall(0.3)) < 1e-12)
    ('samples', True)
    """

    def __init__(self, backend, description: str, kind: str, params: Mapping[str, float] | None = None,
                 samples=None):
        init = object.__setattr__  # the instance is frozen: set each field once, here
        init(self, "_backend", backend)
        init(self, "description", description)
        init(self, "kind", kind)
        init(self, "params", MappingProxyType(dict(params or {})))
        init(self, "samples", samples)
        init(self, "sample_rounding", None)
        init(self, "sample_data", None)
        init(self, "kinks", ())
        init(self, "breaks", ())
        if samples is not None:
            # an interpolant of finite samples is finite and periodic by construction, and has no kinks
            # (data's kinks are found from the samples themselves: inverse/discrete.py)
            init(self, "_scale", max(1.0, float(np.max(np.abs(samples[1])))))
            return
        self._validate()
        kinks, breaks = self._find_kinks()
        init(self, "kinks", kinks)
        init(self, "breaks", breaks)

    def __setattr__(self, name, value):
        raise AttributeError(f"a Wall is immutable: cannot set {name!r}; make a new one (Wall.from_…, .scaled)")

    def __delattr__(self, name):
        raise AttributeError(f"a Wall is immutable: cannot delete {name!r}")

    def __getstate__(self):
        return {**self.__dict__, "params": dict(self.params)}  # a mappingproxy does not pickle

    def __setstate__(self, state):
        for name, value in state.items():
            object.__setattr__(self, name, MappingProxyType(value) if name == "params" else value)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_expression(cls, text: str, params: Mapping[str, float] | None = None) -> Wall:
        """Wall from an expression in ``t`` (alias ``theta``) with named parameters.

        The expression is parsed with a whitelist (see
        :func:`forward.expression.parse_expression`), never evaluated as Python.
        """
        from .expression import parse_expression

        parsed = parse_expression(text, params)
        return cls(_ExpressionBackend(parsed), text.strip(), "expression", dict(parsed.params))

    @classmethod
    def from_fourier(cls, a0: float = 0.0, cos: Sequence[float] = (), sin: Sequence[float] = ()) -> Wall:
        """Wall ``a0 + Σ_{k≥1} cos[k-1]·cos kθ + sin[k-1]·sin kθ``."""
        coeffs = {"a0": np.atleast_1d(np.asarray(a0, dtype=float)),
                  "cos": np.asarray(cos, dtype=float).ravel(),
                  "sin": np.asarray(sin, dtype=float).ravel()}
        for name, arr in coeffs.items():
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise InvalidWall(f"Fourier coefficient `{name}`[{bad[0]}] must be finite, got {arr[bad[0]]}")
        if coeffs["a0"].size != 1:
            raise InvalidWall(f"Fourier coefficient `a0` must be a single number, got {coeffs['a0'].size} values")
        n = max(coeffs["cos"].size, coeffs["sin"].size)
        if n > MAX_HARMONICS:
            raise InvalidWall(f"a Fourier series of {n} harmonics is more than the {MAX_HARMONICS} allowed: every "
                              f"evaluation costs harmonics × angles (about {MS_PER_HARMONIC:g} ms per harmonic for "
                              f"`critical`, so {n} would take about {n * MS_PER_HARMONIC / 1000:.0f} s); give fewer "
                              "harmonics, or samples of the wall")
        return cls(_FourierBackend(float(coeffs["a0"][0]), coeffs["cos"], coeffs["sin"]),
                   f"Fourier series ({n} harmonics)", "fourier")

    @classmethod
    def from_arcs(cls, angles: Sequence[float], centres, radii: Sequence[float], *,
                  description: str | None = None) -> Wall:
        """The exact wall of a convex body bounded by circle arcs, vertices and straight edges.

        Piece k, for wall angles from ``angles[k]`` to the next one, is ``centres[k]·n(θ) + radii[k]``:
        the arc of radius ``radii[k]`` about ``centres[k]``, or the vertex ``centres[k]`` when the
        radius is 0.  Pieces must meet continuously (a straight edge joins two pieces that meet with
        different slopes, a kink of the wall).  Reuleaux polygons, polygons and rounded polygons are
        represented exactly, which no sampled or Fourier wall can do.
        """
        angles = np.asarray(angles, dtype=float).ravel()
        centres = np.asarray(centres, dtype=float).reshape(-1, 2)
        radii = np.asarray(radii, dtype=float).ravel()
        if not (angles.size == len(centres) == radii.size) or angles.size < 1:
            raise InvalidWall(f"arcs: {angles.size} angles, {len(centres)} centres and {radii.size} radii; "
                              "give one of each per piece")
        for name, arr in (("angles", angles), ("centres", centres), ("radii", radii)):
            if not np.all(np.isfinite(arr)):
                raise InvalidWall(f"arcs: `{name}` must be finite")
        if np.any(radii < 0):
            raise InvalidWall(f"arcs: `radii` must be ≥ 0, got {radii.min():g}")
        order = np.argsort(np.mod(angles, TWO_PI), kind="stable")
        angles, centres, radii = np.mod(angles, TWO_PI)[order], centres[order], radii[order]
        if np.any(np.diff(angles) <= 0):
            raise InvalidWall("arcs: two pieces start at the same angle")
        # continuity at every break: the pieces on either side give the same support value
        before = np.roll(np.arange(angles.size), 1)
        n = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        left = np.sum(centres[before] * n, axis=1) + radii[before]
        right = np.sum(centres * n, axis=1) + radii
        scale = max(1.0, float(np.max(np.abs(right))))
        worst = int(np.argmax(np.abs(left - right)))
        if abs(left[worst] - right[worst]) > 1e-9 * scale:
            raise InvalidWall(f"arcs: the pieces do not meet at θ = {angles[worst]:.6g} "
                              f"({left[worst]:.9g} from the left, {right[worst]:.9g} from the right)")
        backend = _ArcsBackend(angles, centres, radii)
        return cls(backend, description or f"arcs ({angles.size} pieces)", "arcs")

    @classmethod
    def from_samples(cls, theta: Sequence[float], b: Sequence[float], *, max_harmonics: int | None = None,
                     rounding=None, theta_rounding=None, labels=None, merge: str = "intersect", sd=None,
                     theta_sd=None, grid=None) -> Wall:
        """Wall from periodic samples ``(θ_i, b_i)``, uniform or not.

        Each sample is an interval (:mod:`coinwall.forward.sampledata`): ``b_i`` is known to ``±rounding``
        and ``θ_i`` to ``±theta_rounding`` (radians; default: both at face value, a few ulps).  Samples at
        the same angle (θ and θ + 2π, duplicates) are merged into the intersection of their intervals;
        two that cannot both hold are an error naming them (``labels``, e.g. the file's line numbers);
        ``merge="mean"`` averages them instead (noisy measurements, :func:`coinwall.inverse.fit.fit_convex`).
        The intervals are kept as :attr:`sample_data`; :attr:`samples` holds the distinct angles and the
        middle of each interval, :attr:`sample_rounding` its half-width.  ``sd`` and ``theta_sd`` are standard
        deviations of the values and angles (statistics, not bounds: the solvers then estimate, with confidence
        intervals); samples at one angle are then averaged.  ``grid``: the step (radians) of a uniform grid the
        angles were written on, taken as exact only where the samples agree (:func:`~.sampledata.sample_intervals`).

        The samples are replaced by a trigonometric polynomial: the interpolant
        (FFT) for uniform samples, a least-squares fit with at most a third as
        many harmonics as samples (at most 256) for non-uniform ones.  Derivatives are those
        of the trigonometric polynomial, hence spectrally accurate for smooth
        walls.  The samples must cover the whole period.  The interpolant is made on first use (the
        critical offset and the half-plane body of the data never need it).  At most
        :data:`MAX_SAMPLES` distinct angles, and :data:`~.wallbackends.MAX_LSQ_SAMPLES` non-uniform ones
        for the interpolant.
        """
        from .sampledata import sample_intervals

        theta = np.asarray(theta, dtype=float).ravel()
        b = np.asarray(b, dtype=float).ravel()
        if theta.size != b.size:
            raise InvalidWall(f"samples: {theta.size} angles but {b.size} wall values")
        for name, arr in (("θ", theta), ("b", b)):
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise InvalidWall(f"samples: {name} of sample {bad[0]} is {arr[bad[0]]}; every sample must be finite")
        check_magnitude("samples", theta, b)
        if theta.size > 4 * MAX_SAMPLES:
            raise InvalidWall(f"samples: {theta.size} samples, at most {4 * MAX_SAMPLES}; thin the samples")
        if theta.size < _MIN_SAMPLES:
            raise InvalidWall(f"samples: too short: {theta.size} samples, need at least {_MIN_SAMPLES}")
        data = sample_intervals(theta, b, rounding, theta_rounding, labels, merge=merge, sd=sd, theta_sd=theta_sd,
                                grid=grid)
        reduced, values = data.theta, data.b
        scale = max(1.0, float(np.max(np.abs(values))))
        n = reduced.size
        if n < _MIN_SAMPLES:
            raise InvalidWall(f"samples: too short: {n} distinct angles, need at least {_MIN_SAMPLES}")
        if n > MAX_SAMPLES:
            raise InvalidWall(f"samples: {n} distinct angles, at most {MAX_SAMPLES} (about 30 s of work and "
                              f"{BYTES_PER_SAMPLE * MAX_SAMPLES / 2**20:.0f} MiB); thin the samples")
        check_memory(f"{n} samples ({BYTES_PER_SAMPLE} bytes per sample)", n * BYTES_PER_SAMPLE, error=InvalidWall)
        gaps = np.diff(np.concatenate([reduced, [reduced[0] + TWO_PI]]))
        big = int(np.argmax(gaps))
        if gaps[big] > 10.0 * np.median(gaps) and gaps[big] > 0.2:
            raise InvalidWall(
                f"samples: the wall does not cover a full period: no sample between θ = {reduced[big]:.4g} and "
                f"θ = {(reduced[big] + gaps[big]):.4g}; give b(θ) over all of [0, 2π)")
        uniform = np.allclose(gaps, TWO_PI / n, rtol=0, atol=1e-9)
        harmonics = None if uniform else (max_harmonics or max(1, min(n // 3, _MAX_LSQ_HARMONICS)))
        if uniform:
            desc = f"uniform samples (n={n})"
        else:
            desc = f"non-uniform samples (n={n}, {harmonics} harmonics, least squares)"
        reduced.setflags(write=False)
        values.setflags(write=False)
        # the interpolant is made on first use: the data's own geometry (critical offset, half-plane body)
        # never needs it, and a least-squares fit of many non-uniform samples costs n·k²
        wall = cls(_SampledBackend(reduced, values, harmonics, scale), desc, "samples", samples=(reduced, values))
        object.__setattr__(wall, "sample_rounding", data.halfwidth)
        object.__setattr__(wall, "sample_data", data)
        return wall

    # ------------------------------------------------------------------ evaluation
    def __call__(self, theta):
        """b(θ) for an array (or scalar) of angles."""
        scalar = np.ndim(theta) == 0
        out = self._backend.values(np.atleast_1d(theta))
        return float(out[0]) if scalar else out.reshape(np.shape(theta))

    def derivatives(self, theta):
        """``(b, b', b'')`` at ``theta`` (arrays).

        At a kink the value of b' is not meaningful: use :meth:`one_sided`."""
        shape = np.shape(theta)
        return tuple(v.reshape(shape) for v in self._backend.derivatives(np.atleast_1d(theta)))

    def one_sided(self, theta: float, side: int):
        """One-sided limits ``(b, b', b'')`` at ``theta`` from the left (``side=-1``) or right (``+1``).

        Evaluated a small step δ away and corrected to first order with the
        exact b'' there; b'' is extrapolated from δ and 2δ; both errors are O(δ²) ≈ 1e-14.
        """
        delta = 1e-7
        b, d1, d2 = self._backend.derivatives(np.array([theta, theta + side * delta, theta + 2 * side * delta]))
        # b'' extrapolated linearly from δ and 2δ: error O(δ²)
        return float(b[0]), float(d1[1] - side * delta * d2[1]), float(2 * d2[1] - d2[2])

    def scaled(self, factor: float) -> Wall:
        """The wall ``factor · b(θ)``, of the same kind, with exact derivatives.

        Used to change the length unit: a wall given in millimetres, for a body
        of radius of gyration κ mm, is ``wall.scaled(1 / κ)`` in units of κ.
        """
        from dataclasses import replace

        if isinstance(factor, bool) or not isinstance(factor, (int, float, np.floating)) \
                or not (math.isfinite(factor) and factor > 0):
            raise InvalidWall(f"the scale factor `factor` must be a positive finite number, got {factor!r}")
        factor = float(factor)
        backend = self._backend
        description = f"{factor:.12g}·({self.description})"
        if isinstance(backend, _ExpressionBackend):
            parsed = replace(backend.parsed, expr=backend.parsed.expr * factor)
            return Wall(_ExpressionBackend(parsed), description, self.kind, self.params)
        if isinstance(backend, _ArcsBackend):
            return Wall(_ArcsBackend(backend.angles, backend.centres * factor, backend.radii * factor), description,
                        self.kind, self.params)
        samples = None if self.samples is None else (self.samples[0], self.samples[1] * factor)
        if isinstance(backend, _SampledBackend):
            return Wall(backend.scaled(factor), description, self.kind, self.params, samples=samples)
        return Wall(_FourierBackend(backend.a0 * factor, backend.cos * factor, backend.sin * factor), description,
                    self.kind, self.params, samples=samples)

    @property
    def scale(self) -> float:
        """A typical magnitude of the wall (max ``|b|``, at least 1), used for relative tolerances."""
        return self._scale

    @safe_repr
    def __repr__(self) -> str:
        params = ", ".join(f"{k}={v:g}" for k, v in sorted(self.params.items()))
        extra = f" [{params}]" if params else ""
        kinks = f", {len(self.kinks)} kinks" if self.kinks else ""
        return f"Wall({self.description!r}{extra}{kinks})"

    # ------------------------------------------------------------------ checks
    def _validate(self):
        theta = np.linspace(0.0, TWO_PI, _CHECK_POINTS, endpoint=False) + 0.5 * TWO_PI / _CHECK_POINTS / 3
        b, d1, d2 = self._backend.derivatives(theta)
        for name, arr in (("b", b), ("b'", d1), ("b''", d2)):
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                raise InvalidWall(
                    f"wall {self.description!r}: {name}(θ) is not finite at θ = {theta[bad[0]]:.6g} "
                    f"({name} = {arr[bad[0]]}); the wall must be finite with finite slopes everywhere")
        # the offset grid never lands on "round" angles, where singular walls (1/(1+cos t) at π)
        # usually blow up: check multiples of π/24 exactly as well
        special = np.arange(48) * (TWO_PI / 48)
        values = self._backend.values(special)
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise InvalidWall(
                f"wall {self.description!r}: b(θ) is not finite at θ = {special[bad[0]]:.6g} "
                f"(b = {values[bad[0]]}); the wall must be finite everywhere")
        check_magnitude(self.description, theta, b, d1)
        object.__setattr__(self, "_scale", max(1.0, float(np.max(np.abs(b)))))
        if isinstance(self._backend, _ExpressionBackend):
            from .precision import check_precision

            # what floating point computes must still be the formula (cos(2t + 1e20) no longer depends on t);
            # before the periodicity check, which such a formula fails for the same reason
            check_precision(self.description, self._backend.parsed, theta[::8], self._scale)
        with np.errstate(all="ignore"):  # a non-periodic formula may overflow one period on: judged below
            shifted = self._backend.values(theta + TWO_PI)
            diff = np.abs(shifted - b)
        diff[~np.isfinite(diff)] = np.inf
        worst = int(np.argmax(diff))
        if diff[worst] > 1e-9 * self._scale:
            raise InvalidWall(
                f"wall {self.description!r} is not 2π-periodic: b(θ + 2π) − b(θ) = {shifted[worst] - b[worst]:.3g} "
                f"at θ = {theta[worst]:.6g}")
        if isinstance(self._backend, _ExpressionBackend):  # a series or arcs with finite numbers has no pole
            from .singularities import check_singularities

            # after the periodicity check: the interval after the last check angle wraps to the first
            check_singularities(self.description, self._backend.derivatives, theta, (b, d1, d2))
            from .continuity import check_continuity

            # a support function is continuous: a jump between the check angles (a sign written with abs)
            check_continuity(self.description, self._backend.derivatives, theta, (b, d1), self._scale)


    def _find_kinks(self):
        theta = np.linspace(0.0, TWO_PI, _CHECK_POINTS + 1)
        candidates = []
        for k, s in enumerate(self._backend.switching(theta)):
            sign = np.sign(s)
            # an exact zero on the grid, or a sign change between neighbours
            for i in np.flatnonzero(sign == 0):
                candidates.append(theta[i])
            for i in np.flatnonzero(sign[:-1] * sign[1:] < 0):
                from scipy.optimize import brentq  # here, not above: importing it costs ~0.35 s

                func = self._switching_scalar(k)
                candidates.append(brentq(func, theta[i], theta[i + 1], xtol=1e-15, rtol=1e-15, maxiter=200))
        kinks, breaks = [], []
        # several switching functions may find one kink: keep the first of any within 1e-11 (no
        # rounding of the angles themselves: a break's angle places the solvers' nodes)
        for angle in sorted(self._place_switch(float(np.mod(c, TWO_PI))) for c in candidates):
            if (kinks and abs(angle - kinks[-1].angle) < 1e-11) or (breaks and abs(angle - breaks[-1]) < 1e-11):
                continue
            b, left, c_left = self.one_sided(angle, -1)
            _, right, c_right = self.one_sided(angle, +1)
            jump = right - left
            if abs(jump) > 1e-8 * self._scale:
                # kink angles keep 13 decimals, as the solvers' grids and the polar branches were tuned
                # with (the polar solver's edge ends misorder on unrounded angles: tests/cases/test_cases.py)
                kinks.append(Kink(round(angle, 13), jump, left, right, c_left, c_right))
            elif abs(c_right - c_left) > 1e-6 * self._scale:
                breaks.append(angle)
        if len(kinks) > 1 and abs(kinks[-1].angle - TWO_PI) < 1e-11:
            kinks.pop()
        if len(breaks) > 1 and abs(breaks[-1] - TWO_PI) < 1e-11:
            breaks.pop()
        return tuple(kinks), tuple(breaks)

    def _place_switch(self, angle: float) -> float:
        """Where a switch found near ``angle`` really is, when it is a break.

        A ``min``/``max`` whose branches meet with equal slope (a break: the lens's and the Reuleaux
        body's corner windows) has a switching function that vanishes quadratically on one side, so its
        root is only known to ~1e-8 (√eps); there the one-sided slopes, each its own branch extrapolated to
        ``angle``, differ by (curvature jump)·(error), a false kink, and two nodes 1e-8 apart cross.  One
        Newton step on the slope difference, ``e = (b'₊ − b'₋)/(b''₋ − b''₊)``, finds where the branches
        are tangent; it is kept when the slopes then agree ten times better (a true kink stays put).
        """
        _, left, c_left = self.one_sided(angle, -1)
        _, right, c_right = self.one_sided(angle, +1)
        jump, bend = right - left, c_left - c_right
        if jump == 0 or bend == 0 or not abs(jump) < 1e-6 * abs(bend):
            return angle
        moved = angle + jump / bend
        _, left2, _ = self.one_sided(moved, -1)
        _, right2, _ = self.one_sided(moved, +1)
        return float(np.mod(moved, TWO_PI)) if abs(right2 - left2) < 0.1 * abs(jump) else angle

    def _switching_scalar(self, k):
        backend = self._backend

        def func(x):
            return float(backend.switching(np.array([x]))[k][0])

        return func
