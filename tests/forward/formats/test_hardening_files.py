"""Hostile and careless input files: each is refused with one line, exit status 2, no traceback, no output.

The files are the reproducers of issues 12 ("Input files") and 16 ("invalid but accepted"), made by
:func:`make_hostile` (``python tests/forward/formats/test_hardening_files.py /tmp/hostile`` writes them to a folder to
try by hand).  Large inputs (a path of 10⁶ segments, 2·10⁵ DXF circles) must be refused up front by a
count, so the test stays fast; the memory of the largest accepted inputs is measured in
``tests/benchmarks`` and the notes, not here.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward.errors import InvalidOutline, InvalidWall
from coinwall.forward.formats import inputfile

CIRCLE_PATH = "M 10 0 A 10 10 0 0 1 -10 0 A 10 10 0 0 1 10 0 Z"


def _svg(body, head='<?xml version="1.0"?>\n', attributes=""):
    return f'{head}<svg xmlns="http://www.w3.org/2000/svg"{attributes}>{body}</svg>\n'


def _dxf_text(count):
    """DXF text of ``count`` circles written directly (ezdxf takes minutes to build 2·10⁵ entities)."""
    head = "0\nSECTION\n2\nENTITIES\n"
    body = "".join(f"0\nCIRCLE\n8\n0\n10\n{3.0 * (k % 500)}\n20\n{3.0 * (k // 500)}\n30\n0.0\n40\n1.0\n"
                   for k in range(count))
    return head + body + "0\nENDSEC\n0\nEOF\n"


def make_hostile(folder):
    """Write the hostile files to ``folder``; returns ``{name: (command, path, words)}``: the coinwall
    subcommand that reads the file and words its one-line error must contain."""
    os.makedirs(folder, exist_ok=True)
    cases = {}

    def put(name, command, words, text=None, data=None):
        path = os.path.join(folder, name)
        if text is not None:
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text)
        elif data is not None:
            with open(path, "wb") as fh:
                fh.write(data)
        cases[name] = (command, path, words)
        return path

    # --- not regular files
    fifo = os.path.join(folder, "fifo.csv")
    if not os.path.exists(fifo):
        os.mkfifo(fifo)
    cases["fifo.csv"] = ("critical", fifo, "not a regular file")
    fifo_svg = os.path.join(folder, "fifo.svg")
    if not os.path.exists(fifo_svg):
        os.mkfifo(fifo_svg)
    cases["fifo.svg"] = ("wall", fifo_svg, "not a regular file")
    for name, device in (("zero.csv", "/dev/zero"), ("urandom.json", "/dev/urandom"), ("zero.svg", "/dev/zero"),
                         ("urandom.dxf", "/dev/urandom")):
        path = os.path.join(folder, name)
        if not os.path.lexists(path):
            os.symlink(device, path)
        cases[name] = ("critical" if name.endswith((".csv", ".json")) else "wall", path, "not a regular file")
    for name in ("folder.csv", "folder.svg"):
        os.makedirs(os.path.join(folder, name), exist_ok=True)
        cases[name] = ("critical" if name.endswith(".csv") else "wall", os.path.join(folder, name),
                       "not a regular file")
    put("latin1.csv", "critical", "UTF-8", data="theta,b\n0,1\n1,1\n2,1é\n".encode("latin-1"))

    # --- wall CSV
    put("onecol.csv", "critical", "2 (theta, b", "\n".join(str(k * 0.1) for k in range(20)) + "\n")
    put("threecol.csv", "critical", "2 (theta, b", "\n".join(f"{k * 0.1},1,2" for k in range(20)) + "\n")
    put("empty.csv", "critical", "no rows", "")
    put("comments.csv", "critical", "no rows", "# nothing but a comment\n\n")
    rows = [f"{k * 0.1},1" for k in range(60)]
    put("badrow.csv", "critical", "line 31", "\n".join(rows[:30] + ["0.3,abc"] + rows[30:]) + "\n")
    put("missing.csv", "critical", "line 11", "\n".join(rows[:10] + ["0.3,"] + rows[10:]) + "\n")
    put("nanrow.csv", "critical", "not finite", "\n".join(rows[:10] + ["1.05,nan"] + rows[11:]) + "\n")
    # --- wall JSON
    put("deep.json", "critical", "nested", "[" * 100000 + "]" * 100000)
    put("deepkey.json", "critical", "nested", '{"theta": ' + "[" * 100000 + "]" * 100000 + ', "b": [1]}')
    put("strings.json", "critical", "`theta`", json.dumps({"theta": ["0", "1", "2"], "b": [1, 1, 1]}))
    put("booleans.json", "critical", "`b`", json.dumps({"theta": [0, 1, 2], "b": [True, 1, 1]}))
    put("nested.json", "critical", "`b`", json.dumps({"theta": [0, 1, 2], "b": [[1], 1, 1]}))
    put("nan.json", "critical", "NaN", '{"theta": [0, 1, 2, 3], "b": [1, NaN, 1, 1]}')
    put("infinity.json", "critical", "Infinity", '{"a0": Infinity, "cos": [0.1]}')
    put("bigint.json", "critical", "`a0`", '{"a0": 1' + "0" * 400 + ', "cos": [0.1]}')

    # --- SVG
    put("encoding.svg", "wall", "encoding", _svg(f'<path d="{CIRCLE_PATH}"/>',
                                                 head='<?xml version="1.0" encoding="no-such-codec"?>\n'))
    put("nested.svg", "wall", "nested", _svg("<g>" * 10000 + f'<path d="{CIRCLE_PATH}"/>' + "</g>" * 10000))
    put("bigcircle.svg", "wall", "circle", _svg('<circle cx="0" cy="0" r="1e308"/>'))
    put("tinycircle.svg", "wall", "circle", _svg('<circle cx="0" cy="0" r="1e-308"/>'))
    put("infcoord.svg", "wall", "finite", _svg('<path d="M 0 0 L 1e400 0 L 0 1 Z"/>'))
    put("huge.svg", "wall", "larger than", _svg('<path d="M 0 0 L 1e308 0 L 0 1e308 Z"/>'))
    put("overflow.svg", "wall", "after its transforms", _svg('<g transform="scale(1e90)"><path d="M 0 0 L 1e90 0 '
                                                             'L 0 1e90 Z"/></g>'))
    put("nantransform.svg", "wall", "transform", _svg(f'<path d="{CIRCLE_PATH}" transform="matrix(1e400 0 0 1 0 0)"/>'))
    put("scale0.svg", "wall", "singular", _svg(f'<path d="{CIRCLE_PATH}" transform="scale(0)"/>'))
    put("singular.svg", "wall", "singular", _svg(f'<path d="{CIRCLE_PATH}" transform="matrix(1 2 2 4 0 0)"/>'))
    put("nomoveto.svg", "wall", "moveto", _svg('<path d="L 10 0 L 0 10 L -10 0 Z"/>'))
    put("bomb.svg", "wall", "entit", '<?xml version="1.0"?>\n<!DOCTYPE svg [\n<!ENTITY a "aaaaaaaaaa">\n'
        + "".join(f'<!ENTITY {chr(98 + k)} "{("&" + chr(97 + k) + ";") * 10}">\n' for k in range(8))
        + ']>\n<svg xmlns="http://www.w3.org/2000/svg"><title>&i;</title>'
          f'<path d="{CIRCLE_PATH}"/></svg>\n')
    put("external.svg", "wall", "entit", '<?xml version="1.0"?>\n<!DOCTYPE svg [\n'
        '<!ENTITY secret SYSTEM "file:///etc/passwd">\n]>\n<svg xmlns="http://www.w3.org/2000/svg">'
        f'<title>&secret;</title><path d="{CIRCLE_PATH}"/></svg>\n')
    put("kappa-3.svg", "wall", "kappa", _svg(f'<path d="{CIRCLE_PATH}"/>', attributes=' data-coinwall-kappa="-3"'))
    put("kappainf.svg", "wall", "kappa", _svg(f'<path d="{CIRCLE_PATH}"/>',
                                               attributes=' data-coinwall-kappa="1e999"'))
    put("comoutside.svg", "wall", "centre of mass", _svg(f'<path d="{CIRCLE_PATH}"/>',
                                                        attributes=' data-coinwall-com="50,50"'))
    put("nanattribute.svg", "wall", "not a number", _svg('<circle cx="nan" cy="0" r="3"/>'))
    put("oddpoints.svg", "wall", "odd", _svg('<polygon points="0,0 1,0 inf,1"/>'))
    rng = np.random.default_rng(12)
    segments = " ".join(f"L {x:.3f} {y:.3f}" for x, y in rng.uniform(-100, 100, (1_000_000, 2)))
    put("path1m.svg", "wall", "segments", _svg(f'<path d="M 0 0 {segments} Z"/>'))
    curves = " ".join("C " + " ".join(f"{v:.1f}" for v in row) for row in rng.uniform(-1e4, 1e4, (10_000, 6)))
    put("pathrandom.svg", "wall", "points", _svg(f'<path d="M 0 0 {curves} Z"/>'))
    put("circles.svg", "wall", "points", _svg("".join(f'<circle cx="{3 * k}" cy="0" r="1"/>' for k in range(5000))))

    # --- DXF
    full = _dxf_text(3)
    put("truncated.dxf", "wall", "DXF", full[: len(full) // 2])
    put("truncated2.dxf", "wall", "DXF", full[: full.index("CIRCLE") + 9])
    put("garbage.dxf", "wall", "DXF", "0\nSECTION\n2\nENTITIES\n0\nCIRCLE\n10\nnot-a-number\n0\nENDSEC\n0\nEOF\n")
    put("binary.dxf", "wall", "DXF", data=bytes(range(256)) * 40)
    put("circles2e5.dxf", "wall", "entities", _dxf_text(200_000))
    put("bigcircle.dxf", "wall", "larger than", _dxf_text(1).replace("40\n1.0\n", "40\n1e308\n"))
    put("tinycircle.dxf", "wall", "measures", _dxf_text(1).replace("40\n1.0\n", "40\n1e-308\n"))
    put("nancircle.dxf", "wall", "DXF", _dxf_text(1).replace("40\n1.0\n", "40\nnan\n"))
    import ezdxf

    for name, value in (("kappa-3.dxf", "-3"), ("kappainf.dxf", "inf")):
        doc = ezdxf.new()
        doc.modelspace().add_circle((0, 0), 1.0)
        doc.ezdxf_metadata()["coinwall_kappa"] = value
        doc.saveas(os.path.join(folder, name))
        cases[name] = ("wall", os.path.join(folder, name), "kappa")
    doc = ezdxf.new()
    doc.modelspace().add_circle((0, 0), 1.0)
    doc.modelspace().add_point((5, 5), dxfattribs={"layer": "ANNOTATION_CENTRE_OF_MASS"})
    doc.saveas(os.path.join(folder, "comoutside.dxf"))
    cases["comoutside.dxf"] = ("wall", os.path.join(folder, "comoutside.dxf"), "outside the body")

    # --- body JSON and points CSV
    put("deepbody.json", "mass", "nested", '{"outline": ' + "[" * 100000 + "]" * 100000 + "}")
    put("stringpoints.json", "mass", "outline", json.dumps({"outline": [["1", 0], [0, 1], [-1, 0]]}))
    put("boolpoints.json", "mass", "outline", json.dumps({"outline": [[True, 0], [0, 1], [-1, 0]]}))
    put("nestedpoints.json", "mass", "outline", json.dumps({"outline": [[[1], 0], [0, 1], [-1, 0]]}))
    put("kappa-3.json", "mass", "kappa", json.dumps({"outline": [[1, 0], [0, 1], [-1, 0]], "kappa": -3}))
    nodes = np.array([[10.0, 0.0], [11.0, 0.0], [10.0, 1.0]])  # a coinwall body (straight Béziers) far from (0, 0)
    controls = np.stack([nodes + (np.roll(nodes, -1, axis=0) - nodes) / 3,
                         nodes + 2 * (np.roll(nodes, -1, axis=0) - nodes) / 3], axis=1)
    put("comoutside.json", "mass", "outside", json.dumps({"outline": nodes.tolist(), "controls": controls.tolist()}))
    put("nanpoints.json", "mass", "NaN", '{"points": [[1, 0], [0, NaN], [-1, 0]]}')
    put("onecol.csv.body.csv", "mass", "2 columns", "1\n2\n3\n")
    put("threecol.body.csv", "mass", "line 2", "1,0\n0,1,5\n-1,0\n")
    put("emptybody.csv", "mass", "no x,y points", "# just a comment\n")
    put("badrow.body.csv", "mass", "line 3", "x,y\n1,0\n0,abc\n-1,0\n0,-1\n")
    return cases


# ------------------------------------------------------------------------------------------------ every hostile file
@pytest.fixture(scope="module")
def hostile(tmp_path_factory):
    return make_hostile(str(tmp_path_factory.mktemp("hostile")))


def _names():
    """The names make_hostile writes, listed without writing the large files twice."""
    import inspect
    import re

    source = inspect.getsource(make_hostile)
    names = re.findall(r'put\("([^"]+)"', source)
    return names + ["kappa-3.dxf", "kappainf.dxf", "comoutside.dxf", "fifo.csv", "fifo.svg", "zero.csv", "urandom.json", "zero.svg", "urandom.dxf", "folder.csv",
                    "folder.svg"]


@pytest.mark.parametrize("name", _names())
def test_hostile_file_is_one_line_exit_2_no_output(hostile, name, tmp_path, capsys):
    """Each reproducer of issues 12 and 16: exit status 2, exactly one stderr line naming the file and the
    problem (the words of make_hostile), no traceback, and no output file."""
    command, path, words = hostile[name]
    out = tmp_path / "out.csv"
    argv = [command, path] + (["-o", str(out)] if command == "wall" else [])
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("coinwall: error: ") and "Traceback" not in err[0]
    assert words.lower() in err[0].lower(), err[0]
    assert os.path.basename(path) in err[0]
    assert not out.exists()


def test_hostile_file_in_a_subprocess_has_no_warning_lines(hostile):
    """The same through the installed entry point, for the cases where NumPy used to print RuntimeWarnings
    and a UserWarning (nothing is captured by pytest there)."""
    for name in ("overflow.svg", "emptybody.csv", "nantransform.svg", "empty.csv"):
        command, path, _ = hostile[name]
        run = subprocess.run([sys.executable, "-c", "import sys; from coinwall.cases.cli.main import main; sys.exit(main())",
                              command, path], capture_output=True,
                             text=True, timeout=120, check=False)
        assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1, (name, run.stderr)


# ----------------------------------------------------------------------------------------------------- valid inputs
def test_valid_drawings_still_read(tmp_path):
    """What the bounds must not refuse: a DOCTYPE naming the SVG DTD (Inkscape writes one), a path starting with a
    relative moveto, a centre of mass on the outline (a critical body), a rotated group."""
    from coinwall.forward.formats import load_outline

    doctype = ('<?xml version="1.0" encoding="UTF-8"?>\n<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" '
               '"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">\n')
    drawing = tmp_path / "ok.svg"
    # a triangle (10, 0), (0, 10), (-10, 0) with its recorded centre of mass (0, 0) on its lower edge
    drawing.write_text(_svg('<path d="m 10 0 l -10 10 l -10 -10 z"/>', head=doctype,
                            attributes=' data-coinwall-com="0,0"'))
    outline, _ = load_outline(str(drawing))
    # every vertex is 10 from the centre of mass (closed form)
    np.testing.assert_allclose(np.max(np.hypot(*outline.polygon().T)), 10.0, rtol=1e-12)
    rotated = tmp_path / "rotated.svg"
    rotated.write_text(_svg('<g transform="rotate(30) translate(5 5)"><rect width="4" height="2"/></g>'))
    outline, _ = load_outline(str(rotated))
    # a 4 × 2 rectangle about its centroid: half-diagonal √5 (closed form), whatever the rotation
    np.testing.assert_allclose(np.max(np.hypot(*outline.polygon().T)), np.sqrt(5.0), rtol=1e-12)


def test_largest_accepted_counts_are_accepted(tmp_path):
    """A path just under MAX_SEGMENTS... would take seconds; here: a 5 000-segment path and a DXF of 300 circles'
    worth of LINEs pass the up-front counts (the counts refuse only above the bounds)."""
    from coinwall.forward.formats import load_outline
    from coinwall.forward.formats.dxf import _count_entities

    angles = np.linspace(0, 2 * np.pi, 5000, endpoint=False)
    d = "M " + " L ".join(f"{10 * np.cos(a):.9f} {10 * np.sin(a):.9f}" for a in angles) + " Z"
    drawing = tmp_path / "many.svg"
    drawing.write_text(_svg(f'<path d="{d}"/>'))
    outline, _ = load_outline(str(drawing))
    assert np.max(np.hypot(*outline.polygon().T)) == pytest.approx(10.0, rel=1e-8)  # the polygon's circumradius
    assert _count_entities(_dxf_text(300).encode()) == 300 + 3  # SECTION, ENDSEC, EOF are structures too


# -------------------------------------------------------------------------------------------------- inputfile units
def test_read_bytes_reads_a_regular_file_and_refuses_the_rest(tmp_path):
    path = tmp_path / "a.csv"
    path.write_bytes(b"0,1\n1,1\n")
    assert inputfile.read_bytes(str(path)) == b"0,1\n1,1\n"
    assert inputfile.read_text(str(path)) == "0,1\n1,1\n"
    fifo = tmp_path / "p.csv"
    os.mkfifo(fifo)
    with pytest.raises(InvalidWall, match="FIFO"):
        inputfile.read_bytes(str(fifo), what="wall file", error=InvalidWall)  # returns at once: never opened
    with pytest.raises(InvalidOutline, match="folder"):
        inputfile.read_bytes(str(tmp_path))
    with pytest.raises(InvalidOutline, match="character device"):
        inputfile.read_bytes("/dev/zero")
    with pytest.raises(InvalidOutline, match="does not exist"):
        inputfile.read_bytes(str(tmp_path / "missing.svg"))
    with pytest.raises(InvalidOutline, match="too large: 8 bytes, at most 4"):
        inputfile.read_bytes(str(path), max_bytes=4)


def test_a_fifo_swapped_in_after_the_check_does_not_block(tmp_path, monkeypatch):
    """os.stat says "regular file" (the FIFO appeared after the check): the non-blocking open returns and
    fstat on the descriptor refuses it."""
    regular = tmp_path / "r.csv"
    regular.write_bytes(b"x")
    fifo = tmp_path / "p.csv"
    os.mkfifo(fifo)
    real_stat = os.stat
    monkeypatch.setattr(os, "stat", lambda p, *a, **k: real_stat(regular) if str(p) == str(fifo) else real_stat(p))
    with pytest.raises(InvalidOutline, match="FIFO"):
        inputfile.read_bytes(str(fifo))


def test_read_text_names_the_first_bad_byte(tmp_path):
    path = tmp_path / "w.csv"
    path.write_bytes(b"0,1\n1,\xff\n")
    with pytest.raises(InvalidWall, match=r"not UTF-8 text: byte 0xff at offset 6"):
        inputfile.read_text(str(path), what="wall file", error=InvalidWall)


def test_json_nesting_and_non_finite_literals(tmp_path):
    assert inputfile.json_nesting('[[1, {"a": "[[[["}]]') == 3  # brackets in strings do not count
    assert inputfile.json_nesting('"[\\"["') == 0
    assert inputfile.json_nesting("[" * 5000 + "]" * 5000) == 5000
    path = tmp_path / "w.json"
    path.write_text('{"b": [1, NaN]}')
    assert np.isnan(inputfile.read_json(str(path))["b"][1])  # read, so that the reader can name `b`[1]
    path.write_text("[" * (inputfile.MAX_NESTING + 1) + "]" * (inputfile.MAX_NESTING + 1))
    with pytest.raises(InvalidOutline, match="nested 201 levels deep"):
        inputfile.read_json(str(path))


if __name__ == "__main__":  # write the hostile files to a folder, to try them by hand
    for command, path, _ in make_hostile(sys.argv[1] if len(sys.argv) > 1 else "/tmp/hostile").values():
        print(f"coinwall {command} {path}")
