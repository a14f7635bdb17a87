"""Envelope solver: the exact Legendre construction of the body from its support function.

With ``h = b0 + b`` and ``n = (cos φ, sin φ)``, the boundary point whose
outward normal is ``n(φ)`` is ``x(φ) = h n + h' n'`` (DESIGN.md), so the body
is written down directly, with no equation to solve.  Polar quantities follow:
``R = sqrt(h² + h'²)``, ``α = φ + atan(h'/h)``, radius of curvature
``ρ = h + h''``.  When ρ < 0 somewhere (b0 below the critical offset) the
swallowtails are cut off by :mod:`inverse.corners`.
"""

from __future__ import annotations

import numpy as np

from .corners import find_windows
from .nodes import Nodes

__all__ = ["envelope_nodes"]


def envelope_nodes(samples, wall, b0: float, case_three: bool):
    """Outline nodes of the body from sampled support values.

    Parameters
    ----------
    samples : inverse.support.SupportSamples
    wall : forward.Wall
    b0 : float
    case_three : bool
        Cut swallowtails (b0 below the critical offset).

    Returns
    -------
    nodes : Nodes
    windows : list of inverse.corners.Window
    """
    x = samples.points()
    rho = samples.rho
    phi = samples.phi
    keep = np.ones(phi.size, bool)
    windows = find_windows(samples, wall, b0) if case_three else []
    if not windows:
        nodes = Nodes(x, phi, phi.copy(), rho, rho.copy(), samples.edge_after.copy())
        return nodes, windows
    two_pi = 2 * np.pi
    origin = phi[0]
    for w in windows:
        # drop every sampled line inside the window (they do not touch the body)
        rel = np.mod(phi - w.phi1, two_pi)
        keep &= ~(rel < w.phi2 - w.phi1 + 1e-15) | (rel > two_pi - 1e-15)
    # sort key: angle from the first sample, so kink pairs keep their order
    key = np.concatenate([phi[keep] - origin, [np.mod(w.phi1 - origin, two_pi) for w in windows]])
    order = np.argsort(key, kind="stable")
    xs = np.concatenate([x[keep], np.array([w.point for w in windows])])
    phi_in = np.concatenate([phi[keep], [w.phi1 for w in windows]])
    phi_out = np.concatenate([phi[keep], [w.phi2 for w in windows]])
    rho_in = np.concatenate([rho[keep], [w.rho1 for w in windows]])
    rho_out = np.concatenate([rho[keep], [w.rho2 for w in windows]])
    straight = np.concatenate([samples.edge_after[keep], np.zeros(len(windows), bool)])[order]
    # an unpolished corner is joined to its neighbours by straight lines (sampled accuracy)
    inexact = np.concatenate([np.zeros(int(keep.sum()), bool), [not w.exact for w in windows]])[order]
    straight = straight | inexact | np.roll(inexact, -1)
    nodes = Nodes(xs[order], phi_in[order], phi_out[order], rho_in[order], rho_out[order], straight)
    return nodes, windows
