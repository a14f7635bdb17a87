"""``coinwall cases``: the catalog of named cases (walls and bodies usable as ``case:NAME``), or one of them."""

from __future__ import annotations

import json
import numbers

from .common import add_command

__all__ = ["register"]

_DESCRIPTION = """\
The named cases: the walls and bodies of the paper (the stick, the ellipse family with the paper's
eps values, the Appendix regimes, the coin) and beyond (constant-width bodies, rectangle, triangle,
asymmetric and few-extrema walls).  Each comes with the offset b0 it is meant for, a wall distance H
where the paper uses one, and reference values with where they come from.  Without NAME: the list;
with NAME: that case in full.  Use any of them as case:NAME where a wall is expected."""

_EXAMPLE = """\
coinwall cases
coinwall cases ellipse-0.55
coinwall solve case:appendix-corner"""


def register(subparsers):
    """Add the ``cases`` subcommand."""
    parser = add_command(subparsers, "cases", help="list the named cases (walls and bodies) usable as case:NAME, "
                                                   "or show one", description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("name", nargs="?", default=None, metavar="NAME",
                        help="show this case in full (with or without the case: prefix)")
    parser.add_argument("--json", action="store_true", help="print the case(s) with reference values as JSON")
    parser.set_defaults(run=run)


def _document(case):
    """A case as JSON-ready data (the references keep their full precision)."""
    return {"name": case.name, "title": case.title, "source": case.source, "b0": case.b0, "H": case.H,
            "wall": case.expression, "params": case.params, "has_wall": case.make_wall is not None,
            "has_body": case.make_outline is not None,
            "references": [{"name": r.name, "value": _plain(r.value), "source": r.source} for r in case.references]}


def _plain(value):
    """A reference value with NumPy scalars and tuples turned into JSON's numbers and lists."""
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return int(value)
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return float(value)
    return value


def _text(value):
    """A reference value as a reader sees it: numbers to 15 significant digits, sequences in brackets."""
    value = _plain(value)
    if isinstance(value, list):
        return "(" + ", ".join(_text(v) for v in value) + ")"
    if isinstance(value, float):
        return f"{value:.15g}"
    return str(value)


def _show(case):
    print(f"case       {case.name}: {case.title}")
    print(f"source     {case.source}")
    if case.expression is not None:
        params = ", ".join(f"{k} = {_text(v)}" for k, v in case.params.items())
        print(f"wall       b(θ) = {case.expression}" + (f"  ({params})" if params else ""))
    elif case.make_wall is not None:
        print(f"wall       {case.wall()!r} (no closed-form expression)")
    else:
        print("wall       none in closed form: a body; use it where a body is expected")
    print(f"body       {'closed form' if case.make_outline is not None else 'solved from the wall at b0'}")
    print(f"b0         {_text(case.b0)}")
    print(f"H          {_text(case.H) if case.H is not None else '— (no wall distance: not a dynamics case)'}")
    for ref in case.references:
        print(f"reference  {ref.name} = {_text(ref.value)}  [{ref.source}]")


def run(args):
    """List the catalog, or show one case."""
    from ..catalog import all_cases, get_case

    if args.name is not None:
        case = get_case(args.name)
        if args.json:
            print(json.dumps(_document(case), indent=1, allow_nan=False))
        else:
            _show(case)
        return 0
    cases = all_cases()
    if args.json:
        print(json.dumps([_document(c) for c in cases.values()], indent=1, allow_nan=False))
        return 0
    width = max(len(n) for n in cases)
    for case in cases.values():
        print(f"{case.name:<{width}}  {case.title}  [{case.source}]")
    print(f"\nUse any of them as case:NAME where a wall is expected, e.g. `coinwall solve case:{next(iter(cases))}`; "
          f"`coinwall cases NAME` shows one in full.")
    return 0
