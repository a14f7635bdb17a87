"""``coinwall verify``: every claim of the registry recomputed, the report, and its figures written.

Each claim's check runs once per distinct input (claims that share a computation share its
result); its measured numbers give the row's text and verdict (:func:`.claims.judge`).  With an
output folder, ``paper-check.md`` and the figures are written all or nothing.
"""

from __future__ import annotations

import os
import sys
import time

from coinwall.forward.errors import InvalidArgument, OutputError
from coinwall.forward.formats.figure import FIGURE_FORMATS
from coinwall.forward.formats.output import check_folder, write_all
from coinwall.forward.validation import check_choice

from .checks import Resolution
from .claims import REGISTRY, judge, render
from .report import Report, Row

__all__ = ["measure", "evaluate", "run_verify"]


def measure(claims, resolution: Resolution, progress: bool = False) -> dict:
    """``{key: measured numbers}`` for every claim of ``claims``, at ``resolution``.

    A check shared by several claims with the same inputs runs once.  With ``progress``, each check
    that runs is announced on stderr.
    """
    results, measured = {}, {}
    for claim in claims:
        # inputs hold lists (they print as the paper's lists), so their repr is the cache key
        key = (claim.check, repr(sorted(claim.inputs.items())))
        if key not in results:
            if progress:
                print(f"verify: {claim.source}: {claim.check.__name__}", file=sys.stderr, flush=True)
            results[key] = claim.check(resolution, **claim.inputs)
        measured[claim.key] = results[key]
    return measured


def evaluate(claims, resolution: Resolution, progress: bool = False) -> tuple:
    """One :class:`~.report.Row` per claim of ``claims``, at ``resolution`` (see :func:`measure`)."""
    claims = tuple(claims)
    measured = measure(claims, resolution, progress)
    return tuple(Row(claim.key, claim.claim, claim.source, render(claim.paper, claim, measured[claim.key]),
                     render(claim.computed, claim, measured[claim.key]), judge(claim, measured[claim.key]),
                     claim.expected, render(claim.detail, claim, measured[claim.key]))
                 for claim in claims)


def _output_folder(out) -> str:
    """``out`` as a folder that is writable or can be made; nothing is created before the report and its
    figures are written together (write_all makes the folders, and removes them again if that fails)."""
    if not isinstance(out, (str, os.PathLike)):
        raise InvalidArgument(f"`out` must be a folder path, got {out!r}")
    out = os.fspath(out)
    try:
        check_folder(os.path.join(out, "figures"))
    except OutputError as exc:
        raise OutputError(f"`out` {out!r}: {exc}") from None
    return out


def run_verify(fast: bool = False, out: str | None = None, progress: bool = False,
               figure_format: str = ".png") -> Report:
    """Recompute every claim of the paper in :data:`~.claims.REGISTRY`.

    Parameters
    ----------
    fast : bool
        Fewer nodes and collisions (:meth:`.checks.Resolution.of`); what the test suite runs.
    out : str or path, optional
        Folder to write ``paper-check.md`` and ``figures/*`` into (created if missing).
    progress : bool
        Announce each computation on stderr.
    figure_format : str
        ``.png``, ``.svg`` or ``.pdf``: the figures' file format.

    Returns
    -------
    Report
        ``report.ok`` is True when every verdict is the recorded one.
    """
    if not isinstance(fast, bool):
        raise InvalidArgument(f"`fast` must be True or False, got {fast!r}")
    check_choice("figure_format", figure_format, FIGURE_FORMATS)
    if out is not None:
        # before the work: a folder that cannot be written is known in a second, not after the run
        out = _output_folder(out)
    started = time.perf_counter()
    resolution = Resolution.of(fast)
    rows = evaluate(REGISTRY.values(), resolution, progress)
    if out is None:
        return Report(rows, (), None, time.perf_counter() - started, fast)
    from .figures import figure_files

    files = figure_files(os.path.join(out, "figures"), resolution.points, figure_format)
    figures = tuple(files)
    md_path = os.path.join(out, "paper-check.md")
    report = Report(rows, figures, md_path, time.perf_counter() - started, fast)
    files[md_path] = report.markdown().encode("utf-8")
    write_all(files)
    return report
