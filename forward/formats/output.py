"""File output shared by every writer: all or nothing, through temporary files renamed at the end.

Outputs are checked before any work (:func:`check_paths`, :func:`prepare_folder`): a bad name fails
before a long computation, and missing folders are created only once every name is known to be
good.  :func:`write_all` then writes every file or none, and says which ones replaced a file.
"""

import os
import tempfile

from ..errors import OutputError

__all__ = ["Written", "check_paths", "default_file_mode", "existing_files", "prepare_folder", "write_all"]


class Written(list):
    """The paths :func:`write_all` wrote, in order (a ``list``), with :attr:`replaced`.

    Attributes
    ----------
    replaced : tuple of str
        The paths that replaced an existing file.
    """

    def __init__(self, paths=(), replaced=()):
        super().__init__(paths)
        self.replaced = tuple(replaced)


def _missing_folders(folder: str) -> list:
    """The folders from ``folder`` up to the first existing ancestor, which must be a writable folder.

    Returns the missing ones, outermost first (the order to create them in).

    Raises
    ------
    OutputError
        If an ancestor is a file, or the first existing ancestor is not writable.
    """
    missing = []
    current = os.path.abspath(folder)
    while not os.path.isdir(current):
        if os.path.lexists(current):
            raise OutputError(f"{current!r} is not a folder")
        missing.append(current)
        parent = os.path.dirname(current)
        if parent == current:  # only reached for a root that does not exist
            break
        current = parent
    if not os.access(current, os.W_OK):
        if missing:
            raise OutputError(f"folder {os.path.abspath(folder)!r} does not exist and cannot be created "
                              f"({current!r} is not writable)")
        raise OutputError(f"folder {current!r} is not writable")
    return missing[::-1]


def _create(folders) -> None:
    for folder in folders:
        try:
            os.makedirs(folder, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"cannot create folder {folder!r}: {exc.strerror or exc}") from None


def check_paths(paths, allowed) -> None:
    """Before any work: every output has an extension in ``allowed`` and a place to go.

    Every path is checked first (extension, not a folder, an existing file writable, a folder that
    exists or can be created); only then are missing folders created, so a bad name anywhere in
    ``paths`` creates nothing.

    Raises
    ------
    OutputError
        Naming the first bad path.
    """
    to_create = []
    for path in paths:
        ext = os.path.splitext(path)[1].lower()
        if ext not in allowed:
            raise OutputError(f"output {path!r}: unknown extension {ext or '(none)'!r}; known: {', '.join(allowed)}")
        if os.path.isdir(path):
            raise OutputError(f"output {path!r} is a folder, not a file")
        if os.path.exists(path) and not os.access(path, os.W_OK):
            raise OutputError(f"output {path!r}: the existing file is not writable")
        try:
            to_create += _missing_folders(os.path.dirname(os.path.abspath(path)))
        except OutputError as exc:
            raise OutputError(f"output {path!r}: {exc}") from None
    _create(dict.fromkeys(to_create))


def prepare_folder(folder: str) -> str:
    """Make sure the output folder ``folder`` exists and is writable, creating it (and its parents)
    when missing; returns ``folder``.

    Raises
    ------
    OutputError
        If ``folder`` or one of its parents is a file, or it cannot be created or written to.
    """
    try:
        _create(_missing_folders(folder))
    except OutputError as exc:
        raise OutputError(f"output folder {folder!r}: {exc}") from None
    if not os.access(folder, os.W_OK):
        raise OutputError(f"output folder {folder!r} is not writable")
    return folder


def existing_files(paths) -> tuple:
    """The paths among ``paths`` that exist now, i.e. that writing them would replace."""
    return tuple(path for path in paths if os.path.isfile(path))


def default_file_mode() -> int:
    """The mode a plain ``open(path, "w")`` would give (0o666 minus the umask).

    ``tempfile.mkstemp`` creates files readable by their owner only; outputs renamed from such a
    temporary file would otherwise surprise users (and web servers) with mode 0600.
    """
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def write_all(files) -> Written:
    """Write ``{path: bytes}`` all or nothing: every file goes to a temporary file in its own
    folder first, and all are renamed only when every one was written.

    Returns
    -------
    Written
        The paths (a list, in the order given), with ``replaced``: those that replaced a file.

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
        replaced = existing_files(files)  # looked up last, just before the renames
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
    return Written(files, replaced)
