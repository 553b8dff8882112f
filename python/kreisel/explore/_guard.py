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


REQUEST_TIMEOUT = 5.0  # s for a request, headers and body, to arrive


def guarded_protocol(timeout: float = REQUEST_TIMEOUT):
    """uvicorn's HTTP/1.1 protocol (h11) with a deadline: a request must arrive whole, its
    headers and its body, within ``timeout`` s of its first byte (or of the connection, for
    the first request); else the server answers 408 and closes the connection (a connection
    on which nothing came is closed with no answer: a browser may be about to use it). uvicorn
    itself only times out an idle connection between requests, so a client that sends a byte
    now and then (slow headers, a slow body) would hold its connection for ever."""
    import h11
    from uvicorn.protocols.http.h11_impl import H11Protocol

    late = _refusal(
        408, f"the request did not arrive within {timeout:g} s: the connection is closed"
    )

    class DeadlineH11Protocol(H11Protocol):
        deadline = None
        begun = False  # part of a request has come

        def _arm(self) -> None:
            if self.deadline is None:
                self.deadline = self.loop.call_later(timeout, self._too_slow)

        def _disarm(self) -> None:
            if self.deadline is not None:
                self.deadline.cancel()
                self.deadline = None
            self.begun = False

        def connection_made(self, transport) -> None:
            super().connection_made(transport)
            self._arm()

        def data_received(self, data: bytes) -> None:
            if self.conn.their_state is h11.IDLE:
                self._arm()  # the first byte of a request after an idle keep-alive
            self.begun = True
            super().data_received(data)
            if self.conn.their_state not in (h11.IDLE, h11.SEND_BODY):
                self._disarm()  # the request arrived whole (or the connection ends)

        def connection_lost(self, exc) -> None:
            self._disarm()
            super().connection_lost(exc)

        def _too_slow(self) -> None:
            self.deadline = None
            if self.transport.is_closing():
                return
            if self.begun and (self.cycle is None or not self.cycle.response_started):
                self.transport.write(late)
            self.transport.close()

    return DeadlineH11Protocol


def _refusal(status: int, message: str) -> bytes:
    """A whole HTTP/1.1 response that closes the connection, written as bytes."""
    body = json.dumps({"error": message}).encode()
    reason = {408: "Request Timeout"}[status]
    head = (
        f"HTTP/1.1 {status} {reason}\r\ncontent-type: application/json\r\n"
        f"content-length: {len(body)}\r\nconnection: close\r\n\r\n"
    )
    return head.encode() + body
