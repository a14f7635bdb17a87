"""Walls from data against bodies known in closed form: the table of what coinwall certifies and how well.

Run:  python tests/benchmarks/bench_data_truth.py [--smoke] [--seeds 100]

Every truth comes from ``tests/datatruth.py`` and ``tests/walldata.py`` (numpy and scipy only, never coinwall).
The samples are written to CSV files as people write them and read back by coinwall, as a user's file would be.

1. **Cases**: for each body, the certified interval of b_c against the truth, the corners found against the
   true ones (and those whose window holds two samples or more: the ones the data can force), the Hausdorff
   distance from the returned outline to the true body (computed here from the outline's own Bézier points)
   against the reported outline tolerance, and the solve time.
2. **Random polygons**: 24 convex polygons of 5–15 sides at 4–8 digits, 360–2,000 angles: vertices found.
3. **Noise**: samples with standard deviations, the 95 % confidence interval of b_c over many seeds:
   coverage and median width.
4. **Dense data**: solve time at 10⁴, 10⁵ and 10⁶ samples of a superellipse written to 8 digits (CPU seconds),
   and as a ratio to a baseline run in the same process: 100 real FFTs of the samples (numpy).
--smoke: two cases, three polygons, five seeds, 10⁴ samples only (checks the script in seconds).
"""

import argparse
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
import datatruth as T  # noqa: E402
import walldata as W  # noqa: E402

from coinwall import solve_body  # noqa: E402
from coinwall.forward.errors import CoinwallError  # noqa: E402
from coinwall.forward.formats.wallfile import load_wall_file  # noqa: E402


def _solve(path, b0=0.0):
    start = time.process_time()
    body = solve_body(load_wall_file(path), b0)
    return body, time.process_time() - start


def _outer_spread(body, theta, upper):
    """The Hausdorff distance from the returned outline to the outer body (every upper end of the samples'
    intervals a support line of it: a body consistent with the samples whenever any is), built here with
    scipy's HalfspaceIntersection: a lower bound on how far the consistent bodies spread about the outline."""
    from scipy.spatial import ConvexHull, HalfspaceIntersection

    inside = np.zeros(2)
    cut = HalfspaceIntersection(np.column_stack([np.cos(theta), np.sin(theta), -upper]), inside)
    points = cut.intersections[ConvexHull(cut.intersections).vertices]
    grid = np.linspace(0, T.TWO_PI, 20_000, endpoint=False)
    outer = np.max(np.cos(grid)[:, None] * points[:, 0] + np.sin(grid)[:, None] * points[:, 1], axis=1)
    own = T.outline_support(body.outline.nodes, body.outline.controls, grid, 1 if body.method == "halfplanes" else 16)
    return float(np.max(np.abs(outer - own)))


def _corner_match(body, truth, theta):
    """(found, true, true with two samples or more inside their window, largest distance of a found corner to
    the nearest true vertex)."""
    seen, _ = truth.corners_seen(theta, 2)
    found = np.array([[c.distance * math.cos(c.direction), c.distance * math.sin(c.direction)] for c in body.corners])
    far = 0.0
    if found.size and truth.vertices.size:
        far = float(np.max(np.min(np.hypot(*(found[:, None, :] - truth.vertices[None]).transpose(2, 0, 1)),
                                  axis=1)))
    return len(body.corners), len(truth.vertices), len(seen), far


def cases(folder, smoke):
    rng = np.random.default_rng(2024)
    deg = np.radians(np.arange(360.0))
    random300 = np.sort(rng.uniform(0, T.TWO_PI, 300))
    uniform = lambda n: np.arange(n) * T.TWO_PI / n  # noqa: E731
    table = [
        ("pentagon, whole degrees, 8 decimals", T.regular_polygon(5), deg, dict(digits=8, degrees=True,
                                                                                  theta_digits=0), 0.0),
        ("12-gon, 2,000 angles, 8 digits", T.regular_polygon(12, phase=0.1), uniform(2000), dict(digits=8), 0.0),
        ("triangle ⊕ disc 0.3, 300 random angles, 6 digits",
         T.polygon([[1.0, 0.0], [-0.5, 0.8660254], [-0.5, -0.8660254]], "triangle", 0.3), random300,
         dict(digits=6), 0.0),
        ("pentagon ⊕ disc 0.05, 720 angles, 4 digits", T.regular_polygon(5, rounding=0.05), uniform(720),
         dict(digits=4), 0.0),
        ("lens R=1 d=0.6, 720 angles, 8 digits", T.lens(), uniform(720), dict(digits=8), 0.0),
        ("half disc (one long edge), 1°, 6 digits", T.d_shape(), deg, dict(digits=6, degrees=True, theta_digits=0),
         0.0),
        ("egg, 360 random angles, 6 digits", T.egg(), np.sort(rng.uniform(0, T.TWO_PI, 360)), dict(digits=6), 0.0),
        ("superellipse p=4, 1,000 angles, 6 digits", T.superellipse(), uniform(1000), dict(digits=6), 0.0),
        ("ellipse 1×0.65 off centre, rows shuffled, 10% twice", T.ellipse(1.0, 0.65, (0.1, -0.05)), uniform(720),
         dict(digits=7, shuffle=True, duplicate=0.1), 0.0),
        ("paper wall ε=1 at b0 = b_c = −0.5, 1°, 8 decimals", T.paper_wall(1.0), deg,
         dict(digits=8, degrees=True, theta_digits=0), -0.5),
        ("ellipse × 1e-3 (tiny), 720 angles, 9 decimals", T.ellipse(1e-3, 6.5e-4), uniform(720), dict(digits=9), 0.0),
        ("ellipse × 1e3 (huge), 720 angles, 3 decimals", T.ellipse(1e3, 650.0), uniform(720), dict(digits=3), 0.0),
    ]
    if smoke:
        table = table[:2]
    rows = []
    for name, truth, theta, how, b0 in table:
        path = T.write_csv(os.path.join(folder, "case.csv"), theta, truth.h(theta), rng=rng, **how)
        body, seconds = _solve(path, b0)
        found, true, seen, far = _corner_match(body, truth, theta)
        dist = T.distance(body, truth)
        tol = body.outline_tolerance
        data = body.wall.sample_data
        spread = _outer_spread(body, data.theta, b0 + data.b + data.halfwidth) if tol is not None else None
        rows.append((name, body.b_c_lower, truth.b_c, body.b_c_upper, found, true, seen, far, dist, tol, seconds,
                     "/".join(body.regimes), spread))
    # Reuleaux pentagon and a cam from walldata (their own closed forms)
    if not smoke:
        for name, ref, digits in (("Reuleaux pentagon, 720 angles, 6 digits", W.reuleaux(5, 720), 6),
                                  ("cycloidal cam at b0 = b_c + 0.5, 360 angles, 6 digits", W.cam("cycloidal", 360),
                                   6)):
            written = W.write_rounded(ref, digits, theta_digits=digits)
            path = os.path.join(folder, "ref.csv")
            with open(path, "w") as stream:
                stream.write(written.text)
            b0 = 0.0 if ref.b_c <= 0 else ref.b_c + 0.5  # a cam's b_c is positive: solved where it is convex
            body, seconds = _solve(path, b0)
            truth = T.Truth(name, ref.b_of, ref.b_c, ref.vertices if ref.vertices is not None else np.zeros((0, 2)),
                            np.zeros((0, 2)))
            dist = T.distance(body, truth)
            data = body.wall.sample_data
            spread = _outer_spread(body, data.theta, b0 + data.b + data.halfwidth)
            rows.append((name, body.b_c_lower, ref.b_c, body.b_c_upper, len(body.corners), ref.corners or 0, None,
                         0.0, dist, body.outline_tolerance, seconds, "/".join(body.regimes), spread))
    print("| case | b_c lower ≤ truth ≤ upper | holds | regime | corners found / true (≥2 samples) | "
          "distance to truth | outline tolerance | distance to the outer body | tolerance / that | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, lo, truth, hi, found, true, seen, far, dist, tol, sec, regimes, spread in rows:
        holds = lo is not None and lo - 1e-12 <= truth <= hi + 1e-12
        covers = tol is not None and dist <= tol
        seen_text = "" if seen is None else f" ({seen})"
        tol_text = "—" if tol is None else f"{tol:.3g}{'' if covers else ' (BELOW)'}"
        ratio = "—" if tol is None or not spread else f"{tol / spread:.3g}"
        print(f"| {name} | {lo:.6g} ≤ {truth:.6g} ≤ {hi:.6g} | {'yes' if holds else 'NO'} | {regimes} | "
              f"{found} / {true}{seen_text} | {dist:.3g} | {tol_text} | {'—' if spread is None else f'{spread:.3g}'} | "
              f"{ratio} | {sec:.2f} |")


def random_polygons(folder, smoke):
    rng = np.random.default_rng(5)
    total = found = resolvable = false = 0
    count = 3 if smoke else 24
    worst = 0.0
    for _ in range(count):
        sides, digits = int(rng.integers(5, 16)), int(rng.integers(4, 9))
        truth = T.random_polygon(sides, rng)
        n = int(rng.choice([360, 720, 1000, 2000]))
        theta = np.arange(n) * T.TWO_PI / n
        path = T.write_csv(os.path.join(folder, "poly.csv"), theta, truth.h(theta), digits=digits)
        body, _ = _solve(path)
        f, t, s, far = _corner_match(body, truth, theta)
        total, found, resolvable = total + t, found + f, resolvable + s
        false += int(far > 1e-2)
        worst = max(worst, T.distance(body, truth) / body.outline_tolerance)
    print(f"\nrandom polygons ({count}, 5–15 sides, 4–8 digits, 360–2,000 angles): {found} corners found of {total} "
          f"vertices ({resolvable} with two samples or more inside their window); corners farther than 0.01 from "
          f"every vertex: {false}; largest outline distance / outline tolerance {worst:.3g}")


def noise(seeds):
    from coinwall.inverse.noise import noisy_critical

    print(f"\nnoisy samples, 95% confidence interval of b_c over {seeds} seeds")
    print("| wall | samples | σ | coverage | median width | largest width |")
    print("|---|---|---|---|---|---|")
    for truth, n, sigma, random in ((T.ellipse(1.0, 0.65), 360, 1e-3, False), (T.paper_wall(1.0), 360, 1e-3, False),
                                    (T.ellipse(1.0, 0.65), 360, 1e-3, True), (T.paper_wall(1.0), 360, 1e-2, False),
                                    (T.egg(), 720, 1e-3, False)):
        hits, widths = 0, []
        for seed in range(seeds):
            rng = np.random.default_rng(1000 + seed)
            theta = np.sort(rng.uniform(0, T.TWO_PI, n)) if random else np.arange(n) * T.TWO_PI / n
            found = noisy_critical(theta, truth.h(theta) + sigma * rng.standard_normal(n), sigma)
            hits += found.lower <= truth.b_c <= found.upper
            widths.append(found.upper - found.lower)
        print(f"| {truth.name}{' (random angles)' if random else ''} | {n} | {sigma:g} | {hits / seeds:.2f} | "
              f"{np.median(widths):.3g} | {np.max(widths):.3g} |")


def dense(smoke):
    from coinwall import Wall

    truth = T.superellipse()
    print("\ndense data: superellipse p=4 at 8 digits (solve_body; CPU seconds, and as a ratio to 100 real FFTs of "
          "the samples in this process)")
    print("| samples | solve s | 100 FFTs s | ratio | regime | outline tolerance | distance | warnings |")
    print("|---|---|---|---|---|---|---|---|")
    for n in ((10_000,) if smoke else (10_000, 100_000, 1_000_000)):
        theta = np.arange(n) * T.TWO_PI / n
        b = np.round(truth.h(theta), 8)
        wall = Wall.from_samples(theta, b, rounding=np.full(n, 5e-9))
        start = time.process_time()
        for _ in range(100):
            np.fft.rfft(b)
        base = time.process_time() - start
        start = time.process_time()
        body = solve_body(wall, 0.0)
        seconds = time.process_time() - start
        print(f"| {n:,} | {seconds:.2f} | {base:.3f} | {seconds / max(base, 1e-9):.0f} | {body.regime} | "
              f"{body.outline_tolerance:.2g} | {T.distance(body, truth, 20_000):.2g} | {len(body.warnings)} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="a few cases: checks the script")
    parser.add_argument("--seeds", type=int, default=100, help="seeds of the noise study")
    args = parser.parse_args()
    solve_body(load_wall_file(T.write_csv(os.path.join(tempfile.gettempdir(), "warm.csv"),
                                          np.arange(64) * T.TWO_PI / 64, np.ones(64))), 0.5)  # imports
    with tempfile.TemporaryDirectory() as folder:
        try:
            cases(folder, args.smoke)
            random_polygons(folder, args.smoke)
        except CoinwallError as exc:  # pragma: no cover - a case the library refuses is a finding
            print(f"refused: {exc}")
            raise
    noise(5 if args.smoke else args.seeds)
    dense(args.smoke)


if __name__ == "__main__":
    main()
