"""The one writer, through the command line: a replaced file keeps what it was (its mode, its owner), only a
regular file is ever replaced, and the report is never lost (a closed or full standard output is an error).

Each case compares the folder before and after (nothing created, changed or deleted on a refusal).
"""

import os
import stat
import subprocess
import sys

import numpy as np
import pytest

from coinwall.cases.cli.main import main

# every format of every kind of writer: the solved body (the exporters), the wall tables and figures (`wall`),
# a staged commit (`fit`: the fitted wall, then the body)
COMMANDS = {
    "solve": (["solve", "1+0.05*cos(2*t)", "--no-cross-check"], [".csv", ".dxf", ".json", ".svg", ".png", ".pdf"]),
    "wall": (["wall", "--polar", "1"], [".csv", ".json", ".svg", ".png"]),
    "fit": (["fit", "scan.csv"], ["wall.csv", ".json", ".svg"]),
}


def _scan(folder):
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    np.savetxt(folder / "scan.csv", np.column_stack([theta, 1 + 0.05 * np.cos(2 * theta)]), delimiter=",",
               header="theta,b", comments="", fmt="%.6f")


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_a_replaced_file_keeps_its_mode_and_owner(tmp_path, monkeypatch, capsys, command):
    """`solve -o priv.csv` over a 0600 file used to leave a 0644 file; the owner and group were lost too."""
    monkeypatch.chdir(tmp_path)
    _scan(tmp_path)
    args, suffixes = COMMANDS[command]
    names = [f"out{suffix}" if suffix.startswith(".") else f"fitted-{suffix}" for suffix in suffixes]
    modes = [0o600, 0o640, 0o604, 0o664, 0o400 | 0o200, 0o660][:len(names)]
    root = hasattr(os, "geteuid") and os.geteuid() == 0
    for name, mode in zip(names, modes):
        (tmp_path / name).write_text("old")
        os.chmod(name, mode)
        if root:
            os.chown(name, 4242, 4343)  # another user's file in a folder of ours (only root may give files away)
    assert main([*args, *(x for name in names for x in ("-o", name))]) == 0
    assert "replaced" in capsys.readouterr().out
    for name, mode in zip(names, modes):
        info = os.stat(name)
        assert (tmp_path / name).read_bytes() != b"old"
        assert stat.S_IMODE(info.st_mode) == mode, name
        if root:
            assert (info.st_uid, info.st_gid) == (4242, 4343), name


def test_a_new_file_gets_the_mode_of_a_plain_open(tmp_path, capsys):
    mask = os.umask(0o027)
    try:
        assert main(["wall", "--polar", "1", "-o", str(tmp_path / "new" / "w.csv")]) == 0
    finally:
        os.umask(mask)
    assert stat.S_IMODE(os.stat(tmp_path / "new" / "w.csv").st_mode) == 0o640
    assert stat.S_IMODE(os.stat(tmp_path / "new").st_mode) == 0o750


def _fifo(path):
    os.mkfifo(path)


def _link(path):
    (path.parent / "target.csv").write_text("old")
    os.symlink(path.parent / "target.csv", path)


def _dangling(path):
    os.symlink(path.parent / "nowhere.csv", path)


def _socket(path):
    import socket

    sock = socket.socket(socket.AF_UNIX)
    sock.bind(str(path))
    sock.close()


@pytest.mark.parametrize("make,words", [(_fifo, "FIFO"), (_link, "symbolic link"), (_dangling, "symbolic link"),
                                        (_socket, "socket")])
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_only_a_regular_file_is_replaced(tmp_path, monkeypatch, capsys, make, words, command):
    """A named pipe given as the output used to be replaced by a regular file; so did a link."""
    monkeypatch.chdir(tmp_path)
    _scan(tmp_path)
    args, suffixes = COMMANDS[command]
    name = "x" + suffixes[-1] if command != "fit" else "fitted-wall.csv"
    make(tmp_path / name)
    before = {entry.name: (entry.stat(follow_symlinks=False).st_mode, entry.stat(follow_symlinks=False).st_mtime_ns)
              for entry in os.scandir(tmp_path)}
    assert main([*args, "-o", "other" + suffixes[0] if command != "fit" else "o.json", "-o", name]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err and name in err and "regular file" in err, err
    after = {entry.name: (entry.stat(follow_symlinks=False).st_mode, entry.stat(follow_symlinks=False).st_mtime_ns)
             for entry in os.scandir(tmp_path)}
    assert after == before


_REPORT = [sys.executable, "-m", "coinwall", "critical", "1+0.1*cos(2*t)", "--json"]


def test_a_closed_standard_output_is_refused(tmp_path):
    """`coinwall critical ... --json >&-` used to lose the JSON and exit 0."""
    done = subprocess.run(_REPORT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True, cwd=tmp_path, timeout=120, preexec_fn=lambda: os.close(1), check=False)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "standard output is closed" in done.stderr
    assert os.listdir(tmp_path) == []


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
def test_a_full_standard_output_is_an_error():
    """The report written to a full disk (/dev/full): one line, exit status 2, not 0."""
    with open("/dev/full", "w") as full:
        done = subprocess.run(_REPORT, stdout=full, stderr=subprocess.PIPE, text=True, timeout=120, check=False)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "No space left on device" in done.stderr
