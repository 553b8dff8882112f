"""The README's tour runs as written (so the README stays true)."""

import os
import pathlib
import re

import pytest

README = pathlib.Path(__file__).resolve().parents[1] / "README.md"


def test_readme_tour_runs(monkeypatch, tmp_path):
    pytest.importorskip("matplotlib")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)  # the tour writes files
    import matplotlib

    matplotlib.use("Agg")
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "the README has a python tour"
    namespace = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), namespace)
    import matplotlib.pyplot as plt

    plt.close("all")
    assert os.environ["MPLBACKEND"] == "Agg"
