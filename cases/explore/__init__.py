"""``coinwall explore``: the body, its wall and its billiard, live in a browser (docs/explore.md).

A Starlette application served by uvicorn on 127.0.0.1; the page (``static/``) is plain HTML,
JavaScript and SVG shipped in the package (no CDN: it works offline).  Nothing here is imported by
``import coinwall``: the web framework is an optional extra (``pip install -e ".[explore]"``).
"""

from coinwall._lazy import attach_stub

# the public names and the modules that define them are in __init__.pyi; each is imported on first use
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
