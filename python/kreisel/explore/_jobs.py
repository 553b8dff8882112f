"""The computations of a request in a process of their own, so that a request whose client has
gone is abandoned: its process is ended and the work stops (a thread computing in kreisel's
core cannot be stopped from outside).

The processes come from a fork server that has imported kreisel once, so a run starts in a few
milliseconds; each runs one function of :mod:`kreisel.explore._api` on the request's body and
sends back its answer, or the mistake it found.
"""

from __future__ import annotations

import asyncio
import multiprocessing
import traceback

from starlette.concurrency import run_in_threadpool

from .._errors import KreiselError

POLL = 0.05  # s between two looks at the client and at the computation
_context = None


def context():
    """The fork server's multiprocessing context (started on first use, with kreisel loaded)."""
    global _context
    if _context is None:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(["kreisel.explore._api"])
        _context = ctx
    return _context


def start() -> None:
    """Starts the fork server now, so that the first run does not wait for it."""
    from multiprocessing import forkserver

    context()
    forkserver.ensure_running()


def _child(conn, work, body) -> None:
    from . import _api

    try:
        answer = ("ok", work(body))
    except _api.RequestError as e:
        answer = ("request", str(e), e.status)
    except KreiselError as e:
        answer = ("kreisel", type(e), str(e))
    except ModuleNotFoundError as e:
        answer = ("module", str(e), e.name)
    except BaseException:  # noqa: BLE001 - any other failure is the server's, reported as such
        answer = ("crash", traceback.format_exc())
    try:
        conn.send(answer)
    finally:
        conn.close()


class Abandoned(Exception):
    """The client went away before the answer was ready: the computation was ended."""


async def compute(work, body, gone) -> object:
    """``work(body)`` in a process of its own; ``await gone()`` is polled every ``POLL`` s and,
    once true (the client disconnected), the process is ended and :class:`Abandoned` raised.
    The mistakes ``work`` raises (RequestError, KreiselError, ModuleNotFoundError) are raised
    here as they were."""
    from . import _api

    ctx = context()
    receiver, sender = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(sender, work, body), daemon=True)
    loop = asyncio.get_running_loop()
    ready = asyncio.Event()  # the answer (or the end of the process) can be read
    watched = False
    try:
        await run_in_threadpool(proc.start)
        sender.close()
        loop.add_reader(receiver.fileno(), ready.set)
        watched = True
        while not ready.is_set():
            if await gone():
                raise Abandoned
            try:
                await asyncio.wait_for(ready.wait(), POLL)
            except asyncio.TimeoutError:
                pass
        try:
            answer = await run_in_threadpool(receiver.recv)
        except EOFError:
            answer = ("crash", f"the computation ended with no answer (exit code {proc.exitcode})")
    finally:
        if watched:
            loop.remove_reader(receiver.fileno())
        if proc.pid is not None:
            proc.kill()
            await run_in_threadpool(proc.join)
        receiver.close()
        sender.close()
    if answer[0] == "ok":
        return answer[1]
    if answer[0] == "request":
        raise _api.RequestError(answer[1], answer[2])
    if answer[0] == "kreisel":
        raise answer[1](answer[2])
    if answer[0] == "module":
        raise ModuleNotFoundError(answer[1], name=answer[2])
    raise RuntimeError(answer[1])
