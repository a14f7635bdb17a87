"""Every file coinwall writes, written all or nothing: the one writer.

:func:`write_all` writes each file to a temporary file in the target's own folder (:func:`tempfile.mkstemp`:
a name no other file has, on the same filesystem, so that the rename is atomic), gives it the mode and
owner of the file it replaces (a new file gets the mode of a plain ``open(path, "w")``), and only once
every temporary is complete renames them over their targets with :func:`os.replace`.  Missing folders
are made at that moment, and only then: an output folder never exists without its content.  Whatever
goes wrong (a full disk, bad input found late, Ctrl-C) the ``finally`` clause removes the temporaries and
the folders made, so nothing half-written and nothing of ours is left, and no file of the user's is
touched.  The scan store (:func:`new_folder`) and the kernel cache use the same writer.

The renames (the commit) are all or nothing as well: when several files replace existing ones, each
existing file first gets a second name (a hard link, or a copy), so that a rename that fails puts back
what the earlier ones replaced; those names are removed at the end either way.  A signal with a Python
handler (Ctrl-C's ``KeyboardInterrupt``, and the command line's SIGTERM and SIGHUP, which
:func:`coinwall.cases.cli.main.main` turns into a normal exit) is handled after the commit, which takes a
few system calls.  A SIGKILL or a power cut cannot be caught: it can leave a ``.coinwall-*.tmp`` file
beside an output (remove it by hand), or, during the commit, some outputs old and some new, each whole.

:func:`check_paths` applies the same rules to the outputs before a long computation, so that a bad name
fails in a second; :func:`command_scope` (the span of one command) refuses an output that is one of the
command's input files.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import secrets
import shutil
import signal
import stat
import tempfile
import threading

from ..errors import OutputError

__all__ = ["Written", "check_folder", "check_paths", "command_scope", "default_file_mode", "existing_files",
           "new_folder", "note_input", "refuse_non_finite", "transaction", "write_all"]

_PREFIX, _SUFFIX = ".coinwall-", ".tmp"  # the temporaries: .coinwall-<8 random characters>.tmp
_TEMP_LENGTH = len(_PREFIX) + 8 + len(_SUFFIX)
_BATCH = contextvars.ContextVar("coinwall_output_batch", default=None)
# inside command_scope (the command line): {(st_dev, st_ino): name} of the input files read or named
_INPUTS = contextvars.ContextVar("coinwall_inputs", default=None)
# the signals whose Python handler waits for the end of a commit
_HELD = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


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


def _short(path: str, limit: int = 80) -> str:
    return repr(path) if len(path) <= limit else repr(path[:limit // 2]) + "…" + repr(path[-limit // 2:])


def _missing_folders(folder: str) -> list:
    """The folders from ``folder`` up to the first existing one, outermost first (the order to make them in).

    Raises
    ------
    OutputError
        If a level is a file, or the first existing folder is not writable.
    """
    missing, current = [], os.path.abspath(folder)
    while not os.path.isdir(current):
        if os.path.lexists(current):
            raise OutputError(f"{current!r} is not a folder")
        missing.append(current)
        if os.path.dirname(current) == current:  # a root that does not exist
            break
        current = os.path.dirname(current)
    if not os.access(current, os.W_OK | os.X_OK):
        raise OutputError(f"folder {os.path.abspath(folder)!r} does not exist and cannot be created ({current!r} is "
                          "not writable)" if missing else f"folder {current!r} is not writable")
    return missing[::-1]


def _check_length(path: str, existing: str) -> None:
    """Refuse a name the filesystem of the folder ``existing`` cannot hold (a component or the whole path too
    long, with its temporary), before any folder is made for it."""
    def limit(name, default):
        with contextlib.suppress(OSError, ValueError, AttributeError):
            value = os.pathconf(existing, name)
            return value if value > 0 else default
        return default

    name_max, path_max = limit("PC_NAME_MAX", 255), limit("PC_PATH_MAX", 4096)
    full = os.path.abspath(path)
    for part in full.split(os.sep):
        if len(os.fsencode(part)) > name_max:
            raise OutputError(f"output {_short(path)}: the name {_short(part, 40)} is {len(os.fsencode(part))} bytes "
                              f"long, more than the {name_max} this filesystem allows")
    longest = len(os.fsencode(os.path.dirname(full))) + 1 + max(len(os.fsencode(os.path.basename(full))), _TEMP_LENGTH)
    if longest >= path_max:
        raise OutputError(f"output {_short(path)}: the path is {longest} bytes long (with its temporary), more than "
                          f"the {path_max - 1} this system allows; choose a shorter one")


def _check_target(path: str) -> list:
    """The rules for one output, checked before the work (:func:`check_paths`) and again when it is written:
    a name the filesystem holds, a folder that exists or can be made, nothing there but a writable regular
    file, and not an input of the running command.  Returns the missing folders (outermost first)."""
    try:
        folder = os.path.dirname(os.path.abspath(path))
        missing = _missing_folders(folder)
    except OutputError as exc:
        raise OutputError(f"output {path!r}: {exc}") from None
    except ValueError:  # a NUL byte
        raise OutputError(f"output {path!r} is not a valid file name") from None
    _check_length(path, os.path.dirname(missing[0]) if missing else folder)
    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return missing
    if stat.S_ISDIR(info.st_mode):
        raise OutputError(f"output {path!r} is a folder, not a file; nothing was written")
    if not stat.S_ISREG(info.st_mode):
        from .inputfile import file_kind

        kind = "a symbolic link" if stat.S_ISLNK(info.st_mode) else file_kind(info.st_mode)
        raise OutputError(f"output {path!r} is {kind}, not a regular file; coinwall replaces only regular files: "
                          "give the name of a new or a regular file")
    if not os.access(path, os.W_OK):
        raise OutputError(f"output {path!r}: the existing file is not writable")
    name = _same_as_input(path)
    if name is not None:
        same = "" if os.path.abspath(name) == os.path.abspath(path) else f" (the input {name!r})"
        raise OutputError(f"output {path!r} is an input file of this command{same}; writing it would replace the "
                          "input: choose another name")
    return missing


def check_paths(paths, allowed=None, inputs=()) -> None:
    """Before any work: every output has an extension in ``allowed`` and can be written.

    The rules are :func:`write_all`'s (a name the filesystem holds, a folder that exists or can be made,
    nothing in the way but a writable regular file, not an input of the command: ``inputs`` and, inside
    :func:`command_scope`, the files it read or names), and two names of one file are refused.  Nothing
    is created: the folders are made when the files are written.

    Parameters
    ----------
    paths : list of str
        The outputs.
    allowed : sequence of str, optional
        The extensions accepted (lower case, with the dot); any when None.
    inputs : sequence of str
        Input files that no output may be.

    Raises
    ------
    OutputError
        Naming the first bad path.

    Examples
    --------
    >>> check_paths(["body.json"], (".json", ".svg"))
    >>> check_paths(["body.gif"], (".json", ".svg"))
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.OutputError: output 'body.gif': unknown extension '.gif'; known: .json, .svg
    """
    seen = {}
    for path in paths:
        ext = os.path.splitext(path)[1].lower()
        if allowed is not None and ext not in allowed:
            raise OutputError(f"output {path!r}: unknown extension {ext or '(none)'!r}; known: {', '.join(allowed)}")
        _check_target(path)
        for name in inputs:
            if os.path.exists(path) and os.path.exists(name) and os.path.samefile(path, name):
                raise OutputError(f"output {path!r} is an input file of this command; writing it would replace "
                                  "the input: choose another name")
        same = os.path.realpath(path)  # a.csv and ./a.csv: the first copy would be lost
        if seen.setdefault(same, path) != path:
            raise OutputError(f"output {path!r} is the same file as {seen[same]!r}")


def check_folder(folder: str) -> str:
    """Before any work: ``folder`` is a folder that exists and is writable, or can be made; returns it.

    Nothing is created (:func:`write_all` makes the folder with its files).

    Raises
    ------
    OutputError
        If ``folder`` or a level above it is a file, or it cannot be written or made.
    """
    try:
        _missing_folders(folder)
    except OutputError as exc:
        raise OutputError(f"output folder {folder!r}: {exc}") from None
    return folder


@contextlib.contextmanager
def command_scope(inputs=()):
    """The span of one command: the files in ``inputs`` and every input file read inside it
    (:func:`note_input`) cannot be outputs of it (``coinwall solve wall.csv -o wall.csv`` is refused instead
    of replacing the data it was computed from)."""
    token = _INPUTS.set({})
    try:
        for name in inputs:
            note_input(name)
        yield
    finally:
        _INPUTS.reset(token)


def note_input(path) -> None:
    """Record ``path`` (an existing regular file) as an input of the running command (:func:`command_scope`;
    outside one, nothing is recorded)."""
    inputs = _INPUTS.get()
    with contextlib.suppress(OSError, ValueError, TypeError):
        info = os.stat(path)
        if inputs is not None and stat.S_ISREG(info.st_mode):
            inputs.setdefault((info.st_dev, info.st_ino), os.fspath(path))


def _same_as_input(path: str):
    inputs = _INPUTS.get()
    with contextlib.suppress(OSError, ValueError):
        info = os.stat(path)
        return (inputs or {}).get((info.st_dev, info.st_ino))
    return None


def existing_files(paths) -> tuple:
    """The paths among ``paths`` that exist now, i.e. that writing them would replace."""
    return tuple(path for path in paths if os.path.isfile(path))


def _umask() -> int:
    """The process's umask, read without changing it where the system says it (Linux): setting it for a moment
    would give a file another thread creates meanwhile the wrong mode."""
    with contextlib.suppress(OSError, ValueError), open("/proc/self/status", encoding="ascii") as status:
        for line in status:
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    mask = os.umask(0o22)
    os.umask(mask)
    return mask


def default_file_mode() -> int:
    """The mode a plain ``open(path, "w")`` gives a new file (0o666 minus the umask)."""
    return 0o666 & ~_umask()


def refuse_non_finite(what: str, **arrays) -> None:
    """Refuse to write ``what`` when one of ``arrays`` (name -> numbers) holds a NaN or an infinity.

    A file of ``nan`` rows is a silently wrong result; the writers call this on what they are about to
    write.  The message names the array, how many values are bad and the first index.

    Raises
    ------
    OutputError

    Examples
    --------
    >>> refuse_non_finite("the wall", b=[1.0, float("nan")])
    Traceback (most recent call last):
    ...
    coinwall.forward.errors.OutputError: refusing to write the wall: b has 1 non-finite value(s) (first at index 1); \
nothing was written
    """
    import numpy as np

    for name, values in arrays.items():
        values = np.asarray(values, dtype=float)
        bad = ~np.isfinite(values)
        if bad.any():
            first = np.unravel_index(int(np.argmax(bad)), values.shape) if values.ndim else ()
            where = f" (first at index {', '.join(map(str, first))})" if first else ""
            raise OutputError(f"refusing to write {what}: {name} has {int(bad.sum())} non-finite value(s)"
                              f"{where}; nothing was written")


# ----------------------------------------------------------------------------------------------------- writing
@contextlib.contextmanager
def _signals_held():
    """Run the block to its end: a signal whose handler is Python's (Ctrl-C, the command line's SIGTERM) waits
    until the block ends.  Main thread only, where Python runs handlers; other handlers are left alone."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending, previous = [], {}
    for number in _HELD:
        handler = signal.getsignal(number)
        if callable(handler):
            previous[number] = signal.signal(number, lambda n, frame: pending.append((n, frame)))
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        for number, frame in pending:
            previous[number](number, frame)


def _make_folders(missing, made) -> None:
    """Make the folders of ``missing`` (outermost first), listing each in ``made``."""
    for folder in missing:
        try:
            os.mkdir(folder)
        except FileExistsError:
            continue  # made meanwhile by someone else: not ours to remove
        except OSError as exc:
            raise OutputError(f"cannot create folder {folder!r}: {exc.strerror or exc}; nothing was written") from None
        made.append(folder)


def _temporary(path: str, data: bytes, temps: list) -> str:
    """``data`` in a new temporary file beside ``path``, with the mode and owner of the file at ``path`` (where
    this user may set them) or the mode of a new file; its name is listed in ``temps`` before it can exist."""
    folder = os.path.dirname(os.path.abspath(path))
    with _signals_held():  # the name is listed as soon as the file exists
        fd, temp = tempfile.mkstemp(prefix=_PREFIX, suffix=_SUFFIX, dir=folder)
        temps.append(temp)
    try:
        with os.fdopen(fd, "wb") as fh:
            try:
                info = os.stat(path)
            except FileNotFoundError:
                os.fchmod(fh.fileno(), default_file_mode())
            else:
                for owner in ((info.st_uid, info.st_gid), (-1, info.st_gid)):
                    with contextlib.suppress(OSError):  # only root may give a file away; a group of ours is fine
                        os.fchown(fh.fileno(), *owner)
                        break
                os.fchmod(fh.fileno(), stat.S_IMODE(info.st_mode) & 0o777)
            fh.write(data)
    except OSError as exc:
        raise OutputError(f"cannot write output {path!r}: {exc.strerror or exc}; nothing was written") from None
    return temp


def _commit(pairs) -> tuple:
    """Rename every ``(temporary, path)`` over its target, all or nothing; returns the paths that replaced a
    file.  If a rename fails, the targets already replaced get their old content back (those that did not
    exist are removed) and :class:`OutputError` names the path that failed."""
    backups, done = {}, []
    with _signals_held():
        try:
            replaced = tuple(path for _, path in pairs if os.path.lexists(path))
            for path in replaced if len(pairs) > 1 else ():  # one file: a failed rename changes nothing
                backups[path] = _backup(path)
            for temp, path in pairs:
                try:
                    os.replace(temp, path)
                except OSError as exc:
                    lost = _roll_back(done, backups)
                    extra = f"; could not restore {', '.join(lost)}" if lost else "; nothing was changed"
                    raise OutputError(f"cannot write output {path!r}: {exc.strerror or exc}{extra}") from None
                done.append(path)
            return replaced
        finally:
            _remove(backups.values())


def _backup(path: str) -> str:
    """A second name of the existing ``path`` beside it (a hard link, or a copy where links are not supported)."""
    folder = os.path.dirname(os.path.abspath(path))
    backup = os.path.join(folder, f"{_PREFIX}{secrets.token_hex(4)}{_SUFFIX}")
    try:
        os.link(path, backup, follow_symlinks=False)  # never over an existing name
        return backup
    except FileExistsError:
        return _backup(path)
    except OSError:
        pass
    fd, backup = tempfile.mkstemp(prefix=_PREFIX, suffix=_SUFFIX, dir=folder)
    try:
        with os.fdopen(fd, "wb") as copy, open(path, "rb") as old:
            shutil.copyfileobj(old, copy)
    except OSError as exc:
        _remove([backup])
        raise OutputError(f"cannot write output {path!r}: cannot keep a copy of the existing file "
                          f"({exc.strerror or exc}); nothing was written") from None
    return backup


def _roll_back(done, backups) -> list:
    """Put back what the renames in ``done`` replaced; returns what could not be put back (each described with
    where its old content is kept, which is then not removed)."""
    lost = []
    for path in reversed(done):
        try:
            if path in backups:
                os.replace(backups.pop(path), path)
            else:
                os.unlink(path)
        except OSError:
            kept = backups.pop(path, None)
            lost.append(f"{path!r}" + (f" (its old content is in {kept!r})" if kept else ""))
    return lost


def _remove(paths) -> None:
    for path in list(paths):
        with contextlib.suppress(OSError):
            os.unlink(path)


def _remove_folders(made) -> None:
    """Remove the folders of ``made``, innermost first, each only if it is empty."""
    for folder in reversed(made):
        with contextlib.suppress(OSError):
            os.rmdir(folder)


@contextlib.contextmanager
def transaction():
    """Make every :func:`write_all` inside the block one commit: the calls only collect their files, which
    are written, all or nothing, when the block ends without an exception (and not at all when it raises).
    For a writer that produces its files in stages (``coinwall fit``: the fitted wall, then the body through
    :func:`coinwall.inverse.export.export_body`).

    Yields the dictionary ``{path: bytes}`` being collected.
    """
    if _BATCH.get() is not None:  # nested: the outer transaction commits
        yield _BATCH.get()
        return
    batch = {}
    token = _BATCH.set(batch)
    try:
        yield batch
    finally:
        _BATCH.reset(token)
    if batch:
        write_all(batch)


def write_all(files) -> Written:
    """Write ``{path: bytes}`` all or nothing (module docstring); inside :func:`transaction` the files are
    only collected.

    Parameters
    ----------
    files : dict
        ``{path: bytes}``; the folders of the paths are made if missing.

    Returns
    -------
    Written
        The paths (a list, in the order given), with ``replaced``: those that replaced a file.

    Raises
    ------
    OutputError
        If any file cannot be written, naming it: no output is changed, and no temporary file and no folder
        made for the outputs is left behind.

    Examples
    --------
    >>> written = write_all({"out/wall.csv": b"theta,b\\n0,1\\n"})
    >>> written, written.replaced
    (['out/wall.csv'], ())
    >>> write_all({"out/wall.csv": b"theta,b\\n0,2\\n"}).replaced
    ('out/wall.csv',)
    >>> import os
    >>> os.listdir("out")  # nothing else
    ['wall.csv']
    """
    batch = _BATCH.get()
    if batch is not None:
        batch.update(files)
        return Written(files, existing_files(files))
    missing = {path: _check_target(path) for path in files}
    temps, made, pairs = [], [], []
    committed = False
    try:
        for path, data in files.items():
            _make_folders(missing[path], made)
            pairs.append((_temporary(path, data, temps), path))
        for path in files:
            _check_target(path)  # what is there now (a folder or a FIFO may have appeared meanwhile)
        replaced = _commit(pairs)
        committed = True
    finally:
        if not committed:
            _remove(temps)
            _remove_folders(made)
    return Written(files, replaced)


@contextlib.contextmanager
def new_folder(path: str):
    """A new folder at ``path``, all or nothing: yields a temporary folder beside it to fill, which becomes
    ``path`` when the block ends without an exception and is removed otherwise (the scan store is made so).

    Raises
    ------
    OutputError
        If something is at ``path`` already, or its folder cannot be written.
    """
    if os.path.lexists(path):
        raise OutputError(f"output {path!r} exists already")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        check_folder(folder)
        if not os.path.isdir(folder):
            raise OutputError(f"the folder {folder!r} does not exist")
    except OutputError as exc:
        raise OutputError(f"output {path!r}: {exc}") from None
    with _signals_held():
        partial = tempfile.mkdtemp(prefix=_PREFIX, suffix=_SUFFIX, dir=folder)
    try:
        os.chmod(partial, 0o777 & ~_umask())  # mkdtemp's folder is private; a store gets the mode of mkdir
        yield partial
        os.rename(partial, path)
    finally:
        if os.path.lexists(partial):
            shutil.rmtree(partial, ignore_errors=True)
