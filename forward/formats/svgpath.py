"""SVG path data: the scanner and flattener of ``d`` attributes, and the checked numbers every SVG reader uses.

Path data is read as the SVG 1.1 specification (section 8.3) writes it: commands ``MLHVCSQTAZ`` (lower
case relative), implicit repeats, arc flags without separators.  Béziers and arcs are flattened on the
exact geometry (arcs by the endpoint-to-centre conversion, implementation notes F.6.5) with the chord
error of :mod:`.geometry`.  A path must start with a moveto; a drawing holds at most ``MAX_SEGMENTS``
segments (refused before any number is read when its commands alone are too many) and the points of its
:class:`~.geometry.PointBudget`.  Every number is finite and at most :data:`~.geometry.MAX_COORDINATE`.
"""

from __future__ import annotations

import math
import re

import numpy as np

from ..angles import TWO_PI
from ..errors import InvalidOutline
from .geometry import MAX_COORDINATE, PointBudget, cubic_points, ellipse_points

__all__ = ["MAX_SEGMENTS", "NUMBER", "WSP", "checked_number", "svg_numbers", "svg_path"]

#: path segments per drawing at most (parsing is ~1 µs a token in Python; flattening and the hull follow)
MAX_SEGMENTS = 200_000

#: SVG's number: ASCII digits only (``\d`` would take other scripts' digits, which float() reads as well)
NUMBER = r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?"
#: SVG's white space (wsp): space, tab, CR, LF; not the Unicode spaces ``\s`` takes
WSP = "[ \t\r\n]"


def checked_number(value: float, text) -> float:
    """``value`` if finite and at most MAX_COORDINATE in absolute value (``text`` names it in the message)."""
    if not abs(value) <= MAX_COORDINATE:
        reason = "is not finite" if not math.isfinite(value) else f"is larger than {MAX_COORDINATE:g} in absolute value"
        raise InvalidOutline(f"the number {text!r} {reason}")
    return value


def svg_numbers(text):
    return [checked_number(float(v), v) for v in re.findall(NUMBER, text or "")]


_NUMBER_AT = re.compile(NUMBER)
_COMMANDS = re.compile(r"[MLHVCSQTAZmlhvcsqtaz]")


class _PathScanner:
    """Tokens of SVG path data; arc flags may be written without separators ("a1 1 0 01.5.5")."""

    def __init__(self, text):
        self.text, self.pos = text, 0

    def _skip(self):
        while self.pos < len(self.text) and self.text[self.pos] in " \t\r\n,":
            self.pos += 1

    def command(self):
        self._skip()
        if self.pos < len(self.text) and self.text[self.pos].isalpha():
            self.pos += 1
            return self.text[self.pos - 1]
        return None

    def at_number(self):
        self._skip()
        return self.pos < len(self.text) and self.text[self.pos] in "+-.0123456789"

    def number(self):
        self._skip()
        m = _NUMBER_AT.match(self.text, self.pos)
        if not m:
            raise InvalidOutline(f"SVG path data is malformed near {self.text[self.pos:self.pos + 20]!r}")
        self.pos = m.end()
        return checked_number(float(m.group()), m.group())

    def flag(self):
        self._skip()
        if self.pos < len(self.text) and self.text[self.pos] in "01":
            self.pos += 1
            return self.text[self.pos - 1] == "1"
        raise InvalidOutline(f"SVG path data: arc flag expected near {self.text[self.pos:self.pos + 20]!r}")


def _arc_points(p0, rx, ry, phi_deg, large, sweep, p1, size):
    """SVG elliptical arc (endpoint parametrisation, SVG 1.1 implementation notes F.6.5)."""
    if np.allclose(p0, p1):
        return np.empty((0, 2))
    rx, ry = abs(rx), abs(ry)
    if rx == 0 or ry == 0:
        return p1[None, :]
    phi = math.radians(phi_deg % 360)
    c, s = math.cos(phi), math.sin(phi)
    dx, dy = (p0 - p1) / 2
    x1, y1 = c * dx + s * dy, -s * dx + c * dy
    lam = x1 * x1 / (rx * rx) + y1 * y1 / (ry * ry)
    if lam > 1:
        rx, ry = rx * math.sqrt(lam), ry * math.sqrt(lam)
    num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1
    den = rx * rx * y1 * y1 + ry * ry * x1 * x1
    if den == 0:  # the end points coincide to within underflow: nothing to draw
        return p1[None, :]
    coef = math.sqrt(max(num / den, 0.0)) * (-1 if large == sweep else 1)
    cxp, cyp = coef * rx * y1 / ry, -coef * ry * x1 / rx
    centre = np.array([c * cxp - s * cyp, s * cxp + c * cyp]) + (p0 + p1) / 2
    t1 = math.atan2((y1 - cyp) / ry, (x1 - cxp) / rx)
    t2 = math.atan2((-y1 - cyp) / ry, (-x1 - cxp) / rx)
    dt = (t2 - t1) % TWO_PI
    if not sweep and dt > 0:
        dt -= TWO_PI
    return ellipse_points(centre, rx, ry, phi, t1, dt, size)


def svg_path(d, budget: PointBudget | None = None):
    """Subpaths of SVG path data as (points, closed) pairs.

    ``budget`` counts segments and points across a drawing (default: a fresh one for this path); the
    path is refused as soon as it holds more than :data:`MAX_SEGMENTS` segments or the budget's points.
    """
    budget = budget if budget is not None else PointBudget("(path)")
    # commands are at most the segments: a path of far too many is refused before any number is read
    commands = len(_COMMANDS.findall(d or ""))
    if budget.segments + commands > MAX_SEGMENTS:
        raise InvalidOutline(f"SVG path data has {commands} commands; coinwall reads drawings of at most "
                             f"{MAX_SEGMENTS} segments: simplify the path")
    scan = _PathScanner(d or "")
    subpaths, current, start, pos = [], [], np.zeros(2), np.zeros(2)
    last_ctrl, last_cmd, cmd = None, "", None
    size_guess = max(1e-300, max((abs(v) for v in svg_numbers(d)), default=1.0))

    def close_subpath(closed):
        if len(current) > 1:
            subpaths.append((np.array(current), closed))

    while True:
        new = scan.command()
        if new is None:
            if not scan.at_number():
                if scan.pos < len(scan.text.strip()) and scan.text[scan.pos:].strip():
                    raise InvalidOutline(f"SVG path data is malformed near {scan.text[scan.pos:scan.pos + 20]!r}")
                break
            if cmd is None:
                raise InvalidOutline("SVG path data must start with a moveto command")
            new = {"M": "L", "m": "l"}.get(cmd, cmd)
        if cmd is None and new.upper() != "M":
            # SVG 1.1 section 8.3.2: path data must begin with a moveto; renderers draw nothing otherwise
            raise InvalidOutline(f"SVG path data must start with a moveto (M or m), got {new!r}")
        budget.segments += 1
        if budget.segments > MAX_SEGMENTS:
            raise InvalidOutline(f"SVG path data has more than {MAX_SEGMENTS} segments; coinwall reads drawings of "
                                 "at most that many: simplify the path")
        before = len(current)
        cmd = new
        rel = cmd.islower()
        up = cmd.upper()
        if up not in "MLHVCSQTAZ":
            raise InvalidOutline(f"SVG path data: unknown command {cmd!r}")
        base = pos if rel else np.zeros(2)
        if up == "Z":
            close_subpath(True)
            current, pos = [], start.copy()
            last_ctrl, last_cmd = None, "Z"
            continue
        if up == "M":
            close_subpath(False)
            pos = base + [scan.number(), scan.number()]
            start, current = pos.copy(), [pos.copy()]
            last_ctrl, last_cmd = None, "M"
            continue
        if not current:
            current = [pos.copy()]
            start = pos.copy()
        if up == "L":
            pos = base + [scan.number(), scan.number()]
            current.append(pos.copy())
            last_ctrl = None
        elif up == "H":
            pos = np.array([(pos[0] if rel else 0.0) + scan.number(), pos[1]])
            current.append(pos.copy())
            last_ctrl = None
        elif up == "V":
            pos = np.array([pos[0], (pos[1] if rel else 0.0) + scan.number()])
            current.append(pos.copy())
            last_ctrl = None
        elif up in "CS":
            if up == "C":
                c1 = base + [scan.number(), scan.number()]
            else:
                c1 = 2 * pos - last_ctrl if last_ctrl is not None and last_cmd in "CS" else pos.copy()
            c2 = base + [scan.number(), scan.number()]
            end = base + [scan.number(), scan.number()]
            current.extend(cubic_points(pos, c1, c2, end, size_guess))
            pos, last_ctrl = end, c2
        elif up in "QT":
            if up == "Q":
                q = base + [scan.number(), scan.number()]
            else:
                q = 2 * pos - last_ctrl if last_ctrl is not None and last_cmd in "QT" else pos.copy()
            end = base + [scan.number(), scan.number()]
            current.extend(cubic_points(pos, pos + 2 * (q - pos) / 3, end + 2 * (q - end) / 3, end, size_guess))
            pos, last_ctrl = end, q
        else:
            rx, ry, rot = scan.number(), scan.number(), scan.number()
            large, sweep = scan.flag(), scan.flag()
            end = base + [scan.number(), scan.number()]
            current.extend(_arc_points(pos, rx, ry, rot, large, sweep, end, size_guess))
            pos, last_ctrl = end, None
        last_cmd = up
        budget.take(len(current) - before)
    close_subpath(False)
    out = []
    for pts, closed in subpaths:
        span = float(np.ptp(pts, axis=0).max()) if len(pts) else 0.0
        if not closed and len(pts) > 2 and np.hypot(*(pts[0] - pts[-1])) <= 1e-9 * max(span, 1e-300):
            closed = True
        out.append((pts, closed))
    return out
