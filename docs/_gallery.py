"""The gallery's hooks for sphinx-gallery (named in conf.py by their import paths, so that
Sphinx can cache its configuration).

Each script in examples/ writes its figure or animation into the folder given as its first
argument. The gallery gives it a fresh folder, kreisel-out/NAME, relative to examples/ (where
sphinx-gallery runs it), so that the output the pages show reads as a user's run would, with
no path of the build machine in it; it shows what the script wrote: PNG and GIF files as
images, MP4 and HTML files as downloads.
"""

from __future__ import annotations

import pathlib
import shutil

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"
OUT = pathlib.Path("kreisel-out")  # relative to examples/, the folder the scripts run in


def _out(src_file) -> pathlib.Path:
    return EXAMPLES / OUT / pathlib.Path(src_file).stem


def argv(gallery_conf, script_vars):
    """The script's command line: its own output folder, emptied."""
    stem = pathlib.Path(script_vars["src_file"]).stem
    shutil.rmtree(_out(script_vars["src_file"]), ignore_errors=True)
    return [str(OUT / stem)]


def written_files(block, block_vars, gallery_conf):
    """A scraper: the files the script wrote into its output folder."""
    from sphinx_gallery.scrapers import figure_rst

    out = _out(block_vars["src_file"])
    images, downloads = [], []
    for path in sorted(out.glob("*")) if out.is_dir() else []:
        if path.suffix in (".png", ".gif"):
            target = pathlib.Path(next(block_vars["image_path_iterator"]))
            target = target.with_suffix(path.suffix)
            shutil.copyfile(path, target)
            images.append(str(target))
        elif path.suffix in (".mp4", ".html"):
            target = pathlib.Path(block_vars["target_file"]).parent / "images" / path.name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(path, target)
            downloads.append(path.name)
    rst = figure_rst(images, gallery_conf["src_dir"]) if images else ""
    for name in downloads:
        rst += f"\n\nThe script wrote :download:`{name} <images/{name}>`.\n"
    return rst
