"""Benchmark: `critical_offset` of formula walls (every minimiser, certified) vs one evaluation of b, b', b''.

Run:  python tests/benchmarks/bench_critical.py [--smoke]
Each wall is made afresh for every repeat (a wall keeps its critical offset once computed), and its
critical offset timed interleaved with the baseline: evaluating b, b', b'' of the same wall on 8,192 angles
(the grid the critical offset used to bracket its minimum on).  Medians of the repeats, and their ratio
(the shared machine's load moves both alike).  Target: each formula well under a second.
``--smoke``: three walls, two repeats (checks the script, not the numbers).
"""

import argparse
import statistics
import time

import numpy as np

from coinwall.forward import Wall
from coinwall.inverse import critical_offset

WALLS = [
    ("1+0.1*cos(3*t)", {}),
    ("1+0.02*cos(5*t)+0.02*cos(10*t)", {}),
    ("sqrt((1+eps*cos(t)**2)/(1+eps))", {"eps": 99.0}),
    ("abs(cos(t)) + 0.5*abs(sin(t))", {}),
    ("max(cos(t), 0.5*cos(t-2))", {}),
    ("2+tanh(1e5*sin(t-1))", {}),
    ("(abs(cos(t))**(4/3) + abs(sin(t))**(4/3))**(3/4)", {}),
    ("1 + 0.06*cos(2*t) + 0.04*sin(3*t) + 0.05*cos(t)", {}),
]
REPEATS = 7


def _fourier():
    rng = np.random.default_rng(1)
    k = np.arange(1, 101)
    return Wall.from_fourier(5.0, rng.normal(size=100) / k**3, rng.normal(size=100) / k**3)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="three walls, two repeats: checks the script")
    args = parser.parse_args(argv)
    walls, repeats = (WALLS[:3], 2) if args.smoke else (WALLS, REPEATS)
    grid = np.linspace(0.0, 2 * np.pi, 8192, endpoint=False)
    makers = [(text, (lambda text=text, params=params: Wall.from_expression(text, params))) for text, params in walls]
    makers.append(("Fourier series, 100 harmonics (coefficients ~ k^-3)", _fourier))
    for name, make in makers:
        base, times = [], []
        for _ in range(repeats):
            wall = make()
            start = time.perf_counter()
            wall.derivatives(grid)
            base.append(time.perf_counter() - start)
            wall = make()
            start = time.perf_counter()
            result = critical_offset(wall)
            times.append(time.perf_counter() - start)
        b, t = statistics.median(base), statistics.median(times)
        print(f"{name[:52]:52s} critical {t * 1e3:7.1f} ms  (b,b',b'' on 8192 angles {b * 1e3:6.2f} ms, ratio "
              f"{t / b:6.1f})  b_c = {result.b_c:.15g} ± {result.b_c_tolerance:.1g}, {len(result.angles)} angles "
              f"± {max(result.angle_errors, default=0):.1g}")


if __name__ == "__main__":
    main()
