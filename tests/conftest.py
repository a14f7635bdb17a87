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
# `-n auto` gives each worker process a core: BLAS threads on top of that oversubscribe the machine (OpenBLAS
# threads wait by spinning), so in a worker numpy and scipy run on one thread (numpy is loaded before this file:
# threadpoolctl sets the loaded libraries), as do the subprocesses it starts (the variables)
if os.environ.get("PYTEST_XDIST_WORKER"):
    from threadpoolctl import threadpool_limits

    for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_name, "1")
    threadpool_limits(1, user_api="blas")

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))


def pytest_configure(config):
    try:
        import coinwall.forward.errors  # noqa: F401
    except ImportError as exc:
        pytest.exit(f"coinwall is not installed ({exc}); run: pip install -e \".[test]\" (the package-dir mapping "
                    "needs an install)", returncode=4)
