"""`--com X,Y` and `com=(x, y)` are in drawing coordinates: the coordinates as written in the file.

SVG: user units (the viewBox's coordinates, whatever its offset), y pointing down, not converted to
the physical unit of `width`/`height`; a transform on a group moves the shape, not `com`.  DXF: the
drawing's x, y, y up, in its `$INSUNITS`.  The SVG reader turns the body over (y up); `com` must name
the same point of the drawing, so the walls are compared with a support function computed here with
numpy from the vertices and the centre of mass as written, h(θ) = max_k (v_k − c)·n(θ) / scale, on an
asymmetric body (a reflection would show), placed away from the origin.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from coinwall.cases.cli import main
from coinwall.forward.formats.load import load_outline, read_outline

#: an asymmetric convex quadrilateral, as written in the drawing, away from the origin
QUAD = np.array([[40.0, 10.0], [95.0, 18.0], [80.0, 52.0], [47.0, 44.0]])
#: a centre of mass inside it, off the centroid, as written in the drawing
COM = (60.0, 25.0)
THETA = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
ANGLES = np.random.default_rng(7).uniform(0.0, 2 * np.pi, 300)


def support(vertices, com, scale, theta):
    """h(θ) = max_k (v_k − c)·n(θ) / scale, in the frame of ``vertices`` and ``com`` (y up)."""
    normals = np.column_stack([np.cos(theta), np.sin(theta)])
    return ((np.asarray(vertices, float) - np.asarray(com, float)) @ normals.T).max(axis=0) / scale


def svg_expected(vertices, com, scale, theta):
    """The convention for SVG: the body and the centre of mass as written, both turned over to y up."""
    flip = np.array([1.0, -1.0])
    return support(np.asarray(vertices) * flip, np.asarray(com) * flip, scale, theta)


def relative_error(got, expected):
    return float(np.max(np.abs(got - expected)) / np.max(np.abs(expected)))


def points_text(vertices):
    return " ".join(f"{float(x)!r},{float(y)!r}" for x, y in vertices)


def write_svg(path, body, width="50mm", height="25mm", view_box="-40 -30 200 100"):
    """``body`` inside an SVG with a viewBox offset and a physical width: one user unit is 0.25 mm."""
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
                    f'viewBox="{view_box}">{body}</svg>')
    return str(path)


def write_dxf(path, vertices, insunits=4):
    import ezdxf

    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = insunits
    doc.modelspace().add_lwpolyline([tuple(v) for v in vertices], close=True)
    doc.saveas(path)
    return str(path)


def cli_wall(tmp_path, args, samples=len(THETA)):
    csv = str(tmp_path / "wall.csv")
    assert main(["wall", *args, "--samples", str(samples), "-o", csv]) == 0
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 0], THETA, rtol=0, atol=1e-15)
    return data[:, 1]


# --------------------------------------------------------------------------------------------------- SVG

def test_svg_com_is_in_user_units_y_down(tmp_path, capsys):
    """viewBox offset (−40, −30), 0.25 mm a user unit; `--kappa 3 --units mm` is 12 user units."""
    path = write_svg(tmp_path / "quad.svg", f'<polygon points="{points_text(QUAD)}"/>')
    expected = svg_expected(QUAD, COM, 12.0, THETA)
    got = cli_wall(tmp_path, [path, "--com", f"{COM[0]!r},{COM[1]!r}", "--kappa", "3", "--units", "mm"])
    assert relative_error(got, expected) < 1e-9
    assert "centre of mass given at (60, 25)" in capsys.readouterr().out
    # the library: the same convention, at other angles and in other units (0.3 cm = 12 user units)
    reading = read_outline(path, com=COM, kappa=0.3, units="cm")
    assert relative_error(reading.outline.support(ANGLES), svg_expected(QUAD, COM, 12.0, ANGLES)) < 1e-9
    outline, _ = load_outline(path, com=list(COM), kappa=0.3, units="cm")
    assert relative_error(outline.support(ANGLES), svg_expected(QUAD, COM, 12.0, ANGLES)) < 1e-9


def test_svg_com_flipped_would_be_far_off(tmp_path):
    """The test above tells the conventions apart: the mirrored point (60, −25) read as the centre of
    mass (y taken up) is inside too, and gives a wall off by a large part of the body's size."""
    path = write_svg(tmp_path / "quad.svg", f'<polygon points="{points_text(QUAD)}"/>', view_box="0 -100 200 200",
                     height="50mm")
    right = svg_expected(QUAD, COM, 1.0, ANGLES)
    wrong = support(QUAD * [1, -1], COM, 1.0, ANGLES)  # the body turned over, the centre of mass not
    assert relative_error(wrong, right) > 0.2
    got = read_outline(path, com=COM).outline.support(ANGLES)
    assert relative_error(got, right) < 1e-9


def test_svg_triangle_com_0_10(tmp_path):
    """A right triangle around the origin where both (0, 10) and (0, −10) are inside: `--com 0,10` is the
    SVG point (0, 10), 10 user units *below* the origin; reading it as (0, −10) errs by 40 % of the size."""
    triangle = np.array([[-20.0, -15.0], [30.0, -15.0], [-20.0, 35.0]])
    path = write_svg(tmp_path / "tri.svg", f'<polygon points="{points_text(triangle)}"/>', width="100",
                     height="100", view_box="-50 -50 100 100")
    expected = svg_expected(triangle, (0.0, 10.0), 1.0, THETA)
    got = cli_wall(tmp_path, [path, "--com", "0,10"])
    assert relative_error(got, expected) < 1e-9
    mirrored = svg_expected(triangle, (0.0, -10.0), 1.0, THETA)
    assert np.max(np.abs(mirrored - expected)) == pytest.approx(0.4 * 50, rel=1e-12)


def test_svg_group_transform_moves_the_shape_not_the_com(tmp_path):
    """A shape inside a transformed group: `com` stays in the root's user units."""
    local = np.array([[0.0, 0.0], [22.0, 4.0], [16.0, 17.0], [3.0, 14.0]])
    matrix = np.array([[2.5, 0.0], [0.0, 2.5]])
    offset = np.array([40.0, 10.0])
    placed = local @ matrix.T + offset  # where the group puts it, in the root's user units (y down)
    path = write_svg(tmp_path / "group.svg", f'<g transform="translate(40,10) scale(2.5)">'
                                             f'<polygon points="{points_text(local)}"/></g>')
    com = (placed[:, 0].mean() + 3.0, placed[:, 1].mean() - 2.0)
    reading = read_outline(path, com=com, kappa=3.0, units="mm")
    assert relative_error(reading.outline.support(ANGLES), svg_expected(placed, com, 12.0, ANGLES)) < 1e-9


def test_svg_root_transform_applies_to_com_as_to_shapes(tmp_path):
    """A transform on the root element applies to its children; `com` is written as a child would be."""
    root = '<svg xmlns="http://www.w3.org/2000/svg" transform="translate(7,-3)">'
    (tmp_path / "root.svg").write_text(f'{root}<polygon points="{points_text(QUAD)}"/></svg>')
    reading = read_outline(str(tmp_path / "root.svg"), com=COM)
    shifted = QUAD + [7.0, -3.0]
    com = np.asarray(COM) + [7.0, -3.0]
    assert relative_error(reading.outline.support(ANGLES), svg_expected(shifted, com, 1.0, ANGLES)) < 1e-9


def test_svg_printed_centroid_is_a_com(tmp_path, capsys):
    """The centroid the note prints is in drawing coordinates: given back as `--com`, the same wall."""
    path = write_svg(tmp_path / "quad.svg", f'<polygon points="{points_text(QUAD)}"/>')
    _, note = load_outline(path)
    x, y = (float(v) for v in note.split("centroid (")[1].split(")")[0].split(", "))
    assert y > 0  # as written (y down), not turned over
    plain = load_outline(path)[0].support(ANGLES)
    again = load_outline(path, com=(x, y))[0].support(ANGLES)
    assert relative_error(again, plain) < 1e-5  # the note prints 6 digits
    assert relative_error(plain, svg_expected(QUAD, (x, y), 1.0, ANGLES)) < 1e-5


def test_svg_com_outside_is_refused_in_drawing_coordinates(tmp_path, capsys):
    """(90, 45) is outside the quadrilateral as drawn (its mirror (90, −45) would be inside the turned-over
    body): refused, exit 2, and the message gives the point as typed."""
    path = write_svg(tmp_path / "quad.svg", f'<polygon points="{points_text(QUAD)}"/>')
    csv = tmp_path / "wall.csv"
    assert main(["wall", path, "--com", "90,45", "-o", str(csv)]) == 2
    assert "(90, 45) lies outside" in capsys.readouterr().err
    assert not csv.exists()
    inside = cli_wall(tmp_path, [path, "--com", "85,22"])
    assert relative_error(inside, svg_expected(QUAD, (85.0, 22.0), 1.0, THETA)) < 1e-9


def test_mass_com_is_in_drawing_coordinates(tmp_path, capsys):
    """`coinwall mass --com` follows the same rule: the centroid as written, given as `--com`, puts the
    uniform centroid at the origin."""
    path = write_svg(tmp_path / "quad.svg", f'<polygon points="{points_text(QUAD)}"/>')
    doubled = np.vstack([QUAD, QUAD[:1]])
    cross = doubled[:-1, 0] * doubled[1:, 1] - doubled[1:, 0] * doubled[:-1, 1]
    area = cross.sum() / 2
    centroid = ((doubled[:-1] + doubled[1:]) * cross[:, None]).sum(axis=0) / (6 * area)
    assert main(["mass", path, "--com", f"{float(centroid[0])!r},{float(centroid[1])!r}", "--json"]) == 0
    centre = json.loads(capsys.readouterr().out)["uniform"]
    centre = centre.get("centre", centre.get("centroid"))
    assert np.max(np.abs(centre)) < 1e-9 * 55


# --------------------------------------------------------------------------------------------------- DXF

def test_dxf_com_is_as_written_y_up(tmp_path, capsys):
    """DXF in mm ($INSUNITS 4): `--kappa 0.3 --units cm` is 3 drawing units; no flip."""
    pytest.importorskip("ezdxf")
    path = write_dxf(tmp_path / "quad.dxf", QUAD)
    expected = support(QUAD, COM, 3.0, THETA)
    got = cli_wall(tmp_path, [path, "--com", f"{COM[0]!r},{COM[1]!r}", "--kappa", "0.3", "--units", "cm"])
    assert relative_error(got, expected) < 1e-9
    reading = read_outline(path, com=COM, kappa=3.0, units="mm")
    assert relative_error(reading.outline.support(ANGLES), support(QUAD, COM, 3.0, ANGLES)) < 1e-9


def test_svg_and_dxf_of_the_same_drawing_agree(tmp_path):
    """The same quadrilateral drawn in SVG (y down) and in DXF (y up, the mirror image) with the same
    centre of mass drawn: the walls are those of mirror images, h_svg(θ) = h_dxf(−θ)."""
    pytest.importorskip("ezdxf")
    svg = write_svg(tmp_path / "quad.svg", f'<polygon points="{points_text(QUAD)}"/>', width="200",
                    height="100")
    dxf = write_dxf(tmp_path / "quad.dxf", QUAD, insunits=0)
    h_svg = read_outline(svg, com=COM).outline.support(ANGLES)
    h_dxf = read_outline(dxf, com=COM).outline.support(-ANGLES)
    assert relative_error(h_svg, h_dxf) < 1e-9


# ------------------------------------------------------------------------------------------ other inputs

def test_csv_points_com_as_written(tmp_path):
    path = tmp_path / "quad.csv"
    path.write_text("x,y\n" + "\n".join(f"{float(x)!r},{float(y)!r}" for x, y in QUAD) + "\n")
    reading = read_outline(str(path), com=COM)
    assert relative_error(reading.outline.support(ANGLES), support(QUAD, COM, 1.0, ANGLES)) < 1e-9


def test_explore_upload_takes_no_com(tmp_path):
    """The explorer's upload reads a drawing about its centroid (it takes no centre of mass): the centroid
    is a point of the drawing, so the wall is that of the drawn body whichever way y points."""
    from coinwall.cases.explore import compute

    path = write_svg(tmp_path / "quad.svg", f'<polygon points="{points_text(QUAD)}"/>')
    with open(path, "rb") as stream:
        wall = compute._read_upload("quad.svg", stream.read())
    doubled = np.vstack([QUAD, QUAD[:1]])
    cross = doubled[:-1, 0] * doubled[1:, 1] - doubled[1:, 0] * doubled[:-1, 1]
    centroid = ((doubled[:-1] + doubled[1:]) * cross[:, None]).sum(axis=0) / (3 * cross.sum())
    theta = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)[::11]
    # the drawing's wall at b0 = 0, sampled on 4096 angles: exact at the samples
    assert relative_error(wall(theta), svg_expected(QUAD, centroid, 1.0, theta)) < 1e-9
