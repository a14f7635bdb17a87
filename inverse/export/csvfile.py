"""CSV export: one row per outline node with x, y, α, R and curvature K (inf at corners)."""

import io

import numpy as np

__all__ = ["EXTENSION", "write"]

EXTENSION = ".csv"


def write(body, stream):
    text = io.StringIO()
    text.write(f"# coinwall body: wall {body.wall.description!r}, b0={body.b0!r}, regime={body.regime}, "
               f"units of kappa\n")
    text.write("x,y,alpha,R,K\n")
    data = np.column_stack([body.x, body.y, body.alpha, body.R, body.K])
    np.savetxt(text, data, delimiter=",", fmt="%.17g")
    stream.write(text.getvalue().encode())
