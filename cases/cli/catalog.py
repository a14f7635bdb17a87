"""``coinwall cases`` (list the catalog) and ``coinwall verify`` (recompute the paper's claims)."""

from __future__ import annotations

import json

__all__ = ["register"]


def _cmd_cases(args):
    from ..catalog import all_cases

    cases = all_cases()
    if args.json:
        doc = [{"name": c.name, "title": c.title, "source": c.source, "b0": c.b0, "H": c.H,
                "wall": c.expression, "params": c.params, "has_wall": c.make_wall is not None,
                "has_body": c.make_outline is not None,
                "references": [{"name": r.name, "value": r.value, "source": r.source} for r in c.references]}
               for c in cases.values()]
        print(json.dumps(doc, indent=1))
        return 0
    width = max(len(n) for n in cases)
    for case in cases.values():
        print(f"{case.name:<{width}}  {case.title}  [{case.source}]")
    print(f"\nUse any of them as case:NAME where a wall is expected, e.g. `coinwall solve case:{next(iter(cases))}`.")
    return 0


def _cmd_verify(args):
    from ..paper.verify import run_verify

    report = run_verify(fast=args.fast, out=args.out, progress=not args.json)
    if args.json:
        print(json.dumps(report.as_dict(), indent=1, allow_nan=False))
    else:
        print(report.table())
        if args.out:
            print(f"\nwrote {report.markdown_path} and {len(report.figures)} figure(s) in {args.out}")
    return 0 if report.ok else 1


def register(subparsers):
    cases = subparsers.add_parser("cases", help="list the named cases (walls and bodies) usable as case:NAME")
    cases.add_argument("--json", action="store_true", help="print the catalog with reference values as JSON")
    cases.set_defaults(run=_cmd_cases)

    verify = subparsers.add_parser("verify", help="recompute the paper's claims and print a table (yes/no/partly)")
    verify.add_argument("--out", metavar="DIR", default=None,
                        help="also write the report as Markdown (paper-check.md) with figures into DIR")
    verify.add_argument("--fast", action="store_true", help="fewer points and samples (what the test suite runs)")
    verify.add_argument("--json", action="store_true", help="print the rows as JSON")
    verify.set_defaults(run=_cmd_verify)
