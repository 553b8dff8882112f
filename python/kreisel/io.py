"""Readers of recordings made with common tools, each returning :class:`kreisel.Observations`.

- :func:`read_phyphox`: phyphox's export of its gyroscope experiment (a phone's body rates).
- :func:`read_tracker`: Tracker's data export of a point tracked in a video (a camera above
  the top).

Both name the line and column they cannot read; a file of another format is refused with a
message that says what was expected.
"""

from __future__ import annotations

import csv
import io as _io
import math
import zipfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ._errors import ParameterError
from ._observations import Observations

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["read_phyphox", "read_tracker"]

#: the columns of phyphox's gyroscope export ("Raw Data" set of its "Gyroscope" experiment)
PHYPHOX_TIME = "Time (s)"
PHYPHOX_RATES = ("Gyroscope x (rad/s)", "Gyroscope y (rad/s)", "Gyroscope z (rad/s)")


def read_phyphox(
    path: str | Path,
    *,
    sigma: float | ArrayLike | None = None,
    frame: str = "sensor",
    rotation: ArrayLike = (0.0, 0.0, 0.0),
) -> Observations:
    """Body rates from phyphox's export of its gyroscope experiment.

    phyphox (RWTH Aachen's app for phone sensors) exports the "Raw Data" set of its
    "Gyroscope" experiment as one CSV file, or as a zip holding ``Raw Data.csv`` and a
    ``meta/`` folder. The first line holds the quoted column names ``"Time (s)"``,
    ``"Gyroscope x (rad/s)"``, ``"Gyroscope y (rad/s)"``, ``"Gyroscope z (rad/s)"`` (and
    ``"Absolute (rad/s)"``, not read), each further line one sample as numbers like
    ``1.234567890E-1`` (NaN for a missing one); the separator is a comma, a tab or a
    semicolon, and the decimal mark a point or (with a tab or semicolon) a comma: the five
    CSV flavours of phyphox's export dialog. Times are in s from the start of the
    measurement, rates in rad/s about the phone's axes.

    Parameters
    ----------
    path : str or Path
        The ``.csv`` file, or phyphox's ``.zip`` export.
    sigma : float or array_like, optional
        Standard deviation of one rate sample (rad/s); None: estimated by the fit.
    frame : str
        ``"sensor"`` (default: the phone's axes are not the top's principal axes; fit
        ``"sensor_rotation"``) or ``"principal"``.
    rotation : sequence of 3 floats
        Starting sensor rotation vector (rad) for ``frame="sensor"``.

    Returns
    -------
    Observations
        kind ``"body_rates"``; the times as recorded (the fitted state is the one at t = 0).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from kreisel.io import read_phyphox
    >>> text = ('"Time (s)","Gyroscope x (rad/s)","Gyroscope y (rad/s)",'
    ...         '"Gyroscope z (rad/s)","Absolute (rad/s)"\\n'
    ...         '0.000000000E0,1.000000000E-2,-2.000000000E-2,3.140000000E1,3.140000000E1\\n'
    ...         '1.000000000E-2,1.100000000E-2,-2.100000000E-2,3.139000000E1,3.139000000E1\\n')
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "Raw Data.csv"
    >>> _ = p.write_text(text)
    >>> obs = read_phyphox(p, sigma=0.01)
    >>> obs.t.tolist(), obs.values[1].tolist()
    ([0.0, 0.01], [0.011, -0.021, 31.39])
    """
    p = Path(path)
    text = _read_text(p)
    lines = text.splitlines()
    if not lines:
        raise ParameterError(f"path = {str(p)!r} is empty, which is not allowed: {_PHYPHOX_HINT}")
    header = lines[0]
    sep = next((s for s in (",", "\t", ";") if f'"{s}"' in header), None)
    if sep is None or not header.startswith('"'):
        raise ParameterError(
            f"path = {str(p)!r} is not a phyphox export: its first line {header[:80]!r} is not "
            f"a row of quoted column names; {_PHYPHOX_HINT}"
        )
    names = next(csv.reader([header], delimiter=sep))
    missing = [c for c in (PHYPHOX_TIME, *PHYPHOX_RATES) if c not in names]
    if missing:
        raise ParameterError(
            f"path = {str(p)!r} has no column {missing[0]!r}, which is needed: its columns are "
            f"{names}; {_PHYPHOX_HINT}"
        )
    cols = [names.index(c) for c in (PHYPHOX_TIME, *PHYPHOX_RATES)]
    decimal_comma = sep != ","
    data = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        cells = line.split(sep)
        row = []
        for c, name in zip(cols, (PHYPHOX_TIME, *PHYPHOX_RATES)):
            cell = cells[c] if c < len(cells) else ""
            row.append(_number(cell, decimal_comma, p, number, name))
        data.append(row)
    if not data:
        raise ParameterError(f"path = {str(p)!r} has a header but no samples, which is not allowed")
    arr = np.array(data)
    keep = ~np.isnan(arr[:, 0])  # phyphox pads a shorter column with NaN: no time, no sample
    arr = arr[keep]
    return Observations(arr[:, 0], arr[:, 1:], "body_rates", sigma=sigma, frame=frame,
                        rotation=rotation, name=f"{p.stem} (phyphox)")  # fmt: skip


_PHYPHOX_HINT = (
    'phyphox\'s gyroscope export starts with the quoted names "Time (s)", "Gyroscope x '
    '(rad/s)", "Gyroscope y (rad/s)", "Gyroscope z (rad/s)"'
)


def read_tracker(
    path: str | Path,
    *,
    axis_point: float,
    scale: float = 1.0,
    origin: ArrayLike = (0.0, 0.0),
    sigma: float | ArrayLike | None = None,
    track: str | None = None,
) -> Observations:
    """Positions of a point on the figure axis from Tracker's data export.

    Tracker (Open Source Physics' video analysis tool) exports a track's data table with
    File > Export > Data as text: a first line with the track's name (spaces written as
    ``_``), a line of column names (``t``, ``x``, ``y``, and any others the table shows),
    then one line per frame, separated by the delimiter chosen in the dialog (tab by
    default; comma, semicolon or space); an empty cell where a frame has no mark. Unformatted
    numbers look like ``1.234567890E-1``, with the decimal mark of the computer's language.
    Several tracks in one file start with a line ``#multi:``, then a line of track names,
    then the columns of each; ``track`` picks one. x and y are in the units of Tracker's
    calibration (often m or cm), pixels if none was set: ``scale`` gives metres per unit.

    Parameters
    ----------
    path : str or Path
    axis_point : float
        Distance (m) along the figure axis from the pivot to the tracked point.
    scale : float
        Metres per unit of the file's x and y (0.01 for cm; m/pixel for pixels).
    origin : sequence of 2 floats
        Where the pivot is in the file's x, y (Tracker's coordinate origin is often set on it:
        then (0, 0)).
    sigma : float, optional
        Standard deviation of one position (file units); None: estimated by the fit.
    track : str, optional
        The track to read from a ``#multi:`` file (default: the first).

    Returns
    -------
    Observations
        kind ``"axis_tip"`` (stored in metres).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from kreisel.io import read_tracker
    >>> text = ("mass_A\\nt\\tx\\ty\\n0.000000000E0\\t1.0E0\\t0.0E0\\n"
    ...         "1.666666667E-2\\t0.9E0\\t0.1E0\\n")
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "tip.txt"
    >>> _ = p.write_text(text)
    >>> obs = read_tracker(p, axis_point=0.05, scale=0.01)
    >>> obs.kind, obs.values[1].round(6).tolist()
    ('axis_tip', [0.009, 0.001])
    """
    p = Path(path)
    text = _read_text(p)
    lines = [ln.rstrip("\r\n") for ln in text.splitlines()]
    if len(lines) < 2:
        raise ParameterError(
            f"path = {str(p)!r} is too short for a Tracker export: {_TRACKER_HINT}"
        )
    multi = lines[0].strip().lower().startswith("#multi")
    head = 2 if multi else 1
    if len(lines) <= head:
        raise ParameterError(f"path = {str(p)!r} has no column names: {_TRACKER_HINT}")
    header = lines[head]
    sep = next((s for s in ("\t", ",", ";") if s in header), " ")
    names = [c.strip() for c in (header.split(sep) if sep != " " else header.split())]
    if "t" not in names or "x" not in names or "y" not in names:
        raise ParameterError(
            f"path = {str(p)!r} line {head + 1} is not Tracker's column names with t, x and y: "
            f"{header[:80]!r}; {_TRACKER_HINT}"
        )
    # which x and y: a #multi: file repeats them per track
    ti = names.index("t")
    xs = [i for i, c in enumerate(names) if c == "x"]
    ys = [i for i, c in enumerate(names) if c == "y"]
    k = 0
    if multi:
        tracks = [c.strip() for c in lines[1].split(sep) if c.strip()]
        if track is not None:
            if track not in tracks and track.replace(" ", "_") not in tracks:
                raise ParameterError(
                    f"track = {track!r} is not allowed: the tracks in {str(p)!r} are {tracks}"
                )
            k = tracks.index(track if track in tracks else track.replace(" ", "_"))
        if k >= min(len(xs), len(ys)):
            raise ParameterError(
                f"path = {str(p)!r}: track {k} has no x and y columns in line {head + 1}"
            )
    xi, yi = xs[k], ys[k]
    decimal_comma = sep != ","
    data = []
    for number, line in enumerate(lines[head + 1 :], start=head + 2):
        if not line.strip():
            continue
        cells = line.split(sep) if sep != " " else line.split()
        row = []
        for c, name in ((ti, "t"), (xi, "x"), (yi, "y")):
            cell = cells[c] if c < len(cells) else ""
            row.append(_number(cell, decimal_comma, p, number, name))
        if math.isnan(row[0]):
            raise ParameterError(f"path = {str(p)!r} line {number}, column 't' is empty")
        data.append(row)
    if not data:
        raise ParameterError(f"path = {str(p)!r} has column names but no samples")
    arr = np.array(data)
    if multi:
        name = tracks[k]
    else:
        name = lines[0].strip().replace("_", " ") or "track"
    return Observations(arr[:, 0], arr[:, 1:], "axis_tip", sigma=sigma, scale=scale,
                        axis_point=axis_point, origin=origin, name=f"{name} (Tracker)")  # fmt: skip


_TRACKER_HINT = (
    "Tracker's data export is a line with the track's name, a line of column names with t, x "
    "and y, then one line per frame"
)


def _read_text(p: Path) -> str:
    if not p.is_file():
        raise ParameterError(f"path = {str(p)!r} is not allowed: there is no such file")
    raw = p.read_bytes()
    if raw[:4] == b"PK\x03\x04":
        with zipfile.ZipFile(_io.BytesIO(raw)) as z:
            names = [n for n in z.namelist() if n.endswith(".csv") and not n.startswith("meta/")]
            if not names:
                raise ParameterError(
                    f"path = {str(p)!r} is a zip file without a data CSV file (it holds "
                    f"{z.namelist()[:5]})"
                )
            raw = z.read(names[0])
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise ParameterError(
            f"path = {str(p)!r} is not a text file (byte {e.start} is not UTF-8)"
        ) from None


def _number(cell: str, decimal_comma: bool, p: Path, line: int, column: str) -> float:
    s = cell.strip().strip('"')
    if s == "" or s.lower() == "nan":
        return math.nan
    if decimal_comma:
        s = s.replace(",", ".")
    try:
        x = float(s)
    except ValueError:
        raise ParameterError(
            f"path = {str(p)!r} line {line}, column {column!r}: {cell.strip()!r} is not a number"
        ) from None
    if not math.isfinite(x):
        raise ParameterError(
            f"path = {str(p)!r} line {line}, column {column!r}: {cell.strip()!r} is not finite"
        )
    return x
