"""How much the measured KAM boundary ε_c(H) of the elliptic billiard depends on its criterion.

Run:  python tests/benchmarks/kam_sensitivity.py [--quick] [--H 2,3]
          [--figure docs/figures/kam_islands_H2.png] [--json kam_sensitivity.json]
          [--parts 0,1,2,3] [--probe 30,100]

Full run: ~6 min per H value on 2 shared cores (default H = 2,3: 656 s wall, 930 s CPU); ``--quick`` (smaller samples,
coarser bisection) ~1 min per H, for checking that the script runs, not for numbers.

The table is the paper's ellipse wall ``sqrt((1+eps*cos(t)**2)/(1+eps))`` (``coinwall.forward.dynamics.analysis.islands.ELLIPSE_WALL``).
The criterion of :func:`coinwall.forward.dynamics.analysis.kam.kam_boundary`: ``orbits`` Liouville-random orbits, each classified
regular when its Lyapunov exponent per collision over N = ``collisions`` collisions is ≤ 3 ln N / N
(:func:`coinwall.forward.dynamics.analysis.lyapunov.chaotic_fraction`); fully chaotic when the regular fraction is < ``regular_max``.

Parts (each prints a markdown table):

0. Closed form: the period-2 orbits that carry the islands.  The wall b is π-periodic and even
   about π/2, so the strip is symmetric under the point reflection (θ, η) → (π − θ, H − η) about
   C = (π/2, H/2).  A period-2 orbit is a segment normal to both walls; through C it is:

   * the *vertical* orbit θ = π/2 (the body bouncing on its flat side): b = 1/√(1+ε), b' = 0,
     b'' = ε/√(1+ε); the lower wall has a minimum and the upper wall H − b(θ+π) a maximum, so the
     orbit bounces between two equal focusing mirrors of radius R = 1/b'' a distance
     L = H − 2/√(1+ε) apart;
   * the *tilted* pair, born where the vertical one turns unstable: the normal to the lower wall at
     θ₁ = π/2 − δ passes through C iff δ = −b'(θ₁)·(H/2 − b(θ₁)); then L = 2·√(δ² + (H/2 − b)²) and
     R = (1 + b'²)^{3/2}/b'' at θ₁ (the same at the other end, by the symmetry).

   Both hit the walls at normal incidence, so the optical-resonator rule applies: with g = 1 − L/R
   the orbit is linearly stable iff 0 < g² < 1, and otherwise its exponent per collision is
   arccosh|g| (the defocusing case arccosh(1 + L/R) is tested in tests/forward/dynamics/analysis/test_analysis.py).
   ε*(H): the vertical orbit turns unstable (L = 2R, g = −1; the tilted pair is born, pitchfork).
   ε**(H): the tilted orbit's contact point reaches the wall's inflection point (b'' = 0, R = ∞,
   g = 1) and it turns unstable.  In between, a linearly stable periodic orbit is generically
   surrounded by KAM curves (Moser's twist theorem), i.e. a regular island of positive measure, so
   the true boundary of "no regular region at all" is at least ε**(H).  Checked numerically: the
   tilted orbit returns to itself after 2 collisions; :func:`coinwall.forward.dynamics.analysis.lyapunov.lyapunov` on the orbit
   and 0.003 beside it is ≤ 3 ln N/N inside the window, and matches arccosh|g| outside it.
1. Sensitivity of ε_c to the sampling: ``kam_boundary`` with a wide bracket (the regular fraction is
   not monotonic in ε, and at H = 2 regular orbits are found at ε = 12) and 7 bisection steps,
   criteria varied one at a time from the default (100 orbits × 1000 collisions, regular_max 0.01),
   plus other seeds of the default.  With 100 orbits regular_max 0.01 and 0.0025 are the same
   criterion (no regular orbit at all), so 0.0025 is run with 400 orbits.  Note: when the tables in
   docs/dynamics.md were made, kam_boundary compared ``regular_fraction = 1 − fraction`` with
   ``regular_max``, and 1 − 399/400 rounds to 0.0024999999999999467 < 0.0025, so with 400 orbits
   regular_max 0.0025 accepted ONE regular orbit.  ``regular_fraction`` is now ``regular / orbits``
   (exact), so a rerun gives the "no regular orbit among 400" result for 0.0025, as for 0.002.
2. The regular fraction on a grid of ε from 0.9 ε* to 1.4 ε** with the strictest sampling (400 orbits
   × 5000 collisions, seed 0), the paper's ε = 1/H + 17/H² included: fraction ± binomial stderr (so ε_c
   for any regular_max can be read off), and the mean θ_c of each regular orbit's bottom-wall section
   (:func:`coinwall.forward.dynamics.analysis.poincare.poincare_section`) against the tilted orbit's θ_c = π/2 ± δ (mod π).
3. Artefact check: orbits classified regular, and borderline ones (λ up to 10× the threshold), at
   the paper's ε, at the largest grid ε with a regular orbit, and at the last ε where the default
   bisection (seed 0) found a regular orbit, are rerun 10× longer; an orbit stays regular if λ over
   10 N collisions is ≤ 3 ln(10 N)/(10 N).
Probe (``--probe``): at the given large ε, 2000 orbits × 1000 collisions, the regular ones rerun over
   10 000: small islands far above the boundary that a 100-orbit sample hits now and then.
4. Figure (``--figure``, only when H = 2 is among ``--H``): the Poincaré section at H = 2, ε = 4.75 with
   the regular orbits of part 2 highlighted, and the two period-2 orbits marked.

Nothing is asserted: this is a measurement.  Every sample is seeded, so a rerun gives the same numbers.
"""

import argparse
import json
import math
import os
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

from coinwall.forward.dynamics.analysis.islands import ELLIPSE_WALL, paper_boundary  # noqa: E402
from coinwall.forward.dynamics.analysis.kam import kam_boundary  # noqa: E402
from coinwall.forward.dynamics.analysis.lyapunov import chaotic_fraction, default_threshold, lyapunov, lyapunov_many  # noqa: E402
from coinwall.forward.dynamics.analysis.poincare import poincare_section  # noqa: E402
from coinwall.forward.dynamics.billiard.table import Billiard, simulate  # noqa: E402
from coinwall.forward.wall import Wall  # noqa: E402

BRACKETS = {2.0: (2.0, 100.0), 3.0: (1.0, 30.0), 8.0: (0.2, 2.0)}
CLOSED_FORM_H = (2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0)


def wall(eps):
    return Wall.from_expression(ELLIPSE_WALL, {"eps": float(eps)})


def table(eps, H):
    return Billiard(wall(eps), float(H))


def log(*text):
    print(*text, file=sys.stderr, flush=True)


# ------------------------------------------------------------------------------------------------ part 0
def vertical_orbit(eps, H):
    """g = 1 − L/R of the vertical orbit θ = π/2 (module docstring)."""
    L = H - 2.0 / math.sqrt(1.0 + eps)
    R = math.sqrt(1.0 + eps) / eps
    return 1.0 - L / R


def eps_star(H):
    """ε at which the vertical orbit turns unstable: g = −1 (L = 2R); L − 2R increases with ε."""
    from scipy.optimize import brentq

    return brentq(lambda e: vertical_orbit(e, H) + 1.0, 1e-6, 1e6, xtol=1e-13)


def tilted_orbit(eps, H):
    """The tilted period-2 orbit through (π/2, H/2) with δ closest to 0, or None.

    Returns a dict with δ, L, R, g and a start state on the orbit (moving up along the lower wall's normal).
    """
    from scipy.optimize import brentq

    w = wall(eps)

    def F(delta):
        b, b1, _ = (float(x[0]) for x in w.derivatives(np.array([math.pi / 2 - delta])))
        return delta + b1 * (H / 2 - b)

    grid = np.linspace(1e-7, math.pi / 2 - 1e-7, 4000)
    values = np.array([F(x) for x in grid])
    cross = np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))
    if cross.size == 0:
        return None
    delta = brentq(F, grid[cross[0]], grid[cross[0] + 1], xtol=1e-15)
    theta = math.pi / 2 - delta
    b, b1, b2 = (float(x[0]) for x in w.derivatives(np.array([theta])))
    L = 2.0 * math.hypot(delta, H / 2 - b)
    inv_R = b2 / (1.0 + b1 * b1) ** 1.5
    normal = np.array([-b1, 1.0]) / math.hypot(b1, 1.0)
    point = np.array([theta, b]) + 0.25 * L * normal
    return {"delta": delta, "L": L, "R": (1.0 / inv_R if inv_R else math.inf), "g": 1.0 - L * inv_R,
            "state": np.r_[point, normal]}


def eps_star_star(H):
    """ε at which the tilted orbit turns unstable: its contact point reaches b'' = 0 (g = 1)."""
    from scipy.optimize import brentq

    low = eps_star(H) * 1.001
    high = low
    while tilted_orbit(high, H)["g"] < 1.0:
        high *= 1.5
    return brentq(lambda e: tilted_orbit(e, H)["g"] - 1.0, high / 1.5 if high > low else low, high, xtol=1e-6)


def measured_exponent(tab, state, closed):
    """λ per collision of a periodic orbit: long when stable; when unstable, short: rounding pushes the
    reference orbit off like 1e-16·e^{λn}, so n ≈ 25/λ collisions in all (drift ≲ 1e-5), of which the
    first 10 align the separation with the unstable direction and are not counted."""
    if closed == 0.0:
        return float(lyapunov(tab, state, collisions=5000).per_collision[0])
    counted = max(5, 5 * int((25.0 / closed - 10.0) // 5))
    return float(lyapunov(tab, state, collisions=counted, every=5, transient=2).per_collision[0])


def part0(H_values):
    closed_rows = []
    for H in CLOSED_FORM_H:
        closed_rows.append({"H": H, "eps_star": eps_star(H), "eps_star_star": eps_star_star(H),
                            "paper": float(paper_boundary(H))})
    print("\n### 0. Period-2 orbits: stability window of the tilted orbit (closed form + root finding)\n")
    print("| H | ε* (vertical orbit unstable, tilted born) | ε** (tilted orbit unstable) | paper 1/H + 17/H² |"
          " paper / ε* | ε** / paper |")
    print("|---|---|---|---|---|---|")
    for r in closed_rows:
        print(f"| {r['H']:g} | {r['eps_star']:.4g} | {r['eps_star_star']:.4g} | {r['paper']:.4g} | "
              f"{r['paper'] / r['eps_star']:.3f} | {r['eps_star_star'] / r['paper']:.2f} |")
    checks = []
    for H in H_values:
        es, ess = eps_star(H), eps_star_star(H)
        for label, eps in (("vertical", 0.9 * es), ("vertical", 1.1 * es), ("tilted", math.sqrt(es * ess)),
                           ("tilted", float(paper_boundary(H))), ("tilted", 1.3 * ess)):
            tab = table(eps, H)
            if label == "vertical":
                g = vertical_orbit(eps, H)
                state = np.array([math.pi / 2, H / 2, 0.0, 1.0])
                returns = float("nan")
            else:
                orbit = tilted_orbit(eps, H)
                if orbit is None:
                    continue
                g, state = orbit["g"], orbit["state"]
                traj = simulate(tab, state, 3)
                # after two collisions the orbit is back at the same wall point with the same velocity
                returns = float(max(abs(traj.theta[2] - traj.theta[0]), abs(traj.eta[2] - traj.eta[0]),
                                    abs(traj.v_theta[2] - traj.v_theta[0]), abs(traj.v_eta[2] - traj.v_eta[0])))
            closed = math.acosh(abs(g)) if abs(g) > 1.0 else 0.0
            lam = measured_exponent(tab, state, closed)
            beside = float("nan")
            if closed == 0.0:
                shifted = state.copy()
                shifted[0] += 0.003
                beside = float(lyapunov(tab, shifted, collisions=5000).per_collision[0])
            checks.append({"H": H, "orbit": label, "eps": eps, "g": g, "closed_form": closed, "measured": lam,
                           "beside": beside, "period2_return": returns})
    print(f"\nNumerical check (stable: λ over 5000 collisions, regular if ≤ {default_threshold(5000):.2e}; "
          "'beside': start shifted by 0.003 in θ):\n")
    print("| H | orbit | ε | g = 1 − L/R | λ closed form | λ measured | λ beside | period-2 return error |")
    print("|---|---|---|---|---|---|---|---|")
    for r in checks:
        closed = "stable" if r["closed_form"] == 0.0 else f"{r['closed_form']:.4f}"
        beside = "" if math.isnan(r["beside"]) else f"{r['beside']:.2e}"
        ret = "" if math.isnan(r["period2_return"]) else f"{r['period2_return']:.1e}"
        print(f"| {r['H']:g} | {r['orbit']} | {r['eps']:.4g} | {r['g']:.4f} | {closed} | {r['measured']:.4g} | "
              f"{beside} | {ret} |")
    return closed_rows, checks


# ------------------------------------------------------------------------------------------------ part 1
def configs(quick):
    if quick:
        return [("default", 100, 1000, 0.01, (0, 1)), ("orbits 400, regular_max 0.0025", 400, 1000, 0.0025, (0,))]
    return [("default", 100, 1000, 0.01, (0, 1, 2, 3, 4)),
            ("orbits 400", 400, 1000, 0.01, (0,)),
            ("orbits 400, regular_max 0.0025", 400, 1000, 0.0025, (0,)),
            ("orbits 400, regular_max 0.002", 400, 1000, 0.002, (0,)),
            ("collisions 5000", 100, 5000, 0.01, (0,)),
            ("400 × 5000, regular_max 0.0025", 400, 5000, 0.0025, (0,))]


def part1(H_values, quick):
    steps = 3 if quick else 7
    rows = []
    for H in H_values:
        bracket = BRACKETS.get(H) or (0.5 * eps_star(H), 3.0 * eps_star_star(H))
        for name, orbits, collisions, regular_max, seeds in configs(quick):
            for seed in seeds:
                begin = time.perf_counter()
                kb = kam_boundary([H], bracket=bracket, steps=steps, orbits=orbits, collisions=collisions,
                                  regular_max=regular_max, seed=seed)
                seconds = time.perf_counter() - begin
                rows.append({"H": H, "criterion": name, "orbits": orbits, "collisions": collisions,
                             "regular_max": regular_max, "seed": seed, "eps": float(kb.eps[0]),
                             "eps_low": float(kb.eps_low[0]), "eps_high": float(kb.eps_high[0]),
                             "paper": float(kb.paper[0]), "bracket": list(bracket), "steps": steps,
                             "seconds": seconds, "history": [[float(e), float(f)] for e, f in kb.history[0]]})
                log(f"part 1: H={H:g} {name} seed {seed}: eps_c {kb.eps[0]:.4g} ({seconds:.0f} s)")
    print(f"\n### 1. ε_c by bisection (kam_boundary, {steps} steps in log ε)\n")
    print("| H | criterion | orbits × collisions | regular_max | seed | bracket | ε_c | final bracket | paper "
          "| ε_c / paper | s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['H']:g} | {r['criterion']} | {r['orbits']} × {r['collisions']} | {r['regular_max']:g} | "
              f"{r['seed']} | [{r['bracket'][0]:g}, {r['bracket'][1]:g}] | {r['eps']:.3g} | "
              f"[{r['eps_low']:.3g}, {r['eps_high']:.3g}] | {r['paper']:.3g} | {r['eps'] / r['paper']:.2f} | "
              f"{r['seconds']:.0f} |")
    return rows


# ------------------------------------------------------------------------------------------------ part 2
def locate(eps, H, frac):
    """Mean θ_c/π and the φ_c/π range of each regular orbit's bottom-wall section."""
    lam = frac.exponents.per_collision
    idx = np.flatnonzero(lam <= frac.threshold)
    if idx.size == 0:
        return []
    sec = poincare_section(table(eps, H), states=frac.exponents.starts[idx], collisions=frac.collisions)
    out = []
    for k, i in enumerate(idx):
        m = sec.orbit == k
        th, ph = sec.theta[m] / math.pi, sec.phi[m] / math.pi
        out.append({"orbit": int(i), "lambda": float(lam[i]), "theta_min": float(th.min()),
                    "theta_max": float(th.max()), "theta_mean": float(th.mean()), "phi_min": float(ph.min()),
                    "phi_max": float(ph.max())})
    return out


def part2(H_values, quick):
    orbits, collisions = (200, 2000) if quick else (400, 5000)
    points = 4 if quick else 8
    rows, fracs = [], {}
    for H in H_values:
        paper = float(paper_boundary(H))
        grid = sorted({paper, *np.geomspace(0.9 * eps_star(H), 1.4 * eps_star_star(H), points).tolist()})
        for eps in grid:
            begin = time.perf_counter()
            frac = chaotic_fraction(table(eps, H), orbits, collisions, seed=0)
            lam = frac.exponents.per_collision
            orbit = tilted_orbit(eps, H)
            tilted = None if orbit is None else orbit["delta"] / math.pi
            stable = orbit is not None and orbit["g"] ** 2 < 1.0
            rows.append({"H": H, "eps": eps, "paper": eps == paper, "orbits": frac.orbits,
                         "collisions": collisions, "regular": frac.regular, "regular_fraction": frac.regular_fraction,
                         "stderr": frac.stderr, "threshold": frac.threshold,
                         "borderline": int(np.count_nonzero((lam > frac.threshold) & (lam <= 10 * frac.threshold))),
                         "tilted_delta_over_pi": tilted, "tilted_stable": stable,
                         "regular_orbits": locate(eps, H, frac), "seconds": time.perf_counter() - begin})
            fracs[(H, eps)] = frac
            log(f"part 2: H={H:g} eps={eps:.4g}: {frac!r}")
    print(f"\n### 2. Regular fraction against ε ({orbits} orbits × {collisions} collisions, seed 0)\n")
    print("| H | ε | ε / paper | regular | regular fraction ± stderr | borderline | tilted orbit θ_c/π = ½ ± δ/π "
          "| θ_c/π (mean, mod 1) of the regular orbits |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        mark = " (paper)" if r["paper"] else ""
        if r["tilted_delta_over_pi"] is None:
            tilted = "none (vertical stable)"
        else:
            tilted = f"½ ± {r['tilted_delta_over_pi']:.3f} ({'stable' if r['tilted_stable'] else 'unstable'})"
        where = ", ".join(f"{o['theta_mean'] % 1:.3f}" for o in r["regular_orbits"])
        print(f"| {r['H']:g} | {r['eps']:.4g}{mark} | {r['eps'] / float(paper_boundary(r['H'])):.2f} | "
              f"{r['regular']}/{r['orbits']} | {100 * r['regular_fraction']:.2f} ± {100 * r['stderr']:.2f} % | "
              f"{r['borderline']} | {tilted} | {where} |")
    print("\nRegular orbits at the paper's ε, bottom-wall section (angles / π):\n")
    print("| H | ε | orbit | λ/collision | θ_c range | θ_c mean | φ_c range |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        if r["paper"]:
            for o in r["regular_orbits"]:
                print(f"| {r['H']:g} | {r['eps']:.4g} | {o['orbit']} | {o['lambda']:.2e} | [{o['theta_min']:.3f}, "
                      f"{o['theta_max']:.3f}] | {o['theta_mean']:.3f} | [{o['phi_min']:.3f}, {o['phi_max']:.3f}] |")
    return rows, fracs


# ------------------------------------------------------------------------------------------------ part 3
def long_check(eps, H, frac, label, factor=10, cap=10):
    """Rerun the regular and borderline orbits of ``frac`` ``factor``× longer (at most ``cap``, smallest λ first)."""
    lam = frac.exponents.per_collision
    thr = frac.threshold
    idx = np.flatnonzero(lam <= 10 * thr)
    idx = idx[np.argsort(lam[idx])][:cap]
    if idx.size == 0:
        return []
    long_n = factor * frac.collisions
    long_thr = default_threshold(long_n)
    res = lyapunov_many(table(eps, H), frac.exponents.starts[idx], collisions=long_n)
    return [{"H": H, "eps": eps, "label": label, "orbit": int(i), "collisions": frac.collisions,
             "lambda": float(lam[i]), "regular": bool(lam[i] <= thr), "long_collisions": long_n,
             "long_lambda": float(res.per_collision[j]), "long_regular": bool(res.per_collision[j] <= long_thr),
             "threshold": thr, "long_threshold": long_thr} for j, i in enumerate(idx)]


def part3(H_values, part1_rows, part2_rows, fracs):
    rows = []
    for H in H_values:
        mine = [r for r in part2_rows if r["H"] == H]
        paper = next(r for r in mine if r["paper"])
        rows += long_check(paper["eps"], H, fracs[(H, paper["eps"])], "paper ε, part 2")
        last = max((r for r in mine if r["regular"] > 0), key=lambda r: r["eps"], default=None)
        if last is not None and last["eps"] != paper["eps"]:
            rows += long_check(last["eps"], H, fracs[(H, last["eps"])], "largest part-2 ε with a regular orbit")
        default = next((r for r in part1_rows if r["H"] == H and r["criterion"] == "default" and r["seed"] == 0), None)
        if default is not None and default["eps_low"] > 0 and math.isfinite(default["eps_high"]):
            # chaotic_fraction is deterministic: the same orbits the bisection classified at its last regular ε
            frac = chaotic_fraction(table(default["eps_low"], H), default["orbits"], default["collisions"], seed=0)
            rows += long_check(default["eps_low"], H, frac, "last regular ε of default bisection")
        log(f"part 3: H={H:g} done")
    print("\n### 3. Orbits called regular or borderline (λ ≤ 10 × threshold), rerun 10× longer\n")
    print("| H | ε | sample | orbit | λ over N | class | λ over 10 N | class at 10 N |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['H']:g} | {r['eps']:.4g} | {r['label']} | {r['orbit']} | {r['lambda']:.2e} (N={r['collisions']}) | "
              f"{'regular' if r['regular'] else 'chaotic'} | {r['long_lambda']:.2e} | "
              f"{'regular' if r['long_regular'] else 'chaotic'} |")
    return rows


# ------------------------------------------------------------------------------------------------ probe
def probe(H_values, eps_values, orbits=2000, collisions=1000):
    """Large sample at large ε: regular orbits the default criterion can stumble on far above the boundary."""
    rows = []
    for H in H_values:
        for eps in eps_values:
            frac = chaotic_fraction(table(eps, H), orbits, collisions, seed=0)
            checked = long_check(eps, H, frac, "probe", cap=orbits)
            where = {o["orbit"]: o for o in locate(eps, H, frac)}
            for r in checked:
                o = where.get(r["orbit"])
                r["where"] = None if o is None else (o["theta_min"], o["theta_max"], o["phi_min"], o["phi_max"])
            stay = sum(1 for r in checked if r["regular"] and r["long_regular"])
            rows.append({"H": H, "eps": eps, "orbits": frac.orbits, "collisions": collisions, "regular": frac.regular,
                         "regular_long": stay, "orbits_checked": checked})
            log(f"probe: H={H:g} eps={eps:g}: {frac!r}")
    print("\n### Probe: large ε, 2000 orbits × 1000 collisions (seed 0), regular ones rerun over 10 000\n")
    print("| H | ε | regular at N = 1000 | still regular at 10 N | regular fraction (10 N) | "
          "where (θ_c/π range, φ_c/π range) of those still regular |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        where = "; ".join(f"[{w[0]:.2f}, {w[1]:.2f}], [{w[2]:.3f}, {w[3]:.3f}]" for w in
                          (c["where"] for c in r["orbits_checked"] if c["regular"] and c["long_regular"]) if w)
        print(f"| {r['H']:g} | {r['eps']:g} | {r['regular']}/{r['orbits']} | {r['regular_long']} | "
              f"{100 * r['regular_long'] / r['orbits']:.2f} % | {where} |")
    return rows


# ------------------------------------------------------------------------------------------------ part 4
def figure(path, part2_rows, fracs, long_rows):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    H = 2.0
    eps = next(r["eps"] for r in part2_rows if r["H"] == H and r["paper"])
    frac = fracs[(H, eps)]
    tab = table(eps, H)
    lam = frac.exponents.per_collision
    starts = frac.exponents.starts
    regular = np.flatnonzero(lam <= frac.threshold)
    sticky = {r["orbit"] for r in long_rows if r["H"] == H and r["eps"] == eps and r["regular"]
              and not r["long_regular"]}
    chaotic = np.flatnonzero(lam > frac.threshold)[:120]
    back = poincare_section(tab, states=starts[chaotic], collisions=2000)
    fore = poincare_section(tab, states=starts[regular], collisions=frac.collisions)
    orbit = tilted_orbit(eps, H)
    delta = orbit["delta"] / math.pi
    # a few orbits started beside the tilted orbit (not random) show the extent of its island
    near = np.array([orbit["state"] + [d, 0.0, 0.0, 0.0] for d in (0.01, 0.02, 0.03, 0.04)])
    near_lam = lyapunov_many(tab, near, collisions=frac.collisions).per_collision
    island = poincare_section(tab, states=near, collisions=frac.collisions)
    fig, axes = plt.subplots(1, 2, figsize=(10, 5.0), gridspec_kw={"width_ratios": [1.3, 1]})
    zoom = (1.35, 1.65, -0.06, 0.06)
    from matplotlib.lines import Line2D

    colours = plt.get_cmap("tab10")
    handles = []
    for n_ax, ax in enumerate(axes):
        # the table is π-periodic in θ (b(θ + π) = b(θ)): the zoom folds θ_c into [π, 2π) to show both halves
        x = (lambda th: th / math.pi) if n_ax == 0 else (lambda th: np.mod(th, math.pi) / math.pi + 1.0)
        ax.plot(x(back.theta), back.phi / math.pi, ",", color="0.7", rasterized=True)
        ax.plot(x(island.theta), island.phi / math.pi, linestyle="none", marker="o", markersize=0.6,
                markeredgewidth=0, color="navy", rasterized=True)
        for k, i in enumerate(regular):
            m = fore.orbit == k
            colour = "k" if int(i) in sticky else colours(k % 10)
            ax.plot(x(fore.theta[m]), fore.phi[m] / math.pi, linestyle="none", marker="o", markersize=1.2,
                    markeredgewidth=0, color=colour, rasterized=True)
            if n_ax == 0:
                handles.append(Line2D([], [], linestyle="none", marker="o", markersize=4, color=colour,
                                      label=f"random orbit {i}, λ = {lam[i]:.1e}"
                                            + (": chaotic over 10 N" if int(i) in sticky else "")))
        ax.plot([0.5, 1.5], [0, 0], "r+", markersize=7)
        ax.plot([0.5 - delta, 0.5 + delta, 1.5 - delta, 1.5 + delta], [0] * 4, "bx", markersize=5)
    handles += [Line2D([], [], linestyle="none", marker="s", markersize=4, color="navy",
                       label=f"4 orbits started 0.01–0.04 beside the tilted orbit, max λ = {np.max(near_lam):.1e}"),
                Line2D([], [], linestyle="none", marker="+", markersize=7, color="r",
                       label="vertical period-2 orbit (unstable)"),
                Line2D([], [], linestyle="none", marker="x", markersize=5, color="b",
                       label=f"tilted period-2 orbit, θ_c/π = ½ ± {delta:.3f} (stable)")]
    axes[0].set_xlim(0, 2)
    axes[0].set_ylim(-0.5, 0.5)
    axes[0].add_patch(plt.Rectangle((zoom[0], zoom[2]), zoom[1] - zoom[0], zoom[3] - zoom[2], fill=False, lw=0.8))
    axes[0].set_title(f"H = 2, ε = {eps:.3g} (paper's boundary): {regular.size} of {lam.size} Liouville-random "
                      f"orbits regular\n(grey: {chaotic.size} chaotic orbits × 2000 collisions)", fontsize=9)
    axes[1].set_xlim(zoom[0], zoom[1])
    axes[1].set_ylim(zoom[2], zoom[3])
    axes[1].set_title(r"zoom on the box, $\theta_c$ folded mod $\pi$ into $[\pi, 2\pi)$ (π-periodic table)",
                      fontsize=9)
    for ax in axes:
        ax.set_xlabel(r"contact angle $\theta_c/\pi$")
    axes[0].set_ylabel(r"angle of incidence $\phi_c/\pi$")
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.15, 1, 1))
    folder = os.path.dirname(os.path.abspath(path))
    handle, tmp = tempfile.mkstemp(suffix=".png", dir=folder)
    os.close(handle)
    try:
        fig.savefig(tmp, dpi=110)
        os.chmod(tmp, 0o644)  # mkstemp creates 0600
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    plt.close(fig)
    log(f"figure: {path} ({os.path.getsize(path) / 1024:.0f} KB); λ beside the tilted orbit: {near_lam}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--H", default="2,3", help="comma-separated wall distances (default 2,3)")
    parser.add_argument("--quick", action="store_true", help="small samples: checks the script, not the numbers")
    parser.add_argument("--figure", help="PNG path of the H = 2 Poincaré section with the regular orbits")
    parser.add_argument("--json", help="write every number to this JSON file")
    parser.add_argument("--parts", default="0,1,2,3",
                        help="parts to run (default 0,1,2,3; part 3 and the figure need 1 and 2)")
    parser.add_argument("--probe", help="comma-separated large ε values for the probe (2000 orbits × 1000 "
                                        "collisions each, ~15 s per value and H)")
    parser.add_argument("--smoke", action="store_true", help="the closed forms at H = 2 only: checks the script")
    args = parser.parse_args()
    if args.smoke:  # part 0 (closed forms and their checks); parts 1-3 take about a minute even with --quick
        args.H, args.parts, args.quick = "2", "0", True
    H_values = [float(v) for v in args.H.split(",")]
    parts = set(args.parts.split(","))
    begin, cpu = time.perf_counter(), time.process_time()
    print(f"## KAM criterion sensitivity, H = {args.H}{' (quick)' if args.quick else ''}")
    closed_rows, checks = part0(H_values) if "0" in parts else ([], [])
    rows1 = part1(H_values, args.quick) if "1" in parts else []
    rows2, fracs = part2(H_values, args.quick) if "2" in parts else ([], {})
    rows3 = part3(H_values, rows1, rows2, fracs) if {"1", "2", "3"} <= parts else []
    rows_probe = probe(H_values, [float(v) for v in args.probe.split(",")]) if args.probe else []
    if args.figure and 2.0 in H_values and {"1", "2", "3"} <= parts:
        figure(args.figure, rows2, fracs, rows3)
    seconds, cpu = time.perf_counter() - begin, time.process_time() - cpu
    print(f"\nTotal: {seconds:.0f} s wall, {cpu:.0f} s CPU of this process.")
    if args.json:
        record = {"H": H_values, "quick": args.quick, "period2_closed_form": closed_rows, "period2_checks": checks,
                  "bisection": rows1, "scan": rows2, "long_check": rows3, "probe": rows_probe, "seconds": seconds, "cpu_seconds": cpu}
        folder = os.path.dirname(os.path.abspath(args.json))
        handle, tmp = tempfile.mkstemp(suffix=".json", dir=folder)
        with os.fdopen(handle, "w") as stream:
            json.dump(record, stream, indent=1)
        os.chmod(tmp, 0o644)  # mkstemp creates 0600
        os.replace(tmp, args.json)


if __name__ == "__main__":
    main()
