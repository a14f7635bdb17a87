"""Angles: the period of every wall, and reduction to one period."""

import math

__all__ = ["TWO_PI", "reduce_angle"]

TWO_PI = 2.0 * math.pi


def reduce_angle(theta):
    """θ reduced to [0, 2π) (scalars and arrays)."""
    import numpy as np

    reduced = np.mod(theta, TWO_PI)
    # np.mod can return exactly 2π for tiny negative θ (rounding); fold it back
    if np.ndim(reduced):
        return np.where(reduced >= TWO_PI, 0.0, reduced)
    return 0.0 if reduced >= TWO_PI else float(reduced)
