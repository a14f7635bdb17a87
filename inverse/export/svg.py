"""SVG export: the outline as a closed path of the solver's own cubic Béziers (exact, to scale).

The viewBox is in body units (radius of gyration κ); y is flipped so the
picture has the usual mathematical orientation.  The centre of mass is marked.
"""

import numpy as np

__all__ = ["EXTENSION", "write", "svg_text"]

EXTENSION = ".svg"


def svg_text(body, size_px: int = 400) -> str:
    nodes, controls = body.outline.nodes, body.outline.controls
    extent = float(np.max(np.abs(np.vstack([nodes, controls.reshape(-1, 2)])))) or 1.0
    pad = 0.08 * extent
    half = extent + pad

    def xy(p):
        return f"{p[0]:.10g},{-p[1]:.10g}"

    parts = [f"M {xy(nodes[0])}"]
    n = len(nodes)
    for i in range(n):
        parts.append(f"C {xy(controls[i, 0])} {xy(controls[i, 1])} {xy(nodes[(i + 1) % n])}")
    path = " ".join(parts) + " Z"
    stroke = 2 * half / size_px
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{size_px}" height="{size_px}" '
        f'viewBox="{-half:.10g} {-half:.10g} {2 * half:.10g} {2 * half:.10g}">\n'
        f"<title>coinwall body: b0={body.b0:g}, regime {body.regime} (units of kappa)</title>\n"
        f'<path d="{path}" fill="#dde6f0" stroke="#123" stroke-width="{stroke:.6g}"/>\n'
        f'<circle cx="0" cy="0" r="{3 * stroke:.6g}" fill="#c00"><title>centre of mass</title></circle>\n'
        "</svg>\n")


def write(body, stream):
    stream.write(svg_text(body).encode())
