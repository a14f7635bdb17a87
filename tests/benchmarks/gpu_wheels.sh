#!/usr/bin/env bash
# Prepare .whl/ for tests/benchmarks/gpu_check.sh: the wheels (CPython 3.12, manylinux x86_64) of what coinwall needs
# and a GPU machine without network lacks.  Run here, from anywhere in the checkout (needs PyPI); .whl/ is ignored
# by git (.git/info/exclude).
#
# The GPU image has Python 3.12 with numpy, scipy, matplotlib, numba, numba-cuda, tqdm, lazy-loader and the CUDA
# libraries; coinwall adds casadi, shapely, ezdxf, scikit-fem and defusedxml.  casadi's wheel is 93 MB, almost all of
# it solver plugins (IPOPT, HiGHS, MUMPS, ...) that coinwall's forward side never loads: the wall code needs casadi's
# core (SX, Function, jacobian: casadi.py, _casadi.so, libcasadi.so), so the wheel is rewritten with only those files
# (and a RECORD that lists them); the ~20 MB that remain are what travels.  numba-cuda 0.30.4 is carried as well, to be
# installed only where the machine has none (gpu_check.sh decides).  GPU_WHEELS_PYTHON (default 3.12, the GPU
# image's) picks another interpreter's wheels, e.g. this machine's for GPU_CHECK_DRY_RUN=1 of gpu_check.sh here.
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
rm -rf .whl
mkdir -p .whl
platforms=(--platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_24_x86_64
           --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 --platform manylinux1_x86_64)
python3 -m pip download -q --no-deps --only-binary=:all: --python-version "${GPU_WHEELS_PYTHON:-3.12}" --implementation cp "${platforms[@]}" \
    -d .whl casadi==3.8.2 shapely==2.2.0 ezdxf==1.4.5 scikit-fem==12.0.2 defusedxml==0.7.1 numba-cuda==0.30.4
python3 - .whl/casadi-*.whl <<'EOF'
import base64, hashlib, sys, zipfile

path = sys.argv[1]
keep = {"casadi/__init__.py", "casadi/casadi.py", "casadi/_casadi.so", "casadi/libcasadi.so.3.7"}
with zipfile.ZipFile(path) as src:
    names = src.namelist()
    missing = keep - set(names)
    if missing:
        sys.exit(f"gpu_wheels: casadi's wheel has no {sorted(missing)}: update the list of core files")
    files = {n: src.read(n) for n in names if n in keep or (".dist-info/" in n and not n.endswith("RECORD"))}
record_name = next(n for n in names if n.endswith(".dist-info/RECORD"))
lines = []
for name, data in files.items():
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    lines.append(f"{name},sha256={digest},{len(data)}")
lines.append(f"{record_name},,")
with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as dst:
    for name, data in files.items():
        dst.writestr(name, data)
    dst.writestr(record_name, "\n".join(lines) + "\n")
EOF
ls -l .whl
du -sh .whl
