"""Jumps of a wall expression: a support function is continuous.

A wall written as a formula can jump where no check angle sees it: ``1 + 0.1*cos(t)/abs(cos(t))`` is
finite, periodic and smooth on both sides of ±π/2, with equal slopes there, so neither the kink finder
(it compares slopes) nor the pole finder (it looks for values that grow) objects, and a b_c came out.

The test needs no guess of where to look.  Between two check angles ``a < c`` the trapezoid rule on the
exact slope predicts the change of the wall, ``b(c) − b(a) ≈ (c − a)(b'(a) + b'(c))/2``; its defect is
``O((c − a)³ b''')`` for a smooth wall, ``O((c − a)·[b'])`` across a kink, ``O(√(c − a))`` across an
infinite slope, but the size of the jump across a jump, however small the bracket.  Every interval whose
defect exceeds the tolerance is halved (keeping the half with the larger defect) until it either falls
below the tolerance (continuous: a steep or kinked wall) or the bracket is ~1e-13 wide; there the defect
must also not have shrunk over the last 2¹⁰ of narrowing (a jump does not; ``√`` shrinks 32 times),
which certifies a jump of the value.
"""

from __future__ import annotations

import numpy as np

from .angles import TWO_PI
from .errors import InvalidWall

__all__ = ["check_continuity"]

#: a change of the wall, unexplained by its slope, above this (relative to the wall's scale) is looked at
JUMP_TOLERANCE = 1e-8
#: halvings of a check interval (2π/4096 → ~9e-14 rad) and how many of the last are compared
_LEVELS = 34
_COMPARED = 10


def check_continuity(description: str, derivatives, theta, values, scale: float) -> None:
    """Refuse a wall whose value jumps between the check angles ``theta``.

    Parameters
    ----------
    description : str
        The wall, for the message.
    derivatives : callable
        ``derivatives(angles) -> (b, b', b'')`` (exact).
    theta : ndarray
        Increasing check angles covering one period (the interval after the last wraps to the first).
    values : tuple of ndarray
        ``(b, b', ...)`` at ``theta``, finite (the caller checked).
    scale : float
        The wall's scale, ``max(1, max |b|)``.

    Raises
    ------
    InvalidWall
        "jumps at θ = …", with the values on either side.
    """
    tol = JUMP_TOLERANCE * scale
    b, d1 = (np.asarray(v, dtype=float) for v in values[:2])
    lo, hi = np.asarray(theta, dtype=float), np.append(theta[1:], theta[0] + TWO_PI)
    b_lo, d_lo, b_hi, d_hi = b, d1, np.roll(b, -1), np.roll(d1, -1)

    def defect(a, c, ba, da, bc, dc):
        return np.abs(bc - ba - 0.5 * (c - a) * (da + dc))

    with np.errstate(all="ignore"):
        size = defect(lo, hi, b_lo, d_lo, b_hi, d_hi)
        keep = size > tol
        lo, hi, b_lo, d_lo, b_hi, d_hi, size = (x[keep] for x in (lo, hi, b_lo, d_lo, b_hi, d_hi, size))
        earlier = size.copy()
        for level in range(_LEVELS):
            if not lo.size:
                return
            if level == _LEVELS - _COMPARED:
                earlier = size.copy()
            mid = 0.5 * (lo + hi)
            b_mid, d_mid, _ = derivatives(mid)
            left = defect(lo, mid, b_lo, d_lo, b_mid, d_mid)
            right = defect(mid, hi, b_mid, d_mid, b_hi, d_hi)
            go_left = left >= right
            hi, b_hi, d_hi = np.where(go_left, mid, hi), np.where(go_left, b_mid, b_hi), np.where(go_left, d_mid, d_hi)
            lo, b_lo, d_lo = np.where(go_left, lo, mid), np.where(go_left, b_lo, b_mid), np.where(go_left, d_lo, d_mid)
            size = np.where(go_left, left, right)
            # a non-finite value inside is the pole finder's business; below the tolerance: continuous there
            keep = np.isfinite(b_mid) & np.isfinite(d_mid) & (size > tol)
            lo, hi, b_lo, d_lo, b_hi, d_hi, size, earlier = (
                x[keep] for x in (lo, hi, b_lo, d_lo, b_hi, d_hi, size, earlier))
    jumps = np.flatnonzero(size > 0.5 * earlier)
    if jumps.size:
        k = jumps[np.argmin(np.mod(lo[jumps], TWO_PI))]
        angle = float(np.mod(0.5 * (lo[k] + hi[k]), TWO_PI))
        raise InvalidWall(
            f"wall {description!r} jumps at θ = {angle:.10g}: b goes from {b_lo[k]:.6g} to {b_hi[k]:.6g} there; "
            "a support function is continuous (a kink, where the slope jumps, is allowed; a jump of the value is not)")
