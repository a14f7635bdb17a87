"""The GPU side of tests/benchmarks/bench_gpu.py: its kernels' variants, the layouts of the collision arrays, and
one collision from given states with a given compiled kernel (the benchmark's docstring says what each is for)."""

import numpy as np

CARRY = '''
from numba import cuda


@cuda.jit
def carry(states, turns, leaving, eta, vt, ve, side, done, last):
    # the next launch continues each orbit from its last collision (an orbit that stopped is left as it is)
    k = cuda.grid(1)
    if k < states.shape[0]:
        d = done[k]
        if d > 0:
            states[k, 0] = last[k, 0]
            states[k, 1] = eta[k, d - 1]
            states[k, 2] = vt[k, d - 1]
            states[k, 3] = ve[k, d - 1]
            turns[k] = int(last[k, 1])
            leaving[k] = side[k, d - 1]
'''


def carry_kernel():
    namespace = {}
    exec(compile(CARRY, "<bench_gpu carry>", "exec"), namespace)  # noqa: S102 -- our own text above
    return namespace["carry"]


def simulator() -> bool:
    from numba import config

    return bool(config.ENABLE_CUDASIM)


def variant_kernel(wall, fma=True, registers=None):
    """The billiard's launcher in a module of its own (compiled at its first launch, inside ``nvvm_options``), with
    at most ``registers`` registers a thread when given."""
    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.kernel import KERNEL_SOURCE

    launcher = gpu.BILLIARD_LAUNCHER
    if registers and not simulator():  # (the simulator's cuda.jit takes no max_registers)
        launcher = launcher.replace("@cuda.jit\ndef _run_gpu", f"@cuda.jit(max_registers={int(registers)})\ndef _run_gpu")
        if launcher == gpu.BILLIARD_LAUNCHER:
            raise RuntimeError("the launcher's text has changed: no @cuda.jit line before _run_gpu to cap")
    prefix = f"coinwall_gpu_fma{int(fma)}_r{registers or 0}"
    return gpu.gpu_module(wall, KERNEL_SOURCE, launcher, prefix)._run_gpu


def collision_rows(cuda, m, n, layout):
    """The six collision arrays (m, n) on the GPU: row-major (``C``), collision-major with a pad so that numba
    types them as strided (``coalesced``), or all collisions of an orbit in one place (``nowrite``, stride 0)."""
    kinds = [np.float64] * 5 + [np.int8]
    if layout == "C":
        return [cuda.device_array((m, n), dtype=d) for d in kinds]
    if simulator():  # (the simulator has no memory layout to speak of; it copies host arrays, contiguous ones)
        from numpy.lib.stride_tricks import as_strided

        if layout == "coalesced":
            return [np.empty((m, n), dtype=d, order="F") for d in kinds]
        return [as_strided(np.empty(m, dtype=d), (m, n), (np.dtype(d).itemsize, 0)) for d in kinds]
    from numba.cuda.cudadrv.devicearray import DeviceNDArray

    out = []
    for d in kinds:
        size = np.dtype(d).itemsize
        base = cuda.device_array(n * (m + 1) if layout == "coalesced" else m, dtype=d)
        strides = (size, size * (m + 1)) if layout == "coalesced" else (size, 0)
        array = DeviceNDArray((m, n), strides, d, gpu_data=base.gpu_data)
        array.base_keepalive = base  # the view does not own its memory
        out.append(array)
    return out


def registers_per_thread(kernel, layout):
    if simulator():
        return None
    try:
        for args, compiled in kernel.overloads.items():
            strided = any(getattr(t, "layout", "C") == "A" for t in args)
            if strided == (layout != "C"):
                return int(compiled.regs_per_thread)
    except Exception:  # noqa: BLE001 -- a report only
        return None
    return None


def gpu_step(table, kernel, fma, threads=128):
    """One collision of ``kernel`` (compiled with NVVM's ``-fma`` = ``fma``) from each state (a ``device`` of
    one_step_check: another compiled kernel)."""
    from coinwall.forward.dynamics.billiard import gpu
    from coinwall.forward.dynamics.billiard.kernel import compiled

    cuda = gpu.cuda_module()
    H, b0, c, cells, lookup, wmin, wmax, tol = compiled(table).args(table)

    def step(states, turns, leaving):
        m = states.shape[0]
        rows = collision_rows(cuda, m, 1, "C")
        done, status, last = (cuda.device_array(m, dtype=np.int64), cuda.device_array(m, dtype=np.int64),
                              cuda.device_array((m, 2)))
        sent = [cuda.to_device(np.ascontiguousarray(a)) for a in (states, turns, leaving, c, cells, lookup)]
        with gpu.nvvm_options(fma=fma):  # (already compiled for these types: this holds if it were not)
            kernel[(m + threads - 1) // threads, threads](*sent[:3], 1, float(H), float(b0), *sent[3:], float(wmin),
                                                          float(wmax), float(tol), *rows, done, status, last)
        host = [np.asarray(r.copy_to_host() if hasattr(r, "copy_to_host") else r)[:, 0] for r in rows]
        return np.column_stack(host[:5]), host[5], done.copy_to_host()
    return step
