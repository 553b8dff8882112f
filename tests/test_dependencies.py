"""What `pip install kreisel` installs and what each extra adds: the base install is the
library and a working command line (runs, NetCDF and CSV files, figures); a command whose
extra is missing says which extra to install. A missing package is simulated in a child
process by an import hook that refuses it."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
# the distribution that provides each top-level module
DISTRIBUTION = {"PIL": "pillow", "imageio_ffmpeg": "imageio-ffmpeg", "distributed": "dask"}


def _names(requirements) -> set[str]:
    return {re.split(r"[\[<>=;~! ]", r, maxsplit=1)[0].lower() for r in requirements}


def test_the_base_install_has_what_the_command_line_needs_and_not_the_web_server():
    base = _names(PYPROJECT["dependencies"])
    # play writes NetCDF (xarray, scipy's engine), --format csv (pandas), demo figures
    assert {"numpy", "click", "xarray", "pandas", "scipy", "matplotlib"} <= base
    assert not base & {"starlette", "uvicorn", "zarr", "dask", "plotly"}


def test_every_extra_named_in_an_error_installs_that_package():
    from kreisel._extras import EXTRA_OF

    extras = PYPROJECT["optional-dependencies"]
    for module, extra in EXTRA_OF.items():
        wanted = DISTRIBUTION.get(module, module).lower()
        assert wanted in _names(extras[extra]), (module, extra)
    assert _names(extras["all"]) == {"kreisel"}
    assert set(re.findall(r"\w+", extras["all"][0].split("[")[1])) == set(EXTRA_OF.values())


BLOCK = """
import sys
from importlib.abc import MetaPathFinder

class Missing(MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] == {module!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None

for name in list(sys.modules):
    if name.split(".")[0] == {module!r}:
        del sys.modules[name]
sys.meta_path.insert(0, Missing())
from kreisel._cli import main
sys.exit(main({argv!r}))
"""


@pytest.mark.parametrize(
    "module, argv, hint",
    [
        ("starlette", ["explore", "--no-browser", "--port", "0"], "pip install 'kreisel[explore]'"),
        (
            "zarr",
            [
                "sweep",
                str(ROOT / "examples" / "tippe_inversion_map.toml"),
                "--store",
                "s.zarr",
                "--quiet",
            ],
            "pip install 'kreisel[sweep]'",
        ),
        (
            "PIL",
            [
                "lagrange",
                "--preset",
                "cusps",
                "--animate",
                "gif",
                "--frames",
                "2",
                "--no-figures",
                "--out",
                "o",
            ],
            "pip install 'kreisel[animate]'",
        ),
        ("matplotlib", ["demo", "--no-animation", "--out", "o"], "pip install --force-reinstall"),
    ],  # fmt: skip
)
def test_a_missing_package_names_the_extra_that_installs_it(module, argv, hint, tmp_path):
    code = textwrap.dedent(BLOCK.format(module=module, argv=argv))
    env = {"MPLBACKEND": "Agg", "PATH": "/usr/bin:/bin"}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tmp_path, timeout=300, env=env)  # fmt: skip
    assert proc.returncode == 1, proc.stderr[-3000:]
    line = proc.stderr.strip().splitlines()[-1]
    assert f"this needs the package {module!r}, which is not installed: {hint}" in line, line


@pytest.mark.parametrize("page", ["README.md", "docs/index.md"])
def test_the_install_lines_name_extras_that_exist(page):
    text = (ROOT / page).read_text()
    named = re.findall(r'pip install "\.\[(\w+)\]"', text)
    assert set(named) == {"animate", "sweep", "explore", "all"}
    assert set(named) <= set(PYPROJECT["optional-dependencies"])
    assert "numpy and click only" not in text
