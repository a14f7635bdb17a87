#!/usr/bin/env bash
# The GPU check, on a machine with an NVIDIA GPU and no network: from the repository root, with .whl/ beside it
# (made by tests/benchmarks/gpu_wheels.sh on a machine with PyPI):
#
#     bash tests/benchmarks/gpu_check.sh
#
# 1. prints nvidia-smi and the versions of Python, numpy, numba, numba-cuda, llvmlite, casadi and the CUDA bindings;
# 2. installs the carried wheels into /tmp/site (pip --target, nothing of the machine's own packages is changed;
#    numba-cuda from .whl only where the machine has none), copies coinwall's folders there as pyproject.toml's
#    package-dir maps them, and puts /tmp/site first on PYTHONPATH;
# 3. runs tests/forward/dynamics/billiard/test_gpu.py and tests/forward/dynamics/floor/test_toss_gpu.py on the device
#    (NUMBA_ENABLE_CUDASIM=0), not the simulator;
# 4. runs tests/benchmarks/bench_gpu.py (collisions/s on the GPU against all CPU cores, with the invariants).
#
# Everything goes to "$OUT" (default /tmp/gpu-check), six files: gpu_check.log (all of it), nvidia-smi.txt,
# versions.txt, bench_gpu.txt, bench_gpu.json, pytest.txt.  The whole run keeps within GPU_CHECK_SECONDS (default
# 230 s: the numba compiles included, ~13 s each on an H200's host; the tests are given 60 % of what is left after
# the install, the benchmark the rest) and stops at the first missing piece with one line "gpu_check: FAILED: ...".  Exit status: 0
# when every step passed, 1 otherwise.  GPU_CHECK_BENCH_ARGS adds options to bench_gpu.py (e.g. "--variants nofma"
# to leave out the variants' compiles when the device time is short).  GPU_CHECK_DRY_RUN=1 runs the script itself in numba's CUDA simulator at
# the benchmark's --smoke size (to check the script, not a GPU).
set -uo pipefail
OUT="${OUT:-/tmp/gpu-check}"
mkdir -p "$OUT"
exec > >(tee "$OUT/gpu_check.log") 2>&1
START=$(date +%s)
BUDGET="${GPU_CHECK_SECONDS:-230}"
left() { echo $(( BUDGET - ($(date +%s) - START) )); }
fail() { echo "gpu_check: FAILED: $*"; exit 1; }
step() { echo; echo "== $* ($(( $(date +%s) - START )) s)"; }

step "the machine"
[ -f pyproject.toml ] && [ -d forward/dynamics/billiard ] || fail "run this from the coinwall repository root"
command -v nvidia-smi >/dev/null || fail "nvidia-smi is missing: no NVIDIA driver on this machine"
nvidia-smi > "$OUT/nvidia-smi.txt" 2>&1 || { cat "$OUT/nvidia-smi.txt"; fail "nvidia-smi failed: no usable GPU"; }
cat "$OUT/nvidia-smi.txt"
nproc
[ -d .whl ] || fail ".whl/ is missing: run tests/benchmarks/gpu_wheels.sh on a machine with PyPI and carry .whl"

step "install the carried wheels and coinwall into /tmp/site"
SITE="${GPU_CHECK_SITE:-/tmp/site}"
rm -rf "$SITE"
wheels=$(ls .whl/*.whl | grep -v '/numba_cuda-')
# shellcheck disable=SC2086
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target "$SITE" $wheels \
    || fail "pip could not install the wheels of .whl/ (for Python 3.12, manylinux x86_64)"
if ! python3 -P -c "import numba_cuda" 2>/dev/null && ! python3 -P -c "from numba import cuda" 2>/dev/null; then
    echo "the machine has no numba-cuda: installing the carried one"
    python3 -m pip install -q --no-index --no-deps --no-compile --target "$SITE" .whl/numba_cuda-*.whl \
        || fail "could not install .whl/numba_cuda"
fi
# coinwall itself: its folders where pyproject.toml's package-dir maps them (coinwall/, coinwall/forward, ...)
cp -r coinwall "$SITE/coinwall" && cp -r forward inverse cases "$SITE/coinwall/" \
    || fail "could not copy coinwall's folders into $SITE"
export PYTHONPATH="$SITE"
export COINWALL_CACHE_DIR="${COINWALL_CACHE_DIR:-/tmp/coinwall-cache}" NUMBA_ENABLE_CUDASIM=0 PYTHONUNBUFFERED=1 MPLBACKEND=Agg
size=()
if [ "${GPU_CHECK_DRY_RUN:-0}" = 1 ]; then
    export NUMBA_ENABLE_CUDASIM=1
    size=(--smoke)
fi

step "versions and the device"
# -P: the checkout's own coinwall/ folder must not shadow the installed package
python3 -P - <<'EOF' 2>&1 | tee "$OUT/versions.txt"
import importlib.metadata as md
import os
import platform
import sys

print("python", platform.python_version(), sys.executable)
print("cpus", os.cpu_count(), "usable", len(os.sched_getaffinity(0)))
for name in ("numpy", "numba", "numba-cuda", "llvmlite", "casadi", "cuda-bindings", "cuda-core", "cuda-pathfinder",
             "scipy", "shapely", "ezdxf"):
    try:
        print(name, md.version(name))
    except md.PackageNotFoundError:
        print(name, "not installed")
import coinwall
from coinwall.forward.dynamics.billiard import gpu

import numba

print("numba threads", numba.config.NUMBA_NUM_THREADS, "threading layer asked", numba.config.THREADING_LAYER)
print("coinwall", coinwall.__version__, coinwall.__file__)
why = gpu.device_status()
if why:
    sys.exit(f"gpu_check: FAILED: {why}")
print("device", gpu.device_name())
EOF
[ "${PIPESTATUS[0]}" = 0 ] || fail "the device is not usable from numba-cuda (versions.txt)"

step "test_gpu.py on the device"
timeout $(( $(left) * 6 / 10 )) python3 -P -m pytest -q -p no:cacheprovider -n 4 tests/forward/dynamics/billiard/test_gpu.py \
    tests/forward/dynamics/floor/test_toss_gpu.py </dev/null \
    2>&1 | tee "$OUT/pytest.txt"
tests=${PIPESTATUS[0]}
[ "$tests" = 124 ] && echo "gpu_check: the tests ran out of their time"

step "bench_gpu.py: collisions/s, GPU against all CPU cores, with the invariants"
# shellcheck disable=SC2086
timeout $(( $(left) - 5 )) python3 -P tests/benchmarks/bench_gpu.py "${size[@]}" ${GPU_CHECK_BENCH_ARGS:-} --json "$OUT/bench_gpu.json" 2>&1 \
    | tee "$OUT/bench_gpu.txt"
bench=${PIPESTATUS[0]}
[ "$bench" = 124 ] && echo "gpu_check: bench_gpu.py ran out of its time"

step "done"
echo "bench_gpu.py exit $bench; test_gpu.py exit $tests; $(( $(date +%s) - START )) s in all"
[ "$bench" = 0 ] && [ "$tests" = 0 ] || fail "see bench_gpu.txt and pytest.txt"
echo "gpu_check: ok"
