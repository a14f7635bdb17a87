"""The explorer's web application: the page from the package, and a small JSON API over the library.

Starlette (an ASGI toolkit: routing, static files, responses; no template engine, no database) run
by uvicorn: small, well kept, and all the page needs.  The routes are thin: read a size-limited JSON
body, hand it to a :class:`~.worker.Worker`, return its result.

=================  =========================================  ====================================
route              request (JSON unless said)                 answer
=================  =========================================  ====================================
GET  /             —                                          the page (static/index.html)
GET  /api/cases    —                                          the catalog cases with a wall
POST /api/wall     wall spec (+ b0)                           b_c, its text, slider range, b0
POST /api/body     wall spec, b0                              outline path, regime, corners, curves
POST /api/realize  wall spec, b0                              κ_uniform, κ_max, realizable
POST /api/export   wall spec, b0, format, kappa, units        the file (SVG/DXF/JSON bytes)
POST /api/upload   raw bytes, ``?name=wall.csv``              like /api/wall, plus an ``upload`` id
POST /api/table    wall spec, b0, H                           the strip's walls
POST /api/beam     wall spec, b0, H, theta, eta, direction    trajectories + Poincaré section
=================  =========================================  ====================================

A wall spec is ``{"expression": "...", "params": "eps=1"}``, ``{"case": "ellipse"}`` or
``{"upload": id}``.  Errors are JSON ``{"error": message, "field": name}`` with status 400 (bad
input), 413 (too large), 408 (time limit), 503 (the worker died and was restarted, or too many uploads at
once) or 422 (a bug: the message says so); the page shows the message next to the field.  No route answers with a
traceback or a bare 500 (:func:`guarded` and the exception handlers).  ``{"superseded": true}``
(status 409) answers a request that a newer one of the same kind replaced before it ran.

A local server is still a server: a request whose ``Host`` is not the address the server is bound to is
refused (400, Starlette's ``TrustedHostMiddleware``: a web page cannot reach the API through a DNS name
it controls), a POST whose ``Origin`` is not the page's own is refused (403: another site open in the
same browser cannot drive it), at most :data:`MAX_CONCURRENT_UPLOADS` uploads are read at a time (the
others wait, and :data:`MAX_WAITING_UPLOADS` waiting at most: 503 beyond), and a number of more than
:data:`MAX_NUMBER_CHARS` characters in a JSON request is a 400.
"""

from __future__ import annotations

import asyncio
import collections
import contextlib
import functools
import hashlib
import json
import logging
import os

__all__ = ["LIMITS", "MAX_CONCURRENT_UPLOADS", "MAX_JSON_BYTES", "MAX_NUMBER_CHARS", "MAX_UPLOAD_BYTES",
           "MAX_WAITING_UPLOADS", "STATIC", "RequestError", "allowed_hosts", "create_app", "guarded"]

#: the page and its assets, shipped in the package
STATIC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "static")
#: largest JSON request body (an expression is at most 2,000 characters: forward/expression.py)
MAX_JSON_BYTES = 64 * 2**10
#: largest upload; the file readers then apply their own limits (forward/formats/inputfile.py MAX_BYTES)
MAX_UPLOAD_BYTES = 16 * 2**20
#: uploads read at the same time (each holds up to MAX_UPLOAD_BYTES, a few times over, until its worker has it)
MAX_CONCURRENT_UPLOADS = 2
#: uploads waiting for a slot; one more is answered 503 at once (a waiting upload holds ~64 KiB: uvicorn's buffer)
MAX_WAITING_UPLOADS = 8
#: seconds an upload waits for a slot
_UPLOAD_WAIT = 60.0
#: a request body must keep coming: READ_GRACE seconds, plus one more for every MIN_READ_RATE bytes received (a
#: client that sends a byte every two seconds holds an upload slot for READ_GRACE seconds, not for ever; 16 MiB
#: at the slowest rate allowed arrive in under nine minutes)
READ_GRACE = 5.0
MIN_READ_RATE = 32 * 2**10
#: bytes of a refused request body read and thrown away before the answer, so that a client still sending
#: receives the answer instead of a connection reset
MAX_DRAIN_BYTES = 64 * 2**20
#: the longest upload name kept (its extension, which says what the file is, always kept)
MAX_NAME_CHARS = 200
#: longest number literal in a JSON request (Python refuses integers over 4,300 digits with a ValueError)
MAX_NUMBER_CHARS = 100
#: uploads kept for a restarted worker (by id), the oldest dropped first
_MAX_UPLOADS = 4
#: time limits in seconds, per job (the first billiard of a wall compiles its numba kernel: ~10 s)
LIMITS = {"wall": 20.0, "body": 20.0, "realize": 30.0, "export": 30.0, "upload": 30.0, "cases": 20.0,
          "table": 20.0, "beam": 120.0}
#: which worker runs which job: the live one stays free for the slider
_WORKER_OF = {"wall": "live", "body": "live", "cases": "live", "realize": "heavy", "export": "heavy",
              "upload": "heavy", "table": "heavy", "beam": "heavy"}
_STATUS = {"input": 400, "timeout": 408, "crashed": 503, "bug": 422}
_MEDIA = {"svg": "image/svg+xml", "dxf": "application/dxf", "json": "application/json"}

log = logging.getLogger("coinwall.explore")


class RequestError(Exception):
    """Bad request before any computation (size, JSON); ``status`` and ``field`` for the answer."""

    def __init__(self, message, status=400, field=None):
        super().__init__(message)
        self.message, self.status, self.field = message, status, field


def _error(message, status, field=None):
    from starlette.responses import JSONResponse

    return JSONResponse({"error": message, "field": field}, status_code=status)


def _size(limit: int) -> str:
    return f"{limit // 2**20} MiB" if limit >= 2**20 else f"{limit // 1024} KiB"


async def _chunks(request):
    """The chunks of the request body, each within its deadline (:data:`READ_GRACE`, :data:`MIN_READ_RATE`):
    a body that stops coming, or trickles, is a 408, and the server's shutdown a 503, instead of a request held
    open for ever (or cancelled by uvicorn with a traceback)."""
    loop = asyncio.get_running_loop()
    start, size = loop.time(), 0
    stream = request.stream().__aiter__()
    app = request.scope.get("app") if hasattr(request, "scope") else None
    stopping = getattr(getattr(app, "state", None), "stopping", None)
    while True:
        left = start + READ_GRACE + size / MIN_READ_RATE - loop.time()
        waits = [asyncio.ensure_future(stream.__anext__())]
        if stopping is not None:
            waits.append(asyncio.ensure_future(stopping.wait()))
        done, pending = await asyncio.wait(waits, timeout=max(left, 0.0), return_when=asyncio.FIRST_COMPLETED)
        for task in pending:
            task.cancel()
        if waits[0] not in done:
            with contextlib.suppress(BaseException):
                await asyncio.gather(*pending, return_exceptions=True)
            if stopping is not None and stopping.is_set():
                raise RequestError("the server is stopping", 503)
            raise RequestError(f"the request arrived too slowly ({size} bytes in {loop.time() - start:.0f} s; at "
                               f"least {MIN_READ_RATE // 1024} KiB/s are needed)", 408)
        try:
            chunk = waits[0].result()
        except StopAsyncIteration:
            return
        size += len(chunk)
        yield chunk


async def _read_limited(request, limit: int, field=None) -> bytes:
    """The request body, refused as soon as it exceeds ``limit`` bytes (a declared length is checked first,
    before any byte of the body is read), and read within its deadline (:func:`_chunks`)."""
    what = "the file" if field == "upload" else "the request"
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > limit):
        raise RequestError(f"{what} is larger than {_size(limit)}", 413, field)
    chunks, size = [], 0
    stream = _chunks(request) if hasattr(request, "receive") else request.stream()
    async for chunk in stream:
        size += len(chunk)
        if size > limit:
            raise RequestError(f"{what} is larger than {_size(limit)}", 413, field)
        chunks.append(chunk)
    return b"".join(chunks)


async def _drain(request) -> None:
    """Read and throw away what is left of a refused request's body (at most :data:`MAX_DRAIN_BYTES`, within the
    read deadline), so that a client still sending gets the answer rather than a reset connection."""
    size = 0
    with contextlib.suppress(Exception):
        async for chunk in _chunks(request):
            size += len(chunk)
            if size > MAX_DRAIN_BYTES:
                break


def _number(text: str, kind):
    if len(text) > MAX_NUMBER_CHARS:
        raise RequestError(f"a number in the request has {len(text)} characters; at most {MAX_NUMBER_CHARS}")
    return kind(text)


def _constant(text: str):
    raise RequestError(f"{text} is not a number the page can use; give a finite number")


#: request fields that must be text when given (anything else is a 400 naming the field)
_TEXT_FIELDS = {"expression": "wall", "case": "case", "upload": "upload", "format": "format", "units": "kappa",
                "field": "wall"}
#: request fields that must be JSON booleans when given: ``"false"`` (a string) and ``[]`` are not false, and a
#: truth value read from them would be a guess
_BOOLEAN_FIELDS = {"allow_unrealizable": "kappa"}


async def _read_json(request) -> dict:
    data = await _read_limited(request, MAX_JSON_BYTES)
    try:
        value = json.loads(data.decode("utf-8"), parse_int=lambda t: _number(t, int),
                           parse_float=lambda t: _number(t, float), parse_constant=_constant)
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:  # JSONDecodeError is a ValueError
        raise RequestError(f"the request is not JSON: {exc}") from None
    if not isinstance(value, dict):
        raise RequestError("the request must be a JSON object")
    for key, field in _TEXT_FIELDS.items():
        if value.get(key) is not None and not isinstance(value[key], str):
            raise RequestError(f"`{key}` must be text, got {type(value[key]).__name__}", field=field)
    for key, field in _BOOLEAN_FIELDS.items():
        if key in value and not isinstance(value[key], bool):
            raise RequestError(f"`{key}` must be true or false, got {json.dumps(value[key])[:40]}", field=field)
    params = value.get("params")
    if params is not None and not isinstance(params, (str, dict)):
        raise RequestError("the parameters must be NAME=VALUE pairs", field="params")
    return value


def guarded(handler):
    """Every route answers JSON on failure: known errors with their status, anything else as a bug (422)."""
    from .worker import JobError, Superseded

    @functools.wraps(handler)
    async def wrapped(request):
        from starlette.requests import ClientDisconnect
        from starlette.responses import Response

        try:
            return await handler(request)
        except ClientDisconnect:  # the page was closed or the request aborted: nobody reads an answer
            log.info("explore: the client disconnected during %s", request.url.path)
            return Response(status_code=400)
        except RequestError as exc:
            return _error(exc.message, exc.status, exc.field)
        except Superseded:
            from starlette.responses import JSONResponse

            return JSONResponse({"superseded": True}, status_code=409)
        except JobError as exc:
            return _error(exc.message, _STATUS.get(exc.kind, 422), exc.field)
        except Exception as exc:  # noqa: BLE001 - the last line of defence: a bug, as a message, never a traceback
            log.warning("explore: internal error in %s: %s: %s", request.url.path, type(exc).__name__, exc)
            return _error(f"internal error: {type(exc).__name__}: {exc} -- this is a bug in coinwall; please report "
                          "it", 422)

    return wrapped


def _uploaded(request, spec):
    """A callable giving the bytes of the upload ``spec`` names, for a worker that lost it."""
    uploads = request.app.state.uploads
    key = spec.get("upload")
    return (lambda: uploads.get(key, (None, None))[1]) if key else None


def _job(job, channel=None):
    """A route that runs ``job`` on the request's JSON (``channel``: latest wins, see worker.py)."""

    async def handler(request):
        from starlette.responses import JSONResponse

        spec = await _read_json(request)
        if spec.get("upload"):
            spec["upload_name"] = request.app.state.uploads.get(spec["upload"], ("", None))[0]
        spec.pop("upload_bytes", None)  # only the server attaches bytes
        worker = request.app.state.workers[_WORKER_OF[job]]
        result = await worker.call(job, spec, timeout=LIMITS[job], channel=channel, upload=_uploaded(request, spec))
        return JSONResponse(result)

    return guarded(handler)


@guarded
async def _cases(request):
    from starlette.responses import JSONResponse

    worker = request.app.state.workers["live"]
    return JSONResponse(await worker.call("cases", {}, timeout=LIMITS["cases"]))


@guarded
async def _export(request):
    from starlette.responses import Response

    spec = await _read_json(request)
    spec.pop("upload_bytes", None)
    worker = request.app.state.workers["heavy"]
    result = await worker.call("export", spec, timeout=LIMITS["export"], upload=_uploaded(request, spec))
    headers = {"Content-Disposition": f'attachment; filename="{result["filename"]}"'}
    return Response(result["bytes"], media_type=_MEDIA[result["format"]], headers=headers)


@guarded
async def _upload(request):
    from starlette.responses import JSONResponse

    name = _upload_name(request.query_params.get("name", ""))
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > MAX_UPLOAD_BYTES):
        await _drain(request)
        raise RequestError(f"the file is larger than {_size(MAX_UPLOAD_BYTES)}", 413, "upload")  # before waiting
    state = request.app.state
    if state.uploads_waiting >= MAX_WAITING_UPLOADS:
        await _drain(request)
        raise RequestError("the server is busy reading other files; try again in a moment", 503, "upload")
    state.uploads_waiting += 1
    try:
        await asyncio.wait_for(state.upload_slots.acquire(), _UPLOAD_WAIT)
    except TimeoutError:
        await _drain(request)
        raise RequestError("the server is busy reading other files; try again in a moment", 503, "upload") from None
    finally:
        state.uploads_waiting -= 1
    try:  # one of MAX_CONCURRENT_UPLOADS slots: the body is read, hashed and handed to the worker
        try:
            data = await _read_limited(request, MAX_UPLOAD_BYTES, "upload")
        except RequestError as exc:
            if exc.status == 413:
                await _drain(request)
            raise
        if not data:
            raise RequestError("the file is empty", field="upload")
        key = hashlib.sha256(data).hexdigest()[:16]
        worker = state.workers["heavy"]
        result = await worker.call("upload", {"upload_name": name, "upload_bytes": data}, timeout=LIMITS["upload"])
    finally:
        state.upload_slots.release()
    uploads = state.uploads  # kept (for a restarted worker) only once it has been read as a wall
    uploads[key] = (name, data)
    uploads.move_to_end(key)
    while len(uploads) > _MAX_UPLOADS:
        uploads.popitem(last=False)
    return JSONResponse(result)


def _upload_name(text: str) -> str:
    """The upload's file name (its last path part) cut to :data:`MAX_NAME_CHARS` characters, keeping its extension
    (``.csv``, ``.svg``: it says how the file is read).

    Examples
    --------
    >>> _upload_name("../" + "w" * 300 + ".csv")[-8:], len(_upload_name("w" * 300 + ".csv"))
    ('wwww.csv', 200)
    """
    name = os.path.basename(text)
    if len(name) <= MAX_NAME_CHARS:
        return name
    stem, ext = os.path.splitext(name)
    ext = ext[:16]
    return stem[:MAX_NAME_CHARS - len(ext)] + ext


async def _index(request):
    from starlette.responses import FileResponse

    return FileResponse(os.path.join(STATIC, "index.html"), headers={"Cache-Control": "no-store"})


_WILDCARDS = ("", "0.0.0.0", "::")
_LOOPBACK_NAMES = ("localhost", "127.0.0.1", "::1", "[::1]")


def allowed_hosts(host: str) -> list:
    """The ``Host`` header values (without port) the server answers when bound to ``host``.

    A loopback address answers its loopback names (``localhost``, ``127.0.0.1``, ``[::1]``); a named address
    itself; a wildcard (``0.0.0.0``, ``::``) this machine's name and addresses.  Any other name is refused:
    a page that points a DNS name of its own at this machine cannot read the API.
    """
    import ipaddress
    import socket

    host = host.strip().strip("[]").lower()
    names = {host, f"[{host}]"} if ":" in host else {host}
    try:
        loopback = ipaddress.ip_address(host).is_loopback
    except ValueError:
        loopback = host == "localhost"
    if loopback:
        names.update(_LOOPBACK_NAMES)
    if host in _WILDCARDS:
        names.discard(host)
        names.update(_LOOPBACK_NAMES)
        with contextlib.suppress(OSError):
            for name in {socket.gethostname(), socket.getfqdn()}:
                names.add(name.lower())
                for info in socket.getaddrinfo(name, None):
                    address = info[4][0]
                    names.update({address, f"[{address}]"} if ":" in address else {address})
    return sorted(n for n in names if n)


class _SameOrigin:
    """Refuse (403, JSON) a request other than GET/HEAD whose ``Origin`` is not the page's own
    (``http://`` + the Host it was sent to); requests without ``Origin`` (not from a browser) pass."""

    def __init__(self, app):
        self.app = app

    async def __call__(self, scope, receive, send):
        if scope["type"] == "http" and scope["method"] not in ("GET", "HEAD", "OPTIONS"):
            from starlette.datastructures import Headers

            headers = Headers(scope=scope)
            origin = headers.get("origin")
            if origin is not None and origin.lower() != f"http://{headers.get('host', '')}".lower():
                response = _error("this page may only be used from its own address (another site sent "
                                  "this request)", 403)
                await response(scope, receive, send)
                return
        await self.app(scope, receive, send)


def create_app(*, warm: bool = True, host: str = "127.0.0.1"):
    """The Starlette application (workers start with it and stop with it).

    Parameters
    ----------
    warm : bool
        Start the worker processes at start-up (they import the library: a second or two), so the
        first slider move is fast.
    host : str
        The address the server is bound to: requests naming another host are refused (:func:`allowed_hosts`).
    """
    from starlette.applications import Starlette
    from starlette.exceptions import HTTPException
    from starlette.middleware import Middleware
    from starlette.middleware.trustedhost import TrustedHostMiddleware
    from starlette.routing import Mount, Route
    from starlette.staticfiles import StaticFiles

    from .worker import Worker

    @contextlib.asynccontextmanager
    async def lifespan(app):
        app.state.workers = {"live": Worker("live", warm=warm), "heavy": Worker("heavy", warm=warm)}
        app.state.uploads = collections.OrderedDict()
        app.state.upload_slots = asyncio.Semaphore(MAX_CONCURRENT_UPLOADS)
        app.state.uploads_waiting = 0
        app.state.stopping = asyncio.Event()  # set by the server's shutdown (server.py): bodies being read end
        app.state.loop = asyncio.get_running_loop()
        try:
            yield
        finally:
            for worker in app.state.workers.values():
                worker.close()

    async def http_error(request, exc):  # 404, 405: JSON too, never an HTML page with a trace
        return _error(exc.detail, exc.status_code)

    async def any_error(request, exc):
        return _error(f"internal error: {type(exc).__name__} -- this is a bug in coinwall; please report it", 422)

    routes = [
        Route("/", _index),
        Route("/api/cases", _cases),
        Route("/api/wall", _job("wall", channel="wall"), methods=["POST"]),
        Route("/api/body", _job("body", channel="body"), methods=["POST"]),
        Route("/api/realize", _job("realize", channel="realize"), methods=["POST"]),
        Route("/api/export", _export, methods=["POST"]),
        Route("/api/upload", _upload, methods=["POST"]),
        Route("/api/table", _job("table", channel="table"), methods=["POST"]),
        Route("/api/beam", _job("beam", channel="beam"), methods=["POST"]),
        Mount("/static", StaticFiles(directory=STATIC), name="static"),
    ]
    middleware = [Middleware(TrustedHostMiddleware, allowed_hosts=allowed_hosts(host)), Middleware(_SameOrigin)]
    return Starlette(routes=routes, lifespan=lifespan, middleware=middleware,
                     exception_handlers={HTTPException: http_error, Exception: any_error})
