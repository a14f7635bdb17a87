"""File output shared by every writer: all or nothing, through temporary files renamed at the end.

Outputs are checked before any work (:func:`check_paths`, :func:`prepare_folder`): a bad name fails
before a long computation, and missing folders are created only once every name is known to be
good.  :func:`write_all` then writes every file or none, and says which ones replaced a file;
:func:`transaction` makes several calls (a writer that writes in two stages) one such commit.

How the all-or-nothing promise is kept
--------------------------------------
1. Every file is written to a temporary file in its own folder (so the final rename stays on one
   filesystem and is atomic), named ``.coinwall-<host>-<pid>-<random><ext>``: ``host`` is a hash of
   the host name and ``pid`` our process id, so a later run can tell a temporary left by a process
   that no longer exists (killed with SIGKILL, a power cut) from one still being written.  Each
   :func:`write_all` first sweeps such stale temporaries (:func:`sweep_stale`) from the folders it
   writes to: only regular files of this naming, owned by the current user, whose process is gone on
   this host or which are older than :data:`STALE_SECONDS`.  Nothing else is ever touched.
2. While the temporaries exist, SIGTERM and SIGHUP (main thread only, and only when the process does
   not ignore them) remove them before the process dies of the signal as it would have, with the
   conventional status (128 + 15 in a shell); the previous handler is restored afterwards.
   SIGINT is a ``KeyboardInterrupt``, which the ``finally`` clean-up covers.
3. Once every temporary is complete the commit starts; a SIGTERM/SIGHUP that comes during it is
   handled when it ends (it takes a few system calls): every target is checked again (a folder there is refused, naming
   it); every existing target gets a backup (a hard link, or a copy where the filesystem has none,
   also of our temporary naming); then the temporaries are renamed over the targets one by one.  If
   a rename fails, the targets already replaced get their backup back (those that did not exist are
   removed), so the folder is as it was before; the error names the path that failed.  The backups
   are removed at the end either way.

A SIGKILL cannot be caught: it can leave a temporary (swept by the next write into that folder) or,
during the commit, a mix of old and new files, each of them complete.
"""

import contextlib
import contextvars
import errno
import hashlib
import os
import re
import secrets
import shutil
import signal
import socket
import stat
import threading
import time

from ..errors import OutputError

__all__ = [
    "STALE_SECONDS",
    "Written",
    "check_paths",
    "default_file_mode",
    "existing_files",
    "prepare_folder",
    "refuse_non_finite",
    "sweep_stale",
    "temporary_name",
    "transaction",
    "write_all",
]

#: a temporary of ours older than this is stale whoever made it (a process on another host sharing the
#: folder, or a pid that was reused): no coinwall write takes a day
STALE_SECONDS = 24 * 3600

_PREFIX = ".coinwall-"
# .coinwall-<8 hex of the host>-<pid>-<8 hex random><ext>
_OURS = re.compile(r"\.coinwall-([0-9a-f]{8})-([0-9]{1,10})-[0-9a-f]{8}(\.[A-Za-z0-9]{1,8})?")
# tempfile.mkstemp's names in coinwall 0.x (8 characters of [a-z0-9_]): swept by age only
_LEGACY = re.compile(r"\.coinwall-[a-z0-9_]{8}(\.[A-Za-z0-9]{1,8})?")
_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))
_BATCH = contextvars.ContextVar("coinwall_output_batch", default=None)


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
    exists or can be created, not the same file as another output); only then are missing folders
    created, so a bad name anywhere in ``paths`` creates nothing.

    Raises
    ------
    OutputError
        Naming the first bad path.
    """
    to_create, seen = [], {}
    for path in paths:
        ext = os.path.splitext(path)[1].lower()
        if ext not in allowed:
            raise OutputError(f"output {path!r}: unknown extension {ext or '(none)'!r}; known: {', '.join(allowed)}")
        if os.path.isdir(path):
            raise OutputError(f"output {path!r} is a folder, not a file")
        if os.path.exists(path) and not os.access(path, os.W_OK):
            raise OutputError(f"output {path!r}: the existing file is not writable")
        # two names of one file (a.csv and ./a.csv) would be written twice, the first copy lost
        same = os.path.realpath(path)
        if same in seen and seen[same] != path:
            raise OutputError(f"output {path!r} is the same file as {seen[same]!r}")
        seen[same] = path
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

    Temporary files are created with this mode, so the outputs renamed from them get the mode users
    (and web servers) expect of a new file.
    """
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def refuse_non_finite(what: str, **arrays) -> None:
    """Refuse to write ``what`` when one of ``arrays`` (name -> numbers) holds a NaN or an infinity.

    A file of ``nan`` rows is a silently wrong result; the writers call this on what they are about to
    write.  The message names the array, how many values are bad and the first index.

    Raises
    ------
    OutputError
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


# ------------------------------------------------------------------ temporaries of our own naming

def _host_tag() -> str:
    return hashlib.sha256(socket.gethostname().encode("utf-8", "replace")).hexdigest()[:8]


def temporary_name(path: str) -> str:
    """A fresh temporary name next to ``path``: ``.coinwall-<host>-<pid>-<random><ext>`` (module docstring)."""
    folder = os.path.dirname(os.path.abspath(path))
    ext = os.path.splitext(path)[1]
    ext = ext if re.fullmatch(r"\.[A-Za-z0-9]{1,8}", ext) else ""
    return os.path.join(folder, f"{_PREFIX}{_host_tag()}-{os.getpid()}-{secrets.token_hex(4)}{ext}")


def _process_gone(pid: int) -> bool:
    """True only when no process ``pid`` exists on this host (a process of another user exists too)."""
    if pid <= 0 or pid == os.getpid():
        return False  # os.kill(0, …) would address our process group; our own pid is alive
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except OSError:  # PermissionError: it exists, it is someone else's
        return False
    return False


def _stale(name: str, info, now: float) -> bool:
    old = now - info.st_mtime > STALE_SECONDS
    ours = _OURS.fullmatch(name)
    if ours:
        return old or (ours.group(1) == _host_tag() and _process_gone(int(ours.group(2))))
    return bool(_LEGACY.fullmatch(name)) and old


def sweep_stale(folder: str) -> list:
    """Remove the stale temporaries of coinwall's own naming from ``folder``; returns their paths.

    Only regular files (not links) owned by the current user, named ``.coinwall-<host>-<pid>-<random>[.ext]``
    whose process is gone on this host, or of that naming (or the older ``.coinwall-<8 chars>[.ext]``)
    and older than :data:`STALE_SECONDS`.  Errors (an unreadable folder, a file removed meanwhile) are
    ignored: sweeping is housekeeping, never a reason to fail a write.
    """
    removed = []
    now = time.time()
    uid = os.getuid() if hasattr(os, "getuid") else None
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        if not entry.name.startswith(_PREFIX):
            continue
        try:
            info = entry.stat(follow_symlinks=False)
            if not stat.S_ISREG(info.st_mode) or (uid is not None and info.st_uid != uid):
                continue
            if _stale(entry.name, info, now):
                os.unlink(entry.path)
                removed.append(entry.path)
        except OSError:
            continue
    return removed


def _remove(paths) -> None:
    for path in list(paths):
        try:
            os.unlink(path)
        except OSError:
            pass


class _Termination:
    """While active (a ``with`` block), SIGTERM/SIGHUP first remove the files listed in :attr:`temps`,
    then do what they did before: the default action kills the process with the signal (status 128 +
    signal number in a shell), a Python handler is called.  Inside :meth:`held` (the commit) a signal
    waits until the block ends.  Main thread only (the only thread that may set handlers; Python runs
    handlers there, between bytecodes); a signal the process ignores stays ignored."""

    def __init__(self):
        self.temps = []  # every name is listed before its file is created
        self.previous = {}
        self.holding = False
        self.pending = None
        self.committed = False

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for number in _SIGNALS:
                handler = signal.getsignal(number)
                if handler not in (signal.SIG_IGN, None):  # ignored, or set outside Python: leave it alone
                    self.previous[number] = handler
            for number in self.previous:
                signal.signal(number, self._handle)
        return self

    def __exit__(self, *exc):
        for number, handler in self.previous.items():
            signal.signal(number, handler)
        return False

    @contextlib.contextmanager
    def held(self):
        """The commit (a handful of renames) is not cut short: a signal is handled after it."""
        self.holding = True
        try:
            yield
        finally:
            self.holding = False
            if self.pending is not None:
                self._handle(self.pending, None)

    def _handle(self, number, frame):
        if self.holding:
            self.pending = number
            return
        _remove(self.temps)
        before = self.previous[number]
        signal.signal(number, before)
        if callable(before):
            before(number, frame)  # the program's own handler, which chose to go on
            if not self.committed:
                raise OutputError("writing was interrupted by a signal; nothing was written")
            return
        os.kill(os.getpid(), number)  # SIG_DFL now: die of the signal as if it had never been caught
        os._exit(128 + number)  # not reached where the signal kills (POSIX delivers it before kill returns)


def _backup(path: str) -> str:
    """A second name for the existing ``path`` (hard link; a copy where links are not supported)."""
    backup = temporary_name(path)
    try:
        os.link(path, backup, follow_symlinks=False)
    except OSError:
        shutil.copy2(path, backup, follow_symlinks=False)
    return backup


def _commit(pairs) -> tuple:
    """Rename every ``(temp, path)`` over its target, all or nothing (module docstring, step 3).

    Returns the paths that replaced a file.  On failure the replaced files are restored and
    :class:`OutputError` names the path that failed.
    """
    for _, path in pairs:
        if os.path.isdir(path):
            raise OutputError(f"output {path!r} is a folder, not a file; nothing was written")
    backups, done = {}, []
    try:
        for _, path in pairs:
            if os.path.lexists(path):
                try:
                    backups[path] = _backup(path)
                except OSError as exc:
                    raise OutputError(f"cannot write output {path!r}: cannot keep a copy of the existing file "
                                      f"({exc.strerror or exc}); nothing was written") from None
        replaced = tuple(path for _, path in pairs if path in backups and os.path.isfile(path))
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


def _roll_back(done, backups) -> list:
    """Put back what the renames in ``done`` replaced; returns what could not be put back (each
    described with where its old content is kept, which is then not removed)."""
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


@contextlib.contextmanager
def transaction():
    """Make every :func:`write_all` inside the block one commit: the calls only collect their files,
    which are written, all or nothing, when the block ends without an exception (and not at all when
    it raises).  For a writer that produces its files in stages (``coinwall fit``: the fitted wall,
    then the body through :func:`coinwall.inverse.export.export_body`).

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
    """Write ``{path: bytes}`` all or nothing: every file goes to a temporary file in its own folder
    first, and all are renamed only when every one was written; a failed rename restores the files
    already replaced (module docstring).  Inside :func:`transaction` the files are only collected.

    Returns
    -------
    Written
        The paths (a list, in the order given), with ``replaced``: those that replaced a file.

    Raises
    ------
    OutputError
        If any file cannot be written, naming it; no output is changed and no temporary file is left
        behind.
    """
    batch = _BATCH.get()
    if batch is not None:
        batch.update(files)
        return Written(files, existing_files(files))
    for folder in dict.fromkeys(os.path.dirname(os.path.abspath(path)) for path in files):
        sweep_stale(folder)
    pairs = []
    with _Termination() as termination:
        temps = termination.temps
        try:
            for path, data in files.items():
                temp = temporary_name(path)
                temps.append(temp)  # listed before it exists, so that a signal handler removes it
                try:
                    # O_EXCL: never write through a file (or link) someone put under our name
                    fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0),
                                 default_file_mode())
                    with os.fdopen(fd, "wb") as fh:
                        fh.write(data)
                except OSError as exc:
                    if exc.errno == errno.EEXIST:  # not ours (O_EXCL refused it): never remove it
                        temps.remove(temp)
                    raise OutputError(f"cannot write output {path!r}: {exc.strerror or exc}; "
                                      "nothing was written") from None
                pairs.append((temp, path))
            with termination.held():
                replaced = _commit(pairs)
                temps.clear()
                termination.committed = True
        finally:
            _remove(temps)
    return Written(files, replaced)
