"""Which extra of kreisel installs a package that is missing.

``pip install kreisel`` installs what the library and the command line need (numpy, click,
xarray, pandas, scipy for NetCDF files, matplotlib for figures); the extras add what one
command needs: ``[animate]`` (GIF, MP4, HTML animations), ``[sweep]`` (Zarr stores, Dask)
and ``[explore]`` (the local web page); ``[all]`` is all three.
"""

from __future__ import annotations

# the top-level module a missing package leaves missing -> the extra that installs it
EXTRA_OF = {
    "imageio": "animate",
    "imageio_ffmpeg": "animate",
    "PIL": "animate",
    "plotly": "animate",
    "zarr": "sweep",
    "dask": "sweep",
    "distributed": "sweep",
    "tqdm": "sweep",
    "starlette": "explore",
    "uvicorn": "explore",
}


def install_hint(module: str) -> str:
    """How to install the package of ``module`` (a dotted module name)."""
    extra = EXTRA_OF.get(module.split(".")[0])
    if extra is not None:
        return f"pip install 'kreisel[{extra}]'"
    return "pip install --force-reinstall kreisel (kreisel itself needs it)"


def missing_message(module: str) -> str:
    """The message for a ``ModuleNotFoundError`` of ``module``."""
    return (
        f"this needs the package {module.split('.')[0]!r}, which is not installed: "
        + install_hint(module)
    )
