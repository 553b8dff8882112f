"""`kreisel atlas` as a user runs it: files written and decodable, bad input exits 2."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest


def _kreisel(*args, cwd):
    return subprocess.run(
        [sys.executable, "-m", "kreisel", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env={**os.environ, "MPLBACKEND": "Agg"},
        timeout=120,
    )


def test_atlas_with_a_preset_writes_three_figures(tmp_path):
    pytest.importorskip("matplotlib")
    from PIL import Image

    proc = _kreisel("atlas", "--preset", "tippe", "--out", str(tmp_path / "a"), cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "zone" in proc.stdout
    for name in ("atlas.png", "vertical_axis.png", "J_R.png"):
        with Image.open(tmp_path / "a" / name) as im:
            assert im.size[0] > 300


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--preset", "toy"), "preset = 'toy'"),
        (("--m", "1"), "missing"),
        (("--m", "-1", "--A", "1", "--C", "1", "--s", "0.1", "--rho", "1"), "m = -1"),
    ],
)
def test_atlas_bad_input_is_one_line_and_exit_2(tmp_path, args, needle):
    proc = _kreisel("atlas", *args, "--out", str(tmp_path / "b"), cwd=tmp_path)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], proc.stderr
