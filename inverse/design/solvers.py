"""The solvers of a design: which free parameters give the target odds.

* **Exact models, one parameter, one target**: the target's probability P(x) is scanned on 33 points of the
  range for sign changes of P − target, each is refined by Brent's method to 1e-13 (relative to the range),
  and the root is certified by a sign change across ``x ± 1e-10·max(1, |x|)``: the reported interval.  Several
  roots are all reported (the first is the design); none is an error naming the range of P.
* **Exact models, several targets or parameters**: weighted least squares of P_i(x) − target_i (scipy's
  ``least_squares``, trust region in the box, from the centre and 8 seeded points), polished by Gauss–Newton;
  the interval is ±(the last Gauss–Newton correction + 1e-10·range).
* **Monte Carlo models, one parameter, one target**: sample-average approximation with common random numbers.
  With the same N launches for every x, P̂_N(x) is a deterministic (piecewise constant) function, and its
  crossing of the target is found by bisection, to a tenth of the statistical width.  The standard error at
  the crossing is ``se = √(t(1 − t)/N_decided)``, the slope P' a common-random-number central difference over
  ± twice the parameter's half-width, and the parameter's interval ``x̂ ± z·se/|P'|`` (z of the confidence).
  Stopping rule: N grows (×(z·se/tol)², at least ×2) until ``z·se ≤ tol``, the next stage bisecting only
  within ±3 half-widths of the last crossing (wider when that does not bracket).
* **Monte Carlo models, several targets or parameters**: Gauss–Newton on the weighted residuals
  (weights 1/var of each P̂), the Jacobian by common-random-number central differences, steps damped to
  lower the weighted residual; N grows until every target's ``z·se ≤ tol``.  The parameters' covariance is the
  sandwich ``A Σ Aᵀ`` with ``A = (JᵀWJ)⁻¹JᵀW`` and Σ the covariance of the outcome indicators over N.

Probabilities of a Monte Carlo model are shares of the *decided* tosses (undecided ones are reported apart).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.errors import InvalidArgument

__all__ = ["Ensemble", "Estimate", "exact_least_squares", "exact_root", "stochastic_least_squares",
           "stochastic_root", "z_value"]

_SCAN = 33
_START = 4096  # launches of a Monte Carlo model's first stage


def z_value(confidence: float) -> float:
    """The two-sided normal quantile of ``confidence`` (1.96 for 0.95)."""
    from scipy.stats import norm

    if not 0.5 <= confidence < 1.0:
        raise InvalidArgument(f"`confidence` must be in [0.5, 1), got {confidence!r}")
    return float(norm.ppf(0.5 + 0.5 * confidence))


@dataclass(frozen=True)
class Estimate:
    """Monte Carlo odds at ``x``: ``hits[name]`` among ``decided`` of ``n`` tosses; ``indicators`` (decided,
    k) the outcome of each decided toss per name, in the order of ``names`` (for covariances)."""

    x: np.ndarray
    n: int
    decided: int
    hits: dict
    indicators: np.ndarray
    names: tuple = ()

    def covariance(self, names) -> np.ndarray:
        """The covariance of the probabilities of ``names`` (the outcome indicators' over ``decided``)."""
        cols = [self.names.index(k) for k in names]
        return np.atleast_2d(np.cov(self.indicators[:, cols].astype(float), rowvar=False)) / self.decided

    def p(self, name) -> float:
        return self.hits[name] / self.decided if self.decided else math.nan

    def se(self, name) -> float:
        p = self.p(name)
        return math.sqrt(max(p * (1 - p), 0.0) / self.decided) if self.decided else math.nan

    @property
    def undecided(self) -> float:
        return 1.0 - self.decided / self.n


class Ensemble:
    """The launches of a Monte Carlo model for one family, drawn block by block from ``seed`` (common random
    numbers: the same first N launches for every parameter value; ``stream`` 1 gives independent ones).

    ``evaluate`` runs the model's toss in chunks of ``chunk`` launches (a progress step, and the longest stretch
    Ctrl-C waits for).
    """

    def __init__(self, model, family, names, seed=0, stream: int = 0, progress=None, chunk: int | None = None):
        self.model, self.family, self.names = model, family, list(names)
        from ...forward.validation import check_seed

        self.seed = np.random.SeedSequence(check_seed(seed)).entropy
        self.stream = int(stream)
        self.progress = progress
        self.chunk = chunk or (512 if model.name == "bounce3d" else 16384)
        self.block = 4096
        self._blocks = []
        self.tosses = 0  # simulated so far (all evaluations)

    def draws(self, n: int) -> np.ndarray:
        while len(self._blocks) * self.block < n:
            seq = np.random.SeedSequence(self.seed, spawn_key=(self.stream, len(self._blocks)))
            self._blocks.append(self.model.draw(np.random.default_rng(seq), self.block))
        return np.concatenate(self._blocks)[:n] if self._blocks else np.zeros((0, self.model.dimensions))

    def evaluate(self, x, n: int) -> Estimate:
        x = np.atleast_1d(np.asarray(x, dtype=float))
        body = self.family.body(x)
        draws = self.draws(n)
        hits = {name: 0 for name in self.names}
        rows, undecided = [], 0
        for lo in range(0, n, self.chunk):
            part = draws[lo:lo + self.chunk]
            got, lost = self.model.simulate(self.family.kind, body, part, self.names, b0=self.family.b0)
            keep = ~np.asarray(lost, dtype=bool)
            for name in self.names:
                hits[name] += int(np.sum(got[name] & keep))
            rows.append(np.column_stack([got[name][keep] for name in self.names]))
            undecided += int(np.sum(~keep))
            self.tosses += part.shape[0]
            if self.progress is not None:
                self.progress(part.shape[0])
        decided = n - undecided
        if decided == 0:
            raise InvalidArgument(f"no toss of the {n} at {self._where(x)} came to rest (every one is undecided)")
        return Estimate(x, n, decided, hits, np.concatenate(rows).astype(bool), tuple(self.names))

    def _where(self, x):
        return ", ".join(f"{k}={v:.6g}" for k, v in zip(self.family.names, x))


# ---------------------------------------------------------------------------------------------------- exact
def exact_root(f, lo: float, hi: float, target: float):
    """Every x in [lo, hi] with f(x) = target (module docstring); returns ``(roots, intervals, scan)``.

    Raises
    ------
    InvalidArgument
        No sign change of f − target on the scan, or a crossing where f jumps over the target.

    Examples
    --------
    >>> roots, intervals, _ = exact_root(lambda x: x * x, 0.0, 2.0, 2.0)
    >>> abs(roots[0] - 2 ** 0.5) < 1e-12
    True
    """
    from scipy.optimize import brentq

    xs = np.linspace(lo, hi, _SCAN)
    fs = np.array([f(x) for x in xs])
    g = fs - target
    cells = [i for i in range(_SCAN - 1) if g[i] == 0 or (g[i] < 0) != (g[i + 1] < 0) and g[i + 1] != 0]
    if g[-1] == 0:
        cells.append(_SCAN - 1)
    if not cells:
        raise InvalidArgument(f"the target {target:.6g} is not reached for {lo:g} <= x <= {hi:g}: the probability "
                              f"ranges from {fs.min():.6g} to {fs.max():.6g} there")
    roots, intervals = [], []
    for i in cells:
        if g[i] == 0:
            x = xs[i]
        else:
            x = brentq(lambda s: f(s) - target, xs[i], xs[i + 1], xtol=1e-13 * max(1.0, abs(lo), abs(hi)),
                       rtol=8.9e-16)
        width = 1e-10 * max(1.0, abs(x))
        a, b = max(lo, x - width), min(hi, x + width)
        fa, fb, fx = f(a) - target, f(b) - target, f(x) - target
        if not (fa == 0 or fb == 0 or (fa < 0) != (fb < 0)):
            raise InvalidArgument(f"the root at x = {x:.12g} is not bracketed by x ± {width:.1e} (f − target "
                                  f"= {fa:.3g}, {fb:.3g})")
        if abs(fx) > 1e-8:
            raise InvalidArgument(f"the probability jumps over the target {target:.6g} at x = {x:.12g} (from "
                                  f"{f(a):.6g} to {f(b):.6g}): no parameter value gives it")
        roots.append(float(x))
        intervals.append((float(a), float(b)))
    return roots, intervals, (xs, fs)


def exact_least_squares(residuals, bounds, seed: int = 0):
    """Minimise ``|residuals(x)|²`` in the box ``bounds`` (k, 2) (module docstring).

    Returns ``(x, half_widths, residual_norm)``.

    Examples
    --------
    >>> x, hw, r = exact_least_squares(lambda x: np.array([x[0] - 0.3, x[1] + x[0] - 1.0]), [[0, 1], [0, 1]])
    >>> np.allclose(x, [0.3, 0.7]), r < 1e-12
    (True, True)
    """
    from scipy.optimize import least_squares

    bounds = np.asarray(bounds, dtype=float).reshape(-1, 2)
    lo, hi = bounds[:, 0], bounds[:, 1]
    rng = np.random.default_rng(seed)
    starts = [0.5 * (lo + hi)] + [lo + (hi - lo) * (0.1 + 0.8 * rng.random(lo.size)) for _ in range(8)]
    best = None
    for x0 in starts:
        sol = least_squares(residuals, x0, bounds=(lo, hi), xtol=1e-15, ftol=1e-15, gtol=1e-15, x_scale="jac")
        if best is None or sol.cost < best.cost:
            best = sol
        if best.cost < 1e-26:
            break
    x = best.x.copy()
    step = np.zeros_like(x)
    for _ in range(5):  # Gauss–Newton polish with a central-difference Jacobian
        r = residuals(x)
        jac = _jacobian(residuals, x, 1e-6 * (hi - lo), lo, hi)
        step = np.linalg.lstsq(jac, -r, rcond=None)[0]
        trial = np.clip(x + step, lo, hi)
        if np.linalg.norm(residuals(trial)) <= np.linalg.norm(r):
            x = trial
        if np.all(np.abs(step) <= 1e-13 * (hi - lo)):
            break
    half = np.abs(step) + 1e-10 * (hi - lo)
    return x, half, float(np.linalg.norm(residuals(x)))


def _jacobian(fun, x, h, lo, hi):
    cols = []
    for i in range(x.size):
        a, b = x.copy(), x.copy()
        a[i] = max(lo[i], x[i] - h[i])
        b[i] = min(hi[i], x[i] + h[i])
        cols.append((fun(b) - fun(a)) / (b[i] - a[i]))
    return np.column_stack(cols)


# ---------------------------------------------------------------------------------------------------- Monte Carlo
@dataclass(frozen=True)
class StochasticResult:
    """What a Monte Carlo solver found: the parameters ``x`` with ``half_widths``, the odds ``estimate`` at
    ``x`` (N launches), the Jacobian, the stages' evaluations, whether ``tol`` was reached, and ``notes``."""

    x: np.ndarray
    half_widths: np.ndarray
    estimate: Estimate
    jacobian: np.ndarray
    history: list
    reached: bool
    notes: tuple = ()


def _grow(n, se, tol, z, limit):
    want = int(math.ceil(n * (z * se / tol) ** 2 * 1.1))
    return int(min(limit, max(2 * n, want)))


def stochastic_root(ensemble: Ensemble, name: str, target: float, lo: float, hi: float, *, tol: float, z: float,
                    max_tosses: int) -> StochasticResult:
    """The parameter at which ``name`` has probability ``target`` (module docstring)."""
    n = min(_START, max_tosses)
    history = []

    def at(x, n):
        est = ensemble.evaluate([x], n)
        history.append((float(x), n, est.p(name), est.se(name)))
        return est

    xs = np.linspace(lo, hi, 9)
    ps = np.array([at(x, n).p(name) for x in xs])
    cross = np.flatnonzero(np.sign(ps[:-1] - target) * np.sign(ps[1:] - target) <= 0)
    if cross.size == 0:
        raise InvalidArgument(f"the target P({name}) = {target:.6g} is not reached for {lo:g} <= x <= {hi:g}: "
                              f"with {n} tosses it ranges from {ps.min():.4g} to {ps.max():.4g} there")
    a, b = xs[cross[0]], xs[cross[0] + 1]
    slope = (ps[cross[0] + 1] - ps[cross[0]]) / (b - a)
    notes = ()
    if cross.size > 1:
        where = ", ".join(f"{0.5 * (xs[i] + xs[i + 1]):.4g}" for i in cross)
        notes = (f"P({name}) crosses the target more than once in the range (near {where}, {n} tosses each): "
                 "the design is the first crossing",)
    while True:
        fa, fb = at(a, n).p(name) - target, at(b, n).p(name) - target
        widen = 0
        while fa * fb > 0 and widen < 8:  # the last stage's window does not bracket with the new launches
            span = b - a
            a, b = max(lo, a - span), min(hi, b + span)
            fa, fb = at(a, n).p(name) - target, at(b, n).p(name) - target
            widen += 1
        if fa * fb > 0:
            raise InvalidArgument(f"P({name}) = {target:.6g} is not bracketed near x = {0.5 * (a + b):.6g} with {n} "
                                  "tosses: the probability may not cross the target there")
        se = math.sqrt(target * (1 - target) / max(1, n))
        half = z * se / max(abs(slope), 1e-300)
        while b - a > max(0.1 * half, 1e-12 * (hi - lo)):  # (a jump of P: the width floors at rounding)
            m = 0.5 * (a + b)
            fm = at(m, n).p(name) - target
            if fm == 0:
                a = b = m
                break
            if (fm < 0) == (fa < 0):
                a, fa = m, fm
            else:
                b, fb = m, fm
        x = a + (b - a) * fa / (fa - fb) if fa != fb else 0.5 * (a + b)  # the crossing, linearly
        est = at(x, n)
        se = math.sqrt(target * (1 - target) / est.decided)
        delta = max(2.0 * half, 1e-9 * (hi - lo))
        xm, xp = max(lo, x - delta), min(hi, x + delta)
        slope = (at(xp, n).p(name) - at(xm, n).p(name)) / (xp - xm)
        if slope == 0:
            raise InvalidArgument(f"P({name}) does not change with the parameter near x = {x:.6g} ({n} tosses): the "
                                  "design is not determined")
        half = z * se / abs(slope) + (b - a)
        if z * se <= tol or n >= max_tosses:
            return StochasticResult(np.array([x]), np.array([half]), est, np.array([[slope]]), history,
                                    z * se <= tol, notes)
        n = _grow(n, se, tol, z, max_tosses)
        a, b = max(lo, x - 3 * half), min(hi, x + 3 * half)


def stochastic_least_squares(ensemble: Ensemble, targets: dict, bounds, *, tol: float, z: float,
                             max_tosses: int) -> StochasticResult:
    """Free parameters whose odds match ``targets`` in weighted least squares (module docstring)."""
    bounds = np.asarray(bounds, dtype=float).reshape(-1, 2)
    lo, hi = bounds[:, 0], bounds[:, 1]
    names = list(targets)
    t = np.array([targets[k] for k in names])
    n = min(_START, max_tosses)
    x = 0.5 * (lo + hi)
    step = 0.05 * (hi - lo)
    history = []

    def at(x, n):
        est = ensemble.evaluate(x, n)
        history.append((x.tolist(), n, [est.p(k) for k in names], [est.se(k) for k in names]))
        return est

    def weighted(est):
        p = np.array([est.p(k) for k in names])
        var = np.maximum(p * (1 - p), 1.0 / est.decided) / est.decided
        return p - t, 1.0 / var

    while True:
        est = at(x, n)
        for _ in range(25):
            r, w = weighted(est)
            jac = np.column_stack([_difference(at, x, i, step[i], lo, hi, n, names) for i in range(x.size)])
            sw = np.sqrt(w)
            delta = np.linalg.lstsq(sw[:, None] * jac, -sw * r, rcond=None)[0]
            cost = float(np.sum(w * r * r))
            for _ in range(6):  # damped: the weighted residual must fall
                trial = np.clip(x + delta, lo, hi)
                trial_est = at(trial, n)
                tr, _ = weighted(trial_est)
                if float(np.sum(w * tr * tr)) <= cost:
                    break
                delta = 0.5 * delta
            else:
                trial, trial_est = x, est
            moved = np.abs(trial - x)
            x, est = trial, trial_est
            cov = _covariance(est, names, jac, w)
            half = z * np.sqrt(np.maximum(np.diag(cov), 0.0))
            step = np.clip(2.0 * half, 1e-6 * (hi - lo), 0.05 * (hi - lo))
            if np.all(moved <= 0.2 * np.maximum(half, 1e-12 * (hi - lo))):
                break
        worst = max(est.se(k) for k in names)
        if z * worst <= tol or n >= max_tosses:
            return StochasticResult(x, half, est, jac, history, z * worst <= tol)
        n = _grow(n, worst, tol, z, max_tosses)


def _difference(at, x, i, h, lo, hi, n, names):
    a, b = x.copy(), x.copy()
    a[i] = max(lo[i], x[i] - h)
    b[i] = min(hi[i], x[i] + h)
    ea, eb = at(a, n), at(b, n)
    return (np.array([eb.p(k) for k in names]) - np.array([ea.p(k) for k in names])) / (b[i] - a[i])


def _covariance(est, names, jac, w):
    """The sandwich covariance of the parameters (module docstring)."""
    sigma = est.covariance(names)
    jw = jac.T * w
    a = np.linalg.pinv(jw @ jac) @ jw
    return a @ sigma @ a.T
