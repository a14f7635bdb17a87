"""What every test folder shares.

The tests mirror the package (``tests/forward/dynamics/``, ``tests/inverse/``, ``tests/cases/cli/``, …);
helpers that several folders use live here in ``tests/`` (``walldata.py``, ``cli_fuzz.py``, ``cli_fuzz_classes.py``,
``benettin_loop.py``) and are imported by name, so this folder goes on the path.  coinwall itself must be
installed (``pip install -e ".[test]"``): its three parts are mapped to their folders by the install
(``package-dir`` in ``pyproject.toml``), so a bare checkout cannot import ``coinwall.forward``; the run
then stops with that one line instead of an error in every file.
"""

import os
import sys
from pathlib import Path

import pytest

# device="gpu" runs in numba's CUDA simulator (the GPU code path, executed in Python) unless a run asks for the
# real device with NUMBA_ENABLE_CUDASIM=0 (tests/benchmarks/gpu_check.sh); set before numba is first imported
os.environ.setdefault("NUMBA_ENABLE_CUDASIM", "1")

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))


def pytest_configure(config):
    try:
        import coinwall.forward.errors  # noqa: F401
    except ImportError as exc:
        pytest.exit(f"coinwall is not installed ({exc}); run: pip install -e \".[test]\" (the package-dir mapping "
                    "needs an install)", returncode=4)
