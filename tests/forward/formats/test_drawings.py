"""Drawings as users write them: units, LINE/ARC chains, one shape picked, merged shapes, page
backgrounds, and cut-ready output (issue 11, "Reading data as users write it — Drawings" and
"Cut-ready drawings").

Provenance: every reference value is computed here with numpy from the drawn geometry (vertices,
shoelace centroid, support function h(θ) = max_v (v − c)·(cos θ, sin θ), the unit lengths of the SVG
and DXF specifications: 1 in = 25.4 mm, 1 px = 1/96 in, 1 pt = 1/72 in), never by the reader itself.
"""

from __future__ import annotations

import io
import math
import random

import numpy as np
import pytest

from coinwall.cases.cli import main
from coinwall.forward.errors import InvalidArgument, InvalidOutline
from coinwall.forward.formats.load import read_outline

THETA = np.linspace(0, 2 * np.pi, 720, endpoint=False)
# an irregular convex pentagon (drawing coordinates, y up)
PENTAGON = np.array([[0.0, 0.0], [40.0, -5.0], [55.0, 20.0], [30.0, 45.0], [-5.0, 25.0]])


def shoelace_centroid(pts):
    x, y = pts[:, 0], pts[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * area)


def support(pts, theta=THETA):
    """Support function of the points about the origin (their hull's)."""
    return np.max(np.outer(np.cos(theta), pts[:, 0]) + np.outer(np.sin(theta), pts[:, 1]), axis=1)


def pentagon_wall(kappa_in_coordinates):
    c = shoelace_centroid(PENTAGON)
    return support((PENTAGON - c) / kappa_in_coordinates)


def svg_polygon(pts, root_attributes, element_id="body", extra=""):
    # SVG y points down: the drawing is written with y flipped, as a user's editor would store it
    text = " ".join(f"{float(x)!r},{float(-y)!r}" for x, y in pts)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" {root_attributes}>{extra}'
            f'<polygon id="{element_id}" points="{text}"/></svg>')


# --- units ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("width, per_coordinate_mm", [
    ('width="200mm" height="100mm" viewBox="-100 -100 2000 1000"', 0.1),
    ('width="20cm" height="10cm" viewBox="-100 -100 1000 500"', 0.2),
    ('width="4in" height="2in" viewBox="-100 -100 400 200"', 0.254),
    ('width="96px" height="48px" viewBox="-100 -100 96 48"', 25.4 / 96),
    ('width="72pt" height="36pt" viewBox="-100 -100 144 72"', 25.4 / 144),
    ('width="50mm" height="50mm"', 25.4 / 96),  # no viewBox: a user unit is one CSS px
])
def test_svg_units_give_the_physical_scale(tmp_path, width, per_coordinate_mm):
    path = tmp_path / "p.svg"
    path.write_text(svg_polygon(PENTAGON, width))
    kappa_mm = 12.0
    expected = pentagon_wall(kappa_mm / per_coordinate_mm)
    for kappa, units in [(12.0, "mm"), (1.2, "cm"), (12.0 / 25.4, "in")]:
        reading = read_outline(str(path), kappa=kappa, units=units)
        assert np.max(np.abs(reading.outline.support(THETA) - expected)) < 1e-12 * np.max(expected)
        assert reading.warnings == []


def test_kappa_alone_is_in_the_drawings_own_unit(tmp_path):
    path = tmp_path / "p.svg"
    path.write_text(svg_polygon(PENTAGON, 'width="200mm" height="100mm" viewBox="0 0 2000 1000"'))
    reading = read_outline(str(path), kappa=12.0)
    assert np.allclose(reading.outline.support(THETA), pentagon_wall(120.0), rtol=0, atol=1e-12)
    assert "kappa = 12 mm" in reading.note
    # a unitless width is a screen size, no unit: κ is then in drawing coordinates, or in --units
    plain = tmp_path / "plain.svg"
    plain.write_text(svg_polygon(PENTAGON, 'width="400" height="400" viewBox="0 0 100 100"'))
    assert np.allclose(read_outline(str(plain), kappa=12.0).outline.support(THETA), pentagon_wall(12.0), atol=1e-12)
    reading = read_outline(str(plain), kappa=12.0, units="mm")
    assert "records no unit" in reading.note
    with pytest.raises(InvalidArgument, match="`units` mm needs `kappa`"):
        read_outline(str(plain), units="mm")
    with pytest.raises(InvalidArgument, match="`units`"):
        read_outline(str(plain), kappa=1.0, units="furlong")


@pytest.mark.parametrize("code, mm", [(4, 1.0), (5, 10.0), (1, 25.4), (6, 1000.0)])
def test_dxf_insunits(tmp_path, code, mm):
    import ezdxf

    doc = ezdxf.new()
    doc.header["$INSUNITS"] = code
    doc.modelspace().add_lwpolyline([tuple(p) for p in PENTAGON], close=True)
    path = str(tmp_path / "p.dxf")
    doc.saveas(path)
    reading = read_outline(path, kappa=12.0, units="mm")
    assert np.max(np.abs(reading.outline.support(THETA) - pentagon_wall(12.0 / mm))) < 1e-12 * 60 * mm / 12


def test_solved_svg_round_trips_and_so_does_a_foreign_copy(tmp_path, capsys):
    """`solve -o body.svg --kappa 12 --units mm` read back by `wall` gives the prescribed wall; the same
    outline drawn by someone else (coordinates ×10 in a 0.1 mm viewBox, no coinwall metadata, origin
    moved) gives it too with `--kappa 12 --units mm --com X,Y`."""
    import re

    wall = "1+0.1*cos(3*t)"  # convex (1 − 8·0.1 > 0); the uniform body has κ_max ≥ 1 at this size
    body = str(tmp_path / "body.svg")
    assert main(["solve", wall, "-o", body, "--kappa", "12", "--units", "mm"]) == 0
    prescribed = 1 + 0.1 * np.cos(3 * THETA)
    for extra in ([], ["--kappa", "12", "--units", "mm"], ["--kappa", "12"]):
        csv = str(tmp_path / "w.csv")
        assert main(["wall", body, "-o", csv, "--samples", "720"] + extra) == 0
        data = np.loadtxt(csv, delimiter=",", skiprows=1)
        assert np.max(np.abs(data[:, 1] - prescribed)) < 1e-7  # solve error + 1e-8 flattening
    capsys.readouterr()
    with open(body) as handle:
        d = re.search(r'id="outline" d="([^"]+)"', handle.read()).group(1)
    shift = (300.0, 200.0)  # the foreign origin, in the foreign coordinates

    def foreign(match):
        x, y = float(match.group(1)), float(match.group(2))
        return f"{10 * x + shift[0]!r},{10 * y + shift[1]!r}"

    moved = re.sub(r"([-+]?[\d.]+(?:e[-+]?\d+)?),([-+]?[\d.]+(?:e[-+]?\d+)?)", foreign, d)
    drawing = tmp_path / "foreign.svg"
    drawing.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="60mm" viewBox="0 0 600 600">'
                       f'<path d="{moved}"/></svg>')
    csv = str(tmp_path / "f.csv")
    # the centre of mass in drawing coordinates, as written in the file (SVG user units, y down)
    com = f"{shift[0]!r},{shift[1]!r}"
    assert main(["wall", str(drawing), "--kappa", "12", "--units", "mm", "--com", com, "-o", csv]) == 0
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert np.max(np.abs(data[:, 1] - prescribed)) < 1e-7
    capsys.readouterr()


# --- DXF LINE and ARC chains ------------------------------------------------------------------------

def _stadium_pieces(half_length, radius):
    """Two LINEs and two ARCs of a stadium centred at the origin, as (kind, data) in drawing order."""
    a, r = half_length, radius
    return [("line", ((-a, -r), (a, -r))), ("arc", ((a, 0.0), r, -90.0, 90.0)),
            ("line", ((a, r), (-a, r))), ("arc", ((-a, 0.0), r, 90.0, 270.0))]


def _write_pieces(path, pieces, seed, layer="0"):
    import ezdxf

    rng = random.Random(seed)
    pieces = list(pieces)
    rng.shuffle(pieces)  # CAD files list entities in any order and direction
    doc = ezdxf.new()
    msp = doc.modelspace()
    for kind, data in pieces:
        if kind == "line":
            start, end = data if rng.random() < 0.5 else data[::-1]
            msp.add_line(start, end, dxfattribs={"layer": layer})
        else:
            msp.add_arc(*data, dxfattribs={"layer": layer})
    doc.saveas(path)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_dxf_line_arc_chain_is_an_outline(tmp_path, seed):
    path = str(tmp_path / "stadium.dxf")
    a, r = 2.0, 1.0
    _write_pieces(path, _stadium_pieces(a, r), seed)
    reading = read_outline(path)
    # the stadium's support function about its centre (= centroid, by symmetry): r + a |cos θ|
    expected = r + a * np.abs(np.cos(THETA))
    assert np.max(np.abs(reading.outline.support(THETA) - expected)) < 1e-7
    assert reading.warnings == []


def test_dxf_polygon_of_lines(tmp_path):
    pieces = [("line", (tuple(PENTAGON[k]), tuple(PENTAGON[(k + 1) % 5]))) for k in range(5)]
    path = str(tmp_path / "pentagon.dxf")
    _write_pieces(path, pieces, 3)
    assert np.max(np.abs(read_outline(path).outline.support(THETA) - pentagon_wall(1.0))) < 1e-12 * 60


def test_open_chain_names_the_gap(tmp_path, capsys):
    pieces = [("line", (tuple(PENTAGON[k]), tuple(PENTAGON[(k + 1) % 5]))) for k in range(4)]  # one edge missing
    path = str(tmp_path / "open.dxf")
    _write_pieces(path, pieces, 4)
    gap = float(np.hypot(*(PENTAGON[4] - PENTAGON[0])))
    with pytest.raises(InvalidOutline, match="open") as info:
        read_outline(path)
    assert f"{gap:.3g}" in str(info.value)
    assert main(["wall", path]) == 2
    assert f"{gap:.3g} apart" in capsys.readouterr().err


# --- one shape, merged shapes, backgrounds ------------------------------------------------------------

def test_element_picks_one_shape_and_merging_warns(tmp_path, capsys):
    square = np.array([[100.0, 0.0], [110.0, 0.0], [110.0, 10.0], [100.0, 10.0]])
    text = " ".join(f"{float(x)!r},{float(-y)!r}" for x, y in square)
    path = tmp_path / "two.svg"
    path.write_text(svg_polygon(PENTAGON, 'viewBox="-10 -60 200 100"',
                                extra=f'<g id="other"><polygon points="{text}"/></g>'))
    picked = read_outline(str(path), element="body")
    assert np.max(np.abs(picked.outline.support(THETA) - pentagon_wall(1.0))) < 1e-12 * 60
    assert picked.warnings == []
    other = read_outline(str(path), element="other")
    assert np.max(np.abs(other.outline.support(THETA) - support(square - square.mean(axis=0)))) < 1e-12 * 100
    merged = read_outline(str(path))
    assert len(merged.warnings) == 1 and "2 shapes merged" in merged.warnings[0]
    # the merged hull is the hull of both (its centre of mass: the union's centroid, areas as weights)
    x, y = PENTAGON.T
    area_p = 0.5 * abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    c = (area_p * shoelace_centroid(PENTAGON) + 100.0 * square.mean(axis=0)) / (area_p + 100.0)
    assert np.allclose(merged.outline.support(THETA), support(np.vstack([PENTAGON, square]) - c), atol=1e-9)
    csv = str(tmp_path / "w.csv")
    assert main(["wall", str(path), "-o", csv]) == 0  # the wall of the merged hull is well defined
    err = capsys.readouterr().err
    assert err.startswith("warning: 2 shapes merged") and "--element" in err
    assert main(["wall", str(path), "--element", "nope"]) == 2
    err = capsys.readouterr().err
    assert "'nope'" in err and "'body'" in err and "'other'" in err


def test_layer_picks_one_shape_and_inner_shapes_are_noted(tmp_path, capsys):
    import ezdxf

    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_lwpolyline([tuple(p) for p in PENTAGON], close=True, dxfattribs={"layer": "BODY"})
    msp.add_circle((25.0, 20.0), 3.0, dxfattribs={"layer": "HOLE"})  # inside: no effect on the hull
    msp.add_circle((200.0, 0.0), 3.0, dxfattribs={"layer": "FAR"})
    path = str(tmp_path / "layers.dxf")
    doc.saveas(path)
    picked = read_outline(path, layer="BODY")
    assert np.max(np.abs(picked.outline.support(THETA) - pentagon_wall(1.0))) < 1e-12 * 60
    assert picked.warnings == []
    assert len(read_outline(path).warnings) == 1
    assert main(["wall", path, "--layer", "FAR"]) == 0
    assert "warning" not in capsys.readouterr().err
    doc.modelspace().delete_entity(doc.modelspace().query("CIRCLE[layer=='FAR']").first)
    doc.saveas(path)
    reading = read_outline(path)
    assert reading.warnings == [] and "1 shape inside the largest one" in reading.note


def test_page_background_is_left_out(tmp_path):
    path = tmp_path / "bg.svg"
    path.write_text(svg_polygon(PENTAGON, 'width="100mm" height="100mm" viewBox="-20 -60 100 100"',
                                extra='<rect x="-20" y="-60" width="100" height="100" fill="white"/>'))
    reading = read_outline(str(path))
    assert "background rectangle covering 100% of the page left out" in reading.note
    assert reading.warnings == []
    assert np.max(np.abs(reading.outline.support(THETA) - pentagon_wall(1.0))) < 1e-12 * 60
    alone = tmp_path / "alone.svg"
    alone.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">'
                     '<rect id="page" x="2" y="2" width="96" height="96"/></svg>')
    with pytest.raises(InvalidOutline, match="background"):
        read_outline(str(alone))
    # picked on purpose, it is the body: a 96 × 96 square about its centre
    square = read_outline(str(alone), element="page").outline
    assert np.allclose(square.support(THETA), 48 * (np.abs(np.cos(THETA)) + np.abs(np.sin(THETA))), atol=1e-9)


def test_dxf_frame_is_left_out(tmp_path):
    import ezdxf

    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_lwpolyline([(-100, -100), (300, -100), (300, 200), (-100, 200)], close=True)
    msp.add_lwpolyline([tuple(p) for p in PENTAGON], close=True)
    path = str(tmp_path / "frame.dxf")
    doc.saveas(path)
    reading = read_outline(path)
    assert "frame" in reading.note and reading.warnings == []
    assert np.max(np.abs(reading.outline.support(THETA) - pentagon_wall(1.0))) < 1e-12 * 60


# --- cut-ready drawings ---------------------------------------------------------------------------

def _entities_per_layer(path):
    import collections

    import ezdxf

    doc = ezdxf.readfile(path)
    count = collections.Counter((e.dxf.layer, e.dxftype()) for e in doc.modelspace())
    return dict(count)


def test_cut_dxf_is_one_contour_on_one_layer(tmp_path, capsys):
    wall = "1+0.1*cos(3*t)"
    cut, full = str(tmp_path / "cut.dxf"), str(tmp_path / "full.dxf")
    body_json = str(tmp_path / "body.json")
    assert main(["solve", wall, "-o", cut, "-o", body_json, "--kappa", "10", "--units", "mm", "--cut",
                 "--tolerance", "1e-4"]) == 0
    assert _entities_per_layer(cut) == {("CUT", "LWPOLYLINE"): 1}
    assert main(["solve", wall, "-o", full, "--kappa", "10", "--units", "mm"]) == 0
    assert _entities_per_layer(full) == {("OUTLINE", "SPLINE"): 1, ("OUTLINE_POLYLINE", "LWPOLYLINE"): 1,
                                         ("ANNOTATION_CENTRE_OF_MASS", "POINT"): 1,
                                         ("ANNOTATION_CENTRE_OF_MASS", "LINE"): 2,
                                         ("ANNOTATION_NOTES", "TEXT"): 1}
    # the cut contour reads back (scale and centre of mass from the metadata) within the tolerance
    csv = str(tmp_path / "w.csv")
    assert main(["wall", cut, "-o", csv]) == 0
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert np.max(np.abs(data[:, 1] - (1 + 0.1 * np.cos(3 * data[:, 0])))) < 1e-4 / 10 + 1e-7
    # the default drawing read as a whole: annotations are not outline, the copies coincide: no warning
    assert main(["wall", full, "-o", csv]) == 0
    assert "warning" not in capsys.readouterr().err
    again = str(tmp_path / "again.dxf")
    assert main(["export", body_json, "-o", again, "--kappa", "10", "--units", "mm", "--cut"]) == 0
    assert _entities_per_layer(again) == {("CUT", "LWPOLYLINE"): 1}
    capsys.readouterr()


def test_cut_svg_is_one_path(tmp_path, capsys):
    import xml.etree.ElementTree as ET

    cut = str(tmp_path / "cut.svg")
    assert main(["solve", "1+0.1*cos(3*t)", "-o", cut, "--kappa", "10", "--units", "mm", "--cut"]) == 0
    capsys.readouterr()
    root = ET.parse(cut).getroot()
    drawn = [e.tag.rsplit("}", 1)[-1] for e in root.iter()]
    assert drawn == ["svg", "g", "path"]
    reading = read_outline(cut)
    prescribed = 1 + 0.1 * np.cos(3 * THETA)
    assert np.max(np.abs(reading.outline.support(THETA) - prescribed)) < 1e-7
    assert math.isclose(float(root.get("width")[:-2]), float(root.get("viewBox").split()[2]))


# --------------------------------------------------------------- DXF files as CAD programs write them
def _circle_dxf(path, radius, n, layer, line_end=b"\n"):
    """A closed n-gon inscribed in a circle of ``radius``, one LWPOLYLINE on ``layer``, saved as DXF R2010."""
    import ezdxf

    doc = ezdxf.new("R2010")  # from R2007 on, a DXF's text is UTF-8 by the standard, whatever $DWGCODEPAGE says
    doc.layers.add(layer)
    phi = 2 * np.pi * np.arange(n) / n
    doc.modelspace().add_lwpolyline(np.column_stack([radius * np.cos(phi), radius * np.sin(phi)]).tolist(),
                                    close=True, dxfattribs={"layer": layer})
    stream = io.StringIO()
    doc.write(stream)
    data = stream.getvalue().encode("utf-8").replace(b"\r\n", b"\n")
    with open(path, "wb") as handle:
        handle.write(data.replace(b"\n", line_end))


@pytest.mark.parametrize("line_end", [b"\n", b"\r\n"], ids=["LF", "CRLF"])
def test_dxf_with_crlf_lines_and_a_non_ascii_layer_name(tmp_path, line_end):
    # Windows CAD programs write CRLF line ends; ezdxf reads them, and so must coinwall.  The layer name is
    # UTF-8 in an R2010 file (read as cp1252 it became 'Schicht_Ã¤Ã¶Ã¼' and --layer found nothing)
    path = str(tmp_path / "circle.dxf")
    _circle_dxf(path, 20.0, 400, "Schicht_äöü", line_end)
    reading = read_outline(path, layer="Schicht_äöü")
    # the 400-gon's support function: r cos(distance of θ to the nearest vertex direction), vertices at 2πk/400
    nearest = np.abs((THETA + np.pi / 400) % (2 * np.pi / 400) - np.pi / 400)
    assert np.max(np.abs(reading.outline.support(THETA) - 20.0 * np.cos(nearest))) < 1e-9


def test_drawn_circle_certified_interval_covers_the_circle(tmp_path):
    # a drawn circle of r = 20 (a 20,000-gon) used to report b_c = -19.8012 ± 4.6e-07; the circle's b_c is
    # -r exactly (b = r, b'' = 0): the interval coinwall certifies from the drawing's wall must hold it
    from coinwall.forward.formats.wallfile import load_wall_file
    from coinwall.inverse import critical_offset

    drawing, wall_csv = str(tmp_path / "circle.dxf"), str(tmp_path / "wall.csv")
    _circle_dxf(drawing, 20.0, 20_000, "outline")
    assert main(["wall", drawing, "-o", wall_csv]) == 0
    result = critical_offset(load_wall_file(wall_csv))
    assert result.lower <= -20.0 <= result.upper
    assert result.upper - result.lower < 2e-3 * 20  # and says something: the drawing's flattening is 20·(1−cos(π/n))
