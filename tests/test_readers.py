"""kreisel.io reads the files phyphox and Tracker export, and names what it cannot read.

The files are written here the way each tool writes them (from their sources: phyphox's
DataExport.java and the "Raw Data" set of its gyroscope experiment; Tracker's
ExportDataDialog.java and TrackerIO.getData): Java's number pattern ``0.000000000E0``,
quoted column names in phyphox's first line, the track's name then the column names in
Tracker's.
"""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

import kreisel
from kreisel.io import read_phyphox, read_tracker

NAMES = ['"Time (s)"', '"Gyroscope x (rad/s)"', '"Gyroscope y (rad/s)"', '"Gyroscope z (rad/s)"',
         '"Absolute (rad/s)"']  # fmt: skip


def java_sci(x: float, decimal: str = ".") -> str:
    """``x`` as Java's DecimalFormat("0.000000000E0") writes it: 1.234567890E-1, 0.000000000E0."""
    if np.isnan(x):
        return "NaN"
    mantissa, exponent = f"{x:.9E}".split("E")
    return f"{mantissa}E{int(exponent)}".replace(".", decimal)


def _recording(n=50, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01 + 0.0123
    w = rng.normal(0.0, 3.0, (n, 3))
    return t, w


def _phyphox_text(t, w, sep=",", decimal="."):
    rows = [sep.join(NAMES)]
    for ti, wi in zip(t, w):
        cells = [ti, *wi, float(np.linalg.norm(wi))]
        rows.append(sep.join(java_sci(c, decimal) for c in cells))
    return "\n".join(rows) + "\n"


# the five CSV flavours of phyphox's export dialog
FLAVOURS = [(",", "."), ("\t", "."), (";", "."), ("\t", ","), (";", ",")]


@pytest.mark.parametrize(("sep", "decimal"), FLAVOURS)
def test_phyphox_csv_round_trip(tmp_path, sep, decimal):
    t, w = _recording()
    p = tmp_path / "Raw Data.csv"
    p.write_text(_phyphox_text(t, w, sep, decimal))
    obs = read_phyphox(p, sigma=0.01)
    assert obs.kind == "body_rates" and obs.frame == "sensor"
    assert np.allclose(obs.t, t, rtol=1e-9) and np.allclose(obs.values, w, rtol=1e-9)


def test_phyphox_zip_export_round_trip_and_padding(tmp_path):
    t, w = _recording()
    w[5, 1] = np.nan  # a missing sample
    text = _phyphox_text(t, w) + "NaN,NaN,NaN,NaN,NaN\n"  # a shorter column padded by phyphox
    p = tmp_path / "Gyroscope 2026-11-25 10-00-00.zip"
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("Raw Data.csv", text)
        z.writestr("meta/device.csv", '"property","value"\n"model","phone"\n')
    obs = read_phyphox(p, frame="principal")
    assert len(obs.t) == len(t) and np.isnan(obs.values[5, 1])
    assert np.allclose(obs.values[6:], w[6:], rtol=1e-9)


def test_phyphox_bad_files_are_named(tmp_path):
    t, w = _recording(5)
    p = tmp_path / "a.csv"
    p.write_text(_phyphox_text(t, w).replace('"Gyroscope y (rad/s)"', '"Gyro y"'))
    with pytest.raises(kreisel.ParameterError, match=r"no column 'Gyroscope y \(rad/s\)'"):
        read_phyphox(p)
    text = _phyphox_text(t, w).splitlines()
    text[3] = text[3].replace("E", "x", 1)
    p.write_text("\n".join(text))
    with pytest.raises(kreisel.ParameterError, match=r"line 4, column 'Time \(s\)'.*not a number"):
        read_phyphox(p)
    p.write_text("mass_A\nt\tx\ty\n0.0\t1.0\t2.0\n")  # a Tracker file
    with pytest.raises(kreisel.ParameterError, match="is not a phyphox export"):
        read_phyphox(p)
    p.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe")
    with pytest.raises(kreisel.ParameterError, match="not a text file"):
        read_phyphox(p)
    p.write_text("")
    with pytest.raises(kreisel.ParameterError, match="is empty"):
        read_phyphox(p)
    with pytest.raises(kreisel.ParameterError, match="no such file"):
        read_phyphox(tmp_path / "missing.csv")
    p.write_text(_phyphox_text([0.0, 0.02, 0.01], np.zeros((3, 3))))
    with pytest.raises(kreisel.ParameterError, match=r"t\[2\] = 0.01 .*earlier than"):
        read_phyphox(p)


def _tracker_text(t, xy, name="tip of axis", sep="\t", decimal=".", extra=True):
    cols = ["t", "x", "y"] + (["r", "v_{x}"] if extra else [])
    rows = [name.replace(" ", "_"), sep.join(cols)]
    for i, (ti, (x, y)) in enumerate(zip(t, xy)):
        cells = [java_sci(ti, decimal), java_sci(x, decimal), java_sci(y, decimal)]
        if extra:
            v = "" if i in (0, len(t) - 1) else java_sci(1.0, decimal)
            cells += [java_sci(float(np.hypot(x, y)), decimal), v]
        rows.append(sep.join(c if c != "NaN" else "" for c in cells))
    return "\n".join(rows) + "\n"


@pytest.mark.parametrize(("sep", "decimal"), [("\t", "."), (",", "."), (";", ","), ("\t", ",")])
def test_tracker_export_round_trip(tmp_path, sep, decimal):
    t = np.arange(40) / 60.0
    xy = np.stack([2.0 * np.cos(t), 2.0 * np.sin(t)], axis=1)  # cm
    xy[7] = np.nan  # a frame without a mark
    p = tmp_path / "tip.txt"
    p.write_text(_tracker_text(t, xy, sep=sep, decimal=decimal))
    obs = read_tracker(p, axis_point=0.05, scale=0.01, origin=(0.5, 0.0), sigma=0.1)
    assert obs.kind == "axis_tip" and obs.name.startswith("tip of axis")
    assert np.allclose(obs.t, t, rtol=1e-9)
    expected = (xy - [0.5, 0.0]) * 0.01
    assert np.isnan(obs.values[7]).all()
    assert np.allclose(obs.values[8:], expected[8:], rtol=1e-8)
    assert np.allclose(obs.sigma, 1e-3)


def test_tracker_multi_track_export_picks_the_track(tmp_path):
    t = np.arange(5) / 30.0
    lines = ["#multi:", "mass_A\t\tmass_B\t", "t\tx\ty\tx\ty"]
    for ti in t:
        lines.append("\t".join(java_sci(v) for v in (ti, 1.0, 2.0, 3.0 + ti, 4.0)))
    p = tmp_path / "two.txt"
    p.write_text("\n".join(lines) + "\n")
    obs = read_tracker(p, axis_point=0.05, track="mass B")
    assert np.allclose(obs.values[:, 0], 3.0 + t) and obs.name.startswith("mass_B")
    with pytest.raises(kreisel.ParameterError, match=r"track = 'mass C'.*\['mass_A', 'mass_B'\]"):
        read_tracker(p, axis_point=0.05, track="mass C")


def test_tracker_bad_files_are_named(tmp_path):
    t = np.arange(5) / 30.0
    xy = np.ones((5, 2))
    p = tmp_path / "tip.txt"
    p.write_text(_tracker_text(t, xy).replace("\tx\t", "\tX\t"))
    with pytest.raises(kreisel.ParameterError, match="line 2 is not Tracker's column names"):
        read_tracker(p, axis_point=0.05)
    text = _tracker_text(t, xy).splitlines()
    cells = text[4].split("\t")
    cells[1] = "1.0.0E0"
    text[4] = "\t".join(cells)
    p.write_text("\n".join(text))
    with pytest.raises(kreisel.ParameterError, match=r"line 5, column 'x'.*not a number"):
        read_tracker(p, axis_point=0.05)
    t_, w = _recording(5)
    p.write_text(_phyphox_text(t_, w))  # a phyphox file
    with pytest.raises(kreisel.ParameterError, match="not Tracker's column names"):
        read_tracker(p, axis_point=0.05)
    p.write_text("only one line")
    with pytest.raises(kreisel.ParameterError, match="too short for a Tracker export"):
        read_tracker(p, axis_point=0.05)
