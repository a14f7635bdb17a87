"""The explorer's computations: JSON-ready dicts in, JSON-ready dicts out, run inside a worker process.

Every public function here takes the decoded request (a dict) and returns a dict that
``json.dumps`` accepts (no NaN: missing numbers are ``None``).  They call the library only
(``Wall.from_expression``, ``critical_offset``, ``solve_body``, ``realizability``, the exporters,
``ensemble``, ``poincare_section``) and never read a path a request names: uploaded files arrive as
bytes and are written to a private temporary folder before the project's file readers read them.

Bad input raises a :class:`~coinwall.forward.errors.CoinwallError`; :func:`field` tags it with the
page field it belongs to (``wall``, ``params``, ``b0``, ``H`` ...), so the page can show the message
next to that field.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import math
import os
import tempfile

import numpy as np

from coinwall.forward.display import json_number

__all__ = ["CASE_DEFAULT", "CURVATURE_POINTS", "JOBS", "LIVE_POINTS", "MAX_BEAM", "MAX_BEAM_COLLISIONS", "MAX_PARAMS",
           "MAX_SECTION_COLLISIONS", "PARAM_DEFAULT", "MissingUpload", "beam", "body", "cases", "export",
           "field", "free_names", "get_wall", "number", "realize", "table", "upload", "wall_info"]

#: the case the page opens on: the paper's Appendix wall (ellipse ε = 1), b_c = −1/2, at b0 = −0.3 (convex)
CASE_DEFAULT = "appendix-convex"
#: outline nodes of the live body (the issue's "1,024-point body")
LIVE_POINTS = 1024
#: a beam has at most this many trajectories, each at most this many collisions (payload ~ 1 MB)
MAX_BEAM = 500
MAX_BEAM_COLLISIONS = 200
#: collisions of the orbit a click adds to the Poincaré section
MAX_SECTION_COLLISIONS = 20000
#: at most this many angles of a sampled wall's discrete curvature go to the page; denser data go as the bounds of
#: each of this many equal bins of θ (the least lower and the largest upper bound of the samples in it)
CURVATURE_POINTS = 2048
_UPLOAD_KINDS = (".csv", ".json", ".svg", ".dxf")
_PLOT_ANGLES = 361
_DIGITS = 6

# walls already built in this process, by key (parsing an expression and its casadi functions costs ~15 ms)
_WALLS: dict = {}
_MAX_WALLS = 16


class MissingUpload(Exception):
    """The worker does not hold the uploaded wall a request names (it was restarted): send the bytes."""


@contextlib.contextmanager
def field(name: str):
    """Tag an exception raised inside with the page field ``name`` (the first tag wins)."""
    try:
        yield
    except Exception as exc:
        if not hasattr(exc, "explore_field"):
            with contextlib.suppress(AttributeError, TypeError):
                exc.explore_field = name
        raise


_MISSING = object()


def number(spec: dict, key: str, default=_MISSING) -> float:
    """The finite number ``spec[key]`` (``default`` when absent or null): a JSON number, never text or a truth value.

    The page sends numbers as JSON numbers; the command line's grammar for text (ASCII decimals) is not
    re-implemented here because text is simply refused: ``"3_0"``, ``"３"`` or ``"0x1"`` would each have
    been read by Python's ``float`` (as 30, 3 and an error), and ``true`` as 1.
    """
    from coinwall.forward.errors import InvalidArgument

    value = spec.get(key)
    if value is None:
        if default is _MISSING:
            raise InvalidArgument(f"`{key}` is missing; give a number")
        return default
    return _finite(value, f"`{key}`", InvalidArgument)


def _finite(value, what: str, error) -> float:
    """``value`` as a finite float if it is a JSON number (not a truth value); ``error`` naming ``what`` else."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise error(f"{what} must be a number, got {value!r}"[:200])
    value = float(value)  # the JSON reader caps numbers at 100 characters: no overflow here
    if not math.isfinite(value):
        raise error(f"{what} must be finite, got {value}")
    return value


def _list(values, digits=_DIGITS):
    arr = np.asarray(values, dtype=float)
    out = np.round(arr, digits).tolist()
    bad = ~np.isfinite(arr)
    if bad.any():  # JSON has no NaN/inf: the plot leaves a gap there
        for i in np.flatnonzero(bad.ravel()):
            out[int(i)] = None
    return out


def _remember(key, wall):
    if len(_WALLS) >= _MAX_WALLS:
        _WALLS.pop(next(iter(_WALLS)))
    _WALLS[key] = wall
    return wall


#: the value a parameter starts at when the expression first names it (the page gives it a slider)
PARAM_DEFAULT = 0.5
#: at most this many parameters (sliders) for one expression
MAX_PARAMS = 12


def free_names(text) -> list:
    """The parameter names of an expression, in the order they first appear: every name that is not
    ``t``/``theta``, a constant or a function (``[]`` if the text does not parse: the parser says why)."""
    import ast

    from coinwall.forward.expression import _NAME_RE, _RESERVED

    if not isinstance(text, str) or len(text) > 2000:
        return []
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return []
    called = {id(node.func) for node in ast.walk(tree) if isinstance(node, ast.Call)}
    names = []
    for node in sorted((n for n in ast.walk(tree) if isinstance(n, ast.Name) and id(n) not in called),
                       key=lambda n: (n.lineno, n.col_offset)):
        ident = node.id
        if ident not in names and ident not in _RESERVED and _NAME_RE.match(ident) and not ident.startswith("__"):
            names.append(ident)
    return names


def _given_params(spec) -> dict:
    """``params`` as given: a dict ``{name: value}`` or text ``"eps=1, a=0.5"`` (the library's parser)."""
    from coinwall.forward.errors import InvalidParameter
    from coinwall.forward.expression import parse_params

    raw = spec.get("params") or {}
    if isinstance(raw, str):
        # the command line's grammar: NAME=VALUE items separated by commas, none of them empty
        items = [part.strip() for part in raw.split(",")]
        if raw.strip() and not all(items):
            raise InvalidParameter(f"the parameters {raw[:80]!r} have an empty item; write NAME=VALUE pairs separated "
                                   "by single commas, e.g. eps=1, a=0.5")
        return parse_params([item for item in items if item], what="parameter")
    if not isinstance(raw, dict):
        raise InvalidParameter("the parameters must be NAME=VALUE pairs, e.g. eps=1")
    return {str(k): v for k, v in raw.items()}


def _params(spec) -> dict:
    """The parameters of the expression: one per free name of the expression (:func:`free_names`), its
    value as given, else :data:`PARAM_DEFAULT`; values given for names the expression no longer uses are
    dropped (the page's sliders follow the expression)."""
    from coinwall.forward.errors import InvalidParameter

    given = _given_params(spec)
    names = free_names(spec.get("expression"))
    if len(names) > MAX_PARAMS:
        raise InvalidParameter(f"the expression has {len(names)} parameters ({', '.join(names[:MAX_PARAMS])}, …); "
                               f"at most {MAX_PARAMS}")
    return {name: _finite(given.get(name, PARAM_DEFAULT), f"parameter {name}", InvalidParameter) for name in names}


def get_wall(spec: dict):
    """The :class:`~coinwall.forward.wall.Wall` a request names: ``case``, ``upload`` or ``expression``."""
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.wall import Wall

    if spec.get("case"):
        with field("case"):
            from coinwall.cases.catalog import get_case

            name = str(spec["case"])
            key = ("case", name)
            return _WALLS.get(key) or _remember(key, get_case(name).wall())
    if spec.get("upload"):
        key = ("upload", str(spec["upload"]))
        if key in _WALLS:
            return _WALLS[key]
        if spec.get("upload_bytes") is None:
            raise MissingUpload(spec["upload"])
        with field("upload"):
            return _remember(key, _read_upload(spec.get("upload_name", ""), spec["upload_bytes"]))
    text = spec.get("expression")
    with field("wall"):
        if not isinstance(text, str) or not text.strip():
            raise InvalidWall("the wall is empty; type an expression in t, e.g. 1 + 0.1*cos(3*t)")
    with field("params"):
        params = _params(spec)
    key = ("expression", text, tuple(sorted((k, float(v)) for k, v in params.items())))
    if key in _WALLS:
        return _WALLS[key]
    with field("wall"):
        # never formats.load_wall: it would open a file whose name a request typed
        return _remember(key, Wall.from_expression(text, params))


def _read_upload(name: str, data: bytes):
    """A wall from uploaded bytes: .csv/.json wall samples, or a .svg/.dxf drawing (its support function)."""
    from coinwall.forward.errors import InvalidWall
    from coinwall.forward.formats import load_outline, load_wall_file
    from coinwall.forward.wall import Wall

    ext = os.path.splitext(str(name))[1].lower()
    if ext not in _UPLOAD_KINDS:
        raise InvalidWall(f"upload {name!r}: coinwall reads walls from .csv/.json and drawings from .svg/.dxf, "
                          f"got {ext or 'no extension'!r}")
    with tempfile.TemporaryDirectory(prefix="coinwall-explore-") as folder:
        path = os.path.join(folder, "upload" + ext)  # our own name: the client's never reaches the file system
        with open(path, "wb") as stream:
            stream.write(data)
        if ext in (".csv", ".json"):
            return load_wall_file(path)  # the readers' own size, nesting and sample limits apply
        outline, _ = load_outline(path)
    theta = np.linspace(0.0, 2 * math.pi, 4096, endpoint=False)
    return Wall.from_samples(theta, outline.support(theta))  # the drawing's wall at b0 = 0


def upload(request: dict) -> dict:
    """Read an uploaded wall and describe it like :func:`wall_info` (plus the id the page refers to it by)."""
    digest = hashlib.sha256(request["upload_bytes"]).hexdigest()[:16]
    spec = {"upload": digest, "upload_name": request.get("upload_name", ""), "upload_bytes": request["upload_bytes"]}
    out = wall_info(spec)
    out["upload"] = digest
    return out


def cases(request: dict) -> dict:
    """The catalog cases that have a wall (the case picker)."""
    from coinwall.cases.catalog import all_cases

    out = [{"name": c.name, "title": c.title, "b0": c.b0, "H": c.H, "expression": c.expression,
            "params": dict(c.params)} for c in all_cases().values() if c.make_wall is not None]
    return {"cases": out, "default": CASE_DEFAULT}


def _bc_text(wall, result) -> str:
    """b_c at its precision: the shortest decimal within its certified tolerance (`coinwall critical`'s rule),
    so the coin's b_c = −1/100 prints as -0.01, not -0.0099999999999998."""
    from coinwall.forward.display import format_number, format_within
    from coinwall.inverse.tolerances import OFFSET_TOLERANCE

    if not math.isfinite(result.b_c):
        return "inf"
    fine = OFFSET_TOLERANCE * max(1.0, wall.scale)
    if result.lower is not None:  # data: the certified (or confidence) interval, as `coinwall critical` prints it
        kind = "95% confidence interval" if wall.sample_data.sd is not None else "certified in"
        return (f"{format_number(result.b_c, fine, 6)}, {kind} [{format_number(result.lower, fine, 6)}, "
                f"{format_number(result.upper, fine, 6)}]")
    return format_within(result.b_c, result.b_c_tolerance)


def _angles_text(result) -> str:
    """Where b + b'' is smallest, as `coinwall critical` prints it (the same list, the same digits)."""
    from coinwall.inverse.critical import format_critical_angles

    angles, spread = format_critical_angles(result.angles, result.angle_errors)
    return f"θ = {angles}" + (f" (each {spread})" if spread else "")


def _round(value: float, digits: int = 2) -> float:
    """``value`` to ``digits`` significant digits (a starting H the reader can read)."""
    if value == 0 or not math.isfinite(value):
        return value
    return round(value, digits - 1 - math.floor(math.log10(abs(value))))


def wall_info(spec: dict) -> dict:
    """The wall's critical offset (number and text), its parameters, the slider range, b0 and H to start at.

    A new wall starts at b0 = 0 (the body whose support function the wall is: a drawing comes back at its
    own size) unless ``spec["b0"]`` is a number it keeps (a case's b0, or the page's b0 while a parameter
    moves); b0 is raised above −min b (where the centre of mass would leave the body) if it must.  The
    slider spans b0 and b_c with a margin of the wall's size, and H is 1.5 times the body's largest
    width at that b0, so the body turns freely between the walls whatever the drawing's units.
    """
    from coinwall.inverse import critical_offset

    wall = get_wall(spec)
    with field(spec.get("field", "wall")):
        result = critical_offset(wall)
        values = wall(np.linspace(0.0, 2 * math.pi, 720, endpoint=False))
        if not np.all(np.isfinite(values)):
            from coinwall.forward.errors import InvalidWall

            raise InvalidWall(f"wall {wall.description!r} is not finite at every angle")
    lo_b, hi_b = float(values.min()), float(values.max())
    size = max(abs(hi_b), abs(lo_b), 1e-9)  # the wall's scale: the drawing's units
    floor = -lo_b + 0.01 * size  # below it the centre of mass leaves the body
    start = spec.get("b0")
    if isinstance(start, bool) or not isinstance(start, (int, float)) or not math.isfinite(start) or start < floor:
        start = 0.0 if floor < 0 else floor + 0.2 * size
    start = float(start)
    bc = result.b_c if math.isfinite(result.b_c) and result.b_c > floor - size else start
    low = max(floor, min(start, bc) - 0.3 * size)
    high = max(start, bc) + 0.5 * size
    widths = 2 * start + values + np.roll(values, -values.size // 2)
    H = _round(1.5 * float(widths.max()))
    out = {"description": wall.description, "b_c": json_number(result.b_c, 12), "b_c_text": _bc_text(wall, result),
           "b_c_infinite": not math.isfinite(result.b_c), "b_c_tolerance": json_number(result.b_c_tolerance, 12),
           "b_c_lower": json_number(result.lower, 12) if result.lower is not None else None,
           "b_c_upper": json_number(result.upper, 12) if result.upper is not None else None,
           "critical_angles": _list(result.angles), "critical_angle_errors": [float(e) for e in result.angle_errors],
           "critical_angles_text": _angles_text(result), "min": lo_b, "max": hi_b, "scale": wall.scale,
           "range": [low, high], "b0": start, "H": H, "sampled": wall.samples is not None, "params": None}
    if not spec.get("case") and not spec.get("upload"):
        out["params"] = [[name, value] for name, value in _params(spec).items()]
    return out


def _solve(spec: dict, points: int = LIVE_POINTS):
    from coinwall.inverse import solve_body

    wall = get_wall(spec)
    with field("b0"):
        return wall, solve_body(wall, spec.get("b0"), points=points)


def _path(outline) -> str:
    """The outline as an SVG path in body coordinates (y up: the page flips it), its exact cubic segments."""
    nodes, controls = outline.nodes, outline.controls
    n = len(nodes)
    # one C-level %-formatting of all numbers (per-number f-strings took a quarter of the live request)
    rows = np.concatenate([controls.reshape(n, 4), np.roll(nodes, -1, axis=0)], axis=1).ravel()
    return f"M{nodes[0, 0]:.6g} {nodes[0, 1]:.6g}" + ("C%.6g %.6g %.6g %.6g %.6g %.6g" * n) % tuple(rows) + "Z"


# the discrete curvature of the sampled walls seen last, at b0 = 0 (it moves with b0 as a whole): (wall, dict)
_CURVATURES: dict = {}


def _data_curvature(solved) -> dict | None:
    """A sampled wall's radius of curvature as data, for the ρ curve: the discrete ρ of the samples with the
    interval their rounding allows, as ``coinwall solve -o body.png`` draws it
    (:func:`coinwall.inverse.export.figure.sampled_curvature`, i.e. :func:`coinwall.inverse.discrete.discrete_support`:
    no interpolant is differentiated), ``low``/``high``/``value`` at ``theta`` plus b0, and the certified
    interval of b_c.  More than :data:`CURVATURE_POINTS` samples go as per-bin bounds (``binned``).  None for a
    formula wall."""
    from coinwall.inverse.export.figure import sampled_curvature

    wall = solved.wall
    if wall.samples is None:
        return None
    cached = _CURVATURES.get(id(wall))
    if cached is None or cached[0] is not wall:
        theta, rho, tolerance = sampled_curvature(solved)
        rho = rho - solved.b0  # kept at b0 = 0
        low, high, value = rho - tolerance, rho + tolerance, rho
        binned = theta.size > CURVATURE_POINTS
        if binned:  # the bounds of the bounds in each bin: still an interval that holds every sample in it
            edges = np.linspace(0.0, 2 * math.pi, CURVATURE_POINTS + 1)
            starts = np.unique(np.searchsorted(theta, edges[:-1]))
            starts = starts[starts < theta.size]
            low, high = np.minimum.reduceat(low, starts), np.maximum.reduceat(high, starts)
            value = None
            theta = theta[starts]
        if len(_CURVATURES) >= _MAX_WALLS:
            _CURVATURES.pop(next(iter(_CURVATURES)))
        cached = _CURVATURES[id(wall)] = (wall, {"theta": theta, "low": low, "high": high, "value": value,
                                                 "samples": int(wall.samples[0].size), "binned": binned})
    data = cached[1]
    shift = solved.b0
    return {"theta": _list(data["theta"], 6), "low": _list(data["low"] + shift), "high": _list(data["high"] + shift),
            "value": None if data["value"] is None else _list(data["value"] + shift), "samples": data["samples"],
            "binned": data["binned"], "b_c_lower": json_number(solved.b_c_lower, 12),
            "b_c_upper": json_number(solved.b_c_upper, 12)}


def body(spec: dict) -> dict:
    """The live body: outline path, centre of mass, corners, regime, and the three curves over θ.

    For a formula wall ``rho`` is ``b0 + b + b''`` from its exact derivatives; for a sampled wall (a CSV, an
    uploaded drawing) ``rho`` is None and ``rho_data`` holds the discrete curvature of the samples with its
    intervals (:func:`_data_curvature`)."""
    import time

    started = time.perf_counter()
    wall, solved = _solve(spec)
    theta = np.linspace(0.0, 2 * math.pi, _PLOT_ANGLES)
    b, _, b2 = wall.derivatives(theta)
    corners = []
    for c in solved.corners:
        x, y = c.distance * math.cos(c.direction), c.distance * math.sin(c.direction)
        corners.append({"x": x, "y": y, "direction": c.direction, "half_width": c.half_width,
                        "distance": c.distance, "max_deficit": c.max_deficit, "window": list(c.window)})
    extent = float(np.max(np.hypot(solved.x, solved.y)))
    # a wall given as data: every regime the data allow, every critical angle, the certified band of the outline
    # (what `coinwall solve` reports for the same data)
    data = {"regimes": list(solved.regimes or (solved.regime,)), "regime_decided": solved.regime_decided,
            "critical_angles": _list(solved.critical_angles),
            "outline_tolerance": json_number(solved.outline_tolerance, 12),
            "possible_corners": len(solved.possible_corners)}
    return {**data, "b0": solved.b0, "b_c": json_number(solved.b_c, 12), "regime": solved.regime,
            "points": int(solved.x.size),
            "path": _path(solved.outline), "extent": extent, "corners": corners,
            "area": solved.area, "perimeter": solved.perimeter,
            "max_wall_error": json_number(solved.max_wall_error, 12),
            "warnings": list(solved.warnings), "notes": list(solved.notes),
            "theta": _list(theta, 5), "wall": _list(solved.b0 + b), "own_wall": _list(solved.outline.support(theta)),
            "rho": None if wall.samples is not None else _list(solved.b0 + b + b2), "rho_data": _data_curvature(solved),
            "solve_ms": 1e3 * solved.seconds,
            "server_ms": 1e3 * (time.perf_counter() - started)}


def realize(spec: dict) -> dict:
    """κ of the uniform body, κ_max, and whether any mass distribution gives κ = 1 (inverse/realizability.py)."""
    from coinwall.inverse import realizability

    _, solved = _solve(spec)
    r = realizability(solved)
    return {"b0": solved.b0, "kappa_uniform": json_number(r.kappa_uniform, 12),
            "kappa_max": json_number(r.kappa_max, 12),
            "centroid_offset": json_number(r.centroid_offset, 12), "realizable": r.realizable,
            "uniform_consistent": r.uniform_consistent}


def export(spec: dict) -> dict:
    """The bytes of the body on the screen as SVG, DXF or JSON (``coinwall export``'s writers), with
    ``kappa``/``units`` as on the command line."""
    from coinwall.forward.errors import InvalidArgument
    from coinwall.inverse.export import EXPORTERS, ExportOptions

    with field("format"):
        ext = "." + str(spec.get("format", "")).lower().lstrip(".")
        if ext not in (".svg", ".dxf", ".json"):
            raise InvalidArgument(f"`format` must be svg, dxf or json, got {spec.get('format')!r}")
    with field("kappa"):
        kappa = spec.get("kappa")
        kappa = None if kappa in (None, "") else number(spec, "kappa")
        units = spec.get("units") or None
        options = ExportOptions(kappa=kappa, units=units) if kappa is not None else ExportOptions()
    _, solved = _solve(spec)
    if kappa is not None and ext != ".json" and not spec.get("allow_unrealizable"):
        from coinwall.inverse import realizability

        physical = realizability(solved)
        if not physical.realizable:  # the rule of `coinwall solve --kappa` (and its --allow-unrealizable)
            with field("kappa"):
                raise InvalidArgument(f"no mass distribution inside this body gives it κ = 1 (κ_max = "
                                      f"{physical.kappa_max:.4g} κ), so a part cut at this size would not have this "
                                      "wall; choose another b0 or tick 'draw anyway' (--allow-unrealizable)")
    stream = io.BytesIO()
    EXPORTERS[ext].write(solved, stream, options)
    return {"format": ext[1:], "bytes": stream.getvalue(), "filename": f"body{ext}"}


def _table(spec):
    from coinwall.forward.dynamics.billiard.table import Billiard

    wall = get_wall(spec)
    with field("H"):
        H = number(spec, "H")
    with field("b0"):
        b0 = number(spec, "b0")
    with field("H"):
        return Billiard(wall, H, b0)


def beam(spec: dict) -> dict:
    """A beam of trajectories from a clicked point (θ, η), a fan of directions; the central orbit's section.

    Returns the collisions of every trajectory (the page moves the points along straight flights
    between them) and the bottom-wall Poincaré section (θ_c, φ_c) of the central orbit, followed for
    ``section_collisions`` collisions.
    """
    from coinwall.forward.dynamics.analysis.poincare import poincare_section
    from coinwall.forward.dynamics.billiard.table import ensemble
    from coinwall.forward.validation import check_count, check_range

    table = _table(spec)
    with field("beam"):
        n = check_count("rays", spec.get("rays", 200), minimum=1, maximum=MAX_BEAM)
        collisions = check_count("collisions", spec.get("collisions", 30), minimum=1, maximum=MAX_BEAM_COLLISIONS)
        spread = check_range("spread", number(spec, "spread", 0.02), 0.0, math.pi)
        direction = number(spec, "direction", 1.0)
        theta, eta = number(spec, "theta"), number(spec, "eta")
        angles = direction + (np.linspace(-spread, spread, n) if n > 1 else np.zeros(1))
        angles = np.concatenate([[direction], angles[:-1]]) if n > 1 else angles  # orbit 0: the centre ray
        states = np.column_stack([np.full(n, theta), np.full(n, eta), np.cos(angles), np.sin(angles)])
        runs = ensemble(table, states, collisions)
        extra = check_count("section_collisions", spec.get("section_collisions", 4000), minimum=1,
                            maximum=MAX_SECTION_COLLISIONS)
        section = poincare_section(table, states=states[:1], collisions=extra)
    rays = [{"t": _list(r.time, 5), "theta": _list(r.theta, 5), "eta": _list(r.eta, 5),
             "vt": _list(r.v_theta, 5), "ve": _list(r.v_eta, 5)} for r in runs]
    grid = np.linspace(0.0, 2 * math.pi, _PLOT_ANGLES)
    return {"start": states.tolist(), "rays": rays, "lower": _list(table.lower(grid)), "upper": _list(table.upper(grid)),
            "theta": _list(grid, 5), "section": {"theta": _list(section.theta, 5), "phi": _list(section.phi, 5)},
            "H": table.H, "b0": table.b0, "gap_min": table.gap_min}


def table(spec: dict) -> dict:
    """The strip's two walls over one period for the billiard pane."""
    tb = _table(spec)
    grid = np.linspace(0.0, 2 * math.pi, _PLOT_ANGLES)
    return {"theta": _list(grid, 5), "lower": _list(tb.lower(grid)), "upper": _list(tb.upper(grid)),
            "H": tb.H, "b0": tb.b0, "gap_min": tb.gap_min, "gap_max": tb.gap_max}


#: job name -> function (the worker runs only these)
JOBS = {"wall": wall_info, "body": body, "realize": realize, "export": export, "upload": upload, "cases": cases,
        "beam": beam, "table": table}
