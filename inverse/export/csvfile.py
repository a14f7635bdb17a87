"""CSV export: one row per outline node with x, y, α, R and curvature K (inf at corners).

The header line and the columns are those :mod:`coinwall.forward.formats.points` reads back.
"""

import io

import numpy as np

from coinwall.forward.formats.points import COLUMNS, HEADER_PREFIX

__all__ = ["EXTENSION", "write"]

EXTENSION = ".csv"


def write(body, stream, options=None):
    """Write the CSV to a binary ``stream`` (always in units of κ: ``options`` do not apply)."""
    text = io.StringIO()
    text.write(f"{HEADER_PREFIX}: wall {body.wall.description!r}, b0={body.b0!r}, regime={body.regime}, "
               f"units of kappa\n")
    text.write(",".join(COLUMNS) + "\n")
    data = np.column_stack([body.x, body.y, body.alpha, body.R, body.K])
    np.savetxt(text, data, delimiter=",", fmt="%.17g")
    stream.write(text.getvalue().encode())
