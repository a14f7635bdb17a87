"""Exporters of solved bodies, chosen by file extension.

Every module in this package that defines ``EXTENSION`` and ``write(body, stream)``
is an exporter: adding a format (DXF, say) is adding one module.  Files are
written atomically: all outputs go to temporary files first and are renamed
only when every one of them succeeded, so a failure leaves nothing behind.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import tempfile

from forward.errors import OutputError

__all__ = ["exporters", "check_outputs", "write_outputs"]


def exporters() -> dict:
    """Map of extension (``".svg"``) to exporter module, discovered from this package."""
    found = {}
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        ext = getattr(module, "EXTENSION", None)
        if ext and callable(getattr(module, "write", None)):
            found[ext] = module
    return found


def check_outputs(paths) -> list:
    """Validate output paths before any work: known extension, existing writable folder."""
    known = exporters()
    checked = []
    for path in paths:
        ext = os.path.splitext(path)[1].lower()
        if ext not in known:
            raise OutputError(f"output {path!r}: unknown extension {ext or '(none)'!r}; "
                              f"known: {', '.join(sorted(known))}")
        folder = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(folder):
            raise OutputError(f"output {path!r}: folder {folder!r} does not exist")
        if not os.access(folder, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
            raise OutputError(f"output {path!r}: not writable")
        if os.path.isdir(path):
            raise OutputError(f"output {path!r} is a folder")
        checked.append((path, known[ext]))
    return checked


def write_outputs(body, paths) -> list:
    """Write ``body`` to every path (format by extension), all or nothing."""
    checked = check_outputs(paths)
    temps = []
    try:
        for path, module in checked:
            folder = os.path.dirname(os.path.abspath(path))
            fd, temp = tempfile.mkstemp(prefix=".coinwall-", suffix=os.path.splitext(path)[1], dir=folder)
            temps.append(temp)
            with os.fdopen(fd, "wb") as stream:
                module.write(body, stream)
        for (path, _), temp in zip(checked, temps):
            os.replace(temp, path)
        temps = []
    except OSError as exc:
        raise OutputError(f"cannot write output: {exc}") from None
    finally:
        for temp in temps:
            try:
                os.unlink(temp)
            except OSError:
                pass
    return [p for p, _ in checked]
