"""The field kernel on a CUDA GPU: the toss's source text (:data:`.fieldkernel.FIELD_SOURCE`) compiled by numba-cuda,
one toss per thread.

The mechanism is the billiard's (:mod:`..billiard.gpu`): the same header in front of the same text, so every
``@njit`` function of the friction kernel, the contact phases and the flight loop becomes a CUDA device function,
and a launcher of a few lines (:data:`FIELD_LAUNCHER`) runs the CPU kernel's own ``_run`` in thread k on toss k:
float64 throughout, the same certified search, the same Stronge/Routh impacts with Coulomb friction, the same
Dormand–Prince contact phases with their step bounds and rolling resistance.  Nothing of the friction kernel is
left out or approximated on the GPU.  The results differ from the CPU's by rounding only (CUDA's fused
multiply-adds, its ``cos``/``sin``, :data:`..billiard.gpu.FMA`); a toss is a short chaotic orbit, so a toss whose
launch lies within rounding of a basin boundary may land on the other face on the two devices, as it may between
two CPU compilers.  In numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) the kernel text runs as Python and
gives the CPU's floats exactly: the tests compare the two record by record.
"""

from __future__ import annotations

import weakref

import numpy as np

__all__ = ["FIELD_LAUNCHER", "run_gpu"]

#: The field kernel's launchers, appended after its text: thread k runs ``_run`` on toss k, summaries only (as the
#: CPU's ``_run_many``: it reads the two shared one-element arrays for the records it never writes), or with every
#: record of toss k written to row k of the record arrays (as the CPU's ``field_run``).
FIELD_LAUNCHER = '''

@cuda.jit
def _field_gpu(states, n, H, b0, g, e, mu, rr, ceiling, catch, chatter, c, cells, lookup, wmin, wmax, tol, valleys,
               lscale, dummy_f, dummy_i, done, status, summary):
    k = cuda.grid(1)
    if k < states.shape[0]:
        d, s = _run(states[k], 0, -1, n, H, b0, g, e, mu, rr, ceiling, catch, chatter, c, cells, lookup, wmin, wmax,
                    tol, valleys, lscale, False, dummy_f, dummy_f, dummy_f, dummy_f, dummy_f, dummy_f, dummy_i,
                    summary[k])
        done[k] = d
        status[k] = s


@cuda.jit
def _field_gpu_record(states, turns, leaving, n, H, b0, g, e, mu, rr, ceiling, catch, chatter, c, cells, lookup,
                      wmin, wmax, tol, valleys, lscale, out_time, out_theta, out_eta, out_vt, out_ve, out_vx,
                      out_side, done, status, summary):
    k = cuda.grid(1)
    if k < states.shape[0]:
        d, s = _run(states[k], turns[k], leaving[k], n, H, b0, g, e, mu, rr, ceiling, catch, chatter, c, cells,
                    lookup, wmin, wmax, tol, valleys, lscale, True, out_time[k], out_theta[k], out_eta[k], out_vt[k],
                    out_ve[k], out_vx[k], out_side[k], summary[k])
        done[k] = d
        status[k] = s
'''

_MODULES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _module(wall):
    """The field kernel's CUDA module of ``wall`` (kept while the wall lives, like the CPU's)."""
    from ..billiard.gpu import gpu_module
    from .fieldkernel import FIELD_SOURCE

    module = _MODULES.get(wall)
    if module is None:
        module = _MODULES[wall] = gpu_module(wall, FIELD_SOURCE, FIELD_LAUNCHER, "coinwall_gpu_field")
    return module


def run_gpu(table, states, impacts: int, catch: bool, turns=None, leaving=None, record: bool = False) -> dict:
    """Run the field kernel on the GPU, one toss per thread, in groups that fit its memory.

    The caller checks its arguments (:func:`.field.field_run_many` does, and reduces θ to [0, 2π)).

    Parameters
    ----------
    table : FieldTable
    states : ndarray (m, 5)
        ``[θ, η, θ̇, η̇, ξ̇]`` per toss, θ in [0, 2π).
    impacts : int
        The most records per toss.
    catch : bool
        Stop each toss at its first floor contact.
    turns, leaving : ndarray (m,) of int64, optional
        With ``record``: whole turns of θ and the wall each state is on (as :func:`.field.field_run` passes them);
        without, every toss starts inside the table with no turns (as the CPU's ``_run_many``).
    record : bool
        Bring back every record (``(m, impacts)`` arrays: 49 bytes a record) as well as the summaries.

    Returns
    -------
    dict of ndarray
        ``done``, ``status`` (m,) int64 and ``summary`` (m, 9) as the CPU kernel fills them; with ``record``,
        ``time, theta, eta, v_theta, v_eta, v_xi`` (m, impacts) and ``side`` (m, impacts) int8.

    Examples
    --------
    >>> run_gpu  # doctest: +ELLIPSIS
    <function run_gpu at ...>
    """
    from ..billiard.gpu import Orbits, launch
    from .fieldkernel import _kernel

    comp = _kernel(table)
    module = _module(table.wall)
    m = states.shape[0]
    done, status, summary = np.zeros(m, dtype=np.int64), np.zeros(m, dtype=np.int64), np.zeros((m, 9))
    common = [int(impacts), *comp.args(table), bool(catch), float(table.chatter), *comp.wall_args(table)]
    ends = [Orbits(done, out=True), Orbits(status, out=True), Orbits(summary, out=True)]
    out = {"done": done, "status": status, "summary": summary}
    if not record:
        launch(module._field_gpu, [Orbits(np.ascontiguousarray(states)), *common, np.zeros(1),
                                   np.zeros(1, dtype=np.int8), *ends])
        return out
    names = ("time", "theta", "eta", "v_theta", "v_eta", "v_xi")
    for name in names:
        out[name] = np.zeros((m, impacts))
    out["side"] = np.zeros((m, impacts), dtype=np.int8)
    turns = np.zeros(m, dtype=np.int64) if turns is None else np.asarray(turns, dtype=np.int64)
    leaving = np.full(m, -1, dtype=np.int64) if leaving is None else np.asarray(leaving, dtype=np.int64)
    launch(module._field_gpu_record, [Orbits(np.ascontiguousarray(states)), Orbits(turns), Orbits(leaving), *common,
                                      *[Orbits(out[name], out=True) for name in names + ("side",)], *ends])
    return out
