"""The web application of ``kreisel explore`` (Starlette): the page, its static files and a
JSON API over :mod:`kreisel.explore._api`, behind :class:`~kreisel.explore._guard.LoopbackGuard`."""

from __future__ import annotations

import json
from pathlib import Path

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import ClientDisconnect, Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from .._errors import KreiselError, ParameterError
from .._extras import missing_message
from . import _api, _jobs
from ._guard import BodyTooLarge, LoopbackGuard

STATIC = Path(__file__).resolve().parent / "static"
VENDOR_FILES = ("three.module.min.js", "OrbitControls.js", "uPlot.esm.js", "uPlot.min.css")


def missing_vendor() -> list[str]:
    """The JavaScript libraries not in static/vendor (`make setup` copies them there)."""
    return [f for f in VENDOR_FILES if not (STATIC / "vendor" / f).is_file()]


async def _json(request: Request):
    try:
        return json.loads(await request.body())
    except BodyTooLarge as e:  # a body sent without its length, cut off as it arrived
        raise _api.RequestError(str(e), 413) from None
    except ClientDisconnect:  # the client went (or was closed for sending too slowly)
        message = "the client closed the connection before its body arrived"
        raise _api.RequestError(message, 408) from None
    except (ValueError, UnicodeDecodeError) as e:
        raise _api.RequestError(f"the request body is not JSON: {e}") from None
    except RecursionError:
        raise _api.RequestError("the request body nests arrays or objects too deeply") from None


def _error(e: Exception) -> JSONResponse:
    if isinstance(e, _api.RequestError):
        return JSONResponse({"error": str(e)}, status_code=e.status)
    table, field, message = _api.field_of(str(e))
    status = 400 if isinstance(e, ParameterError) else 422
    return JSONResponse({"error": message, "table": table, "field": field}, status_code=status)


def create_app(port: int, store: Path | None = None) -> LoopbackGuard:
    """The application serving on ``127.0.0.1:port``, reading sweep stores under ``store``."""

    def guarded(work, *, isolated: bool = False):
        """The endpoint answering ``work(body)``: in a thread, or (``isolated``: a run) in a
        process of its own that ends when the client goes (see :mod:`._jobs`)."""

        async def endpoint(request: Request):
            try:
                body = await _json(request) if request.method == "POST" else None
                if isolated:
                    result = await _jobs.compute(work, body, request.is_disconnected)
                else:
                    result = await run_in_threadpool(work, body)
            except _jobs.Abandoned:
                return Response(status_code=499)  # nobody reads it: the client has gone
            except (_api.RequestError, KreiselError) as e:
                return _error(e)
            except ModuleNotFoundError as e:
                # sweeps need zarr, NetCDF needs xarray: optional dependencies
                if e.name is None or e.name.split(".")[0] == "kreisel":
                    raise
                return JSONResponse({"error": missing_message(e.name)}, 501)
            if isinstance(result, _api.File):
                return Response(
                    result.content,
                    media_type=result.media,
                    headers={"content-disposition": f'attachment; filename="{result.name}"'},
                )
            return result if isinstance(result, Response) else JSONResponse(result)

        return endpoint

    def needs_store(body):
        if store is None:
            raise _api.RequestError("no store folder: start kreisel explore with --store DIR", 404)
        return store

    async def index(request: Request):
        return FileResponse(STATIC / "index.html")

    routes = [
        Route("/", index),
        Route("/api/schema", guarded(lambda body: _api.schema())),
        Route("/api/run", guarded(_api.run_request, isolated=True), methods=["POST"]),
        Route("/api/import/toml", guarded(_api.import_toml), methods=["POST"]),
        Route("/api/atlas", guarded(lambda body: _api.atlas_plane())),
        Route(
            "/api/stores",
            guarded(
                lambda body: {
                    "stores": _api.list_stores(store),
                    "root": str(store) if store else None,
                }
            ),
        ),
        Route(
            "/api/sweep",
            guarded(lambda body: _api.sweep_view(needs_store(body), body)),
            methods=["POST"],
        ),
        Route(
            "/api/sweep/cell",
            guarded(lambda body: _api.sweep_cell(needs_store(body), body)),
            methods=["POST"],
        ),
        Route("/api/export/toml", guarded(_api.toml_file), methods=["POST"]),
        Route(
            "/api/export/trajectory",
            guarded(_api.trajectory_request, isolated=True),
            methods=["POST"],
        ),
        Mount("/static", StaticFiles(directory=STATIC), name="static"),
    ]
    return LoopbackGuard(Starlette(routes=routes), port, _api.MAX_BODY)
