"""File output shared by every writer: all or nothing, through temporary files renamed at the end."""

import os
import tempfile

from ..errors import OutputError

__all__ = ["check_paths", "default_file_mode", "write_all"]


def check_paths(paths, allowed) -> None:
    """Before any work: every output has an extension in ``allowed`` and a writable folder.

    Raises
    ------
    OutputError
        Naming the first bad path.
    """
    for path in paths:
        ext = os.path.splitext(path)[1].lower()
        if ext not in allowed:
            raise OutputError(f"output {path!r}: unknown extension {ext or '(none)'!r}; known: {', '.join(allowed)}")
        folder = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(folder) or not os.access(folder, os.W_OK):
            raise OutputError(f"output {path!r}: folder {folder!r} does not exist or is not writable")


def default_file_mode() -> int:
    """The mode a plain ``open(path, "w")`` would give (0o666 minus the umask).

    ``tempfile.mkstemp`` creates files readable by their owner only; outputs renamed from such a
    temporary file would otherwise surprise users (and web servers) with mode 0600.
    """
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def write_all(files) -> list:
    """Write ``{path: bytes}`` all or nothing: every file goes to a temporary file in its own
    folder first, and all are renamed only when every one was written.  Returns the paths.

    Raises
    ------
    OutputError
        If any file cannot be written; no output and no temporary file is left behind.
    """
    temps = []
    try:
        for path, data in files.items():
            fd, temp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(path)), prefix=".coinwall-",
                                        suffix=os.path.splitext(path)[1])
            os.fchmod(fd, default_file_mode())
            temps.append((temp, path))
            with os.fdopen(fd, "wb") as fh:
                fh.write(data)
        for temp, path in temps:
            os.replace(temp, path)
        temps = []
    except OSError as exc:
        raise OutputError(f"cannot write output: {exc.strerror or exc}") from None
    finally:
        for temp, _ in temps:
            try:
                os.unlink(temp)
            except OSError:
                pass
    return list(files)
