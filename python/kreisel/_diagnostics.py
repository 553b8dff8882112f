"""What a trajectory says about its own quality: the conserved quantities and their drift."""

from __future__ import annotations

import numpy as np

_RIGID = (
    ("energy", "energy E"),
    ("Mz", r"$M_z$"),
    ("M3", r"$M_3$"),
    ("kovalevskaya", "Kovalevskaya's K"),
)


def lagrange_columns(traj):
    """Energy (J), Mz, M3 (kg m^2/s) and the potential (J) of an exact Lagrange trajectory
    (the core's columns, from its angles and rates), or None for any other trajectory."""
    from ._lagrange import LagrangeTop

    top = getattr(traj, "model", None)
    if not isinstance(top, LagrangeTop) or "psi_dot" not in traj.columns:
        return None
    return {k: traj[k] for k in ("energy", "Mz", "M3", "potential")}


def _angular_momentum(traj):
    """``|L|`` at the start (kg m^2/s) of a top on a pivot, or None."""
    from ._lagrange import LagrangeTop

    model = getattr(traj, "model", None)
    if "omega" in traj.columns and model is not None and hasattr(model, "I3"):
        i2 = model.I1 if isinstance(model, LagrangeTop) else model.I2
        inertia = np.array([model.I1, i2, model.I3])
        return float(np.linalg.norm(inertia * np.asarray(traj.omega)[0]))
    if isinstance(model, LagrangeTop) and "psi_dot" in traj.columns:
        th, thd, phd, psd = (
            float(traj[k][0]) for k in ("theta", "theta_dot", "phi_dot", "psi_dot")
        )
        m3 = model.I3 * (psd + phd * np.cos(th))
        return float(np.sqrt((model.I1 * thd) ** 2 + (model.I1 * phd * np.sin(th)) ** 2 + m3**2))
    return None


def conserved(traj):
    """``[(key, label, values, scale)]``: the quantities the motion conserves, as the
    trajectory carries them, each with the scale its drift is measured against: energy, Mz,
    M3, Kovalevskaya's K for a top on a pivot (Mz and M3 against ``|L|``, which stays meaningful
    when Mz or M3 is zero); Jellett's integral and the energy balance E + dissipated for a
    play top."""
    cols = set(traj.columns)
    if len(traj) == 0:
        return []
    if "jellett" in cols:
        balance = np.asarray(traj.energy + traj.dissipated)
        out = [("energy_balance", "E + dissipated", balance, abs(balance[0]))]
        # Jellett's integral is conserved by forces at one contact point, not by a drilling
        # torque (Coulomb-Contensou friction) nor by forces at several parts.
        model = getattr(traj, "model", None)
        one_point = model is None or (
            len(getattr(model, "shape", (None,))) == 1
            and type(getattr(model, "friction", None)).__name__ != "CoulombContensou"
        )
        if one_point:
            out.insert(
                0, ("jellett", "Jellett's J", np.asarray(traj.jellett), abs(traj.jellett[0]))
            )
        return out
    if "balance" in cols:
        # A moving or damped pivot: E + dissipated - work_by_pivot is the one constant.
        b = np.asarray(traj.balance)
        scale = float(np.abs(traj.energy).max() + np.abs(traj.work_by_pivot).max())
        return [("balance", "E + dissipated - W", b, scale)]
    lag = lagrange_columns(traj)
    source = lag if lag is not None else {k: traj[k] for k, _ in _RIGID if k in cols}
    big_l = _angular_momentum(traj)
    out = []
    for k, label in _RIGID:
        if k in source:
            y = np.asarray(source[k])
            scale = abs(y[0])
            if k in ("Mz", "M3") and big_l:
                scale = big_l
            out.append((k, label, y, scale))
    return out


def relative_drift(values, scale=None):
    """``|X(t) - X(0)| / scale``; ``scale`` defaults to ``|X(0)|`` (the largest |X| when that
    is zero)."""
    y = np.asarray(values, dtype=float)
    if scale is None or not scale > 0:
        scale = abs(y[0]) if y[0] != 0 else float(np.abs(y).max())
    return np.abs(y - y[0]) / max(scale, 1e-300)
