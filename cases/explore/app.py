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
input), 413 (too large), 408 (time limit), 503 (the worker died and was restarted) or 422 (a bug:
the message says so); the page shows the message next to the field.  No route answers with a
traceback or a bare 500 (:func:`guarded` and the exception handlers).  ``{"superseded": true}``
(status 409) answers a request that a newer one of the same kind replaced before it ran.
"""

from __future__ import annotations

import collections
import contextlib
import functools
import hashlib
import json
import logging
import os

__all__ = ["LIMITS", "MAX_JSON_BYTES", "MAX_UPLOAD_BYTES", "STATIC", "RequestError", "create_app", "guarded"]

#: the page and its assets, shipped in the package
STATIC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "static")
#: largest JSON request body (an expression is at most 2,000 characters: forward/expression.py)
MAX_JSON_BYTES = 64 * 2**10
#: largest upload; the file readers then apply their own limits (forward/formats/inputfile.py MAX_BYTES)
MAX_UPLOAD_BYTES = 16 * 2**20
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


async def _read_limited(request, limit: int) -> bytes:
    """The request body, refused as soon as it exceeds ``limit`` bytes (a declared length is checked first)."""
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > limit):
        raise RequestError(f"the request is larger than {limit // 1024} KiB", 413)
    chunks, size = [], 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise RequestError(f"the request is larger than {limit // 1024} KiB", 413)
        chunks.append(chunk)
    return b"".join(chunks)


async def _read_json(request) -> dict:
    data = await _read_limited(request, MAX_JSON_BYTES)
    try:
        value = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise RequestError(f"the request is not JSON: {exc}") from None
    if not isinstance(value, dict):
        raise RequestError("the request must be a JSON object")
    return value


def guarded(handler):
    """Every route answers JSON on failure: known errors with their status, anything else as a bug (422)."""
    from .worker import JobError, Superseded

    @functools.wraps(handler)
    async def wrapped(request):
        try:
            return await handler(request)
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

    name = os.path.basename(request.query_params.get("name", ""))[:200]
    data = await _read_limited(request, MAX_UPLOAD_BYTES)
    if not data:
        raise RequestError("the upload is empty", field="upload")
    key = hashlib.sha256(data).hexdigest()[:16]
    uploads = request.app.state.uploads
    uploads[key] = (name, data)
    uploads.move_to_end(key)
    while len(uploads) > _MAX_UPLOADS:
        uploads.popitem(last=False)
    worker = request.app.state.workers["heavy"]
    result = await worker.call("upload", {"upload_name": name, "upload_bytes": data}, timeout=LIMITS["upload"])
    return JSONResponse(result)


async def _index(request):
    from starlette.responses import FileResponse

    return FileResponse(os.path.join(STATIC, "index.html"), headers={"Cache-Control": "no-store"})


def create_app(*, warm: bool = True):
    """The Starlette application (workers start with it and stop with it).

    Parameters
    ----------
    warm : bool
        Start the worker processes at start-up (they import the library: a second or two), so the
        first slider move is fast.
    """
    from starlette.applications import Starlette
    from starlette.exceptions import HTTPException
    from starlette.routing import Mount, Route
    from starlette.staticfiles import StaticFiles

    from .worker import Worker

    @contextlib.asynccontextmanager
    async def lifespan(app):
        app.state.workers = {"live": Worker("live", warm=warm), "heavy": Worker("heavy", warm=warm)}
        app.state.uploads = collections.OrderedDict()
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
    return Starlette(routes=routes, lifespan=lifespan,
                     exception_handlers={HTTPException: http_error, Exception: any_error})
