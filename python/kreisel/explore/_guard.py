"""The server answers only its own page on the loopback address (against DNS rebinding: a
foreign site whose name resolves to 127.0.0.1 sends its own Host and Origin), and reads at
most ``max_body`` bytes of a request."""

from __future__ import annotations

import json


def _refuse(status: int, message: str):
    body = json.dumps({"error": message}).encode()
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]

    async def respond(send):
        await send({"type": "http.response.start", "status": status, "headers": headers})
        await send({"type": "http.response.body", "body": body})

    return respond


class LoopbackGuard:
    """ASGI middleware: refuses (403) a request whose Host is not ``127.0.0.1:PORT`` or
    ``localhost:PORT``, or whose Origin, when it has one, is not ``http://`` one of those;
    refuses (413) a body longer than ``max_body`` bytes by its Content-Length, and raises
    :class:`BodyTooLarge` from ``receive`` when a body sent without one passes the limit."""

    def __init__(self, app, port: int, max_body: int) -> None:
        self.app = app
        self.hosts = {f"127.0.0.1:{port}", f"localhost:{port}"}
        self.origins = {f"http://{h}" for h in self.hosts}
        self.max_body = max_body

    async def __call__(self, scope, receive, send):
        if scope["type"] not in ("http", "websocket"):
            return await self.app(scope, receive, send)
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope["headers"]}
        host = headers.get("host")
        if host not in self.hosts:
            return await _refuse(
                403, f"Host {host!r} is not served here: only {' or '.join(sorted(self.hosts))}"
            )(send)
        origin = headers.get("origin")
        if origin is not None and origin not in self.origins:
            return await _refuse(
                403,
                f"Origin {origin!r} is not served here: only {' or '.join(sorted(self.origins))}",
            )(send)
        length = headers.get("content-length")
        too_big = (
            f"the request body is larger than {self.max_body} bytes, the most one request may send"
        )
        if length is not None and (not length.isdigit() or int(length) > self.max_body):
            return await _refuse(413, too_big)(send)
        seen = 0

        async def capped_receive():
            nonlocal seen
            message = await receive()
            if message["type"] == "http.request":
                seen += len(message.get("body", b""))
                if seen > self.max_body:
                    raise BodyTooLarge(too_big)
            return message

        # the application reads the body: it answers BodyTooLarge with 413 (see _app._json)
        return await self.app(scope, capped_receive, send)


class BodyTooLarge(Exception):
    """A streamed request body passed the limit."""
