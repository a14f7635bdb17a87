"""Public names of this package: the table that its ``__init__.py`` loads lazily (SPEC 1)."""

from .rigidbody import (
    EllipseShape,
    PolygonShape,
    RigidBody,
    RigidBodyTrajectory,
    billiard_to_body,
    body_to_billiard,
    simulate_rigid_body,
)
from .table import Billiard, compile_kernel, ensemble, random_states, simulate
from .trajectory import Trajectory

__all__ = [
    "Billiard",
    "EllipseShape",
    "PolygonShape",
    "RigidBody",
    "RigidBodyTrajectory",
    "Trajectory",
    "billiard_to_body",
    "body_to_billiard",
    "compile_kernel",
    "ensemble",
    "random_states",
    "simulate",
    "simulate_rigid_body",
]
