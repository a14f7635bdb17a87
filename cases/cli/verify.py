"""``coinwall verify``: recompute the paper's claims and print (and write) the comparison report."""

from __future__ import annotations

import json

from .common import add_command

__all__ = ["register"]

_DESCRIPTION = """\
Recompute every claim of the paper (Balazs, Chatterjee, Jackson, "Coin Tossing as a Billiard
Problem") that coinwall can check: the specular-reflection equations, the critical offset and the
Appendix regimes, the large-offset limit, the extrema counts, the equivalence of the rigid body and
the billiard.  Prints one row per claim with the paper's value, the computed one and a verdict
(yes / no / partly); exit status 1 if a verdict differs from the recorded one.  With --out DIR,
also writes DIR/paper-check.md and its figures in DIR/figures (folders created if missing)."""

_EXAMPLE = """\
coinwall verify --fast --out report --figure-format svg"""


def register(subparsers):
    """Add the ``verify`` subcommand."""
    parser = add_command(subparsers, "verify", help="recompute the paper's claims and print a table (yes/no/partly)",
                         description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("--out", metavar="DIR", default=None,
                        help="also write the report as Markdown (paper-check.md) with figures into DIR "
                             "(created if missing)")
    parser.add_argument("--figure-format", choices=["png", "svg", "pdf"], default="png",
                        help="file format of the figures written with --out (default png)")
    parser.add_argument("--fast", action="store_true", help="fewer points and samples (what the test suite runs)")
    parser.add_argument("--json", action="store_true", help="print the rows as JSON")
    parser.set_defaults(run=run)


def run(args):
    """Recompute the claims, print the table; exit status 1 when a verdict changed."""
    from ..paper.verify import run_verify

    report = run_verify(fast=args.fast, out=args.out, progress=not args.json,
                        figure_format=f".{args.figure_format}")
    if args.json:
        print(json.dumps(report.to_dict(), indent=1, allow_nan=False))
    else:
        import shutil
        import sys

        # the terminal's width when there is one (claims and results are wrapped, never cut), else 100 columns
        width = shutil.get_terminal_size((100, 24)).columns if sys.stdout.isatty() else 100
        print(report.table(width=max(60, min(width, 140))))
        print(f"checked in {report.seconds:.0f} s ({'fast' if args.fast else 'full'} mode)")
        if args.out:
            print(f"\nwrote {report.markdown_path} and {len(report.figures)} figure(s) in {args.out}")
    return 0 if report.ok else 1
