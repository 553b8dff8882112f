"""Sphinx configuration of kreisel's documentation site (``make docs``).

The build needs no network and the site loads nothing from it: the intersphinx inventories
are in docs/_inventories, there are no remote images, and MathJax (the maths renderer, from
npm through web/package.json) is served from the site itself (docs/_vendor/mathjax, copied
there by `make docs`). The table of integration methods is written here from
``kreisel.methods()``, the gallery runs every script in ``examples/`` and the tutorials are
executed as notebooks.
"""

from __future__ import annotations

import os
import pathlib
import sys

import kreisel

DOCS = pathlib.Path(__file__).resolve().parent
ROOT = DOCS.parent
os.environ.setdefault("MPLBACKEND", "Agg")

project = "kreisel"
author = "the kreisel authors"
copyright = "kreisel authors, MIT licence"
release = kreisel.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx.ext.intersphinx",
    "sphinx_copybutton",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "myst_nb",
]

exclude_patterns = [
    "_build",
    "_generated",
    "_inventories",
    "_vendor",
    "jupyter_execute",
    "**.ipynb_checkpoints",
    "auto_examples/*.ipynb",  # sphinx-gallery writes notebooks for download, not for myst-nb
]
templates_path = ["_templates"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb"}
# Links to SciPy and pandas from inventories shipped in docs/_inventories (Debian's
# documentation packages; see the README there): the build fetches nothing.
intersphinx_mapping = {
    "scipy": ("https://docs.scipy.org/doc/scipy-1.10.1/", "_inventories/scipy-1.10.1.inv"),
    "pandas": ("https://pandas.pydata.org/pandas-docs/version/1.5.3/",
               "_inventories/pandas-1.5.3.inv"),
}  # fmt: skip

# -- maths: MathJax 3 from the site itself ------------------------------------------------
# `make docs` copies MathJax's tex-svg-full.js (npm, pinned in web/package-lock.json) into
# docs/_vendor/mathjax; html_static_path serves it as _static/mathjax/. SVG output: no fonts
# to fetch; "full": every TeX extension is in the one file, none is loaded on demand.
if not (DOCS / "_vendor" / "mathjax" / "tex-svg-full.js").is_file():
    raise RuntimeError("MathJax is missing from docs/_vendor/mathjax: build with `make docs`")
mathjax_path = "mathjax/tex-svg-full.js"

# -- copy buttons on code blocks: copy the code, not the prompts ---------------------------
copybutton_prompt_text = r">>> |\.\.\. |\$ "
copybutton_prompt_is_regexp = True

# -- API reference -------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = False
autodoc_typehints = "signature"
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()  # docstrings are checked by tests/test_docs.py

# -- tutorials (myst-nb) -------------------------------------------------------------------
nb_execution_mode = "force"
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3

# -- gallery (sphinx-gallery) --------------------------------------------------------------
# Every script in examples/ runs; _gallery.py gives each its output folder and shows what it
# wrote. Set KREISEL_GALLERY_PATTERN to run a subset (a regular expression on the path).
sys.path.insert(0, str(DOCS))
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": os.environ.get("KREISEL_GALLERY_PATTERN", r"/[a-z][a-z_]*\.py$"),
    "ignore_pattern": r"(^|/)_",
    "reset_argv": "_gallery.argv",
    "image_scrapers": ("_gallery.written_files",),
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "plot_gallery": "True",
    "show_memory": False,
    "matplotlib_animations": False,
    # no page of execution times: sphinx-gallery's loads its tables' scripts from CDNs
    "write_computation_times": False,
}

# -- generated tables ----------------------------------------------------------------------
_GENERATED = DOCS / "_generated"
_GENERATED.mkdir(exist_ok=True)


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"


_rows = [
    "| method | order | step | symplectic | events | what it is |",
    "|---|---|---|---|---|---|",
]
for _m in kreisel.methods():
    _rows.append(
        f"| `{_m.name}` | {_m.order} | {'adaptive' if _m.adaptive else 'fixed (dt)'} | "
        f"{_yes(_m.symplectic)} | {_yes(_m.events)} | {_m.summary} |"
    )
(_GENERATED / "methods.md").write_text("\n".join(_rows) + "\n")

# -- HTML ----------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"kreisel {release}"
html_static_path = ["_vendor"]  # MathJax (see above)
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_sidebars = {"index": [], "benchmarks": [], "theory": []}
