"""Every public name of the API reference has a numpydoc docstring with the sections a reader looks for.

The public names are those of the ``__init__.pyi`` stubs (``coinwall`` and its subpackages) and the
``__all__`` of every module that ``docs/api/*.rst`` documents, each object counted once (an everyday name is
documented under ``coinwall.NAME``). Module-level constants (``METHODS``, ``UNITS``, ...) are documented in
the ``.rst`` pages themselves and are not checked here.

For each name, its docstring (parsed by numpydoc, as the site renders it) must have:

* a function: **Parameters** (when it takes any), **Returns** (or Yields) when it returns a value,
  **Raises** when its own source raises, and **Examples** with at least one ``>>>`` line;
* a data class (a dataclass or a named tuple): **Attributes** (or **Parameters**, for one that users
  construct, like :class:`~coinwall.Billiard`) and **Examples**;
* any other class: **Parameters** (when its constructor takes any) and **Examples**;
* an exception: **Examples**.

The Examples themselves run in ``tests/test_doctests.py``. ``_NOT_YET`` lists the names still missing a
section, each with the sections it misses: a name documented since must leave that list (the test fails on
a stale entry), so the list only shrinks.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import re
import textwrap
from pathlib import Path

import pytest

numpydoc_docscrape = pytest.importorskip("numpydoc.docscrape")

ROOT = Path(__file__).resolve().parents[1]

# the packages whose stub lists public names, and the modules whose __all__ the API reference documents
STUB_PACKAGES = ("coinwall", "coinwall.forward", "coinwall.forward.dynamics", "coinwall.forward.formats",
                 "coinwall.forward.quantum", "coinwall.inverse", "coinwall.inverse.export",
                 "coinwall.inverse.design", "coinwall.cases", "coinwall.cases.scan")

# classes built by named constructors (Wall.from_expression, ...), whose __init__ is internal: their
# Attributes are checked instead of Parameters
_NAMED_CONSTRUCTORS = {"Wall"}

# names not yet documented in full: name -> the sections it misses (shrinks; never add to it)
_NOT_YET: dict[str, set[str]] = {
}


def _documented_modules():
    """Modules named by ``.. module::`` / ``.. currentmodule::`` in docs/api/*.rst."""
    found = []
    for rst in sorted((ROOT / "docs" / "api").glob("*.rst")):
        for match in re.finditer(r"^\.\. (?:current)?module:: (\S+)", rst.read_text(encoding="utf-8"), re.M):
            if match.group(1) not in found:
                found.append(match.group(1))
    return found


def _public_objects():
    """``{qualified name: object}``: every public function and class, each object once (first name wins)."""
    objects, seen = {}, set()
    for module_name in dict.fromkeys((*STUB_PACKAGES, *_documented_modules())):
        module = importlib.import_module(module_name)
        for name in getattr(module, "__all__", ()):
            if name.startswith("__"):
                continue
            value = getattr(module, name)
            if not (inspect.isclass(value) or inspect.isfunction(value)) or id(value) in seen:
                continue
            seen.add(id(value))
            objects[f"{module_name}.{name}"] = value
    return objects


def _is_data_class(value):
    return dataclasses.is_dataclass(value) or (issubclass(value, tuple) and hasattr(value, "_fields"))


def _own_statements(function):
    """The statements of the function's own body (not those of functions or classes defined inside it)."""
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    except (OSError, TypeError, SyntaxError):
        return
    stack = list(tree.body[0].body)
    while stack:
        node = stack.pop()
        yield node
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            stack.extend(ast.iter_child_nodes(node))


def _raises_itself(function):
    return any(isinstance(node, ast.Raise) and node.exc is not None for node in _own_statements(function))


def _returns_a_value(function):
    return any(isinstance(node, (ast.Return, ast.Yield, ast.YieldFrom)) and node.value is not None
               and not (isinstance(node.value, ast.Constant) and node.value.value is None)
               for node in _own_statements(function))


def _takes_arguments(function):
    try:
        parameters = list(inspect.signature(function).parameters.values())
    except (TypeError, ValueError):
        return False
    return any(p.name not in ("self", "cls") for p in parameters)


def missing_sections(value):
    """The numpydoc sections the docstring of ``value`` lacks (an empty set when it has what it needs)."""
    doc = inspect.getdoc(value) or ""
    if not doc.strip():
        return {"docstring"}
    parsed = numpydoc_docscrape.NumpyDocString(doc)
    missing = set()
    if ">>>" not in "\n".join(parsed["Examples"]):
        missing.add("Examples")
    if inspect.isclass(value):
        if issubclass(value, BaseException):
            return missing
        if _is_data_class(value):
            if not (parsed["Attributes"] or parsed["Parameters"]):
                missing.add("Attributes")
        elif value.__name__ in _NAMED_CONSTRUCTORS:
            if not parsed["Attributes"]:
                missing.add("Attributes")
        elif "__init__" in vars(value) and _takes_arguments(value.__init__) and not parsed["Parameters"]:
            missing.add("Parameters")
        return missing
    if _takes_arguments(value) and not parsed["Parameters"]:
        missing.add("Parameters")
    if _returns_a_value(value) and not (parsed["Returns"] or parsed["Yields"]):
        missing.add("Returns")
    if _raises_itself(value) and not parsed["Raises"]:
        missing.add("Raises")
    return missing


def _report():
    return {name: missing_sections(value) for name, value in _public_objects().items()}


def test_the_public_api_is_enumerated():
    names = _public_objects()
    for name in ("coinwall.solve_body", "coinwall.Wall", "coinwall.forward.formats.load_wall",
                 "coinwall.forward.dynamics.basin_map", "coinwall.inverse.design.design", "coinwall.simulate"):
        assert name in names, name
    assert len(names) > 120


def test_every_public_name_has_its_sections():
    report = _report()
    stale = sorted(name for name in _NOT_YET if name not in report)
    assert not stale, f"_NOT_YET names no public object: {stale}"
    wrong = {name: sorted(sections) for name, sections in report.items()
             if sections and sections != _NOT_YET.get(name)}
    done = sorted(name for name in _NOT_YET if not report[name])
    assert not wrong, "numpydoc sections missing (name: sections):\n" + "\n".join(
        f"  {name}: {', '.join(sections)}" for name, sections in sorted(wrong.items()))
    assert not done, f"documented in full now, take them out of _NOT_YET: {done}"


def test_the_check_sees_a_missing_section():
    def bare(x):
        """Twice x.

        Parameters
        ----------
        x : float
            A number.
        """
        if x is None:
            raise ValueError("x")
        return 2 * x

    assert missing_sections(bare) == {"Returns", "Raises", "Examples"}
    assert missing_sections(lambda: None) == {"docstring"}


def _index_groups():
    """``{group title: [qualified names]}`` of the task groups of docs/api/index.rst."""
    groups, title, previous = {}, None, ""
    for line in (ROOT / "docs" / "api" / "index.rst").read_text(encoding="utf-8").splitlines():
        if re.fullmatch(r"~{3,}", line):
            title = previous
            groups[title] = []
        elif title and re.fullmatch(r"   coinwall\.[.\w]+", line):
            groups[title].append(line.strip())
        previous = line
    return groups


def test_the_index_groups_every_public_name_by_task():
    groups = _index_groups()
    for title in ("Walls and bodies", "From data", "The billiard", "The toss on a floor", "The 3-D coin", "Design",
                  "Quantum", "Scans"):
        assert groups.get(title), f"docs/api/index.rst has no group {title!r}"
    listed = [name for names in groups.values() for name in names]
    duplicates = sorted({name for name in listed if listed.count(name) > 1})
    assert not duplicates, f"listed in two groups: {duplicates}"
    public = _public_objects()
    assert not sorted(set(public) - set(listed)), f"in no group of docs/api/index.rst: {sorted(set(public) - set(listed))}"
    assert not sorted(set(listed) - set(public)), f"not a public name: {sorted(set(listed) - set(public))}"
