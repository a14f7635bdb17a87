"""The exporters' table (``EXPORTERS``) and the writers of solved bodies (``export_body``, ``write_outputs``).

What an exporter module defines, and the promises (atomic files, the same bytes for the same body), are in
the package's docstring, :mod:`coinwall.inverse.export`.
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass, field

from coinwall.forward.display import safe_repr
from coinwall.forward.errors import OutputError
from coinwall.forward.formats.output import check_paths, write_all

from . import csvfile, dxf, jsonfile, pdf, png, svg
from .options import UNITS, ExportOptions

__all__ = [
    "EXPORTERS",
    "UNITS",
    "ExportOptions",
    "ExportResult",
    "check_outputs",
    "export_body",
    "exporters",
    "write_outputs",
]

#: extension -> exporter module
EXPORTERS = {module.EXTENSION: module for module in (svg, dxf, jsonfile, csvfile, png, pdf)}

# report entries that are not deviations
_NOT_DEVIATIONS = {"tolerance", "units", "polyline_vertices", "diameter"}


@dataclass(frozen=True, repr=False)
class ExportResult:
    """What :func:`export_body` wrote.

    Attributes
    ----------
    paths : list of str
        The files written, in the order given.
    reports : dict
        ``path -> report``: for DXF ``{"spline", "polyline", "tolerance", "polyline_vertices", "units"}``,
        for SVG ``{"path", "tolerance", "diameter", "units"}``; deviations and the tolerance
        in output units.  Formats without approximation have an empty report.
    options : ExportOptions

    Examples
    --------
    >>> from coinwall import Wall, solve_body
    >>> disc = solve_body(Wall.from_expression("1"), 0.0, points=64)
    >>> from coinwall import export_body
    >>> result = export_body(disc, ["disc.dxf", "disc.svg"], kappa=12.0, units="mm")
    >>> result.paths, {path: round(report["tolerance"], 9) for path, report in result.reports.items()}
    (['disc.dxf', 'disc.svg'], {'disc.dxf': 0.0024, 'disc.svg': 0.0024})
    >>> all(deviation <= 0.0024 for deviation in result.deviations().values())     # mm: within the tolerance
    True
    """

    paths: list
    reports: dict = field(default_factory=dict)
    options: ExportOptions = field(default_factory=ExportOptions)

    def deviations(self) -> dict:
        """``path -> largest achieved deviation`` for the files that have one."""
        out = {}
        for path, report in self.reports.items():
            values = [v for k, v in report.items() if k not in _NOT_DEVIATIONS]
            if values:
                out[path] = max(values)
        return out

    def to_dict(self) -> dict:
        """JSON-ready: the paths, the reports and the options."""
        return {"paths": list(self.paths), "reports": {p: dict(r) for p, r in self.reports.items()},
                "options": self.options.to_dict()}

    @safe_repr
    def __repr__(self) -> str:
        devs = ", ".join(f"{os.path.basename(p)}: {d:.2g}" for p, d in self.deviations().items())
        return f"ExportResult({len(self.paths)} files, units {self.options.unit_name}, deviations {{{devs}}})"


def exporters() -> dict:
    """Map of extension (``".svg"``) to exporter module (a copy of ``EXPORTERS``).

    Returns
    -------
    dict
        ``{extension: module}``.

    Examples
    --------
    >>> from coinwall.inverse.export import exporters
    >>> sorted(exporters())
    ['.csv', '.dxf', '.json', '.pdf', '.png', '.svg']
    """
    return dict(EXPORTERS)


def check_outputs(paths) -> list:
    """Before any work: every path has an exporter (by its extension) and can be written (the writer's rules,
    :func:`coinwall.forward.formats.output.check_paths`); returns ``[(path, exporter module)]``.

    Parameters
    ----------
    paths : list of str
        The output files.

    Returns
    -------
    list of (str, module)
        Each path with the exporter module its extension names.

    Raises
    ------
    OutputError
        Naming the first path that has no exporter or cannot be written.

    Examples
    --------
    >>> check_outputs(["body.xyz"])
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.OutputError: output 'body.xyz': unknown extension '.xyz'; known: .csv, .dxf, .json, \
.pdf, .png, .svg
    """
    check_paths(paths, sorted(EXPORTERS))
    return [(path, EXPORTERS[os.path.splitext(path)[1].lower()]) for path in paths]


def _check_finite_outline(body):
    """A body read back from a file (or made by hand) is not a checked :class:`~inverse.Body`: refuse a
    non-finite outline before any byte is produced, so no file of ``nan`` is ever written."""
    import numpy as np

    from coinwall.forward.errors import InvalidOutline

    outline = getattr(body, "outline", None)
    for name in ("nodes", "controls"):
        values = np.asarray(getattr(outline, name, np.zeros(0)), dtype=float)
        bad = np.flatnonzero(~np.isfinite(values.reshape(len(values), -1)).all(axis=1)) if values.size else []
        if len(bad):
            raise InvalidOutline(f"the body's outline is not finite at node {int(bad[0])}; nothing was written")


def write_outputs(body, paths, *, kappa=None, units=None, tolerance=None, dimension=False, cut=False) -> list:
    """Write ``body`` to every path (format by extension), all or nothing; returns the paths.

    ``kappa``/``units``/``tolerance``/``dimension``/``cut`` are :class:`ExportOptions`; use
    :func:`export_body` to also get the achieved deviations.

    Parameters
    ----------
    body : Body
    paths : list of str
        Output files; the format follows the extension.
    kappa, units, tolerance, dimension, cut
        As for :func:`export_body`.

    Returns
    -------
    list of str
        The paths written.

    Raises
    ------
    OutputError
        Unknown extension or unwritable place (nothing is written then).

    Examples
    --------
    >>> from coinwall import Wall, solve_body
    >>> disc = solve_body(Wall.from_expression("1"), 0.0, points=64)
    >>> from coinwall import load_outline
    >>> from coinwall.inverse.export import write_outputs
    >>> write_outputs(disc, ["disc.json", "disc.csv"])
    ['disc.json', 'disc.csv']
    >>> outline, note = load_outline("disc.json")          # a written body reads back
    >>> round(outline.area, 3)
    3.142
    """
    return export_body(body, paths, kappa=kappa, units=units, tolerance=tolerance, dimension=dimension,
                       cut=cut).paths


def export_body(body, paths, *, kappa=None, units=None, tolerance=None, dimension=False,
                cut=False) -> ExportResult:
    """Write ``body`` to every path, all or nothing, and report the deviations achieved.

    Parameters
    ----------
    body : inverse.Body
    paths : list of str
        Output files; the format follows the extension.
    kappa, units : float, str, optional
        Radius of gyration in ``units`` (mm, cm, in): physical size.  Without them,
        units of κ.  Only formats that draw the body (SVG, DXF) are scaled; JSON and
        CSV stay in units of κ, the form ``coinwall wall``/``export`` read back.
    tolerance : float, optional
        Largest deviation from the exact outline, in output units.
    dimension : bool
        Draw the largest diameter (SVG).
    cut : bool
        Cut-ready SVG/DXF: one closed contour on one layer, nothing else (:class:`ExportOptions`).

    Returns
    -------
    ExportResult
        The paths written, each format's report, and the deviation each approximated outline achieved
        (:meth:`ExportResult.deviations`).

    Examples
    --------
    A disc of radius κ drawn at real size with κ = 10 mm; the SVG approximates the exact outline within the
    tolerance reported:

    >>> from coinwall import Wall, export_body, solve_body
    >>> disc = solve_body(Wall.from_expression("1"), 0.0, points=64)
    >>> result = export_body(disc, ["disc.json", "disc.svg"], kappa=10.0, units="mm")
    >>> result.paths
    ['disc.json', 'disc.svg']
    >>> max(result.deviations().values()) < 1e-6
    True

    Raises
    ------
    OutputError
        Unknown extension, unwritable place, or a tolerance that cannot be reached — by the drawing, or
        by the outline itself: a body from samples whose outline tolerance (in output units) exceeds
        ``tolerance`` is refused, since the samples do not fix the part that well.
    InvalidArgument
        Bad scale or tolerance.
    """
    options = ExportOptions(kappa=kappa, units=units, tolerance=tolerance, dimension=dimension, cut=cut)
    checked = check_outputs(paths)
    _check_finite_outline(body)
    if options.tolerance is not None:  # refused for every format, also those that do not approximate (CSV)
        from .flatten import largest_diameter

        options.tolerance_for(largest_diameter(body.outline)[0] * options.scale)
        band = getattr(body, "outline_tolerance", None)
        if band is not None and band * options.scale > options.tolerance:
            # refused, not warned: a file made to a tolerance promises the part to it, and data that fix the
            # outline only to their band cannot keep that promise
            raise OutputError(f"`tolerance` {options.tolerance:.3g} {options.unit_name}: the samples fix the outline "
                              f"only to {band * options.scale:.3g} {options.unit_name} (its outline tolerance: every "
                              "body within their intervals is that close to it, the true one too); give a tolerance "
                              "at least that large, or samples that are denser or have more digits")
    reports, files = {}, {}
    path = None
    try:
        for path, module in checked:
            stream = io.BytesIO()
            report = module.write(body, stream, options)
            reports[path] = dict(report) if isinstance(report, dict) else {}
            achieved = [v for k, v in reports[path].items() if k not in _NOT_DEVIATIONS]
            limit = reports[path].get("tolerance")
            if achieved and limit is not None and max(achieved) > limit:
                raise OutputError(f"output {path!r}: deviation {max(achieved):.3g} exceeds `tolerance` "
                                  f"{limit:.3g} {options.unit_name}; give a larger tolerance")
            files[path] = stream.getvalue()
    except OSError as exc:
        raise OutputError(f"cannot write output {path!r}: {exc.strerror or exc}") from None
    write_all(files)  # only once every format was produced: all or nothing
    return ExportResult([p for p, _ in checked], reports, options)
