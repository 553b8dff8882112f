"""kreisel.sweep: specs, the Zarr store, resuming, and Dask clusters of real processes.

References: every stored summary is compared with ``kreisel.simulate_many`` called directly
on tops and states built here from the same numbers (an independent path that does not go
through the spec, the chunking or the store); local and Dask runs must agree bit for bit.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import kreisel

pytest.importorskip("zarr")
pytest.importorskip("distributed")

M, RHO, S = 0.02, 0.02, 0.006
C = 0.4 * M * RHO**2
A = 0.8 * C


def play_spec(**over):
    spec = {
        "top": {"kind": "play", "m": M, "A": A, "C": C, "rho": RHO, "friction": "viscous",
                "mu": 1.0},
        "state": {"theta": np.pi - 0.1},
        "simulation": {"t_end": 2.5, "rtol": 1e-8},
        "grid": {"psi_dot": {"start": 80.0, "stop": 200.0, "num": 4}, "s": [0.004, 0.006, 0.008]},
        "output": {"chunk": 3},
    }  # fmt: skip
    for table, values in over.items():
        spec[table] = values
    return spec


def direct(spec_tables, ds):
    """simulate_many on tops built here for every grid point of a play spec."""
    grid = ds["psi_dot"].values, ds["s"].values
    tops, states = [], []
    for psi_dot in grid[0]:
        for s in grid[1]:
            top = kreisel.PlayTop(M, A, C, s, RHO, friction=kreisel.Viscous(1.0))
            tops.append(top)
            states.append(top.state(spec_tables["state"]["theta"], psi_dot=psi_dot))
    sim = spec_tables["simulation"]
    return kreisel.simulate_many(tops, states, sim["t_end"], rtol=sim["rtol"])


def assert_same(a, b):
    assert list(a.data_vars) == list(b.data_vars)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    for name in a.coords:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)


# --------------------------------------------------------------------------------------
# specs
# --------------------------------------------------------------------------------------


def test_grid_layout_and_values_equal_direct_batch(tmp_path):
    tables = play_spec()
    ds = kreisel.sweep(tables, tmp_path / "s.zarr", progress=False)
    assert ds["final_u"].dims == ("psi_dot", "s") and ds["final_u"].shape == (4, 3)
    np.testing.assert_array_equal(ds["psi_dot"].values, np.linspace(80, 200, 4))
    ref = direct(tables, ds)
    np.testing.assert_array_equal(ds["final_u"].values.ravel(), ref.final_u)
    np.testing.assert_array_equal(ds["inversion_time"].values.ravel(), ref.inversion_time)
    np.testing.assert_array_equal(ds["jellett_drift"].values.ravel(), ref.jellett_drift)
    np.testing.assert_array_equal(ds["steps"].values.ravel(), ref.steps)
    assert list(ds["final_mode"].values.ravel()) == list(ref.final_mode)
    assert np.all(ds["status"].values == 1)
    assert ds.attrs["chunks_done"] == ds.attrs["chunks"] == 4
    # a fast tippe top turns over (u rises through 0.9) within 2.5 s
    assert np.isfinite(ds["inversion_time"].values).any()
    # the store alone gives the same dataset back
    assert_same(kreisel.open_sweep(tmp_path / "s.zarr"), ds)


def test_random_samples_are_reproducible_and_crossed_with_the_grid(tmp_path):
    tables = play_spec(
        state={},
        grid={"s": [0.005, 0.007]},
        random={"n": 5, "seed": 3, "psi_dot": {"low": 50.0, "high": 300.0, "scale": "log"},
                "theta": {"low": 2.9, "high": 3.1}},
        output={"chunk": 3, "keep": ["final_u", "inversion_time"]},
    )  # fmt: skip
    ds = kreisel.sweep(tables, tmp_path / "r.zarr", progress=False)
    assert ds["final_u"].dims == ("s", "sample")
    assert set(ds.data_vars) == {"final_u", "inversion_time", "status"}
    rng = np.random.default_rng(3)
    psi = np.exp(rng.uniform(np.log(50.0), np.log(300.0), 5))
    theta = rng.uniform(2.9, 3.1, 5)
    np.testing.assert_array_equal(ds["psi_dot"].values, psi)
    np.testing.assert_array_equal(ds["theta"].values, theta)
    for i, s in enumerate((0.005, 0.007)):
        top = kreisel.PlayTop(M, A, C, s, RHO, friction=kreisel.Viscous(1.0))
        ref = kreisel.simulate_many(
            top, [top.state(th, psi_dot=p) for th, p in zip(theta, psi)], 2.5, rtol=1e-8
        )
        np.testing.assert_array_equal(ds["final_u"].values[i], ref.final_u)


def test_heavy_sweep_over_the_centre_of_mass(tmp_path):
    tables = {
        "top": {"kind": "heavy", "I1": 2.0, "I2": 2.0, "I3": 1.0, "m": 1.0, "g": 1.0},
        "state": {"theta": 1.0, "psi_dot": 1.0, "phi_dot": 0.3},
        "simulation": {"t_end": 5.0, "method": "splitting4", "dt": 1e-3},
        "grid": {"com_x": [0.0, 0.5], "com_z": [0.0, 0.2]},
    }
    ds = kreisel.sweep(tables, tmp_path / "h.zarr", progress=False)
    # Mz is kept to round-off by the splitting whatever the top
    assert np.all(ds["Mz_drift"].values < 1e-12)
    # (com_x, com_z) = (0.5, 0): a Kovalevskaya top (I1 = I2 = 2 I3), K kept to O(dt^4)
    assert ds["kovalevskaya_drift"].values[1, 0] < 1e-8
    assert np.isnan(ds["kovalevskaya_drift"].values[1, 1])
    # (0, 0.2): a Lagrange top, so M3 is an integral; (0.5, 0.2) is not symmetric about e3
    assert ds["M3_drift"].values[0, 1] < 1e-12 and np.isnan(ds["M3_drift"].values[1, 1])
    top = kreisel.HeavyTop(2.0, 2.0, 1.0, 1.0, [0.5, 0.0, 0.2], g=1.0)
    ref = kreisel.simulate_many(top, top.state(1.0, psi_dot=1.0, phi_dot=0.3), 5.0,
                                method="splitting4", dt=1e-3)  # fmt: skip
    assert ds["final_theta"].values[1, 1] == ref.final_theta[0]


@pytest.mark.parametrize(
    ("over", "match"),
    [
        ({"grid": {"spin": [1.0]}}, "spin is not a parameter that can be swept"),
        ({"grid": {"psi_dot": []}}, "psi_dot is an empty grid"),
        ({"grid": {"psi_dot": {"start": 1, "stop": 2, "num": 0}}}, "psi_dot.num = 0"),
        ({"grid": {"psi_dot": 100.0}}, "single value belongs in"),
        ({"grid": {}}, "nothing is swept"),
        ({"grid": {"theta": [3.0]}}, "theta is swept and also fixed in \\[state\\]"),
        ({"grid": {"s": [0.006], "restitution": [0.5, 1.5]}}, r"\[grid\] restitution = 1.5"),
        ({"grid": {"s": {"start": 0, "stop": 1, "num": 3, "scale": "log"}}}, "both ends"),
        ({"random": {"n": 0, "psi_dot": {"low": 1, "high": 2}}}, "n = 0"),
        ({"random": {"n": 3, "psi_dot": {"low": 2, "high": 1}}}, "need low < high"),
        ({"output": {"keep": ["final_theta"]}}, "not a summary of a play top"),
        ({"output": {"chunk": 0}}, "chunk = 0"),
        ({"simulation": {"t_end": -1.0}}, "t_end"),
        ({"simulation": {"t_end": 1.0, "exact": True}}, "exact"),
        ({"plot": {}}, "\\[plot\\] is not a known table"),
    ],
)
def test_bad_specs_fail_at_once_and_touch_no_store(tmp_path, over, match):
    good = tmp_path / "good.zarr"
    kreisel.sweep(play_spec(output={"chunk": 6}), good, progress=False)
    before = {p: p.stat().st_mtime_ns for p in good.rglob("*")}
    with pytest.raises(kreisel.ParameterError, match=match):
        kreisel.sweep(play_spec(**over), good, progress=False, overwrite=True)
    assert {p: p.stat().st_mtime_ns for p in good.rglob("*")} == before


def test_a_store_of_another_sweep_or_of_something_else_is_left_alone(tmp_path):
    store = tmp_path / "s.zarr"
    kreisel.sweep(play_spec(output={"chunk": 6}), store, progress=False)
    other = play_spec(simulation={"t_end": 0.5, "rtol": 1e-8}, output={"chunk": 6})
    with pytest.raises(kreisel.ParameterError, match="holds another sweep"):
        kreisel.sweep(other, store, progress=False)
    ds = kreisel.sweep(other, store, progress=False, overwrite=True)
    assert json.loads(ds.attrs["spec"])["simulation"]["t_end"] == 0.5
    foreign = tmp_path / "data"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    with pytest.raises(kreisel.ParameterError, match="not a kreisel sweep store"):
        kreisel.sweep(play_spec(), foreign, progress=False, overwrite=True)
    assert (foreign / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in foreign.iterdir()) == ["notes.txt"]


def test_unreachable_scheduler_fails_before_the_store_is_created(tmp_path):
    store = tmp_path / "never.zarr"
    with pytest.raises(kreisel.ParameterError, match="scheduler = 'tcp://127.0.0.1:9' is not"):
        kreisel.sweep(play_spec(), store, "tcp://127.0.0.1:9", progress=False, connect_timeout=1)
    assert not store.exists()


def test_runs_that_cannot_start_are_kept_as_failures(tmp_path):
    # a tip below the floor is a state error of those runs only, not of the sweep
    tables = play_spec(grid={"height": [0.01, -0.01]}, output={"chunk": 1})
    tables["top"]["s"] = S
    tables["state"]["psi_dot"] = 100.0
    ds = kreisel.sweep(tables, tmp_path / "f.zarr", progress=False)
    assert list(ds["status"].values) == [1, 2]
    assert ds["final_mode"].values[1] == "error" and ds["final_mode"].values[0] != "error"
    errors = json.loads(ds.attrs["run_errors"])
    assert list(errors) == ["1"] and "height" in errors["1"]
    # a rerun leaves them; retry_failed computes (only) their chunk again
    again = []
    kreisel.sweep(tables, tmp_path / "f.zarr", progress=False, callback=lambda *a: again.append(a))
    assert again == []
    retried = kreisel.sweep(tables, tmp_path / "f.zarr", progress=False, retry_failed=True,
                            callback=lambda *a: again.append(a[0]))  # fmt: skip
    assert again == [1]
    assert_same(retried, ds)
    assert retried.attrs["run_errors"] == ds.attrs["run_errors"]


# --------------------------------------------------------------------------------------
# interruption and resume
# --------------------------------------------------------------------------------------


class Stop(Exception):
    pass


def interrupt(tables, store, after: int, scheduler=None) -> list:
    """Runs a sweep and stops it (an exception from the callback) after ``after`` chunks;
    returns the chunks written."""
    seen = []

    def stop(chunk, done, total):
        seen.append(chunk)
        if len(seen) == after:
            raise Stop

    with pytest.raises(Stop):
        kreisel.sweep(tables, store, scheduler, progress=False, callback=stop)
    return seen


def test_interrupted_sweep_resumes_with_only_the_missing_chunks(tmp_path):
    tables = play_spec()
    store = tmp_path / "i.zarr"
    seen = interrupt(tables, store, 2)
    partial = kreisel.open_sweep(store)
    assert partial.attrs["chunks_done"] == 2
    assert (partial["status"].values == 1).sum() == 6 and (partial["status"].values == 0).sum() == 6
    assert np.isnan(partial["final_u"].values[partial["status"].values == 0]).all()
    again = []
    ds = kreisel.sweep(tables, store, progress=False, callback=lambda k, d, t: again.append(k))
    assert sorted(again) == sorted(set(range(4)) - set(seen))
    assert_same(ds, kreisel.sweep(tables, None, progress=False))
    # complete: a third call computes nothing
    third = []
    kreisel.sweep(tables, store, progress=False, callback=lambda k, d, t: third.append(k))
    assert third == []


def test_thread_count_changes_no_bit(tmp_path):
    a = kreisel.sweep(play_spec(), None, progress=False, threads=1)
    b = kreisel.sweep(play_spec(output={"chunk": 5}), None, progress=False, threads=2)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values)


# --------------------------------------------------------------------------------------
# a real Dask cluster: a scheduler and two workers as separate processes on loopback
# --------------------------------------------------------------------------------------


def _spawn(args, log):
    return subprocess.Popen(
        [sys.executable, "-m", *args],
        stdout=log,
        stderr=subprocess.STDOUT,
        cwd=str(Path(__file__).resolve().parent),
        env={**os.environ, "OPENBLAS_NUM_THREADS": "1"},
    )


class Cluster:
    def __init__(self, tmp: Path, workers: int = 2):
        self.log = open(tmp / "cluster.log", "w")  # noqa: SIM115
        file = tmp / "scheduler.json"
        self.scheduler = _spawn(
            ["kreisel", "scheduler", "--host", "127.0.0.1", "--port", "0",
             "--dashboard-address", "127.0.0.1:0", "--scheduler-file", str(file)],
            self.log,
        )  # fmt: skip
        self.workers = []
        try:
            self._start(file, workers)
        except BaseException:
            self.close()
            raise

    def _start(self, file: Path, workers: int):
        deadline = time.time() + 60
        while time.time() < deadline:
            try:  # the scheduler may be halfway through writing the file
                self.address = json.loads(file.read_text())["address"]
                break
            except (OSError, ValueError, KeyError):
                time.sleep(0.1)
        else:
            raise RuntimeError(f"no scheduler after 60 s: see {self.log.name}")
        self.workers = [
            _spawn(
                [
                    "kreisel",
                    "worker",
                    self.address,
                    "--nthreads",
                    "1",
                    "--no-nanny",
                    "--dashboard-address",
                    "127.0.0.1:0",
                    "--memory-limit",
                    "0",
                ],
                self.log,
            )  # fmt: skip
            for _ in range(workers)
        ]
        from distributed import Client

        with Client(self.address, timeout=30, set_as_default=False) as c:
            c.wait_for_workers(workers, timeout=60)

    def close(self):
        for p in (*self.workers, self.scheduler):
            if p.poll() is None:
                p.terminate()
        for p in (*self.workers, self.scheduler):
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        self.log.close()


@pytest.fixture
def cluster(tmp_path):
    c = Cluster(tmp_path)
    yield c
    c.close()


def test_dask_cluster_equals_local_bit_for_bit(tmp_path, cluster):
    tables = play_spec()
    local = kreisel.sweep(tables, tmp_path / "local.zarr", progress=False)
    remote = kreisel.sweep(tables, tmp_path / "dask.zarr", cluster.address, progress=False)
    assert_same(local, remote)
    # a Client works as well as an address
    from distributed import Client

    with Client(cluster.address, set_as_default=False) as client:
        again = kreisel.sweep(tables, None, client, progress=False)
    assert_same(local, again)


def test_kreisel_worker_and_scheduler_run_dask_with_kreisels_settings(cluster):
    """The cluster fixture starts `kreisel scheduler` and `kreisel worker`: they are Dask's
    processes, with the profiler off and slow ticks (read back from each process)."""
    from distributed import Client

    def settings():
        import dask

        return (
            dask.config.get("distributed.worker.profile.enabled"),
            dask.config.get("distributed.admin.tick.interval"),
        )

    with Client(cluster.address, set_as_default=False) as client:
        on_workers = client.run(settings)
        on_scheduler = client.run_on_scheduler(settings)
    assert len(on_workers) == 2
    for got in [*on_workers.values(), on_scheduler]:
        assert got[0] in (False, "False") and got[1] == "1s", got


def test_dask_settings_made_by_the_user_come_first(monkeypatch):
    from kreisel._sweep import DASK_ENV, dask_command

    monkeypatch.setenv("DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL", "50ms")
    cmd, env = dask_command("worker", ["tcp://127.0.0.1:1", "--nthreads", "3"])
    assert cmd[1:] == ["-m", "distributed.cli.dask_worker", "tcp://127.0.0.1:1", "--nthreads", "3"]
    assert env["DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL"] == "50ms"
    assert env["DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED"] == "False"
    assert set(DASK_ENV) <= set(env)


def test_the_environment_sends_an_unchanged_script_to_the_cluster(tmp_path, cluster, monkeypatch):
    monkeypatch.setenv("KREISEL_SCHEDULER", cluster.address)
    tables = play_spec(output={"chunk": 6})
    ds = kreisel.sweep(tables, None, progress=False)
    from distributed import Client

    with Client(cluster.address, set_as_default=False) as client:
        # the workers ran the tasks: the scheduler remembers them
        logs = client.run_on_scheduler(
            lambda dask_scheduler: [k for k in dask_scheduler.task_prefixes]
        )
    assert "kreisel-sweep" in " ".join(map(str, logs)), logs
    monkeypatch.setenv("KREISEL_SCHEDULER", "local")
    assert_same(ds, kreisel.sweep(tables, None, progress=False))


def test_killing_a_worker_midway_still_completes_every_run(tmp_path, cluster):
    tables = play_spec(
        grid={"psi_dot": {"start": 80.0, "stop": 200.0, "num": 8}, "s": [0.004, 0.006, 0.008]},
        simulation={"t_end": 2.0, "rtol": 1e-8},
        output={"chunk": 1},
    )
    victim = cluster.workers[0]
    killed_at = []

    def kill_once(chunk, done, total):
        if victim.poll() is None:
            os.kill(victim.pid, signal.SIGKILL)
            victim.wait()
            killed_at.append(done)

    remote = kreisel.sweep(tables, tmp_path / "k.zarr", cluster.address, progress=False,
                           callback=kill_once)  # fmt: skip
    assert victim.poll() is not None and cluster.workers[1].poll() is None
    assert killed_at == [1]  # in the middle: 23 chunks were still queued or running
    assert remote.attrs["chunks_done"] == 24 and np.all(remote["status"].values == 1)
    assert_same(remote, kreisel.sweep(tables, None, progress=False))


def test_interrupted_dask_sweep_resumes_locally_with_the_same_bits(tmp_path, cluster):
    tables = play_spec()
    store = tmp_path / "d.zarr"
    count = interrupt(tables, store, 3, cluster.address)
    rest = []
    ds = kreisel.sweep(tables, store, progress=False, callback=lambda k, d, t: rest.append(k))
    assert sorted(rest + count) == list(range(4))
    assert_same(ds, kreisel.sweep(tables, None, progress=False))


# --------------------------------------------------------------------------------------
# command line and figure
# --------------------------------------------------------------------------------------

SPEC_TOML = f"""
[top]
kind = "play"
m = {M}
A = {A}
C = {C}
rho = {RHO}
friction = "viscous"
mu = 1.0
[state]
theta = 3.0
[simulation]
t_end = 2.5
rtol = 1e-8
[grid]
psi_dot = {{start = 80, stop = 200, num = 3}}
s = [0.004, 0.008]
"""


def test_command_line_writes_store_and_figure_and_resumes(tmp_path, capsys):
    from kreisel._cli import main

    spec = tmp_path / "tippe.toml"
    spec.write_text(SPEC_TOML)
    store = tmp_path / "out.zarr"
    assert main(["sweep", str(spec), "--store", str(store), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "6 runs of a play top over psi_dot, s (3 x 2): 6 done, 0 failed" in out
    assert (tmp_path / "out.png").stat().st_size > 10_000
    ds = kreisel.open_sweep(store)
    assert ds["final_u"].shape == (3, 2) and np.all(ds["status"].values == 1)
    # run again: nothing is missing, the same numbers come back
    assert main(["sweep", str(spec), "--store", str(store), "--quiet", "--no-figure"]) == 0
    assert_same(kreisel.open_sweep(store), ds)
    spec.write_text(SPEC_TOML.replace("s = [0.004, 0.008]", "s = []"))
    assert main(["sweep", str(spec), "--store", str(store), "--quiet"]) == 2
    assert "s is an empty grid" in capsys.readouterr().err


def test_the_command_line_shows_a_store_as_its_path_and_names_its_own_flag(tmp_path, capsys):
    """Not PosixPath('...') and not the library's overwrite=True alone: the path as given,
    and the command line's --overwrite."""
    from kreisel._cli import main

    spec = tmp_path / "tiny.toml"
    spec.write_text(SPEC_TOML.replace("num = 3", "num = 1").replace("[0.004, 0.008]", "[0.006]")
                    .replace("t_end = 2.5", "t_end = 0.05"))  # fmt: skip
    store = tmp_path / "out.zarr"
    assert main(["sweep", str(spec), "--store", str(store), "--quiet", "--no-figure"]) == 0
    capsys.readouterr()
    spec.write_text(spec.read_text().replace("theta = 3.0", "theta = 2.9"))
    assert main(["sweep", str(spec), "--store", str(store), "--quiet", "--no-figure"]) == 2
    err = capsys.readouterr().err.strip()
    assert "PosixPath" not in err
    assert f"store = {str(store)!r} holds another sweep" in err
    assert "--overwrite" in err
    assert main(["sweep", str(spec), "--store", str(store), "--quiet", "--no-figure",
                 "--overwrite"]) == 0  # fmt: skip
    (tmp_path / "foreign").mkdir()
    (tmp_path / "foreign" / "x.txt").write_text("mine")
    assert main(["sweep", str(spec), "--store", str(tmp_path / "foreign"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "PosixPath" not in err and repr(str(tmp_path / "foreign")) in err


def test_figures_of_grids_samples_and_modes(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from kreisel import plot

    grid = kreisel.sweep(play_spec(), None, progress=False)
    ax = plot.sweep(grid)
    assert ax.get_xlabel().startswith(r"$\dot\psi$") and ax.get_ylabel() == "s (m)"
    ax = plot.sweep(grid, "final_mode")
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["slip"]
    ax = plot.sweep(grid, "final_u", x="s", psi_dot=200.0)
    assert ax.get_title() == "final_u, psi_dot = 200" and len(ax.lines) == 1
    samples = kreisel.sweep(
        play_spec(grid={"s": [0.006]}, random={"n": 4, "psi_dot": {"low": 80, "high": 200}}),
        None,
        progress=False,
    )
    ax = plot.sweep(samples, "final_u")
    assert len(ax.collections) == 1 and len(ax.collections[0].get_offsets()) == 4
    with pytest.raises(kreisel.ParameterError, match="var = 'spin'"):
        plot.sweep(grid, "spin")


def test_exact_lagrange_sweep_maps_the_kinds_of_motion(tmp_path):
    lag = {"kind": "lagrange", "I1": 1.75e-4, "I3": 2.0e-5, "m": 0.1, "l": 0.04}
    top = kreisel.LagrangeTop(1.75e-4, 2.0e-5, 0.1, 0.04)
    slow = top.steady_precession(0.6, 300.0)[0]
    tables = {
        "top": lag,
        "state": {"theta": 0.6, "psi_dot": 300.0},
        "simulation": {"exact": True},
        "grid": {"phi_dot": [-0.5 * slow, 0.0, 0.3 * slow]},
    }
    ds = kreisel.sweep(tables, tmp_path / "kinds.zarr", progress=False)
    # below zero: loops; zero: cusps; between zero and the slow steady rate: waves
    assert list(ds["motion_kind"].values) == ["loops", "cusps", "waves"]
    for i, w in enumerate(ds["phi_dot"].values):
        a = top.analyse(top.state(0.6, phi_dot=w, psi_dot=300.0))
        assert ds["nutation_period"].values[i] == a.nutation_period
        assert ds["theta_max"].values[i] == a.theta_max
    with pytest.raises(kreisel.ParameterError, match="only a lagrange top"):
        kreisel.sweep(play_spec(simulation={"exact": True}), None, progress=False)
    with pytest.raises(kreisel.ParameterError, match="not a summary of the exact solution"):
        kreisel.sweep({**tables, "output": {"keep": ["steps"]}}, None, progress=False)


def test_tasks_shrink_toward_the_end_of_a_sweep_and_cover_every_run_once():
    from kreisel import _sweep

    tables = play_spec(grid={"psi_dot": {"start": 50.0, "stop": 250.0, "num": 10_000}},
                       output={"chunk": 700})  # fmt: skip
    tables["top"]["s"] = S
    sp = _sweep.load_spec(tables)
    todo = [k for k in range(sp.n_chunks) if k != 3]  # as in a rerun: chunk 3 is done
    sizes = {k: len(sp.chunk_values(k, {})["psi_dot"]) for k in todo}
    total = sum(sizes.values())
    assert sp.n_chunks == 15 and total == 10_000 - 700
    tasks = _sweep._tasks(sp, todo, {}, lanes=2)
    runs = [len(t[1]["psi_dot"]) for t in tasks]
    assert sum(runs) == total and max(runs) == _sweep.TASK_RUNS
    # guided: each task at most a 1/(TASK_SHARE lanes) share of what was left, down to TAIL_RUNS
    left, share = total, _sweep.TASK_SHARE * 2
    for n in runs:
        assert n <= max(_sweep.TAIL_RUNS, -(-left // share))
        left -= n
    assert runs[-2] == _sweep.TAIL_RUNS and runs[-1] <= _sweep.TAIL_RUNS
    # the tasks' sizes do not depend on the chunks: a task may span chunks or end inside one
    assert max(len(t[0]) for t in tasks) >= 2
    assert all(sum(m for _, _, m in t[0]) == len(t[1]["psi_dot"]) for t in tasks)
    # every run once, in order: the pieces run through the chunks to do, each from 0 to its
    # end, and the values are those of the chunks
    pieces = [p for t in tasks for p in t[0]]
    assert [k for k, _, _ in pieces] == sorted(k for k, _, _ in pieces)
    for k in todo:
        mine = [(a, m) for c, a, m in pieces if c == k]
        assert [a for a, _ in mine] == list(np.cumsum([0] + [m for _, m in mine])[:-1])
        assert sum(m for _, m in mine) == sizes[k]
    got = np.concatenate([t[1]["psi_dot"] for t in tasks])
    want = np.concatenate([sp.chunk_values(k, {})["psi_dot"] for k in todo])
    assert np.array_equal(got, want)


@pytest.mark.parametrize("chunk", [8, 2])
def test_tasks_that_split_or_span_chunks_give_the_same_store(tmp_path, monkeypatch, chunk):
    from kreisel import _sweep

    def tables_with(chunk):
        tables = play_spec(
            grid={"psi_dot": [80.0, 120.0, 160.0, 200.0], "height": [0.004, -0.01]},
            output={"chunk": chunk},
        )
        tables["top"]["s"] = S
        return tables

    # the reference: one chunk of all 8 runs, computed as one task (a single piece: no
    # cutting of results, whatever the chunks of the run compared with it)
    whole = kreisel.sweep(tables_with(8), tmp_path / "whole.zarr", progress=False)
    tables = tables_with(chunk)
    monkeypatch.setattr(_sweep, "TASK_RUNS", 3)  # 8 runs in tasks of 3, 3 and 2
    sp = _sweep.load_spec(tables)
    tasks = _sweep._tasks(sp, list(range(sp.n_chunks)), {})
    assert [len(t[1]["psi_dot"]) for t in tasks] == [3, 3, 2]
    # one chunk of 8 split in three; or chunks of 2 runs, which tasks of 3 span
    assert max(len(t[0]) for t in tasks) == (1 if chunk == 8 else 2)
    split = kreisel.sweep(tables, tmp_path / "split.zarr", progress=False)
    assert_same(whole, split)
    assert split.attrs["run_errors"] == whole.attrs["run_errors"]
    assert len(json.loads(split.attrs["run_errors"])) == 4  # the runs below the floor


def test_failed_runs_store_the_same_steps_wherever_they_failed(tmp_path):
    """A run that cannot start (a state error, found in Python) and a run the core refuses
    (Stoermer-Verlet on an asymmetric top) both store steps = -1, status 2 and their message;
    the one that went through stores its steps."""
    tables = {
        "top": {"kind": "heavy", "I1": 2.0, "I3": 1.0, "m": 1.0, "g": 1.0, "com": [0, 0, 0.2]},
        "state": {"psi_dot": 1.0, "phi_dot": 0.3},
        "simulation": {"t_end": 0.5, "method": "verlet", "dt": 1e-3},
        "grid": {"I2": [2.0, 2.5], "theta": [1.0, -1.0]},
        "output": {"keep": ["final_theta", "steps"]},
    }
    ds = kreisel.sweep(tables, tmp_path / "v.zarr", progress=False)
    steps, status = ds["steps"].values, ds["status"].values
    assert steps[0, 0] == 500 and status[0, 0] == 1
    assert np.all(steps[:, 1] == -1) and np.all(status[:, 1] == 2)  # theta < 0: no state
    assert steps[1, 0] == -1 and status[1, 0] == 2  # the core: verlet needs I1 == I2
    errors = json.loads(ds.attrs["run_errors"])
    assert "verlet" in errors["1,0"] and "theta" in errors["0,1"] and "theta" in errors["1,1"]


@pytest.mark.parametrize(
    ("section", "table"),
    [
        ("grid", {"psi_dot": {"start": 1.0, "stop": 2.0, "num": 10**12}}),
        ("random", {"n": 10**12, "psi_dot": {"low": 1.0, "high": 2.0}}),
    ],
)
def test_a_sweep_too_large_to_hold_is_refused_before_any_allocation(tmp_path, section, table):
    """[grid] num = 1e12 used to allocate 7 TiB; the cap is checked on
    each axis before its values are made."""
    tables = play_spec(**{section: table})
    start = time.perf_counter()
    with pytest.raises(kreisel.ParameterError, match=r"at most 100000000 runs"):
        kreisel.sweep(tables, tmp_path / "big.zarr", progress=False)
    assert time.perf_counter() - start < 5.0
    assert not (tmp_path / "big.zarr").exists()


def test_a_wrong_field_is_reported_before_nothing_is_swept(tmp_path):
    """The wrong field is named before anything else is checked."""
    tables = play_spec()
    tables.pop("grid", None)
    tables["top"].update(s=0.006, rho=1e-320)
    with pytest.raises(kreisel.ParameterError, match=r"rho = 1e-320"):
        kreisel.sweep(tables, tmp_path / "x.zarr", progress=False)


def test_a_sweep_without_progress_does_not_load_tqdm_auto():
    """tqdm.auto warns in a notebook without ipywidgets (the tutorials showed the build
    machine's path in that warning) even when no bar is shown: without progress it is not
    imported."""
    code = (
        "import sys, kreisel\n"
        "kreisel.sweep({'top': {'preset': 'tippe-ball'}, 'simulation': {'t_end': 0.01},"
        " 'grid': {'s': [0.004, 0.006]}}, None, progress=False)\n"
        "print('tqdm.auto' in sys.modules)\n"
    )
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "False"
