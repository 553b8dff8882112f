"""The gallery runs: every script in examples/ writes its figure or animation, fast.

Each script runs as a user who downloaded it from the site would run it: copied alone into an
empty folder (nothing else of examples/ next to it), in a subprocess with that folder as its
working directory and the output folder as its argument, two at a time. Its docstring names
the file it writes; that file must exist and open.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SCRIPTS = sorted(p for p in EXAMPLES.glob("*.py") if not p.name.startswith("_"))
LIMIT_S = 15.0  # each script takes under ~5 s alone; the margin is for a busy 2-core machine


def _run(script: Path, out: Path):
    alone = out.parent / f"{script.stem}-downloaded"
    alone.mkdir(parents=True)
    shutil.copyfile(script, alone / script.name)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, script.name, str(out)], capture_output=True, text=True, timeout=120,
        env={**env, "MPLBACKEND": "Agg"}, cwd=alone,
    )  # fmt: skip
    return proc, time.perf_counter() - start


def _written(script: Path) -> str:
    doc = script.read_text().split('"""')[1]
    names = re.findall(r"[Ww]rites\s+([\w.]+\.(?:png|gif|mp4|html))", doc)
    assert names, f"{script.name}: its docstring says which file it writes"
    return names[-1]


@pytest.fixture(scope="module")
def gallery(tmp_path_factory):
    out = tmp_path_factory.mktemp("gallery")
    with ThreadPoolExecutor(max_workers=2) as pool:
        results = dict(zip(SCRIPTS, pool.map(lambda s: _run(s, out / s.stem), SCRIPTS)))
    return out, results


def test_there_is_a_gallery():
    assert len(SCRIPTS) >= 10


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_example_writes_its_file(script, gallery):
    out, results = gallery
    proc, seconds = results[script]
    assert proc.returncode == 0, proc.stderr
    path = out / script.stem / _written(script)
    assert path.is_file() and path.stat().st_size > 1000, path
    assert f"wrote {path}" in proc.stdout
    assert seconds < LIMIT_S, f"{script.name} took {seconds:.1f} s"
    if path.suffix in (".png", ".gif"):
        from PIL import Image

        with Image.open(path) as im:
            im.load()


def test_the_sweep_example_runs_the_sweep_of_its_toml_file():
    """tippe_inversion_map.py carries its sweep as tables (it runs alone when downloaded);
    they are the tables of tippe_inversion_map.toml, which `kreisel sweep` reads."""
    import ast

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib

    source = (EXAMPLES / "tippe_inversion_map.py").read_text()
    spec = next(node.value for node in ast.parse(source).body if isinstance(node, ast.Assign)
                and getattr(node.targets[0], "id", None) == "spec")  # fmt: skip
    toml = tomllib.loads((EXAMPLES / "tippe_inversion_map.toml").read_text())
    assert ast.literal_eval(spec) == toml
