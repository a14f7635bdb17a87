"""Shared by the benchmark scripts: a log to stderr and a clock of the time spent in the compiled kernels."""

from __future__ import annotations

import sys
import time

from coinwall.forward.dynamics.billiard.kernel import CompiledKernel


def log(*text):
    print(*text, file=sys.stderr, flush=True)


class KernelClock:
    """Sums the seconds spent in the compiled kernel functions while active."""

    def __enter__(self):
        self.seconds = 0.0
        self.original = CompiledKernel.call
        clock = self

        def timed(kernel, name, *args):
            start = time.perf_counter()
            try:
                return clock.original(kernel, name, *args)
            finally:
                clock.seconds += time.perf_counter() - start

        CompiledKernel.call = timed
        return self

    def __exit__(self, *exc):
        CompiledKernel.call = self.original
