"""Figures of a scan store: the (parameter, H) phase diagram, and a quantity against H with error bars.

Both take the :class:`xarray.Dataset` of a store (``xarray.open_zarr(path)``) and return matplotlib Axes.
Cells not computed (status 0) or refused (status 2) are left blank.  On a chaotic-fraction diagram of the
paper's ellipse wall over ``eps``, the paper's fit ε = 1/H + 17/H² (eq. 20) and the closed-form limits
ε*(H) and ε**(H) of :mod:`.islands` are drawn.  Both are drawn in the house style
(:mod:`coinwall.forward.formats.style`): titles name the quantity, the wall and the cells, colour has a colour bar,
log axes print one number format.
"""

from __future__ import annotations

import numpy as np

from coinwall.forward.dynamics.analysis.islands import eps_star, eps_star_star, paper_boundary
from coinwall.forward.errors import InvalidArgument
from coinwall.forward.formats.style import plain_log_axis, styled

__all__ = ["plot_line", "plot_phase_diagram", "plot_scan"]


def _main_variable(dataset):
    """The quantity's first variable (a Zarr store lists its arrays in alphabetical order, not in ours)."""
    from .quantities import QUANTITIES

    quantity = QUANTITIES.get(dataset.attrs.get("quantity"))
    if quantity is not None:
        return next(iter(quantity.variables))
    return next(name for name in dataset.data_vars if name not in ("cell_seed", "cell_status"))


def _about(dataset) -> str:
    """The wall and its parameters as the store records them, for a title."""
    import ast

    wall, params = dataset.attrs.get("wall", ""), dataset.attrs.get("params", "")
    try:  # the driver stores the fixed parameters as the repr of a dict
        params = ast.literal_eval(params) if isinstance(params, str) and params else params
    except (ValueError, SyntaxError):
        pass
    if isinstance(params, dict):
        params = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in params.items())
    return f"{wall}{', ' + str(params) if params else ''}"


def _units(array) -> str:
    """The units of a store's array as a label writes them (κ, dimensionless)."""
    units = str(array.attrs.get("units", "") or "")
    return {"": "dimensionless", "1": "dimensionless", "kappa": "κ", "1/kappa**2": "1/κ²"}.get(units, units)


def _values(dataset, variable):
    values = np.asarray(dataset[variable].values, dtype=float)
    return np.where(np.asarray(dataset["cell_status"].values) == 1, values, np.nan)


def _edges(values, log):
    """Cell edges around the coordinate values (geometric midpoints on a log axis)."""
    v = np.asarray(values, dtype=float)
    if v.size == 1:
        return np.array([v[0] * 0.9, v[0] * 1.1]) if log else np.array([v[0] - 0.5, v[0] + 0.5])
    if log:
        mid = np.sqrt(v[1:] * v[:-1])
        return np.concatenate([[v[0] ** 2 / mid[0]], mid, [v[-1] ** 2 / mid[-1]]])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


#: at most this many cells along an axis are labelled one by one, at their centres
MAX_CELL_TICKS = 12


def _cell_ticks(axis, values):
    """Ticks at the computed values (the cells' centres) when there are few: the cells' edges lie halfway
    to the neighbours, and an axis ticked at round numbers past the last value reads as data that is not
    there (restitution 1.0 on a grid that ends at 0.9)."""
    from matplotlib.ticker import FixedLocator, NullLocator

    v = np.asarray(values, dtype=float)
    if v.size <= MAX_CELL_TICKS:
        axis.set_major_locator(FixedLocator(v))
        axis.set_minor_locator(NullLocator())
        axis.set_ticklabels([f"{x:.3g}" for x in v])


def _is_log(values):
    v = np.asarray(values, dtype=float)
    if v.size < 3 or np.any(v <= 0):
        return False
    ratios = v[1:] / v[:-1]
    return bool(np.allclose(ratios, ratios[0], rtol=1e-6) and not np.allclose(np.diff(v), v[1] - v[0], rtol=1e-6))


@styled
def plot_phase_diagram(dataset, variable=None, ax=None, curves=True):
    """The 2-d map of ``variable`` over (H, parameter), with the ellipse wall's curves when they apply.

    Parameters
    ----------
    dataset : xarray.Dataset
        A store with two dimensions (a wall parameter, then H).
    variable : str, optional
        Default: the quantity's first variable (the chaotic fraction for ``chaotic-fraction``).
    ax : matplotlib Axes, optional
    curves : bool
        Draw 1/H + 17/H², ε*(H) and ε**(H) (only for the ellipse wall scanned over ``eps``).
    """
    from coinwall.forward.dynamics.analysis.islands import ELLIPSE_WALL
    from coinwall.forward.formats.figure import axes_or_new

    variable = variable or _main_variable(dataset)
    dims = dataset[variable].dims
    if len(dims) != 2 or dims[-1] != "H":
        raise InvalidArgument(f"a phase diagram needs two axes (a parameter, then H), the store has {dims}")
    name = dims[0]
    ax, own = axes_or_new(ax, (7, 4.8))
    p, H = dataset[name].values, dataset["H"].values
    log = _is_log(p)
    data = np.ma.masked_invalid(_values(dataset, variable))
    mesh = ax.pcolormesh(_edges(H, False), _edges(p, log), data, shading="flat", cmap="viridis")
    bar = ax.figure.colorbar(mesh, ax=ax)
    bar.set_label(f"{variable} ({_units(dataset[variable])})")
    if log:
        ax.set_yscale("log")
    if curves and name == "eps" and dataset.attrs.get("wall") == ELLIPSE_WALL and dataset.attrs.get("kappa") == "none":
        grid = np.linspace(max(H.min(), 1.2), H.max(), 60)
        import matplotlib.patheffects as effects

        ax.plot(grid, paper_boundary(grid), "w-", lw=2, label=r"paper: $1/H + 17/H^2$",
                path_effects=[effects.Stroke(linewidth=3.2, foreground="k"), effects.Normal()])
        ax.plot(grid, [eps_star(h) for h in grid], "r--", lw=1.5, label=r"$\varepsilon^*(H)$: vertical orbit unstable")
        ax.plot(grid, [eps_star_star(h) for h in grid], "m:", lw=2, label=r"$\varepsilon^{**}(H)$: tilted orbit unstable")
        ax.set_ylim(_edges(p, log)[0], _edges(p, log)[-1])
        ax.legend(loc="upper right", fontsize=7, frameon=True, framealpha=0.8)
    if log:
        plain_log_axis(ax.yaxis)
    ax.grid(False)  # the cells are the picture
    _cell_ticks(ax.xaxis, H)
    _cell_ticks(ax.yaxis, p)
    toss = dataset.attrs.get("quantity") == "toss"  # its H is the launch height; restitution is not of the wall
    ax.set_xlabel(f"{'launch height' if toss else 'wall distance'} H ({_units(dataset['H'])})")
    ax.set_ylabel(f"{'' if toss and name == 'restitution' else 'wall parameter '}{name} ({_units(dataset[name])})")
    done = int(np.count_nonzero(np.asarray(dataset["cell_status"].values) == 1))
    ax.set_title(f"{variable} on {p.size} {name} × {H.size} H cells ({done} computed)\n{_about(dataset)}")
    if own:
        ax.figure.tight_layout()
    return ax


@styled
def plot_line(dataset, variable=None, ax=None):
    """``variable`` against H with error bars from ``<variable>_stderr`` (one line per other coordinate)."""
    from coinwall.forward.formats.figure import axes_or_new

    variable = variable or _main_variable(dataset)
    ax, own = axes_or_new(ax, (6, 4))
    values = _values(dataset, variable)
    err_name = f"{variable}_stderr"
    errors = _values(dataset, err_name) if err_name in dataset else np.zeros_like(values)
    H = dataset["H"].values
    dims = dataset[variable].dims
    if len(dims) == 1:
        ax.errorbar(H, values, yerr=errors, fmt="o-", capsize=3)
    else:
        other = dims[0]
        for k, v in enumerate(dataset[other].values):
            ax.errorbar(H, values[k], yerr=errors[k], fmt="o-", capsize=3, label=f"{other} = {v:.4g}")
        ax.legend()
    units = _units(dataset[variable])
    if np.nanmin(values, initial=np.inf) > 0:
        ax.set_yscale("log")
        plain_log_axis(ax.yaxis)
    ax.set_xlabel(f"wall distance H ({_units(dataset['H'])})")
    ax.set_ylabel(f"{variable} ({units})")
    ax.set_title(f"{variable} against H ({H.size} heights)\n{_about(dataset)}")
    if own:
        ax.figure.tight_layout()
    return ax


def plot_scan(dataset, variable=None, ax=None):
    """The figure that fits the store: a phase diagram for two axes, a line with error bars for one."""
    variable = variable or _main_variable(dataset)
    if len(dataset[variable].dims) == 2 and dataset[variable].shape[0] > 1 and dataset[variable].shape[1] > 1:
        return plot_phase_diagram(dataset, variable, ax)
    return plot_line(dataset, variable, ax)
