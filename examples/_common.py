"""Shared by the gallery scripts: where to write, and a non-interactive matplotlib."""

from __future__ import annotations

import pathlib
import sys


def out_dir(argv=None) -> pathlib.Path:
    """The folder given as the first argument, else kreisel-out/ (created)."""
    argv = sys.argv[1:] if argv is None else argv
    out = pathlib.Path(argv[0]) if argv else pathlib.Path("kreisel-out")
    out.mkdir(parents=True, exist_ok=True)
    return out


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
