"""Wall files: ``.csv`` samples ``theta,b`` and ``.json`` Fourier coefficients ``{"a0", "cos", "sin"}``."""

from __future__ import annotations

import json

from ..errors import InvalidWall

__all__ = ["WALL_FORMATS", "load_wall_file"]

WALL_FORMATS = (".csv", ".json")


def load_wall_file(path: str):
    """A wall from a file: ``.csv`` (theta,b samples) or ``.json`` (Fourier coefficients a0, cos, sin)."""
    import numpy as np

    from ..wall import Wall

    try:
        if path.lower().endswith(".csv"):
            data = np.genfromtxt(path, delimiter=",", comments="#", names=None, invalid_raise=True)
            if data.ndim != 2 or data.shape[1] < 2:
                raise InvalidWall(f"wall file {path!r}: need two columns theta,b")
            data = data[~np.all(np.isnan(data), axis=1)] if np.isnan(data[0]).all() else data
            if np.isnan(data[0]).any():  # a header row
                data = data[1:]
            return Wall.from_samples(data[:, 0], data[:, 1])
        with open(path, encoding="utf-8") as fh:
            doc = json.load(fh)
        if not isinstance(doc, dict):
            raise InvalidWall(f"wall file {path!r}: expected an object with a0, cos, sin")
        unknown = set(doc) - {"a0", "cos", "sin"}
        if unknown:
            raise InvalidWall(f"wall file {path!r}: unknown keys {sorted(unknown)}; expected a0, cos, sin")
        return Wall.from_fourier(doc.get("a0", 0.0), doc.get("cos", []), doc.get("sin", []))
    except OSError as exc:
        raise InvalidWall(f"wall file {path!r} is not readable: {exc.strerror}") from None
    except (ValueError, TypeError) as exc:
        if isinstance(exc, InvalidWall):
            raise
        raise InvalidWall(f"wall file {path!r} is not readable: {exc}") from None
