"""The field kernel's text and its compiled module per wall: what :mod:`.field` calls.

The kernel is three texts, each the part after a marker line of its file: the friction kernel (the impact with
friction and the helpers of the contact phases, :mod:`._friction_kernel`), the contact phase
(:mod:`._contact_kernel`) and the flight loop (:mod:`._field_kernel`).  They are joined after the wall's generated
code and the search the billiard kernel compiles too (:func:`.kernel.kernel_module`) and loaded as one module
per wall structure (numba's cache finds its machine code again in the next process).
"""

from __future__ import annotations

from ...wall import Wall
from ..billiard.kernel import source_after_marker

__all__ = ["FIELD_SOURCE"]

_MARKER = ("# ---- field kernel: the text from the line after this one to the end of the file is joined to the "
           "wall code ----\n")
_FRICTION_MARKER = ("# ---- friction kernel: the text from the line after this one to the end of the file is joined "
                    "to the field kernel ----\n")
_CONTACT_MARKER = ("# ---- contact kernel: the text from the line after this one to the end of the file is joined "
                   "to the field kernel ----\n")
FIELD_SOURCE = (source_after_marker(__package__, "_friction_kernel.py", _FRICTION_MARKER)
                + source_after_marker(__package__, "_contact_kernel.py", _CONTACT_MARKER)
                + source_after_marker(__package__, "_field_kernel.py", _MARKER))


class _FieldKernel:
    def __init__(self, wall: Wall):
        from ..billiard.kernel import compiled, kernel_module

        base = compiled(_WallHolder(wall))  # the billiard's constants and cell bounds of this wall (kept per wall)
        # the wall's code, the search the billiard kernel compiles too (_search.py), then this kernel's text
        self.module, _ = kernel_module(wall, FIELD_SOURCE, "coinwall_field")
        self.constants, self.bounds, self.cells = base.constants, base.bounds, base.cells

    def call(self, name, *args):
        return getattr(self.module, name)(*args)

    def args(self, table):
        H = float(table.H) if table.H is not None else 0.0
        return (H, float(table.b0), float(table.g), float(table.e), float(table.mu), float(table.rolling),
                table.H is not None)

    def wall_args(self, table):
        bd = self.bounds
        return (self.constants, self.cells, bd["lookup"], bd["wmin"], bd["wmax"], float(table.tol),
                table.landscape.table, max(1.0, float(table.wall.scale)))


class _WallHolder:
    # kernel.compiled() keys its cache on ``table.wall``
    def __init__(self, wall):
        self.wall = wall


_FIELD_KERNELS: dict = {}


def _kernel(table) -> _FieldKernel:
    import weakref

    global _FIELD_KERNELS
    if not isinstance(_FIELD_KERNELS, weakref.WeakKeyDictionary):
        _FIELD_KERNELS = weakref.WeakKeyDictionary()
    comp = _FIELD_KERNELS.get(table.wall)
    if comp is None:
        comp = _FIELD_KERNELS[table.wall] = _FieldKernel(table.wall)
    return comp
