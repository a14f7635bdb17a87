"""A computation worker: one child process that runs :data:`.compute.JOBS`, with a time limit and "latest wins".

Why a process (and not a thread).  A thread cannot be stopped: a wall whose casadi evaluation or
numba compilation hangs would keep a thread (and the GIL, in a C call) busy for ever and the
server would answer nothing else.  A child process is killed when its time limit passes, and the
next job starts a fresh one.  ``spawn`` rather than ``fork``: the server has threads (uvicorn's, the
event loop's executor) and forking a threaded process can copy a held lock into the child.

Why one process per worker, jobs one at a time.  The machine may have two cores; the live view
needs one solve at a time, fast, not many stale ones in parallel.  Each :class:`Worker` has
*channels* (``"body"``, ``"beam"`` ...): a request that is still waiting when a newer request of
the same channel arrives is answered "superseded" without running, so a burst of slider moves
costs at most the job that is running plus the newest one.

The child ignores SIGINT: Ctrl-C in the terminal reaches the whole process group, and the server
(uvicorn) stops the workers itself; a child that died of it would print a traceback.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import multiprocessing
import re
import threading

from coinwall.forward.display import one_line

__all__ = ["JobError", "Superseded", "Worker", "page_words"]


class JobError(Exception):
    """A job that failed: ``kind`` is ``"input"`` (bad input: a message for the page), ``"timeout"``,
    ``"crashed"`` (the child died) or ``"bug"``; ``field`` the page field it belongs to (or None)."""

    def __init__(self, kind: str, message: str, field: str | None = None):
        super().__init__(message)
        self.kind, self.message, self.field = kind, message, field


class Superseded(Exception):
    """A newer request of the same channel arrived while this one waited: it was not run."""


#: the command line's words in the library's messages, and what the page calls the same thing
_PAGE_WORDS = (
    (re.compile(r";? *declare it with --param \S+"), ""),
    (re.compile(r",? *or pass --degrees"), ""),
    (re.compile(r" *\(pass --kappa to override\)"), ""),
    (re.compile(r" *\(--allow-unrealizable\)"), ""),
    (re.compile(r"--param\b"), "parameter"),
    (re.compile(r"--(kappa|units|b0|H)\b"), r"\1"),
)


def page_words(text: str) -> str:
    """A library message in the page's words: no command-line flags (the page has fields, not options)."""
    for pattern, words in _PAGE_WORDS:
        text = pattern.sub(words, text)
    return text


def _one_line(text, limit=600) -> str:
    """A message for the page: :func:`~coinwall.forward.display.one_line` of it in the page's words."""
    return one_line(page_words(" ".join(str(text).split())), limit)


def _child(conn, jobs="coinwall.cases.explore.compute") -> None:
    """The child's loop: receive ``(job, request)``, run it from the table ``JOBS`` of the module ``jobs``, send
    ``("ok", result)`` or ``(kind, message, field)``."""
    import importlib
    import signal
    import warnings

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    warnings.simplefilter("ignore")  # a library warning is not the page's business; results are checked
    from coinwall.forward.errors import CoinwallError

    from . import compute

    table = importlib.import_module(jobs).JOBS
    while True:
        try:
            job, request = conn.recv()
        except (EOFError, OSError):
            return
        try:
            reply = ("ok", table[job](request))
        except compute.MissingUpload as exc:
            reply = ("missing-upload", str(exc), "upload")
        except CoinwallError as exc:
            reply = ("input", _one_line(exc), getattr(exc, "explore_field", None))
        except (ValueError, TypeError, KeyError, OverflowError) as exc:  # a request field of the wrong type
            reply = ("input", _one_line(f"bad request value: {exc}"), getattr(exc, "explore_field", None))
        except MemoryError:
            reply = ("input", "not enough memory for this request; ask for less", None)
        except RecursionError:
            reply = ("input", "the input is nested too deeply to process; simplify it", None)
        except Exception as exc:  # noqa: BLE001 - a bug: reported as a message, the worker stays up
            reply = ("bug", _one_line(f"internal error: {type(exc).__name__}: {exc} -- this is a bug in coinwall; "
                                      "please report it"), getattr(exc, "explore_field", None))
        try:
            conn.send(reply)
        except (OSError, ValueError):  # the server went away
            return


class Worker:
    """One child process running explorer jobs one at a time (module docstring).

    Parameters
    ----------
    name : str
        For messages.
    warm : bool
        Start the child at once (imports take a second or two) instead of on the first job.
    jobs : str
        The module whose table ``JOBS`` the child runs (the tests add jobs of their own).
    """

    def __init__(self, name: str, warm: bool = True, jobs: str = "coinwall.cases.explore.compute"):
        self.name, self.jobs = name, jobs
        self._context = multiprocessing.get_context("spawn")
        self._process = None
        self._conn = None
        self._lock = asyncio.Lock()
        self._start_lock = threading.Lock()
        self._latest: dict = {}
        self._ticket = itertools.count(1)
        self.restarts = 0
        if warm:
            self._ensure()

    def _ensure(self):
        with self._start_lock:
            if self._process is not None and self._process.is_alive():
                return
            parent, child = self._context.Pipe()
            process = self._context.Process(target=_child, args=(child, self.jobs), name=f"coinwall-explore-{self.name}",
                                            daemon=True)
            process.start()
            child.close()
            self._process, self._conn = process, parent

    def _kill(self):
        process, conn = self._process, self._conn
        self._process = self._conn = None
        if process is not None:
            process.kill()
            process.join(5)
        if conn is not None:
            conn.close()
        self.restarts += 1

    def _run(self, job, request, timeout):
        """Blocking: send one job and wait for its reply (in a thread of the event loop's executor)."""
        self._ensure()
        conn = self._conn
        try:
            conn.send((job, request))
            if not conn.poll(timeout):
                self._kill()
                return ("timeout", (f"the computation took longer than {timeout:g} s and was stopped; try a simpler "
                                   "wall, fewer points or fewer collisions"), None)
            return conn.recv()
        except (EOFError, OSError, BrokenPipeError):
            if self._process is None:  # close(): the server is stopping
                return ("crashed", "the server is stopping; the computation was stopped", None)
            code = self._process.exitcode
            self._kill()
            return ("crashed", f"the computation ended unexpectedly (worker exit code {code}); it was restarted", None)

    async def call(self, job: str, request: dict, *, timeout: float, channel: str | None = None, upload=None):
        """Run ``job`` on ``request`` and return its result.

        ``upload``, a callable, returns the bytes of the uploaded wall the request names (or None), for a
        child that was restarted and no longer holds it.

        Raises
        ------
        Superseded
            A newer request of ``channel`` arrived before this one started.
        JobError
            Bad input, time limit, a crash or a bug (:class:`JobError`).
        """
        ticket = next(self._ticket)
        if channel is not None:
            self._latest[channel] = ticket
        async with self._lock:
            if channel is not None and self._latest.get(channel) != ticket:
                raise Superseded(channel)
            reply = await asyncio.to_thread(self._run, job, request, timeout)
            data = upload() if reply[0] == "missing-upload" and upload is not None else None
            if data is not None:
                reply = await asyncio.to_thread(self._run, job, dict(request, upload_bytes=data), timeout)
        if reply[0] == "ok":
            return reply[1]
        kind, message, field = reply
        if kind == "missing-upload":
            kind, message = "input", "the uploaded wall is no longer held by the server; upload it again"
        raise JobError(kind, message, field)

    def close(self):
        """Stop the child process (the server's shutdown).

        The child is killed before the pipe is closed: a thread may be waiting on the pipe for a job's
        reply, and only the child's end closing (EOF) wakes it; closing our end under it would not.
        """
        process, conn = self._process, self._conn
        self._process = self._conn = None
        if process is not None:
            process.kill()  # jobs hold no state worth saving
            process.join(5)
        if conn is not None:
            with contextlib.suppress(OSError):
                conn.close()
