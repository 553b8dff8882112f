"""The built documentation site (`make docs`, docs/_build/html) as a reader uses it: offline
(every formula rendered by the MathJax the site ships, nothing loaded from the network), and
as a user downloads its examples (each script, notebook and zip runs alone from an empty
folder), with no path of the build machine on any page. Skipped until the site is built."""

from __future__ import annotations

import ast
import importlib.util
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SITE = ROOT / "docs" / "_build" / "html"
pytestmark = pytest.mark.skipif(not (SITE / "theory.html").is_file(),
                                reason="the site is not built (make docs)")  # fmt: skip
DOWNLOADS = sorted((SITE / "_downloads").glob("*/*")) if SITE.is_dir() else []
SCRIPTS = [p for p in DOWNLOADS if p.suffix == ".py"]
ENV = {**{k: v for k, v in os.environ.items() if k != "PYTHONPATH"}, "MPLBACKEND": "Agg"}


def _pages():
    return sorted(SITE.rglob("*.html"))


def test_no_page_loads_anything_from_the_network():
    remote = re.compile(r"<(?:script|link|img)[^>]+(?:src|href)=\"(?:https?:)?//", re.I)
    found = [f"{p.relative_to(SITE)}: {m.group(0)}" for p in _pages()
             for m in remote.finditer(p.read_text(errors="replace"))]  # fmt: skip
    assert not found, "\n".join(found[:20])
    theory = (SITE / "theory.html").read_text()
    assert "_static/mathjax/tex-svg-full.js" in theory
    assert (SITE / "_static" / "mathjax" / "tex-svg-full.js").stat().st_size > 1_000_000


def test_the_theory_page_renders_its_formulas_with_no_network():
    from _browser import chromium, have_browser, wait_for

    if not have_browser():
        pytest.skip("Debian's chromium and chromium-driver are not installed (make browser)")
    driver = chromium()
    try:
        driver.set_network_conditions(offline=True, latency=0, download_throughput=0,
                                      upload_throughput=0)  # fmt: skip
        driver.get((SITE / "theory.html").as_uri())
        count = wait_for(driver, "const n = document.querySelectorAll('mjx-container svg').length;"
                         " return n > 50 ? n : 0;", timeout=60)  # fmt: skip
        text = driver.execute_script("return document.querySelector('article').innerText")
        errors = driver.execute_script("return document.querySelectorAll('mjx-merror').length")
    finally:
        driver.quit()
    assert count > 50 and errors == 0
    for raw in ("\\(", "\\)", "\\[", "$$", "\\frac", "\\omega"):
        assert raw not in text, raw


def test_no_page_shows_a_path_of_the_build_machine():
    machine = re.compile(r"/tmp/|kreisel-gallery-|" + re.escape(str(ROOT)))
    found = [f"{p.relative_to(SITE)}: {m.group(0)}" for p in _pages()
             for m in machine.finditer(p.read_text(errors="replace"))]  # fmt: skip
    assert not found, "\n".join(found[:20])


def _imports(source: str) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.add(node.module.split(".")[0])
    return out


def test_every_downloaded_script_and_notebook_imports_only_installed_packages():
    """Every script, notebook and zip of the gallery: all it imports is installed (not a
    module next to it in examples/, such as the _common it used to import)."""
    import nbformat

    sources = {p.name: p.read_text() for p in SCRIPTS}
    for p in DOWNLOADS:
        if p.suffix == ".ipynb":
            nb = nbformat.read(p, as_version=4)
            sources[p.name] = "\n".join(c.source for c in nb.cells if c.cell_type == "code")
        elif p.suffix == ".zip":
            with zipfile.ZipFile(p) as z:
                for name in z.namelist():
                    if name.endswith(".py"):
                        sources[f"{p.name}/{name}"] = z.read(name).decode()
    assert len(SCRIPTS) >= 20 and len(sources) >= 3 * len(SCRIPTS)
    for name, source in sources.items():
        for module in _imports(source):
            assert importlib.util.find_spec(module) is not None, (name, module)


def _run_alone(script: Path, tmp_path: Path):
    folder = tmp_path / script.stem
    folder.mkdir()
    shutil.copyfile(script, folder / script.name)
    return subprocess.run([sys.executable, script.name], cwd=folder, env=ENV, text=True,
                          capture_output=True, timeout=300)  # fmt: skip


# a representative set: a figure, a play top of several parts, an animation
RUN = ["effective_potential", "tippe_top_peg", "tippe_top_gif"]


@pytest.mark.parametrize("stem", RUN)
def test_a_downloaded_script_runs_from_an_empty_folder(stem, tmp_path):
    script = next(p for p in SCRIPTS if p.stem == stem)
    proc = _run_alone(script, tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "wrote kreisel-out/" in proc.stdout


@pytest.mark.parametrize("stem", RUN[:2])
def test_a_downloaded_notebook_runs_from_an_empty_folder(stem, tmp_path):
    import nbformat
    from nbclient import NotebookClient

    notebook = next(p for p in DOWNLOADS if p.suffix == ".ipynb" and p.stem == stem)
    nb = nbformat.read(notebook, as_version=4)
    os.environ.setdefault("MPLBACKEND", "Agg")
    NotebookClient(nb, timeout=300, resources={"metadata": {"path": str(tmp_path)}}).execute()
    assert list((tmp_path / "kreisel-out").glob("*.png"))


def test_a_downloaded_zip_holds_the_script_and_notebook_and_runs(tmp_path):
    archive = next(p for p in DOWNLOADS if p.suffix == ".zip" and p.stem == RUN[0])
    with zipfile.ZipFile(archive) as z:
        z.extractall(tmp_path / "unzipped")
    files = sorted(p.name for p in (tmp_path / "unzipped").rglob("*") if p.is_file())
    assert files == [f"{RUN[0]}.ipynb", f"{RUN[0]}.py"]
    script = next((tmp_path / "unzipped").rglob("*.py"))
    proc = _run_alone(script, tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]


def test_intersphinx_links_come_from_the_shipped_inventories():
    """pandas and SciPy names link to those projects' documentation (inventories shipped in
    docs/_inventories: the build fetches nothing)."""
    trajectory = (SITE / "api" / "generated" / "kreisel.Trajectory.html").read_text()
    assert "https://pandas.pydata.org/pandas-docs/version/1.5.3/" in trajectory
    special = (SITE / "api" / "special.html").read_text()
    assert "https://docs.scipy.org/doc/scipy-1.10.1/" in special


def test_pages_have_copy_buttons_source_links_and_the_changelog():
    assert "copybutton.js" in (SITE / "index.html").read_text()
    assert (SITE / "_modules" / "kreisel" / "bodies.html").is_file()  # [source] links
    assert "viewcode-link" in (SITE / "api" / "bodies.html").read_text()
    changelog = (SITE / "changelog.html").read_text()
    assert "Unreleased" in changelog and "architecture" in (SITE / "index.html").read_text()
    architecture = (SITE / "architecture.html").read_text()
    for layer in ("crates/kreisel-core", "crates/kreisel-py", "python/kreisel"):
        assert layer in architecture
