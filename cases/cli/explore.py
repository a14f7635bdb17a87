"""``coinwall explore``: the body, its wall and its billiard, live in a browser (a local web server)."""

from __future__ import annotations

from .common import add_command, count

__all__ = ["register"]

_DESCRIPTION = """\
Start a local web server and open the explorer in the browser: type a wall (or pick a case, or
upload a CSV wall or an SVG/DXF drawing), drag b0 and watch the body change, pass b_c and watch
corners appear, download the body (SVG, DXF, JSON), and click the billiard table to send a beam of
trajectories, fill a Poincaré section and watch the rigid body bounce between the walls.  The page
is served from the package and works offline.  Needs the optional extra: pip install "coinwall[explore]".
Ctrl-C stops the server."""

_EXAMPLE = """\
coinwall explore
coinwall explore --port 8800 --no-browser"""


def register(subparsers):
    """Add the ``explore`` subcommand."""
    parser = add_command(subparsers, "explore", help="the explorer: body, wall and billiard live in a browser",
                         description=_DESCRIPTION, example=_EXAMPLE)
    parser.add_argument("--port", type=count, default=8765, help="port to listen on (default 8765; 0: any free port)")
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to listen on (default 127.0.0.1: this machine only; the explorer has no "
                             "login, so think twice before 0.0.0.0)")
    parser.add_argument("--no-browser", action="store_true", help="do not open the browser (print the URL only)")
    parser.set_defaults(run=run)


def run(args):
    """Serve until Ctrl-C; 0 when stopped, 130 if interrupted before the server was up."""
    from coinwall.forward.errors import InvalidArgument

    try:
        import starlette  # noqa: F401 - only to say what is missing before anything starts
        import uvicorn  # noqa: F401

        from coinwall.cases.explore import serve
    except ImportError as exc:
        raise InvalidArgument(f"the explorer needs the optional packages starlette and uvicorn ({exc.name} is "
                              "missing): pip install \"coinwall[explore]\"") from None
    serve(args.host, args.port, open_browser=not args.no_browser)
    return 0
