"""Progress bars of the long CLI commands, checked on a real pseudo-terminal.

``coinwall simulate``, ``correlation``, ``kam``, ``section`` and ``coin3d bounce`` draw a tqdm bar on stderr when
stderr is a terminal, counting in whole numbers, and draw nothing with ``--json`` or when stderr is a pipe; Ctrl-C
stops ``coin3d bounce`` within a second with one line.  ``isatty`` cannot be faked with pytest's capture, so the
tests on a terminal give the command the slave side of a pty from ``os.openpty`` as stderr (and for ``--json`` as
stdout too): in this process (:func:`_run_here`: ``sys.stderr`` is a text stream on the pty, as a terminal's is),
and, for a terminal that reports no size and for Ctrl-C, in a fresh Python process whose descriptors are the pty
(:func:`_run`: interpreter start, imports, the kernel's load, a short run: a second or two each).  Without a
terminal the commands run in this process (pytest's capture is no terminal either).
"""

import io
import json
import os
import re
import subprocess
import sys
import threading

import pytest

if not hasattr(os, "openpty") or sys.platform.startswith("win"):
    pytest.skip("needs a POSIX pseudo-terminal (os.openpty)", allow_module_level=True)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"
BAR = re.compile(r"\d+%\|")  # tqdm's "  0%|", " 50%|", "100%|"

# (command, unit of its bar): sizes chosen to be short but to need a bar (simulate draws one only
# above its 200 000-collision chunk)
COMMANDS = {
    "simulate": (["simulate", ELLIPSE, "--param", "eps=99", "--H", "2.4", "--collisions", "1000000", "--seed", "1"],
                 "coll"),
    "correlation": (["correlation", ELLIPSE, "--param", "eps=99", "--H", "2.4", "--bounces", "100000",
                     "--max-lag", "10", "--orbits", "10", "--seed", "1"], "bounce"),
    "kam": (["kam", "--H", "3", "--orbits", "4", "--collisions", "200", "--steps", "1"], "eval"),
    # two groups of 20 orbits (poincare_section holds 2·10⁶ collisions at a time), no figure
    "section": (["section", ELLIPSE, "--param", "eps=0.55", "--H", "1.9", "--orbits", "30", "--collisions", "100000",
                 "--seed", "1"], "orbit"),
    # three batches of 2,000 tosses × 10 bounces
    "coin3d": (["coin3d", "bounce", "--e", "0.6", "--bounces", "10", "--samples", "6000", "--seed", "1"], "toss"),
}
SCALED = re.compile(r"\d\.\d+/\d")  # "7.00/45.0": a count printed as a scaled float


def _set_size(fd, rows, columns):
    import fcntl
    import struct
    import termios

    fcntl.ioctl(fd, termios.TIOCSWINSZ, struct.pack("HHHH", rows, columns, 0, 0))


def _drain(master, received):
    """Read the pty's master side until every slave descriptor is closed (so the writer never blocks)."""
    while True:
        try:
            data = os.read(master, 65536)
        except OSError:  # EIO: every slave descriptor is closed (Linux)
            return
        if not data:
            return
        received.append(data)


def _run(argv, stdout_tty=False, size=(24, 100), timeout=180):
    """Run ``coinwall argv`` with stderr on a pty (and with ``stdout_tty`` stdout too); returns (exit status,
    stdout text, "", what reached the terminal) (the pty turns "\\n" into "\\r\\n")."""
    env = dict(os.environ)
    env["PYTHONPATH"] = ROOT + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env.pop("COLUMNS", None), env.pop("LINES", None)  # the terminal's own size must decide
    command = [sys.executable, "-c", "import sys; from coinwall.cases.cli import main; sys.exit(main())", *argv]
    master, slave = os.openpty()
    if size is not None:
        _set_size(slave, *size)
    received = []
    reader = threading.Thread(target=_drain, args=(master, received), daemon=True)  # the child never blocks
    reader.start()
    try:
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=slave if stdout_tty else subprocess.PIPE,
                                   stderr=slave, env=env)
    finally:
        os.close(slave)
    try:
        stdout, _ = process.communicate(timeout=timeout)
    finally:
        if process.poll() is None:
            process.kill()
        reader.join(10)
        os.close(master)
    return process.returncode, (stdout or b"").decode(), "", b"".join(received).decode(errors="replace")


def _run_here(argv, stdout_tty=False, size=(24, 100)):
    """:func:`_run` in this process: ``sys.stderr`` (and with ``stdout_tty`` ``sys.stdout``) a text stream on the
    slave side of a pty of ``size``, as Python makes it for a terminal; otherwise stdout is collected."""
    from coinwall.cases.cli.main import main

    master, slave = os.openpty()
    _set_size(slave, *size)
    received = []
    reader = threading.Thread(target=_drain, args=(master, received), daemon=True)
    reader.start()
    terminal = io.TextIOWrapper(io.FileIO(slave, "w", closefd=True), encoding="utf-8", errors="backslashreplace",
                                line_buffering=True)
    collected = terminal if stdout_tty else io.StringIO()
    try:
        with pytest.MonkeyPatch.context() as patch:
            patch.delenv("COLUMNS", raising=False), patch.delenv("LINES", raising=False)  # the terminal's size decides
            patch.setattr(sys, "stderr", terminal)
            patch.setattr(sys, "stdout", collected)
            try:
                status = main(argv)
            except SystemExit as exc:
                status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            stdout = "" if stdout_tty else collected.getvalue()
    finally:
        terminal.close()  # the last slave descriptor: the reader sees EIO
        reader.join(10)
        os.close(master)
    return status, stdout, "", b"".join(received).decode(errors="replace")


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_bar_on_a_terminal(name):
    argv, unit = COMMANDS[name]
    status, stdout, _, terminal = _run_here(argv)
    assert status == 0, terminal
    assert BAR.search(terminal) and f"{unit}/s" in terminal, terminal
    assert re.search(r"\| *\d+/\d+ \[", terminal) and not SCALED.search(terminal), terminal  # whole numbers
    # leave=False: the bar is wiped at the end ("\r", blanks, "\r"), the summary goes to stdout
    assert terminal.rstrip(" ").endswith("\r"), terminal[-200:]
    assert stdout.strip()


def test_bar_on_a_terminal_that_reports_no_size():
    # a pty nobody sized is 0 × 0 (some containers and CI runners): tqdm alone would hide its bar
    argv, unit = COMMANDS["simulate"]
    status, _, _, terminal = _run(argv, size=None)
    assert status == 0, terminal
    assert BAR.search(terminal) and f"{unit}/s" in terminal, terminal


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_json_on_a_terminal_is_quiet(name):
    # stdout and stderr both on the terminal, as when a user types the command: everything that
    # arrives must be the JSON document and nothing else
    argv, unit = COMMANDS[name]
    status, _, _, terminal = _run_here(argv + ["--json"], stdout_tty=True)
    assert status == 0, terminal
    assert not BAR.search(terminal) and f"{unit}/s" not in terminal, terminal
    doc = json.loads(terminal.replace("\r\n", "\n"))
    assert isinstance(doc, dict) and doc


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_no_bar_when_stderr_is_not_a_terminal(name, capsys):
    """In this process: pytest's capture is a stream that is not a terminal, as a pipe or a file is."""
    from coinwall.cases.cli.main import main

    argv, unit = COMMANDS[name]
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert not sys.stderr.isatty()
    assert not BAR.search(captured.err) and f"{unit}/s" not in captured.err and "\r" not in captured.err, captured.err
    assert captured.out.strip()


def test_ctrl_c_stops_coin3d_bounce_within_a_second():
    """Ctrl-C while the tosses run (the bar is on the terminal): one line, status 130, within a second (the compiled
    kernel runs in batches of a fraction of a second; it used to run all tosses in one call, for a minute)."""
    import signal
    import time

    argv = ["coin3d", "bounce", "--e", "0.6", "--bounces", "20", "--samples", "2000000", "--seed", "1", "--allow-long"]
    env = dict(os.environ)
    env["PYTHONPATH"] = ROOT + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    command = [sys.executable, "-c", "import sys; from coinwall.cases.cli import main; sys.exit(main())", *argv]
    master, slave = os.openpty()
    _set_size(slave, 24, 100)
    received = []
    seen = threading.Event()

    def read():
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:
                return
            if not data:
                return
            received.append(data)
            if BAR.search(b"".join(received).decode(errors="replace")):
                seen.set()

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=slave, env=env,
                                   start_new_session=True,
                                   preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    finally:
        os.close(slave)
    try:
        assert seen.wait(120), "no progress bar"
        time.sleep(0.5)
        sent = time.monotonic()
        os.killpg(process.pid, signal.SIGINT)
        process.wait(30)
        took = time.monotonic() - sent
    finally:
        if process.poll() is None:
            process.kill()
        reader.join(10)
        os.close(master)
    terminal = b"".join(received).decode(errors="replace")
    assert process.returncode == 130, terminal[-500:]
    assert "coinwall: interrupted" in terminal and "Traceback" not in terminal
    assert took < 1.5, f"took {took:.2f} s to stop"  # a second, with a margin for a loaded machine
