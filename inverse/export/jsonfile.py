"""JSON export: the summary plus the outline (nodes and Bézier control points)."""

import json

__all__ = ["EXTENSION", "write", "body_document"]

EXTENSION = ".json"


def body_document(body) -> dict:
    """The JSON document for ``body``: summary, outline ``[[x, y], …]`` and ``controls``."""
    doc = body.summary()
    doc["outline"] = body.points.tolist()
    doc["controls"] = body.outline.controls.tolist()
    doc["units"] = "radius of gyration (kappa)"
    return doc


def write(body, stream):
    stream.write(json.dumps(body_document(body), indent=1, allow_nan=False).encode())
