"""File output shared by every writer: all or nothing, through temporary files renamed at the end.

Outputs are checked before any work (:func:`check_paths`, :func:`prepare_folder`): a bad name fails
before a long computation, and missing folders are created only once every name is known to be
good.  :func:`write_all` then writes every file or none, and says which ones replaced a file;
:func:`transaction` makes several calls (a writer that writes in two stages) one such commit.

How the all-or-nothing promise is kept
--------------------------------------
1. Every file is written to a temporary file in its own folder (so the final rename stays on one
   filesystem and is atomic), named ``.coinwall-tmp.<host>.<pid>.<random>.<mark>.part``: ``host`` is a
   hash of the host name and ``pid`` our process id, so a later run can tell a temporary left by a
   process that no longer exists (killed with SIGKILL, a power cut) from one still being written, and
   ``mark`` is a keyed hash (HMAC-SHA-256) of the rest of the name under a per-user secret
   (:func:`marked_name`).  Only a name whose mark verifies was made by coinwall for this user: a user's
   own ``.coinwall-settings.json`` or ``.coinwall-tmp.…`` file can never be taken for one.  Each
   :func:`write_all` first sweeps such stale temporaries (:func:`sweep_stale`) from the folders it
   writes to: only regular files owned by the current user whose mark verifies and whose process is
   gone on this host, or which are older than :data:`STALE_SECONDS`.  Nothing else is ever touched.
   Missing folders are made once every name is known to be good (:func:`check_paths`, or
   :func:`write_all` itself); those :func:`write_all` made are removed again when it fails, and inside
   :func:`command_scope` (the command line) every folder made for the command's outputs is removed
   when the command fails, each only if it is still the empty folder made here.
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
import hmac
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
    "command_scope",
    "default_file_mode",
    "existing_files",
    "is_marked",
    "marked_name",
    "note_input",
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

_PREFIX = ".coinwall-tmp."
# .coinwall-tmp.<8 hex of the host>.<pid>.<16 hex random>.<16 hex mark>.<kind>; the mark is an HMAC of the rest
_OURS = re.compile(r"\.coinwall-tmp\.([0-9a-f]{8})\.([0-9]{1,10})\.([0-9a-f]{16})\.([0-9a-f]{16})\.([a-z]{1,8})")
#: the kinds of marked names: ``part`` a file being written, ``store`` a folder being made (a scan store)
KINDS = ("part", "store")
_KEY_FILE = "temporary-names.key"
_KEY: list = []  # [the key] once known (per process)
_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))
_BATCH = contextvars.ContextVar("coinwall_output_batch", default=None)
# inside command_scope (the command line): {(st_dev, st_ino): name} of the input files read or named
_INPUTS = contextvars.ContextVar("coinwall_inputs", default=None)
# inside command_scope: the folders made for the command's outputs, [(path, (st_dev, st_ino))]
_MADE = contextvars.ContextVar("coinwall_made_folders", default=None)


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


def _limits(folder: str) -> tuple:
    """(longest file name, longest path) of the filesystem holding the existing ``folder``."""
    def limit(name, default):
        try:
            value = os.pathconf(folder, name)
        except (OSError, ValueError, AttributeError):
            value = -1
        return value if value and value > 0 else default

    return limit("PC_NAME_MAX", 255), limit("PC_PATH_MAX", 4096)


#: the longest temporary name (marked_name), which must fit beside every output
_TEMP_LENGTH = len(_PREFIX) + 8 + 1 + 10 + 1 + 16 + 1 + 16 + 1 + 8


def _short(path: str, limit: int = 80) -> str:
    return repr(path) if len(path) <= limit else repr(path[:limit // 2]) + "…" + repr(path[-limit // 2:])


def _check_length(path: str) -> None:
    """Refuse a name the filesystem cannot hold (a component or the whole path too long), before any
    folder is made for it: ``-o d/d/…/d/x.csv`` used to make thousands of folders, then fail."""
    full = os.path.abspath(path)
    existing = full
    while not os.path.isdir(existing) and os.path.dirname(existing) != existing:
        existing = os.path.dirname(existing)
    name_max, path_max = _limits(existing)
    for part in full.split(os.sep):
        if len(os.fsencode(part)) > name_max:
            raise OutputError(f"output {_short(path)}: the name {_short(part, 40)} is {len(os.fsencode(part))} bytes "
                              f"long, more than the {name_max} this filesystem allows")
    longest = len(os.fsencode(os.path.dirname(full))) + 1 + max(len(os.fsencode(os.path.basename(full))), _TEMP_LENGTH)
    if longest >= path_max:
        raise OutputError(f"output {_short(path)}: the path is {longest} bytes long (with its temporary), more than "
                          f"the {path_max - 1} this system allows; choose a shorter one")


def _same_as_input(path: str):
    """The input file that ``path`` names (the same file, by device and inode), inside :func:`command_scope`."""
    inputs = _INPUTS.get()
    if not inputs:
        return None
    try:
        info = os.stat(path)
    except (OSError, ValueError):
        return None
    return inputs.get((info.st_dev, info.st_ino))


def _refuse_input(path: str) -> None:
    name = _same_as_input(path)
    if name is not None:
        same = "" if os.path.abspath(name) == os.path.abspath(path) else f" (the input {name!r})"
        raise OutputError(f"output {path!r} is an input file of this command{same}; writing it would replace the "
                          "input: choose another name")


def check_paths(paths, allowed, inputs=()) -> None:
    """Before any work: every output has an extension in ``allowed`` and a place to go.

    Every path is checked first (extension, a name the filesystem can hold, not a folder, an existing
    file writable, a folder that exists or can be created, not the same file as another output, not an
    input of the command: ``inputs`` and, inside :func:`command_scope`, the files it names); only then
    are missing folders created, so a bad name anywhere in ``paths`` creates nothing.  Inside
    :func:`command_scope` the folders made are removed again if the command fails.

    Raises
    ------
    OutputError
        Naming the first bad path.
    """
    for name in inputs:
        note_input(name)
    seen = {}
    for path in paths:
        ext = os.path.splitext(path)[1].lower()
        if ext not in allowed:
            raise OutputError(f"output {path!r}: unknown extension {ext or '(none)'!r}; known: {', '.join(allowed)}")
        _check_length(path)
        if os.path.isdir(path):
            raise OutputError(f"output {path!r} is a folder, not a file")
        if os.path.exists(path) and not os.access(path, os.W_OK):
            raise OutputError(f"output {path!r}: the existing file is not writable")
        _refuse_input(path)
        for name in inputs:  # outside a command scope too
            if os.path.exists(path) and os.path.exists(name) and os.path.samefile(path, name):
                raise OutputError(f"output {path!r} is an input file of this command; writing it would replace "
                                  "the input: choose another name")
        # two names of one file (a.csv and ./a.csv) would be written twice, the first copy lost
        same = os.path.realpath(path)
        if same in seen and seen[same] != path:
            raise OutputError(f"output {path!r} is the same file as {seen[same]!r}")
        seen[same] = path
        try:
            _missing_folders(os.path.dirname(os.path.abspath(path)))
        except OutputError as exc:
            raise OutputError(f"output {path!r}: {exc}") from None
    _make_folders(paths, [])


def prepare_folder(folder: str) -> str:
    """Make sure the output folder ``folder`` exists and is writable, creating it (and its parents)
    when missing; returns ``folder``.  Inside :func:`command_scope` the folders made are removed again
    if the command fails.

    Raises
    ------
    OutputError
        If ``folder`` or one of its parents is a file, or it cannot be created or written to.
    """
    try:
        _check_length(os.path.join(folder, "x"))
        _make_folders([os.path.join(folder, "x")], [])
    except OutputError as exc:
        raise OutputError(f"output folder {folder!r}: {exc}") from None
    if not os.access(folder, os.W_OK):
        raise OutputError(f"output folder {folder!r} is not writable")
    return folder


def _make_folders(paths, made) -> None:
    """Make the missing folders of ``paths`` (outermost first), listing each in ``made`` (and in the
    command's list, inside :func:`command_scope`) as ``(folder, (dev, ino))``; on failure the ones
    made are removed again."""
    scope = _MADE.get()
    for folder in dict.fromkeys(os.path.dirname(os.path.abspath(p)) for p in paths):
        for missing in _missing_folders(folder):
            try:
                os.mkdir(missing)
            except FileExistsError:
                continue  # made meanwhile by someone else: not ours to remove
            except OSError as exc:
                _remove_folders(made)
                raise OutputError(f"cannot create folder {missing!r}: {exc.strerror or exc}; nothing was written") \
                    from None
            info = os.lstat(missing)
            made.append((missing, (info.st_dev, info.st_ino)))
            if scope is not None:
                scope.append(made[-1])


def _remove_folders(made) -> None:
    """Remove the folders of ``made`` (innermost first), each only if it is still the one made here and empty."""
    for folder, identity in reversed(made):
        try:
            info = os.lstat(folder)
            if (info.st_dev, info.st_ino) == identity:
                os.rmdir(folder)  # fails (and keeps it) if anything was put in it
        except OSError:
            pass


@contextlib.contextmanager
def command_scope(inputs=()):
    """The span of one command.

    * The files in ``inputs`` and every input file read inside it (:func:`note_input`) cannot be
      outputs of it (``coinwall solve wall.csv -o wall.csv`` is refused instead of replacing the data
      it was computed from).
    * The folders made for its outputs (:func:`check_paths`, :func:`prepare_folder`,
      :func:`write_all`) are removed again, innermost first and each only if it is still the empty
      folder made here, when the command ends with an exception (bad input found late, a full disk,
      Ctrl-C): a failed command leaves no folders behind.
    """
    token, made_token = _INPUTS.set({}), _MADE.set([])
    try:
        for name in inputs:
            note_input(name)
        yield
    except BaseException:
        _remove_folders(_MADE.get())
        raise
    finally:
        _MADE.reset(made_token)
        _INPUTS.reset(token)


def note_input(path) -> None:
    """Record ``path`` (an existing regular file) as an input of the running command (:func:`command_scope`;
    outside one, nothing is recorded)."""
    inputs = _INPUTS.get()
    if inputs is None:
        return
    try:
        info = os.stat(path)
    except (OSError, ValueError, TypeError):
        return
    if stat.S_ISREG(info.st_mode):
        inputs.setdefault((info.st_dev, info.st_ino), os.fspath(path))


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


def _key_folder() -> str:
    chosen = os.environ.get("COINWALL_CACHE_DIR")
    if chosen:
        return os.path.abspath(chosen)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(os.path.abspath(base), "coinwall")


def _private(info, uid) -> bool:
    return (uid is None or info.st_uid == uid) and not info.st_mode & (stat.S_IWGRP | stat.S_IWOTH)


def _stored_key():
    """The per-user secret in ``<cache>/temporary-names.key`` (32 random bytes, mode 0600), made once; None
    when the folder or the file cannot be trusted (another owner, writable by others) or written."""
    uid = os.getuid() if hasattr(os, "getuid") else None
    folder = _key_folder()
    path = os.path.join(folder, _KEY_FILE)
    try:
        os.makedirs(folder, mode=0o700, exist_ok=True)
        if not _private(os.stat(folder), uid):
            return None
        try:
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0))
        except FileNotFoundError:
            temp = os.path.join(folder, f".{_KEY_FILE}.{os.getpid()}.{secrets.token_hex(8)}")
            fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o600)
            try:
                try:
                    os.write(fd, secrets.token_bytes(32))
                finally:
                    os.close(fd)
                with contextlib.suppress(FileExistsError):  # another process made it first: use theirs
                    os.link(temp, path)
            finally:
                with contextlib.suppress(OSError):
                    os.unlink(temp)
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0))
        try:
            info = os.fstat(fd)
            key = os.read(fd, 65)
        finally:
            os.close(fd)
        if not stat.S_ISREG(info.st_mode) or not _private(info, uid) or info.st_mode & 0o077 or len(key) != 32:
            return None
        return key
    except OSError:
        return None


def _key() -> bytes:
    """The key of the marks: the per-user secret, or (where it cannot be kept) a key derived from the user
    and the host, which still no name chosen by hand matches."""
    if not _KEY:
        key = _stored_key()
        if key is None:
            uid = os.getuid() if hasattr(os, "getuid") else 0
            key = hashlib.sha256(f"coinwall temporary names|{uid}|{socket.gethostname()}".encode(
                "utf-8", "replace")).digest()
        _KEY.append(key)
    return _KEY[0]


def _mark(body: str) -> str:
    return hmac.new(_key(), body.encode("ascii"), hashlib.sha256).hexdigest()[:16]


def marked_name(folder: str, kind: str = "part") -> str:
    """A fresh name in ``folder`` that only this program makes, for this user:
    ``.coinwall-tmp.<host>.<pid>.<random>.<mark>.<kind>``, where ``mark`` is an HMAC of the rest under a
    per-user secret (module docstring).  ``kind`` is one of :data:`KINDS`."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    body = f"{_host_tag()}.{os.getpid()}.{secrets.token_hex(8)}"
    return os.path.join(folder, f"{_PREFIX}{body}.{_mark(body + '.' + kind)}.{kind}")


def is_marked(name: str):
    """``(host, pid, kind)`` when ``name`` (a base name) is a :func:`marked_name` of this user, else None."""
    match = _OURS.fullmatch(name)
    if not match or match.group(5) not in KINDS:
        return None
    body = f"{match.group(1)}.{match.group(2)}.{match.group(3)}"
    if not hmac.compare_digest(_mark(body + "." + match.group(5)), match.group(4)):
        return None
    return match.group(1), int(match.group(2)), match.group(5)


def temporary_name(path: str) -> str:
    """A fresh temporary name next to ``path`` (:func:`marked_name`, kind ``part``)."""
    return marked_name(os.path.dirname(os.path.abspath(path)), "part")


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


def sweep_stale(folder: str, age: float = STALE_SECONDS) -> list:
    """Remove the stale temporaries this program made in ``folder``; returns their paths.

    Only entries whose name is a :func:`marked_name` of this user (the mark verifies), owned by the
    current user, not links: files of kind ``part`` and folders of kind ``store``; stale means their
    process is gone on this host, or they are older than ``age`` seconds.  Every other name is left
    alone, whatever it looks like.  Errors (an unreadable folder, a file removed meanwhile) are ignored:
    sweeping is housekeeping, never a reason to fail a write.
    """
    removed = []
    now = time.time()
    uid = os.getuid() if hasattr(os, "getuid") else None
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    host = None
    for entry in entries:
        if not entry.name.startswith(_PREFIX):
            continue
        try:
            mine = is_marked(entry.name)
            if mine is None:
                continue
            info = entry.stat(follow_symlinks=False)
            if uid is not None and info.st_uid != uid:
                continue
            kind_ok = stat.S_ISREG(info.st_mode) if mine[2] == "part" else stat.S_ISDIR(info.st_mode)
            if not kind_ok:
                continue
            host = host or _host_tag()
            if now - info.st_mtime > age or (mine[0] == host and _process_gone(mine[1])):
                if mine[2] == "store":
                    shutil.rmtree(entry.path)
                else:
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
        self.folders = []  # the folders made for the outputs, removed with the temporaries
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
        _remove_folders(self.folders)
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
    for path in files:
        _refuse_input(path)
        _check_length(path)
    for folder in dict.fromkeys(os.path.dirname(os.path.abspath(path)) for path in files):
        if os.path.isdir(folder):
            sweep_stale(folder)
    pairs = []
    with _Termination() as termination:
        temps, made = termination.temps, termination.folders
        try:
            _make_folders(files, made)
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
                made.clear()
        finally:
            _remove(temps)
            _remove_folders(made)  # the write failed: the folders made for it go too
    return Written(files, replaced)
