"""One import name, ``coinwall``: the lazy everyday API, the version, and nothing else at the top level.

These are packaging facts, checked the way a user meets them: a fresh interpreter, a working folder with
files that share our old top-level names, and the wheel pip builds.
"""

import importlib.metadata
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

import coinwall

ROOT = Path(__file__).resolve().parents[1]


def _python(code, cwd):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, capture_output=True, text=True, env=env,
                          timeout=120)


def test_version_is_the_installed_distribution_version():
    assert coinwall.__version__ == importlib.metadata.version("coinwall")


def test_everyday_api_is_reachable_from_the_top():
    from coinwall.forward.dynamics import Billiard
    from coinwall.inverse import critical_offset, solve_body

    assert coinwall.solve_body is solve_body
    assert coinwall.critical_offset is critical_offset
    assert coinwall.Billiard is Billiard
    assert set(coinwall.__all__) <= set(dir(coinwall))
    for name in coinwall.__all__:
        assert getattr(coinwall, name) is not None, name
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        coinwall.nonsense  # noqa: B018


def test_import_coinwall_is_light():
    """``import coinwall`` loads none of the heavy libraries (they come with the first use)."""
    result = _python("import sys, coinwall; print(sorted(m for m in ('numpy', 'scipy', 'casadi', 'matplotlib', "
                     "'numba') if m in sys.modules))", cwd=ROOT.parent)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[]"


def test_users_own_modules_named_like_our_folders_do_not_shadow_coinwall(tmp_path):
    """A user's inverse.py / forward.py / cases.py in the working folder used to shadow ours."""
    for name in ("inverse", "forward", "cases"):
        (tmp_path / f"{name}.py").write_text("raise ImportError('the user module was imported')\n")
    result = _python("from coinwall import solve_body, Wall; import coinwall.cases.catalog; "
                     "print(solve_body.__module__)", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "coinwall.inverse.solve"


def test_python_m_coinwall_version():
    result = subprocess.run([sys.executable, "-m", "coinwall", "--version"], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == f"coinwall {coinwall.__version__}"


def test_wheel_has_exactly_one_top_level_name(tmp_path):
    """``pip wheel .`` (an isolated build, as a user's ``pip install .`` does) packs one name: coinwall."""
    result = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(ROOT)],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    wheels = list(tmp_path.glob("coinwall-*.whl"))
    assert len(wheels) == 1
    names = zipfile.ZipFile(wheels[0]).namelist()
    top = {n.split("/")[0] for n in names if not n.split("/")[0].endswith(".dist-info")}
    assert top == {"coinwall"}
    for module in ("coinwall/forward/wall.py", "coinwall/forward/dynamics/billiard/table.py",
                   "coinwall/forward/formats/__init__.py", "coinwall/inverse/solve.py",
                   "coinwall/inverse/export/__init__.py", "coinwall/cases/cli/__init__.py",
                   "coinwall/cases/paper/__init__.py"):
        assert module in names, module
    # every package folder of the checkout is in the wheel (a folder left out of pyproject's list is lost)
    for folder in ("forward", "inverse", "cases"):
        for init in (ROOT / folder).rglob("__init__.py"):
            assert f"coinwall/{init.relative_to(ROOT).as_posix()}" in names, init
            # and its stub, which the lazy __init__ reads when the package is imported
            assert f"coinwall/{init.relative_to(ROOT).with_suffix('.pyi').as_posix()}" in names, init
    assert "coinwall/__init__.pyi" in names


def test_wall_is_immutable():
    wall = coinwall.Wall.from_expression("1 + a*cos(2*t)", {"a": 0.1})
    with pytest.raises(AttributeError, match="immutable"):
        wall.description = "something else"
    with pytest.raises(TypeError):
        wall.params["a"] = 0.5
    assert wall.params["a"] == 0.1
    theta = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    sampled = coinwall.Wall.from_samples(theta, 1 + 0.1 * np.cos(2 * theta))
    with pytest.raises(ValueError):  # the samples a wall keeps are read-only arrays
        sampled.samples[1][0] = 5.0


def test_body_derives_polar_coordinates_area_and_perimeter():
    body = coinwall.solve_body(coinwall.Wall.from_expression("1 + 0.1*cos(2*t)"), b0=0.0, points=256,
                               cross_check=False)
    np.testing.assert_allclose(body.R, np.hypot(body.x, body.y), rtol=0, atol=0)
    np.testing.assert_allclose(np.cos(body.alpha) * body.R, body.x, rtol=0, atol=1e-14)
    assert body.area == body.outline.area and body.perimeter == body.outline.perimeter
    # Cauchy: perimeter = ∫ h dφ = 2π (b0 + a0) = 2π for this wall (DESIGN.md, closed forms)
    assert abs(body.perimeter - 2 * np.pi) < 1e-6
