"""``kreisel explore``: the tops in a browser, in 3D, as they move.

A local web application: :func:`serve` starts a server on 127.0.0.1 that serves a page
(three.js for the 3D view, uPlot for the charts, both shipped in ``static/vendor``) and
computes every motion with kreisel in the server's process. The command line imports this
package only when ``kreisel explore`` runs, so ``import kreisel`` needs no web framework.
"""

from __future__ import annotations

import errno
import socket
import threading
import webbrowser
from pathlib import Path

from .._errors import ParameterError

HOST = "127.0.0.1"  # the loopback interface only, never 0.0.0.0


def bind(port: int) -> socket.socket:
    """A listening socket on 127.0.0.1:port (0: a free port)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((HOST, port))
    except OSError as e:
        sock.close()
        if e.errno == errno.EADDRINUSE:
            raise ParameterError(
                f"port = {port} is busy: another program listens on {HOST}:{port}; give "
                "another port (0: any free one)"
            ) from None
        raise ParameterError(f"port = {port} is not allowed: {HOST}:{port} {e.strerror}") from None
    sock.listen(128)
    return sock


def serve(
    port: int = 8765, *, open_browser: bool = True, store: Path | None = None, ready=None
) -> None:
    """Serves the page on http://127.0.0.1:PORT until interrupted.

    ``store`` is the folder whose sweep stores the page may open (none outside it);
    ``ready(url)`` is called once the server listens (the command line prints the address).
    Each run computes in a process of its own (:mod:`kreisel.explore._jobs`, Python's
    ``multiprocessing`` with a fork server): a script that calls ``serve`` runs it under
    ``if __name__ == "__main__":``, as every script that starts processes does.
    """
    import uvicorn

    from . import _jobs
    from ._app import create_app, missing_vendor
    from ._guard import guarded_protocol

    missing = missing_vendor()
    if missing:
        raise ParameterError(
            f"the page's JavaScript is missing ({', '.join(missing)}): run `make setup` in "
            "kreisel's source tree (npm ci --prefix web copies it into the package)"
        )
    if store is not None:
        store = Path(store)
        if not store.is_dir():
            raise ParameterError(f"store = {str(store)!r} is not allowed: it is not a folder")
    sock = bind(port)
    url = f"http://{HOST}:{sock.getsockname()[1]}/"
    app = create_app(sock.getsockname()[1], store)
    # h11 with a deadline for each request to arrive (slow headers, slow bodies: _guard)
    config = uvicorn.Config(app, log_level="warning", lifespan="off", http=guarded_protocol())
    server = uvicorn.Server(config)
    _jobs.start()  # the runs' fork server, with kreisel loaded, before the first run
    if ready is not None:
        ready(url)
    if open_browser:
        threading.Timer(0.5, webbrowser.open, args=(url,)).start()
    server.run(sockets=[sock])
