"""The ``bounce3d`` toss: a body of revolution dropped at random, bouncing on a frictionless floor until it rests.

Units: the lengths of the family (radius, thickness: any one unit, say mm), time in seconds, ``g`` in that
unit per s² (9810 for mm), speeds in that unit per second, spins in rad/s.

The launch (:class:`Launch3D`).  The axis of the body points in a uniformly random direction (the tilt θ0
from the upward vertical with cos θ0 uniform in [−1, 1]), its lowest point is ``height`` above the floor, it
moves up at ``v0 ~ N(mean, sd²)``, and it turns with an angular velocity whose three lab components are
independent ``N(0, spin²)``: an isotropic tumble.  Four uniforms/normals per toss, independent of the body
(common random numbers across a family).

The toss.  A frictionless horizontal floor keeps ``L_z`` and the spin ``L₃``, and the motion is the reduced
billiard of :mod:`coinwall.forward.dynamics.coin3d.top` in the tilt and the height with the top's potential;
:func:`coinwall.forward.dynamics.coin3d.rest.rest_outcomes` bounces each toss until it cannot leave its
valley and reads the face it rests on: heads, edge or tails.  Angular velocity ω and axis a give
``ℓ = ω⊥ + (I₃/I₁)(ω·a) a`` (``ℓ = L/I₁``), ``ℓ₃ = ℓ·a``, ``ℓ_z = ℓ·ẑ`` and ``θ̇ = −(ω × a)_z / sin θ``.
A toss that comes to slide above its barrier (rolling or rocking on its rim for ever, which a frictionless
floor allows) or exhausts ``impacts`` is undecided; the odds are among the decided tosses.  Without friction
the spin about the axis is never lost, so a tumbling coin may keep more of its start than a real one does.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from coinwall.forward.display import safe_repr
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.validation import check_count, check_finite

from .bounce import _pair

__all__ = ["Bounce3D", "Launch3D"]

_NAMES = ("heads", "edge", "tails")


@dataclass(frozen=True, repr=False)
class Launch3D:
    """The tumbling drop (module docstring): ``g``, ``height`` of the lowest point, ``v0`` (mean, sd) and the
    spread ``spin`` (rad/s) of each lab component of the angular velocity.

    Parameters
    ----------
    g : float
        The field (κ₁/s², > 0).
    height : float
        Height of the body's lowest point above the floor at launch (κ₁).
    v0 : (float, float)
        Mean and standard deviation of the upward launch velocity.
    spin : float
        Standard deviation of each lab component of the angular velocity (rad/s, ≥ 0).

    Examples
    --------
    >>> Launch3D().draw(np.random.default_rng(0), 2).shape
    (2, 5)
    """

    g: float = 1.0
    height: float = 2.0
    v0: tuple = (0.0, 0.0)
    spin: float = 3.0

    def __post_init__(self):
        g = check_finite("g", self.g)
        if not g > 0:
            raise InvalidArgument(f"`g` must be a positive field, got {g:g}")
        height = check_finite("height", self.height)
        if not height > 0:
            raise InvalidArgument(f"`height` (of the lowest point above the floor) must be positive, got {height:g}")
        spin = check_finite("spin", self.spin)
        if spin < 0:
            raise InvalidArgument(f"`spin` must be >= 0, got {spin:g}")
        object.__setattr__(self, "g", g)
        object.__setattr__(self, "height", height)
        object.__setattr__(self, "spin", spin)
        object.__setattr__(self, "v0", _pair("v0", self.v0))

    dimensions = 5

    def draw(self, rng, n: int) -> np.ndarray:
        """``(n, 5)``: a uniform (the tilt) and four standard normals (v0 and the three spin components)."""
        return np.column_stack([rng.random(n), rng.standard_normal((n, 4))])

    def to_dict(self) -> dict:
        return {"g": self.g, "height": self.height, "v0": list(self.v0), "spin": self.spin}

    @safe_repr
    def __repr__(self):
        return f"Launch3D(g={self.g:g}, height={self.height:g}, v0={self.v0[0]:g}±{self.v0[1]:g}, spin σ={self.spin:g})"


def reduced_states(body, launch: Launch3D, draws):
    """``(states, ℓz, ℓ3)`` of the reduced billiard (units of κ₁) for the draws (module docstring)."""
    d = np.asarray(draws, dtype=float)
    k1 = body.kappa1
    cos0 = np.clip(1.0 - 2.0 * d[:, 0], -1.0 + 1e-12, 1.0 - 1e-12)
    theta = np.arccos(cos0)
    s = np.sin(theta)
    axis = np.column_stack([s, np.zeros_like(s), cos0])
    omega = launch.spin * d[:, 2:5]
    along = np.sum(omega * axis, axis=1)
    ell = omega - along[:, None] * axis + (body.I3 / body.I1) * along[:, None] * axis
    l3 = np.sum(ell * axis, axis=1)
    lz = ell[:, 2]
    rate = np.cross(omega, axis)
    theta_dot = -rate[:, 2] / s
    h = body.support(theta)[0]
    eta = (h + launch.height) / k1
    v = (launch.v0[0] + launch.v0[1] * d[:, 1]) / k1
    return np.column_stack([theta, eta, theta_dot, v]), lz, l3


class Bounce3D:
    """The 3-D bounce toss (module docstring).

    Parameters
    ----------
    e : float
        Restitution in (0, 1].
    launch : Launch3D, optional
        The tumbling drop (default :class:`Launch3D`'s defaults).
    impacts : int
        Impacts per toss at most.
    workers : int, optional
        Threads of the compiled toss.

    Examples
    --------
    >>> Bounce3D(e=0.5).name
    'bounce3d'
    """

    name = "bounce3d"
    exact = False

    def __init__(self, e: float = 0.6, launch: Launch3D | None = None, impacts: int = 10_000, workers=None):
        e = check_finite("e", e)
        if not 0.0 < e <= 1.0:
            raise InvalidArgument(f"`e` must be a coefficient of restitution in (0, 1], got {e:g}")
        self.e = e
        self.launch = launch if launch is not None else Launch3D()
        if not isinstance(self.launch, Launch3D):
            raise InvalidArgument(f"`launch` must be a Launch3D, got {type(self.launch).__name__}")
        self.impacts = check_count("impacts", impacts, maximum=10 ** 9)
        self.workers = workers

    @property
    def dimensions(self) -> int:
        return self.launch.dimensions

    def draw(self, rng, n):
        return self.launch.draw(rng, n)

    def simulate(self, kind, body, draws, names, b0=0.0):
        """Toss ``body`` (a Revolution) once per draw; returns ``(hits, undecided)`` (bool arrays)."""
        from coinwall.forward.dynamics.coin3d.rest import rest_outcomes
        from coinwall.forward.dynamics.coin3d.top import TopTable

        if kind != "cylinder":
            raise InvalidArgument("the bounce3d toss is for a body of revolution; a planar body bounces in the bounce "
                                  "toss")
        unknown = [n for n in names if n not in _NAMES]
        if unknown:
            raise InvalidArgument(f"outcome {unknown[0]!r}: the bounce3d toss tells heads, edge and tails only")
        k1 = body.kappa1
        table = TopTable(body, g=self.launch.g / k1, e=self.e)
        states, lz, l3 = reduced_states(body, self.launch, draws)
        out = rest_outcomes(table, states, lz, l3, self.impacts, workers=self.workers)["outcome"]
        return {name: out == _NAMES.index(name) for name in names}, out < 0

    def to_dict(self) -> dict:
        return {"model": self.name, "e": self.e, "impacts": self.impacts, "launch": self.launch.to_dict()}

    @safe_repr
    def __repr__(self):
        return f"Bounce3D(e={self.e:g}, {self.launch!r})"

