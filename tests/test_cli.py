"""The command line as a user drives it: subprocesses of the installed ``kreisel`` script.

Every output file is opened with an independent reader (xarray for NetCDF, pandas for CSV,
Pillow for PNG, imageio for GIF and MP4); every bad input ends with exit code 2 and one line
on stderr that names the field.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from kreisel import simulate
from kreisel._presets import PRESETS as _PRESETS

PRESET_NAMES = list(_PRESETS)

SCRIPT = Path(sys.executable).with_name("kreisel")
KREISEL = [str(SCRIPT)] if SCRIPT.exists() else [sys.executable, "-m", "kreisel"]
ENV = {**os.environ, "MPLBACKEND": "Agg"}


def kreisel(*args, cwd=None, check=True):
    proc = subprocess.run(
        [*KREISEL, *map(str, args)], capture_output=True, text=True, cwd=cwd, env=ENV, timeout=300
    )
    if check and proc.returncode != 0:
        raise AssertionError(f"kreisel {args} exited {proc.returncode}:\n{proc.stderr}")
    return proc


def png_ok(path: Path):
    from PIL import Image

    with Image.open(path) as im:
        im.load()
        assert im.format == "PNG"
        assert im.width >= 400 and im.height >= 300, (path, im.size)


def gif_frames(path: Path) -> int:
    import imageio.v3 as iio

    return iio.imread(path, index=None).shape[0]


def mp4_frames(path: Path) -> int:
    """Frames decoded by the ffmpeg that imageio-ffmpeg ships (each of the full size)."""
    import gc
    import warnings

    import imageio_ffmpeg

    # imageio-ffmpeg leaves its pipe to ffmpeg for the garbage collector to close
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)
        gen = imageio_ffmpeg.read_frames(str(path))
        try:
            meta = next(gen)
            w, h = meta["size"]
            sizes = [len(frame) for frame in gen]
        finally:
            gen.close()
            del gen
            gc.collect()
    assert (w, h) == (480, 480) and set(sizes) == {w * h * 3}
    return len(sizes)


def test_demo_writes_its_report_figures_and_gif(tmp_path):
    proc = kreisel("demo", "--out", tmp_path / "out")
    out = tmp_path / "out"
    expected = [
        "lagrange_axis_paths.png",
        "lagrange_effective_potential.png",
        "tippe_top.png",
        "tippe_track.png",
        "tippe_top.gif",
        "tippe_sweep.png",
        "report.md",
    ]
    for name in expected:
        assert (out / name).is_file(), name
    assert f"wrote {out / 'report.md'}" in proc.stdout
    report = (out / "report.md").read_text()
    for name in expected[:-1]:
        assert f"({name})" in report, f"report.md links {name}"
        if name.endswith(".png"):
            png_ok(out / name)
    for kind in ("waves", "cusps", "loops"):
        assert f"| {kind} | {kind} |" in report
    # the real tippe top, with its peg, not the ball alone with a painted stem: onto the peg
    # at 1.37 s (Leine and Glocker's top inverts in about 1.4 s) and back onto the ball
    assert "Leine and Glocker's tippe top" in report and "name='peg'" in report
    assert "the peg touches down at t = 1.37" in report
    assert "it falls back onto its ball at t = 4.55" in report
    assert gif_frames(out / "tippe_top.gif") == 60
    from kreisel import open_sweep

    sweep = open_sweep(out / "tippe_sweep.zarr")
    assert sweep["final_u"].shape == (12, 12) and (sweep["status"].values == 1).all()
    assert f"{np.isfinite(sweep['inversion_time'].values).sum()} turn over" in report


def test_lagrange_preset_writes_netcdf_summary_figures_and_gif(tmp_path):
    import xarray as xr

    out = tmp_path / "cusps"
    proc = kreisel("lagrange", "--preset", "cusps", "--out", out, "--animate", "gif",
                   "--frames", 8)  # fmt: skip
    assert "motion: cusps" in proc.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["kind"] == "lagrange" and summary["preset"] == "cusps"
    assert summary["analysis"]["motion"] == "cusps"
    assert summary["simulation"]["solver"] == "exact"
    # the exact solution keeps its integrals to round-off
    assert max(summary["result"]["invariant_drift"].values()) < 1e-12
    files = summary["files"]
    assert files["trajectory"] == "trajectory.nc" and files["animation"] == "animation.gif"
    with xr.open_dataset(out / "trajectory.nc", engine="scipy") as ds:
        assert ds.sizes["t"] == 2001
        assert ds["theta"].attrs["units"] == "rad"
        theta = ds["theta"].values
        assert theta.min() == pytest.approx(0.6, abs=1e-9)
        assert theta.max() == pytest.approx(summary["analysis"]["theta_max"], abs=1e-6)
        assert "LagrangeTop" in ds.attrs["model"]
    for name in files["figures"]:
        png_ok(out / name)
    assert set(files["figures"]) == {
        "time_series.png", "axis_path.png", "invariant_drift.png", "effective_potential.png"
    }  # fmt: skip
    assert gif_frames(out / "animation.gif") == 8


def test_heavy_writes_csv_and_an_mp4_with_the_frames_asked_for(tmp_path):
    import pandas as pd

    out = tmp_path / "kov"
    kreisel("heavy", "--preset", "kovalevskaya", "--t-end", 2, "--format", "csv",
            "--animate", "mp4", "--frames", 12, "--out", out, "--samples", 201)  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    assert summary["analysis"]["kind"] == "kovalevskaya"
    assert set(summary["result"]["invariant_drift"]) == {"energy", "Mz", "kovalevskaya"}
    df = pd.read_csv(out / "trajectory.csv", index_col="t")
    assert len(df) == 201
    q = df[["quaternion_w", "quaternion_x", "quaternion_y", "quaternion_z"]].to_numpy()
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    assert mp4_frames(out / "animation.mp4") == 12
    for name in summary["files"]["figures"]:
        png_ok(out / name)


def test_play_writes_an_interactive_html_view(tmp_path):
    out = tmp_path / "tippe"
    proc = kreisel("play", "--preset", "tippe-ball", "--t-end", 3, "--animate", "html",
                   "--frames", 6, "--no-figures", "--out", out)  # fmt: skip
    assert "(a tippe top)" in proc.stdout
    summary = json.loads((out / "summary.json").read_text())
    # BENCHMARKS case T1: u rises through 0.9 at 2.65 s (the demo's number)
    assert summary["result"]["inversion_time"] == pytest.approx(2.65, abs=0.02)
    assert "figures" not in summary["files"]
    page = (out / "animation.html").read_text()
    assert page.count('"name":"5"') + page.count('"name": "5"') >= 1  # the 6th frame
    assert "plotly" in page.lower() and len(page) > 1_000_000  # plotly.js is inside


def test_the_tippe_preset_turns_over_onto_its_peg_and_nothing_drawn_enters_the_floor(tmp_path):
    """The preset is Leine and Glocker's top (theory: bodies of revolution): the peg first touches
    at 1.371 s
    (tests/test_peg.py checks the physics); the animation draws the parts as they are."""
    import xarray as xr

    from kreisel import animate

    out = tmp_path / "tippe"
    proc = kreisel("play", "--preset", "tippe", "--t-end", 3, "--animate", "gif",
                   "--frames", 8, "--no-figures", "--out", out)  # fmt: skip
    assert "peg touches 1.37" in proc.stdout and "on the floor at the end: peg" in proc.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["result"]["parts"]["peg"]["first_touchdown"] == pytest.approx(1.371, abs=1e-3)
    assert (out / "animation.gif").stat().st_size > 10_000
    # every vertex of the drawn body, at every frame of a fine sampling, is above the floor
    problem = kreisel_config_problem("tippe")
    traj = simulate(problem.model, problem.state, 3.0)
    shape = animate.shape_of(problem.model)
    verts, _ = animate._mesh(shape, 24)

    def lowest(times):
        frames = animate._at(traj, problem.model, times)
        world = np.einsum("fij,abj->fabi", frames.rotation, verts + shape.centre)
        return (world + frames.origin[:, None, None, :])[..., 2].min()

    # at the computed states exactly; between them the frames interpolate (slerp), which
    # may dip by a few micrometres on this 3 cm body
    assert lowest(traj.t[::5]) > -1e-9
    assert lowest(np.linspace(0.0, 3.0, 300)) > -1e-5
    ds = xr.open_dataset(out / "trajectory.nc")
    assert list(ds["part"].values) == ["ball", "peg"]


def kreisel_config_problem(name):
    from kreisel._config import from_tables, preset

    return from_tables(preset(name))


def test_flags_alone_describe_a_top(tmp_path):
    import xarray as xr

    out = tmp_path / "flags"
    kreisel("lagrange", "--I1", 1.0, "--I3", 0.5, "--m", 1.0, "--l", 0.3, "--g", 1.0,
            "--theta", 1.0, "--theta-dot", 0.3, "--phi-dot", 0.7, "--psi-dot", 5.0,
            "--method", "splitting", "--dt", 1e-3, "--t-end", 5, "--samples", 101,
            "--no-figures", "--out", out)  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    assert summary["simulation"]["solver"] == "splitting"
    assert summary["analysis"]["motion"] == "loops"  # the top of the order tests
    assert summary["result"]["invariant_drift"]["Mz"] < 1e-13  # the splitting keeps Mz
    with xr.open_dataset(out / "trajectory.nc", engine="scipy") as ds:
        assert ds.sizes["t"] == 101
        assert ds.sizes["component"] == 4


def test_a_preset_printed_as_toml_runs_the_same(tmp_path):
    text = kreisel("presets", "--toml", "waves").stdout
    path = tmp_path / "waves.toml"
    path.write_text(text)
    kreisel("run", path, "--no-figures", cwd=tmp_path)
    summary = json.loads((tmp_path / "kreisel-out" / "waves" / "summary.json").read_text())
    assert summary["analysis"]["motion"] == "waves"
    assert summary["top"]["kind"] == "lagrange"


def test_a_toml_file_overrides_a_preset(tmp_path):
    path = tmp_path / "top.toml"
    path.write_text('[top]\npreset = "gyroscope"\nm = 0.19\n\n[state]\npsi_dot = 900.0\n\n'
                    '[simulation]\nt_end = 0.5\nsamples = 51\n')  # fmt: skip
    kreisel("run", path, "--no-figures", "--out", tmp_path / "o")
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["top"]["m"] == 0.19 and summary["top"]["I3"] == 1.024e-4
    assert summary["state"]["psi_dot"] == 900.0 and summary["state"]["theta"] > 1.5
    assert summary["result"]["samples"] == 51


def test_presets_lists_every_preset():
    from kreisel._presets import PRESETS

    out = kreisel("presets").stdout
    for name in PRESETS:
        assert name in out
    assert len(PRESETS) >= 11


@pytest.mark.parametrize("command", [[], ["demo"], ["presets"], ["lagrange"], ["heavy"],
                                     ["play"], ["run"]])  # fmt: skip
def test_every_command_has_help(command):
    proc = kreisel(*command, "--help")
    assert proc.stdout.startswith("Usage: kreisel")
    assert proc.stderr == ""


BAD = {
    "unknown TOML field": (["run", "{bad_field}"], "mass"),
    "unknown TOML table": (["run", "{bad_table}"], "[output]"),
    "negative mass in TOML": (["run", "{negative_mass}"], "m = -0.1"),
    "malformed TOML": (["run", "{malformed}"], "not valid TOML"),
    "missing TOML file": (["run", "{missing}"], "does not exist"),
    "unknown preset": (["lagrange", "--preset", "nope"], "known presets are"),
    "preset of another kind": (["lagrange", "--preset", "tippe"], "kreisel play --preset tippe"),
    "negative mass flag": (["play", "--preset", "tippe", "--m", "-1"], "m = -1"),
    "missing parameter": (
        ["heavy", "--I1", "1", "--I2", "1", "--I3", "1", "--m", "1", "--theta", "0.1"],
        "com is missing",
    ),  # fmt: skip
    "not a number": (["play", "--preset", "tippe", "--mu", "abc"], "'--mu'"),
    "unknown friction": (["play", "--preset", "tippe", "--friction", "glue"], "'coulomb'"),
    "unknown flag": (["lagrange", "--preset", "toy", "--mass", "1"], "--mass"),
    "unknown method": (
        ["heavy", "--preset", "kovalevskaya", "--method", "euler"],
        "known methods are",
    ),  # fmt: skip
    "fixed step without dt": (["lagrange", "--preset", "toy", "--method", "rk4"], "dt is missing"),
    "exact and method": (
        ["lagrange", "--preset", "toy", "--exact", "--method", "rk4"],
        "exact",
    ),  # fmt: skip
    "theta out of range": (["lagrange", "--preset", "toy", "--theta", "4"], "theta = 4"),
    "Euler and quaternion": (
        ["heavy", "--preset", "kovalevskaya", "--theta", "0.3", "--quaternion", "1", "0", "0", "0"],
        "not both",
    ),  # fmt: skip
    "negative duration": (["play", "--preset", "tippe", "--t-end", "-1"], "t_end"),
    "too few frames": (["play", "--preset", "tippe", "--frames", "1"], "--frames"),
    "unknown command": (["spin"], "spin"),
}


@pytest.fixture(scope="module")
def bad_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad")
    good = '[top]\nkind = "lagrange"\nI1 = 1.75e-4\nI3 = 2e-5\nm = 0.1\nl = 0.04\n'
    files = {
        "bad_field": good + "mass = 3\n[state]\ntheta = 0.5\n",
        "bad_table": good + "[state]\ntheta = 0.5\n[output]\nformat = 'csv'\n",
        "negative_mass": good.replace("m = 0.1", "m = -0.1") + "[state]\ntheta = 0.5\n",
        "malformed": '[top]\nkind = "lagrange"\nI1 = \n',
    }
    paths = {}
    for name, text in files.items():
        paths[name] = d / f"{name}.toml"
        paths[name].write_text(text)
    paths["missing"] = d / "missing.toml"
    return paths


@pytest.mark.parametrize("case", list(BAD))
def test_bad_input_exits_2_with_one_line(case, bad_files, tmp_path):
    args, needle = BAD[case]
    args = [a.format(**bad_files) for a in args]
    proc = kreisel(*args, "--out", tmp_path / "o", check=False) if args[0] != "spin" else (
        kreisel(*args, check=False))  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("kreisel"), lines[0]
    assert "Traceback" not in proc.stderr
    if needle is not None:
        assert needle in lines[0], lines[0]
    # nothing was written
    assert not (tmp_path / "o").exists()


def test_the_readme_toml_example_runs(tmp_path):
    import re

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    block, sweep_block = re.findall(r"```toml\n(.*?)```", readme, flags=re.S)
    path = tmp_path / "top.toml"
    path.write_text(block)
    proc = kreisel("run", path, "--no-figures", "--out", tmp_path / "o")
    assert "u rose through 0.9" in proc.stdout
    # the sweep tables on the run file with its swept fields left out, as the README says
    from kreisel import SweepSpec
    from kreisel._config import read_toml

    path.write_text(block + sweep_block)
    tables = read_toml(path)
    for table in ("top", "state"):
        for name in list(tables[table]):
            if name in tables["grid"] or name in tables["random"]:
                del tables[table][name]
    spec = SweepSpec.from_tables(tables)
    assert spec.dims == ("s", "psi_dot", "sample") and spec.size == 23 * 4 * 1000


def test_another_friction_law_takes_its_own_coefficient(tmp_path):
    # the tippe preset is viscous with mu = 1 s/m; Coulomb's default is 0.3, none has none
    for law, shown in (("coulomb", "Coulomb(mu=0.3)"), ("none", "Frictionless()")):
        kreisel("play", "--preset", "tippe", "--friction", law, "--t-end", 0.2, "--no-figures",
                "--out", tmp_path / law)  # fmt: skip
        summary = json.loads((tmp_path / law / "summary.json").read_text())
        assert f"friction={shown}" in summary["top"]["repr"]


@pytest.mark.parametrize("name", sorted(PRESET_NAMES))
def test_every_preset_printed_as_toml_reruns_its_own_run(name, tmp_path, capsys):
    """`kreisel presets --toml NAME` is a TOML file (read by the standard library's parser)
    that `kreisel run` turns into the very run of the preset: the same top, state and
    settings, so the same trajectory, number for number."""
    import tomllib

    from kreisel._cli import main
    from kreisel._config import from_tables, preset, read_toml
    from kreisel._run import compute

    assert main(["presets", "--toml", name]) == 0
    text = capsys.readouterr().out
    tomllib.loads(text)  # valid TOML, whatever kreisel makes of it
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    via_file = compute(from_tables(read_toml(path), prefix="table", source=path.name))
    direct = compute(from_tables(preset(name)))
    assert via_file.columns == direct.columns
    assert len(via_file) == len(direct) > 1
    for column in direct.columns:
        np.testing.assert_array_equal(via_file[column], direct[column], err_msg=column)


def test_a_preset_with_parts_runs_from_its_toml_file(tmp_path):
    """The user's round trip: `kreisel presets --toml tippe > top.toml && kreisel run top.toml`
    (the tippe top is made of two parts, written as [[top.shape]] tables)."""
    path = tmp_path / "top.toml"
    path.write_text(kreisel("presets", "--toml", "tippe").stdout)
    assert "[[top.shape]]" in path.read_text()
    kreisel("run", path, "--no-figures", "--out", tmp_path / "o")
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert [p["name"] for p in summary["top"]["shape"]] == ["ball", "peg"]
    assert summary["result"]["inversion_time"] is not None


@pytest.mark.parametrize("flag", ["--s", "--rho"])
def test_a_tip_field_on_a_top_of_parts_says_what_clashes(flag):
    proc = kreisel("play", "--preset", "tippe", flag, "0.01", check=False)
    assert proc.returncode == 2
    err = proc.stderr
    assert "missing" not in err
    assert f"{flag[2:]} = 0.01 clashes with the shape of preset 'tippe'" in err
    assert "(ball, peg)" in err and "[[top.shape]]" in err
    assert "kreisel presets --toml tippe" in err


def test_play_help_lists_only_the_presets_play_takes():
    from kreisel._presets import PRESETS

    text = " ".join(kreisel("play", "--help").stdout.split())
    listed = text.split("start from a built-in play top:", 1)[1].split("--t-end", 1)[0]
    names = {n.strip() for n in listed.split(",")}
    assert names == {n for n, p in PRESETS.items() if p.kind == "play"}
    for n in names:  # and play takes each of them
        assert PRESETS[n].kind == "play"


def _preset_run(name, tmp_path):
    from kreisel._config import from_tables, preset
    from kreisel._run import run

    problem = from_tables(preset(name))
    return run(problem, tmp_path / name, figures=False)


def _times(summary: str) -> list[float]:
    import re

    return [float(x) for x in re.findall(r"at (\d+\.\d+) s", summary)]


def _event(result, name, part=None, after=-1.0):
    return next(e["t"] for e in result["events"]
                if e["name"] == name and e.get("part") == part and e["t"] > after)  # fmt: skip


@pytest.mark.parametrize("name", ["tippe", "tippe-ball", "euler-disk", "coin", "toy-top"])
def test_the_times_in_a_preset_description_are_those_of_its_run(name, tmp_path):
    """`kreisel presets` says when things happen; each time is the run's, to its digits."""
    summary = _PRESETS[name].summary
    result = _preset_run(name, tmp_path)["result"]
    if name == "tippe":
        peg = _event(result, "touchdown", "peg")
        measured = [peg, _event(result, "touchdown", "ball", after=peg)]
    elif name == "tippe-ball":
        measured = [result["inversion_time"]]
    elif name in ("euler-disk", "coin"):
        measured = [_event(result, "flat", "lower_rim")]
    else:
        measured = [_event(result, "touchdown", "shoulder"), _event(result, "rest")]
    stated = _times(summary)
    assert len(stated) == len(measured)
    for s, m in zip(stated, measured):
        digits = len(str(s).split(".")[1])
        assert round(m, digits) == s, (summary, measured)


def test_the_other_preset_descriptions_say_what_their_runs_do(tmp_path):
    runs = {n: _preset_run(n, tmp_path) for n in ("egg", "blunt", "pointed", "rate-gyro",
                                                 "toy", "sleeping", "gyroscope")}  # fmt: skip
    egg = runs["egg"]["result"]["final"]["u"]
    assert "rises to u = 0.88 in 3 s" in _PRESETS["egg"].summary and round(egg, 2) == 0.88
    blunt = runs["blunt"]["result"]
    assert any(e["name"] == "lift_off" for e in blunt["events"])  # "it hops"
    assert blunt["final"]["u"] > 0.999  # "then rises upright"
    assert abs(runs["pointed"]["result"]["final"]["u"] - np.cos(0.3)) < 0.01
    gyro = runs["rate-gyro"]["result"]["final"]
    assert round(gyro["phi"] / 0.2 * 1e3) == 7  # "drifts at 7 mrad/s"
    assert runs["toy"]["analysis"]["motion"] == "cusps"
    assert runs["sleeping"]["analysis"]["theta_max"] < 0.07  # stays within 4 degrees
    a = runs["gyroscope"]["analysis"]
    assert a["motion"] == "regular_precession" and a["theta_max"] - a["theta_min"] < 1e-12


@pytest.mark.parametrize("page", ["README.md", "docs/guide/cli.md"])
def test_the_readme_and_the_guide_list_every_preset(page):
    import re

    text = (Path(__file__).parents[1] / page).read_text()
    block = re.search(r"kreisel presets +# (.*?)\n +kreisel (?:atlas|lagrange)", text,
                      flags=re.S).group(1)  # fmt: skip
    listed = {n.strip(" ,#\n") for n in re.split(r"[,\n]", block) if n.strip(" ,#\n")}
    assert listed == set(_PRESETS)


def test_figures_and_animations_report_their_progress_on_stderr(tmp_path):
    """Off a terminal (a pipe, a log) the seconds that figures and the animation take are
    not silent: a line per stage and per tenth of the frames, each with the time so far."""
    import re

    proc = kreisel("lagrange", "--preset", "cusps", "--animate", "gif", "--frames", "20",
                   "--out", tmp_path / "o")  # fmt: skip
    lines = proc.stderr.strip().splitlines()
    stages = [re.fullmatch(r"kreisel lagrange: (.*) \((\d+\.\d) s\)", ln) for ln in lines]
    assert all(stages), lines
    said = [m.group(1) for m in stages]
    times = [float(m.group(2)) for m in stages]
    assert times == sorted(times)
    for stage in ("computing the motion", "drawing time_series.png",
                  "drawing effective_potential.png", "rendering animation.gif",
                  "writing animation.gif", "done"):  # fmt: skip
        assert stage in said, said
    assert sum(s.startswith("rendering animation.gif, ") for s in said) >= 5


def test_the_atlas_reports_each_figure_it_draws(tmp_path):
    proc = kreisel("atlas", "--preset", "tippe-ball", "--out", tmp_path / "a")
    for name in ("atlas.png", "vertical_axis.png", "J_R.png"):
        assert f"kreisel atlas: drawing {name} (" in proc.stderr


@pytest.mark.parametrize("name", [n for n, p in _PRESETS.items() if "shape" in p.top])
def test_the_explorers_toml_export_of_a_top_of_parts_reruns_it(name, tmp_path):
    """The explorer's "Download TOML" (kreisel.explore._api.toml) of a preset made of parts
    is valid TOML that kreisel run turns into the same run as the page's."""
    import tomllib

    from kreisel._config import from_tables, preset, read_toml
    from kreisel._run import compute
    from kreisel.explore import _api

    page = _api.problem(preset(name))
    text = _api.toml(page)
    tomllib.loads(text)
    path = tmp_path / "export.toml"
    path.write_text(text)
    again = compute(from_tables(read_toml(path), prefix="table"))
    run = compute(page)
    for column in run.columns:
        np.testing.assert_array_equal(again[column], run[column], err_msg=column)
