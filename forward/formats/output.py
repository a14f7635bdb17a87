"""Every file coinwall writes, written all or nothing: the one writer.

:func:`write_all` writes each file to a new temporary file in the target's own folder (so that the rename is
atomic), gives it the mode and owner of the file it replaces (a new file gets the mode of a plain
``open(path, "w")``), and once every temporary is complete renames them over their targets with
:func:`os.replace`.  Missing folders are made only then: an output folder never exists without its content.
Whatever goes wrong (a full disk, bad input found late, Ctrl-C) the ``finally`` clause removes the temporaries
and the folders made, so nothing half-written and nothing of ours is left, and no file of the user's is
touched.  When several files replace existing ones, each existing file first gets a second name (a hard link,
or a copy), so that a rename that fails puts back what the earlier ones replaced.  A signal with a Python
handler (Ctrl-C, and the command line's SIGTERM and SIGHUP, which :func:`coinwall.cases.cli.main.main` turns
into a normal exit) waits for the renames, a few system calls.  A SIGKILL or a power cut can leave a
``.coinwall-*.tmp`` file beside an output (remove it by hand) or, during the renames, some outputs old and
some new, each whole.  The scan store (:func:`new_folder`) and the kernel cache use the same writer.

:func:`check_paths` applies the same rules before a long computation, so that a bad name fails in a second;
inside :func:`command_scope` (one command) an output that is one of the command's input files is refused.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import secrets
import shutil
import signal
import stat
import threading

from ..errors import OutputError

__all__ = ["Written", "check_folder", "check_paths", "command_scope", "existing_files", "new_folder", "note_input",
           "refuse_non_finite", "transaction", "write_all"]

_PREFIX, _SUFFIX = ".coinwall-", ".tmp"  # the temporaries: .coinwall-<8 hex digits>.tmp
_TEMP_LENGTH = len(_PREFIX) + 8 + len(_SUFFIX)
_BATCH = contextvars.ContextVar("coinwall_output_batch", default=None)
# inside command_scope (the command line): {(st_dev, st_ino): name} of the input files read or named
_INPUTS = contextvars.ContextVar("coinwall_inputs", default=None)
# the signals whose Python handler waits for the end of a commit
_HELD = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


class Written(list):
    """The paths :func:`write_all` wrote, in order (a ``list``), with ``replaced``: those that replaced a file."""

    def __init__(self, paths=(), replaced=()):
        super().__init__(paths)
        self.replaced = tuple(replaced)


def _short(path: str, limit: int = 80) -> str:
    return repr(path) if len(path) <= limit else repr(path[:limit // 2]) + "…" + repr(path[-limit // 2:])


def _missing_folders(folder: str) -> list:
    """The folders from ``folder`` up to the first existing one, outermost first (the order to make them in);
    :class:`OutputError` if a level is a file or the first existing folder is not writable."""
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


def _check_length(path: str, full: str, existing: str) -> None:
    """Refuse a name the filesystem of the folder ``existing`` cannot hold (a component, or the whole path with
    its temporary, too long), before any folder is made for it."""
    def limit(name, default):
        with contextlib.suppress(OSError, ValueError, AttributeError):
            value = os.pathconf(existing, name)
            return value if value > 0 else default
        return default

    name_max, path_max = limit("PC_NAME_MAX", 255), limit("PC_PATH_MAX", 4096)
    for part in map(os.fsencode, full.split(os.sep)):
        if len(part) > name_max:
            raise OutputError(f"output {_short(path)}: the name {_short(os.fsdecode(part), 40)} is {len(part)} bytes "
                              f"long, more than the {name_max} this filesystem allows")
    longest = len(os.fsencode(full)) + max(0, _TEMP_LENGTH - len(os.fsencode(os.path.basename(full))))
    if longest >= path_max:
        raise OutputError(f"output {_short(path)}: the path is {longest} bytes long (with its temporary), more than "
                          f"the {path_max - 1} this system allows; choose a shorter one")


def _check_target(path: str) -> list:
    """The rules for one output, checked before the work (:func:`check_paths`) and when it is written: a name
    the filesystem holds, a folder that exists or can be made, nothing there but a writable regular file, and
    not an input of the running command.  Returns the missing folders (outermost first)."""
    full = os.path.abspath(path)
    try:
        missing = _missing_folders(os.path.dirname(full))
    except OutputError as exc:
        raise OutputError(f"output {path!r}: {exc}") from None
    _check_length(path, full, os.path.dirname(missing[0] if missing else full))
    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return missing
    except ValueError:  # a NUL byte
        raise OutputError(f"output {path!r} is not a valid file name") from None
    if stat.S_ISDIR(info.st_mode):
        raise OutputError(f"output {path!r} is a folder, not a file; nothing was written")
    if not stat.S_ISREG(info.st_mode):
        from .inputfile import file_kind

        kind = "a symbolic link" if stat.S_ISLNK(info.st_mode) else file_kind(info.st_mode)
        raise OutputError(f"output {path!r} is {kind}, not a regular file; coinwall replaces only regular files: "
                          "give the name of a new or a regular file")
    if not os.access(path, os.W_OK):
        raise OutputError(f"output {path!r}: the existing file is not writable")
    name = (_INPUTS.get() or {}).get((info.st_dev, info.st_ino))
    if name is not None:
        same = "" if os.path.abspath(name) == full else f" (the input {name!r})"
        raise OutputError(f"output {path!r} is an input file of this command{same}; writing it would replace the "
                          "input: choose another name")
    return missing


def check_paths(paths, allowed=None) -> None:
    """Before any work: every output has an extension in ``allowed`` and can be written.

    The rules are :func:`write_all`'s (a name the filesystem holds, a folder that exists or can be made,
    nothing in the way but a writable regular file, not an input of the command inside :func:`command_scope`),
    and two names of one file are refused.  Nothing is created: the folders are made with the files.

    Parameters
    ----------
    paths : list of str
        The outputs.
    allowed : sequence of str, optional
        The extensions accepted (lower case, with the dot); any when None.

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
        same = os.path.realpath(path)  # a.csv and ./a.csv: the first copy would be lost
        if seen.setdefault(same, path) != path:
            raise OutputError(f"output {path!r} is the same file as {seen[same]!r}")


def check_folder(folder: str) -> str:
    """Before any work: ``folder`` is a folder that exists and is writable, or can be made; returns it (nothing
    is created: :func:`write_all` makes the folder with its files).

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


def existing_files(paths) -> tuple:
    """The paths among ``paths`` that exist now, i.e. that writing them would replace."""
    return tuple(path for path in paths if os.path.isfile(path))


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
        if callable(signal.getsignal(number)):
            previous[number] = signal.signal(number, lambda n, frame: pending.append((n, frame)))
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        for number, frame in pending:
            previous[number](number, frame)


def _new_entry(folder: str, make):
    """``(make(name), name)`` for a new name of the temporaries' pattern in ``folder``.  ``make`` refuses an
    existing name (``O_EXCL``, ``mkdir``, ``link``), so no file of the user's is ever taken.  Not
    :mod:`tempfile`: its files and folders are private (0600), and an output gets the mode of a plain ``open``,
    which the system applies from the umask to ``os.open(..., 0o666)`` and ``os.mkdir``."""
    while True:
        name = os.path.join(folder, f"{_PREFIX}{secrets.token_hex(4)}{_SUFFIX}")
        with contextlib.suppress(FileExistsError):
            return make(name), name


def _create(name: str) -> int:
    return os.open(name, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)


def _temporary(path: str, data: bytes, temps: list) -> str:
    """``data`` in a new temporary file beside ``path``, with the mode and owner of the file at ``path`` (where
    this user may set them); its name is listed in ``temps`` before it can exist."""
    try:
        with _signals_held():
            fd, temp = _new_entry(os.path.dirname(os.path.abspath(path)), _create)
            temps.append(temp)
        with os.fdopen(fd, "wb") as fh:
            with contextlib.suppress(FileNotFoundError):
                info = os.stat(path)
                for owner in ((info.st_uid, info.st_gid), (-1, info.st_gid)):
                    with contextlib.suppress(OSError):  # only root may give a file away; a group of ours is fine
                        os.fchown(fh.fileno(), *owner)
                        break
                os.fchmod(fh.fileno(), stat.S_IMODE(info.st_mode) & 0o777)
            fh.write(data)
    except OSError as exc:
        raise OutputError(f"cannot write output {path!r}: {exc.strerror or exc}; nothing was written") from None
    return temp


def _backup(path: str) -> str:
    """A second name of the existing ``path`` beside it: a hard link, or a copy where links are not supported."""
    folder = os.path.dirname(os.path.abspath(path))
    with contextlib.suppress(OSError):
        return _new_entry(folder, lambda name: os.link(path, name, follow_symlinks=False))[1]
    fd, backup = _new_entry(folder, _create)
    os.close(fd)
    try:
        shutil.copy2(path, backup)  # its content and mode (its owner only root could give it)
    except OSError as exc:
        _remove([backup])
        raise OutputError(f"cannot write output {path!r}: cannot keep a copy of the existing file "
                          f"({exc.strerror or exc}); nothing was written") from None
    return backup


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
                    lost = []  # put back what the renames in done replaced; name what could not be
                    for old in reversed(done):
                        try:
                            os.replace(backups.pop(old), old) if old in backups else os.unlink(old)
                        except OSError:
                            kept = backups.pop(old, None)  # then not removed: it holds the old content
                            lost.append(f"{old!r}" + (f" (its old content is in {kept!r})" if kept else ""))
                    extra = f"; could not restore {', '.join(lost)}" if lost else "; nothing was changed"
                    raise OutputError(f"cannot write output {path!r}: {exc.strerror or exc}{extra}") from None
                done.append(path)
            return replaced
        finally:
            _remove(backups.values())


def _remove(paths) -> None:
    for path in list(paths):
        with contextlib.suppress(OSError):
            os.unlink(path)


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
    temps, made, pairs, committed = [], [], [], False
    try:
        for path, data in files.items():
            for folder in missing[path]:  # outermost first
                try:
                    os.mkdir(folder)
                    made.append(folder)
                except FileExistsError:
                    pass  # made for an earlier file, or meanwhile by someone else: not ours to remove then
                except OSError as exc:
                    raise OutputError(f"cannot create folder {folder!r}: {exc.strerror or exc}; nothing was "
                                      "written") from None
            pairs.append((_temporary(path, data, temps), path))
        replaced = _commit(pairs)
        committed = True
    finally:
        if not committed:
            _remove(temps)
            for folder in reversed(made):
                with contextlib.suppress(OSError):
                    os.rmdir(folder)
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
    with _signals_held():
        try:
            _, partial = _new_entry(folder, lambda name: os.mkdir(name, 0o777))
        except OSError as exc:
            raise OutputError(f"output {path!r}: cannot create it in {folder!r} ({exc.strerror or exc})") from None
    try:
        yield partial
        os.rename(partial, path)
    finally:
        if os.path.lexists(partial):
            shutil.rmtree(partial, ignore_errors=True)
