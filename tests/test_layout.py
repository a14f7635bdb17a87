"""The package's shape: no import cycle between modules, no module over 600 lines, lazy package namespaces
that agree with their stubs, and a ``coinwall --help`` that loads none of the heavy libraries.

The import graph is read from the source with :mod:`ast` (module-level imports only: an import inside a
function runs when the function does, after every module it needs has loaded) and checked with the
standard library's :mod:`graphlib`, which names a cycle when it finds one.
"""

import ast
import graphlib
import importlib
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: folder -> import name (pyproject.toml's package-dir)
FOLDERS = {"coinwall": "coinwall", "forward": "coinwall.forward", "inverse": "coinwall.inverse",
           "cases": "coinwall.cases"}
HEAVY = ("numpy", "scipy", "casadi", "matplotlib", "numba", "shapely", "ezdxf", "skfem")


def _modules():
    """Import name -> source file of every module of the package."""
    found = {}
    for folder, name in FOLDERS.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = path.relative_to(ROOT / folder).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            found[".".join((name, *parts))] = path
    return found


def _module_level(tree):
    """The statements that run when the module is imported (into if/try/with blocks, not into def/class)."""
    pending = list(tree.body)
    while pending:
        node = pending.pop()
        yield node
        if isinstance(node, (ast.If, ast.Try, ast.With)):
            for field in ("body", "orelse", "finalbody"):
                pending.extend(getattr(node, field, []))
            pending.extend(statement for handler in getattr(node, "handlers", []) for statement in handler.body)


def import_graph():
    """Module -> the package modules it imports at module level."""
    modules = _modules()
    graph = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = set()
        for node in _module_level(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                    base = f"{base}.{node.module}" if node.module else base
                else:
                    base = node.module
                targets.add(base)
                targets.update(f"{base}.{alias.name}" for alias in node.names)  # `from . import module`
        graph[name] = {t for t in targets if t in modules and t != name}
    return graph


def test_the_import_graph_is_read():
    """The reader finds the edges that are there (a check of the check)."""
    graph = import_graph()
    assert "coinwall.inverse.smooth" in graph["coinwall.inverse.solve"]
    assert "coinwall.inverse.certify" in graph["coinwall.inverse.sampled"]
    assert "coinwall.forward.errors" in graph["coinwall.forward.validation"]
    # an import inside a function is not an edge (critical.py imports certify.py when data need it)
    assert "coinwall.inverse.certify" not in graph["coinwall.inverse.critical"]


def test_no_import_cycle_between_modules():
    try:
        order = list(graphlib.TopologicalSorter(import_graph()).static_order())
    except graphlib.CycleError as exc:
        pytest.fail(f"import cycle: {' -> '.join(exc.args[1])}")
    assert order


def test_a_cycle_would_be_found():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}}
    with pytest.raises(graphlib.CycleError):
        list(graphlib.TopologicalSorter(graph).static_order())


#: the most lines a module of the package may have (docs/architecture.md)
MAX_LINES = 600


def test_no_module_is_over_600_lines():
    """Every module of the package (as ``wc -l`` counts) is at most MAX_LINES long."""
    lengths = {name: len(path.read_bytes().splitlines()) for name, path in _modules().items()}
    over = [f"{name} ({n} lines)" for name, n in sorted(lengths.items()) if n > MAX_LINES]
    assert not over, f"modules over {MAX_LINES} lines (split them along a seam): {', '.join(over)}"


def _stub(path):
    """(module -> names) imported by a stub, and its ``__all__``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    imports, listed = {}, None
    for node in tree.body:
        if isinstance(node, ast.ImportFrom):
            assert node.level == 1, f"{path}: a stub imports from inside its package only"
            imports.setdefault(node.module, []).extend(alias.name for alias in node.names)
        elif isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in node.targets):
            listed = ast.literal_eval(node.value)
    return imports, listed


PACKAGES = sorted(name for name, path in _modules().items() if path.name == "__init__.py")


@pytest.mark.parametrize("package", PACKAGES)
def test_stub_and_lazy_table_agree(package):
    """Every package has an ``__init__.pyi``; its imports are the package's ``__all__``, each name is the
    object its module defines, and the stub's own ``__all__`` lists the same names."""
    path = _modules()[package].with_suffix(".pyi")
    assert path.is_file(), f"{package} has no __init__.pyi"
    imports, listed = _stub(path)
    names = sorted(n for ns in imports.values() for n in ns)
    module = importlib.import_module(package)
    extra = ["__version__"] if package == "coinwall" else []
    assert sorted(module.__all__) == sorted(names + extra)
    assert sorted(listed) == sorted(names + extra), f"{path.name}: __all__ and the imports differ"
    for source, members in imports.items():
        defining = importlib.import_module(f"{package}.{source}")
        for name in members:
            assert getattr(module, name) is getattr(defining, name), f"{package}.{name}"
    with pytest.raises(AttributeError, match=f"module '{package}' has no attribute 'nonsense'"):
        module.nonsense  # noqa: B018


def _python(code):
    env = {k: v for k, v in os.environ.items() if k != "EAGER_IMPORT"}
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout.strip()


def test_importing_a_package_imports_none_of_its_modules():
    """``import coinwall.forward.dynamics`` (and every other package) loads the packages and the lazy loader,
    no module of ours and none of the heavy libraries."""
    code = (f"import importlib, sys\nfor p in {PACKAGES!r}:\n    importlib.import_module(p)\n"
            "print(sorted(m for m in sys.modules if m.startswith('coinwall')))\n"
            f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))")
    loaded, heavy = _python(code).splitlines()
    assert sorted(ast.literal_eval(loaded)) == sorted({*PACKAGES, "coinwall._lazy", "coinwall._version"})
    assert heavy == "[]"


def test_help_imports_no_numpy():
    """``coinwall --help`` builds every subcommand's parser and needs none of the heavy libraries."""
    code = ("import sys\nfrom coinwall.cases.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit as e:\n"
            "    assert e.code == 0, e.code\n"
            f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))")
    out = _python(code)
    assert out.splitlines()[-1] == "[]"
    assert "COMMAND" in out
