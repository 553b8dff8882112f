"""Trajectories: columns of numpy arrays sharing one time axis."""

from __future__ import annotations

import html
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

# Units and meanings of the columns kreisel's trajectories carry (SI; angles in rad).
COLUMNS = {
    "t": ("s", "time"),
    "theta": ("rad", "nutation angle from the upward vertical"),
    "phi": ("rad", "precession angle (unwrapped)"),
    "psi": ("rad", "spin angle (unwrapped)"),
    "theta_dot": ("rad/s", "nutation rate"),
    "phi_dot": ("rad/s", "precession rate"),
    "psi_dot": ("rad/s", "spin rate"),
    "quaternion": ("1", "orientation (w, x, y, z), body to space"),
    "omega": ("rad/s", "angular velocity, body frame"),
    "energy": ("J", "total energy"),
    "Mz": ("kg m^2/s", "vertical angular momentum"),
    "M3": ("kg m^2/s", "axial angular momentum"),
    "kovalevskaya": ("kg^2 m^4 s^-4", "Kovalevskaya's integral"),
    "com": ("m", "centre of mass, space frame"),
    "com_velocity": ("m/s", "velocity of the centre of mass"),
    "dissipated": ("J", "energy dissipated so far"),
    "u": ("1", "cos(theta); 1 upright"),
    "contact_point": ("m", "contact point on the floor, space frame"),
    "slip_velocity": ("m/s", "slip velocity of the contact point"),
    "slip_speed": ("m/s", "slip speed"),
    "normal_force": ("N", "normal force of the floor"),
    "jellett": ("kg m^2/s", "Jellett's integral"),
    "mode": ("", "contact mode: slip (a part slides), roll (every touching part sticks), flight"),
    "energy_translation": ("J", "translational kinetic energy"),
    "energy_rotation": ("J", "rotational kinetic energy"),
    "energy_potential": ("J", "potential energy m g z_G"),
    "potential": ("J", "potential energy m g z_G (pivot at z = 0)"),
    "pivot_position": ("m", "position of the pivot, space frame"),
    "pivot_velocity": ("m/s", "velocity of the pivot, space frame"),
    "reaction_force": ("N", "force of the pivot on the top, space frame"),
    "power_pivot": ("W", "power the pivot puts in, R . v_O"),
    "power_dissipated": ("W", "power dissipated at the pivot"),
    "work_by_pivot": ("J", "work done by the pivot so far"),
    "balance": ("J", "energy + dissipated - work_by_pivot (constant)"),
    "stuck": ("", "whether dry friction holds the top at rest relative to the pivot"),
    "part_in_contact": ("", "whether each contact part touches the floor"),
    "part_normal_force": ("N", "normal force at each contact part"),
    "part_slip_velocity": ("m/s", "slip velocity (x, y) at each contact part"),
    "part_mode": ("", "contact state of each part: flight, rolling, drilling, sliding or flat"),
    "part_contact_point": ("m", "contact point (lowest point) of each part, space frame"),
    "part_friction_force": ("N", "friction force (x, y) at each contact part"),
}

# Columns with one entry per contact part (second axis "part"; the third, if any, "horizontal").
_PER_PART = (
    "part_in_contact",
    "part_normal_force",
    "part_slip_velocity",
    "part_mode",
    "part_contact_point",
    "part_friction_force",
)
# The third axis of a per-part column: horizontal (x, y) or space (x, y, z).
_PER_PART_AXIS: dict[str, tuple[str, tuple[str, ...]]] = {
    "part_contact_point": ("space_axis", ("x", "y", "z"))
}

# Names of the second axis of 2-D columns.
_COMPONENTS = {
    "quaternion": ("component", ("w", "x", "y", "z")),
    "omega": ("body_axis", ("1", "2", "3")),
}
_SPACE = ("space_axis", ("x", "y", "z"))


class Deferred:
    """Columns computed together on first use: ``make()`` returns a dict of them.

    A simulation returns its states at once and leaves the diagnostics derived from them
    (Euler angles, energies, forces) to a :class:`Trajectory` that computes them, all in one
    native call, only when one of them is read.
    """

    __slots__ = ("_make",)

    def __init__(self, make):
        self._make = make


class Trajectory:
    """A motion sampled at times ``t``: every column is a numpy array of the same length.

    Columns are attributes (``traj.theta``) and items (``traj["theta"]``); ``columns`` lists
    them. Angles are in radians, rates in rad/s, times in s. A column may be given as a
    :class:`Deferred` (the same object for every column it makes); it is computed when first
    read.

    Examples
    --------
    >>> import numpy as np
    >>> from kreisel import LagrangeTop
    >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> traj = top.exact(top.state(theta=0.5, psi_dot=150.0), np.linspace(0.0, 0.1, 3))
    >>> len(traj), traj.columns[:4]
    (3, ['t', 'theta', 'phi', 'psi'])
    >>> np.round(traj["theta"], 6).tolist() == np.round(traj.theta, 6).tolist()
    True
    >>> [round(float(e), 6) for e in traj.energy]
    [56.680454, 56.680454, 56.680454]
    """

    __slots__ = ("_cols", "_meta")
    _cols: dict[str, Any]
    _meta: dict[str, Any]

    def __init__(self, columns: dict[str, Any], **meta: Any) -> None:
        n = len(columns["t"])
        for k, v in columns.items():
            if not isinstance(v, Deferred) and len(v) != n:
                raise ValueError(f"column {k!r} has length {len(v)}, expected {n}")
        object.__setattr__(self, "_cols", dict(columns))
        object.__setattr__(self, "_meta", dict(meta))

    def _column(self, name: str) -> np.ndarray:
        cols = object.__getattribute__(self, "_cols")
        col = cols[name]
        if isinstance(col, Deferred):
            made = col._make()
            for k, v in cols.items():
                if v is col:
                    cols[k] = made[k]
            col = cols[name]
        return col

    def _all(self) -> dict[str, np.ndarray]:
        return {name: self._column(name) for name in self._cols}

    def __getattr__(self, name: str) -> np.ndarray:
        cols = object.__getattribute__(self, "_cols")
        if name in cols:
            return self._column(name)
        meta = object.__getattribute__(self, "_meta")
        if name in meta:
            return meta[name]
        raise AttributeError(f"Trajectory has no column {name!r}; columns: {list(cols)}")

    def __setattr__(self, name, value):
        raise AttributeError("Trajectory is read-only")

    def __getitem__(self, name: str) -> np.ndarray:
        if name not in self._cols:
            raise KeyError(name)
        return self._column(name)

    def __len__(self) -> int:
        return len(self._cols["t"])

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._cols) | set(self._meta))

    @property
    def sensitivities(self) -> dict[str, dict[str, np.ndarray]] | None:
        """The forward sensitivities of the run, if :func:`kreisel.simulate` was asked for
        them (``sensitivities=[...]``): a dict from each name to a dict of arrays
        (``"omega"``, ``"orientation"``, ``"quaternion"``, ``"theta"``, ``"phi"``,
        ``"psi"``), one row per row of the trajectory; else None."""
        return self._meta.get("sensitivities")

    @property
    def part_modes(self) -> dict[str, np.ndarray] | None:
        """Each contact part's state per sample, a dict from the part's name (in the order of
        the top's ``shape``) to an array of str; None for a trajectory without parts.

        The states are the engine's (the contact mode each part integrates in), not a
        threshold on a slip speed: ``"flight"`` (not touching), ``"rolling"`` (sticking, the
        angular velocity at least as much along the floor as about its normal, at rest
        included), ``"drilling"`` (sticking, turning mainly about the floor's normal:
        ``|omega_z| > |omega_horizontal|``, a top sleeping on its tip), ``"sliding"`` (slipping;
        under Coulomb-Contensou friction a contact patch that spins about the normal slides
        too, even at zero slip velocity) and ``"flat"`` (a ring lying flat on its face,
        touching along its whole circle, or the pole on which a top lies flat where that pole
        reaches past the ring's plane; whether it sticks is in ``mode``). The column
        ``part_mode`` holds the same as an array (n, parts).

        Examples
        --------
        >>> import numpy as np
        >>> import kreisel
        >>> from kreisel.shapes import Sphere
        >>> top = kreisel.PlayTop(0.1, 4e-5, 4e-5, shape=[Sphere(0.02, z=0.0, name="ball")])
        >>> s = top.state(theta=0.0, height=0.03)
        >>> traj = kreisel.simulate(top, s, 0.2, t_eval=[0.0, 0.2])
        >>> traj.part_modes["ball"].tolist()
        ['flight', 'rolling']
        """
        cols = object.__getattribute__(self, "_cols")
        if "part_mode" not in cols:
            return None
        states = self._column("part_mode")
        names = self._part_labels(states.shape[1])
        return {name: states[:, i] for i, name in enumerate(names)}

    @property
    def columns(self) -> list[str]:
        """Names of the columns."""
        return list(self._cols)

    def to_dict(self) -> dict[str, np.ndarray]:
        """The columns as a dict of arrays.

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> traj = top.exact(top.state(theta=0.5, psi_dot=150.0), np.linspace(0.0, 0.1, 3))
        >>> d = traj.to_dict()
        >>> sorted(d)[:4], np.round(d["theta"], 6).tolist()
        (['M3', 'Mz', 'energy', 'phi'], [0.5, 0.510655, 0.500426])
        """
        return self._all()

    def _meta_attrs(self) -> dict[str, str]:
        out = {}
        for key in ("model", "state", "method", "status"):
            if key in self._meta:
                out[key] = str(self._meta[key])
        return out

    def to_xarray(self) -> xr.Dataset:
        """The trajectory as an :class:`xarray.Dataset` on the dimension ``t`` (s).

        2-D columns get a second dimension: ``component`` (w, x, y, z) for the quaternion,
        ``body_axis`` (1, 2, 3) for omega, ``space_axis`` (x, y, z) for positions and
        velocities. Every variable carries ``units`` and ``long_name``; the model, the state
        and the method are attributes of the dataset. Needs xarray (``pip install xarray``).

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> traj = top.exact(top.state(theta=0.5, psi_dot=150.0), np.linspace(0.0, 0.1, 3))
        >>> ds = traj.to_xarray()
        >>> ds["theta"].attrs["units"], ds.sizes["t"], [round(float(x), 6) for x in ds["theta"]]
        ('rad', 3, [0.5, 0.510655, 0.500426])
        """
        import xarray as xr

        t = self._cols["t"]
        data = {}
        for name, col in self._all().items():
            if name == "t":
                continue
            col = np.asarray(col)
            dims: tuple[str, ...]
            if col.ndim == 1:
                dims = ("t",)
            elif name in _PER_PART:
                third = _PER_PART_AXIS.get(name, ("horizontal_axis",))[0]
                dims = ("t", "part", third)[: col.ndim]
            else:
                dims = ("t", _COMPONENTS.get(name, _SPACE)[0])
            if col.dtype.kind == "U":
                col = col.astype(str)
            units, meaning = COLUMNS.get(name, ("", name))
            data[name] = xr.Variable(dims, col, attrs={"units": units, "long_name": meaning})
        coords: dict[str, Any] = {"t": ("t", t, {"units": "s", "long_name": "time"})}
        for name, col in self._all().items():
            if name in _PER_PART:
                coords["part"] = ("part", list(self._part_labels(np.shape(col)[1])))
                if np.ndim(col) == 3:
                    axis, names = _PER_PART_AXIS.get(name, ("horizontal_axis", ("x", "y")))
                    coords[axis] = (axis, list(names))
            elif np.ndim(col) == 2:
                dim, labels = _COMPONENTS.get(name, _SPACE)
                coords[dim] = (dim, list(labels))
        return xr.Dataset(data, coords=coords, attrs=self._meta_attrs())

    def to_pandas(self) -> pd.DataFrame:
        """The trajectory as a :class:`pandas.DataFrame` indexed by ``t`` (s); 2-D columns are
        split into one column each (``quaternion_w``, ``omega_1``, ``com_x``, ...). Needs
        pandas.

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel import LagrangeTop
        >>> top = LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> traj = top.exact(top.state(theta=0.5, psi_dot=150.0), np.linspace(0.0, 0.1, 3))
        >>> df = traj.to_pandas()
        >>> df.index.name, df.shape, [round(float(x), 6) for x in df["theta"]]
        ('t', (3, 10), [0.5, 0.510655, 0.500426])
        """
        import pandas as pd

        flat = {}
        for name, col in self._all().items():
            if name == "t":
                continue
            col = np.asarray(col)
            if col.ndim == 1:
                flat[name] = col
            elif name in _PER_PART:
                for j, part in enumerate(self._part_labels(col.shape[1])):
                    if col.ndim == 2:
                        flat[f"{name}_{part}"] = col[:, j]
                    else:
                        for k, axis in enumerate("xyz"[: col.shape[2]]):
                            flat[f"{name}_{part}_{axis}"] = col[:, j, k]
            else:
                for j, label in enumerate(_COMPONENTS.get(name, _SPACE)[1]):
                    flat[f"{name}_{label}"] = col[:, j]
        return pd.DataFrame(flat, index=pd.Index(self._cols["t"], name="t"))

    def _part_labels(self, n: int) -> tuple[str, ...]:
        names = self._meta.get("part_names")
        return tuple(names) if names is not None else tuple(f"part{i}" for i in range(n))

    def _repr_html_(self) -> str:
        t = self._cols["t"]
        rows = []
        for name, col in self._all().items():
            col = np.asarray(col)
            units, meaning = COLUMNS.get(name, ("", ""))
            if col.dtype.kind in "fi" and col.size:
                rng = f"{np.nanmin(col):.6g} … {np.nanmax(col):.6g}"
            elif col.dtype.kind == "U" and col.size:
                rng = ", ".join(sorted(set(col.ravel().tolist())))
            else:
                rng = ""
            shape = "×".join(str(n) for n in col.shape)
            rows.append(
                f"<tr><td><code>{html.escape(name)}</code></td><td>{shape}</td>"
                f"<td>{html.escape(units)}</td><td>{html.escape(rng)}</td>"
                f"<td>{html.escape(meaning)}</td></tr>"
            )
        span = f"t from {t.min():.6g} s to {t.max():.6g} s" if len(t) else "empty"
        head = f"<b>Trajectory</b>: {len(t)} samples, {span}"
        meta = "".join(
            f"<br><small>{html.escape(k)}: <code>{html.escape(v)}</code></small>"
            for k, v in self._meta_attrs().items()
        )
        events = self._meta.get("events") or []
        if events:
            shown = ", ".join(f"{e.name} at {e.t:.6g} s" for e in events[:8])
            more = f" and {len(events) - 8} more" if len(events) > 8 else ""
            meta += f"<br><small>events: {html.escape(shown)}{more}</small>"
        return (
            f"<div>{head}{meta}<table><thead><tr><th>column</th><th>shape</th><th>units</th>"
            f"<th>range</th><th>meaning</th></tr></thead><tbody>{''.join(rows)}</tbody>"
            "</table></div>"
        )

    def __repr__(self) -> str:
        t = self._cols["t"]
        span = f"t=[{t.min():.6g}, {t.max():.6g}] s" if len(t) else "empty"
        return f"<Trajectory: {len(t)} samples, {span}, columns {self.columns}>"
