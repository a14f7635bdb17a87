"""The kernels on a CUDA GPU: the same source text as on the CPU, compiled by numba-cuda, one orbit per thread.

The CPU kernel is text joined to a wall's generated code (:func:`.kernel.kernel_module`): the wall's
``wall_b1``/``wall_b2``, the certified search (``_search.py``) and the orbit loop (``_kernel.py``), each function
under an ``@njit(...)`` line.  Here the *same text* is compiled for CUDA: only the header placed before it
differs (:data:`GPU_HEADER`).  It defines ``njit`` so that each of those functions becomes a CUDA device
function (``inline='always'`` stays numba's inlining), ``prange`` as ``range`` (the CPU's parallel driver
``_run_many`` becomes an unused device function, never compiled) and the CPU kernel's way around reference
counts (``carray(_data_pointer(a), shape)``; CUDA code counts no references) as the array itself.  After the
text comes a launcher of a few lines (:data:`BILLIARD_LAUNCHER`): thread ``k`` runs ``_run`` on orbit ``k``,
writing row ``k`` of the same output arrays as the CPU's ``_run_many``.  So the GPU makes no approximation
that the CPU kernel does not make: the arithmetic is float64 throughout, the search and its certificates are
the same code.  What differs is rounding: the CUDA compiler contracts ``a·b + c`` into fused multiply-adds
(one rounding instead of two; :data:`FMA` turns that off) and the math library (``cos``, ``sin``) is CUDA's,
within an ulp or two of the CPU's (``sqrt`` and division are correctly rounded on both), so GPU and CPU agree
collision by collision to rounding, not bit for bit: :func:`.onestep.one_step_check` compares, from the same
states, the GPU's next collision with the CPU's, each held to the bound of what the kernel guarantees.

The same mechanism compiles any kernel text written this way (:func:`gpu_module`): the field kernel's text
with a launcher of its own, for instance (:func:`launch` runs any such launcher over all orbits).  What keeps a
kernel text compilable for CUDA: no allocation (``np.empty``) in a function the launcher reaches (the CPU's
``_run_many`` may allocate: it is never compiled for the GPU), no exceptions, prints or recursion, and no use
of ``math.floor`` as an integer (it returns a float on CUDA, an int on the CPU; the kernels use it in float
arithmetic only, where both give the same number).  ``tests/forward/dynamics/billiard/test_gpu.py`` has a slow
test that compiles the billiard kernel's text through NVVM for sm_90 without a GPU.

Without a GPU, numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``, set for the test run) runs the same code
path in Python, thread by thread: slow, but it executes the kernel text as the GPU would and the tests compare
it with the CPU kernel.

numba-cuda releases up to 0.30.4 register an overload of ``numpy.row_stack`` when their CUDA target is first
used, and numpy 2.5 removed that name: the first compile fails with ``AttributeError``.  :func:`cuda_module`
imports that one numba-cuda module while the name is present (as ``numpy.vstack``, what it was an alias of)
and removes the name again; nothing of numpy is changed after that.
"""

from __future__ import annotations

import contextlib
import weakref

import numpy as np

from ...errors import InvalidArgument
from ...validation import check_choice

__all__ = ["BILLIARD_LAUNCHER", "DEVICES", "FMA", "GPU_HEADER", "THREADS", "Orbits", "check_device", "cuda_module",
           "device_name", "device_status", "gpu_module", "group_collisions", "launch", "nvvm_options", "run_into",
           "run_statistics"]

#: The values of every ``device`` argument: all CPU cores (numba threads) or one CUDA GPU.
DEVICES = ("cpu", "gpu")
#: Threads per block of a launch: the kernel needs ~150 registers a thread on sm_90, so 128 threads make
#: blocks that several fit on one multiprocessor.
THREADS = 128
#: Whether CUDA's compiler may contract ``a·b + c`` into one fused multiply-add (NVVM's ``-fma``, on in CUDA by
#: default).  The CPU kernel never contracts (numba compiles it without ``fastmath``): False makes the GPU's
#: arithmetic the CPU's operation for operation, up to CUDA's ``cos``/``sin``.  Applied to the kernels that
#: :func:`launch` compiles (a kernel is compiled at its first launch and kept).
FMA = True

# The imports and the decorators the kernel text expects, for CUDA (kernel.HEADER is the CPU's).  CUDA code is
# compiled in memory in each process: CACHE (which the kernel text names) is False here, whatever the loader set
# (numba-cuda's own disk cache is not used: the kernel cache vouches for the CPU's files only).
GPU_HEADER = '''import math
import numpy as np
from numba import cuda, types

CACHE = False
OPTIONS = {'cache': CACHE, 'error_model': 'numpy'}


def njit(*args, inline="never", cache=False, parallel=False, error_model="numpy"):
    # the kernel text's @njit(...) lines, for CUDA: every function becomes a device function; numba's error model
    # on CUDA is numpy's already, and `parallel`/`cache` have no meaning there
    def device(func):
        return cuda.jit(device=True, inline=inline)(func)
    return device(args[0]) if args else device


prange = range


@cuda.jit(device=True, inline="always")
def _as_is(a):
    return a


def intrinsic(func):
    # the CPU kernel rebuilds its arrays without a reference count (carray(_data_pointer(a), shape));
    # CUDA code counts no references: both are the array itself
    return _as_is


@cuda.jit(device=True, inline="always")
def carray(a, shape):
    return a

'''

#: The billiard's launcher, appended after the kernel text: thread k runs the CPU kernel's ``_run`` on orbit k;
#: and two small kernels that reduce the collisions to what statistics of many orbits need
#: (:func:`run_statistics`), so that those stay on the GPU.
BILLIARD_LAUNCHER = '''

@cuda.jit
def _run_gpu(states, turns, leaving, n, H, b0, c, cells, lookup, wmin, wmax, tol,
             out_time, out_theta, out_eta, out_vt, out_ve, out_side, done, status, last):
    k = cuda.grid(1)
    if k < states.shape[0]:
        d, s = _run(states[k], turns[k], leaving[k], n, H, b0, c, cells, lookup, wmin, wmax, tol,
                    out_time[k], out_theta[k], out_eta[k], out_vt[k], out_ve[k], out_side[k], last[k])
        done[k] = d
        status[k] = s


@cuda.jit
def _summarise(time, eta, vt, ve, side, done, final, side_last, bottom):
    # per orbit, what statistics of many orbits keep of its collisions: the last one (time, η, v) and its wall,
    # and how many were on the bottom wall (run_statistics: only these come back from the GPU)
    k = cuda.grid(1)
    if k < done.shape[0]:
        d = done[k]
        count = 0
        for i in range(d):
            if side[k, i] == 0:
                count += 1
        bottom[k] = count
        side_last[k] = -1
        for i in range(4):
            final[k, i] = 0.0
        if d > 0:
            final[k, 0] = time[k, d - 1]
            final[k, 1] = eta[k, d - 1]
            final[k, 2] = vt[k, d - 1]
            final[k, 3] = ve[k, d - 1]
            side_last[k] = side[k, d - 1]


@cuda.jit
def _count_below(time, done, speed, limit, counts):
    # per orbit, its collisions at times (time / speed: the start speed's) up to the limit
    k = cuda.grid(1)
    if k < done.shape[0]:
        count = 0
        for i in range(done[k]):
            if time[k, i] / speed[k] <= limit:
                count += 1
        counts[k] = count
'''

_CUDA = []  # numba.cuda, once imported (with the numpy guard of the module docstring)


def cuda_module():
    """``numba.cuda``, imported once, with the guard for numpy 2.5 (module docstring).

    Returns
    -------
    module
        ``numba.cuda`` (the simulator when ``NUMBA_ENABLE_CUDASIM=1``).

    Raises
    ------
    ImportError
        numba-cuda is not installed.

    Examples
    --------
    >>> cuda = cuda_module()  # doctest: +SKIP
    """
    if _CUDA:
        return _CUDA[0]
    from numba import config, cuda

    if not config.ENABLE_CUDASIM:
        _hook_nvvm()
    if not config.ENABLE_CUDASIM and not hasattr(np, "row_stack"):
        # numba-cuda <= 0.30.4 evaluates np.row_stack when its target loads this module (removed in numpy 2.5)
        np.row_stack = np.vstack
        try:
            import numba.cuda.np.arrayobj  # noqa: F401
        except ImportError:  # a numba-cuda without this module has no such overload either
            pass
        finally:
            del np.row_stack
    _CUDA.append(cuda)
    return cuda


_NVVM_EXTRA: dict = {}  # NVVM options added to each CUDA compile while set (nvvm_options)


def _hook_nvvm():
    """Let :func:`nvvm_options` reach NVVM: numba-cuda passes it only ``opt`` and (for fastmath) ``fma``/``ftz``/
    ``prec_*``, whatever the launcher asks; its code generator calls ``nvvm.compile_ir`` through the module, so a
    wrapper there sees every compile."""
    from numba.cuda.cudadrv import nvvm

    if getattr(nvvm.compile_ir, "coinwall_hook", False):
        return
    original = nvvm.compile_ir

    def compile_ir(llvmir, **options):
        return original(llvmir, **{**options, **_NVVM_EXTRA})

    compile_ir.coinwall_hook = True
    nvvm.compile_ir = compile_ir


@contextlib.contextmanager
def nvvm_options(**options):
    """NVVM options (``fma=False``: ``-fma=0``) for the CUDA kernels compiled inside the ``with`` block.

    A kernel is compiled at its first launch (and kept): launch it inside the block.  The simulator compiles
    nothing and ignores them.

    Parameters
    ----------
    **options
        NVVM's option names without the dash (booleans as 0/1), e.g. ``fma=False``.

    Returns
    -------
    context manager

    Examples
    --------
    >>> with nvvm_options(fma=False):
    ...     pass
    """
    previous = dict(_NVVM_EXTRA)
    _NVVM_EXTRA.update(options)
    try:
        yield
    finally:
        _NVVM_EXTRA.clear()
        _NVVM_EXTRA.update(previous)


def device_status() -> str:
    """Why ``device="gpu"`` cannot run here, in one line; ``""`` when it can.

    Returns
    -------
    str
        Empty when numba-cuda is installed and sees a CUDA GPU (or its simulator is on), else the reason.

    Examples
    --------
    >>> isinstance(device_status(), str)
    True
    """
    from ...display import one_line

    try:
        cuda = cuda_module()
    except ImportError as exc:
        return f"numba-cuda is not installed ({exc}); install it with: pip install 'coinwall[gpu]'"
    from numba import config

    if config.ENABLE_CUDASIM:
        return ""
    try:
        if cuda.is_available() and len(cuda.gpus) > 0:
            return ""
        driver = cuda.cudadrv.driver.driver
        why = getattr(driver, "initialization_error", None) or "the CUDA driver reports no device"
    except Exception as exc:  # noqa: BLE001 -- whatever the driver layer raises, the answer is "not here"
        why = str(exc)
    return f"no CUDA GPU is usable here ({one_line(str(why))})"


def check_device(device) -> str:
    """Check a ``device`` argument: one of :data:`DEVICES`, and for ``"gpu"`` a GPU that can run.

    Parameters
    ----------
    device : {"cpu", "gpu"}

    Returns
    -------
    str
        ``device``.

    Raises
    ------
    InvalidArgument
        An unknown device, or ``"gpu"`` where numba-cuda or a CUDA GPU is missing (the message says which).

    Examples
    --------
    >>> check_device("cpu")
    'cpu'
    """
    check_choice("device", device, DEVICES)
    if device == "gpu":
        why = device_status()
        if why:
            raise InvalidArgument(f"`device` = 'gpu' cannot run: {why}")
    return device


def device_name() -> str:
    """The GPU's name and compute capability as numba-cuda reports them (``"simulator"`` in the simulator).

    Returns
    -------
    str

    Examples
    --------
    >>> device_name()  # doctest: +SKIP
    'NVIDIA H100 80GB HBM3 (compute capability 9.0)'
    """
    from numba import config

    cuda = cuda_module()
    if config.ENABLE_CUDASIM:
        return "simulator"
    dev = cuda.get_current_device()
    name = dev.name.decode() if isinstance(dev.name, bytes) else str(dev.name)
    return f"{name} (compute capability {dev.compute_capability[0]}.{dev.compute_capability[1]})"


def gpu_module(wall, kernel_source: str, launcher: str, prefix: str):
    """The module of one kernel text for CUDA: :data:`GPU_HEADER`, the wall's code, the search, the kernel and the
    launcher.

    The CPU's :func:`.kernel.kernel_module` joins the same texts after its own header.

    Parameters
    ----------
    wall : Wall
        The wall whose generated code (:func:`.wallcode.wall_source`) is placed first.
    kernel_source : str
        The kernel's text (:data:`.kernel.KERNEL_SOURCE`, or the field kernel's).
    launcher : str
        The CUDA kernel(s) that call the kernel text's functions, one orbit per thread.
    prefix : str
        The module name's prefix (:func:`.wallcode.load_module`).

    Returns
    -------
    module
        The loaded module (its functions compile for the GPU on first launch).

    Examples
    --------
    >>> from coinwall.forward import Wall
    >>> from coinwall.forward.dynamics.billiard.kernel import KERNEL_SOURCE
    >>> module = gpu_module(Wall.from_fourier(1.0, [0.1]), KERNEL_SOURCE, BILLIARD_LAUNCHER, "coinwall_gpu")
    >>> hasattr(module, "_run_gpu")
    True
    """
    from .kernel import SEARCH_SOURCE
    from .wallcode import load_module, wall_source

    cuda_module()  # the guard runs before the text imports numba.cuda
    source, _ = wall_source(wall, "@njit(**OPTIONS)\n")
    return load_module(GPU_HEADER + source + SEARCH_SOURCE + kernel_source + launcher, prefix)


_MODULES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _billiard_module(wall):
    """The billiard kernel's CUDA module of ``wall`` (kept while the wall lives, like the CPU's)."""
    from .kernel import KERNEL_SOURCE

    module = _MODULES.get(wall)
    if module is None:
        module = _MODULES[wall] = gpu_module(wall, KERNEL_SOURCE, BILLIARD_LAUNCHER, "coinwall_gpu")
    return module


def group_collisions(on_host: bool = True) -> int:
    """How many collisions the analyses that follow orbits in groups (sections, P(n), statistics) hold at once on
    the GPU.

    On the CPU they hold 2·10^6 (82 MB at 41 bytes a collision: the cores are busy with a group of any size).
    A GPU needs 10^4–10^5 orbits in one launch to be busy, so its groups are up to 2^26 collisions (2.8 GB), as
    far as 1/(8·141 bytes) of the available memory allows (an analysis holds up to ~141 bytes per collision of a
    group while it reads it) and half the GPU's free memory at 41 bytes a collision.  With ``on_host=False`` the
    collisions stay on the GPU (:func:`run_statistics`: the host keeps ~80 bytes per orbit), so only the GPU's
    memory bounds the group, up to 2^28 collisions (11 GB; 2^18 orbits of 1024 collisions: ~5 waves of blocks on
    an H100, where fewer leave the last wave's tail a larger share).

    Parameters
    ----------
    on_host : bool
        Whether the group's collisions are brought to the host.

    Returns
    -------
    int

    Examples
    --------
    >>> group_collisions() >= 2_000_000
    True
    """
    from ...validation import available_memory

    on_gpu = _free_bytes(cuda_module()) / (2 * 41)
    if not on_host:
        return int(max(2_000_000, min(2 ** 28, on_gpu)))
    return int(max(2_000_000, min(2 ** 26, available_memory() / (8 * 141), on_gpu)))


def _free_bytes(cuda) -> float:
    """Free memory on the GPU (the simulator: a fixed 1 GiB)."""
    from numba import config

    if config.ENABLE_CUDASIM:
        return float(2 ** 30)
    free, _total = cuda.current_context().get_memory_info()
    return float(free)


def run_into(table, states, turns, leaving, n, rows, done, status, last, threads=THREADS):
    """Run the billiard kernel on the GPU for each state, into the host arrays the CPU's ``_run_many`` fills.

    The orbits go to the GPU in groups whose arrays take at most half of its free memory; each group is
    copied in, launched (thread k: orbit k) and copied back into its rows.

    Parameters
    ----------
    table : Billiard
        The table (its wall's cell table is :func:`.kernel.compiled`'s, shared with the CPU kernel).
    states : ndarray (m, 4)
        Unit-speed states with θ in [0, 2π).
    turns, leaving : ndarray (m,) of int64
        Whole turns of θ, and the wall each state is on (−1: none).
    n : int
        Collisions per orbit.
    rows : list of six ndarray (m, n) or None
        time, θ, η, v_θ, v_η (float64) and side (int8), filled; None for one that the caller does not read (it
        stays on the GPU and is not copied: 8 bytes a collision fewer to bring back).
    done, status : ndarray (m,) of int64
        Collisions computed and the stop code per orbit, filled.
    last : ndarray (m, 2)
        θ mod 2π and its turns after the last collision, filled.
    threads : int
        Threads per block.

    Returns
    -------
    None

    Examples
    --------
    >>> # as kernel.run_many(..., device="gpu") calls it (needs a GPU or the simulator)
    >>> run_into  # doctest: +ELLIPSIS
    <function run_into at ...>
    """
    from .kernel import compiled

    module = _billiard_module(table.wall)
    H, b0, c, cells, lookup, wmin, wmax, tol = compiled(table).args(table)
    m = states.shape[0]
    kinds = [np.float64] * 5 + [np.int8]
    outs = [Orbits(r, out=True) if r is not None else Orbits(np.broadcast_to(np.zeros((), d), (m, n)), out="gpu")
            for r, d in zip(rows, kinds)]
    launch(module._run_gpu, [Orbits(states), Orbits(turns), Orbits(leaving), n, float(H), float(b0), c, cells, lookup,
                             float(wmin), float(wmax), float(tol), *outs, Orbits(done, out=True),
                             Orbits(status, out=True), Orbits(last, out=True)], threads)


def run_statistics(table, states, turns, leaving, n, speed, window, threads=THREADS) -> dict:
    """Run the billiard kernel on the GPU for each state and bring back per-orbit summaries only.

    The collisions stay on the GPU (41 bytes each); what comes back is ~80 bytes per orbit: how many collisions
    were computed and why an orbit stopped, the last one (time, η, v_θ, v_η, its wall, θ mod 2π with its turns),
    the number on the bottom wall, and the number at times up to a limit that ``window`` computes from the last
    times (the counts in a common window of :func:`.orbitstats.ensemble_statistics`).  The caller sizes the group
    (:func:`group_collisions`): all its collisions are held on the GPU at once.

    Parameters
    ----------
    table : Billiard
    states : ndarray (m, 4)
        Unit-speed states with θ in [0, 2π).
    turns, leaving : ndarray (m,) of int64
        Whole turns of θ, and the wall each state is on (−1: none).
    n : int
        Collisions per orbit.
    speed : ndarray (m,)
        The start speed of each orbit: its times are the kernel's divided by it.
    window : callable or None
        ``window(last_time, done)`` (kernel times of the last collisions, collisions per orbit) → the limit of
        the times counted, or None for no counts.
    threads : int
        Threads per block.

    Returns
    -------
    dict
        ``done``, ``status`` (m,) int64; ``last`` (m, 2) θ mod 2π and turns after the last collision; ``final``
        (m, 4) time, η, v_θ, v_η of the last collision; ``side`` (m,) int8 its wall (−1: none); ``bottom`` (m,)
        int64; ``counts`` (m,) int64 or None.

    Examples
    --------
    >>> run_statistics  # doctest: +ELLIPSIS
    <function run_statistics at ...>
    """
    from .kernel import compiled

    cuda = cuda_module()
    module = _billiard_module(table.wall)
    H, b0, c, cells, lookup, wmin, wmax, tol = compiled(table).args(table)
    m = states.shape[0]
    blocks = (m + threads - 1) // threads
    rows = [cuda.device_array((m, n)) for _ in range(5)] + [cuda.device_array((m, n), dtype=np.int8)]
    done, status, last = (cuda.device_array(m, dtype=np.int64), cuda.device_array(m, dtype=np.int64),
                          cuda.device_array((m, 2)))
    sent = [cuda.to_device(np.ascontiguousarray(a)) for a in (states, turns, leaving)]
    with nvvm_options(fma=FMA):
        module._run_gpu[blocks, threads](*sent, n, float(H), float(b0), cuda.to_device(c), cuda.to_device(cells),
                                         cuda.to_device(lookup), float(wmin), float(wmax), float(tol), *rows, done,
                                         status, last)
    final, side, bottom = cuda.device_array((m, 4)), cuda.device_array(m, dtype=np.int8), cuda.device_array(
        m, dtype=np.int64)
    module._summarise[blocks, threads](rows[0], rows[2], rows[3], rows[4], rows[5], done, final, side, bottom)
    out = {"done": done.copy_to_host(), "status": status.copy_to_host(), "last": last.copy_to_host(),
           "final": final.copy_to_host(), "side": side.copy_to_host(), "bottom": bottom.copy_to_host(), "counts": None}
    limit = None if window is None else window(out["final"][:, 0], out["done"])
    if limit is not None:
        counts = cuda.device_array(m, dtype=np.int64)
        module._count_below[blocks, threads](rows[0], done, cuda.to_device(np.ascontiguousarray(speed, dtype=float)),
                                             float(limit), counts)
        out["counts"] = counts.copy_to_host()
    return out


class Orbits:
    """An argument of :func:`launch` with one row per orbit: sent to the GPU in the launch's groups (``out=False``),
    filled there and copied back into the host array's rows (``out=True``), or filled there and left there
    (``out="gpu"``: ``host`` gives only the shape and dtype, e.g. ``numpy.broadcast_to`` of a scalar)."""

    def __init__(self, host, out=False):
        self.host, self.out = host, out


def launch(kernel, args, threads: int = THREADS) -> None:
    """Launch a CUDA ``kernel`` of one orbit per thread over all orbits, in groups that fit the GPU's memory.

    Parameters
    ----------
    kernel : numba.cuda dispatcher
        Thread k works on row k of every :class:`Orbits` argument.
    args : list
        The kernel's arguments in order: :class:`Orbits` (host arrays with one row per orbit, the same number of
        rows each), arrays shared by all orbits (sent once) and scalars.
    threads : int
        Threads per block.

    Returns
    -------
    None
        The ``out=True`` arrays are filled.

    Examples
    --------
    >>> launch  # doctest: +ELLIPSIS
    <function launch at ...>
    """
    cuda = cuda_module()
    rows = [a for a in args if isinstance(a, Orbits)]
    m = rows[0].host.shape[0]
    per_orbit = sum(a.host.nbytes for a in rows) / max(m, 1) + 64.0
    group = int(max(1, min(m, 0.5 * _free_bytes(cuda) // per_orbit)))
    shared = [cuda.to_device(np.ascontiguousarray(a)) if isinstance(a, np.ndarray) else a for a in args]
    for first in range(0, m, group):
        part = slice(first, min(m, first + group))
        k = part.stop - part.start
        sent = [(cuda.device_array((k,) + a.host.shape[1:], dtype=a.host.dtype) if a.out
                 else cuda.to_device(np.ascontiguousarray(a.host[part]))) if isinstance(a, Orbits) else d
                for a, d in zip(args, shared)]
        with nvvm_options(fma=FMA):  # (compiled at the first launch)
            kernel[(k + threads - 1) // threads, threads](*sent)
        for a, d in zip(args, sent):
            if isinstance(a, Orbits) and a.out is True:
                d.copy_to_host(a.host[part])
