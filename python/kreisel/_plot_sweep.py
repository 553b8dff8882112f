"""The summary figure of a sweep (see :func:`kreisel.plot.sweep`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ._errors import ParameterError
from ._plot_base import _pyplot

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes

MODE_COLORS = {"slip": "#4477aa", "roll": "#228833", "flight": "#ccbb44", "error": "#ee6677"}
LABELS = {
    "psi_dot": r"$\dot\psi$ (rad/s)",
    "phi_dot": r"$\dot\phi$ (rad/s)",
    "theta_dot": r"$\dot\theta$ (rad/s)",
    "theta": r"$\theta$ (rad)",
    "mu": r"$\mu$",
    "s": "s (m)",
    "rho": r"$\rho$ (m)",
    "final_u": "final u",
    "inversion_time": "inversion time (s)",
}


def _default_var(ds) -> str:
    for name in ("inversion_time", "final_u", "theta_max", "final_theta"):
        if name in ds.data_vars:
            return name
    return next(n for n in ds.data_vars if n != "status")


def sweep(
    ds: xr.Dataset,
    var: str | None = None,
    ax: Axes | None = None,
    *,
    x: str | None = None,
    y: str | None = None,
    **select: Any,
) -> Axes:
    """A figure of one summary over the swept parameters.

    Two grid dimensions: a colour map over (x, y); one: a line; random samples: the samples
    as points over two sampled parameters, coloured by the summary. ``final_mode`` is drawn
    in one colour per mode. Dimensions beyond the two shown are fixed by ``select``
    (``name=value``, the nearest grid value) or else at their first value, as the title
    says. Runs not yet computed are left blank.
    """
    plt = _pyplot()
    var = _default_var(ds) if var is None else var
    if var not in ds.data_vars:
        raise ParameterError(
            f"var = {var!r} is not allowed: the sweep holds {', '.join(ds.data_vars)}"
        )
    da = ds[var]
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 4.8), constrained_layout=True)
    dims = list(da.dims)
    if "sample" in dims:
        sampled = [c for c in ds.coords if ds[c].dims == ("sample",) and c != "sample"]
        x = x or sampled[0]
        y = y or (sampled[1] if len(sampled) > 1 else None)
        dims.remove("sample")
        show: list[Any] = []
    else:
        show = [d for d in (x, y) if d is not None] or dims[:2]
    fixed = {}
    for d in dims:
        if d in show:
            continue
        v = select.get(d, ds[d].values[0])
        fixed[d] = float(ds[d].sel({d: v}, method="nearest"))
    da = da.sel(fixed) if fixed else da
    title = var + "".join(f", {k} = {v:.4g}" for k, v in fixed.items())
    categorical = da.dtype.kind in "US"
    if not categorical and np.isnan(da.values.astype(float)).any():
        title += " (blank: NaN" + (", no inversion)" if var == "inversion_time" else ")")
    ax.set_title(title)
    if "sample" in da.dims:
        xs = ds[x].values
        ys = ds[y].values if y else np.zeros_like(xs)
        _points(ax, xs, ys, da.values, categorical)
        ax.set_xlabel(LABELS.get(x, x))  # type: ignore[arg-type]  # x is set above
        ax.set_ylabel(LABELS.get(y, y) if y else "")
        return ax
    if len(show) == 1:
        (d,) = show
        vals = da.transpose(d).values
        if categorical:
            _points(ax, ds[d].values, np.zeros(len(vals)), vals, True)
        else:
            ax.plot(ds[d].values, vals, "o-")
            ax.set_ylabel(LABELS.get(var, var))
        ax.set_xlabel(LABELS.get(d, d))
        return ax
    dx, dy = show
    vals = da.transpose(dy, dx).values
    xs, ys = ds[dx].values, ds[dy].values
    if categorical:
        _categories(ax, xs, ys, vals)
    else:
        mesh = ax.pcolormesh(xs, ys, vals, shading="nearest", cmap="viridis")
        ax.figure.colorbar(mesh, ax=ax, label=LABELS.get(var, var))
    ax.set_xlabel(LABELS.get(dx, dx))
    ax.set_ylabel(LABELS.get(dy, dy))
    return ax


def _colors(vals) -> dict:
    present = sorted(v for v in dict.fromkeys(np.ravel(vals)) if v != "")  # "" = not computed
    return {v: MODE_COLORS.get(v, f"C{i}") for i, v in enumerate(present)}


def _categories(ax, xs, ys, vals):
    """A map of named values: one flat colour each, a legend, blank where not computed."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    colors = _colors(vals)
    index = {v: i for i, v in enumerate(colors)}
    codes = np.ma.masked_less(np.vectorize(lambda v: index.get(v, -1), otypes=[float])(vals), 0)
    cmap = ListedColormap(list(colors.values()) or ["white"])
    ax.pcolormesh(xs, ys, codes, shading="nearest", cmap=cmap, vmin=-0.5,
                  vmax=len(colors) - 0.5)  # fmt: skip
    ax.legend(handles=[Patch(color=c, label=v) for v, c in colors.items()], loc="best",
              fontsize="small")  # fmt: skip


def _points(ax, xs, ys, vals, categorical, marker="o"):
    if categorical:
        for value, color in _colors(vals).items():
            pick = vals == value
            ax.scatter(xs[pick], ys[pick], c=color, marker=marker, label=value)
        ax.legend(loc="best", fontsize="small")
    else:
        sc = ax.scatter(xs, ys, c=vals, cmap="viridis", marker=marker)
        ax.figure.colorbar(sc, ax=ax)
