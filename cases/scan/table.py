"""What a worker needs to rebuild a cell's billiard table: the wall as text (or as a picklable Wall), the fixed
parameters, b0 and κ.

A :class:`~coinwall.forward.wall.Wall` made from an expression holds casadi SX objects, which do not pickle
("Cannot pickle SX objects without a casadi context"), so a scan never sends one: it sends the expression's
text and parameters, small and exact, and each worker parses it again (about 10 ms once casadi is loaded).
Walls made from Fourier coefficients, samples or arcs pickle and may be sent as objects (the CLI sends those,
and the walls of ``case:NAME``), but then no wall parameter can be scanned.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from coinwall.forward.errors import InvalidArgument
from coinwall.forward.wall import Wall

__all__ = ["DEFAULT_RESTITUTION", "TOSS_AXES", "TableSpec", "wall_digest"]

#: axis names that are not wall parameters: the toss quantities read them (the coefficient of restitution)
TOSS_AXES = ("restitution",)
#: the coefficient of restitution of a toss scan that neither scans nor fixes one (as ``coinwall toss --e``)
DEFAULT_RESTITUTION = 0.6


@dataclass(frozen=True)
class TableSpec:
    """The billiard of a cell, as data.

    Attributes
    ----------
    wall : str or Wall
        An expression in ``t`` (parsed on the worker with the cell's parameter values) or a Wall; a Wall made
        from an expression is kept as its text and parameters, any other must pickle.
    params : tuple of (str, float)
        Fixed parameters of the expression (the scanned ones come with each cell).
    b0 : float
        Offset added to the wall, in the unit of the wall (divided by ``kappa`` when given).
    kappa : float or None
        Radius of gyration in the wall's length unit: wall, H and b0 are divided by it (docs/dynamics.md, Units).

    Examples
    --------
    >>> from coinwall.cases.scan import TableSpec
    >>> TableSpec("sqrt((1+eps*cos(t)**2)/(1+eps))", b0=-0.1)
    TableSpec(wall='sqrt((1+eps*cos(t)**2)/(1+eps))', params=(), b0=-0.1, kappa=None)
    """

    wall: object
    params: tuple = field(default=())
    b0: float = 0.0
    kappa: float | None = None

    def __post_init__(self):
        if not isinstance(self.wall, (str, Wall)):
            raise InvalidArgument(f"`wall` must be an expression or a Wall, got {type(self.wall).__name__}")
        params = dict(self.params)
        if isinstance(self.wall, Wall) and self.wall.kind == "expression":
            # an expression Wall does not pickle: keep its text and parameters, from which it is rebuilt exactly
            params = {**dict(self.wall.params), **params}
            object.__setattr__(self, "wall", self.wall.description)
        object.__setattr__(self, "params", tuple(sorted((str(k), float(v)) for k, v in params.items())))
        if not math.isfinite(float(self.b0)):
            raise InvalidArgument(f"`b0` must be a finite number, got {self.b0!r}")
        if self.kappa is not None and not (math.isfinite(float(self.kappa)) and self.kappa > 0):
            raise InvalidArgument(f"`kappa` must be a positive length, got {self.kappa!r}")

    @property
    def description(self) -> str:
        """The wall as text, for the store's attributes."""
        return self.wall if isinstance(self.wall, str) else self.wall.description

    def wall_at(self, values: dict) -> Wall:
        """The Wall with the scanned parameter ``values`` (a dict) on top of the fixed ones, scaled by 1/κ."""
        values = {k: v for k, v in values.items() if k not in TOSS_AXES}
        if isinstance(self.wall, str):
            fixed = {k: v for k, v in self.params if k not in TOSS_AXES}
            wall = Wall.from_expression(self.wall, {**fixed, **values})
        elif values:
            raise InvalidArgument(f"wall {self.description!r} is not an expression: its parameters "
                                  f"{sorted(values)} cannot be scanned")
        else:
            wall = self.wall
        return wall if self.kappa is None else wall.scaled(1.0 / self.kappa)

    def table_at(self, values: dict, H: float):
        """The :class:`~coinwall.forward.dynamics.billiard.table.Billiard` of a cell (H in the wall's length unit)."""
        from coinwall.forward.dynamics.billiard.table import Billiard

        kappa = 1.0 if self.kappa is None else float(self.kappa)
        return Billiard(self.wall_at(values), float(H) / kappa, float(self.b0) / kappa)

    def field_table_at(self, values: dict, g: float):
        """The :class:`~coinwall.forward.dynamics.floor.field.FieldTable` of a toss cell: a floor only, the field ``g``
        (κ/s²) and the restitution ``restitution`` (a scanned axis or a fixed parameter; else
        :data:`DEFAULT_RESTITUTION`, as ``coinwall toss``)."""
        from coinwall.forward.dynamics.floor.field import FieldTable

        kappa = 1.0 if self.kappa is None else float(self.kappa)
        restitution = {**dict(self.params), **values}.get("restitution", DEFAULT_RESTITUTION)
        return FieldTable(self.wall_at(values), g=g, e=float(restitution),
                          b0=float(self.b0) / kappa)

    def identity(self) -> dict:
        """JSON-ready description (compared when a scan resumes into an existing store).  A wall that is not an
        expression (samples, Fourier coefficients, arcs: a file's content) is there by :func:`wall_digest`, so a
        wall file whose content changed under the same name is another scan."""
        identity = {"wall": self.description, "params": dict(self.params), "b0": float(self.b0),
                    "kappa": None if self.kappa is None else float(self.kappa)}
        if not isinstance(self.wall, str):
            identity["wall_sha256"] = wall_digest(self.wall)
        return identity


#: angles at which :func:`wall_digest` evaluates a wall (no sample grid falls on them)
_DIGEST_ANGLES = 4099


def wall_digest(wall: Wall) -> str:
    """SHA-256 (hex) of what a wall is: its kind, its description, its samples as intervals (angles, values,
    half-widths, counts) or its coefficients, and b, b', b'' at 4099 angles.

    Parameters
    ----------
    wall : Wall

    Returns
    -------
    str
        64 hexadecimal digits; equal for walls read from equal data, different when any number changed.

    Examples
    --------
    >>> theta = [k * math.pi / 4 for k in range(8)]
    >>> a = Wall.from_samples(theta, [1.0, 1.1, 1.2, 1.1, 1.0, 1.1, 1.2, 1.1])
    >>> wall_digest(a) == wall_digest(Wall.from_samples(theta, [1.0, 1.1, 1.2, 1.1, 1.0, 1.1, 1.2, 1.1]))
    True
    >>> wall_digest(a) == wall_digest(Wall.from_samples(theta, [1.0, 1.1, 1.2, 1.1, 1.0, 1.1, 1.2, 1.15]))
    False
    """
    import hashlib

    import numpy as np

    h = hashlib.sha256(f"{wall.kind}\n{wall.description}\n".encode())
    arrays = []
    data = wall.sample_data
    if data is not None:
        arrays += [data.theta, data.b, data.halfwidth, data.sigma_b, data.sigma_theta, data.count]
    elif wall.samples is not None:
        arrays += [*wall.samples, wall.sample_rounding if wall.sample_rounding is not None else []]
    arrays += [getattr(wall._backend, name) for name in ("a0", "cos", "sin", "angles", "centres", "radii")
               if hasattr(wall._backend, name)]
    arrays += list(wall.derivatives(np.linspace(0.0, 2 * math.pi, _DIGEST_ANGLES, endpoint=False) + 1e-3))
    for array in arrays:
        values = np.ascontiguousarray(np.asarray(array, dtype="<f8")).ravel()
        h.update(values.size.to_bytes(8, "little"))
        h.update(values.tobytes())
    return h.hexdigest()
