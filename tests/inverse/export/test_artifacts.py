"""Bodies as artifacts: DXF/SVG export at a physical scale, import of drawings, round trips, errors."""

import json
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from coinwall.cases.cli.main import main
from coinwall.forward import Wall
from coinwall.forward.errors import InvalidArgument, InvalidOutline, OutputError
from coinwall.forward.formats import load_outline, outline_from_polar
from coinwall.inverse import solve_body
from coinwall.inverse.export import export_body

ELLIPSE = "sqrt((1+eps*cos(t)**2)/(1+eps))"  # paper eq. 18; b0 = 0: x² + (1+eps) y² = 1
THETA = np.linspace(0, 2 * np.pi, 997, endpoint=False)


def ellipse_wall(theta, eps=1.0):
    return np.sqrt((1 + eps * np.cos(theta) ** 2) / (1 + eps))


@pytest.fixture(scope="module")
def skew_body():
    # an asymmetric convex body: centroid off the origin, so the round trip must keep the recorded COM
    return solve_body(Wall.from_expression(ELLIPSE + "+0.05*sin(t)+0.02*cos(3*t)", {"eps": 1}), 0.3)


def test_dxf_has_exact_spline_polyline_units_and_passes_audit(tmp_path, skew_body):
    import ezdxf

    out = str(tmp_path / "body.dxf")
    result = export_body(skew_body, [out], kappa=20.0, units="mm", tolerance=1e-4)
    report = result.reports[out]
    assert report["polyline"] <= 1e-4 and report["spline"] < 1e-10
    doc = ezdxf.readfile(out)
    auditor = doc.audit()
    assert len(auditor.errors) == 0
    assert doc.header["$INSUNITS"] == 4
    spline = doc.modelspace().query("SPLINE")
    poly = doc.modelspace().query("LWPOLYLINE")
    assert len(spline) == 1 and len(poly) == 1
    assert spline[0].dxf.layer != poly[0].dxf.layer and poly[0].closed and spline[0].closed
    # the spline read back equals 20 x the Bézier outline (same parametrisation: knot i <-> node i)
    tool = spline[0].construction_tool()
    n = len(skew_body.outline.nodes)
    s = np.array([0.0, 0.25, 0.5, 0.8])
    knots = (np.arange(n)[:, None] + s).ravel()
    got = np.array([(v.x, v.y) for v in tool.points(knots)])
    assert np.max(np.abs(got - 20 * skew_body.outline.point(s).reshape(-1, 2))) < 1e-10
    # the polyline's deviation measured independently: distance of dense curve points to the polygon
    from shapely.geometry import LinearRing, Point

    ring = LinearRing([(p[0], p[1]) for p in poly[0].get_points("xy")])
    dense = 20 * skew_body.outline.polygon(40)
    worst = max(ring.distance(Point(*p)) for p in dense[::7])
    assert worst <= 1e-4 * (1 + 1e-9)


def test_corners_stay_corners_in_dxf(tmp_path):
    import ezdxf

    body = solve_body(Wall.from_expression(ELLIPSE, {"eps": 1}), -0.6)  # Case III: two corners
    assert body.regime == "corner" and len(body.corners) == 2
    out = str(tmp_path / "c.dxf")
    export_body(body, [out], tolerance=1e-5)
    doc = ezdxf.readfile(out)
    assert len(doc.audit().errors) == 0
    verts = np.array(doc.modelspace().query("LWPOLYLINE")[0].get_points("xy"))
    tool = doc.modelspace().query("SPLINE")[0].construction_tool()
    for corner in body.corners:
        tip = corner.distance * np.array([math.cos(corner.direction), math.sin(corner.direction)])
        # the corner point is a vertex of the polyline...
        assert np.min(np.hypot(*(verts - tip).T)) < 1e-9
        # ...and the spline's tangent turns there by a finite angle (C0 knot, not rounded)
        k = int(np.argmin(np.hypot(*(body.outline.nodes - tip).T)))
        d_in = tool.derivative(k - 1e-9 if k else len(body.outline.nodes) - 1e-9, 1)[1]
        d_out = tool.derivative(k + 1e-9, 1)[1]
        turn = abs(math.atan2(d_in.x * d_out.y - d_in.y * d_out.x, d_in.x * d_out.x + d_in.y * d_out.y))
        assert turn > 0.5  # the window half-width is ≈ 0.9 rad, the tangent jumps by twice that


def test_svg_scale_viewbox_com_and_dimension(tmp_path, skew_body):
    out = str(tmp_path / "b.svg")
    result = export_body(skew_body, [out], kappa=2.5, units="cm", dimension=True)
    root = ET.parse(out).getroot()
    assert root.get("width").endswith("cm") and root.get("height").endswith("cm")
    box = [float(v) for v in root.get("viewBox").split()]
    assert box[2] == pytest.approx(float(root.get("width")[:-2]))
    ns = "{http://www.w3.org/2000/svg}"
    assert root.find(f"{ns}circle[@id='centre-of-mass']") is not None
    assert root.find(f"{ns}path[@id='outline']").get("d").rstrip().endswith("Z")
    label = "".join(root.itertext())
    diameter = result.reports[out]["diameter"]
    assert f"D = {diameter:.4g} cm" in label
    # diameter = max width h(θ) + h(θ+π), independently on a fine grid
    width = skew_body.outline.support(THETA) + skew_body.outline.support(THETA + np.pi)
    assert diameter == pytest.approx(2.5 * width.max(), rel=1e-5)
    unscaled = str(tmp_path / "u.svg")
    export_body(skew_body, [unscaled])
    assert "units of kappa" in open(unscaled).read()


def _svg_ellipse(path, eps):
    # drawn as a designer would: shifted, inside a transformed group, with a stray open line
    ry = 1 / math.sqrt(1 + eps)
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">'
                    f'<g transform="translate(4,5) rotate(0)"><ellipse cx="0.5" cy="0.25" rx="1" ry="{ry!r}"/></g>'
                    f'<line x1="0" y1="0" x2="1" y2="1"/></svg>')


def _dxf_ellipse(path, eps, layer="BODY"):
    import ezdxf

    doc = ezdxf.new()
    doc.modelspace().add_ellipse((3.0, -2.0), major_axis=(1, 0), ratio=1 / math.sqrt(1 + eps),
                                 dxfattribs={"layer": layer})
    doc.modelspace().add_circle((0, 0), 0.1, dxfattribs={"layer": "OTHER"})
    doc.saveas(path)


@pytest.mark.parametrize("kind", ["svg", "dxf"])
def test_drawn_ellipse_to_wall_to_body(tmp_path, kind, capsys):
    eps = 1.0
    drawing = tmp_path / f"ellipse.{kind}"
    if kind == "svg":
        _svg_ellipse(drawing, eps)
        extra = []
    else:
        _dxf_ellipse(str(drawing), eps)
        extra = ["--layer", "BODY"]
    wall_csv = str(tmp_path / "wall.csv")
    assert main(["wall", str(drawing), "-o", wall_csv, "--samples", "512"] + extra) == 0
    assert "centroid" in capsys.readouterr().out
    data = np.loadtxt(wall_csv, delimiter=",", skiprows=1)
    # flattening chord error 1e-8 x size bounds the wall error (support function of an inscribed polygon)
    assert np.max(np.abs(data[:, 1] - ellipse_wall(data[:, 0], eps))) < 1e-7
    body_json = str(tmp_path / "body.json")
    assert main(["solve", wall_csv, "--b0", "0", "-o", body_json, "--json"]) == 0
    capsys.readouterr()
    pts = np.array(json.load(open(body_json))["outline"])
    # analytic ellipse x² + (1+eps) y² = 1 (paper, b0 = 0)
    assert np.max(np.abs(pts[:, 0] ** 2 + (1 + eps) * pts[:, 1] ** 2 - 1)) < 1e-5


def test_solve_dxf_import_wall_round_trip_to_tolerance(tmp_path, skew_body):
    out = str(tmp_path / "b.dxf")
    tol = 2e-4  # mm, with kappa = 20 mm
    export_body(skew_body, [out], kappa=20.0, units="mm", tolerance=tol)
    prescribed = skew_body.b0 + skew_body.wall(THETA)
    spline, _ = load_outline(out, layer="OUTLINE")
    poly, _ = load_outline(out, layer="OUTLINE_POLYLINE")
    # the exact spline: only the import flattening (1e-8 relative) and the solve error remain
    assert np.max(np.abs(spline.support(THETA) - prescribed)) < 1e-7
    # the polyline: inscribed, within the export tolerance (in κ: tol / 20)
    err = prescribed - poly.support(THETA)
    assert np.max(np.abs(err)) <= tol / 20 + 1e-9
    assert np.max(np.abs(err)) > 0  # a polyline is not the curve: the check can fail


def test_constant_width_survives_the_loop(tmp_path, capsys):
    # Reuleaux-type body: h(θ) = 1 + 0.1 cos 3θ has h(θ) + h(θ+π) = 2 (convex since 1 − 8·0.1 > 0)
    body = str(tmp_path / "r.json")
    drawing = str(tmp_path / "r.dxf")
    assert main(["solve", "1+0.1*cos(3*t)", "-o", body, "-o", drawing, "--kappa", "10", "--units", "mm",
                 "--tolerance", "1e-5"]) == 0
    wall_csv = str(tmp_path / "w.csv")
    assert main(["wall", drawing, "--layer", "OUTLINE_POLYLINE", "-o", wall_csv, "--samples", "720"]) == 0
    data = np.loadtxt(wall_csv, delimiter=",", skiprows=1)
    b = data[:, 1]
    width = b + np.roll(b, -360)
    assert np.max(np.abs(width - 2)) < 2 * 1e-5 / 10 + 1e-9
    assert main(["solve", wall_csv, "-o", str(tmp_path / "again.dxf")]) == 0
    capsys.readouterr()


def test_polar_expression_and_convex_hull_note(capsys):
    outline, note = outline_from_polar("1+0.3*cos(3*t)")
    assert "convex hull" in note
    smooth, note = outline_from_polar("1+0.05*cos(3*t)")
    assert "convex" in note and "hull" not in note
    # Hermite outline with exact derivatives: the support function of R = 1 + 0.05 cos 3α, checked at
    # directions where the support point is on the α axis of symmetry: h(0) = R(0) = 1.05
    assert smooth.support(np.array([0.0, np.pi / 3]))[0] == pytest.approx(1.05, abs=1e-12)
    assert main(["wall", "--polar", "1+a*cos(3*t)", "--param", "a=0.3"]) == 0
    assert "convex hull" in capsys.readouterr().out


def test_com_option_and_kappa_option(tmp_path):
    path = tmp_path / "sq.csv"
    path.write_text("x,y\n0,0\n2,0\n2,2\n0,2\n")
    centred, note = load_outline(str(path))
    assert "centroid (1, 1)" in note
    assert centred.support(np.array([0.0]))[0] == pytest.approx(1.0)
    given, _ = load_outline(str(path), com=(0.5, 1.0), kappa=0.5)
    assert given.support(np.array([0.0, np.pi]))[0] == pytest.approx(3.0)


# ------------------------------------------------------------------------- errors: one line, exit 2, no file
BAD_FILES = {
    "empty.svg": "",
    "broken.svg": "<svg><path d='M 0 0 L 1",
    "open.svg": '<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 L 1 1 L 2 0"/><line x1="0" y1="0" x2="1" y2="1"/></svg>',
    "broken.dxf": "0\nSECTION\n2\nENTITIES\n0\nGARBAGE\n",
    "body.xyz": "1,2\n",
}


@pytest.mark.parametrize("name, message", [("empty.svg", "empty"), ("broken.svg", "not valid SVG"),
                                           ("open.svg", "no closed shape"), ("broken.dxf", "DXF"),
                                           ("body.xyz", "unsupported extension")])
def test_bad_input_files(tmp_path, capsys, name, message):
    path = tmp_path / name
    path.write_text(BAD_FILES[name])
    out = tmp_path / "wall.csv"
    assert main(["wall", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()


def test_dxf_nothing_on_layer(tmp_path, capsys):
    path = str(tmp_path / "e.dxf")
    _dxf_ellipse(path, 1.0)
    out = tmp_path / "w.csv"
    assert main(["wall", path, "--layer", "NOPE", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "layer 'NOPE'" in err and "BODY" in err and not out.exists()


def test_export_errors_leave_nothing(tmp_path, capsys, skew_body):
    body = str(tmp_path / "b.json")
    export_body(skew_body, [body])
    out = tmp_path / "x.dxf"
    for args, message in [(["--kappa", "20"], "--units"), (["--kappa", "-1", "--units", "mm"], "--kappa"),
                          (["--tolerance", "1e-30"], "tolerance")]:
        assert main(["export", body, "-o", str(out)] + args) == 2
        assert message in capsys.readouterr().err
        assert not out.exists()
        assert not [f for f in os.listdir(tmp_path) if f.startswith(".coinwall-")]
    assert main(["export", body, "-o", str(tmp_path / "x.png")]) == 2
    assert main(["export", body, "-o", str(out), "--kappa", "20", "--units", "mm"]) == 0
    assert "LWPOLYLINE" in capsys.readouterr().out
    with pytest.raises(InvalidArgument):
        export_body(skew_body, [str(out)], units="mm")
    with pytest.raises(OutputError):
        export_body(skew_body, [str(tmp_path / "b.dwg")])


def test_wall_png_output(tmp_path, capsys):
    body = str(tmp_path / "b.json")
    assert main(["solve", ELLIPSE, "--param", "eps=1", "-o", body]) == 0
    png = tmp_path / "w.png"
    assert main(["wall", body, "-o", str(png), "--H", "3"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(InvalidOutline):
        load_outline(str(tmp_path / "missing.svg"))


def test_body_files_are_byte_for_byte_reproducible(tmp_path, skew_body):
    """No dates, timings or random GUIDs inside a body file: solving the same wall again and writing
    every format gives the same bytes (the solve's wall-clock time differs between the two solves;
    ezdxf would stamp $TDCREATE/$TDUPDATE and GUIDs)."""
    import ezdxf

    from coinwall.inverse.export import EXPORTERS

    again = solve_body(skew_body.wall, skew_body.b0)
    option_before = ezdxf.options.write_fixed_meta_data_for_testing
    for ext in EXPORTERS:
        first, second = tmp_path / f"first{ext}", tmp_path / f"second{ext}"
        export_body(skew_body, [str(first)], kappa=20.0, units="mm")
        export_body(again, [str(second)], kappa=20.0, units="mm")
        assert first.read_bytes() == second.read_bytes(), ext
    assert "seconds" not in json.loads((tmp_path / "first.json").read_text())
    assert ezdxf.options.write_fixed_meta_data_for_testing == option_before  # the global option is restored


def test_figure_formats_and_library_load_wall(tmp_path, skew_body):
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.formats import load_wall

    png, pdf = str(tmp_path / "b.png"), str(tmp_path / "b.pdf")
    export_body(skew_body, [png, pdf])
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n" and open(pdf, "rb").read(5) == b"%PDF-"
    # the library's load_wall: an expression, .csv samples and .json Fourier coefficients give one wall
    # (a trigonometric polynomial of order 2: 64 uniform samples determine it exactly)
    expression = load_wall("1+0.2*cos(2*t)")
    (tmp_path / "w.json").write_text('{"a0": 1, "cos": [0, 0.2], "sin": []}')
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    rows = "".join(f"{t!r},{1 + 0.2 * math.cos(2 * t)!r}\n" for t in theta.tolist())
    (tmp_path / "w.csv").write_text("theta,b\n" + rows)
    for name in ("w.json", "w.csv"):
        assert np.max(np.abs(load_wall(str(tmp_path / name))(THETA) - expression(THETA))) < 1e-12
    with pytest.raises(InvalidWall, match="`params`"):
        load_wall(str(tmp_path / "w.json"), {"eps": 1.0})
