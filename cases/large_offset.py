"""The large-offset regime (paper section IV, eq. 23–25).

For ``b0 ≫ |b|`` the body is nearly a circle and ``R(α) ≈ b0 + b(α)`` with
``α ≈ θ`` (eq. 25).  The exact envelope gives the size of the error: with
``h = b0 + b``, ``R = sqrt(h² + h'²)`` at ``α = φ + atan(h'/h)``, so
``R(α) − (b0 + b(α)) = −b'(α)²/(2 b0) + O(b0⁻²)`` (expand ``R`` to second order
and shift the argument by ``atan(h'/h) ≈ b'/b0``; derived in
``tests/inverse/test_known_answers.py::test_large_offset_expansion``).  The error falls
like 1/b0, as the paper's "sufficiently large b0" implies.
"""

from .catalog import Case, Reference
from .ellipse import ELLIPSE_WALL, ellipse_wall

__all__ = ["CASES"]

CASES = (
    Case("large-offset", "ellipse wall ε = 1 at b0 = 20: R(α) ≈ b0 + b(α)", "paper section IV, eq. 25",
         lambda: ellipse_wall(1.0), 20.0, None, None,
         (Reference("error_leading", "−b'(α)²/(2 b0)", "expansion of the envelope (module docstring)"),
          Reference("regime", "convex", "ρ = b0 + b + b'' > 0 for b0 > 1/2")),
         ELLIPSE_WALL, {"eps": 1.0}),
)
