"""The fuzz's classes of the third round of hardening: terminals that cannot show θ, statistics asked of no data,
files of the wrong kind, long runs, options that mean nothing, damaged scan stores.

Used with :mod:`cli_fuzz` (the worker and the contract) by ``tests/cases/cli/test_fuzz_cli.py`` and
``tests/benchmarks/fuzz_cli.py``.  Each table is a list of examples the default run checks one by one; the
``random_*`` functions draw new cases of the same class for the larger run.
"""

from __future__ import annotations

import json
import math
import os

from cli_fuzz import Worker

__all__ = ["ENCODINGS", "LONG_REQUESTS", "MEANINGLESS", "NO_DATA", "ODD_NAMES", "STORE_ARGS", "STORE_DAMAGES",
           "OTHERS", "WRONG_KIND", "damage_store", "others_check", "others_files", "random_no_data", "random_wrong_kind", "reference_store", "store_equal",
           "store_request"]

#: terminals that cannot show every character (a worker is started with each environment)
ENCODINGS = {
    "C": {"LANG": "C", "LC_ALL": "C", "PYTHONCOERCECLOCALE": "0", "PYTHONUTF8": "0"},
    "ascii": {"PYTHONIOENCODING": "ascii", "PYTHONUTF8": "0"},
    "latin-1": {"PYTHONIOENCODING": "latin-1", "PYTHONUTF8": "0"},
}
#: output names with characters such terminals lack (the extension is the command's own)
ODD_NAMES = ["w\u00e4nde", "k\u00f6rper \u03b8", "\u6570\u636e", "caf\u00e9-\u00b1"]

#: statistics asked of no data, or of too little: each is a clear refusal or a share marked "not enough data"
NO_DATA = [
    ["coin3d", "bounce", "--psi", "0", "--samples", "300", "--seed", "1", "--bounces", "3"],
    ["coin3d", "bounce", "--height", "1e300", "--samples", "300", "--seed", "1"],
    ["coin3d", "bounce", "--g", "1e-6", "--samples", "300", "--seed", "1"],
    ["coin3d", "bounce", "--samples", "10", "--seed", "1", "--bounces", "2"],
    ["coin3d", "caught", "--psi", "70", "--samples", "5", "--seed", "1"],
    ["coin3d", "caught", "--psi", "0", "--samples", "200", "--seed", "1"],
    ["toss", "case:coin", "--spread", "2,5,0.05,0.2", "--samples", "3", "--seed", "1"],
    ["toss", "case:coin", "--e", "1", "--impacts", "10", "--spread", "2,5,0.05,0.2", "--samples", "100", "--seed",
     "1"],
    ["toss", "case:coin", "--v0", "0:3", "--omega", "0:8", "--uncertainty", "1e-6:1e-2:3", "--samples", "5",
     "--seed", "1"],
    ["simulate", "case:coin", "--H", "3", "--collisions", "1", "--seed", "1"],
    ["correlation", "case:coin", "--H", "1.5", "--bounces", "500", "--orbits", "2", "--max-lag", "3", "--seed", "1"],
    ["correlation", "case:coin", "--H", "3", "--bounces", "40", "--orbits", "2", "--max-lag", "30", "--seed", "1"],
]
#: files read as what they are not: a wall given as an outline, an outline given as a wall (all refused)
WRONG_KIND = [["wall", "samples.csv", "-o", "out.csv"], ["mass", "samples.csv"], ["wall", "degrees.csv", "-o", "o.csv"],
              ["mass", "wall.json"], ["export", "wall.json", "-o", "out.svg"], ["wall", "angles.csv", "-o", "o.csv"],
              ["solve", "points.csv"], ["critical", "body.json"], ["fit", "body.csv", "-o", "out.json"],
              ["simulate", "points.csv", "--H", "3", "--collisions", "10"], ["solve", "xy.csv"]]
#: long requests: refused before any work without --allow-long
LONG_REQUESTS = [["toss", "case:coin", "--e", "1", "--impacts", "1000000000"],
                 ["toss", "case:coin", "--e", "1", "--impacts", "100000000", "--v0", "0:3:400", "--omega", "0:8:400"],
                 ["simulate", "case:coin", "--H", "3", "--collisions", "10000000000000"],
                 ["correlation", "case:coin", "--H", "3", "--bounces", "10000000000", "--max-lag", "1"],
                 ["coin3d", "bounce", "--samples", "10000000", "--bounces", "1000"],
                 ["section", "case:coin", "--H", "3", "--orbits", "100", "--collisions", "100000000", "-o", "s.png"]]
#: options that mean nothing or conflict (all refused)
MEANINGLESS = [["toss", "case:coin", "--theta0", "1e300", "--v0", "0:1:2", "--omega", "0:1:2"],
               ["toss", "case:coin", "--theta0", "-inf", "--v0", "0:1:2", "--omega", "0:1:2"],
               ["wall", "--polar", "1", "--H", "5e-324", "-o", "out.csv"],
               ["wall", "body.json", "--H", "1e-3", "-o", "out.csv"],
               ["export", "body.json", "-o", "out.svg", "--cut", "--dimension"],
               ["quantum", "1", "--H", "3", "--levels", "4", "--method", "spectral", "--order", "2"]]


# the scan store: a reference made once, then copies damaged in one way and resumed
STORE_ARGS = ["scan", "chaotic-fraction", "sqrt((1+eps*cos(t)**2)/(1+eps))", "--param", "eps=2,8", "--H", "2.5,3",
              "--orbits", "4", "--collisions", "40", "--seed", "3", "--scheduler", "synchronous", "-o", "s.zarr"]
#: the ways :func:`damage_store` changes a store, and whether the resume must refuse it (else: resume to the same
#: arrays as the reference)
STORE_DAMAGES = {"swap-dims": True, "seed-attr": True, "wall-attr": True, "command-attr": True, "units": True,
                 "extra-array": True, "fifo-chunk": False, "devzero-chunk": False, "huge-chunk": False,
                 "truncated-chunk": False, "deleted-chunk": False, "flipped-status": False}
STORE_NAMES = ("chaotic_fraction", "chaotic_fraction_stderr", "regular_orbits", "orbits_used", "cell_status",
               "cell_checksum", "cell_seed")


def reference_store(folder, worker: Worker) -> None:
    """``ref.zarr`` in ``folder``: the store :data:`STORE_ARGS` makes."""
    result = worker.run(STORE_ARGS[:-1] + ["ref.zarr"], folder)
    if result["rc"] != 0:
        raise RuntimeError(f"coinwall scan could not make the reference store: {result}")


def _edit(path, member, edit):
    for name, key in ((member, None), (".zmetadata", member)):
        with open(os.path.join(path, name)) as fh:
            doc = json.load(fh)
        edit(doc if key is None else doc["metadata"][key])
        with open(os.path.join(path, name), "w") as fh:
            json.dump(doc, fh)


def damage_store(path: str, how: str, rng) -> None:
    """Change the store at ``path`` in one of the :data:`STORE_DAMAGES` ways (a chunk chosen with ``rng``)."""
    chunk = os.path.join(path, rng.choice(STORE_NAMES[:4]), rng.choice(["0.0", "0.1", "1.0", "1.1"]))
    if how == "swap-dims":
        for name in STORE_NAMES[:4]:
            _edit(path, f"{name}/.zattrs", lambda a: a.update(_ARRAY_DIMENSIONS=a["_ARRAY_DIMENSIONS"][::-1]))
    elif how.endswith("-attr"):
        key = how.split("-")[0]
        _edit(path, ".zattrs", lambda a: a.update({key: 4 if key == "seed" else "something else"}))
    elif how == "units":
        _edit(path, "chaotic_fraction/.zattrs", lambda a: a.update(units="m"))
    elif how == "extra-array":
        os.mkdir(os.path.join(path, "junk"))
        with open(os.path.join(path, "junk", ".zarray"), "w") as fh:
            json.dump({"zarr_format": 2, "shape": [5], "chunks": [5], "dtype": "<f8", "compressor": None,
                       "fill_value": None, "order": "C", "filters": None}, fh)
        with open(os.path.join(path, "junk", ".zattrs"), "w") as fh:
            json.dump({"_ARRAY_DIMENSIONS": ["H"]}, fh)
    else:
        if how in ("fifo-chunk", "devzero-chunk", "deleted-chunk"):
            os.unlink(chunk)
        if how == "fifo-chunk":
            os.mkfifo(chunk)
        elif how == "devzero-chunk":
            os.symlink("/dev/zero", chunk)
        elif how == "huge-chunk":
            with open(chunk, "r+b") as fh:
                fh.truncate(6 << 30)
        elif how == "truncated-chunk":
            with open(chunk, "r+b") as fh:
                fh.truncate(3)
        elif how == "flipped-status":
            status = os.path.join(path, "cell_status", rng.choice(["0.0", "1.1"]))
            data = bytearray(open(status, "rb").read())
            data[-1] ^= 0x01
            open(status, "wb").write(bytes(data))


def store_request(base, folder, how, rng):
    """Copy the reference store into ``folder`` as s.zarr, damage it; returns the resume's argv."""
    import shutil

    shutil.copytree(os.path.join(base, "ref.zarr"), os.path.join(folder, "s.zarr"), symlinks=True)
    damage_store(os.path.join(folder, "s.zarr"), how, rng)
    return list(STORE_ARGS)


def store_equal(a, b) -> bool:
    """Whether two stores hold the same arrays (NaN equal to NaN)."""
    import numpy as np
    import zarr

    ga, gb = zarr.open_group(a, mode="r"), zarr.open_group(b, mode="r")
    return all(np.array_equal(np.asarray(ga[n][...]), np.asarray(gb[n][...]), equal_nan=ga[n].dtype.kind == "f")
               for n in STORE_NAMES)


def random_wrong_kind(rng, folder):
    """A wall file written as people write them (header names, delimiters, degrees, rows) given to a command that
    reads outlines, or an outline's points given to one that reads walls: ``(argv, certainly_bad=True)``."""
    n = rng.randint(8, 200)
    delimiter = rng.choice([",", ";", "\t", " "])
    if rng.random() < 0.5:  # a wall, given as an outline
        degrees = rng.random() < 0.5
        header = rng.choice([None, "theta", "θ", "angle", "theta_deg" if degrees else "theta", "Theta (deg)"
                             if degrees else "t"])
        value = rng.choice(["b", "h", "wall", "B"])
        start = rng.randrange(n)
        rows = []
        for k in range(n):
            angle = ((k + start) % n) * (360.0 / n if degrees else 2 * math.pi / n)
            rad = math.radians(angle) if degrees else angle
            rows.append(f"{angle:.6g}{delimiter}{1 + 0.1 * math.cos(2 * rad):.6g}")
        text = ((f"{header}{delimiter}{value}\n" if header else "") + "\n".join(rows) + "\n")
        name = "kind.csv"
        argv = rng.choice([["wall", name, "-o", "out.csv"], ["mass", name]])
    else:  # an outline, given as a wall
        phase = rng.uniform(0, 2 * math.pi)
        a, b = rng.uniform(0.5, 2), rng.uniform(0.5, 2)
        header = rng.choice([None, "x,y", "X,Y"]) if delimiter == "," else None
        rows = [f"{a * math.cos(phase + 2 * math.pi * k / n):.6g}{delimiter}{b * math.sin(phase + 2 * math.pi * k / n):.6g}"
                for k in range(n)]
        text = (header + "\n" if header else "") + "\n".join(rows) + "\n"
        name = "kind.csv"
        argv = rng.choice([["solve", name], ["critical", name], ["fit", name, "-o", "out.json"],
                           ["simulate", name, "--H", "3", "--collisions", "10"]])
    with open(os.path.join(folder, name), "w", encoding="utf-8") as fh:
        fh.write(text)
    return argv


def random_no_data(rng):
    """A statistic asked of little or no data, with random parameters (never certainly bad: a right answer, or
    "not enough data", or a refusal)."""
    kind = rng.choice(["bounce", "caught", "spread", "simulate"])
    if kind == "bounce":
        return ["coin3d", "bounce", "--psi", f"{rng.choice([0, 1e-9, 5, 45, 90, 179, 180]):g}", "--height",
                f"{10 ** rng.uniform(-3, 300):.3g}", "--g", f"{10 ** rng.uniform(-8, 3):.3g}", "--samples",
                str(rng.randint(1, 300)), "--bounces", str(rng.randint(1, 4)), "--seed", "1"]
    if kind == "caught":
        return ["coin3d", "caught", "--psi", f"{rng.uniform(0, 180):.4g}", "--samples", str(rng.randint(1, 200)),
                "--seed", "1"]
    if kind == "spread":
        return ["toss", "case:coin", "--e", f"{rng.uniform(0.3, 1):.3g}", "--impacts", str(rng.randint(1, 200)),
                "--spread", "2,5,0.05,0.2", "--samples", str(rng.randint(1, 200)), "--seed", "1"]
    return ["simulate", "case:coin", "--H", f"{rng.uniform(1.2, 6):.3g}", "--collisions", str(rng.randint(1, 60)),
            "--seed", "1"]


# the round's classes that are fixed in other parts of the code (input numerics, the output writer, fit): in the
# larger run only (--others), so that its table shows where each stands
def others_files(folder):
    with open(os.path.join(folder, "neg.dxf"), "w") as fh:  # a DXF circle of negative radius
        fh.write("0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n8\n0\n10\n0\n20\n0\n40\n-1\n0\nENDSEC\n0\nEOF\n")
    with open(os.path.join(folder, "evil.svg"), "w") as fh:  # a transform list the SVG grammar makes invalid
        fh.write('<svg xmlns="http://www.w3.org/2000/svg"><g transform="scale(2) evil(1)">'
                 '<rect x="-1" y="-1" width="2" height="1"/></g></svg>')
    with open(os.path.join(folder, "priv.csv"), "w") as fh:
        fh.write("private\n")
    os.chmod(os.path.join(folder, "priv.csv"), 0o600)
    os.mkfifo(os.path.join(folder, "pipe.csv"))


#: (area, argv, certainly bad): the requests of the other classes of the round
OTHERS = [
    ("input-numerics", ["solve", "1+0.1*cos(2*t)", "--b0", "\u00a0-0.3"], True),
    ("input-numerics", ["wall", "neg.dxf", "-o", "out.csv"], True),
    ("input-numerics", ["wall", "evil.svg", "-o", "out.csv"], True),
    ("input-numerics", ["mass", "body.json", "--density", "r**-3"], True),
    ("input-numerics", ["quantum", "1", "--H", "3", "--levels", "2", "--body", "1e308,1e308"], False),
    ("input-numerics", ["quantum", "1", "--H", "3", "--levels", "2", "--body", "1,1e-300"], False),
    ("input-numerics", ["kam", "--bracket", "5e-324,1", "--H", "3", "--orbits", "8", "--collisions", "200"], False),
    ("input-numerics", ["critical", "2+0.1*cos(2*t+1e20)", "--json"], False),
    ("outputs", ["solve", "1+0.1*cos(2*t)", "--points", "256", "-o", "priv.csv"], False),
    ("outputs", ["solve", "1+0.1*cos(2*t)", "--points", "256", "-o", "pipe.csv"], True),
    ("fit", ["fit", "samples.csv", "--sigma-b", "1e-300", "-o", "out.json"], False),
]


def others_check(folder, argv, result) -> list:
    """What the other classes promise beyond :func:`cli_fuzz.check_clean`: a replaced file keeps its mode, a FIFO
    given as the output is still a FIFO, and b_c of ``2 + 0.1 cos(2t + φ)`` is −1.7 for every phase φ (b + b'' =
    2 − 0.3 cos(2t + φ)) or the answer is refused."""
    import stat

    problems = []
    if "priv.csv" in argv and result["rc"] == 0 and stat.S_IMODE(os.stat(os.path.join(folder, "priv.csv")).st_mode) \
            != 0o600:
        problems.append("the replaced file lost its mode 0600")
    if "pipe.csv" in argv and not stat.S_ISFIFO(os.lstat(os.path.join(folder, "pipe.csv")).st_mode):
        problems.append("the named pipe given as the output was replaced")
    if argv[:2] == ["critical", "2+0.1*cos(2*t+1e20)"] and result["rc"] == 0:
        doc = json.loads(result["stdout"])
        low, high = doc.get("b_c_lower", doc["b_c"]), doc.get("b_c_upper", doc["b_c"])
        tolerance = doc.get("b_c_tolerance") or 0.0
        if not min(low, doc["b_c"] - tolerance) <= -1.7 <= max(high, doc["b_c"] + tolerance):
            problems.append(f"b_c = {doc['b_c']} ± {tolerance:g} excludes the true -1.7")
    return problems
