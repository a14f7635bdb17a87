"""``coinwall explore``'s JSON API without a browser (issue 14): answers, limits, errors, time limits.

Skipped when the optional extra (starlette, uvicorn, httpx for the test client) is not installed.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import io
import json
import math
import types
import warnings
import xml.etree.ElementTree as ET

import pytest

pytest.importorskip("starlette", reason="the explorer needs starlette (pip install -e '.[explore]')")
pytest.importorskip("uvicorn", reason="the explorer needs uvicorn (pip install -e '.[explore]')")
pytest.importorskip("httpx", reason="starlette's test client needs httpx")

with warnings.catch_warnings():  # starlette 1.x asks for httpx2 but still works with httpx
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient

from coinwall.cases.explore import app as explore_app
from coinwall.cases.explore.worker import JobError, Superseded, Worker

ELLIPSE = {"expression": "sqrt((1+eps*cos(t)**2)/(1+eps))", "params": "eps=1"}  # paper eq. 26, ε = 1


@pytest.fixture(scope="module")
def client():
    app = explore_app.create_app()

    @explore_app.guarded
    async def guarded_bug(request):
        raise RuntimeError("an unexpected failure inside a handler")

    async def bare_bug(request):  # not wrapped: the application's last exception handler answers
        raise RuntimeError("an unexpected failure outside the guard")

    app.add_route("/api/test-guarded-bug", guarded_bug, methods=["POST"])
    app.add_route("/api/test-bare-bug", bare_bug, methods=["POST"])
    # the server answers the Host it is bound to (127.0.0.1), not TestClient's default "testserver"
    with TestClient(app, raise_server_exceptions=False, base_url="http://127.0.0.1:8765") as test_client:
        yield test_client


def test_page_and_assets_are_served_from_the_package(client):
    page = client.get("/")
    assert page.status_code == 200 and 'id="body-outline"' in page.text
    for needle in ('id="wall"', 'id="b0" type="range"', 'id="bc"', 'id="regime"'):
        assert needle in page.text
    assert "http://" not in page.text and "https://" not in page.text  # no CDN: works offline
    assert client.get("/static/explore.js").status_code == 200
    assert client.get("/static/explore.css").status_code == 200


def test_default_case_has_b_c_minus_one_half_as_coinwall_critical_prints_it(client, capsys):
    from coinwall.cases.cli.main import main

    cases = client.get("/api/cases").json()
    assert cases["default"] in {c["name"] for c in cases["cases"]}
    info = client.post("/api/wall", json={"case": cases["default"]}).json()
    assert info["b_c"] == pytest.approx(-0.5, abs=1e-12)  # −1/(1+ε), paper Appendix
    main(["critical", f"case:{cases['default']}"])
    printed = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("b_c"))
    assert printed.split()[1] == info["b_c_text"] == "-0.5"
    low, high = info["range"]
    assert low < info["b_c"] < high  # the slider crosses b_c


def test_b_c_prints_at_its_precision(client):
    # the coin: ε = 99, b_c = −1/(1+ε) = −0.01 (computed as −0.0099999999999999)
    info = client.post("/api/wall", json={"case": "coin"}).json()
    assert info["b_c"] == pytest.approx(-0.01, abs=1e-12) and info["b_c_text"] == "-0.01"


def test_parameters_follow_the_expression(client):
    # a value left over from the previous wall is dropped, not refused
    info = client.post("/api/wall", json={"expression": "1 + 0.3*cos(2*t)", "params": "eps=1"})
    assert info.status_code == 200, info.text
    assert info.json()["params"] == [] and info.json()["b_c_text"] == "-0.1"  # b + b'' = 1 − 0.9 cos 2θ
    # a new name gets a value (and the page a slider); the values given are used, in the order of the text
    info = client.post("/api/wall", json={"expression": "a*cos(2*t) + 1", "params": {}}).json()
    assert info["params"] == [["a", explore_app_compute().PARAM_DEFAULT]]
    info = client.post("/api/wall", json={"expression": "1 + a*cos(2*t) + c*cos(3*t)",
                                          "params": {"c": 0.01, "a": 0.1, "gone": 3}}).json()
    assert info["params"] == [["a", 0.1], ["c", 0.01]]
    body = client.post("/api/body", json={"expression": "1 + a*cos(2*t)", "params": {"a": 0.1}, "b0": 0}).json()
    assert body["regime"] == "convex" and body["wall"][0] == pytest.approx(1.1)


def explore_app_compute():
    from coinwall.cases.explore import compute

    return compute


def test_a_new_wall_starts_at_b0_0_with_room_to_move(client):
    info = client.post("/api/wall", json={"expression": "1 + 0.1*cos(3*t)"}).json()
    assert info["b0"] == 0 and info["range"][0] < info["b_c"] < info["range"][1]
    assert info["H"] == pytest.approx(1.5 * 2, rel=0.05)  # 1.5 × the body's width (constant width 2)
    assert client.post("/api/wall", json={"case": "appendix-corner", "b0": -0.6}).json()["b0"] == -0.6  # a case's b0
    # a drawing 40 units wide comes back at its own size (b0 = 0), with a slider and an H of its scale
    svg = (b'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">'
           b'<ellipse cx="50" cy="50" rx="20" ry="12"/></svg>')
    info = client.post("/api/upload?name=e.svg", content=svg).json()
    assert info["b0"] == 0 and info["range"][0] < -10 and info["range"][1] > 5
    assert info["H"] == pytest.approx(60)  # 1.5 × 40
    body = client.post("/api/body", json={"upload": info["upload"], "b0": info["b0"]}).json()
    assert body["area"] == pytest.approx(math.pi * 20 * 12, rel=1e-3)
    table = client.post("/api/table", json={"upload": info["upload"], "b0": 0, "H": info["H"]})
    assert table.status_code == 200, table.text
    # a wall of samples after it starts at b0 = 0 too
    text = "theta,b\n" + "".join(f"{2 * math.pi * k / 64!r},{1 + 0.1 * math.cos(6 * math.pi * k / 64)!r}\n"
                                 for k in range(64))
    assert client.post("/api/upload?name=wall.csv", content=text.encode()).json()["b0"] == 0


def test_messages_speak_the_page_language(client):
    from coinwall.cases.explore.worker import page_words

    assert "--" not in page_words("unknown name 'x'; declare it with --param x=VALUE")
    assert page_words("no κ (--allow-unrealizable)") == "no κ"
    for request_json in ({"expression": "1 + cos(", "params": ""}, {"expression": "1 + x_*cos(2*t)", "params": "x_=a"},
                         {"expression": "1 + ε*cos(2*t)"}, {"expression": "exp(t)"}):
        answer = client.post("/api/wall", json=request_json)
        assert answer.status_code == 400 and "--" not in answer.json()["error"], answer.text
    answer = client.post("/api/export", json=dict(ELLIPSE, b0=-0.3, format="svg", kappa=10, units="mm"))
    assert answer.status_code == 400 and "--" not in answer.json()["error"]


@pytest.mark.parametrize(("b0", "regime", "corners"), [(-0.3, "convex", 0), (-0.5, "critical", 0), (-0.6, "corner", 2)])
def test_body_regimes(client, b0, regime, corners):
    body = client.post("/api/body", json=dict(ELLIPSE, b0=b0)).json()
    assert body["regime"] == regime and len(body["corners"]) == corners
    assert body["path"].startswith("M") and body["path"].endswith("Z")
    assert len(body["theta"]) == len(body["wall"]) == len(body["own_wall"]) == len(body["rho"])
    if regime == "convex":  # R(0) = b0 + 1 (paper Appendix): the outline's first node is on the +x axis
        assert body["extent"] == pytest.approx(b0 + 1, abs=1e-6)
        assert body["points"] == 1024
        assert min(body["rho"]) == pytest.approx(b0 + 0.5, abs=1e-6)  # ρ = b0 + b + b'' has minimum b0 − b_c


def test_realizability(client):
    # b0 = 0.2: the ellipse x²/1.2² + y²/… has κ_max = its semi-major axis 1.2 (realizability.py docstring)
    out = client.post("/api/realize", json=dict(ELLIPSE, b0=0.2)).json()
    assert out["kappa_max"] == pytest.approx(1.2, rel=1e-6) and out["realizable"] is True
    out = client.post("/api/realize", json=dict(ELLIPSE, b0=-0.3)).json()
    assert out["kappa_max"] == pytest.approx(0.7, rel=1e-6) and out["realizable"] is False


@pytest.mark.parametrize("fmt", ["svg", "dxf", "json"])
def test_exports(client, fmt):
    answer = client.post("/api/export", json=dict(ELLIPSE, b0=0.2, format=fmt, kappa=10, units="mm"))
    assert answer.status_code == 200, answer.text
    assert f'filename="body.{fmt}"' in answer.headers["content-disposition"]
    if fmt == "svg":
        root = ET.fromstring(answer.content)
        assert root.tag.endswith("svg") and root.get("width").endswith("mm")
    elif fmt == "json":
        assert json.loads(answer.content)
    else:
        assert b"SECTION" in answer.content


@pytest.mark.parametrize(("request_json", "field", "words"), [
    ({"expression": "1 + cos(", "params": ""}, "wall", "never closed"),
    ({"expression": "__import__('os')", "params": ""}, "wall", "not allowed"),
    ({"expression": "/etc/passwd.csv", "params": ""}, "wall", "syntax error"),  # never read as a file
    ({"expression": "1 + eps*cos(2*t)", "params": "eps=x"}, "params", "eps"),
    ({"expression": "", "params": ""}, "wall", "empty"),
    ({"case": "no-such-case"}, "case", "unknown case"),
])
def test_bad_walls_are_messages_next_to_their_field(client, request_json, field, words):
    answer = client.post("/api/wall", json=request_json)
    assert answer.status_code == 400
    assert answer.json()["field"] == field and words in answer.json()["error"]


@pytest.mark.parametrize(("b0", "words"), [("x", "b0"), (None, "b0"), (-0.8, "b0"), (1e300, "b0")])
def test_bad_offsets(client, b0, words):
    answer = client.post("/api/body", json=dict(ELLIPSE, b0=b0))
    assert answer.status_code == 400 and answer.json()["field"] == "b0", answer.text
    assert words in answer.json()["error"]


def test_bad_requests_and_limits(client, monkeypatch):
    assert client.post("/api/wall", content=b"not json").status_code == 400
    assert client.post("/api/wall", content=b"[1, 2]").json()["error"] == "the request must be a JSON object"
    big = json.dumps(dict(ELLIPSE, padding="x" * explore_app.MAX_JSON_BYTES))
    answer = client.post("/api/wall", content=big)
    assert answer.status_code == 413 and "larger than" in answer.json()["error"]
    answer = client.post("/api/export", json=dict(ELLIPSE, b0=0.2, format="svg", kappa=10))
    assert answer.status_code == 400 and answer.json()["field"] == "kappa" and "units" in answer.json()["error"]
    # as `coinwall solve --kappa`: no real-size drawing of a body that no mass distribution realizes
    answer = client.post("/api/export", json=dict(ELLIPSE, b0=-0.3, format="svg", kappa=10, units="mm"))
    assert answer.status_code == 400 and answer.json()["field"] == "kappa" and "κ_max = 0.7" in answer.json()["error"]
    answer = client.post("/api/export", json=dict(ELLIPSE, b0=-0.3, format="svg", kappa=10, units="mm",
                                                  allow_unrealizable=True))
    assert answer.status_code == 200
    answer = client.get("/api/nothing-here")
    assert answer.status_code == 404 and "error" in answer.json()
    monkeypatch.setattr(explore_app, "MAX_UPLOAD_BYTES", 1000)
    answer = client.post("/api/upload?name=w.csv", content=b"0" * 2000)
    assert answer.status_code == 413


def test_host_and_origin(client):
    answer = client.post("/api/wall", json=ELLIPSE, headers={"Host": "evil.example"})  # DNS rebinding
    assert answer.status_code == 400
    assert client.get("/", headers={"Host": "attacker.example:8765"}).status_code == 400
    assert client.get("/", headers={"Host": "localhost:8765"}).status_code == 200
    answer = client.post("/api/wall", json=ELLIPSE, headers={"Origin": "http://evil.example"})  # another site
    assert answer.status_code == 403 and "error" in answer.json()
    answer = client.post("/api/wall", json=ELLIPSE, headers={"Origin": "null"})
    assert answer.status_code == 403
    assert client.post("/api/wall", json=ELLIPSE, headers={"Origin": "http://127.0.0.1:8765"}).status_code == 200
    assert client.post("/api/wall", json=ELLIPSE).status_code == 200  # not a browser: no Origin
    assert explore_app.allowed_hosts("127.0.0.1") == sorted({"127.0.0.1", "localhost", "::1", "[::1]"})
    assert explore_app.allowed_hosts("192.168.1.5") == ["192.168.1.5"]


@pytest.mark.parametrize(("route", "content", "field"), [
    ("/api/body", b'{"expression": "1", "b0": ' + b"1" * 5000 + b"}", None),  # over Python's 4,300 digits
    ("/api/body", b'{"expression": "1", "b0": ' + b"1" * 4000 + b"}", None),
    ("/api/body", b'{"expression": "1", "b0": 0.' + b"1" * 4000 + b"}", None),
    ("/api/table", b'{"expression": "1", "b0": 0, "H": 1' + b"0" * 400 + b"}", None),
    ("/api/body", b'{"expression": "1", "b0": NaN}', None),
    ("/api/wall", b'{"upload": [1, 2]}', "upload"),
    ("/api/wall", b'{"upload": {"a": 1}}', "upload"),
    ("/api/wall", b'{"case": 3}', "case"),
    ("/api/wall", b'{"expression": ["1"]}', "wall"),
    ("/api/wall", b'{"expression": "1 + a*cos(t)", "params": [1]}', "params"),
    ("/api/wall", b'{"expression": "1 + a*cos(t)", "params": {"a": "x"}}', "params"),
    ("/api/wall", b'{"expression": "1 + a*cos(t)", "params": {"a": 1e308, "b": 2}}', "wall"),
    ("/api/beam", b'{"expression": "1", "b0": 0, "H": 3, "theta": [1], "eta": 1.5}', None),
])
def test_odd_requests_are_4xx_json_never_a_bug(client, route, content, field):
    answer = client.post(route, content=content)
    assert 400 <= answer.status_code < 500 and answer.status_code != 422, answer.text
    assert "internal error" not in answer.json()["error"] and "bug" not in answer.json()["error"]
    if field:
        assert answer.json()["field"] == field


# one grammar: what the command line refuses, the server refuses -- numbers are JSON numbers (Python's float()
# would read "3_0" as 30, "３" as 3, true as 1), parameter lists have no empty item, expressions are one line
_LINE = {"expression": "1 + 0.1*cos(2*t)"}


@pytest.mark.parametrize(("route", "request_json", "field", "needle"), [
    ("/api/table", dict(_LINE, b0=0, H="3_0"), "H", "`H` must be a number, got '3_0'"),
    ("/api/table", dict(_LINE, b0=0, H="\uff13"), "H", "`H` must be a number"),
    ("/api/table", dict(_LINE, b0=0, H=True), "H", "`H` must be a number, got True"),
    ("/api/table", dict(_LINE, b0="0x1", H=3), "b0", "`b0` must be a number"),
    ("/api/beam", dict(_LINE, b0=0, H=3, theta="1_0", eta=1.5), "beam", "`theta` must be a number"),
    ("/api/beam", dict(_LINE, b0=0, H=3, theta=0.1, eta=1.5, direction="1e999"), "beam", "`direction` must be"),
    ("/api/beam", dict(_LINE, b0=0, H=3, theta=0.1, eta=1.5, spread="nan"), "beam", "`spread` must be a number"),
    ("/api/export", dict(_LINE, b0=0, format="svg", kappa="1_0", units="mm"), "kappa", "`kappa` must be a number"),
    ("/api/wall", {"expression": "1 + eps*cos(t)", "params": "eps=0.1,,"}, "params", "empty item"),
    ("/api/wall", {"expression": "1 + eps*cos(t)", "params": ",eps=0.1"}, "params", "empty item"),
    ("/api/wall", {"expression": "1 + eps*cos(t)", "params": "eps=0.1;"}, "params", "plain decimal number"),
    ("/api/wall", {"expression": "1 + 0.1*cos(t) # + 0.2*cos(3*t)"}, "wall", "no comments"),
    ("/api/wall", {"expression": "1 + 0.1*cos(t,)"}, "wall", "empty argument"),
    ("/api/wall", {"expression": "(1 + 0.1\n*cos(t))"}, "wall", "one line"),
])
def test_the_server_reads_the_command_lines_grammar(client, route, request_json, field, needle):
    answer = client.post(route, json=request_json)
    assert answer.status_code == 400, answer.text
    assert answer.json()["field"] == field and needle in answer.json()["error"]



def test_oversize_upload_is_a_json_413_read_no_further(client, monkeypatch):
    answer = client.post("/api/upload?name=w.csv", content=b"0" * (explore_app.MAX_UPLOAD_BYTES + 1))
    assert answer.status_code == 413 and answer.json() == {"error": "the file is larger than 16 MiB", "field": "upload"}

    class Streamed:  # a chunked request (no declared length): reading stops at the limit
        headers = types.MappingProxyType({})
        read = 0

        async def stream(self):
            for _ in range(1000):
                Streamed.read += 1024
                yield b"0" * 1024

    with pytest.raises(explore_app.RequestError) as refused:
        asyncio.run(explore_app._read_limited(Streamed(), 10 * 1024, "upload"))
    assert refused.value.status == 413 and Streamed.read == 11 * 1024


def test_uploads_wait_for_a_slot_and_too_many_are_refused(client, monkeypatch):
    assert client.app.state.upload_slots._value == explore_app.MAX_CONCURRENT_UPLOADS
    monkeypatch.setattr(explore_app, "MAX_WAITING_UPLOADS", 0)  # every slot taken: refused before reading
    answer = client.post("/api/upload?name=w.csv", content=b"theta,b\n0,1\n")
    assert answer.status_code == 503 and answer.json()["field"] == "upload" and "busy" in answer.json()["error"]


def test_a_client_disconnect_is_logged_as_such(caplog):
    from starlette.requests import Request

    async def receive():
        return {"type": "http.disconnect"}

    scope = {"type": "http", "method": "POST", "path": "/api/wall", "headers": [], "query_string": b"",
             "scheme": "http", "server": ("127.0.0.1", 8765)}
    handler = explore_app._job("wall")
    with caplog.at_level("INFO", logger="coinwall.explore"):
        asyncio.run(handler(Request(scope, receive)))
    assert "disconnected" in caplog.text and "internal error" not in caplog.text


def test_uploads(client):
    theta = [2 * math.pi * k / 64 for k in range(64)]
    text = "theta,b\n" + "".join(f"{t!r},{1 + 0.1 * math.cos(3 * t)!r}\n" for t in theta)
    info = client.post("/api/upload?name=wall.csv", content=text.encode()).json()
    assert info["b_c"] == pytest.approx(-0.2, abs=2e-3)  # 1 + 0.1 cos 3θ: b_c = −0.2, from 64 samples
    body = client.post("/api/body", json={"upload": info["upload"], "b0": 0.0}).json()
    assert body["regime"] == "convex"
    square = (b'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">'
              b'<rect x="1" y="1" width="2" height="2"/></svg>')
    info = client.post("/api/upload?name=square.svg", content=square).json()
    assert info["b_c"] == pytest.approx(0.0, abs=1e-6)  # a polygon: ρ = 0 on its vertex windows
    answer = client.post("/api/upload?name=wall.txt", content=b"1,2\n")
    assert answer.status_code == 400 and answer.json()["field"] == "upload"
    answer = client.post("/api/upload?name=w.csv", content=b"theta,b\n0,1\n")
    assert answer.status_code == 400 and answer.json()["field"] == "upload"


def test_billiard(client):
    table = client.post("/api/table", json=dict(ELLIPSE, b0=0.0, H=3)).json()
    assert table["H"] == 3 and len(table["lower"]) == len(table["theta"])
    beam = client.post("/api/beam", json=dict(ELLIPSE, b0=0.0, H=3, theta=1.0, eta=1.5, direction=1.0, rays=20,
                                              collisions=10, section_collisions=200)).json()
    assert len(beam["rays"]) == 20 and all(len(r["t"]) == 10 for r in beam["rays"])
    assert len(beam["section"]["theta"]) > 50
    answer = client.post("/api/beam", json=dict(ELLIPSE, b0=0.0, H=3, theta=1.0, eta=50.0))
    assert answer.status_code == 400 and "outside the strip" in answer.json()["error"]
    answer = client.post("/api/table", json=dict(ELLIPSE, b0=0.0, H=0.5))
    assert answer.status_code == 400 and answer.json()["field"] == "H"


def test_an_unexpected_exception_is_a_json_message(client):
    for route in ("/api/test-guarded-bug", "/api/test-bare-bug"):
        answer = client.post(route, json={})
        assert answer.status_code == 422
        assert "internal error" in answer.json()["error"] and "Traceback" not in answer.text


@contextlib.contextmanager
def _worker():
    worker = Worker("test", jobs="explore_jobs")  # the server's jobs and one that fails as a bug would
    try:
        yield worker
    finally:
        worker.close()


def test_worker_bug_timeout_and_latest_wins():
    spec = dict(ELLIPSE, b0=-0.3)

    async def scenario(worker):
        with pytest.raises(JobError) as bug:  # a bug inside a job: a message, and the worker stays up
            await worker.call("crash", {}, timeout=30)
        assert bug.value.kind == "bug" and "ZeroDivisionError" in bug.value.message
        with pytest.raises(JobError) as late:  # the time limit stops the child; the next job gets a new one
            await worker.call("beam", dict(spec, H=3, theta=1.0, eta=1.5), timeout=0.01)
        assert late.value.kind == "timeout" and worker.restarts == 1
        assert (await worker.call("body", spec, timeout=30))["regime"] == "convex"
        # three quick moves: the first runs, the second is dropped unrun, the third (latest) runs
        results = await asyncio.gather(*(worker.call("body", dict(ELLIPSE, b0=b0), timeout=30, channel="body")
                                          for b0 in (-0.3, -0.4, -0.6)), return_exceptions=True)
        assert results[0]["b0"] == -0.3 and isinstance(results[1], Superseded) and results[2]["regime"] == "corner"

    with _worker() as worker:
        asyncio.run(scenario(worker))


def test_command_line_options():
    from coinwall.cases.cli import explore
    from coinwall.cases.cli.parser import CommandParser

    parser = CommandParser(prog="coinwall")
    explore.register(parser.add_subparsers(dest="command", parser_class=CommandParser))
    args = parser.parse_args(["explore", "--port", "0", "--no-browser"])
    assert (args.port, args.host, args.no_browser) == (0, "127.0.0.1", True)
    help_text = io.StringIO()
    with contextlib.redirect_stdout(help_text), pytest.raises(SystemExit):
        parser.parse_args(["explore", "--help"])
    assert "--no-browser" in help_text.getvalue()
    assert isinstance(parser, argparse.ArgumentParser)


def test_busy_port_is_a_message():
    import socket

    from coinwall.cases.explore.server import check_port
    from coinwall.forward.errors import InvalidArgument

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        with pytest.raises(InvalidArgument, match="choose another"):
            check_port("127.0.0.1", taken.getsockname()[1])


# ------------------------------------------------------------------------------------ fuzzing the server
# every route, a valid request with one or two fields replaced by a hostile value: the answer is 2xx or a 4xx
# JSON naming what was wrong -- never 422 ("a bug"), a 5xx, or a dropped connection
_HOSTILE_VALUES = [None, True, False, "", " ", "1_0", "\uff11", "0x10", "1e999", "nan", "-inf", "1,5", "abc", [], [1],
                   {}, {"a": 1}, 0, -1, 1e308, -1e308, 1e-320, 10 ** 30, 3.5, "1 + cos(", "1+0.1*cos(t) # c",
                   "(1+\n0.1*cos(t))", "\x00", "x" * 5000, "eps=1,,", "case:coin", "../../etc/passwd"]
_VALID = {
    "/api/wall": dict(_LINE),
    "/api/body": dict(_LINE, b0=0),
    "/api/realize": dict(_LINE, b0=0),
    "/api/table": dict(_LINE, b0=0, H=3),
    "/api/export": dict(_LINE, b0=0, format="svg"),
    "/api/beam": dict(_LINE, b0=0, H=3, theta=0.1, eta=1.5, rays=3, collisions=3, section_collisions=10),
}
_KEYS = ["expression", "params", "b0", "H", "theta", "eta", "rays", "collisions", "section_collisions", "direction",
         "spread", "kappa", "units", "format", "case", "upload", "allow_unrealizable"]


def test_fuzzed_requests_are_answered_never_a_bug(client):
    import random

    rng = random.Random(22)
    statuses = {}
    for _ in range(120):
        route = rng.choice(sorted(_VALID))
        request_json = dict(_VALID[route])
        for key in rng.sample(_KEYS, rng.choice([1, 1, 2])):
            request_json[key] = rng.choice(_HOSTILE_VALUES)
        answer = client.post(route, json=request_json)
        statuses[answer.status_code] = statuses.get(answer.status_code, 0) + 1
        assert answer.status_code in (200, 400, 404, 409, 413), (route, request_json, answer.text[:300])
        if answer.status_code != 200 or answer.headers["content-type"].startswith("application/json"):
            text = json.dumps(answer.json())
            assert "internal error" not in text and "bug" not in text, (route, request_json, text[:300])
    assert statuses.get(400, 0) > 30 and statuses.get(200, 0) > 10, statuses  # the fuzz reached both kinds


def test_sampled_walls_show_the_discrete_curvature_of_their_samples(client, tmp_path):
    """A wall given as data gets ρ as data: the discrete radius of curvature of its samples with the interval their
    rounding allows (what `coinwall solve -o body.png` draws), never b + b'' of an interpolant.

    Samples of an ellipse's support h = sqrt(a² cos²θ + b² sin²θ), rounded to 6 digits, 720 of them: each value
    is the uniform-step formula (h_{i−1} + h_{i+1} − 2 cos Δ h_i) / (2 (1 − cos Δ)) on the rounded numbers
    (docs/theory.md; recomputed here), each interval is the rounding of the three values carried through it, and
    the closed form a²b²/h³ lies within the interval widened by the formula's spacing error (Δ² max|ρ''|/12 ≤ 3e-4
    here).  A drawing (a triangle,
    4,096 samples of its support) is shown as per-bin bounds that stay at or above 0 (the vertex windows) — the
    interpolant's b + b'' swings to below −100 there."""
    import numpy as np

    a, b, n, b0 = 1.0, 0.6, 720, 0.25
    theta = 2 * np.pi * np.arange(n) / n
    h = np.round(np.sqrt(a**2 * np.cos(theta) ** 2 + b**2 * np.sin(theta) ** 2), 6)
    text = "theta,b\n" + "".join(f"{t:.12f},{v:.6f}\n" for t, v in zip(theta, h))
    info = client.post("/api/upload?name=ellipse.csv", content=text.encode()).json()
    body = client.post("/api/body", json={"upload": info["upload"], "b0": b0}).json()
    assert body["rho"] is None
    data = body["rho_data"]
    assert data["samples"] == n and not data["binned"] and len(data["theta"]) == n
    step = 2 * np.pi / n
    mine = (np.roll(h, 1) + np.roll(h, -1) - 2 * np.cos(step) * h) / (2 * (1 - np.cos(step))) + b0
    value, low, high = (np.array(data[k]) for k in ("value", "low", "high"))
    assert value == pytest.approx(mine, abs=1e-6)  # the page rounds to 6 decimals
    assert np.all(low <= value + 1e-6) and np.all(value <= high + 1e-6)
    # each value known to ±5e-7 (half its last digit): ρ_i to ±5e-7 (2 + 2 cos Δ) / (2 (1 − cos Δ)) = ±0.026
    half = 5e-7 * (2 + 2 * np.cos(step)) / (2 * (1 - np.cos(step)))
    assert np.median(high - low) == pytest.approx(2 * half, rel=0.02)
    exact = a**2 * b**2 / np.sqrt(a**2 * np.cos(theta) ** 2 + b**2 * np.sin(theta) ** 2) ** 3 + b0
    assert np.all(exact >= low - 3e-4) and np.all(exact <= high + 3e-4)
    assert data["b_c_lower"] <= -min(exact - b0) <= data["b_c_upper"]

    from coinwall.forward import Wall
    from coinwall.forward.formats import load_outline

    triangle = (b'<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
                b'<polygon points="10,10 60,20 25,55"/></svg>')
    info = client.post("/api/upload?name=triangle.svg", content=triangle).json()
    body = client.post("/api/body", json={"upload": info["upload"], "b0": 0.0}).json()
    data = body["rho_data"]
    assert body["rho"] is None and data["samples"] == 4096 and data["binned"] and len(data["theta"]) <= 2048
    assert min(data["low"]) > -1e-6 and max(data["high"]) > 1000  # 0 at the corners, the edges as spikes
    path = tmp_path / "triangle.svg"
    path.write_bytes(triangle)
    outline, _ = load_outline(str(path))
    grid = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)
    wall = Wall.from_samples(grid, outline.support(grid))
    support, _, second = wall.derivatives(np.linspace(0.0, 2 * np.pi, 361))
    assert np.min(support + second) < -100  # what the page drew before: the interpolant's noise
