"""Shared parts of the command-line fuzz tests: a worker process that runs ``coinwall`` commands, and the
hostile inputs they are given.

Used by ``tests/cases/cli/test_fuzz_cli.py`` (the default run, bounded) and ``tests/benchmarks/fuzz_cli.py`` (a
larger run outside it, whose counts are recorded in docs/cli-limits.md ("Fuzz tests")).

Why a worker process: a command that crashes the interpreter (a segmentation fault in compiled code) or
hangs must fail one example, not the test session, and starting Python plus numpy for every one of
hundreds of examples would cost a second each.  The worker imports coinwall once, runs each request in a
fresh folder with file descriptors 1 and 2 captured (so text written by compiled code is seen too), and
answers on a separate descriptor; the client kills and restarts it when a request outlives its timeout.

The contract every request is checked against (:func:`check_clean`):

* exit status 0, 1 (a warning) or 2 (refused); for input that is certainly bad, exactly 2;
* no ``Traceback`` and no raw warning text (``Warning:``) on stderr;
* when refused: at most two stderr lines, and no file created or changed in the working folder.
"""

from __future__ import annotations

import json
import math
import os
import re
import select
import subprocess
import sys
import tempfile
import time

__all__ = ["kind_files", "Worker", "check_clean", "snapshot", "BAD_NUMBERS", "BAD_REQUESTS", "BAD_WALLS", "ODD_WALLS",
           "BASE_COMMANDS",
           "NUMERIC_FLAGS", "WALL_COMMANDS", "FILE_COMMANDS", "VALID_FILES", "valid_files", "hostile_files",
           "make_folder", "mutate", "with_flag", "MUTATION_TARGETS", "MUTATIONS", "mutation_request"]

# ------------------------------------------------------------------------------------------- the worker
_WORKER = r"""
import json, os, sys, tempfile, warnings
resp = os.fdopen(os.dup(1), "w")      # answers go here; fds 1 and 2 are captured per request
captures = tempfile.mkdtemp(prefix="coinwall-fuzz-")  # not in the request's folder, which is watched
from coinwall.cases.cli.main import main
# show every warning every time (the default shows one per place per process, which would hide a
# warning from the second request that triggers it)
warnings.simplefilter("always")
for line in sys.stdin:
    req = json.loads(line)
    # the arguments as the operating system hands them over: bytes (UTF-8 here), decoded by the file system's
    # encoding (under LANG=C without UTF-8 mode, undecodable bytes become surrogates, as in sys.argv)
    argv = [os.fsdecode(a.encode("utf-8", "surrogateescape")) for a in req["argv"]]
    os.chdir(req["cwd"])
    out = os.open(os.path.join(captures, "stdout"), os.O_RDWR | os.O_CREAT | os.O_TRUNC, 0o600)
    err = os.open(os.path.join(captures, "stderr"), os.O_RDWR | os.O_CREAT | os.O_TRUNC, 0o600)
    saved = os.dup(1), os.dup(2)
    sys.stdout.flush(); sys.stderr.flush()
    os.dup2(out, 1); os.dup2(err, 2)
    try:
        try:
            rc = main(argv)
        except SystemExit as exc:
            rc = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except BaseException:
            import traceback
            traceback.print_exc()
            rc = -1
    finally:
        sys.stdout.flush(); sys.stderr.flush()
        os.dup2(saved[0], 1); os.dup2(saved[1], 2)
        os.close(saved[0]); os.close(saved[1])
    texts = []
    for fd in (out, err):
        os.lseek(fd, 0, 0)
        texts.append(os.read(fd, 1 << 20).decode("utf-8", "replace"))
        os.close(fd)
    resp.write(json.dumps({"rc": rc, "stdout": texts[0], "stderr": texts[1]}) + "\n")
    resp.flush()
"""


class Worker:
    """A ``coinwall`` process that runs :func:`coinwall.cases.cli.main.main` for each request.

    ``memory`` bytes of address space at most (``ulimit -v``), so a request that would take the machine's
    memory fails inside the worker instead; ``timeout`` seconds per request; ``env``: variables set for the worker
    (``{"PYTHONIOENCODING": "ascii"}``: a terminal that cannot show every character).
    """

    def __init__(self, timeout: float = 60.0, memory: int = 8 * 2 ** 30, env: dict | None = None):
        self.timeout = timeout
        self.memory = memory
        self.env = env
        self.proc = None

    def _start(self):
        import resource

        def limit():
            resource.setrlimit(resource.RLIMIT_AS, (self.memory, self.memory))

        env = None if self.env is None else {**os.environ, **self.env}
        self.proc = subprocess.Popen([sys.executable, "-c", _WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.DEVNULL, text=True, preexec_fn=limit, env=env,
                                     encoding="utf-8", errors="surrogateescape")

    def run(self, argv, cwd, timeout: float | None = None) -> dict:
        """Run ``coinwall ARGV`` in folder ``cwd``; returns ``{"rc", "stdout", "stderr"}``.

        ``rc`` is ``"timeout"`` when the request outlived the timeout (``timeout``, default the worker's) and
        ``"crash: N"`` when the worker died (a signal, an abort); the worker is restarted for the next request in
        both cases.
        """
        if self.proc is None or self.proc.poll() is not None:
            self._start()
        self.proc.stdin.write(json.dumps({"argv": list(argv), "cwd": str(cwd)}) + "\n")
        self.proc.stdin.flush()
        ready, _, _ = select.select([self.proc.stdout], [], [], self.timeout if timeout is None else timeout)
        if not ready:
            self.close()
            return {"rc": "timeout", "stdout": "", "stderr": ""}
        line = self.proc.stdout.readline()
        if not line:
            code = self.proc.wait()
            self.proc = None
            return {"rc": f"crash: {code}", "stdout": "", "stderr": ""}
        return json.loads(line)

    def close(self):
        if self.proc is not None:
            self.proc.kill()
            self.proc.wait()
            self.proc = None


def snapshot(folder) -> dict:
    """``{name: (size, mtime_ns)}`` of everything in ``folder``, hidden files included, recursively."""
    result = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = os.path.join(root, name)
            st = os.lstat(path)
            result[os.path.relpath(path, folder)] = (st.st_size, st.st_mtime_ns)
    return result


_NAN = re.compile(r"(?<![A-Za-z_])nan(?![A-Za-z_])", re.IGNORECASE)
_NO_DATA = re.compile(r"0\.0+ ± 0\.0+ +\(0 ")


def _outputs(argv):
    """The paths a command writes: its -o/--output/--figure/--out values (scan's store among them)."""
    flags = ("-o", "--output", "--figure", "--out")
    names = []
    for k, arg in enumerate(argv):
        if arg in flags and k + 1 < len(argv):
            names.append(argv[k + 1])
        elif arg.startswith(tuple(f + "=" for f in flags[1:])):
            names.append(arg.split("=", 1)[1])
        elif arg.startswith("-o") and len(arg) > 2:
            names.append(arg[2:])
    return [os.path.normpath(name) for name in names if name]


def check_clean(argv, result, before, after, *, certainly_bad: bool) -> list:
    """The ways ``result`` of ``coinwall ARGV`` breaks the contract (module docstring); empty if none."""
    problems = []
    rc, err = result["rc"], result["stderr"]
    lines = [line for line in err.splitlines() if line.strip()]
    if rc not in (0, 1, 2):
        problems.append(f"exit status {rc!r}")
    elif certainly_bad and rc != 2:
        problems.append(f"exit status {rc} for input that must be refused")
    if "Traceback" in err:
        problems.append("traceback on stderr")
    if "Warning:" in err or "warnings.warn" in err:
        problems.append("raw warning text on stderr")
    if rc in (0, 1) and _NAN.search(result["stdout"]):
        problems.append("a NaN printed as an answer")
    if rc in (0, 1) and _NO_DATA.search(result["stdout"]):
        problems.append("a share from no data printed as an answer (0 ± 0 from 0 samples)")
    if "internal error" in err:
        problems.append("internal error")
    if rc in (0, 1, 2):  # an input (a file there before that the command does not write) is never changed
        outputs = set(_outputs(argv))
        changed = sorted(k for k in before if k not in outputs and not any(k.startswith(o + os.sep) for o in outputs)
                         and after.get(k) != before[k])
        if changed:
            problems.append(f"inputs lost or changed: {changed[:5]}")
    if rc == 2:
        if len(lines) > 2:
            problems.append(f"{len(lines)} stderr lines")
        if not lines or not lines[-1].startswith("coinwall"):
            problems.append("no 'coinwall...' line saying what was wrong")
        if before != after:
            changed = sorted(set(before) ^ set(after) | {k for k in before if k in after and before[k] != after[k]})
            problems.append(f"files created or changed: {changed}")
    return [f"coinwall {' '.join(map(repr, argv))}: {p}\n  stderr: {err[-600:]!r}" for p in problems]


# ------------------------------------------------------------------------------------------- the inputs
# values that no flag of the given kind may accept (each is refused by argparse or by our checks)
_NOT_A_NUMBER = ["", "abc", "nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e400", "-1e400", "0x10", "1_0", "1,5",
                 "--", "1e", "١",
                 # numbers are ASCII: no-break and other Unicode spaces (float() would strip them) are refused
                 "\u00a0-0.3", "\u20070.5", "1\u3000", "\u202f2", "2\u2009"]
BAD_NUMBERS = {
    "count": _NOT_A_NUMBER + ["0", "-1", "1.5", "1e30", "-1e30", "99999999999999999999999", "1e19"],
    "positive": _NOT_A_NUMBER + ["0", "-0", "-1", "-1e-300", "1e308", "-1e308"],
    "restitution": _NOT_A_NUMBER + ["-0.1", "-1e-300", "1.5", "1e308", "-1e308"],
    "nonnegative": _NOT_A_NUMBER + ["-0.1", "-1e-300", "1e308", "-1e308"],
    "offset": _NOT_A_NUMBER + ["1e308", "-1e308", "1e200"],
    "seed": ["", "abc", "nan", "1.5", "-1", "0x10"],
}

# walls that are not walls: unparseable, unsafe, non-finite, with a pole, with lookalike characters
BAD_WALLS = ["", " ", "(", ")", "sin(", "1+", "t**", "1/0", "nan", "inf", "-inf", "1e400", "log(-1)",
             "sqrt(-1-cos(t))", "2+tan(t)", "1/cos(t)", "x+cos(t)", "__import__('os').system('true')",
             "().__class__", "lambda: 1", "t if t else 1", "[1, 2]", "1; 2", "ｓｉｎ(t)+2", "2+𝐭", "0x10+cos(t)",
             "1_0+cos(t)", "2+cos(t" + ")" * 3, "1+0.1*sqrt(1-1e-9-cos(t-1.2358771881065316))",
             "1e308*cos(t)+1e308", "(" * 100000 + "1" + ")" * 100000,
             # one grammar: an expression is one line -- no comment, continuation or empty argument
             "1+0.1*cos(t) # +0.2*cos(3*t)", "1+\\\n0.1*cos(t)", "(1+0.1\n*cos(t))", "1+0.1*cos(t,)", "max(t,1,)+1",
             # walls that jump: no b_c exists
             "1+0.1*cos(t)/abs(cos(t))", "2+sign(sin(t))",
             # walls floating point cannot follow: an argument whose size swamps t, a no-break space
             "2+0.1*cos(2*t+1e20)", "1+1e-30*cos(1e15*t)", "2+0.1*sin(3*t+1e17)", "\u00a01+0.1*cos(t)"]
# walls that may be valid or not, but must never crash anything: long, deep, steep, tiny, huge
ODD_WALLS = ["(" * 200 + "1" + ")" * 200, "2+" + "+".join(["cos(t)"] * 2000), "1+0.999999*cos(2*t)/3",
             "1" + "+0.001*cos(2*t)" * 130, "1" + "+1" * 994 + "+0.1*cos(2*t)",
             "1e-300+0*t", "1e300+cos(t)", "-cos(t)+2", "abs(cos(t))+1", "1+0.1*sign(cos(t))", "exp(50*cos(t))",
             "1+1e-12*cos(1000*t)", "1+0.1*cos(2*t)+1e-9*cos(10000*t)"]

# whole requests that must be refused (exit 2, one line, nothing written): densities with no finite mass or
# that the quadrature cannot integrate, a body whose energies leave floating point, quantum solves past the
# time bound (sizes the tool itself suggested once), a no-break space in a number
BAD_REQUESTS = [["mass", "body.json", "--density", "r**-3"], ["mass", "body.json", "--density", "r**-2"],
                ["mass", "body.json", "--density", "1/abs(x)"], ["mass", "body.json", "--density", "1/x**2"],
                ["mass", "body.json", "--density", "1/((x-0.2)**2+(y-0.1)**2)"],
                ["mass", "body.json", "--density", "r**-1.5"], ["mass", "body.json", "--density", "exp(1/r)"],
                ["quantum", "1", "--H", "3", "--levels", "2", "--body", "1e308,1e308"],
                ["quantum", "1", "--H", "3", "--levels", "2", "--body", "1,1e-300"],
                ["quantum", "1", "--H", "3", "--levels", "2", "--body", "1e-300,1e300"],
                ["quantum", "1", "--H", "2.00403", "--levels", "2", "-o", "out.json"],
                ["quantum", "1", "--H", "1e6", "--levels", "4"],
                ["solve", "1+0.1*cos(2*t)", "--b0", "\u00a0-0.3", "-o", "out.csv"],
                ["critical", "1+eps*cos(2*t)", "--param", "eps=\u00a00.1"],
                ["mass", "body.json", "--kappa", "\u00a01"]]

# one valid, quick command per subcommand: the base the fuzzer breaks one piece of.  Names of files refer
# to :func:`hostile_files`'s folder, where a valid body.json, samples.csv and points.csv are written.
BASE_COMMANDS = {
    "solve": ["1+0.1*cos(2*t)", "--points", "256", "-o", "out.csv"],
    "critical": ["1+0.1*cos(2*t)"],
    "fit": ["samples.csv", "-o", "out.json"],
    "wall": ["--polar", "1+0.1*cos(3*t)", "--samples", "90", "-o", "out.csv"],
    "export": ["body.json", "-o", "out.svg"],
    "mass": ["body.json"],
    "simulate": ["case:coin", "--H", "3", "--collisions", "50", "--seed", "1"],
    "section": ["case:coin", "--H", "3", "--orbits", "2", "--collisions", "20", "--seed", "1", "-o", "out.csv"],
    "quantum": ["1", "--H", "3", "--levels", "4", "--cells", "4", "-o", "out.json"],
    "scan": ["chaotic-fraction", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=2", "--H", "3", "--orbits", "4",
             "--collisions", "50", "--workers", "1", "-o", "out.zarr"],
    "toss": ["case:coin", "--v0", "0:1:4", "--omega", "0:2:4", "-o", "out.json"],
    "correlation": ["case:coin", "--H", "3", "--bounces", "500", "--orbits", "2", "--max-lag", "3", "--seed", "1",
                    "-o", "out.json"],
    "coin3d": ["caught", "--psi", "70", "--samples", "200", "--seed", "1"],
    "design": ["abs(cos(t)) + h*abs(sin(t))", "--param", "h=0.05:3", "--target", "edge=1/3", "-o", "out.svg"],
}
# the numeric flags of each base command and the kind of their values (a key of BAD_NUMBERS)
NUMERIC_FLAGS = {
    "solve": {"--points": "count", "--b0": "offset", "--kappa": "positive", "--tolerance": "positive"},
    "critical": {},
    "fit": {"--b0": "offset"},
    "wall": {"--samples": "count", "--kappa": "positive", "--H": "positive"},
    "export": {"--kappa": "positive", "--tolerance": "positive"},
    "mass": {"--density": "positive", "--kappa": "positive"},
    "simulate": {"--H": "positive", "--b0": "offset", "--kappa": "positive", "--collisions": "count",
                 "--seed": "seed"},
    "section": {"--H": "positive", "--b0": "offset", "--kappa": "positive", "--collisions": "count",
                "--orbits": "count", "--seed": "seed"},
    "quantum": {"--H": "positive", "--b0": "offset", "--levels": "count", "--cells": "count"},
    # (scan's --H is a grid whose out-of-range cells are findings, exit 1: not certainly bad)
    "scan": {"--orbits": "count", "--collisions": "count", "--workers": "count", "--seed": "seed"},
    "toss": {"--g": "positive", "--e": "restitution", "--mu": "nonnegative", "--height": "positive",
             "--kappa": "positive", "--impacts": "count", "--samples": "count", "--seed": "seed"},
    "correlation": {"--H": "positive", "--b0": "offset", "--kappa": "positive", "--bounces": "count",
                    "--orbits": "count", "--max-lag": "count", "--seed": "seed"},
    # (coin3d's --e, --g, --height, --ceiling belong to its bounce mode; checked there)
    "coin3d": {"--samples": "count", "--bounces": "count", "--seed": "seed"},
    "design": {"--b0": "offset", "--kappa": "positive"},
}
# the base commands that write a file with -o (scan writes a store folder, see test_nothing_lost.py)
OUTPUT_COMMANDS = sorted(c for c, argv in BASE_COMMANDS.items() if "-o" in argv and c != "scan")
# output names no filesystem here can hold: refused before any folder is made (the extension is the command's own)
BAD_OUTPUTS = ["d/" * 2100 + "x", "n" * 300, "a/" + "n" * 300 + "/x", "a/b/" + "d/" * 2040 + "x"]
# commands whose output names one of their inputs (the same name, another spelling, a hard link): refused
INPUT_AS_OUTPUT = [["solve", "samples.csv", "-o", "samples.csv"], ["solve", "samples.csv", "-o", "./samples.csv"],
                   ["solve", "samples.csv", "-o", "body.json", "-o", "samples.csv"],
                   ["solve", "samples.csv", "-o", "linked.csv"], ["fit", "samples.csv", "-o", "samples.csv"],
                   ["wall", "body.json", "-o", "body.json"]]
# names of the old temporary patterns a user may have chosen for their own files: planted two days old, they must
# survive every command (only names with coinwall's keyed mark are ever swept)
LOOKALIKES = [".coinwall-settings.json", ".coinwall-my_notes.csv", ".coinwall-abcd_123.svg",
              ".coinwall-0a1b2c3d-1-cafebabe.csv", ".coinwall-tmp.00000000.1.0123456789abcdef.0123456789abcdef.part"]


def with_output(argv, name):
    """``argv`` with its last ``-o`` value replaced by ``name`` plus that value's extension."""
    k = len(argv) - 1 - argv[::-1].index("-o")
    return argv[:k + 1] + [name + os.path.splitext(argv[k + 1])[1]] + argv[k + 2:]


def plant_lookalikes(folder) -> None:
    old = time.time() - 2 * 86400
    for name in LOOKALIKES:
        path = os.path.join(folder, name)
        with open(path, "w") as fh:
            fh.write("the user's own file\n")
        os.utime(path, (old, old))


# the subcommands whose first positional argument is a wall expression
WALL_COMMANDS = ("solve", "critical", "simulate", "section", "correlation", "quantum", "design")
# the subcommands that read a file given as their first positional argument, with the valid file of
# each kind they read (a key of the files :func:`valid_files` writes)
FILE_COMMANDS = {"solve": "samples.csv", "critical": "samples.csv", "fit": "samples.csv", "wall": "body.json",
                 "export": "body.json", "mass": "body.json", "simulate": "samples.csv"}


def valid_files(folder, worker: Worker) -> None:
    """Write the valid inputs the base commands read: samples.csv (a sampled smooth wall), points.csv, and
    body.json, body.svg, body.dxf (the body of ``1+0.1*cos(2*t)``, written by ``coinwall solve``); and the walls
    and outlines of :func:`kind_files`."""
    import math

    with open(os.path.join(folder, "samples.csv"), "w") as fh:
        fh.write("theta,b\n")
        for k in range(90):
            t = 2 * math.pi * k / 90
            fh.write(f"{t!r},{1 + 0.1 * math.cos(2 * t)!r}\n")
    with open(os.path.join(folder, "points.csv"), "w") as fh:
        for k in range(60):
            t = 2 * math.pi * k / 60
            fh.write(f"{math.cos(t)!r},{0.7 * math.sin(t)!r}\n")
    result = worker.run(["solve", "1+0.1*cos(2*t)", "--points", "256", "-o", "body.json", "-o", "body.svg",
                         "-o", "body.dxf"], folder)
    if result["rc"] != 0:
        raise RuntimeError(f"coinwall solve could not write the valid bodies the fuzz tests start from: {result}")
    kind_files(folder)


def hostile_files(folder) -> dict:
    """Write files that are certainly not valid inputs into ``folder``; returns ``{name: why}``.

    Each is refused by every command that reads a file, whatever its kind.
    """
    files = {}

    def put(name, data, why):
        with open(os.path.join(folder, name), "wb") as fh:
            fh.write(data if isinstance(data, bytes) else data.encode())
        files[name] = why

    put("empty.csv", b"", "empty CSV")
    put("empty.json", b"", "empty JSON")
    put("empty.svg", b"", "empty SVG")
    put("empty.dxf", b"", "empty DXF")
    put("binary.csv", bytes(range(256)) * 4, "binary bytes as CSV")
    put("binary.svg", bytes(range(256)) * 4, "binary bytes as SVG")
    put("binary.dxf", bytes(range(256)) * 4, "binary bytes as DXF")
    put("text.csv", "theta,b\nthis,is\nnot,numbers\n", "CSV of words")
    put("onecol.csv", "\n".join(str(k) for k in range(50)), "CSV of one column")
    put("threecol.csv", "\n".join(f"{k},{k},{k}" for k in range(50)), "CSV of three columns")
    put("nan.csv", "\n".join(f"{k * 0.1},nan" for k in range(50)), "CSV of NaN")
    put("nested.json", "[" * 100000 + "]" * 100000, "JSON nested 10^5 deep")
    put("strings.json", json.dumps({"theta": ["a", "b", "c"], "b": ["1", "2", "3"]}), "JSON of strings")
    put("bomb.svg", '<?xml version="1.0"?>\n<!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa">'
        + "".join(f'<!ENTITY a{k} "{"&a;" * 10 if k == 0 else f"&a{k - 1};" * 10}">' for k in range(8))
        + ']>\n<svg xmlns="http://www.w3.org/2000/svg"><desc>&a7;</desc></svg>', "SVG entity expansion")
    put("external.svg", '<?xml version="1.0"?>\n<!DOCTYPE svg [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
        '<svg xmlns="http://www.w3.org/2000/svg"><desc>&x;</desc></svg>', "SVG external entity")
    put("encoding.svg", '<?xml version="1.0" encoding="x-no-such"?>\n<svg xmlns="http://www.w3.org/2000/svg"/>',
        "SVG with an unknown encoding")
    put("deep.svg", '<svg xmlns="http://www.w3.org/2000/svg">' + "<g>" * 10000 + "</g>" * 10000 + "</svg>",
        "SVG nested 10^4 deep")
    put("huge.svg", '<svg xmlns="http://www.w3.org/2000/svg"><circle cx="0" cy="0" r="1e308"/></svg>',
        "SVG circle of radius 1e308")
    put("nancoord.svg", '<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 L NaN 1 L 1 1 Z"/></svg>',
        "SVG path with NaN")
    put("scale0.svg", '<svg xmlns="http://www.w3.org/2000/svg"><g transform="scale(0)">'
        '<rect x="0" y="0" width="1" height="1"/></g></svg>', "SVG scale(0)")
    put("nomove.svg", '<svg xmlns="http://www.w3.org/2000/svg"><path d="L 1 0 L 1 1 Z"/></svg>',
        "SVG path without moveto")
    put("truncated.dxf", "0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n8\n0\n10\n", "truncated DXF")
    put("nothing.svg", '<svg xmlns="http://www.w3.org/2000/svg"/>', "SVG with no shape")
    put("badkappa.json", json.dumps({"outline": [[1, 0], [0, 1], [-1, 0], [0, -1]], "kappa": -3}),
        "body JSON with kappa -3")
    # one grammar and one degrees check for every sample format
    degrees = list(range(0, 360, 2))
    put("degrees.json", json.dumps({"theta": degrees, "b": [1 + 0.1 * math.cos(math.radians(d)) for d in degrees]}),
        "JSON samples in degrees, not marked as such")
    put("underscore.csv", "theta,b\n" + "".join(f"{k / 10},1_0\n" for k in range(60)), "CSV with 1_0")
    put("fullwidth.csv", "theta,b\n" + "".join(f"{k / 10},\uff11\n" for k in range(60)), "CSV with fullwidth digits")
    put("nbsp.csv", "theta,b\n" + "".join(f"\u00a0{k / 10},1\n" for k in range(60)), "CSV with no-break spaces")
    # SVG's grammar: a transform list is applied whole or not at all; numbers are ASCII
    for name, transform in (("evil", "scale(2) evil(1)"), ("rotate2", "rotate(30, 5)"), ("matrix5", "matrix(1 0 0 1 0)"),
                            ("twocommas", "scale(2),,translate(1)"), ("nbsp", "scale(\u00a02)")):
        put(f"transform-{name}.svg", f'<svg xmlns="http://www.w3.org/2000/svg"><g transform="{transform}">'
            '<circle cx="0" cy="0" r="1"/></g></svg>', f"SVG transform {transform!r}")
    put("arabic-digit.svg", '<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 L \u0661 0 L 1 1 Z"/></svg>',
        "SVG path with an Arabic-Indic digit")
    # DXF's ranges: a circle or arc has a positive radius, an ellipse an axis ratio in (0, 1]
    dxf = "0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n8\n0\n10\n0.0\n20\n0.0\n30\n0.0\n40\n{}\n0\nENDSEC\n0\nEOF\n"
    put("negative-radius.dxf", dxf.format("-2.0"), "DXF circle of radius -2")
    put("zero-radius.dxf", dxf.format("0.0"), "DXF circle of radius 0")
    os.mkdir(os.path.join(folder, "folder.csv"))
    files["folder.csv"] = "a folder"
    files["missing.csv"] = "a file that does not exist"
    fifo = os.path.join(folder, "fifo.csv")
    os.mkfifo(fifo)
    files["fifo.csv"] = "a FIFO"
    return files


def with_flag(argv, flag, value, joined):
    """``argv`` with ``flag`` set to ``value`` (replacing a value already given), as ``--flag value`` or
    ``--flag=value``."""
    argv = list(argv)
    if flag in argv:
        i = argv.index(flag)
        del argv[i:i + 2]
    return argv + ([f"{flag}={value}"] if joined else [flag, value])


#: what a broken file is given to: a file-reading subcommand, or ``wall`` given a drawing or a points file
MUTATION_TARGETS = sorted(FILE_COMMANDS) + ["wall-svg", "wall-dxf", "wall-points"]
#: the ways :func:`mutate` breaks a file
MUTATIONS = ("truncate", "flip", "insert", "repeat", "replace")


def mutation_request(target: str, name: str):
    """``(argv, the valid file to break)`` for a :data:`MUTATION_TARGETS` entry whose broken file is ``name``
    (it keeps the extension of the valid file: ``"broken" + ext``)."""
    source = {"wall-svg": "body.svg", "wall-dxf": "body.dxf", "wall-points": "points.csv"}.get(
        target, FILE_COMMANDS.get(target))
    subcommand = "wall" if target.startswith("wall") else target
    rest = ["-o", "out.csv"] if subcommand == "wall" else BASE_COMMANDS[subcommand][1:]
    return [subcommand, name + os.path.splitext(source)[1]] + rest, source


def mutate(data: bytes, how: str, where: float, junk: bytes) -> bytes:
    """``data`` broken in one way: ``how`` is "truncate", "flip", "insert", "repeat" or "replace";
    ``where`` in [0, 1] is the place, ``junk`` the bytes inserted or written over."""
    i = int(where * len(data))
    if how == "truncate":
        return data[:i]
    if how == "flip":
        return data[:i] + bytes([data[i] ^ 0xFF]) + data[i + 1:] if i < len(data) else data + b"\xff"
    if how == "insert":
        return data[:i] + junk + data[i:]
    if how == "repeat":
        return data[:i] + data[i:] * 3
    return data[:i] + junk + data[i + len(junk):]


VALID_FILES = ("samples.csv", "points.csv", "body.json", "body.svg", "body.dxf", "degrees.csv", "angles.csv", "wall.json",
               "xy.csv", "body.csv")


def make_folder(base, tmp=None) -> str:
    """A fresh working folder under ``tmp`` with copies of the valid inputs of ``base``."""
    import shutil

    folder = tempfile.mkdtemp(dir=tmp)
    for name in VALID_FILES:
        shutil.copy(os.path.join(base, name), folder)
    return folder


def kind_files(folder) -> None:
    """The files :data:`WRONG_KIND` names: walls in degrees and as JSON, headerless angles, outlines as CSV."""
    with open(os.path.join(folder, "degrees.csv"), "w") as fh:
        fh.write("theta_deg,b\n" + "".join(f"{d},{1 + 0.1 * math.cos(math.radians(2 * d)):.6f}\n"
                                            for d in range(0, 360, 4)))
    with open(os.path.join(folder, "angles.csv"), "w") as fh:
        fh.write("".join(f"{2 * math.pi * k / 72:.6f},{1 + 0.1 * math.cos(4 * math.pi * k / 72):.6f}\n"
                         for k in range(72)))
    with open(os.path.join(folder, "wall.json"), "w") as fh:
        json.dump({"a0": 1.0, "cos": [0.0, 0.1]}, fh)
    with open(os.path.join(folder, "xy.csv"), "w") as fh:
        fh.write("x,y\n" + "".join(f"{math.cos(k / 5):.6f},{0.7 * math.sin(k / 5):.6f}\n" for k in range(31)))
    with open(os.path.join(folder, "body.csv"), "w") as fh:
        fh.write("# coinwall body: wall '1', b0=0.0, regime=convex, units of kappa\nx,y,alpha,R,K\n"
                 + "".join(f"{math.cos(k / 5):.6f},{math.sin(k / 5):.6f},{k / 5},1,1\n" for k in range(31)))
