"""The Zarr store of a sweep: made, opened, written chunk by chunk and read back."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._errors import ParameterError

if TYPE_CHECKING:
    import xarray as xr

from .spec import CATEGORIES, DESCRIPTIONS, MODE_ERROR, MODE_PENDING, SweepSpec, description

FORMAT = "kreisel-sweep/1"


def _is_path(store) -> bool:
    return isinstance(store, (str, os.PathLike))


def shown(store) -> str:
    """A store as a message shows it: a folder as its path in quotes (not PosixPath(...))."""
    return repr(os.fspath(store)) if _is_path(store) else repr(store)


def _open_existing(store):
    """The root group of an existing kreisel sweep store, None if there is none, and an
    error if something else is there."""
    import zarr

    if _is_path(store):
        p = Path(store)
        if not p.exists():
            return None
        if not p.is_dir():
            raise ParameterError(f"store = {shown(p)} is not allowed: it is a file, not a store")
        if not any(p.iterdir()):
            return None
    try:
        root = zarr.open_group(store, mode="r+")
    except (FileNotFoundError, ValueError, KeyError, zarr.errors.BaseZarrError) as e:
        if _is_path(store):
            raise ParameterError(
                f"store = {shown(store)} is not allowed: it exists and is not a kreisel sweep "
                f"store ({type(e).__name__}); kreisel leaves it as it is"
            ) from None
        return None
    if root.attrs.get("format") != FORMAT:
        if not _is_path(store) and not list(root.keys()):
            return None
        raise ParameterError(
            f"store = {shown(store)} is not allowed: it is not a kreisel sweep store; kreisel "
            "leaves it as it is"
        )
    return root


def _create(store, spec: SweepSpec, samples: dict):
    import zarr

    from .._core import __version__

    root = zarr.open_group(store, mode="w")
    root.attrs.update(
        {
            "format": FORMAT,
            "title": f"kreisel sweep of a {spec.kind} top",
            "kreisel_version": __version__,
            "spec": spec.canonical(),
            "run_errors": "{}",
        }
    )
    for name, values in spec.grid.items():
        root.create_array(
            name,
            data=np.asarray(values, dtype=float),
            chunks=(len(values),),
            dimension_names=[name],
        )
    coords = []
    if spec.random:
        n = spec.n_samples
        root.create_array(
            "sample", data=np.arange(n, dtype=np.int64), chunks=(n,), dimension_names=["sample"]
        )
        for name, v in samples.items():
            root.create_array(name, data=v, chunks=(n,), dimension_names=["sample"])
            coords.append(name)
    attrs = {"coordinates": " ".join(coords)} if coords else {}
    for name in spec.keep:
        dtype, fill = ("i8", -1) if name == "steps" else ("f8", np.nan)
        a: dict[str, Any] = dict(attrs, description=description(name))
        if name in CATEGORIES:
            dtype, fill = "i1", MODE_PENDING
            names = CATEGORIES[name]
            a.update(
                flag_values=[*range(len(names)), MODE_ERROR, MODE_PENDING],
                flag_meanings=" ".join([*names, "error", "pending"]),
            )
        root.create_array(
            name,
            shape=spec.shape,
            chunks=spec.block,
            dtype=dtype,
            fill_value=fill,
            dimension_names=list(spec.dims),
            attributes=a,
            # a few numbers per run: compressing them saves little and costs a
            # millisecond per chunk written, on the core the runs need
            compressors=None,
        )
    root.create_array(
        "status",
        shape=spec.shape,
        chunks=spec.block,
        dtype="i1",
        fill_value=0,
        dimension_names=list(spec.dims),
        attributes=dict(attrs, flag_values=[0, 1, 2], flag_meanings="pending done failed"),
    )
    root.create_array(
        "chunk_done",
        shape=(spec.n_chunks,),
        chunks=(1,),
        dtype="u1",
        fill_value=0,
        dimension_names=["chunk"],
        attributes={"description": "1 once the chunk's results are written"},
    )
    return root


class _Writer:
    """Writes finished chunks into the store: the arrays are opened once; a chunk's flag goes
    last, after its data and its run errors."""

    def __init__(self, root, spec: SweepSpec):
        self.root, self.spec = root, spec
        self.arrays = {n: root[n] for n in (*spec.keep, "status", "chunk_done")}
        self.errors = json.loads(root.attrs.get("run_errors", "{}"))

    def write(self, k: int, result: dict):
        sl = self.spec.chunk_slices(k)
        shape = tuple(s.stop - s.start for s in sl)
        for name in (*self.spec.keep, "status"):
            self.arrays[name][sl] = np.asarray(result[name]).reshape(shape)
        # a rewritten chunk's old messages go, its new ones come
        old = [key for key in self.errors
               if all(s.start <= int(a) < s.stop for s, a in zip(sl, key.split(",")))]  # fmt: skip
        for key in old:
            del self.errors[key]
        for i, msg in result["errors"].items():
            at = (s.start + int(j) for s, j in zip(sl, np.unravel_index(int(i), shape)))
            self.errors[",".join(map(str, at))] = msg
        if old or result["errors"]:
            self.root.attrs["run_errors"] = json.dumps(self.errors, sort_keys=True)
        self.arrays["chunk_done"][k] = 1


def open_sweep(store: str | os.PathLike[str] | Any) -> xr.Dataset:
    """The results of a sweep store (complete or not) as an ``xarray.Dataset`` in memory:
    one variable per kept summary, ``final_mode`` as strings ("" where pending), ``status``
    (0 pending, 1 done, 2 failed), and the spec and run errors in the attributes.

    Examples
    --------
    >>> import zarr
    >>> import kreisel
    >>> top = {"kind": "lagrange", "I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1}
    >>> sim, grid = {"exact": True}, {"theta": [0.3, 0.5]}
    >>> spec = {"top": top, "state": {"psi_dot": 150.0}, "simulation": sim, "grid": grid}
    >>> store = zarr.storage.MemoryStore()
    >>> _ = kreisel.sweep(spec, store, progress=False)
    >>> ds = kreisel.open_sweep(store)
    >>> ds["motion_kind"].values.tolist(), ds["status"].values.tolist(), ds.attrs["chunks_done"]
    (['cusps', 'cusps'], [1, 1], 1)
    """
    import xarray as xr

    root = _open_existing(store)
    if root is None:
        raise ParameterError(f"store = {shown(store)} is not allowed: there is no sweep there")
    ds = xr.open_zarr(store, consolidated=False, chunks=None).load()
    done = ds["chunk_done"].values
    ds = ds.drop_vars("chunk_done")
    for name, values in CATEGORIES.items():
        if name not in ds:
            continue
        names = np.array([*values, "error", ""], dtype=object)
        codes = ds[name].values.astype(int)
        k = len(values)
        lookup = np.where(codes >= 0, codes, np.where(codes == MODE_ERROR, k, k + 1))
        ds[name] = (ds[name].dims, names[lookup].astype(str), {"description": DESCRIPTIONS[name]})
    ds = ds[[*json.loads(ds.attrs["spec"])["keep"], "status"]]  # the spec's order
    ds.attrs["chunks_done"] = int(done.sum())
    ds.attrs["chunks"] = int(done.size)
    return ds
