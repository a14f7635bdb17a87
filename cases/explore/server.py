"""Run the explorer: uvicorn on a local address, the browser opened on the page, Ctrl-C stops it."""

from __future__ import annotations

import socket
import threading

from coinwall.forward.errors import InvalidArgument

__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "check_port", "serve"]

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8765


def check_port(host: str, port: int) -> int:
    """``port`` if it is a valid port that is free on ``host`` (0: any free port, chosen here)."""
    if not 0 <= port <= 65535:
        raise InvalidArgument(f"`port` must be 0 to 65535, got {port}")
    try:
        family = socket.AF_INET6 if ":" in host else socket.AF_INET
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            probe.bind((host, port))
            return probe.getsockname()[1]
    except OSError as exc:
        raise InvalidArgument(f"cannot listen on {host}:{port}: {exc.strerror or exc}; choose another `port` "
                              "(0 picks a free one) or `host`") from None


def _loopback(host: str) -> bool:
    import ipaddress

    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return host == "localhost"


def serve(host: str = DEFAULT_HOST, port: int = DEFAULT_PORT, *, open_browser: bool = True, log_level: str = "warning",
          ready=None) -> None:
    """Serve the explorer until Ctrl-C (or SIGTERM); returns when the server and its workers have stopped.

    Parameters
    ----------
    host, port : str, int
        Where to listen (127.0.0.1: this machine only; port 0: a free port).
    open_browser : bool
        Open the page in the default browser once the server listens.
    log_level : str
        uvicorn's log level ("warning": one line per problem, no access log).
    ready : callable, optional
        Called with the page's URL once the server listens.
    """
    import uvicorn

    from .app import create_app

    port = check_port(host, port)
    shown = f"[{host}]" if ":" in host else host
    url = f"http://{shown}:{port}/"
    app = create_app(host=host)

    class Server(uvicorn.Server):
        def handle_exit(self, sig, frame):
            # stop the computations first: a request waiting for a long job (a beam) then ends at once with
            # a message, instead of being cancelled by uvicorn after its grace period (with a traceback); a
            # request whose body is being read ends too (app.state.stopping: a 503)
            for worker in getattr(app.state, "workers", {}).values():
                worker.close()
            stopping, loop = getattr(app.state, "stopping", None), getattr(app.state, "loop", None)
            if stopping is not None and loop is not None:
                loop.call_soon_threadsafe(stopping.set)
            super().handle_exit(sig, frame)

    config = uvicorn.Config(app, host=host, port=port, log_level=log_level, access_log=False, lifespan="on",
                            timeout_graceful_shutdown=3)
    server = Server(config)

    def announce():  # once uvicorn says it is listening: the URL, then the browser
        import time

        while not server.started and not server.should_exit:
            time.sleep(0.05)
        if server.started:
            print(f"coinwall explore: serving {url} (Ctrl-C stops it)", flush=True)
            if not _loopback(host):
                print(f"coinwall explore: note: listening on {host}: anyone who can reach this machine can use the "
                      "explorer (it has no login)", flush=True)
            if ready is not None:
                ready(url)
            if open_browser:
                import webbrowser

                webbrowser.open(url)

    threading.Thread(target=announce, name="coinwall-explore-announce", daemon=True).start()
    try:
        server.run()
    except KeyboardInterrupt:
        # uvicorn has shut down (the workers are stopped by the app's lifespan) and then re-raises the SIGINT
        # it caught, so that a plain Python program would end as interrupted: here Ctrl-C is how one stops it
        pass
    print("coinwall explore: stopped", flush=True)
