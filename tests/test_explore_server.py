"""The server of ``kreisel explore``: it listens on 127.0.0.1 only, answers only requests for
its own loopback address (Host and Origin: DNS rebinding), reads sweep stores only under
--store, caps the work of a request, and answers with kreisel's own messages and numbers."""

from __future__ import annotations

import http.client
import io
import json
import socket
import subprocess
import sys
import time
from pathlib import Path

import _browser
import numpy as np
import pytest

import kreisel
from kreisel._config import from_tables, preset, read_toml
from kreisel.explore import _api
from kreisel.explore._geometry import axis_tip, body_parts

# the fixtures store (a folder of sweep stores) and server (kreisel explore --store it)
store, server = _browser.store_fixture, _browser.server_fixture


def request(server, method, path, body=None, headers=None):
    """(status, parsed JSON or bytes) of a raw request; Host is the server's unless given."""
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)
    h = {"Host": f"127.0.0.1:{server.port}"}
    h.update(headers or {})
    data = body if isinstance(body, bytes) or body is None else json.dumps(body).encode()
    if data is not None:
        h.setdefault("Content-Type", "application/json")
    conn.putrequest(method, path, skip_host=True, skip_accept_encoding=True)
    for k, v in h.items():
        conn.putheader(k, v)
    if data is not None:
        conn.putheader("Content-Length", str(len(data)))
    conn.endheaders()
    if data is not None:
        conn.send(data)
    r = conn.getresponse()
    raw = r.read()
    conn.close()
    if r.getheader("content-type", "").startswith("application/json"):
        return r.status, json.loads(raw)
    return r.status, raw


def test_listens_on_the_loopback_address_only(server):
    # /proc/net/tcp lists the listening sockets (state 0A) as hex address:port
    rows = Path("/proc/net/tcp").read_text().splitlines()[1:]
    listening = [r.split()[1] for r in rows if r.split()[3] == "0A"]
    ours = [a for a in listening if int(a.split(":")[1], 16) == server.port]
    assert ours == [f"0100007F:{server.port:04X}"]
    assert not any(
        int(a.split(":")[1], 16) == server.port
        for a in (r.split()[1] for r in Path("/proc/net/tcp6").read_text().splitlines()[1:])
    )
    # and a connection to another address of this machine is refused
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.connect(("192.0.2.1", 9))  # no packet is sent: this picks the outgoing address
            ip = s.getsockname()[0]
        except OSError:
            ip = None
    if ip and not ip.startswith("127."):
        with pytest.raises(ConnectionRefusedError):
            socket.create_connection((ip, server.port), timeout=5).close()


def test_the_page_and_its_libraries_are_served_from_the_package(server):
    status, page = request(server, "GET", "/")
    assert status == 200 and b"importmap" in page
    assert b"http://" not in page and b"https://" not in page  # nothing from a CDN
    for f in ("three.module.min.js", "OrbitControls.js", "uPlot.esm.js"):
        status, _ = request(server, "GET", f"/static/vendor/{f}")
        assert status == 200, f


@pytest.mark.parametrize(
    "host", ["evil.example:{port}", "127.0.0.1:1", "localhost", "0.0.0.0:{port}"]
)
def test_a_foreign_host_header_is_refused(server, host):
    host = host.format(port=server.port)
    status, body = request(server, "GET", "/api/schema", headers={"Host": host})
    assert status == 403
    assert body["error"].startswith(f"Host {host!r} is not served here")
    status, _ = request(server, "GET", "/", headers={"Host": host})
    assert status == 403


def test_a_foreign_origin_is_refused_and_the_own_one_served(server):
    tables = preset("toy")
    status, body = request(
        server, "POST", "/api/run", {"tables": tables}, headers={"Origin": "http://evil.example"}
    )
    assert status == 403 and "Origin 'http://evil.example' is not served here" in body["error"]
    status, body = request(
        server,
        "POST",
        "/api/run",
        {"tables": tables},
        headers={"Origin": f"http://localhost:{server.port}"},
    )
    assert status == 200 and body["kind"] == "lagrange"


@pytest.mark.parametrize(
    "name", ["../outside/secret.zarr", "/etc", "link.zarr", "tippe.zarr/../.."]
)
def test_a_store_outside_the_store_folder_is_refused(server, name):
    status, body = request(server, "POST", "/api/sweep", {"store": name})
    assert status == 403
    assert (
        f"store = {name!r} is not allowed: kreisel explore reads stores only under" in body["error"]
    )
    status, body = request(server, "POST", "/api/sweep/cell", {"store": name, "index": [0, 0]})
    assert status == 403


def test_the_stores_under_the_folder_are_listed_and_opened(server, store):
    status, body = request(server, "GET", "/api/stores")
    assert status == 200 and body["stores"] == ["tippe.zarr"]  # not the link out of it
    status, view = request(server, "POST", "/api/sweep", {"store": "tippe.zarr"})
    ds = kreisel.open_sweep(str(store / "tippe.zarr"))
    assert view["var"] == "inversion_time" and view["dims"] == ["s", "A"]
    got = np.array(view["values"], dtype=float)
    np.testing.assert_array_equal(got, ds["inversion_time"].values)


def test_an_oversized_body_is_refused(server):
    status, body = request(server, "POST", "/api/run", b"{" + b" " * _api.MAX_BODY + b"}")
    assert status == 413
    assert body["error"] == (
        f"the request body is larger than {_api.MAX_BODY} bytes, the most one request may send"
    )


@pytest.mark.parametrize(
    "simulation, message",
    [
        (
            {"samples": _api.MAX_SAMPLES + 1},
            f"samples = {_api.MAX_SAMPLES + 1} is not allowed here",
        ),
        ({"t_end": 1e4}, "t_end = 10000.0 is not allowed here: kreisel explore runs at most 600 s"),
        ({"method": "rk4", "dt": 1e-7, "t_end": 1.0}, "dt = 1e-07 is not allowed here"),
    ],
)
def test_a_run_asking_for_too_much_work_is_refused(server, simulation, message):
    tables = preset("toy")
    tables["simulation"] = {**tables["simulation"], **simulation}
    status, body = request(server, "POST", "/api/run", {"tables": tables})
    assert status == 400 and body["table"] == "simulation"
    assert body["error"].startswith(message)


def test_a_sweep_too_large_for_the_page_is_refused(monkeypatch, store):
    monkeypatch.setattr(_api, "MAX_SWEEP_CELLS", 3)
    with pytest.raises(_api.RequestError, match="this sweep has 4 cells: the page shows at most 3"):
        _api.sweep_view(store, {"store": "tippe.zarr"})


@pytest.mark.parametrize(
    "body, message",
    [
        (b"not json", "the request body is not JSON"),
        ({"tables": 3}, 'the request must be a JSON object with "tables"'),
        ({"tables": {"toppings": {}}}, "[toppings] is not a known table"),
    ],
)
def test_a_malformed_request_is_refused_with_a_clear_message(server, body, message):
    status, answer = request(server, "POST", "/api/run", body)
    assert status == 400 and answer["error"].startswith(message)


def test_a_bad_parameter_answers_with_the_api_message_and_its_field(server):
    tables = preset("tippe-ball")
    tables["top"]["m"] = -1.0
    status, body = request(server, "POST", "/api/run", {"tables": tables})
    p = {
        k: v for k, v in preset("tippe-ball")["top"].items() if k not in ("kind", "friction", "mu")
    }
    with pytest.raises(kreisel.ParameterError) as e:
        kreisel.PlayTop(**{**p, "m": -1.0}, friction=kreisel.Viscous(1.0))
    assert status == 400
    assert (body["table"], body["field"], body["error"]) == ("top", "m", str(e.value))


def test_a_run_is_the_one_of_kreisel_simulate(server):
    status, run = request(server, "POST", "/api/run", {"tables": preset("tippe-ball")})
    t = preset("tippe-ball")
    p = {k: v for k, v in t["top"].items() if k not in ("kind", "friction", "mu")}
    top = kreisel.PlayTop(**p, friction=kreisel.Viscous(1.0))
    traj = kreisel.simulate(
        top,
        top.state(**t["state"]),
        8.0,
        rtol=1e-9,
        t_eval=np.linspace(0.0, 8.0, _api.DEFAULT_SAMPLES),
        events=[kreisel.events.inversion(0.9)],
    )
    assert status == 200
    assert run["inversion_time"] == traj.events[0].t
    np.testing.assert_array_equal(run["series"]["u"], traj.u)
    np.testing.assert_array_equal(run["quaternion"], traj.quaternion)
    assert run["tables"]["simulation"]["samples"] == _api.DEFAULT_SAMPLES
    assert run["atlas"]["J"] == top.jellett(top.state(**t["state"]))


def test_a_shaken_top_runs_on_its_moving_pivot(server):
    """The kapitza preset's [pivot] reaches the run: the body's origin follows the pivot's
    path (computed here from the shaking), and the balance replaces the integrals."""
    t = preset("kapitza")
    status, run = request(server, "POST", "/api/run", {"tables": t})
    assert status == 200, run
    assert run["tables"]["pivot"] == t["pivot"]
    p = t["pivot"]
    z = p["amplitude"][2] * np.cos(p["omega"] * np.array(run["t"]))
    np.testing.assert_allclose(np.array(run["com"])[:, 2], z, rtol=0, atol=1e-15)
    b = np.array(run["series"]["balance"])
    # constant to the run's tolerance (rtol 1e-9) accumulated over its ~10^3 steps
    assert np.ptp(b) < 1e-6 * np.abs(run["series"]["energy"]).max()
    assert "Mz" in run["series"] and "M3" not in run["series"]
    # an empty [pivot] or [damping] (a form's empty fields) says nothing
    status, plain = request(
        server, "POST", "/api/run", {"tables": {**preset("toy"), "pivot": {}, "damping": {}}}
    )
    assert status == 200 and "balance" not in plain["series"], plain
    status, bad = request(server, "POST", "/api/run", {"tables": {**t, "damping": {"dry": -1}}})
    assert status == 400 and "dry" in json.dumps(bad), bad


def test_a_lagrange_run_is_posed_by_its_euler_angles(server):
    status, run = request(server, "POST", "/api/run", {"tables": preset("toy")})
    q = np.array(run["quaternion"])
    # the figure axis R(q) e3 = (sin theta sin phi, -sin theta cos phi, cos theta)
    w, x, y, z = q.T
    e3z = 1 - 2 * (x * x + y * y)
    np.testing.assert_allclose(e3z, run["series"]["u"], atol=1e-12)


@pytest.mark.parametrize("fmt", ["csv", "netcdf"])
def test_the_trajectory_exports_are_the_run(server, fmt):
    import xarray as xr

    status, run = request(server, "POST", "/api/run", {"tables": preset("tippe-ball")})
    status, content = request(
        server, "POST", "/api/export/trajectory", {"tables": run["tables"], "format": fmt}
    )
    assert status == 200
    if fmt == "csv":
        import pandas as pd

        df = pd.read_csv(io.BytesIO(content))
        np.testing.assert_allclose(df["t"], run["t"], rtol=1e-15)
        np.testing.assert_allclose(df["u"], run["series"]["u"], rtol=1e-15)
    else:
        ds = xr.open_dataset(io.BytesIO(content), engine="scipy")
        np.testing.assert_array_equal(ds["t"].values, run["t"])
        np.testing.assert_array_equal(ds["u"].values, run["series"]["u"])
    status, body = request(
        server, "POST", "/api/export/trajectory", {"tables": run["tables"], "format": "xlsx"}
    )
    assert (
        status == 400 and body["error"] == 'format = \'xlsx\' is not allowed: use "csv" or "netcdf"'
    )


def test_import_kreisel_does_not_load_the_web_stack():
    code = "import sys, kreisel; print([m for m in ('starlette', 'uvicorn') if m in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_the_body_is_drawn_from_the_tops_shape_when_it_has_one():
    # a top with a ball and a peg: every part drawn
    from kreisel.shapes import Sphere

    parts = [Sphere(0.015, -0.003, "ball"), Sphere(0.005, -0.016, "peg")]
    top = kreisel.PlayTop(m=6e-3, A=8e-7, C=7e-7, shape=parts)
    parts = body_parts(top)
    contact = [(p["kind"], p["name"], p["radius"], p["z"]) for p in parts if p["role"] == "contact"]
    assert contact == [("sphere", "ball", 0.015, -0.003), ("sphere", "peg", 0.005, -0.016)]
    # without a shape: the tip sphere, radius rho, centred at -s
    plain = body_parts(kreisel.PlayTop(m=0.1, A=1.6e-5, C=2e-5, s=0.03, rho=0.0005))
    assert [(p["radius"], p["z"]) for p in plain if p["role"] == "contact"] == [(0.0005, -0.03)]
    assert axis_tip(plain) > 0


def test_a_heavy_top_is_its_inertia_ellipsoid_on_an_arm_from_the_pivot():
    top = kreisel.HeavyTop(I1=2e-3, I2=2e-3, I3=1e-3, m=0.5, com=[0.02, 0.0, 0.0])
    body, rod, pivot = body_parts(top)
    a, b, c = body["radii"]
    # a uniform ellipsoid with semi-axes a, b, c has I1 = m (b^2 + c^2) / 5, ...
    np.testing.assert_allclose(
        [0.5 * (b * b + c * c) / 5, 0.5 * (a * a + c * c) / 5, 0.5 * (a * a + b * b) / 5],
        [2e-3, 2e-3, 1e-3],
        rtol=1e-12,
    )
    assert body["center"] == rod["end"] == [0.02, 0.0, 0.0] and pivot["role"] == "pivot"


def test_the_command_refuses_a_store_that_is_not_a_folder_and_a_port_in_use(tmp_path, capsys):
    from kreisel._cli import main

    missing = tmp_path / "nothing-here"
    assert main(["explore", "--no-browser", "--store", str(missing)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == (
        f"kreisel explore: error: store = {str(missing)!r} is not allowed: it is not a folder"
    )
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        assert main(["explore", "--no-browser", "--port", str(port)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == (
        f"kreisel explore: error: port = {port} is busy: another program listens on "
        f"127.0.0.1:{port}; give another port (0: any free one)"
    )


def _asgi_get(app, path: str, port: int):
    """(status, JSON body) of a GET sent straight to the ASGI application."""
    import asyncio

    sent = []

    async def receive():
        return {"type": "http.request", "body": b"", "more_body": False}

    async def send(message):
        sent.append(message)

    scope = {
        "type": "http",
        "asgi": {"version": "3.0"},
        "http_version": "1.1",
        "method": "GET",
        "scheme": "http",
        "path": path,
        "raw_path": path.encode(),
        "query_string": b"",
        "root_path": "",
        "headers": [(b"host", f"127.0.0.1:{port}".encode())],
        "client": ("127.0.0.1", 50000),
        "server": ("127.0.0.1", port),
    }
    asyncio.run(app(scope, receive, send))
    body = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    return sent[0]["status"], json.loads(body)


def test_a_missing_optional_package_is_named_with_how_to_install_it(monkeypatch):
    from kreisel.explore._app import create_app

    def needs_zarr():
        raise ModuleNotFoundError("No module named 'zarr'", name="zarr")

    monkeypatch.setattr(_api, "atlas_plane", needs_zarr)
    status, body = _asgi_get(create_app(8765), "/api/atlas", 8765)
    assert status == 501
    assert body["error"] == (
        "this needs the package 'zarr', which is not installed: pip install 'kreisel[sweep]'"
    )


def test_a_play_top_outside_the_atlas_still_runs_and_says_why(monkeypatch):
    # a top with several contact parts has no (alpha, gamma): its run goes on without atlas
    def no_atlas(p):
        raise kreisel.ParameterError("shape[0] is not allowed here: the atlas is of one sphere")

    monkeypatch.setattr(_api, "atlas_of", no_atlas)
    run = _api.run(preset("tippe-ball"))
    assert run["atlas"] is None
    assert run["atlas_note"] == "shape[0] is not allowed here: the atlas is of one sphere"
    assert run["inversion_time"] is not None


def test_an_oversized_body_sent_without_its_length_is_refused(server):
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)
    body = [b'{"tables": "', b"x" * (_api.MAX_BODY // 2), b"x" * (_api.MAX_BODY // 2), b'"}']
    conn.request(
        "POST",
        "/api/run",
        body=iter(body),
        encode_chunked=True,
        headers={"Host": f"127.0.0.1:{server.port}", "Transfer-Encoding": "chunked"},
    )
    r = conn.getresponse()
    answer = json.loads(r.read())
    conn.close()
    assert r.status == 413
    assert answer["error"].startswith(f"the request body is larger than {_api.MAX_BODY} bytes")


@pytest.mark.parametrize("name", ["egg", "euler-disk", "coin", "toy-top"])
def test_the_bodies_of_revolution_run_and_are_drawn(name):
    """The presets of spheroids and rings run through the API; every part is drawn (a lathe
    of its profile), with the body's outline."""
    tables = preset(name)
    tables["simulation"]["t_end"] = 0.05
    run = _api.run(tables)
    kinds = {p["name"]: p["kind"] for p in run["body"]["parts"]}
    for part in from_tables(preset(name)).model.part_names:
        assert part in kinds
    assert kinds["body"] == "lathe"


@pytest.mark.parametrize(
    "name, reason",
    [
        ("tippe\x00.zarr", "a path has no NUL character"),
        ("x" * 5000, "a store's path has at most 1024 characters"),
        ("y" * 300, "File name too long"),  # one part longer than the file system allows
    ],
)
def test_a_store_name_the_file_system_refuses_is_a_clear_400(server, name, reason):
    status, answer = request(server, "POST", "/api/sweep", {"store": name})
    assert status == 400
    assert answer["error"].startswith("store = ") and answer["error"].endswith(reason)
    assert len(answer["error"]) < 300  # the name is cut short, not echoed 5000 times


def _tree_cpu_seconds(pid: int) -> float:
    """The CPU time (user + system, s) the live processes of ``pid``'s tree have used."""
    import os

    tick = os.sysconf("SC_CLK_TCK")
    stats = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            stats[int(entry.name)] = (int(fields[1]), int(fields[11]) + int(fields[12]))
    tree, todo = set(), [pid]
    while todo:
        p = todo.pop()
        tree.add(p)
        todo += [c for c, (parent, _) in stats.items() if parent == p and c not in tree]
    return sum(stats[p][1] for p in tree if p in stats) / tick


def test_a_run_whose_client_has_gone_stops_computing(server):
    """A run of about 12 s of work (a heavy top spinning at 30000 rad/s, rtol 1e-13, 600 s)
    is asked for and its client closes the connection after 3 s: the server's processes then
    use (almost) no CPU time, where the run went on computing for its 12 s before."""
    tables = preset("kovalevskaya")
    tables["state"]["omega"] = [1.0, -2.0, 30000.0]
    tables["simulation"].update({"t_end": 600.0, "rtol": 1e-13})
    body = json.dumps({"tables": tables}).encode()
    sock = socket.create_connection(("127.0.0.1", server.port), timeout=10)
    sock.sendall(
        f"POST /api/run HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
        f"Content-Type: application/json\r\nContent-Length: {len(body)}\r\n\r\n".encode()
        + body
    )
    time.sleep(1.0)
    busy = _tree_cpu_seconds(server.proc.pid)
    time.sleep(2.0)
    assert _tree_cpu_seconds(server.proc.pid) - busy > 0.4  # it is computing
    sock.close()
    time.sleep(1.0)  # the server notices within POLL s and ends the computation
    before = _tree_cpu_seconds(server.proc.pid)
    time.sleep(2.0)
    assert _tree_cpu_seconds(server.proc.pid) - before < 0.3
    # and the server still answers
    status, answer = request(server, "POST", "/api/run", {"tables": preset("gyroscope")})
    assert status == 200 and answer["kind"] == "lagrange"


# a request must arrive within 5 s (kreisel.explore._guard.REQUEST_TIMEOUT): a connection
# that dribbles its bytes is closed by then, give or take the test's own pace
CLOSED_WITHIN = 8.0


def _closed_after(sock, dribble: bytes, limit: float) -> tuple[float, bytes]:
    """Sends ``dribble`` one byte every 0.25 s until the server closes the connection (or
    ``limit`` s pass): (seconds until it closed, what it answered)."""
    start = time.monotonic()
    sock.settimeout(0.25)
    answer = b""
    for byte in dribble:
        if time.monotonic() - start > limit:
            break
        try:
            sock.sendall(bytes([byte]))
            chunk = sock.recv(4096)
            answer += chunk
            if not chunk:
                return time.monotonic() - start, answer
        except TimeoutError:
            continue
        except (BrokenPipeError, ConnectionResetError):
            return time.monotonic() - start, answer
    return time.monotonic() - start, answer


def test_slow_headers_do_not_hold_a_connection(server):
    sock = socket.create_connection(("127.0.0.1", server.port), timeout=10)
    headers = f"GET /api/schema HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n" + "X-A: b\r\n" * 200
    took, answer = _closed_after(sock, headers.encode(), 3 * CLOSED_WITHIN)
    sock.close()
    assert took < CLOSED_WITHIN
    assert answer.startswith(b"HTTP/1.1 408 ")
    assert b"the request did not arrive within" in answer


def test_a_slow_body_does_not_hold_a_connection(server):
    body = json.dumps({"tables": preset("gyroscope")}).encode()
    sock = socket.create_connection(("127.0.0.1", server.port), timeout=10)
    sock.sendall(
        f"POST /api/run HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
        f"Content-Type: application/json\r\nContent-Length: {len(body)}\r\n\r\n".encode()
    )
    took, answer = _closed_after(sock, body, 3 * CLOSED_WITHIN)
    sock.close()
    assert took < CLOSED_WITHIN
    assert answer.startswith(b"HTTP/1.1 408 ")


def test_an_idle_connection_is_closed(server):
    # closed with no answer: a browser may be about to send its request on it
    sock = socket.create_connection(("127.0.0.1", server.port), timeout=3 * CLOSED_WITHIN)
    start = time.monotonic()
    answer = sock.recv(4096)
    sock.close()
    assert time.monotonic() - start < CLOSED_WITHIN and answer == b""


def test_a_kept_alive_connection_serves_request_after_request(server):
    """The deadline is per request: a connection kept alive between requests (as a browser
    keeps it) serves each of them, also after a pause."""
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)
    for pause in (0.0, 2.0, 2.0):
        time.sleep(pause)
        conn.request("GET", "/api/schema", headers={"Host": f"127.0.0.1:{server.port}"})
        r = conn.getresponse()
        assert r.status == 200 and json.loads(r.read())["kinds"]
    conn.close()


def test_a_toml_file_is_read_as_kreisel_run_reads_it(server, tmp_path):
    text = '[top]\npreset = "tippe-ball"\nm = 0.021\n\n[state]\npsi_dot = 160.0\n'
    status, answer = request(server, "POST", "/api/import/toml", {"toml": text, "name": "a.toml"})
    path = tmp_path / "a.toml"
    path.write_text(text)
    assert status == 200 and answer["tables"] == from_tables(read_toml(path)).tables
    # kreisel run's own messages, naming the file as the user named it
    status, answer = request(
        server,
        "POST",
        "/api/import/toml",
        {"toml": "[top]\nkind = 'play'\nm = -1\n", "name": "/x/b.toml"},
    )
    assert status == 400 and answer["error"].startswith("b.toml: [top] ")
    status, answer = request(server, "POST", "/api/import/toml", {"toml": 3})
    assert status == 400 and answer["error"].startswith("the request must be a JSON object with")
