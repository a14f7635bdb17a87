"""How a wall is evaluated: a Fourier series (exact derivatives term by term), circle arcs (exact, piece
by piece) and samples (their trigonometric interpolant, made on first use).  :class:`~.wall.Wall` holds
one of these (or the casadi backend of an expression) and is the public face of all of them."""

from __future__ import annotations

import numpy as np

from .angles import TWO_PI
from .errors import InvalidWall

__all__ = ["MAX_HARMONICS", "MAX_LSQ_SAMPLES", "MS_PER_HARMONIC", "_ArcsBackend", "_FourierBackend", "_SampledBackend"]

#: Most non-uniform samples a least-squares interpolant is made of: it costs n·k² (k ≤ 256 harmonics) and
#: 10.4 kB per sample (tracemalloc); 2·10⁴ keeps a solve near ten seconds on two idle cores
#: (tests/benchmarks/bench_dense_data.py).  More samples are solved from their lines (exact for the data).
MAX_LSQ_SAMPLES = 20_000
#: Largest Fourier wall (harmonics).  Every evaluation costs harmonics × angles, and the wall checks and
#: `critical` evaluate on tens of thousands of angles: `coinwall critical f.json` costs about
#: :data:`MS_PER_HARMONIC` ms per harmonic, half a minute at this bound (10^5 harmonics would take minutes).
MAX_HARMONICS = 10_000
MS_PER_HARMONIC = 3.3


class _FourierBackend:
    """b(θ) = a0 + Σ_k (a_k cos kθ + s_k sin kθ), derivatives term by term (exact)."""

    def __init__(self, a0: float, cos: np.ndarray, sin: np.ndarray):
        n = max(len(cos), len(sin))
        self.a0 = float(a0)
        self.cos = np.zeros(n)
        self.sin = np.zeros(n)
        self.cos[: len(cos)] = cos
        self.sin[: len(sin)] = sin
        self.k = np.arange(1, n + 1, dtype=float)

    def _eval(self, theta, orders):
        theta = np.asarray(theta, dtype=float).ravel()
        out = {o: np.zeros(theta.size) for o in orders}
        if 0 in out:
            out[0] += self.a0
        # chunk the outer product so memory stays bounded for long series
        step = max(1, 2_000_000 // max(1, self.k.size))
        for start in range(0, theta.size, step):
            th = theta[start:start + step]
            arg = np.outer(th, self.k)
            c, s = np.cos(arg), np.sin(arg)
            for o in orders:
                kp = self.k**o
                # d^o/dθ^o of cos kθ and sin kθ cycle with period 4 in o
                cc = (c, -s, -c, s)[o % 4]
                ss = (s, c, -s, -c)[o % 4]
                out[o][start:start + step] += cc @ (self.cos * kp) + ss @ (self.sin * kp)
        return [out[o] for o in orders]

    def values(self, theta):
        return self._eval(theta, (0,))[0]

    def derivatives(self, theta):
        return tuple(self._eval(theta, (0, 1, 2)))

    def switching(self, theta):
        return []


class _ArcsBackend:
    """``h(θ) = c_k·n(θ) + r_k`` for θ in ``[a_k, a_{k+1})``: the support function of a convex body
    bounded by circle arcs (radius ``r_k`` about ``c_k``; ``r_k = 0`` is a vertex, whose window of
    normals is ``[a_k, a_{k+1})``) and straight edges (where two pieces meet with different slopes).
    Exact, piece by piece; b'' jumps at every break, which no finite Fourier series can represent."""

    def __init__(self, angles, centres, radii):
        self.angles = angles
        self.centres = centres
        self.radii = radii

    def _piece(self, theta):
        reduced = np.mod(theta, TWO_PI)
        return np.searchsorted(self.angles, reduced, side="right") - 1  # -1 is the last piece (wraps)

    def _eval(self, theta):
        theta = np.asarray(theta, dtype=float).ravel()
        k = self._piece(theta)
        c, s = np.cos(theta), np.sin(theta)
        cx, cy = self.centres[k, 0], self.centres[k, 1]
        return cx * c + cy * s + self.radii[k], -cx * s + cy * c, -cx * c - cy * s

    def values(self, theta):
        return self._eval(theta)[0]

    def derivatives(self, theta):
        return self._eval(theta)

    def switching(self, theta):
        # one function per break, changing sign there only (on [0, 2π])
        theta = np.asarray(theta, dtype=float).ravel()
        return [np.sin(0.5 * (theta - a)) for a in self.angles]


def _interpolant(reduced, values, harmonics, scale) -> _FourierBackend:
    """The trigonometric polynomial through samples: the FFT interpolant of uniform samples
    (``harmonics`` None), or the least-squares fit with ``harmonics`` harmonics."""
    n = reduced.size
    if harmonics is None:
        # trigonometric interpolation; shift the phase so the grid may start anywhere
        spectrum = np.fft.rfft(values) / n
        k = np.arange(spectrum.size)
        spectrum = spectrum * np.exp(-1j * k * reduced[0])
        a0 = spectrum[0].real
        cos = 2 * spectrum[1:].real
        sin = -2 * spectrum[1:].imag
        if n % 2 == 0:  # the Nyquist mode is shared by ±n/2: halve it, and drop its sine part
            cos[-1] /= 2
            sin[-1] = 0.0
        # harmonics below rounding change no value: drop the tail, so that smooth data (whose
        # coefficients decay fast) evaluate as fast as a short series
        size = np.hypot(cos, sin)
        significant = np.flatnonzero(size > 4 * np.finfo(float).eps * scale)
        keep = significant[-1] + 1 if significant.size else 0
        return _FourierBackend(a0, cos[:keep], sin[:keep])
    from .validation import check_memory

    if n > MAX_LSQ_SAMPLES:
        raise InvalidWall(f"samples: {n} non-uniform samples; their least-squares interpolant (needed between the "
                          f"samples, e.g. to simulate) takes at most {MAX_LSQ_SAMPLES} (it costs n·k² with "
                          f"k = {harmonics} harmonics): thin the samples or give them on a uniform grid")
    # the design matrix and lstsq's copies of it: 10.4 kB per sample measured at 3e4 samples, 256 harmonics
    check_memory(f"a least-squares interpolant of {n} non-uniform samples with {harmonics} harmonics "
                 f"({20 * (2 * harmonics + 1)} bytes per sample)", 20.0 * n * (2 * harmonics + 1), error=InvalidWall)
    kk = np.arange(1, harmonics + 1)
    arg = np.outer(reduced, kk)
    design = np.hstack([np.ones((n, 1)), np.cos(arg), np.sin(arg)])
    coef, *_ = np.linalg.lstsq(design, values, rcond=None)
    return _FourierBackend(coef[0], coef[1:harmonics + 1], coef[harmonics + 1:])


class _SampledBackend:
    """The interpolant of samples, made on first use (see :func:`_interpolant`); picklable."""

    def __init__(self, reduced, values, harmonics, scale, factor: float = 1.0):
        self._args = (reduced, values, harmonics, scale)
        self.factor = factor  # Wall.scaled: the interpolant's coefficients times this
        self._fourier = None

    def scaled(self, factor: float) -> _SampledBackend:
        return _SampledBackend(*self._args, factor=self.factor * factor)

    @property
    def fourier(self) -> _FourierBackend:
        if self._fourier is None:
            made = _interpolant(*self._args)
            if self.factor != 1.0:
                made = _FourierBackend(made.a0 * self.factor, made.cos * self.factor, made.sin * self.factor)
            self._fourier = made
        return self._fourier

    # the coefficients, as the kernel's code generator and Wall.scaled read them
    a0 = property(lambda self: self.fourier.a0)
    cos = property(lambda self: self.fourier.cos)
    sin = property(lambda self: self.fourier.sin)
    k = property(lambda self: self.fourier.k)

    def values(self, theta):
        return self.fourier.values(theta)

    def derivatives(self, theta):
        return self.fourier.derivatives(theta)

    def switching(self, theta):
        return []
