"""Design a body for its odds: :func:`design`, the odds of one body (:func:`odds`), the independent
re-simulation of a design (:func:`resimulate`) and the figure of each probability against a parameter.

The toss models are in :data:`MODELS` (one module each: :mod:`.drop`, :mod:`.flip`, :mod:`.bounce`,
:mod:`.bounce3d`), the solvers in :mod:`.solvers`.  A planar family is tossed by drop, flip or bounce; a
cylinder by drop, flip (about a diameter) or bounce3d.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from coinwall.forward.display import json_number, safe_repr
from coinwall.forward.errors import InvalidArgument

from .bounce import Bounce
from .bounce3d import Bounce3D
from .drop import Drop
from .family import Family, outcome_names, planar_valleys
from .flip import Flip
from .solvers import (
    Ensemble,
    exact_least_squares,
    exact_root,
    stochastic_least_squares,
    stochastic_root,
    z_value,
)

__all__ = ["MODELS", "Design", "Resimulation", "design", "design_curves", "odds", "plot_design", "resimulate"]

#: model name -> class, and the families each tosses
MODELS = {"drop": Drop, "flip": Flip, "bounce": Bounce, "bounce3d": Bounce3D}
_KINDS = {"drop": ("planar", "cylinder"), "flip": ("planar", "cylinder"), "bounce": ("planar",),
          "bounce3d": ("cylinder",)}
#: the undecided share above which a Monte Carlo design carries a warning
UNDECIDED_WARNING = 0.01


def _check(family, model):
    if not isinstance(family, Family):
        raise InvalidArgument(f"`family` must be a Family, got {type(family).__name__}")
    if not any(isinstance(model, cls) for cls in MODELS.values()):
        raise InvalidArgument(f"`model` must be one of the toss models {', '.join(MODELS)}, got {model!r}")
    if family.kind not in _KINDS[model.name]:
        other = "bounce3d" if model.name == "bounce" else "bounce"
        raise InvalidArgument(f"the {model.name} toss does not apply to a {family.kind} family (use {other})")


def default_names(family, x) -> list:
    """The outcomes reported by default at ``x``: heads, tails, edge, or every face (:func:`.family.outcome_names`).

    Examples
    --------
    >>> default_names(Family("cylinder", None, {}, {"thickness": 1.0}), [])
    ['heads', 'edge', 'tails']
    """
    if family.kind == "cylinder":
        return ["heads", "edge", "tails"]
    return outcome_names(planar_valleys(family.body(x)), "planar")


@dataclass(frozen=True, repr=False)
class Design:
    """A designed body: the free parameters ``x`` with their ``half_widths`` (the interval is x ± half-width at
    the ``confidence``), and the odds at ``x``: ``probabilities[name] = (p, half-width)``.

    Attributes
    ----------
    family : Family
    model : object
        The toss model (:data:`MODELS`).
    targets : dict
        ``name -> target probability``.
    x, half_widths : ndarray (k,)
    probabilities : dict
        ``name -> (p, half-width)`` (half-width 0 for an exact model).
    undecided : tuple or None
        ``(share, half-width)`` of the tosses that did not come to rest (Monte Carlo models).
    tosses : int
        Launches behind ``probabilities`` (0 for an exact model); ``total_tosses`` all the solver ran.
    method : str
        The solver (:mod:`.solvers`).
    residual : float
        The largest difference ``|P − target|`` at ``x``.
    roots : list
        Every parameter value that reaches the target (one free parameter, exact model).
    warnings : list of str

    Examples
    --------
    >>> fam = Family("cylinder", None, {"thickness": (0.1, 3.0)})
    >>> found = design(fam, {"edge": 1 / 3}, Drop())
    >>> round(float(found.x[0]), 10), found.to_dict()["parameters"]["thickness"]["range"]
    (0.7071067812, [0.1, 3.0])
    """

    family: Family
    model: object
    targets: dict
    x: np.ndarray
    half_widths: np.ndarray
    probabilities: dict
    undecided: tuple | None
    tosses: int
    total_tosses: int
    method: str
    residual: float
    confidence: float
    seed: object
    roots: list = field(default_factory=list)
    warnings: list = field(default_factory=list)

    @property
    def interval(self) -> np.ndarray:
        """``(k, 2)``: the interval of each free parameter."""
        return np.column_stack([self.x - self.half_widths, self.x + self.half_widths])

    @property
    def values(self) -> dict:
        """Every parameter's value at the design point."""
        return self.family.values(self.x)

    def body(self):
        """The designed body (a Wall or a Revolution)."""
        return self.family.body(self.x)

    def to_dict(self) -> dict:
        params = {name: {"value": float(v), "interval": [float(a), float(b)], "range": list(self.family.free[name])}
                  for name, v, (a, b) in zip(self.family.names, self.x, self.interval)}
        outcomes = {}
        for name, (p, h) in self.probabilities.items():
            row = {"p": json_number(p), "interval": [json_number(max(0.0, p - h)), json_number(min(1.0, p + h))]}
            if name in self.targets:
                row["target"] = self.targets[name]
            outcomes[name] = row
        undecided = None
        if self.undecided is not None:
            p, h = self.undecided
            undecided = {"p": p, "interval": [max(0.0, p - h), min(1.0, p + h)]}
        return {"family": self.family.to_dict(), "model": self.model.to_dict(), "targets": dict(self.targets),
                "parameters": params, "fixed": dict(self.family.fixed), "outcomes": outcomes,
                "undecided": undecided, "confidence": self.confidence, "tosses": self.tosses,
                "total_tosses": self.total_tosses, "method": self.method, "residual": json_number(self.residual),
                "roots": list(self.roots), "seed": self.seed if self.tosses else None,
                "warnings": list(self.warnings)}

    @safe_repr
    def __repr__(self):
        params = ", ".join(f"{k} = {v:.10g} ± {h:.2g}" for k, v, h in zip(self.family.names, self.x, self.half_widths))
        odds_ = ", ".join(f"{k} {p:.6g}" + (f" ± {h:.2g}" if h else "") for k, (p, h) in self.probabilities.items())
        return f"Design({self.model.name}: {params}; {odds_})"


def _targets(targets) -> dict:
    try:
        items = dict(targets)
    except (TypeError, ValueError):
        raise InvalidArgument(f"`targets` must map outcome names to probabilities, got {targets!r}") from None
    if not items:
        raise InvalidArgument("`targets` is empty: name at least one outcome and its probability")
    out = {}
    for name, p in items.items():
        p = float(p)
        if not 0.0 < p < 1.0:
            raise InvalidArgument(f"the target probability of {name!r} must be between 0 and 1, got {p:g}")
        out[str(name)] = p
    return out


def design(family: Family, targets, model, *, tolerance: float = 0.005, confidence: float = 0.95, seed=0,
           max_tosses: int = 10_000_000, progress=None) -> Design:
    """The free parameters of ``family`` for which the toss ``model`` has the ``targets`` odds.

    Parameters
    ----------
    family : Family
    targets : dict
        ``name -> probability`` (heads, tails, edge, face@DEG: :mod:`.family`).
    model : Drop, Flip, Bounce or Bounce3D
    tolerance : float
        Monte Carlo models: the half-width (at ``confidence``) to which each target probability is resolved.
    confidence : float
        Of every interval reported.
    seed : int or None
        Of the Monte Carlo launches (None: fresh entropy, reported in the result).
    max_tosses : int
        Monte Carlo: the most launches per evaluation; the result warns when ``tolerance`` was not reached.
    progress : callable, optional
        Called with the number of launches simulated after each chunk.

    Returns
    -------
    Design

    Raises
    ------
    InvalidArgument
        A target that is not reached in the range, an unknown outcome, a model that does not toss this family.

    Examples
    --------
    >>> fam = Family("planar", "abs(cos(t)) + h*abs(sin(t))", {"h": (0.05, 3.0)})
    >>> d = design(fam, {"edge": 1 / 3}, Drop())
    >>> bool(abs(d.x[0] - math.tan(math.pi / 6)) < 1e-10)
    True
    """
    _check(family, model)
    targets = _targets(targets)
    if not family.free:
        raise InvalidArgument("the family has no free parameter (give one as NAME=LO:HI)")
    tolerance = float(tolerance)
    if not 1e-5 <= tolerance <= 0.2:
        raise InvalidArgument(f"`tolerance` must be between 1e-5 and 0.2 (a probability), got {tolerance!r}")
    z = z_value(float(confidence))
    mid = family.bounds.mean(axis=1)
    names = list(dict.fromkeys(list(targets) + default_names(family, mid)))
    bounds = family.bounds
    warnings = []
    roots = []
    if model.exact:
        def at(x):
            return model.odds(family.kind, family.body(x), list(targets))

        if len(targets) == 1 and len(family.free) == 1:
            name, t = next(iter(targets.items()))
            roots, intervals, _ = exact_root(lambda s: at([s])[name], bounds[0, 0], bounds[0, 1], t)
            x = np.array([roots[0]])
            half = np.array([0.5 * (intervals[0][1] - intervals[0][0])])
            method = "brentq (exact model)"
            if len(roots) > 1:
                warnings.append(f"{len(roots)} parameter values reach the target: "
                                + ", ".join(f"{r:.10g}" for r in roots) + "; the design is the first")
        else:
            tnames = list(targets)
            tvec = np.array([targets[k] for k in tnames])
            x, half, _ = exact_least_squares(lambda v: np.array([at(v)[k] for k in tnames]) - tvec, bounds)
            method = "least squares (exact model)"
        found = model.odds(family.kind, family.body(x), names)
        probabilities = {k: (found[k], 0.0) for k in names}
        residual = max(abs(found[k] - t) for k, t in targets.items())
        if residual > 1e-9:
            warnings.append(f"the targets are not all reached: the largest |P − target| is {residual:.3g}")
        return Design(family, model, targets, x, half, probabilities, None, 0, 0, method, residual,
                      float(confidence), None, roots, warnings)
    max_tosses = int(max_tosses)
    if max_tosses < 1000:
        raise InvalidArgument(f"`max_tosses` must be at least 1000, got {max_tosses}")
    ensemble = Ensemble(model, family, names, seed=seed, progress=progress)
    if len(targets) == 1 and len(family.free) == 1:
        name, t = next(iter(targets.items()))
        found = stochastic_root(ensemble, name, t, bounds[0, 0], bounds[0, 1], tol=tolerance, z=z,
                                max_tosses=max_tosses)
        method = "stochastic root finding with common random numbers"
    else:
        found = stochastic_least_squares(ensemble, targets, bounds, tol=tolerance, z=z, max_tosses=max_tosses)
        method = "weighted least squares with common random numbers"
    est = found.estimate
    warnings += list(found.notes)
    probabilities = {k: (est.p(k), z * est.se(k)) for k in names}
    share = est.undecided
    undecided = (share, z * math.sqrt(share * (1 - share) / est.n))
    residual = max(abs(est.p(k) - t) for k, t in targets.items())
    if not found.reached:
        warnings.append(f"the tolerance {tolerance:g} was not reached within {max_tosses} tosses per evaluation: "
                        f"the intervals are wider")
    if share > UNDECIDED_WARNING:
        warnings.append(f"{100 * share:.3g}% of the tosses did not come to rest (they slide on the frictionless floor "
                        "above their barrier, or bounce past the impact budget): the odds are those of the tosses "
                        "that did")
    worst = max(z * est.se(k) for k in targets)
    if residual > 2 * max(worst, tolerance):
        warnings.append(f"the targets are not all reached: the largest |P − target| is {residual:.3g} "
                        f"(resolution {worst:.3g})")
    return Design(family, model, targets, found.x, found.half_widths, probabilities, undecided, est.n,
                  ensemble.tosses, method, residual, float(confidence), ensemble.seed, [], warnings)


def odds(family: Family, model, x=None, *, names=None, tosses: int = 100_000, confidence: float = 0.95, seed=0,
         progress=None) -> dict:
    """The odds of one member of ``family`` (at ``x``; by default its only member, without free parameters).

    Parameters
    ----------
    family : Family
    model : Drop, Flip, Bounce or Bounce3D
    x : sequence of float, optional
        The free values (none for a family without free parameters).
    names : list of str, optional
        The outcomes (default :func:`default_names`).
    tosses, confidence, seed, progress
        Of a Monte Carlo model: launches, the confidence of the half-widths, the seed, a callback.

    Returns
    -------
    dict
        ``name -> (p, half-width)`` (half-width 0 for an exact model) and, for a Monte Carlo model,
        ``"undecided"``: the share of the tosses that did not come to rest (the others' odds are among the rest).

    Raises
    ------
    InvalidArgument
        A model that does not toss this family, an unknown outcome.

    Examples
    --------
    >>> fam = Family("cylinder", None, {}, {"thickness": 1.0})
    >>> round(odds(fam, Drop())["edge"][0], 10)
    0.4472135955
    """
    _check(family, model)
    x = [] if x is None else x
    names = list(names) if names else default_names(family, x)
    z = z_value(float(confidence))
    if model.exact:
        found = model.odds(family.kind, family.body(x), names)
        return {k: (found[k], 0.0) for k in names}
    ensemble = Ensemble(model, family, names, seed=seed, progress=progress)
    est = ensemble.evaluate(x, int(tosses))
    out = {k: (est.p(k), z * est.se(k)) for k in names}
    out["undecided"] = (est.undecided, z * math.sqrt(est.undecided * (1 - est.undecided) / est.n))
    return out


@dataclass(frozen=True, repr=False)
class Resimulation:
    """An independent re-simulation of a design at its point: ``probabilities[name] = (p, standard error)`` from
    ``tosses`` fresh launches, and ``z[name]``: the difference from the design's probability in units of the
    two standard errors combined (the design's own is its half-width / z).

    Attributes
    ----------
    probabilities : dict
        ``{outcome: (p, standard error)}`` from the fresh launches.
    z : dict
        ``{outcome: z}``: the difference from the design's probability over the combined standard error.
    tosses : int
        The fresh launches.

    Examples
    --------
    >>> r = Resimulation({"edge": (0.34, 0.002)}, {"edge": 0.5}, 50000)
    >>> r.agrees()
    True
    """

    probabilities: dict
    z: dict
    tosses: int

    def agrees(self, confidence: float = 0.95) -> bool:
        """Every outcome within the combined interval at ``confidence``."""
        return all(abs(v) <= z_value(confidence) for v in self.z.values())

    def to_dict(self) -> dict:
        return {"tosses": self.tosses, "probabilities": {k: {"p": p, "stderr": s} for k, (p, s) in
                                                         self.probabilities.items()}, "z": dict(self.z)}

    @safe_repr
    def __repr__(self):
        parts = ", ".join(f"{k} {p:.5f} ({self.z[k]:+.2f}σ)" for k, (p, _) in self.probabilities.items())
        return f"Resimulation({self.tosses} tosses: {parts})"


def resimulate(result: Design, tosses: int = 100_000, seed=None, progress=None) -> Resimulation:
    """Toss the designed body ``tosses`` times with launches independent of the design's (the model's own random
    toss; the exact drop model is drawn at random) and compare each outcome with the design.

    Parameters
    ----------
    result : Design
    tosses : int
    seed : int or None
        Of the independent launches (a stream apart from the design's for the same seed).
    progress : callable, optional

    Returns
    -------
    Resimulation

    Raises
    ------
    InvalidArgument
        A model that has no random toss (flip).

    Examples
    --------
    >>> found = design(Family("cylinder", None, {"thickness": (0.1, 3.0)}), {"edge": 1 / 3}, Drop())
    >>> resimulate(found, 20000, seed=1).agrees(0.999)
    True
    """
    model = result.model
    if not hasattr(model, "simulate"):
        raise InvalidArgument(f"the {model.name} toss has no random counterpart to re-simulate")
    z = z_value(result.confidence)
    names = list(result.probabilities)
    entropy = np.random.SeedSequence(seed).entropy
    ensemble = Ensemble(model, result.family, names, seed=entropy, stream=1, progress=progress)
    est = ensemble.evaluate(result.x, int(tosses))
    probs = {k: (est.p(k), est.se(k)) for k in names}
    score = {}
    for k in names:
        p0, h0 = result.probabilities[k]
        spread = math.hypot(h0 / z, est.se(k))
        score[k] = (est.p(k) - p0) / spread if spread > 0 else (0.0 if est.p(k) == p0 else math.inf)
    return Resimulation(probs, score, int(tosses))


def design_curves(result: Design, points: int = 41, tosses: int = 8192, progress=None) -> list:
    """For each free parameter: ``(name, xs, {outcome: (p, half-width) arrays})`` over its range, the others at the
    design point (exact models: exact; Monte Carlo: ``tosses`` launches per point, common random numbers).

    Parameters
    ----------
    result : Design
    points : int
        Values of each parameter.
    tosses : int
        Monte Carlo: launches per value.
    progress : callable, optional

    Returns
    -------
    list of tuple
        A member without one of the outcomes (no heads and tails) is a gap (nan).

    Examples
    --------
    >>> found = design(Family("cylinder", None, {"thickness": (0.1, 3.0)}), {"edge": 1 / 3}, Drop())
    >>> name, xs, rows = design_curves(found, points=3)[0]
    >>> name, [round(float(p), 6) for p in rows["edge"][0]]
    ('thickness', [0.049938, 0.612572, 0.83205])
    """
    fam, model = result.family, result.model
    z = z_value(result.confidence)
    names = list(result.probabilities)
    curves = []
    ensemble = None if model.exact else Ensemble(model, fam, names, seed=result.seed, progress=progress)
    for i, name in enumerate(fam.names):
        lo, hi = fam.free[name]
        xs = np.linspace(lo, hi, points)
        rows = {k: ([], []) for k in names}
        for value in xs:
            x = result.x.copy()
            x[i] = value
            try:
                if model.exact:
                    got = model.odds(fam.kind, fam.body(x), names)
                    found = {k: (got[k], 0.0) for k in names}
                else:
                    est = ensemble.evaluate(x, tosses)
                    found = {k: (est.p(k), z * est.se(k)) for k in names}
            except InvalidArgument:  # a member without these outcomes (e.g. no heads and tails): a gap
                found = {k: (math.nan, math.nan) for k in names}
            for k in names:
                rows[k][0].append(found[k][0])
                rows[k][1].append(found[k][1])
        curves.append((name, xs, {k: (np.array(p), np.array(h)) for k, (p, h) in rows.items()}))
    return curves


def plot_design(result: Design, curves):
    """One panel per free parameter: each outcome's probability against it (band: the interval of a Monte Carlo
    model), the targets dashed, the design point with its intervals.

    Parameters
    ----------
    result : Design
    curves : list
        :func:`design_curves` of ``result``.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> found = design(Family("cylinder", None, {"thickness": (0.1, 3.0)}), {"edge": 1 / 3}, Drop())
    >>> len(plot_design(found, design_curves(found, points=5)).axes)
    1
    """
    from coinwall.forward.formats.figure import new_figure

    k = len(curves)
    fig, axes = new_figure(1, k, figsize=(6.2 * k, 4.4), constrained_layout=True, squeeze=False)
    for ax, (name, xs, rows), x, h in zip(axes[0], curves, result.x, result.half_widths):
        for j, (outcome, (p, half)) in enumerate(rows.items()):
            colour = f"C{j}"
            ax.plot(xs, p, "-", color=colour, lw=1.4, label=f"P({outcome})")
            if np.any(half > 0):
                ax.fill_between(xs, p - half, p + half, color=colour, alpha=0.2, lw=0)
            if outcome in result.targets:
                ax.axhline(result.targets[outcome], color=colour, ls="--", lw=0.9)
                pd, hd = result.probabilities[outcome]
                ax.errorbar([x], [pd], xerr=[[h]], yerr=[[hd]], fmt="o", color=colour, ms=5, capsize=3)
        ax.axvspan(x - h, x + h, color="0.6", alpha=0.25, lw=0)
        ax.axvline(x, color="0.3", lw=0.8)
        ax.set_xlabel(f"{name} (design {x:.6g} ± {h:.2g})")
        ax.set_ylabel("probability")
        ax.set_ylim(-0.02, 1.02)
        ax.legend(fontsize=8)
    where = result.family.describe()
    friction = f" on a floor with friction μ = {result.model.mu:g}" if getattr(result.model, "mu", 0.0) else ""
    fig.suptitle(f"{result.model.name} toss{friction}: {where}", fontsize=9)
    return fig

