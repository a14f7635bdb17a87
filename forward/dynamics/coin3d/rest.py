"""Where a bounced body of revolution comes to rest: heads, edge or tails, on a frictionless floor.

Each toss is the reduced billiard of :mod:`.top` (tilt θ, height η, the conserved ℓz and ℓ3), bounced on a
floor with Newton's restitution e until its outcome is decided.  On the floor η ≥ b(θ), so the energy per
M κ₁², ``E = ½(θ̇² + η̇²) + V(θ) + g η``, is at least the landscape ``U(θ) = V(θ) + g b(θ)`` (V: the top's
potential, the spin's centrifugal barrier).  After every floor impact:

* the *valley* of θ is the interval between the two local maxima of U around it (U on 1024 tilts in (0, π);
  a valley reaching a pole has one barrier only).  When E is below the lower of its two maxima (the barrier),
  the tilt can never leave it: the toss is decided.  The grid's maxima are at most the true ones, so a toss is
  never declared decided too early.  Its outcome is the face of the body that holds the valley's lowest point:
  heads, edge or tails by the maxima of b alone (``faces``; without spin U = g b and the two agree);
* when the gap opens slower than ``√(2 g δ)`` (δ = 1e-9 × max(1, the body's reach) κ₁: a free hop lower than
  δ), the bounces have died out (the chattering limit, as in :mod:`..floor.field`): the normal velocity is
  removed, and the toss is decided if E is below its barrier; if not, it *slides* on the frictionless floor
  with E conserved (a coin rolling and rocking for ever, which the impact model cannot follow): undecided.

Status codes: :data:`REST_STATUS`.  With ``ℓz = ℓ3 = 0`` (a flip about a diameter) V = 0 and this is the
planar body's rule (:mod:`..floor.field`) for the meridian section.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InvalidArgument
from ...validation import check_count
from .top import TopTable, potential

__all__ = ["REST_STATUS", "rest_outcomes"]

#: status codes of :func:`rest_outcomes` (6, 7, 11 as in :data:`.top.STATUS`)
REST_STATUS = {0: "impact budget reached", 1: "settled", 3: "rest", 4: "slides",
               6: "free flight (no further impact)", 7: "the root search did not converge",
               11: "a face met the wall flat at a pole (no departure window)"}
_GRID = 1024
#: the chattering height δ per unit of the body's reach (κ₁), as the planar toss's CHATTER_HEIGHT
CHATTER_HEIGHT = 1e-9


def rest_outcomes(table: TopTable, states, lz, l3, impacts: int = 10_000, workers=None) -> dict:
    """The face each toss comes to rest on (module docstring), compiled and parallel over tosses.

    Parameters
    ----------
    table : TopTable
        The body on a floor in a field g > 0 with restitution e (no ceiling).
    states : array (m, 4)
        ``(θ, η, θ̇, η̇)`` of each toss, strictly above the floor, 0 < θ < π.
    lz, l3 : array (m,) or float
        The conserved ``ℓz = L_z/I₁`` and ``ℓ3 = L₃/I₁`` (rad/s).
    impacts : int
        Impacts per toss at most.
    workers : int, optional
        Threads (numba's; default all).

    Returns
    -------
    dict
        ``outcome`` (0 heads, 1 edge, 2 tails, −1 undecided), ``status`` (:data:`REST_STATUS`),
        ``floor_impacts``.

    Raises
    ------
    InvalidArgument
        A table with a ceiling or no field, or a state that is not strictly above the floor.

    Examples
    --------
    >>> from coinwall.forward.revolution import coin
    >>> table = TopTable(coin(1.0, 0.2), g=1.0, e=0.5)
    >>> h = float(table.floor(0.3))
    >>> rest_outcomes(table, [[0.3, h + 1.0, 0.0, 0.0]], 0.0, 0.0)["outcome"].tolist()
    [0]
    """
    import numba

    k = _kernel()
    if not isinstance(table, TopTable):
        raise InvalidArgument(f"`table` must be a TopTable, got {type(table).__name__}")
    if table.H is not None or not table.g > 0:
        raise InvalidArgument("a toss that comes to rest needs a floor only (no ceiling) and a field g > 0")
    impacts = check_count("impacts", impacts, maximum=100_000_000)
    arr = np.ascontiguousarray(np.asarray(states, dtype=float).reshape(-1, 4))
    m = arr.shape[0]
    lz = np.ascontiguousarray(np.broadcast_to(np.asarray(lz, dtype=float), (m,)))
    l3 = np.ascontiguousarray(np.broadcast_to(np.asarray(l3, dtype=float), (m,)))
    if not (np.all(np.isfinite(arr)) and np.all(np.isfinite(lz)) and np.all(np.isfinite(l3))):
        raise InvalidArgument("states, ℓz and ℓ3 must be finite numbers")
    if np.any((arr[:, 0] <= 0) | (arr[:, 0] >= math.pi)):
        raise InvalidArgument("every toss's tilt θ must be strictly between 0 and π")
    if not np.all(arr[:, 1] > table.floor(arr[:, 0]) + 10 * table.tol):
        raise InvalidArgument("every toss must start above the floor")
    if not np.all(np.isfinite(potential(arr[:, 0], lz, l3))):
        raise InvalidArgument("a toss starts where its ℓz, ℓ3 put an infinite barrier")
    body = table.body
    theta = np.linspace(0.0, math.pi, 16385)
    _, dh = body.support(theta)
    faces = np.sort(theta[1:][(dh[:-1] > 0) & (dh[1:] <= 0)])
    grid = (np.arange(_GRID) + 0.5) * (math.pi / _GRID)
    kind, verts, eps, ea, ec, reach = body.kernel_params()
    chatter = math.sqrt(2.0 * table.g * CHATTER_HEIGHT * max(1.0, reach))
    outcome = np.zeros(m, dtype=np.int64)
    status = np.zeros(m, dtype=np.int64)
    floors = np.zeros(m, dtype=np.int64)
    previous = numba.get_num_threads()
    try:
        if workers is not None:
            numba.set_num_threads(min(check_count("workers", workers), numba.config.NUMBA_NUM_THREADS))
        k.rest_many(arr, lz, l3, impacts, float(table.g), float(table.e), kind, verts, eps, ea, ec, reach,
                    float(table.tol), chatter, grid, faces, outcome, status, floors)
    finally:
        numba.set_num_threads(previous)
    return {"outcome": outcome, "status": status, "floor_impacts": floors}


def _kernel():
    """:mod:`._rest_kernel`, its functions (and :mod:`._top_kernel`'s, which it calls) given coinwall's kernel cache on
    first use, as :func:`.top._kernel` does; without it every process compiled them again (about 6 s)."""
    from ..billiard.wallcode import cache_module
    from . import _rest_kernel
    from .top import _kernel as top_kernel

    top_kernel()
    cache_module(_rest_kernel)
    return _rest_kernel
