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


def _rows(values, depth: int) -> str:
    """A nested list of numbers as JSON, one outer item per line (json's C encoder: ``indent`` would make
    ``json`` use its Python encoder, ten times slower on an outline of 10⁵ points)."""
    text = json.dumps(values, allow_nan=False)
    close, open_ = "]" * depth, "[" * depth
    return text.replace(f"{close}, {open_}", f"{close},\n  {open_}")


def write(body, stream, options=None):
    """Write the JSON to a binary ``stream`` (always in units of κ: ``options`` do not apply).

    The document is :func:`body_document`'s, with the summary indented and the outline and the controls one
    node per line.
    """
    doc = body_document(body)
    arrays = {OUTLINE_KEY: 1, CONTROLS_KEY: 2}  # the nesting depth of one node's entry
    marks = {key: f"@coinwall-{key}@" for key in arrays}
    text = json.dumps({key: marks.get(key, value) for key, value in doc.items()}, indent=1, allow_nan=False)
    for key, depth in arrays.items():
        text = text.replace(json.dumps(marks[key]), _rows(doc[key], depth), 1)
    stream.write(text.encode())
