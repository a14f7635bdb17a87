"""The command line's argument parsing, its last line of defence and file output (issues 12 and 16).

Bad input: one line on stderr, exit status 2, no traceback, no file written or replaced.  Outputs are
written all or nothing (a failed rename restores what was replaced), temporaries are removed on Ctrl-C,
SIGTERM and SIGHUP, and no file is ever written with a NaN or an infinity.
"""

import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from coinwall.cases.cli.main import EX_INTERRUPTED, EX_SOFTWARE, main
from coinwall.cases.cli.parser import build_parser
from coinwall.forward.errors import OutputError
from coinwall.forward.formats import output


def _one_error_line(capsys, *needles):
    """stderr is exactly one ``coinwall: error:`` line containing every needle (case-insensitive)."""
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("coinwall: error:"), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle.lower() in err.lower(), (needle, err)
    return err


def _temporaries(folder):
    return sorted(name for name in os.listdir(folder) if name.startswith(".coinwall-"))


# --------------------------------------------------------------------------- 1. a leading minus sign

def test_negative_offset_in_exponent_notation_is_read(capsys):
    assert main(["solve", "1+0.1*cos(2*t)", "--b0", "-1e-3", "--no-cross-check", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["b0"] == -1e-3


def test_wall_starting_with_minus(capsys):
    # b = 2 − cos t: b + b'' = 2 everywhere, so b_c = −2 exactly (closed form)
    assert main(["critical", "-cos(t)+2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["b_c"] == pytest.approx(-2.0, abs=1e-9)


@pytest.mark.parametrize("text,value", [("-1e-3", -1e-3), ("-.5", -0.5), ("-1.", -1.0), ("-2E+2", -200.0),
                                        ("-inf", -math.inf), ("-Infinity", -math.inf)])
def test_negative_numbers_in_any_notation_reach_the_checks(text, value):
    args = build_parser().parse_args(["simulate", "case:coin", "--collisions", "10", "--H", text])
    assert args.H == value
    assert build_parser().parse_args(["solve", "1", "--b0", text]).b0 == text  # --b0 is parsed by solve
    assert math.isnan(build_parser().parse_args(["simulate", "case:coin", "--H", "-nan"]).H)


@pytest.mark.parametrize("value", ["-inf", "-nan"])
def test_non_finite_wall_distance_refused_by_our_check(value, capsys):
    assert main(["simulate", "case:coin", "--collisions", "10", "--H", value]) == 2
    _one_error_line(capsys, "--H", "finite")


def test_minus_infinite_offset_refused_with_its_reason(capsys):
    assert main(["solve", "1", "--b0", "-inf"]) == 2
    _one_error_line(capsys, "--b0", "finite")


def test_options_still_work_around_the_minus_sign(capsys):
    parser = build_parser()
    args = parser.parse_args(["solve", "-cos(t)+2", "--poin", "100", "-obody.json", "--b0=-1e-3"])
    assert (args.wall, args.points, args.output, args.b0) == ("-cos(t)+2", 100, ["body.json"], "-1e-3")
    assert parser.parse_args(["critical", "--", "-a"]).wall == "-a"  # `--` still ends the options
    for bad, needle in (("--bogus", "unrecognized arguments: --bogus"), ("-x", "unrecognized arguments: -x")):
        with pytest.raises(SystemExit) as exc:
            main(["solve", "1", bad])
        assert exc.value.code == 2
        _one_error_line(capsys, needle)
    with pytest.raises(SystemExit) as exc:
        main(["solve", "--help"])
    assert exc.value.code == 0 and "usage: coinwall solve" in capsys.readouterr().out


@pytest.mark.parametrize("text", ["0x10", "1_0", "1e", "--", "\u0661", "-\u0661"])  # ١: an Arabic-Indic one
def test_number_flags_take_decimal_numbers_only(text, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["simulate", "case:coin", "--collisions", "10", "--H", text])
    assert exc.value.code == 2
    _one_error_line(capsys, "--H")


@pytest.mark.parametrize("args", [["wall", "--polar", "1", "--samples"], ["solve", "1", "--points"]])
@pytest.mark.parametrize("text", ["1_000", "\u0661\u0660\u0660", "0x100", "1.5", "1e-3", "2.55e1", "inf", "1e400"])
def test_count_flags_take_ascii_digits_only(args, text, capsys):
    with pytest.raises(SystemExit) as exc:
        main([*args, text])
    assert exc.value.code == 2
    _one_error_line(capsys, args[-1], "invalid count value")


@pytest.mark.parametrize("text,value", [("1e2", 100), ("2.5e2", 250), ("+90", 90), ("1E3", 1000)])
def test_count_flags_take_whole_numbers_in_exponent_notation(text, value, capsys):
    """The docs and the issues write large counts as 1e8; a whole number in that notation is that count."""
    from coinwall.cases.cli.common import count

    assert count(text) == value
    assert main(["wall", "--polar", "1", "--samples", text, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["samples"] == value


def test_a_double_dash_attached_as_a_value(capsys):
    """`--H=--`: Python 3.11's argparse gave the option an empty list (found by tests/cases/cli/test_fuzz_cli.py)."""
    with pytest.raises(SystemExit) as exc:
        main(["simulate", "case:coin", "--collisions", "10", "--H=--"])
    assert exc.value.code == 2
    _one_error_line(capsys, "--H", "'--'")
    assert main(["solve", "1", "--b0=--"]) == 2  # a text option: our own check refuses it
    _one_error_line(capsys, "--b0", "'--'")


# --------------------------------------------------------------------------- 2. --param

def test_repeated_param_is_refused(capsys):
    assert main(["critical", "1+a*cos(2*t)", "--param", "a=0.1", "--param", "a=0.2"]) == 2
    _one_error_line(capsys, "--param a given twice")
    assert main(["wall", "--polar", "1+a*cos(2*t)", "--param", "a=0.1", "--param", "a=0.1"]) == 2
    _one_error_line(capsys, "given twice")


@pytest.mark.parametrize("value", ["0x1", "1_0", "0o7", "1j", "\u0661"])
def test_param_takes_decimal_numbers_only(value, capsys):
    assert main(["critical", "1+a*cos(2*t)", "--param", f"a={value}"]) == 2
    _one_error_line(capsys, "parameter 'a'")


# --------------------------------------------------------------------------- 3. outputs all or nothing

def test_folder_among_outputs_replaces_nothing(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "good.csv").write_text("old")
    (tmp_path / "isdir.json").mkdir()
    assert main(["wall", "--polar", "1", "-o", "good.csv", "-o", "isdir.json"]) == 2
    _one_error_line(capsys, "'isdir.json'", "folder")
    assert (tmp_path / "good.csv").read_text() == "old" and _temporaries(tmp_path) == []


def test_one_file_under_two_names_is_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["wall", "--polar", "1", "-o", "w.csv", "-o", "./w.csv"]) == 2
    _one_error_line(capsys, "same file")
    assert os.listdir(tmp_path) == []


def test_missing_parent_under_a_file(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file").write_text("")
    assert main(["wall", "--polar", "1", "-o", "a/b.csv", "-o", "file/sub/w.csv"]) == 2
    _one_error_line(capsys, "file/sub/w.csv", "not a folder")
    assert sorted(os.listdir(tmp_path)) == ["file"]  # the folder a/ was not created either


def test_unwritable_existing_file(tmp_path, capsys, monkeypatch):
    """As root every file is writable; os.access is what check_paths asks, so it stands in for the mode."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "locked.csv").write_text("old")
    (tmp_path / "locked.csv").chmod(0o444)
    real_access = os.access
    monkeypatch.setattr(os, "access", lambda p, mode, **kw: False if str(p).endswith("locked.csv")
                        else real_access(p, mode, **kw))
    assert main(["wall", "--polar", "1", "-o", "new.csv", "-o", "locked.csv"]) == 2
    _one_error_line(capsys, "'locked.csv'", "not writable")
    assert sorted(os.listdir(tmp_path)) == ["locked.csv"] and (tmp_path / "locked.csv").read_text() == "old"


def _read(path):
    with open(path) as fh:
        return fh.read()


def _fail_once(monkeypatch, target):
    """os.replace fails (EIO) the first time a temporary is renamed onto ``target``."""
    real_replace = os.replace
    state = {"failed": False}

    def replace(src, dst, *args, **kwargs):
        if os.path.abspath(dst) == os.path.abspath(target) and not state["failed"] and ".coinwall-" in str(src):
            state["failed"] = True
            raise OSError(5, "Input/output error")
        return real_replace(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", replace)
    return state


def test_failed_rename_restores_the_files_already_replaced(tmp_path, monkeypatch):
    a, b, c = (str(tmp_path / name) for name in ("a.csv", "b.csv", "c.csv"))
    for path in (a, b):
        with open(path, "w") as fh:
            fh.write("old " + path)
    state = _fail_once(monkeypatch, b)
    with pytest.raises(OutputError, match=r"cannot write output '.*b\.csv': Input/output error; nothing was changed"):
        output.write_all({c: b"new c", a: b"new a", b: b"new b"})
    assert state["failed"]
    assert _read(a) == "old " + a and _read(b) == "old " + b
    assert not os.path.exists(c)  # written before the failure, removed: it did not exist
    assert _temporaries(tmp_path) == []  # neither temporaries nor backups are left


def test_failed_rename_restores_without_hard_links(tmp_path, monkeypatch):
    """Where the filesystem has no hard links (FAT, some network shares) the old file is kept as a copy: a failed
    rename still puts back its content and its mode."""
    a, b = str(tmp_path / "a.csv"), str(tmp_path / "b.csv")
    for path in (a, b):
        with open(path, "w") as fh:
            fh.write("old " + path)
        os.chmod(path, 0o640)

    def no_links(*args, **kwargs):
        raise OSError(1, "Operation not permitted")

    monkeypatch.setattr(os, "link", no_links)
    _fail_once(monkeypatch, b)
    with pytest.raises(OutputError, match="nothing was changed"):
        output.write_all({a: b"new a", b: b"new b"})
    assert _read(a) == "old " + a and _read(b) == "old " + b
    assert os.stat(a).st_mode & 0o777 == 0o640 and _temporaries(tmp_path) == []


def test_failed_rename_through_the_command_line(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "w.csv").write_text("old")
    _fail_once(monkeypatch, "w.svg")
    assert main(["wall", "--polar", "1", "-o", "w.csv", "-o", "w.svg"]) == 2
    _one_error_line(capsys, "'w.svg'")
    assert sorted(os.listdir(tmp_path)) == ["w.csv"] and (tmp_path / "w.csv").read_text() == "old"


def test_write_all_refuses_a_folder_and_names_every_path(tmp_path):
    """Even without check_paths (a folder created after it ran), nothing is replaced."""
    (tmp_path / "a.csv").write_text("old")
    (tmp_path / "d.json").mkdir()
    with pytest.raises(OutputError, match=r"'.*d\.json' is a folder"):
        output.write_all({str(tmp_path / "a.csv"): b"new", str(tmp_path / "d.json"): b"{}"})
    assert (tmp_path / "a.csv").read_text() == "old" and _temporaries(tmp_path) == []
    with pytest.raises(OutputError, match=r"'.*a\.csv' is not a folder"):  # a missing folder under a file
        output.write_all({str(tmp_path / "a.csv" / "x.csv"): b"1"})
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "d.json"]


def test_transaction_commits_once(tmp_path):
    a, b = str(tmp_path / "a.csv"), str(tmp_path / "b.csv")
    with pytest.raises(RuntimeError), output.transaction():
        output.write_all({a: b"1"})
        raise RuntimeError("the second stage failed")
    assert os.listdir(tmp_path) == []
    with output.transaction() as batch:
        written = output.write_all({a: b"1"})
        output.write_all({b: b"2"})
        assert os.listdir(tmp_path) == [] and set(batch) == {a, b}
    assert written == [a] and _read(a) == "1" and _read(b) == "2"


def test_fit_writes_wall_and_body_together(tmp_path, capsys, monkeypatch):
    """coinwall fit writes the fitted wall, then the body: a failing body format leaves no wall file."""
    from coinwall.inverse.export import svg

    theta = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    np.savetxt(tmp_path / "scan.csv", np.column_stack([theta, 1 + 0.1 * np.cos(2 * theta)]), delimiter=",",
               header="theta,b", comments="")

    def broken(body, stream, options=None):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(svg, "write", broken)
    monkeypatch.chdir(tmp_path)
    assert main(["fit", "scan.csv", "-o", "fitted-wall.csv", "-o", "body.svg"]) == 2
    _one_error_line(capsys, "No space left")
    assert sorted(os.listdir(tmp_path)) == ["scan.csv"]


# --------------------------------------------------------------------------- 4. temporaries and signals

# a command whose output is written slowly: it announces the write of the temporary, then takes long enough to
# receive a signal (run through main(), which turns SIGTERM and SIGHUP into a normal exit, as the shell's
# `coinwall` does)
_SLOW_WRITER = textwrap.dedent("""
    import os, sys, time
    from coinwall.cases.cli.main import main

    real_fdopen = os.fdopen

    class Slow:
        def __init__(self, fh):
            self.fh = fh
        def __enter__(self):
            return self
        def __exit__(self, *exc):
            self.fh.close()
        def fileno(self):
            return self.fh.fileno()
        def write(self, data):
            self.fh.write(data[:10])
            print("writing", flush=True)
            time.sleep(60)

    os.fdopen = lambda *a, **k: Slow(real_fdopen(*a, **k))
    sys.exit(main(["wall", "--polar", "1", "-o", sys.argv[1], "-o", sys.argv[2]]))
""")


@pytest.mark.parametrize("name", ["SIGTERM", "SIGINT", "SIGHUP"])
def test_a_signal_during_a_write_leaves_nothing(tmp_path, name):
    """Killed while the temporary is written: one line, the shell's status for the signal, and the folder as it
    was: the existing output untouched, no temporary, no folder made for the other output."""
    number = getattr(signal, name)
    (tmp_path / "old.csv").write_text("old")
    before = sorted(os.listdir(tmp_path))
    proc = subprocess.Popen([sys.executable, "-c", _SLOW_WRITER, str(tmp_path / "old.csv"),
                             str(tmp_path / "new" / "w.json")], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        assert proc.stdout.readline().strip() == "writing"
        assert len(_temporaries(tmp_path)) == 1  # the temporary exists while the write runs
        proc.send_signal(number)
        _, err = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == 128 + number
    assert err == ("coinwall: interrupted\n" if name == "SIGINT" else f"coinwall: stopped by {name}\n")
    assert sorted(os.listdir(tmp_path)) == before and (tmp_path / "old.csv").read_text() == "old"


def test_verify_killed_leaves_no_folder(tmp_path):
    """`coinwall verify --out report` killed while it computes: the folder is made only with its content."""
    script = textwrap.dedent("""
        import sys, time
        from coinwall.cases.cli.main import main
        from coinwall.cases.paper import verify

        def evaluate(claims, resolution, progress=False):
            print("working", flush=True)
            time.sleep(60)

        verify.evaluate = evaluate
        sys.exit(main(["verify", "--fast", "--json", "--out", "report"]))
    """)
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, cwd=tmp_path)
    try:
        assert proc.stdout.readline().strip() == "working"
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == 143 and err == "coinwall: stopped by SIGTERM\n"
    assert os.listdir(tmp_path) == []


def test_write_all_restores_the_signal_handlers(tmp_path):
    before = {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}
    output.write_all({str(tmp_path / "a.csv"): b"1", str(tmp_path / "b.csv"): b"2"})
    assert {number: signal.getsignal(number) for number in before} == before


def test_ctrl_c_during_the_commit_waits_for_it(tmp_path, monkeypatch):
    """Ctrl-C while the temporaries are renamed over the outputs: the renames end first (every file new, no
    second name of an old file left beside it), then the KeyboardInterrupt."""
    a, b = str(tmp_path / "a.csv"), str(tmp_path / "b.csv")
    for path in (a, b):
        with open(path, "w") as fh:
            fh.write("old")
    real_replace = os.replace
    seen = []

    def replace(src, dst, *args, **kwargs):
        if not seen:
            os.kill(os.getpid(), signal.SIGINT)  # Python's handler would run at the next bytecode: in the commit
            time.sleep(0.01)
        seen.append(dst)
        return real_replace(src, dst, *args, **kwargs)

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        monkeypatch.setattr(os, "replace", replace)
        with pytest.raises(KeyboardInterrupt):
            output.write_all({a: b"1", b: b"2"})
    finally:
        signal.signal(signal.SIGINT, previous)
    assert seen == [a, b] and _read(a) == "1" and _read(b) == "2"
    assert _temporaries(tmp_path) == []


def test_a_program_handler_runs_and_the_write_completes(tmp_path, monkeypatch):
    """A program that handles SIGTERM itself and goes on: its handler runs, the write completes whole."""
    calls = []
    real_fdopen = os.fdopen

    def fdopen(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.01)
        return real_fdopen(*args, **kwargs)

    handler = lambda number, frame: calls.append(number)  # noqa: E731
    previous = signal.signal(signal.SIGTERM, handler)
    try:
        monkeypatch.setattr(os, "fdopen", fdopen)
        assert output.write_all({str(tmp_path / "a.csv"): b"1"}) == [str(tmp_path / "a.csv")]
        assert calls == [signal.SIGTERM] and os.listdir(tmp_path) == ["a.csv"]
        assert signal.getsignal(signal.SIGTERM) is handler
    finally:
        signal.signal(signal.SIGTERM, previous)


# --------------------------------------------------------------------------- 5. the last line of defence

def _raise_in_critical(monkeypatch, exc):
    from coinwall.cases.cli import critical

    def run(args):
        raise exc

    monkeypatch.setattr(critical, "run", run)


@pytest.mark.parametrize("exc,status,needle", [
    (MemoryError("Unable to allocate 7.45 GiB for an array with shape (1000000000,)"), 2, "not enough memory"),
    (RecursionError("maximum recursion depth exceeded"), 2, "nested too deeply"),
    (OSError(13, "Permission denied", "walls.csv"), 2, "'walls.csv': Permission denied"),
])
def test_resource_errors_are_one_line(exc, status, needle, monkeypatch, capsys):
    _raise_in_critical(monkeypatch, exc)
    assert main(["critical", "1"]) == status
    _one_error_line(capsys, needle)


def test_ctrl_c_is_130_without_traceback(monkeypatch, capsys):
    _raise_in_critical(monkeypatch, KeyboardInterrupt())
    assert main(["critical", "1"]) == EX_INTERRUPTED == 130
    assert capsys.readouterr().err == "coinwall: interrupted\n"


def test_a_bug_is_one_line_asking_for_a_report(monkeypatch, capsys):
    _raise_in_critical(monkeypatch, ZeroDivisionError("float division by zero"))
    assert main(["critical", "1"]) == EX_SOFTWARE == 70
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "ZeroDivisionError: float division by zero" in err
    assert "bug in coinwall" in err and "COINWALL_DEBUG=1" in err and "Traceback" not in err
    monkeypatch.setenv("COINWALL_DEBUG", "1")
    with pytest.raises(ZeroDivisionError):
        main(["critical", "1"])


def test_stray_numpy_warnings_become_one_note(monkeypatch, capsys):
    from coinwall.cases.cli import critical

    real_run = critical.run

    def run(args):
        with np.errstate(all="warn"):
            np.float64(1.0) / np.zeros(3)  # RuntimeWarning: divide by zero, three times
            np.log(np.float64(-1.0))  # RuntimeWarning: invalid value
        return real_run(args)

    monkeypatch.setattr(critical, "run", run)
    assert main(["critical", "1"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("coinwall: note:") and "divide by zero" in err[0]
    # with an error, the note is the second and last line
    monkeypatch.setattr(critical, "run", lambda args: (np.log(np.zeros(1)), real_run(args)))
    assert main(["critical", "1", "--param", "a=1"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and err[0].startswith("coinwall: error:") and err[1].startswith("coinwall: note:")


def test_no_traceback_through_the_installed_command(tmp_path):
    """The console script, in a fresh process: a bad option and a bad number, each one line, status 2."""
    for args in (["solve", "1", "--b0", "-1e400x"], ["critical", "1", "--param", "a=1", "--param", "a=2"]):
        done = subprocess.run([sys.executable, "-m", "coinwall", *args], capture_output=True, text=True, timeout=120,
                              cwd=tmp_path, check=False)
        assert done.returncode == 2 and done.stderr.count("\n") == 1 and "Traceback" not in done.stderr
    assert os.listdir(tmp_path) == []


# --------------------------------------------------------------------------- 6. numeric ranges

@pytest.mark.parametrize("args,needles", [
    (["wall", "--polar", "1", "--samples", "1000000000"], ["--samples", "10000000"]),
    (["wall", "--polar", "1", "--H", "1e300"], ["--H", "1e+15"]),
    (["wall", "--polar", "1", "--H", "-1"], ["--H", "positive"]),
    (["solve", "1", "--points", "1000000000"], ["--points"]),
    # the range of b0 is the library's to check (solve_body, fit_convex); 1e308 was an OverflowError traceback
    (["solve", "1", "--b0", "1e308"], ["--b0", "between"]),
    (["fit", "SCAN", "--b0", "1e308"], ["--b0"]),
    # the reader refuses 1e-300 (bodies from 1e-100 to 1e100 across); `wall` itself 1e-6 to 1e6 radii of gyration
    (["wall", "BODY", "--kappa", "1e-300", "-o", "w.csv"], ["--kappa", "radii of gyration"]),
    (["wall", "BODY", "--kappa", "1e-9", "-o", "w.csv"], ["--kappa 1e-09", "between 1e-06 and 1e+06"]),
    (["solve", "1", "--tolerance", "-1", "-o", "x.dxf"], ["--tolerance"]),
    (["export", "BODY", "--kappa", "0", "--units", "mm", "-o", "x.svg"], ["--kappa"]),
])
def test_numeric_arguments_out_of_range(args, needles, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    theta = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    if "SCAN" in args:
        np.savetxt("scan.csv", np.column_stack([theta, 1 + 0.1 * np.cos(2 * theta)]), delimiter=",",
                   header="theta,b", comments="")
        args = [a.replace("SCAN", "scan.csv") for a in args]
    if "BODY" in args:
        assert main(["solve", "1", "-o", "body.json", "--no-cross-check"]) == 0
        capsys.readouterr()
        args = [a.replace("BODY", "body.json") for a in args]
    before = sorted(os.listdir(tmp_path))
    assert main(args) == 2
    _one_error_line(capsys, *needles)
    assert sorted(os.listdir(tmp_path)) == before


def test_samples_beyond_memory_refused_with_the_estimate(monkeypatch, capsys):
    from coinwall.forward import validation

    monkeypatch.setattr(validation, "available_memory", lambda: 10_000_000)  # 10 MB: 5 MB for one request
    assert main(["wall", "--polar", "1", "--samples", "100000"]) == 2
    _one_error_line(capsys, "--samples = 100000", "memory")


# --------------------------------------------------------------------------- 7. no non-finite number in a file

def test_refuse_non_finite():
    output.refuse_non_finite("x", a=[1.0, 2.0], b=np.zeros((2, 2)))
    with pytest.raises(OutputError, match=r"refusing to write the body: nodes has 2 non-finite value\(s\) "
                                          r"\(first at index 1, 0\)"):
        output.refuse_non_finite("the body", nodes=np.array([[0.0, 1.0], [np.nan, np.inf]]))


def test_wall_with_nan_values_writes_nothing(tmp_path, capsys, monkeypatch):
    from coinwall.forward import support

    def nan_walls(outline, theta, H=None):
        lower = np.ones_like(theta)
        lower[5] = np.nan
        return lower, None

    monkeypatch.setattr(support, "wall_functions", nan_walls)
    monkeypatch.chdir(tmp_path)
    assert main(["wall", "--polar", "1", "-o", "w.csv", "-o", "w.json"]) == 2
    _one_error_line(capsys, "non-finite", "index 5")
    assert os.listdir(tmp_path) == []


def test_solved_body_with_nan_writes_nothing(tmp_path, capsys, monkeypatch):
    from coinwall import inverse

    real_solve = inverse.solve_body

    class NanBody:  # what a solver gone wrong could return: one node is NaN
        def __init__(self, body):
            self._body = body
            self.outline = type("O", (), {"nodes": body.outline.nodes.copy(), "controls": body.outline.controls})()
            self.outline.nodes[3, 0] = np.nan
            self.x, self.y, self.b0, self.b_c = body.x, body.y, body.b0, body.b_c

    monkeypatch.setattr(inverse, "solve_body", lambda *a, **k: NanBody(real_solve(*a, **k)))
    monkeypatch.chdir(tmp_path)
    assert main(["solve", "1", "-o", "b.json", "-o", "b.dxf", "-o", "b.csv", "--no-cross-check"]) == 2
    _one_error_line(capsys, "non-finite")
    assert os.listdir(tmp_path) == []


def test_wall_nan_on_a_tiny_interval_writes_nothing(tmp_path, capsys, monkeypatch):
    """Issue 16's wall: NaN on a 9e-5 rad interval; refused (by the wall's own check), no file."""
    monkeypatch.chdir(tmp_path)
    assert main(["solve", "1+0.1*sqrt(1-1e-9-cos(t-1.2358771881065316))", "--points", "2000",
                 "-o", "x.json", "-o", "x.csv", "--no-cross-check"]) == 2
    _one_error_line(capsys, "finite")
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("path", ["/dev/zero", "/dev/urandom"])
def test_a_device_as_the_wall_is_named_as_a_file(path, capsys):
    """Issue 12: `critical /dev/zero` read 1.9 GB and ended in a traceback; a path with no wall-file extension
    was then read as an expression ("syntax error at column 1").  It is named as what it is."""
    assert main(["critical", path]) == 2
    _one_error_line(capsys, path, "is a file, but not a wall file")
