"""JSON export: the summary plus the outline (nodes and Bézier control points).

The field names are those :mod:`coinwall.forward.formats.bodyjson` reads back.  The file holds only
what the body is, so the same body always gives the same bytes: the solve's wall-clock time
(``seconds``) is left out (it is in ``coinwall solve --json``'s summary).
"""

import json

from coinwall.forward.formats.bodyjson import CONTROLS_KEY, OUTLINE_KEY, UNITS_KEY, UNITS_VALUE

__all__ = ["EXTENSION", "write", "body_document"]

EXTENSION = ".json"
# fields of Body.to_dict() that differ from run to run
_NOT_REPRODUCIBLE = ("seconds",)


def body_document(body) -> dict:
    """The JSON document for ``body``: summary, outline ``[[x, y], …]`` and ``controls``."""
    doc = body.to_dict()
    for key in _NOT_REPRODUCIBLE:
        doc.pop(key, None)
    doc[OUTLINE_KEY] = body.points.tolist()
    doc[CONTROLS_KEY] = body.outline.controls.tolist()
    doc[UNITS_KEY] = UNITS_VALUE
    return doc


def write(body, stream, options=None):
    """Write the JSON to a binary ``stream`` (always in units of κ: ``options`` do not apply)."""
    stream.write(json.dumps(body_document(body), indent=1, allow_nan=False).encode())
