"""Polar solver: the paper's first-order equation for R(α), with branch tracking.

The paper (section IV, eq. 23 with our sign convention θ = α − atan(R'/R)) asks for

    F(α, R, R') = b0 + b(α − atan(R'/R)) − R²/sqrt(R² + R'²) = 0.

This is a Clairaut-type equation: its general solutions are the support lines
themselves and the body is its *singular* solution, on which the two roots for
R' coincide (∂F/∂R' = 0) everywhere — which is why following one root of the
quadratic for R' numerically drifts onto a tangent line or loses the real root.
We solve the regular system ``F = 0, ∂F/∂R' = 0`` instead.  Writing
``R' = R tan ψ``, it reads ``R cos ψ = h(α − ψ)``, ``R sin ψ = h'(α − ψ)``, i.e.
with the contact angle φ = α − ψ the single scalar equation

    g(φ) = φ + atan(h'(φ)/h(φ)) = α,     g'(φ) = h ρ / R²,   ρ = h + h''.

*Branch tracking.*  g is monotone exactly where ρ keeps its sign; where ρ
changes sign g has a fold (a cusp of the envelope).  Folds are located exactly
(ρ = 0 by Brent's method) and split φ into monotone branches; a kink of the
wall adds a straight-line branch ``R = h(φ_k)/cos(α − φ_k)``.  For a given α
every branch covering it gives a candidate; the body takes the candidate with
the smallest R, because the ray from the centre of mass leaves the half-plane
intersection through the nearest support line — a deliberate choice, not a
numerical accident.  Where the chosen branch jumps to a non-adjacent one the
ray crosses a corner; the crossing ``R_A(α*) = R_B(α*)`` is located by Brent's
method and reported.  Roots are found by a vectorised Newton iteration kept
inside a bracket from the sampled branch (bisection when Newton leaves it),
so convergence is guaranteed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.angles import TWO_PI

from .nodes import Nodes
from .support import envelope_point, sample_support

__all__ = ["Fold", "PolarSolution", "polar_nodes"]



@dataclass(frozen=True)
class Fold:
    """A fold of α(φ) (a cusp of the envelope): ρ(φ) = 0 with a change of sign.

    Attributes
    ----------
    phi : float
        The normal angle φ where ρ = 0.
    alpha : float
        The polar angle α of the fold point.
    radius : float
        Its distance from the centre of mass.

    Examples
    --------
    Below the critical offset the polar solver meets folds where the envelope turns back (they become the
    corners of the body):

    >>> from coinwall import Wall, solve_body
    >>> wall = Wall.from_expression("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 1.0})
    >>> body = solve_body(wall, -0.6, method="polar", points=256)
    >>> len(body.folds), round(body.folds[0].radius, 6)
    (4, 0.407597)
    """

    phi: float
    alpha: float
    radius: float

    def to_dict(self) -> dict:
        return {"phi": self.phi, "alpha": self.alpha, "R": self.radius}


@dataclass(frozen=True, repr=False)
class PolarSolution:
    """Per-α solution of the regular system, with diagnostics."""

    alpha: np.ndarray
    radius: np.ndarray
    slope: np.ndarray          # R'(α)
    phi: np.ndarray            # contact angle φ = α − atan(R'/R)
    branch: np.ndarray         # index of the branch chosen for every α
    folds: tuple
    switches: tuple            # α* of corner crossings
    residual: float            # max |F| of the paper's equation at the solution
    residual_dF: float         # max |∂F/∂R'|·R


@dataclass
class _Branch:
    kind: str                  # "arc", "line" or "point"
    phi: np.ndarray            # sampled φ (increasing)
    alpha: np.ndarray          # sampled α(φ) (monotone)
    h_k: float = 0.0           # lines: h at the kink
    start: int = 0             # index into the sample array
    sides: tuple = ()          # arcs: (φ, h, h') at an end that is one side of a kink or break, one-sided


def _arc_values(wall, b0, br, phi):
    """``h, h'`` on an arc branch at the roots ``phi``.  At an end that is a kink of the wall the two-sided
    derivative belongs to either side (and at a break where ``max`` ties, it is their mean): there the
    branch's own one-sided values count."""
    _, h, d1, _ = _g(wall, b0, phi)
    for end, h_end, d1_end in br.sides:
        at = np.abs(phi - end) <= 1e-12 * (1.0 + abs(end))
        h, d1 = np.where(at, h_end, h), np.where(at, d1_end, d1)
    return h, d1


def _g(wall, b0, phi):
    b, d1, d2 = wall.derivatives(phi)
    h = b0 + b
    return phi + np.arctan2(d1, h), h, d1, d2


def _locate_fold(wall, b0, a, b):
    from scipy.optimize import brentq

    def rho(x):
        bb, _, dd = wall.derivatives(np.array([x]))
        return float(b0 + bb[0] + dd[0])

    return brentq(rho, a, b, xtol=1e-15, rtol=1e-15, maxiter=200)


def _branches(wall, b0, samples):
    """Split the sampled support function into monotone pieces of α(φ), locating folds."""
    phi, h, h1, rho, edge_after = samples.phi, samples.h, samples.h1, samples.rho, samples.edge_after
    breaks = samples.break_after if samples.break_after is not None else np.zeros(phi.size, bool)
    if not (edge_after | breaks).any():
        # close the ring: the last piece runs up to φ0 + 2π, so no α between the last and first sample is lost
        phi, h, h1, rho = (np.append(phi, phi[0] + TWO_PI), np.append(h, h[0]), np.append(h1, h1[0]),
                           np.append(rho, rho[0]))
        edge_after = np.append(edge_after, False)
        breaks = np.append(breaks, False)
    alpha = phi + np.arctan2(h1, h)
    n = phi.size
    scale = max(1.0, float(np.max(np.abs(h))))
    branches, folds = [], []
    # pieces between kinks and breaks (edge_after / breaks mark the left side of one): on either
    # side of a break α(φ) changes its rate (a vertex window, where α stands still, becomes its own
    # "point" branch)
    cuts = list(np.flatnonzero(edge_after | breaks))
    starts = [0] + [c + 1 for c in cuts if c + 1 < n]
    stops = [c + 1 for c in cuts] + ([n] if not cuts or cuts[-1] + 1 < n else [])
    for lo, hi in zip(starts, stops):
        seg_phi, seg_alpha, seg_rho = phi[lo:hi], alpha[lo:hi], rho[lo:hi]
        sign = np.where(seg_rho > 1e-12 * scale, 1, np.where(seg_rho < -1e-12 * scale, -1, 0))
        change = np.flatnonzero(sign[:-1] * sign[1:] < 0)
        bounds = [0]
        fold_phis = []
        for c in change:
            f = _locate_fold(wall, b0, seg_phi[c], seg_phi[c + 1])
            fold_phis.append(f)
            bounds.append(c + 1)
        bounds.append(seg_phi.size)
        for k in range(len(bounds) - 1):
            i0, i1 = bounds[k], bounds[k + 1]
            p, a = seg_phi[i0:i1], seg_alpha[i0:i1]
            if k > 0:  # prepend the exact fold
                ga, *_ = _g(wall, b0, np.array([fold_phis[k - 1]]))
                p, a = np.r_[fold_phis[k - 1], p], np.r_[ga[0], a]
            if k < len(bounds) - 2:
                ga, *_ = _g(wall, b0, np.array([fold_phis[k]]))
                p, a = np.r_[p, fold_phis[k]], np.r_[a, ga[0]]
            kind = "point" if np.ptp(a) < 1e-12 else "arc"
            sides = tuple((phi[i], h[i], h1[i]) for i, outer in ((lo + i0, k == 0), (lo + i1 - 1, k == len(bounds) - 2))
                          if outer and (edge_after[i] or edge_after[i - 1] or breaks[i] or breaks[i - 1]))
            branches.append(_Branch(kind, p, a, start=lo + i0, sides=sides))
        for f in fold_phis:
            ga, hh, dd1, _ = _g(wall, b0, np.array([f]))
            folds.append(Fold(float(np.mod(f, TWO_PI)), float(np.mod(ga[0], TWO_PI)), float(np.hypot(hh[0], dd1[0]))))
        if edge_after[hi - 1]:  # the straight edge of the kink at phi[hi-1]
            j = hi % n
            a0 = alpha[hi - 1]
            a1 = alpha[j] + (TWO_PI if j < hi - 1 else 0.0)
            k_phi = phi[hi - 1]
            branches.append(_Branch("line", np.array([k_phi, k_phi]), np.array([a0, a1]), h_k=float(h[hi - 1])))
    return branches, folds


def _solve_arc(wall, b0, br, targets):
    """Roots of g(φ) = α on a monotone branch for the targets it covers; returns (mask, φ)."""
    a = br.alpha
    inc = a[-1] >= a[0]
    a_sorted = a if inc else a[::-1]
    p_sorted = br.phi if inc else br.phi[::-1]
    lo_a, hi_a = a_sorted[0], a_sorted[-1]
    # bring each target into the branch's α range (α is defined modulo 2π)
    shift = np.floor((targets - lo_a) / TWO_PI)
    t = targets - shift * TWO_PI
    mask = (t >= lo_a) & (t <= hi_a)
    if not mask.any():
        return mask, np.empty(0), t
    tt = t[mask]
    k = np.clip(np.searchsorted(a_sorted, tt, side="right") - 1, 0, a_sorted.size - 2)
    lo, hi = p_sorted[k], p_sorted[k + 1]
    glo, ghi = a_sorted[k] - tt, a_sorted[k + 1] - tt
    # linear interpolation as the starting guess, then safeguarded Newton
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(ghi != glo, lo - glo * (hi - lo) / (ghi - glo), 0.5 * (lo + hi))
    x = np.where(np.isfinite(x), x, 0.5 * (lo + hi))
    left, right = np.minimum(lo, hi), np.maximum(lo, hi)
    sign_left = np.where(left == lo, np.sign(glo), np.sign(ghi))
    return mask, _newton(wall, b0, x, tt, left, right, sign_left), t


def _newton(wall, b0, x, tt, left, right, sign_left):
    """Safeguarded Newton for g(φ) = tt, each root until its own residual is at the rounding floor.

    Only the roots not yet converged are evaluated again (the wall at 10⁵ angles costs milliseconds,
    and a few roots oscillating at the floor would keep every root iterating, ~40 rounds at 10⁵ nodes).
    """
    x = np.array(x, dtype=float)
    tol = 2e-16 * (1 + np.max(np.abs(tt))) if tt.size else 0.0
    active = np.arange(x.size)
    for _ in range(60):
        xa, ta = x[active], tt[active]
        g, h, d1, d2 = _g(wall, b0, xa)
        res = g - ta
        moving = np.abs(res) > tol
        active, xa, res, h, d1, d2 = active[moving], xa[moving], res[moving], h[moving], d1[moving], d2[moving]
        if not active.size:
            break
        same = np.sign(res) == sign_left[active]
        la = np.where(same, xa, left[active])
        ra = np.where(same, right[active], xa)
        left[active], right[active] = la, ra
        deriv = h * (h + d2) / (h * h + d1 * d1)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = xa - res / deriv
        bad = ~np.isfinite(step) | (step <= la) | (step >= ra)
        x[active] = np.where(bad, 0.5 * (la + ra), step)
        active = active[ra - la >= 1e-15]
        if not active.size:
            break
    return x


def _boundary_order(alpha, phi_in, phi_out):
    """The order of outline nodes along the boundary, from their polar angles ``alpha`` and normal angles.

    Sorting by α alone misorders the nodes of one corner of a polygon: the corner's own node and the ends
    of the two edges that meet there have the same α up to rounding, and their order decides the corner's
    window of normal angles.  Along a convex boundary the normal angle φ increases (cyclically), so the
    nodes are sorted by where their window starts, then by its width (the end of the edge arriving at a
    corner before the corner); nodes with one φ and no width are on one straight edge, ordered along it
    by α (with the centre of mass inside, ``|α − φ| < π/2`` on the edge, so no wrap-around).
    """
    start = np.mod(phi_in, TWO_PI)
    start = np.where(start >= TWO_PI - 1e-12, 0.0, start)  # np.mod(-1e-17, 2π) rounds to 2π
    # one kink's angle reached from either side of the 2π seam differs by rounding: starts within 1e-12
    # are one start, so that the width and the position along the edge decide
    by_start = np.argsort(start, kind="stable")
    group = np.concatenate([[0], np.cumsum(np.diff(start[by_start]) > 1e-12)])
    start[by_start] = group
    width = np.mod(phi_out - phi_in, TWO_PI)
    width = np.where(width >= TWO_PI - 1e-12, 0.0, width)
    along_edge = np.mod(alpha - phi_in + np.pi, TWO_PI) - np.pi
    return np.lexsort((along_edge, width, start))


def _radius_on(wall, b0, branch, a):
    """``(R, φ)`` of ``branch`` at the polar angle ``a`` (nan where the branch does not reach ``a``)."""
    if branch.kind == "line":
        lo, hi = branch.alpha
        t = a - math.floor((a - lo) / TWO_PI) * TWO_PI
        if not lo < t < hi:
            return np.nan, np.nan
        return max(branch.h_k, 0.0) / math.cos(t - branch.phi[0]), float(branch.phi[0])
    if branch.kind != "arc":
        return np.nan, np.nan
    mask, ph, _ = _solve_arc(wall, b0, branch, np.array([a]))
    if not mask[0]:
        return np.nan, np.nan
    h, d1 = _arc_values(wall, b0, branch, ph)
    return float(np.hypot(h[0], d1[0])), float(ph[0])


def polar_nodes(wall, b0: float, points: int, *, oversample: int = 4):
    """Solve the paper's equation on ``points`` uniform polar angles.

    Returns
    -------
    nodes : Nodes
    solution : PolarSolution
    """
    dense = sample_support(wall, b0, max(oversample * points, 4096))
    branches, folds = _branches(wall, b0, dense)
    targets = np.linspace(0.0, TWO_PI, points, endpoint=False)

    def candidates(alpha):
        best_r = np.full(alpha.size, np.inf)
        best_phi = np.full(alpha.size, np.nan)
        best_b = np.full(alpha.size, -1)
        for ib, br in enumerate(branches):
            if br.kind == "arc":
                mask, phi, _ = _solve_arc(wall, b0, br, alpha)
                if phi.size:
                    r = np.hypot(*_arc_values(wall, b0, br, phi))
            elif br.kind == "line":
                lo, hi = br.alpha
                t = alpha - np.floor((alpha - lo) / TWO_PI) * TWO_PI
                mask = (t > lo) & (t < hi)
                phi = np.full(int(mask.sum()), br.phi[0])
                r = max(br.h_k, 0.0) / np.cos(t[mask] - br.phi[0])
            else:
                continue
            if not phi.size:
                continue
            idx = np.flatnonzero(mask)
            better = r < best_r[idx] - 1e-15 * (1 + r)
            best_r[idx[better]] = r[better]
            best_phi[idx[better]] = phi[better]
            best_b[idx[better]] = ib
        return best_r, best_phi, best_b

    radius, phi, chosen = candidates(targets)
    # refine: where consecutive solutions are far apart in φ (high curvature: ρ small, dφ/dα = R²/(hρ)
    # large) bisect the α interval, so the φ-Hermite outline stays as accurate as the envelope's
    max_gap = 2.0 * TWO_PI / points
    for _ in range(40):
        nxt = np.roll(np.arange(targets.size), -1)
        gap = np.abs(np.angle(np.exp(1j * (phi[nxt] - phi))))
        same = (chosen == chosen[nxt]) & np.isfinite(gap)
        wide = np.flatnonzero(same & (gap > max_gap))
        if not wide.size:
            break
        mids = targets[wide] + 0.5 * np.mod(targets[nxt[wide]] - targets[wide], TWO_PI)
        r2, p2, c2 = candidates(np.mod(mids, TWO_PI))
        order = np.argsort(np.concatenate([targets, np.mod(mids, TWO_PI)]), kind="stable")
        targets = np.concatenate([targets, np.mod(mids, TWO_PI)])[order]
        radius = np.concatenate([radius, r2])[order]
        phi = np.concatenate([phi, p2])[order]
        chosen = np.concatenate([chosen, c2])[order]
    points = targets.size
    scale = max(1.0, float(np.nanmax(dense.h)))
    # degenerate branches (a whole arc mapped to one α: a corner with ρ ≡ 0) and kink sides are nodes too
    special = []
    for ib, br in enumerate(branches):
        if br.kind == "point":
            # the corner seen from inside its window: at a kink of the wall (a polygon's vertex windows start
            # and end at kinks) the two-sided b' there belongs to either neighbour, so take the right-hand limit
            b_first, d1_first, _ = wall.one_sided(float(np.mod(br.phi[0], TWO_PI)), +1)
            x = envelope_point(br.phi[0], b0 + b_first, d1_first)
            # the arcs that meet the corner arrive and leave with their own (one-sided) radius of
            # curvature: a break of the wall at either end of the window (0 for a kink-free corner)
            b_in, _, d2_in = wall.one_sided(float(np.mod(br.phi[0], TWO_PI)), -1)
            b_out, _, d2_out = wall.one_sided(float(np.mod(br.phi[-1], TWO_PI)), +1)
            special.append((float(np.mod(br.alpha[0], TWO_PI)), x, br.phi[0], br.phi[-1],
                            max(b0 + b_in + d2_in, 0.0), max(b0 + b_out + d2_out, 0.0), False))
        elif br.kind == "line":
            k = br.phi[0]
            # the edge's ends join the arcs on either side of the kink: their one-sided radius of
            # curvature shapes the neighbouring Hermite segment (ρ = 0 there would flatten it)
            for a, straight, side in ((br.alpha[0], True, -1), (br.alpha[1], False, +1)):
                r = max(br.h_k, 0.0) / math.cos(a - k)
                x = r * np.array([math.cos(a), math.sin(a)])
                b_side, _, d2_side = wall.one_sided(float(np.mod(k, TWO_PI)), side)
                rho_side = max(b0 + float(b_side) + float(d2_side), 0.0)
                special.append((float(np.mod(a, TWO_PI)), x, k, k, rho_side, rho_side, straight))
    if dense.break_after is not None:
        # a break of the wall (only b'' jumps): one point, with the radius of curvature of either side; a
        # target landing on it would take the two-sided b'' there, which belongs to neither
        for i in np.flatnonzero(dense.break_after):
            j = (i + 1) % dense.phi.size
            x = envelope_point(dense.phi[i], dense.h[i], dense.h1[i])
            special.append((float(np.mod(math.atan2(x[1], x[0]), TWO_PI)), x, dense.phi[i], dense.phi[i],
                            float(dense.rho[i]), float(dense.rho[j]), False))
    if special:
        # a corner of the envelope or an end of an edge is a point of the body only when no other support
        # line passes nearer the centre of mass in its direction; below b_c (a polygon's wall lowered, say)
        # the edges cross before their ends and the vertex windows are swallowtails
        nearest, _, _ = candidates(np.array([item[0] for item in special]))
        reach = np.array([math.hypot(*item[1]) for item in special])
        special = [item for item, r, rn in zip(special, reach, nearest) if r <= rn + 1e-12 * scale]
    # corners: the chosen branch jumps between branches that do not join continuously
    switches = []
    nxt = np.roll(np.arange(points), -1)
    for j in np.flatnonzero((chosen != chosen[nxt]) & (chosen >= 0) & (chosen[nxt] >= 0)):
        ba, bb = branches[chosen[j]], branches[chosen[nxt[j]]]
        a0 = targets[j]
        a1 = targets[nxt[j]] + (TWO_PI if nxt[j] == 0 else 0.0)

        def diff(a):
            return _radius_on(wall, b0, ba, a)[0] - _radius_on(wall, b0, bb, a)[0]

        # both branches need not cover all of [a0, a1]: find a sub-bracket where both exist and R_A − R_B changes sign
        # The crossing may sit exactly on a target (a corner on the α = 0 seam, say), where rounding
        # decides the sign of R_A − R_B: widen the bracket by a quarter step each way and count
        # differences at the rounding level as zeros.
        pad = 0.25 * (a1 - a0)
        grid = np.linspace(a0 - pad, a1 + pad, 33)
        values = np.array([diff(a) for a in grid])
        values[np.abs(values) <= 1e-13 * scale] = 0.0
        finite = np.isfinite(values)
        pairs = [k for k in range(32) if finite[k] and finite[k + 1] and values[k] * values[k + 1] <= 0]
        if not pairs:
            continue  # the branches meet at an edge end or a corner already among the special nodes
        k = pairs[0]
        from scipy.optimize import brentq  # here, not above: importing it costs ~0.3 s, most solves never do

        astar = brentq(diff, grid[k], grid[k + 1], xtol=1e-15, rtol=1e-15, maxiter=200) \
            if values[k] * values[k + 1] < 0 else (grid[k] if values[k] == 0 else grid[k + 1])
        ra, pa = _radius_on(wall, b0, ba, astar)
        _, pb = _radius_on(wall, b0, bb, astar)
        x = ra * np.array([math.cos(astar), math.sin(astar)])
        _, _, _, d2a = _g(wall, b0, np.array([pa, pb]))
        ha = b0 + wall(np.array([pa, pb]))
        # a straight edge (a kink's line branch) has no curvature: ρ = 0 on its side of the corner
        rho_a = 0.0 if ba.kind == "line" else float(ha[0] + d2a[0])
        rho_b = 0.0 if bb.kind == "line" else float(ha[1] + d2a[1])
        special.append((float(np.mod(astar, TWO_PI)), x, pa, pb, rho_a, rho_b, bb.kind == "line"))
        switches.append(float(np.mod(astar, TWO_PI)))

    ok = np.isfinite(radius)
    for a, *_ in special:  # a target on top of a corner or edge end would duplicate that node
        ok &= np.abs(np.angle(np.exp(1j * (targets - a)))) > 1e-12
    g, h, d1, d2 = _g(wall, b0, np.where(ok, phi, 0.0))
    rho = h + d2
    on_line = np.array([c >= 0 and branches[c].kind == "line" for c in chosen])
    with np.errstate(invalid="ignore"):  # targets no branch covers have R = inf; they are masked by `ok`
        xs = radius[:, None] * np.stack([np.cos(targets), np.sin(targets)], axis=1)
    rho_nodes = np.where(on_line, 0.0, rho)
    keys = list(targets[ok])
    xs_l, pin, pout, rin, rout, st = list(xs[ok]), list(phi[ok]), list(phi[ok]), list(rho_nodes[ok]), \
        list(rho_nodes[ok]), list(on_line[ok])
    for a, x, p_in, p_out, r_in, r_out, straight in special:
        keys.append(a)
        xs_l.append(x)
        pin.append(p_in)
        pout.append(p_out)
        rin.append(r_in)
        rout.append(r_out)
        st.append(straight)
    order = _boundary_order(np.array(keys), np.array(pin), np.array(pout))
    nodes = Nodes(np.array(xs_l)[order], np.mod(np.array(pin)[order], TWO_PI),
                  np.mod(np.array(pin)[order], TWO_PI) + np.mod(np.array(pout) - np.array(pin), TWO_PI)[order],
                  np.array(rin)[order], np.array(rout)[order], np.array(st)[order])
    nodes = nodes.collapse(1e-12 * scale)

    # the paper's equation, evaluated honestly at the solution: θ = α − atan(R'/R)
    with np.errstate(invalid="ignore"):  # masked by `ok` as above
        slope = np.where(ok, radius * np.where(on_line, np.tan(targets - phi), d1 / np.where(h != 0, h, 1.0)),
                         np.nan)
    theta = targets - np.arctan2(slope, radius)
    hb = b0 + wall(np.mod(np.where(ok, theta, 0.0), TWO_PI))
    F = hb - radius**2 / np.sqrt(radius**2 + slope**2)
    _, hd1, _ = wall.derivatives(np.mod(np.where(ok, theta, 0.0), TWO_PI))
    psi = np.arctan2(slope, radius)
    dF = np.where(on_line, 0.0, -hd1 + radius * np.sin(psi))
    solution = PolarSolution(targets, radius, slope, np.mod(phi, TWO_PI), chosen, tuple(folds), tuple(switches),
                             float(np.nanmax(np.abs(F[ok]))) if ok.any() else math.nan,
                             float(np.nanmax(np.abs(dF[ok & ~on_line]))) if (ok & ~on_line).any() else 0.0)
    return nodes, solution
