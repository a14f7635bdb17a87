"""What a scan computes in one cell: pure, seeded functions of (table, options, seed) → numbers, one per quantity.

Each :class:`Quantity` names its variables (with units, for the store), its options (with defaults and
checks) and its cell function.  A cell function builds the table from a :class:`.table.TableSpec` and the
cell's coordinates, runs the library with one thread (the scan's parallelism is one process per core), and
returns a dict of floats.  The same arguments give the same numbers on any worker.

============================ ===================================================================================
``chaotic-fraction``         share of ``orbits`` Liouville-random orbits with λ/collision > 3 ln N/N over N =
                             ``collisions`` (:func:`coinwall.forward.dynamics.analysis.lyapunov.chaotic_fraction`'s numbers)
``lyapunov``                 mean, spread and median of λ over ``orbits`` orbits, per collision and per unit time
``tau``                      the decay time τ of P(n) (:func:`coinwall.forward.dynamics.analysis.correlation.correlation`)
``splitting``                the lowest heads–tails doublet's splitting
                             (:func:`coinwall.forward.quantum.doublet_splitting`); not random
``toss``                     the toss that lands on a floor (:func:`coinwall.forward.dynamics.floor.hand.heads_fraction`):
                             outcome shares under a Gaussian hand about (``v0``, ``omega0``), relative spread
                             ``spread``, launched from the height H (κ), restitution from a ``restitution`` axis;
                             the toss energy level is ``H + (v0² + ω0²)/(2g)``
============================ ===================================================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coinwall.forward.errors import InvalidArgument
from coinwall.forward.validation import check_choice, check_count, check_memory, check_positive, check_seed

__all__ = ["MAX_CELL_WORK", "QUANTITIES", "Quantity", "check_options", "compute_cell", "work_of"]


@dataclass(frozen=True)
class Quantity:
    """One scannable quantity.

    Attributes
    ----------
    name : str
    variables : dict
        Variable name → (units, description), the arrays of the store.
    defaults : dict
        Option name → default value.
    seeded : bool
        Whether the cell function uses its seed.

    Examples
    --------
    >>> from coinwall.cases.scan import QUANTITIES
    >>> sorted(QUANTITIES)
    ['chaotic-fraction', 'lyapunov', 'splitting', 'tau', 'toss']
    >>> QUANTITIES["lyapunov"].defaults
    {'orbits': 20, 'collisions': 2000, 'every': 10, 'device': 'cpu'}
    """

    name: str
    variables: dict
    defaults: dict
    seeded: bool = True


def _exponents(table, orbits, collisions, every, seed, device="cpu"):
    from coinwall.forward.dynamics.analysis.lyapunov import lyapunov_many
    from coinwall.forward.dynamics.billiard.table import random_states

    # the same start states and separation directions as lyapunov.chaotic_fraction(table, orbits, ..., seed)
    states = random_states(table, orbits, seed)
    result = lyapunov_many(table, states, collisions, every, seed=seed, workers=1, device=device)
    return result.per_collision, result.per_time, result.collisions


def _chaotic_fraction(table, seed, orbits, collisions, every, threshold, device):
    from coinwall.forward.dynamics.analysis.lyapunov import default_threshold

    per_collision, _, _ = _exponents(table, orbits, collisions, every, seed, device)
    lam = per_collision[np.isfinite(per_collision)]
    limit = default_threshold(collisions) if threshold is None else threshold
    n = int(lam.size)
    chaotic = int(np.count_nonzero(lam > limit))
    fraction = chaotic / n if n else math.nan
    return {"chaotic_fraction": fraction,
            "chaotic_fraction_stderr": math.sqrt(fraction * (1 - fraction) / n) if n else math.nan,
            "regular_orbits": float(n - chaotic), "orbits_used": float(n)}


def _lyapunov(table, seed, orbits, collisions, every, device):
    per_collision, per_time, _ = _exponents(table, orbits, collisions, every, seed, device)
    ok = np.isfinite(per_collision)
    n = int(np.count_nonzero(ok))

    def spread(v):
        return float(np.std(v, ddof=1) / math.sqrt(v.size)) if v.size > 1 else math.nan

    pc, pt = per_collision[ok], per_time[ok]
    return {"lambda_collision": float(pc.mean()) if n else math.nan, "lambda_collision_stderr": spread(pc),
            "lambda_collision_median": float(np.median(pc)) if n else math.nan,
            "lambda_time": float(pt.mean()) if n else math.nan, "lambda_time_stderr": spread(pt),
            "orbits_used": float(n)}


def _tau(table, seed, bounces, max_lag, orbits, count, device):
    from coinwall.forward.dynamics.analysis.correlation import correlation

    result = correlation(table, bounces, max_lag, orbits=orbits, count=count, seed=seed, workers=1, device=device)
    return {"tau": result.tau, "tau_stderr": result.tau_stderr, "P1": float(result.P[1]),
            "P1_stderr": float(result.P_stderr[1]), "n_needed_fit": result.n_needed_fit}


def _splitting(table, seed, pair, cells, order):
    from coinwall.forward.quantum import doublet_splitting

    s = doublet_splitting(table.wall, table.H, table.b0, pair=pair, cells=cells, order=order)
    return {"splitting": s.direct, "splitting_flux": s.flux, "direct_trusted": float(s.direct_trusted),
            "flux_trusted": float(s.flux_trusted), "lambda_lower": s.lower, "wkb_action": s.action,
            "neck_width": s.gap}


def _toss(table_spec, values, H, seed, tosses, g, v0, omega0, spread, impacts, device):
    from coinwall.forward.dynamics.floor.toss import UNDECIDED, _outcomes, launch_states

    table = table_spec.field_table_at(values, g)
    kappa = 1.0 if table_spec.kappa is None else float(table_spec.kappa)
    height = float(H) / kappa
    # the draws of dynamics.toss.heads_fraction (same seed, same order), with the bounces kept
    rng = np.random.default_rng(check_seed(seed))
    v = rng.normal(v0, spread * abs(v0), tosses)
    w = rng.normal(omega0, spread * abs(omega0), tosses)
    outcome, bounces, _ = _outcomes(table, launch_states(table, v, w, height), impacts, False, 1, None, device=device)
    names = table.landscape.names
    heads_k = names.index("heads") if "heads" in names else 0
    heads = float(np.mean(outcome == heads_k))
    undecided = float(np.mean(outcome == UNDECIDED))
    tails = 1.0 - heads - undecided
    decided = outcome != UNDECIDED
    n = int(decided.sum())
    p = heads * tosses / n if n else math.nan
    return {"heads": heads, "heads_stderr": math.sqrt(heads * (1 - heads) / tosses), "tails": tails,
            "undecided": undecided, "bias": p - 0.5, "bias_stderr": math.sqrt(p * (1 - p) / n) if n else math.nan,
            "mean_bounces": float(bounces[decided].mean()) if n else math.nan,
            "level": height + (v0 * v0 + omega0 * omega0) / (2.0 * g)}


_FUNCTIONS = {"chaotic-fraction": _chaotic_fraction, "lyapunov": _lyapunov, "tau": _tau, "splitting": _splitting}
#: quantities whose cell function builds its own table from (table spec, values, H)
_OWN_TABLE = {"toss": _toss}

QUANTITIES = {
    "chaotic-fraction": Quantity(
        "chaotic-fraction",
        {"chaotic_fraction": ("1", "share of the sampled orbits that are chaotic"),
         "chaotic_fraction_stderr": ("1", "binomial standard error sqrt(f(1-f)/n)"),
         "regular_orbits": ("1", "orbits with lambda/collision <= threshold"),
         "orbits_used": ("1", "orbits with a result (orbits that stopped early are left out)")},
        {"orbits": 100, "collisions": 1000, "every": 10, "threshold": None, "device": "cpu"}),
    "lyapunov": Quantity(
        "lyapunov",
        {"lambda_collision": ("1/collision", "mean largest Lyapunov exponent over the orbits"),
         "lambda_collision_stderr": ("1/collision", "standard error of the mean over the orbits"),
         "lambda_collision_median": ("1/collision", "median over the orbits"),
         "lambda_time": ("1/kappa", "mean exponent per unit time (unit speed: per unit path length)"),
         "lambda_time_stderr": ("1/kappa", "standard error of the mean"),
         "orbits_used": ("1", "orbits with a result")},
        {"orbits": 20, "collisions": 2000, "every": 10, "device": "cpu"}),
    "tau": Quantity(
        "tau",
        {"tau": ("collision", "decay time of P(n) - 1/2 = A exp(-n/tau), n in counted collisions"),
         "tau_stderr": ("collision", "jackknife standard error of tau"),
         "P1": ("1", "P(1)"), "P1_stderr": ("1", "standard error of P(1)"),
         "n_needed_fit": ("collision", "tau ln(|A|/0.01): collisions until |P(n) - 1/2| < 0.01 (fit)")},
        {"bounces": 100_000, "max_lag": 40, "orbits": 100, "count": "bottom", "device": "cpu"}),
    "splitting": Quantity(
        "splitting",
        {"splitting": ("1/kappa**2", "lambda_minus - lambda_plus of the lowest doublet (direct difference)"),
         "splitting_flux": ("1/kappa**2", "the same by Herring's flux formula (nan if one class)"),
         "direct_trusted": ("1", "1 if the direct difference is above rounding"),
         "flux_trusted": ("1", "1 if the states' neck values are above rounding"),
         "lambda_lower": ("1/kappa**2", "lambda_plus, the lower level of the doublet"),
         "wkb_action": ("1", "WKB action S through one neck (splitting ~ exp(-S))"),
         "neck_width": ("kappa", "H - D, the width of the necks")},
        {"pair": 0, "cells": 8, "order": 2}, seeded=False),
    "toss": Quantity(
        "toss",
        {"heads": ("1", "share of the tosses that end heads (a coin's wall; the first valley otherwise)"),
         "heads_stderr": ("1", "binomial standard error of heads"),
         "tails": ("1", "share of the tosses that end tails"),
         "undecided": ("1", "share still bouncing at the impact budget, or sliding above their barrier"),
         "bias": ("1", "heads/(heads + tails) - 1/2"), "bias_stderr": ("1", "binomial standard error of bias"),
         "mean_bounces": ("1", "mean floor impacts before the outcome was decided (decided tosses)"),
         "level": ("kappa", "toss energy level E/(M g kappa) = H + (v0^2 + omega0^2)/(2g)")},
        {"tosses": 2000, "g": 1.0, "v0": 2.0, "omega0": 5.0, "spread": 0.02, "impacts": 10_000, "device": "cpu"}),
}


#: the most collisions one cell may follow (about an hour of kernel time on one core, as for ``coinwall kam``)
MAX_CELL_WORK = 1e10


def check_options(quantity: str, options: dict | None) -> dict:
    """All options of ``quantity`` in canonical types, defaults filled in; unknown names are refused.

    Parameters
    ----------
    quantity : str
        A key of :data:`QUANTITIES`.
    options : dict or None
        Option name → value.

    Returns
    -------
    dict
        Every option of the quantity.

    Raises
    ------
    InvalidArgument
        For an unknown quantity, an unknown option name or a bad value.

    Examples
    --------
    >>> from coinwall.cases.scan import check_options
    >>> check_options("splitting", {"cells": 4})
    {'pair': 0, 'cells': 4, 'order': 2}
    >>> check_options("lyapunov", {"orbit": 4})
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.InvalidArgument: `orbit` is not an option of 'lyapunov'; its options are orbits, collisions, every, device
    """
    check_choice("quantity", quantity, tuple(QUANTITIES))
    spec = QUANTITIES[quantity]
    options = dict(options or {})
    unknown = sorted(set(options) - set(spec.defaults))
    if unknown:
        raise InvalidArgument(f"`{unknown[0]}` is not an option of {quantity!r}; its options are "
                              f"{', '.join(spec.defaults)}")
    out = {**spec.defaults, **{k: v for k, v in options.items() if v is not None}}
    for name in ("orbits", "collisions", "every", "bounces", "max_lag", "cells", "tosses", "impacts"):
        if name in out:
            out[name] = check_count(name, out[name])
    for name in ("pair", ):
        if name in out:
            out[name] = check_count(name, out[name], minimum=0)
    if "order" in out:
        out["order"] = check_count("order", out["order"], minimum=2, maximum=4)
    if out.get("threshold") is not None:
        out["threshold"] = check_positive("threshold", out["threshold"])
    if "count" in out:
        check_choice("count", out["count"], ("bottom", "all"))
    if "device" in out:  # the GPU itself is checked where the cells run (a cluster's workers may have one)
        check_choice("device", out["device"], ("cpu", "gpu"))
    if quantity == "toss":
        out["g"] = check_positive("g", out["g"])
        for name in ("v0", "omega0", "spread"):
            value = out[name]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise InvalidArgument(f"`{name}` must be a finite number, got {value!r}")
            out[name] = float(value)
        if not 0.0 <= out["spread"] <= 1.0:
            raise InvalidArgument(f"`spread` must be a relative spread in [0, 1], got {out['spread']!r}")
    work = work_of(quantity, out)
    if work > MAX_CELL_WORK:  # (nan for splitting: its cost is the mesh's, bounded by `cells`)
        raise InvalidArgument(f"one cell of {quantity!r} would follow about {work:.3g} collisions, more than the "
                              f"{MAX_CELL_WORK:.0e} (about an hour on one core) a cell may take; lower `orbits`, "
                              "`collisions` or `bounces`")
    if quantity in ("chaotic-fraction", "lyapunov"):
        # every orbit and its companion hold one renormalisation round of states (6 columns of 8 bytes)
        check_memory(f"`orbits` = {out['orbits']} with `every` = {out['every']}",
                     2.0 * out["orbits"] * (out["every"] + 2) * 48.0)
    if quantity == "tau":
        if out["orbits"] < 2:
            raise InvalidArgument(f"`orbits` must be at least 2 for tau (the error comes from the spread), got "
                                  f"{out['orbits']}")
        if out["max_lag"] >= out["bounces"] // out["orbits"]:
            raise InvalidArgument(f"`max_lag` = {out['max_lag']} must be smaller than bounces/orbits = "
                                  f"{out['bounces'] // out['orbits']}")
    return out


def work_of(quantity: str, options: dict) -> float:
    """Collisions one cell follows (each orbit and its companion for the exponents), for estimates."""
    if quantity in ("chaotic-fraction", "lyapunov"):
        every = options["every"]
        return 2.0 * options["orbits"] * (-(-options["collisions"] // every) + 3) * (every + 2)
    if quantity == "tau":
        return 2.0 * options["bounces"]
    if quantity == "toss":
        return float(options["tosses"]) * options["impacts"]
    return math.nan


def compute_cell(quantity: str, table_spec, values: dict, H: float, seed: int, options: dict) -> dict:
    """The numbers of one cell (what a worker runs).

    Parameters
    ----------
    quantity : str
        A key of :data:`QUANTITIES`.
    table_spec : TableSpec
    values : dict
        The cell's scanned wall parameters.
    H : float
        The cell's wall distance (the wall's length unit).
    seed : int
        The cell's seed (:func:`.grid.cell_seed`).
    options : dict
        :func:`check_options` of the quantity.

    Returns
    -------
    dict
        ``{"status": 1, variable: value, ...}``, or ``{"status": 2, "error": message}`` when the library
        refuses this cell's input (a table that does not open at this (ε, H), H below the diameter for a
        splitting): a finding about that cell, not a failure of the scan.

    Raises
    ------
    InvalidArgument
        For an unknown quantity (a refused input of the cell is a status 2, not an exception).

    Examples
    --------
    >>> from coinwall.cases.scan import TableSpec, check_options, compute_cell
    >>> ellipse = TableSpec("sqrt((1+eps*cos(t)**2)/(1+eps))")
    >>> cell = compute_cell("splitting", ellipse, {"eps": 1.0}, 2.3, 0, check_options("splitting", {"cells": 4}))
    >>> cell["status"], f"{cell['splitting']:.3e}"
    (1, '2.068e-05')
    """
    from coinwall.forward.errors import CoinwallError

    if options.get("device") == "gpu":
        from coinwall.forward.dynamics.billiard.gpu import device_status

        why = device_status()
        if why:  # the worker's own failure, not a finding about the cell: the task fails, the cell stays to do
            raise RuntimeError(f"this worker cannot run --device gpu: {why}")
    try:
        if quantity in _OWN_TABLE:
            numbers = _OWN_TABLE[quantity](table_spec, values, H, seed, **options)
        else:
            table = table_spec.table_at(values, H)
            numbers = _FUNCTIONS[quantity](table, seed, **options)
    except CoinwallError as exc:
        return {"status": 2, "error": str(exc)}
    return {"status": 1, **{k: float(v) for k, v in numbers.items()}}
