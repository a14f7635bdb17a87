"""``coinwall explore``: the body, its wall and its billiard, live in a browser (docs/explore.md).

A Starlette application served by uvicorn on 127.0.0.1; the page (``static/``) is plain HTML,
JavaScript and SVG shipped in the package (no CDN: it works offline).  Nothing here is imported by
``import coinwall``: the web framework is an optional extra (``pip install -e ".[explore]"``).
"""

from .server import DEFAULT_HOST, DEFAULT_PORT, serve

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "serve"]
