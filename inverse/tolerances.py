"""The numbers the inverse solver works to: its default resolution and its named tolerances.

One home for each, imported by the solver (:mod:`.smooth`, :mod:`.critical`, :mod:`.sampled`,
:mod:`.realizability`) and by the front ends that print its results (the command line, the explorer): a
number below its tolerance prints as 0.  This module imports nothing, so ``coinwall --help`` can read the
defaults without loading numpy.
"""

__all__ = ["ANGLE_TOLERANCE", "AREA_TOLERANCE", "DEFAULT_POINTS", "DEFICIT_TOLERANCE", "DIRECTION_TOLERANCE",
           "OFFSET_TOLERANCE", "REALIZABLE_TOLERANCE", "WALL_ACCURACY"]

#: Outline nodes of a solved body unless asked otherwise (corners and kinks add nodes).
DEFAULT_POINTS = 1024
#: Largest wall error and solver disagreement (relative to the wall's scale) of a formula wall's body
#: that still counts as the answer; above it the body carries a warning.
WALL_ACCURACY = 1e-6
#: An area below ``AREA_TOLERANCE·scale²`` (scale = max(1, largest R)) is a segment: zero area.
AREA_TOLERANCE = 1e-12
#: A corner deficit above ``DEFICIT_TOLERANCE·(wall scale)`` is a deficit; below it the corner touches the wall.
DEFICIT_TOLERANCE = 1e-10
#: Angular windows narrower than this (rad) are not corners; corner directions are resolved to it.
DIRECTION_TOLERANCE = 1e-9
#: An offset within ``OFFSET_TOLERANCE·max(1, wall scale)`` of b_c is the critical case (Case II).
OFFSET_TOLERANCE = 1e-9
#: How far from the true angle the critical offset's minimum of b + b'' may be reported, when a result
#: does not measure its own: the minimum is flat to rounding, so its location is known to about
#: sqrt(machine epsilon) (1.12e-8 for the ellipse wall at θ = 0); ten times that reads as 0.
ANGLE_TOLERANCE = 1e-7
#: κ_max is measured on points of the outline, a few 1e-8 below the exact value at the default resolution:
#: κ_max = 1 within this is reachable (mass at the far ends).
REALIZABLE_TOLERANCE = 1e-6
