"""Outline nodes labelled by their normal angles, and their conversion to a Bézier outline.

Both solvers produce points of the body together with the normal angle(s) φ
at which the body touches the wall there.  A smooth point has one φ; a corner
of the body owns a whole window ``[phi_in, phi_out]`` of normal angles.  The
outline between two nodes is the cubic Hermite interpolant in φ, using
``dx/dφ = ρ(φ) n'(φ)`` (exact envelope derivative), which is O(Δφ⁴) accurate;
two nodes on either side of a kink of the wall are joined by a straight edge.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI
from coinwall.forward.outline import Outline

__all__ = ["Nodes"]



@dataclass(frozen=True, repr=False)
class Nodes:
    """Points of the outline with normal-angle windows, in increasing φ.

    Attributes
    ----------
    x : ndarray (n, 2)
    phi_in, phi_out : ndarray (n,)
        Normal angle where the outline arrives at / leaves the node (equal at smooth points).
    rho_in, rho_out : ndarray (n,)
        Radius of curvature on either side (``dx/dφ = ρ n'``).
    straight_after : ndarray (n,) of bool
        Node i and i+1 are joined by a straight edge (a kink of the wall).
    """

    x: np.ndarray
    phi_in: np.ndarray
    phi_out: np.ndarray
    rho_in: np.ndarray
    rho_out: np.ndarray
    straight_after: np.ndarray

    def collapse(self, tol: float) -> "Nodes":
        """Merge runs of consecutive nodes at the same point into one corner node.

        Nodes merge when they are within ``tol`` of each other and the
        envelope between them does not move (ρ ≤ tol on both sides, no
        turn of the normal at all, or ρ·Δφ ≤ 1000·tol): this is a corner of the body whose support
        function is ``R cos(φ − φ_k)`` on the merged window (the stick's ends,
        for example), or one point on either side of a break of the wall.
        """
        n = len(self.x)
        nxt = np.roll(np.arange(n), -1)
        # two nodes at one point with no turn of the normal between them (either side of a break of
        # the wall, where only the curvature jumps) are one node too: a zero-length segment has no
        # direction, and the support function's search by segment normals needs one
        step = np.abs(np.mod(self.phi_in[nxt] - self.phi_out + np.pi, TWO_PI) - np.pi)
        # the envelope between them moves by about ρ·Δφ: a radius of curvature at the rounding level of the
        # wall's second derivative (1e-9 from a one-sided limit at a kink, say) over one grid step does not
        # move it, and two such nodes kept apart make a zigzag of 1e-15 that crosses itself
        moves = np.maximum(np.abs(self.rho_out), np.abs(self.rho_in[nxt])) * step
        still = ((np.abs(self.rho_out) <= tol) & (np.abs(self.rho_in[nxt]) <= tol)) | (step <= 1e-15) \
            | (moves <= 1e3 * tol)
        same = (np.hypot(*(self.x[nxt] - self.x).T) <= tol) & still
        if not same.any():
            return self
        if same.all():  # a point body cannot be, but do not loop forever
            return self
        # walk the ring from a node that does not merge with its predecessor
        start = int(np.flatnonzero(~np.roll(same, 1))[0])
        order = (start + np.arange(n)) % n
        new_group = ~same[(order - 1) % n]
        heads = np.flatnonzero(new_group)
        first = order[heads]
        last = order[np.append(heads[1:] - 1, n - 1)]
        phi_out = self.phi_out[last].copy()
        # unwrap windows that cross 2π so that phi_out ≥ phi_in
        phi_out = self.phi_in[first] + np.mod(phi_out - self.phi_in[first], TWO_PI)
        return Nodes(self.x[first], self.phi_in[first], phi_out, self.rho_in[first],
                     self.rho_out[last], self.straight_after[last])

    def window_widths(self) -> np.ndarray:
        return self.phi_out - self.phi_in

    def outline(self) -> Outline:
        """Cubic Hermite (in φ) Bézier outline through the nodes."""
        tangent_out = np.stack([-np.sin(self.phi_out), np.cos(self.phi_out)], axis=1)
        tangent_in = np.stack([-np.sin(self.phi_in), np.cos(self.phi_in)], axis=1)
        steps = np.mod(np.roll(self.phi_in, -1) - self.phi_out, TWO_PI)
        straight = self.straight_after | (steps <= 1e-15)
        # a full turn between two nodes only happens for a single-node body: treat as zero
        steps = np.where(straight, 0.0, steps)
        rho_out, rho_in = self._capped_radii(tangent_out, tangent_in, steps)
        outline = Outline.from_hermite(self.x, rho_out[:, None] * tangent_out, rho_in[:, None] * tangent_in, steps)
        if straight.any():
            nxt = np.roll(self.x, -1, axis=0)
            controls = outline.controls.copy()
            controls[straight, 0] = self.x[straight] + (nxt[straight] - self.x[straight]) / 3
            controls[straight, 1] = self.x[straight] + 2 * (nxt[straight] - self.x[straight]) / 3
            outline = Outline(outline.nodes, controls)
        return outline

    def _capped_radii(self, tangent_out, tangent_in, steps):
        """``rho_out, rho_in`` with every Bézier arm no longer than the distance from its node to where the
        two tangent lines of the segment meet.

        The Hermite arm is ``ρ·Δφ/3``, shorter than that distance (``≈ ρ·Δφ/2``) wherever ρ is resolved by
        the grid; where it is not (ρ → ∞ at the flat points of |x|⁴ + |y|⁴ = 1, where b'' is unbounded)
        an arm 10⁴ times too long loops far outside the body.  Capped, the segment stays inside the
        triangle of its chord and tangents: convex, and as close to the body as the grid allows.
        """
        rho_out, rho_in = self.rho_out.copy(), self.rho_in.copy()
        nxt = np.roll(np.arange(len(self.x)), -1)
        t0, t1 = tangent_out, tangent_in[nxt]
        chord = self.x[nxt] - self.x
        det = t0[:, 0] * t1[:, 1] - t0[:, 1] * t1[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            # x_i + a t0 = x_{i+1} − b t1
            a = (chord[:, 0] * t1[:, 1] - chord[:, 1] * t1[:, 0]) / det
            b = (t0[:, 0] * chord[:, 1] - t0[:, 1] * chord[:, 0]) / det
            ok = (np.abs(det) > 1e-12) & (a > 0) & (b > 0) & (steps > 0)
            cap_out = np.where(ok, 3 * a / steps, np.inf)
            cap_in = np.where(ok, 3 * b / steps, np.inf)
        rho_out = np.where(rho_out > cap_out, cap_out, rho_out)
        rho_in[nxt] = np.where(rho_in[nxt] > cap_in, cap_in, rho_in[nxt])
        return rho_out, rho_in

