"""What the page's form says of each field of a ``kreisel run`` TOML file: a readable label,
the unit, and a tooltip (from the docstrings of the classes the fields build)."""

from __future__ import annotations

# (label, unit, tooltip); a unit "1" is a pure number, "" a field with no unit (text, a flag)
_PIVOT = "through the pivot"
TOP = {
    "I1": ("moment I1", "kg m²", f"principal moment of inertia about the body axis e1 {_PIVOT} "
           "(a Lagrange top: about any axis across the figure axis)"),
    "I2": ("moment I2", "kg m²", f"principal moment of inertia about the body axis e2 {_PIVOT}"),
    "I3": ("moment I3", "kg m²", f"moment of inertia about the figure axis e3 {_PIVOT}"),
    "m": ("mass m", "kg", "mass of the top"),
    "l": ("pivot to G, l", "m", "distance from the pivot to the centre of mass G along e3 "
          "(negative: G below the pivot)"),
    "com": ("centre of mass", "m", "the centre of mass G in the body frame, from the pivot: "
            "x, y, z"),
    "g": ("gravity g", "m/s²", "gravitational acceleration (default 9.81)"),
    "A": ("moment A", "kg m²", "equatorial moment of inertia about the centre of mass"),
    "C": ("moment C", "kg m²", "axial moment of inertia about the centre of mass (C <= 2 A)"),
    "s": ("tip to G, s", "m", "distance from the centre of the tip sphere to the centre of "
          "mass, along the figure axis"),
    "rho": ("tip radius ρ", "m", "radius of the tip sphere"),
    "shape": ("contact parts", "m", "the parts that touch the floor, instead of s and rho: "
              "spheres, spheroids and tori along the figure axis (z from the centre of mass)"),
    "friction": ("friction law", "", "the tangential force at every contact: coulomb (mu "
                 "without unit), viscous (mu in s/m), none, or coulomb_contensou (Coulomb "
                 "with drilling friction over a contact patch)"),
    "mu": ("friction coefficient μ", "1 or s/m", "Coulomb's coefficient (no unit), or the "
           "viscous coefficient in s/m"),
    "patch_radius": ("contact patch radius", "m", "radius of the contact patch of "
                     "coulomb_contensou friction (the drilling torque's lever)"),
    "restitution": ("restitution", "1", "coefficient of restitution of impacts after a "
                    "flight, in [0, 1]"),
    "rolling_resistance": ("rolling resistance", "m", "length of the loss torque "
                           "-delta N against the rolling rotation"),
    "drilling_resistance": ("drilling resistance", "m", "length of the loss torque "
                            "-delta N against the drilling rotation"),
    "air_drag": ("air drag", "N m s", "the torque -air_drag omega of the air"),
    "stick_threshold": ("stick threshold", "1", "a sliding part sticks where its slip falls "
                        "to this share of the top's speed scale (1e-9 by default)"),
}  # fmt: skip
STATE = {
    "theta": ("tilt θ", "rad", "Euler angle: the figure axis from the upward vertical"),
    "phi": ("precession angle φ", "rad", "Euler angle (z-x-z) about the vertical"),
    "psi": ("spin angle ψ", "rad", "Euler angle (z-x-z) about the figure axis"),
    "theta_dot": ("nutation rate θ'", "rad/s", "rate of the tilt"),
    "phi_dot": ("precession rate φ'", "rad/s", "rate of the precession angle"),
    "psi_dot": ("spin rate ψ'", "rad/s", "rate of the spin angle"),
    "quaternion": ("orientation quaternion", "1", "w, x, y, z: body to space (instead of the "
                   "Euler angles)"),
    "omega": ("angular velocity ω", "rad/s", "in the body frame: x, y, z (with the "
              "quaternion)"),
    "vx": ("velocity vx", "m/s", "horizontal velocity of the centre of mass, x"),
    "vy": ("velocity vy", "m/s", "horizontal velocity of the centre of mass, y"),
    "height": ("drop height", "m", "the gap between the tip and the floor at the start (a "
               "dropped top); empty: in contact"),
}  # fmt: skip
SIMULATION = {
    "t_end": ("duration", "s", "time of motion to compute"),
    "method": ("method", "", "the integrator: dop853 (adaptive) or a fixed-step method"),
    "exact": ("exact solution", "", "true: the closed-form solution (Lagrange tops)"),
    "rtol": ("relative tolerance", "1", "relative error tolerance of the adaptive method"),
    "atol": ("absolute tolerance", "1", "absolute error tolerance of the adaptive method"),
    "dt": ("time step", "s", "step of a fixed-step method"),
    "samples": ("samples", "count", "points of the motion recorded and shown"),
}  # fmt: skip
PIVOT = {
    "kind": ("pivot motion", "", "fixed (the default), harmonic: amplitude cos(omega t + "
             "phase), or path (from a TOML file)"),
    "amplitude": ("shaking amplitude", "m", "the harmonic pivot's amplitude vector: x, y, z "
                  "(z up)"),
    "omega": ("shaking frequency ω", "rad/s", "angular frequency of the harmonic pivot"),
    "phase": ("shaking phase", "rad", "phase at t = 0: one number, or one per component "
              "(an ellipse)"),
}  # fmt: skip
DAMPING = {
    "viscous": ("viscous damping", "N m s", "the torque -viscous omega at the pivot"),
    "drag": ("air drag", "N m s²", "the torque -drag |omega| omega"),
    "dry": ("dry friction μp", "1", "Coulomb coefficient of the ball joint: a torque up to "
            "dry pivot_radius |R| against the rotation, sticking at rest"),
    "pivot_radius": ("ball joint radius", "m", "radius of the ball joint (dry friction's "
                     "lever)"),
}  # fmt: skip
TABLES = {
    "top": TOP,
    "pivot": PIVOT,
    "damping": DAMPING,
    "state": STATE,
    "simulation": SIMULATION,
}


def field_info() -> dict:
    """``{table: {field: {"label", "unit", "help"}}}`` for the page."""
    return {
        table: {k: {"label": v[0], "unit": v[1], "help": v[2]} for k, v in fields.items()}
        for table, fields in TABLES.items()
    }


def part_fields() -> dict:
    """The fields of each kind of contact part (``shape`` of a play top), as ``kreisel run``
    reads them: ``{"sphere": ["radius", "z"], ...}``."""
    from .._config import part_kinds

    return {kind: list(fields) for kind, (_, fields) in part_kinds().items()}
