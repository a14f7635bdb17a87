"""The explorer's server under hostile clients: strict request types, slow uploads, shutdown during an upload,
large uploads, long names (cases/explore/app.py, server.py).

The slow-client and shutdown checks run the real server (``coinwall explore`` under uvicorn) in a process of its
own and talk to it over a socket, as a browser or a script would.
"""

from __future__ import annotations

import json
import signal
import socket
import subprocess
import sys
import threading
import time
import warnings

import pytest

pytest.importorskip("starlette", reason="the explorer needs starlette (pip install -e '.[explore]')")
pytest.importorskip("uvicorn", reason="the explorer needs uvicorn (pip install -e '.[explore]')")
pytest.importorskip("httpx", reason="starlette's test client needs httpx")

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient

from coinwall.cases.explore import app as explore_app  # noqa: E402

LINE = {"expression": "1+0.1*cos(2*t)"}
WALL = "theta,b\n" + "".join(f"{k * 0.1},{1 + 0.1 * (k % 3)}\n" for k in range(63))


@pytest.fixture(scope="module")
def client():
    with TestClient(explore_app.create_app(), raise_server_exceptions=False,
                    base_url="http://127.0.0.1:8765") as test_client:
        yield test_client


@pytest.mark.parametrize("value", ["false", "true", [], [0], 0, 1, None, {"x": 1}])
def test_booleans_are_json_booleans(client, value):
    """``"allow_unrealizable": "false"`` was read as true (a non-empty string), and so was a list."""
    answer = client.post("/api/export", json=dict(LINE, b0=0, format="svg", kappa=10, units="mm",
                                                  allow_unrealizable=value))
    assert answer.status_code == 400, answer.text
    assert answer.json()["field"] == "kappa" and "must be true or false" in answer.json()["error"]


def test_a_json_boolean_is_read_as_one(client):
    # ε = 1 ellipse wall at b0 = 0: κ_max < 1 (not realizable at κ = 10 mm), so only `true` draws it
    refused = client.post("/api/export", json=dict(LINE, b0=-0.3, format="svg", kappa=10, units="mm",
                                                   allow_unrealizable=False))
    drawn = client.post("/api/export", json=dict(LINE, b0=-0.3, format="svg", kappa=10, units="mm",
                                                 allow_unrealizable=True))
    assert drawn.status_code == 200
    assert refused.status_code in (200, 400)  # realizable or not, `false` is read as false: never a 4xx for its type
    if refused.status_code == 400:
        assert "draw anyway" in refused.json()["error"]


def test_a_long_upload_name_keeps_its_extension(client):
    name = "w" * 300 + ".csv"
    answer = client.post(f"/api/upload?name={name}", content=WALL.encode())
    assert answer.status_code == 200, answer.text
    kept = explore_app._upload_name(name)
    assert len(kept) == explore_app.MAX_NAME_CHARS and kept.endswith(".csv")
    assert explore_app._upload_name("dir/../w.svg") == "w.svg"


# ------------------------------------------------------------------------------------ the real server
def _free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _start():
    port = _free_port()
    server = subprocess.Popen([sys.executable, "-m", "coinwall", "explore", "--no-browser", "--port", str(port)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = server.stdout.readline()
    assert "serving" in line, (line, server.stderr.read() if server.poll() is not None else "")
    return server, port


def _upload(port, body: bytes, *, declared=None, every=None, timeout=60.0):
    """POST /api/upload over a socket: the status line and the JSON answer (or the OSError), and the seconds."""
    start = time.monotonic()
    with socket.create_connection(("127.0.0.1", port), timeout=timeout) as sock:
        length = len(body) if declared is None else declared
        sock.sendall(f"POST /api/upload?name=w.csv HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Length: {length}"
                     "\r\n\r\n".encode())
        try:
            if every:  # a byte at a time, until the server answers
                import select

                for byte in body:
                    if select.select([sock], [], [], every)[0]:
                        break
                    sock.sendall(bytes([byte]))
            else:
                sock.sendall(body)
            data = b""
            while b"\r\n\r\n" not in data or len(data.split(b"\r\n\r\n", 1)[1]) < _length(data):
                chunk = sock.recv(1 << 16)
                if not chunk:
                    break
                data += chunk
        except OSError as exc:
            return f"OSError: {exc}", None, time.monotonic() - start
    head, _, rest = data.partition(b"\r\n\r\n")
    return head.split(b"\r\n")[0].decode(), json.loads(rest or b"null"), time.monotonic() - start


def _length(data):
    for line in data.split(b"\r\n\r\n", 1)[0].split(b"\r\n"):
        if line.lower().startswith(b"content-length:"):
            return int(line.split(b":")[1])
    return 0


@pytest.fixture(scope="module")
def server():
    process, port = _start()
    yield port
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=30)
    assert "Traceback" not in err, err


def test_slow_clients_do_not_hold_the_upload_slots(server):
    """Two clients sending a byte every two seconds held both slots; a normal upload waited 60 s for a 503.

    The trickling clients themselves get a 408 within the read deadline, and the normal upload its 200."""
    answers = []
    slow = [threading.Thread(target=lambda: answers.append(_upload(server, b"x" * 60, declared=1000, every=2.0)),
                             daemon=True) for _ in range(explore_app.MAX_CONCURRENT_UPLOADS)]
    for thread in slow:
        thread.start()
    time.sleep(1.0)
    status, answer, seconds = _upload(server, WALL.encode())
    assert status.endswith("200 OK"), (status, answer)
    assert seconds < explore_app.READ_GRACE + 10, seconds
    for thread in slow:
        thread.join(30)
    assert len(answers) == explore_app.MAX_CONCURRENT_UPLOADS, answers
    for status, answer, seconds in answers:
        assert status.split()[1] == "408" and "too slowly" in answer["error"], (status, answer)
        assert seconds < explore_app.READ_GRACE + 5, seconds


@pytest.mark.parametrize("declared", [True, False])
def test_a_large_upload_gets_its_413(server, declared):
    body = b"0" * (40 << 20)
    status, answer, _ = _upload(server, body, declared=None if declared else len(body))
    assert status.split()[1] == "413", status
    assert answer == {"error": "the file is larger than 16 MiB", "field": "upload"}


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_stopping_during_an_upload_prints_no_traceback(sig):
    process, port = _start()
    answers = []
    thread = threading.Thread(target=lambda: answers.append(_upload(port, b"x" * 40, every=0.3)), daemon=True)
    thread.start()
    time.sleep(2.0)  # the upload is being read
    process.send_signal(sig)
    out, err = process.communicate(timeout=30)
    thread.join(10)
    assert "Traceback" not in err and "CancelledError" not in err, err
    if sig == signal.SIGINT:
        assert "coinwall explore: stopped" in out
    assert answers and (answers[0][0].startswith("OSError") or answers[0][0].split()[1] in ("503", "408")), answers
