"""Driven and damped heavy tops: a pivot that moves, friction at the pivot, air drag.

Every check compares kreisel with something computed here without it:

- the equations of the driven, damped top written again (``Reference``: quaternion and body
  angular velocity, the inertial force -m a_O(t) at the centre of mass, viscous and drag
  torques) and integrated with scipy's DOP853, with the lab-frame energy, the pivot's force
  and the work and dissipation integrated along;
- closed forms: the axial spin of a symmetric top under viscous damping decays as
  exp(-viscous t / I3) (the axial equation decouples); under dry friction at the pivot a
  sleeping top's spin falls linearly at dry * pivot_radius * m g / I3; a top at rest sticks
  where the needed torque is within dry * pivot_radius * |R|;
- the averaged (Kapitza) potential of a rapidly shaken top, V_eff = m g l cos(theta) +
  (m l a omega sin(theta))^2 / (4 I1) (P. L. Kapitza, Zh. Eksp. Teor. Fiz. 21 (1951) 588;
  L. D. Landau and E. M. Lifshitz, Mechanics, 3rd ed., section 30), and with it the shaken
  top's sleeping threshold M3^2 = 4 I1 m g l - 2 (m l a omega)^2;
- the sleeping top's threshold M3^2 = 4 I1 m g l (Landau and Lifshitz, section 35) and the
  growth rate of the linearised motion about the upright, integrated along the slow decay of
  M3 (the loss of stability is delayed: A. I. Neishtadt, Differential Equations 23 (1987)
  1385);
- quadratures (Simpson) of kreisel's own power columns.
"""

from __future__ import annotations

import math

import _sim_reference as ref
import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import cumulative_simpson, cumulative_trapezoid, solve_ivp
from scipy.optimize import brentq

import kreisel
from kreisel import events, pivots

# --------------------------------------------------------------------------------------
# the tops and pivots of these checks
# --------------------------------------------------------------------------------------

# a generic asymmetric top (chaotic on a fixed pivot, largest Lyapunov exponent ~0.4 /s)
GENERAL = {"I1": 1.0, "I2": 0.75, "I3": 0.5, "m": 1.0, "com": (0.3, 0.2, 0.4), "g": 9.81}
GENERAL_START = (ref.euler_to_quat(0.0, 1.2, 0.3), np.array([2.0, 1.0, 3.0]))
# a Lagrange top (nutation period 2.4 s on a fixed pivot)
LAGRANGE = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.3, "g": 1.0}
LAGRANGE_START = (
    ref.euler_to_quat(0.0, 1.0, 0.0),
    ref.body_omega(1.0, 0.0, 0.3, 0.7, 5.0),
)

# harmonic pivots r_O = amplitude cos(omega t + phase): (amplitude (m), omega (rad/s), phase)
PIVOTS = {
    "x": ((0.05, 0.0, 0.0), 7.0, 0.0),
    "y": ((0.0, 0.05, 0.0), 7.0, 0.3),
    "z": ((0.0, 0.0, 0.05), 7.0, 0.4),
    "oblique": ((0.03, -0.02, 0.04), 6.0, 1.1),
    # an ellipse in the x-z plane: x = 0.05 cos(7 t), z = 0.03 cos(7 t + pi/2)
    "elliptic": ((0.05, 0.0, 0.03), 7.0, (0.0, 0.0, math.pi / 2)),
}
DAMPINGS = {
    "undamped": {},
    "viscous": {"viscous": 0.02},
    "drag": {"drag": 0.01},
    "dry": {"dry": 0.3, "pivot_radius": 0.01},
    "viscous+drag": {"viscous": 0.02, "drag": 0.01},
}


def harmonic(name):
    amplitude, omega, phase = PIVOTS[name]
    return pivots.Harmonic(amplitude, omega, phase=phase)


def damping(name):
    return kreisel.PivotDamping(**DAMPINGS[name])


def general_top(pivot=None, damp=None):
    return kreisel.HeavyTop(**GENERAL, pivot=pivot, damping=damp)


def lagrange_as_heavy(pivot=None, damp=None):
    p = LAGRANGE
    return kreisel.HeavyTop(p["I1"], p["I1"], p["I3"], p["m"], (0.0, 0.0, p["l"]), p["g"],
                            pivot=pivot, damping=damp)  # fmt: skip


def reference(kind, pivot_name=None, damping_name="undamped"):
    """The Reference of the top ``kind`` ("general" or "lagrange") on the named pivot."""
    if kind == "general":
        body = (
            (GENERAL["I1"], GENERAL["I2"], GENERAL["I3"]),
            GENERAL["m"],
            GENERAL["com"],
            GENERAL["g"],
        )
    else:
        p = LAGRANGE
        body = ((p["I1"], p["I1"], p["I3"]), p["m"], (0.0, 0.0, p["l"]), p["g"])
    drive = {}
    if pivot_name is not None:
        amplitude, omega, phase = PIVOTS[pivot_name]
        drive = {"amplitude": amplitude, "omega": omega, "phase": phase}
    damp = {k: v for k, v in DAMPINGS[damping_name].items() if k in ("viscous", "drag")}
    return Reference(*body, **drive, **damp)


def rotation_gap(q_a, q_b):
    """Largest entry of R(q_a) - R(q_b) over all rows (blind to the sign of q)."""
    return float(np.abs(ref.quat_to_matrix(q_a) - ref.quat_to_matrix(q_b)).max())


def energy_scale(traj):
    """The size of the energies in a run: what the balance is measured against (J)."""
    return float(
        np.abs(traj.energy).max() + np.abs(traj.work_by_pivot).max() + traj.dissipated.max()
    )


# --------------------------------------------------------------------------------------
# the reference: the driven, damped heavy top written again, for scipy
# --------------------------------------------------------------------------------------


class Reference:
    """A heavy top on a harmonically moving pivot with viscous and drag torques, written again.

    Body frame: principal axes about the pivot O, inertia diag(I1, I2, I3), centre of mass
    ``com`` (body, from O); q = (w, x, y, z) rotates body vectors into space (z up). The pivot
    moves as r_O(t) = amplitude cos(omega t + phase) (``phase`` a number or one per axis). In
    the frame that translates with O the body feels gravity and the inertial force
    -m a_O(t) at G, so (Euler's equations about O, body frame)

        I domega/dt = (I omega) x omega + m f x com - viscous omega - drag |omega| omega,
        f = R(q)^T (g e_z + a_O(t)),        dq/dt = 1/2 q (x) (0, omega).

    The pivot's force on the top is R = m (a_G + g e_z), a_G = a_O + R(q) (domega/dt x com +
    omega x (omega x com)); its power R . v_O and the dissipated power viscous |omega|^2 +
    drag |omega|^3 are integrated along as two more components.
    """

    def __init__(self, inertia, m, com, g, amplitude=(0.0, 0.0, 0.0), omega=0.0, phase=0.0,
                 viscous=0.0, drag=0.0):  # fmt: skip
        self.inertia = np.asarray(inertia, dtype=float)
        self.m, self.g = float(m), float(g)
        self.com = np.asarray(com, dtype=float)
        self.amplitude = np.asarray(amplitude, dtype=float)
        self.omega = float(omega)
        self.phase = np.broadcast_to(np.asarray(phase, dtype=float), (3,)).copy()
        self.viscous, self.drag = float(viscous), float(drag)

    # the pivot, vectorised: (n, 3) for an array t, (3,) for a number
    def position(self, t):
        arg = self.omega * np.asarray(t, dtype=float)[..., None] + self.phase
        return self.amplitude * np.cos(arg)

    def velocity(self, t):
        arg = self.omega * np.asarray(t, dtype=float)[..., None] + self.phase
        return -self.omega * self.amplitude * np.sin(arg)

    def acceleration(self, t):
        return -(self.omega**2) * self.position(t)

    def rhs(self, t, y):
        qw, qx, qy, qz, w1, w2, w3 = y[:7]
        i1, i2, i3 = self.inertia
        c1, c2, c3 = self.com
        k = 2.0 / (qw * qw + qx * qx + qy * qy + qz * qz)
        xx, yy, zz, xy = k * qx * qx, k * qy * qy, k * qz * qz, k * qx * qy
        xz, yz, wx, wy, wz = k * qx * qz, k * qy * qz, k * qw * qx, k * qw * qy, k * qw * qz
        r = (
            (1 - yy - zz, xy - wz, xz + wy),
            (xy + wz, 1 - xx - zz, yz - wx),
            (xz - wy, yz + wx, 1 - xx - yy),
        )
        wt = self.omega * t
        a = [-(self.omega**2) * self.amplitude[k] * math.cos(wt + self.phase[k]) for k in range(3)]
        v = [-self.omega * self.amplitude[k] * math.sin(wt + self.phase[k]) for k in range(3)]
        fs = (a[0], a[1], a[2] + self.g)
        f1, f2, f3 = (r[0][j] * fs[0] + r[1][j] * fs[1] + r[2][j] * fs[2] for j in range(3))
        speed = math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
        damp = self.viscous + self.drag * speed
        t1 = self.m * (f2 * c3 - f3 * c2) - damp * w1
        t2 = self.m * (f3 * c1 - f1 * c3) - damp * w2
        t3 = self.m * (f1 * c2 - f2 * c1) - damp * w3
        d1 = ((i2 - i3) * w2 * w3 + t1) / i1
        d2 = ((i3 - i1) * w3 * w1 + t2) / i2
        d3 = ((i1 - i2) * w1 * w2 + t3) / i3
        # the acceleration of G relative to O, body frame: domega x com + omega x (omega x com)
        x1, x2, x3 = w2 * c3 - w3 * c2, w3 * c1 - w1 * c3, w1 * c2 - w2 * c1
        b1 = d2 * c3 - d3 * c2 + w2 * x3 - w3 * x2
        b2 = d3 * c1 - d1 * c3 + w3 * x1 - w1 * x3
        b3 = d1 * c2 - d2 * c1 + w1 * x2 - w2 * x1
        # the pivot's force m (a_O + R b + g e_z) . v_O
        fz = (0.0, 0.0, self.g)
        power = self.m * sum(
            (a[k] + r[k][0] * b1 + r[k][1] * b2 + r[k][2] * b3 + fz[k]) * v[k] for k in range(3)
        )
        return [
            0.5 * (-qx * w1 - qy * w2 - qz * w3),
            0.5 * (qw * w1 + qy * w3 - qz * w2),
            0.5 * (qw * w2 + qz * w1 - qx * w3),
            0.5 * (qw * w3 + qx * w2 - qy * w1),
            d1, d2, d3,
            power,
            damp * speed * speed,
        ]  # fmt: skip

    def run(self, q0, omega0, t_eval, *, t0=0.0, rtol=1e-11, atol=1e-13):
        """DOP853 from (q0, omega0) at t0: dict of t, q (normalised), omega, work (by the
        pivot) and dissipated at ``t_eval``."""
        t_eval = np.asarray(t_eval, dtype=float)
        q0 = np.asarray(q0, dtype=float)
        y0 = [*(q0 / np.linalg.norm(q0)), *np.asarray(omega0, dtype=float), 0.0, 0.0]
        sol = solve_ivp(self.rhs, (t0, float(t_eval[-1])), y0, method="DOP853", rtol=rtol,
                        atol=atol, t_eval=t_eval)  # fmt: skip
        assert sol.success, sol.message
        q = sol.y[:4].T
        return {
            "t": sol.t,
            "q": q / np.linalg.norm(q, axis=1, keepdims=True),
            "omega": sol.y[4:7].T,
            "work": sol.y[7],
            "dissipated": sol.y[8],
        }

    def energy(self, t, q, omega):
        """Lab-frame energy: 1/2 m |v_G|^2 + 1/2 omega . I_G omega + m g z_G (vectorised)."""
        r = ref.quat_to_matrix(q)
        w = np.asarray(omega, dtype=float)
        v_g = self.velocity(t) + np.einsum("nij,nj->ni", r, np.cross(w, self.com))
        z_g = self.position(t)[:, 2] + r[:, 2, :] @ self.com
        c2 = self.com @ self.com
        rot = 0.5 * np.sum(self.inertia * w * w, axis=1)
        rot -= 0.5 * self.m * (c2 * np.sum(w * w, axis=1) - (w @ self.com) ** 2)  # I_O -> I_G
        return 0.5 * self.m * np.sum(v_g * v_g, axis=1) + rot + self.m * self.g * z_g

    def reaction(self, t, q, omega):
        """The pivot's force on the top, m (a_G + g e_z), space frame (vectorised)."""
        t = np.asarray(t, dtype=float)
        out = np.empty((len(t), 3))
        for k, (tk, qk, wk) in enumerate(zip(t, q, omega)):
            d = np.asarray(self.rhs(tk, [*qk, *wk])[4:7])
            rel = np.cross(d, self.com) + np.cross(wk, np.cross(wk, self.com))
            out[k] = self.m * (self.acceleration(tk) + ref.quat_to_matrix(qk) @ rel)
        out[:, 2] += self.m * self.g
        return out


# --------------------------------------------------------------------------------------
# the reference is right: it reduces to the fixed pivot and keeps its own energy balance
# --------------------------------------------------------------------------------------


def test_reference_on_a_fixed_pivot_is_the_heavy_top():
    q0, w0 = GENERAL_START
    t = np.linspace(0.0, 3.0, 61)
    out = reference("general").run(q0, w0, t)
    body = ref.Body(GENERAL["I1"], GENERAL["I2"], GENERAL["I3"], GENERAL["m"], GENERAL["com"])
    q, w = ref.integrate_quaternion(body, q0, w0, t)
    assert rotation_gap(out["q"], q) < 1e-8
    assert np.abs(out["omega"] - w).max() < 1e-8
    assert np.abs(out["work"]).max() == 0.0 and np.abs(out["dissipated"]).max() == 0.0


def test_reference_keeps_its_energy_balance():
    """d/dt (T + m g z_G) = R . v_O - dissipated power: the Reference's energy, pivot force and
    powers are consistent with each other (a wrong force or energy would break this)."""
    q0, w0 = GENERAL_START
    t = np.linspace(0.0, 4.0, 401)
    rf = reference("general", "oblique", "viscous+drag")
    out = rf.run(q0, w0, t)
    e = rf.energy(t, out["q"], out["omega"])
    balance = e + out["dissipated"] - out["work"]
    assert np.ptp(e) > 1.0 and out["dissipated"][-1] > 0.1 and np.ptp(out["work"]) > 1.0
    assert np.ptp(balance) < 1e-9 * (np.abs(e).max() + np.abs(out["work"]).max())


# --------------------------------------------------------------------------------------
# pivots
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["x", "z", "oblique"])
def test_harmonic_pivot_kinematics(name):
    amplitude, omega, phase = PIVOTS[name]
    pivot = harmonic(name)
    a = np.asarray(amplitude)
    t = np.linspace(-1.0, 3.0, 57)
    arg = (omega * t + phase)[:, None]
    assert_allclose(pivot.position(t), a * np.cos(arg), rtol=0, atol=1e-15)
    assert_allclose(pivot.velocity(t), -omega * a * np.sin(arg), rtol=0, atol=1e-14)
    assert_allclose(pivot.acceleration(t), -(omega**2) * a * np.cos(arg), rtol=0, atol=1e-13)
    assert pivot.position(t).shape == (57, 3)
    for f in (pivot.position, pivot.velocity, pivot.acceleration):
        assert np.shape(f(0.7)) == (3,)
        assert_allclose(f(0.7), f(np.array([0.7]))[0], rtol=0, atol=0)
    assert pivot.period == pytest.approx(2 * math.pi / omega, rel=1e-15)


def test_elliptic_pivot_kinematics():
    pivot = harmonic("elliptic")
    t = np.linspace(0.0, 2.0, 41)
    r = pivot.position(t)
    assert_allclose(r[:, 0], 0.05 * np.cos(7.0 * t), rtol=0, atol=1e-15)
    assert_allclose(r[:, 2], -0.03 * np.sin(7.0 * t), rtol=0, atol=1e-15)
    # an ellipse, not a line: (x / 0.05)^2 + (z / 0.03)^2 = 1
    assert_allclose((r[:, 0] / 0.05) ** 2 + (r[:, 2] / 0.03) ** 2, 1.0, rtol=1e-13)


def test_fixed_pivot_is_the_default_and_at_rest():
    top = general_top()
    assert isinstance(top.pivot, pivots.Fixed)
    assert top.pivot.period is None
    t = np.linspace(0.0, 1.0, 5)
    for f in (top.pivot.position, top.pivot.velocity, top.pivot.acceleration):
        assert np.array_equal(f(t), np.zeros((5, 3)))
        assert np.array_equal(f(0.3), np.zeros(3))
    # a top on a fixed pivot without damping keeps the plain heavy top's columns; a damped
    # one has the pivot's, at rest, and no work done by it
    damped = general_top(damp=damping("viscous"))
    traj = kreisel.simulate(damped, damped.state_from_quaternion(*GENERAL_START), 1.0)
    assert np.array_equal(traj.pivot_position, np.zeros((len(traj), 3)))
    assert np.array_equal(traj.pivot_velocity, np.zeros((len(traj), 3)))
    assert np.array_equal(traj.work_by_pivot, np.zeros(len(traj)))
    assert np.array_equal(traj.power_pivot, np.zeros(len(traj)))


def smoothstep(s):
    """35 s^4 - 84 s^5 + 70 s^6 - 20 s^7: a septic from 0 to 1 with zero velocity,
    acceleration and jerk at both ends (so the septic spline with those end conditions
    through its samples is itself)."""
    return s**4 * (35.0 - 84.0 * s + 70.0 * s * s - 20.0 * s**3)


PATH_T = np.array([0.0, 0.15, 0.4, 0.5, 0.8, 1.0])
PATH_DIR = np.array([0.02, -0.01, 0.03])  # m


def path_of_smoothstep():
    return pivots.Path(PATH_T, smoothstep(PATH_T)[:, None] * PATH_DIR)


def test_path_reproduces_a_septic_with_its_end_conditions():
    path = path_of_smoothstep()
    t = np.linspace(0.0, 1.0, 201)
    s = smoothstep(t)
    v = 140.0 * t**3 * (1.0 - t) ** 3
    a = 420.0 * t**2 * (1.0 - t) ** 2 * (1.0 - 2.0 * t)
    assert_allclose(path.position(t), s[:, None] * PATH_DIR, rtol=0, atol=1e-14)
    assert_allclose(path.velocity(t), v[:, None] * PATH_DIR, rtol=0, atol=1e-12)
    assert_allclose(path.acceleration(t), a[:, None] * PATH_DIR, rtol=0, atol=1e-10)


def test_path_interpolates_is_c2_and_constant_outside():
    rng = np.random.default_rng(3)
    t_s = np.array([0.0, 0.2, 0.5, 0.6, 1.1, 1.5, 2.0])
    p_s = rng.uniform(-0.05, 0.05, (7, 3))
    path = pivots.Path(t_s, p_s)
    assert path.period is None
    assert_allclose(path.position(t_s), p_s, rtol=0, atol=1e-15)
    # zero velocity and acceleration at both ends, constant outside the samples
    for tt in (t_s[0], t_s[-1]):
        assert np.abs(path.velocity(tt)).max() < 1e-12
        assert np.abs(path.acceleration(tt)).max() < 1e-9
    outside = np.array([-1.0, -1e-3, 2.0 + 1e-3, 5.0])
    assert_allclose(path.position(outside), p_s[[0, 0, -1, -1]], rtol=0, atol=1e-15)
    assert np.array_equal(path.velocity(outside), np.zeros((4, 3)))
    assert np.array_equal(path.acceleration(outside), np.zeros((4, 3)))
    # velocity and acceleration are the derivatives (central differences, h^2 accurate)
    t = np.linspace(0.01, 1.99, 173)
    h = 1e-5
    fd_v = (path.position(t + h) - path.position(t - h)) / (2 * h)
    fd_a = (path.velocity(t + h) - path.velocity(t - h)) / (2 * h)
    assert_allclose(path.velocity(t), fd_v, rtol=0, atol=1e-6)
    assert_allclose(path.acceleration(t), fd_a, rtol=0, atol=1e-4)
    # C2: position, velocity and acceleration continuous across every sample
    eps = 1e-9
    for f, tol in ((path.position, 1e-8), (path.velocity, 1e-6), (path.acceleration, 1e-4)):
        jump = f(t_s[1:-1] + eps) - f(t_s[1:-1] - eps)
        assert np.abs(jump).max() < tol, (f.__name__, np.abs(jump).max())
    # and not C2 by being flat: it moves between the samples
    assert np.abs(path.velocity(t)).max() > 0.01


# --------------------------------------------------------------------------------------
# a second formulation: the same driven, damped top with scipy
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("damping_name", ["undamped", "viscous+drag"])
@pytest.mark.parametrize("pivot_name", ["x", "z", "elliptic"])
@pytest.mark.parametrize("kind", ["general", "lagrange"])
def test_driven_top_agrees_with_the_scipy_formulation(kind, pivot_name, damping_name):
    """kreisel (DOP853, rtol 1e-10, atol 1e-12) against the Reference (DOP853, rtol 1e-11)
    over 4 s. Each keeps its local errors near its tolerance; over 4 s of this motion
    (largest Lyapunov exponent below ~0.5 /s: growth e^2 ~ 7) their global errors stay near
    1e-9 at most (measured: 2e-10 for the general top, 2e-11 for the Lagrange top), so 1e-8
    leaves a margin for the constants without letting an error in the equations through
    (a term of relative size 1e-8 in the torque would show)."""
    make = general_top if kind == "general" else lagrange_as_heavy
    q0, w0 = GENERAL_START if kind == "general" else LAGRANGE_START
    top = make(harmonic(pivot_name), damping(damping_name))
    rf = reference(kind, pivot_name, damping_name)
    t = np.linspace(0.0, 4.0, 161)
    traj = kreisel.simulate(top, top.state_from_quaternion(q0, w0), 4.0, t_eval=t)
    out = rf.run(q0, w0, t)
    assert np.array_equal(traj.t, t)
    w_scale = np.abs(out["omega"]).max()
    assert rotation_gap(traj.quaternion, out["q"]) < 1e-8
    assert np.abs(traj.omega - out["omega"]).max() < 1e-8 * w_scale
    # the pivot's columns are its closed form
    assert_allclose(traj.pivot_position, rf.position(t), rtol=0, atol=1e-14)
    assert_allclose(traj.pivot_velocity, rf.velocity(t), rtol=0, atol=1e-13)
    # the diagnostics are what they claim, recomputed from kreisel's own states
    q, w = traj.quaternion, traj.omega
    e = rf.energy(t, q, w)
    assert_allclose(traj.energy, e, rtol=0, atol=1e-12 * np.abs(e).max())
    force = rf.reaction(t, q, w)
    f_scale = np.abs(force).max()
    assert_allclose(traj.reaction_force, force, rtol=0, atol=1e-11 * f_scale)
    power = np.sum(force * rf.velocity(t), axis=1)
    assert_allclose(traj.power_pivot, power, rtol=0, atol=1e-11 * np.abs(power).max() + 1e-300)
    speed = np.linalg.norm(w, axis=1)
    p_diss = rf.viscous * speed**2 + rf.drag * speed**3
    assert_allclose(traj.power_dissipated, p_diss, rtol=1e-12, atol=0)
    mz = np.einsum("nij,nj->ni", ref.quat_to_matrix(q), rf.inertia * w)[:, 2]
    assert_allclose(traj.Mz, mz, rtol=0, atol=1e-12 * np.abs(rf.inertia * w).max())
    # the work and the dissipation agree with the Reference's own integrals
    e_scale = np.abs(e).max() + np.abs(out["work"]).max() + out["dissipated"].max()
    assert np.abs(traj.work_by_pivot - out["work"]).max() < 1e-8 * e_scale
    assert np.abs(traj.dissipated - out["dissipated"]).max() < 1e-8 * e_scale
    if damping_name == "undamped":
        assert np.array_equal(traj.dissipated, np.zeros(len(t)))
    else:
        assert out["dissipated"][-1] > 0.01 * e_scale


# --------------------------------------------------------------------------------------
# the energy balance: E + dissipated - work_by_pivot is constant
# --------------------------------------------------------------------------------------


def check_balance(traj, tol=1e-8):
    """The balance column is E + dissipated - work, constant to ``tol`` of the energy scale;
    the work and the dissipation are the integrals (Simpson, on kreisel's fine t_eval) of
    their powers; the dissipated power is never negative."""
    scale = energy_scale(traj)
    assert_allclose(
        traj.balance, traj.energy + traj.dissipated - traj.work_by_pivot, rtol=0,
        atol=1e-13 * scale,
    )  # fmt: skip
    assert np.ptp(traj.balance) < tol * scale, (np.ptp(traj.balance), scale)
    t = traj.t
    work = cumulative_simpson(traj.power_pivot, x=t, initial=0.0)
    diss = cumulative_simpson(traj.power_dissipated, x=t, initial=0.0)
    assert np.abs(traj.work_by_pivot - work).max() < tol * scale
    assert np.abs(traj.dissipated - diss).max() < tol * scale
    assert np.all(traj.power_dissipated >= 0.0)
    assert np.all(np.diff(traj.dissipated) >= -1e-15 * scale)
    return scale


@pytest.mark.parametrize("damping_name", ["undamped", "viscous", "drag", "dry"])
@pytest.mark.parametrize("pivot_name", list(PIVOTS))
def test_energy_balance_with_a_harmonic_pivot(pivot_name, damping_name):
    """A spinning general top (it never comes to rest, so dry friction only slides): over 4 s
    the energy changes by several J while the balance stays within 1e-8 of the energy scale
    (the integration's tolerance is 1e-10); t_eval every 0.5 ms makes Simpson's rule exact to
    ~(omega dt)^4 ~ 1e-13."""
    top = general_top(harmonic(pivot_name), damping(damping_name))
    t = np.linspace(0.0, 4.0, 8001)
    traj = kreisel.simulate(top, top.state_from_quaternion(*GENERAL_START), 4.0, t_eval=t)
    scale = check_balance(traj)
    assert np.ptp(traj.energy) > 0.05 * scale  # the pivot did work: the balance is a test
    assert np.abs(traj.work_by_pivot).max() > 0.01 * scale
    if damping_name == "undamped":
        assert np.array_equal(traj.dissipated, np.zeros(len(t)))
        assert np.array_equal(traj.power_dissipated, np.zeros(len(t)))
    else:
        assert traj.dissipated[-1] > 1e-3 * scale
    if damping_name == "dry":
        assert not traj.stuck.any()
        # sliding friction: the torque dry * pivot_radius * |R| against omega
        bound = 0.3 * 0.01 * np.linalg.norm(traj.reaction_force, axis=1)
        expected = bound * np.linalg.norm(traj.omega, axis=1)
        assert_allclose(traj.power_dissipated, expected, rtol=1e-10, atol=0)


def test_energy_balance_with_a_path_pivot():
    """The pivot moves along a sampled path (a smoothstep over 1 s, from 0.5 s) and then
    stands: the balance holds throughout, and once the path ends the pivot does no work."""
    path = pivots.Path(0.5 + PATH_T, smoothstep(PATH_T)[:, None] * PATH_DIR * 5.0)
    top = lagrange_as_heavy(path, damping("viscous"))
    t = np.linspace(0.0, 3.0, 6001)
    traj = kreisel.simulate(top, top.state_from_quaternion(*LAGRANGE_START), 3.0, t_eval=t)
    check_balance(traj)
    assert_allclose(traj.pivot_position, path.position(t), rtol=0, atol=1e-15)
    after = t > 1.5
    assert np.array_equal(traj.power_pivot[after], np.zeros(after.sum()))
    assert np.ptp(traj.work_by_pivot[after]) < 1e-12 * energy_scale(traj)
    assert np.abs(traj.work_by_pivot).max() > 1e-3


# --------------------------------------------------------------------------------------
# viscous damping of a symmetric top: omega3 = omega3(0) exp(-viscous t / I3)
# --------------------------------------------------------------------------------------

SYM = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.3, "g": 9.81}


@pytest.mark.parametrize("pivot_name", [None, "oblique", "z"])
@pytest.mark.parametrize("cls", ["LagrangeTop", "HeavyTop"])
def test_viscous_damping_decays_the_axial_spin_exactly(cls, pivot_name):
    """I3 domega3/dt = (I1 - I2) omega1 omega2 + tau3 - viscous omega3, and for a symmetric
    top with its centre of mass on the figure axis the axial torque of gravity and of the
    inertial force -m a_O (both act at G, on the axis) vanishes: omega3 decays exactly as
    exp(-viscous t / I3), however the axis nutates and the pivot moves."""
    c = 0.05
    pivot = None if pivot_name is None else harmonic(pivot_name)
    damp = kreisel.PivotDamping(viscous=c)
    if cls == "LagrangeTop":
        top = kreisel.LagrangeTop(**SYM, pivot=pivot, damping=damp)
    else:
        top = kreisel.HeavyTop(SYM["I1"], SYM["I1"], SYM["I3"], SYM["m"], (0.0, 0.0, SYM["l"]),
                               SYM["g"], pivot=pivot, damping=damp)  # fmt: skip
    st = top.state(0.8, phi_dot=1.0, psi_dot=20.0)
    t = np.linspace(0.0, 10.0, 201)
    traj = kreisel.simulate(top, st, 10.0, t_eval=t, rtol=1e-12, atol=1e-14)
    w3_0 = 20.0 + 1.0 * math.cos(0.8)
    expected = w3_0 * np.exp(-c * t / SYM["I3"])
    assert_allclose(traj.omega[:, 2], expected, rtol=1e-10, atol=0)
    # the axis moved a lot meanwhile (the law is not trivially met)
    assert np.ptp(traj.theta) > 0.01
    assert traj.omega[-1, 2] < 0.5 * w3_0


# --------------------------------------------------------------------------------------
# a sleeping top that slows, and falls
# --------------------------------------------------------------------------------------


def growth_rate(i1, mgl, c, m3):
    """The largest real part of the roots of I1 l^2 + (c - i M3) l - m g l = 0: the
    linearised motion about the upright, zeta = theta e^(i phi), of a top with axial momentum
    M3 under the viscous torque -c omega (vectorised over m3)."""
    b = c - 1j * np.asarray(m3, dtype=float)
    disc = np.sqrt(b * b + 4.0 * i1 * mgl + 0j)
    return np.maximum((-b + disc).real, (-b - disc).real) / (2.0 * i1)


def test_sleeping_top_slows_and_falls_after_the_threshold():
    """Upright with M3(0) = 2 sqrt(4 I1 m g l) under viscous damping c: M3 = M3(0)
    exp(-c t / I3), so the sleeping condition M3^2 > 4 I1 m g l fails at

        t* = (I3 / c) ln(M3(0) / sqrt(4 I1 m g l)).

    The top does not fall then: its tilt (1e-6 at the start) must first grow, at the rate of
    the linearised motion, which is zero at t* and grows as M3 decays further (a delayed loss
    of stability). Before t* the slow precession mode already grows a little, at ~c m g l /
    M3^2 (dissipation undoes gyroscopic stabilisation: Kelvin, Tait, Chetaev), by a factor of
    at most 2^(I3 / (2 I1)) in all. So the estimate of the fall (theta = 0.1) is the time
    where the integral of the growth rate from 0 reaches ln(0.1 / 1e-6); it neglects the
    splitting of the start into the two modes and the nonlinearity at theta ~ 0.1, worth
    well under 5 % of the delay t_fall - t* (~15 s here)."""
    i1, i3, m, arm, g, c = 1.0, 0.5, 1.0, 1.0, 1.0, 0.05
    mgl = m * g * arm
    m3_0 = 2.0 * math.sqrt(4.0 * i1 * mgl)
    theta0 = 1e-6
    top = kreisel.LagrangeTop(i1, i3, m, arm, g=g, damping=kreisel.PivotDamping(viscous=c))
    st = top.state(theta0, psi_dot=m3_0 / i3)
    fall = events.theta_crossing(0.1, direction=1, terminal=True)
    traj = kreisel.simulate(top, st, 60.0, events=[fall])
    assert traj.status == "event"
    t_fall = traj.events[-1].t
    t_star = (i3 / c) * math.log(m3_0 / math.sqrt(4.0 * i1 * mgl))
    tt = np.linspace(0.0, 60.0, 60001)
    grown = cumulative_trapezoid(growth_rate(i1, mgl, c, m3_0 * np.exp(-c * tt / i3)), tt,
                                 initial=0.0)  # fmt: skip
    t_est = float(np.interp(math.log(0.1 / theta0), grown, tt))
    delay = t_fall - t_star
    print(
        f"sleeping top slows: t* = {t_star:.3f} s, falls (theta = 0.1) at {t_fall:.3f} s, "
        f"delay {delay:.3f} s; linear-growth estimate {t_est:.3f} s "
        f"({100 * (t_fall - t_est) / delay:+.2f} % of the delay)"
    )
    assert t_fall > t_star + 5.0
    assert abs(t_fall - t_est) < 0.05 * delay
    # meanwhile the axial spin decays as the closed form says
    i = np.searchsorted(traj.t, t_star)
    assert_allclose(traj.omega[i, 2], m3_0 / i3 * math.exp(-c * traj.t[i] / i3), rtol=1e-9)


# --------------------------------------------------------------------------------------
# Kapitza: an inverted top on a vertically shaken pivot
# --------------------------------------------------------------------------------------

# I1 about the pivot, centre of mass at l; I1 >= m l^2 and I3 <= 2 (I1 - m l^2): a real body.
KAPITZA = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.5, "g": 2.0}
SHAKE = 50.0  # rad/s: 50 times sqrt(m g l / I1)


def kapitza_amplitude(m3, share=1.0):
    """The shaking amplitude a at which (a omega)^2 is ``share`` of the threshold of the
    averaged potential V_eff = m g l cos(theta) + (m l a omega sin(theta))^2 / (4 I1):
    near theta = 0 it is m g l - (m g l - (m l a omega)^2 / (2 I1)) theta^2 / 2, a top with
    m g l_eff = m g l - (m l a omega)^2 / (2 I1), which sleeps where M3^2 > 4 I1 m g l_eff:

        (a omega)^2 > (4 I1 m g l - M3^2) / (2 m^2 l^2)     (2 g I1 / (m l) at M3 = 0)."""
    p = KAPITZA
    aw2 = (4 * p["I1"] * p["m"] * p["g"] * p["l"] - m3**2) / (2 * p["m"] ** 2 * p["l"] ** 2)
    return math.sqrt(share * aw2) / SHAKE


def shaken_top(a):
    return kreisel.LagrangeTop(**KAPITZA, pivot=pivots.Harmonic([0.0, 0.0, a], SHAKE))


def test_kapitza_threshold_without_spin():
    """No spin, tilted 0.05 rad from the inverted position, at rest: with (a omega)^2 10 %
    above 2 g I1 / (m l) the top stays up over 60 s (477 shaking periods; its slow
    oscillation in the averaged well has a period of ~20 s, the well's rim is at 0.43 rad);
    10 % below it falls (the averaged motion grows at ~0.3 /s)."""
    p = KAPITZA
    assert kapitza_amplitude(0.0) * SHAKE == pytest.approx(
        math.sqrt(2 * p["g"] * p["I1"] / (p["m"] * p["l"]))
    )
    up = shaken_top(kapitza_amplitude(0.0, 1.1))
    st = up.state(0.05)
    traj = kreisel.simulate(up, st, 60.0)
    assert traj.theta.max() < 0.15, traj.theta.max()
    down = shaken_top(kapitza_amplitude(0.0, 0.9))
    fall = events.theta_crossing(1.0, direction=1, terminal=True)
    traj = kreisel.simulate(down, st, 60.0, events=[fall])
    assert traj.status == "event" and traj.events[-1].t < 30.0
    # and without shaking it falls at once (the inverted top is unstable)
    still = kreisel.LagrangeTop(**KAPITZA)
    traj = kreisel.simulate(still, st, 60.0, events=[fall])
    assert traj.status == "event" and traj.events[-1].t < 5.0


def leaves_the_upright(shares, m3s, t_end=60.0):
    """For each (share, M3): whether the top, tilted 0.01 rad at rest with axial momentum M3,
    leaves the upright (theta > 0.3) within t_end on the pivot shaken at that share of the
    threshold amplitude, all runs in one simulate_many batch."""
    tops = [shaken_top(kapitza_amplitude(m3, s)) for s, m3 in zip(shares, m3s)]
    states = [t.state(0.01, psi_dot=m3 / KAPITZA["I3"]) for t, m3 in zip(tops, m3s)]
    out = kreisel.simulate_many(tops, states, t_end)
    assert all(e is None for e in out.errors), out.errors
    return out.theta_max > 0.3


def test_kapitza_sleeping_threshold_with_spin():
    """The shaken, spinning top's sleeping threshold M3^2 = 4 I1 m g l - 2 (m l a omega)^2
    (from V_eff): at three spins the simulated boundary in the amplitude a, found by
    bisection between 0.85 and 1.15 of the formula's a (7 halvings: 0.25 %), lies within 3 %
    of the formula. Near the boundary the linearised motion grows at sqrt(4 I1 m g l_eff -
    M3^2) / (2 I1), fast enough within 60 s to leave 0.3 rad once a is 0.5 % below it; above
    it the two nutation modes stay near 0.01 * M3 / sqrt(4 I1 m g l_eff - M3^2) < 0.3."""
    m3s = np.array([0.5, 1.0, 1.4])
    lo, hi = np.full(3, 0.85), np.full(3, 1.15)  # in units of the formula's amplitude
    assert leaves_the_upright(lo**2, m3s).all()
    assert not leaves_the_upright(hi**2, m3s).any()
    for _ in range(7):
        mid = 0.5 * (lo + hi)
        leaves = leaves_the_upright(mid**2, m3s)
        lo, hi = np.where(leaves, mid, lo), np.where(leaves, hi, mid)
    boundary = 0.5 * (lo + hi)
    for m3, b in zip(m3s, boundary):
        print(
            f"Kapitza with spin M3 = {m3}: simulated boundary a = {b * kapitza_amplitude(m3):.5f}"
            f" m, formula {kapitza_amplitude(m3):.5f} m ({100 * (b - 1):+.2f} %)"
        )
    assert np.all(np.abs(boundary - 1.0) < 0.03), boundary


# --------------------------------------------------------------------------------------
# chaos on a shaken pivot
# --------------------------------------------------------------------------------------

# A Lagrange top (a real body: I1 - m l^2 = 0.75 >= I3 / 2) shaken vertically at 0.4 m,
# 3 rad/s, near its own frequencies: chaotic (scipy reference: ~0.27 /s over 100 s).
CHAOS = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.5, "g": 2.0}
CHAOS_PIVOT = ((0.0, 0.0, 0.4), 3.0, 0.0)
CHAOS_START = (ref.euler_to_quat(0.0, 1.0, 0.0), np.array([0.0, 0.0, 2.0]))
DIRECTION = np.ones(6) / math.sqrt(6.0)


def chaos_reference(shaken=True):
    p = CHAOS
    amplitude, omega, phase = CHAOS_PIVOT if shaken else ((0.0, 0.0, 0.0), 0.0, 0.0)
    return Reference((p["I1"], p["I1"], p["I3"]), p["m"], (0.0, 0.0, p["l"]), p["g"],
                     amplitude, omega, phase)  # fmt: skip


def chaos_top(shaken=True):
    pivot = pivots.Harmonic(CHAOS_PIVOT[0], CHAOS_PIVOT[1]) if shaken else None
    return kreisel.LagrangeTop(**CHAOS, pivot=pivot)


def reference_lyapunov(rf, q0, w0, tau, n, d0=1e-9):
    """Benettin's renormalisation (as kreisel documents it: a second motion d0 away along
    DIRECTION, renormalised every tau) with the Reference at rtol 1e-12; the clock runs on,
    so each segment starts at its own time on the moving pivot."""
    q, w = np.asarray(q0, dtype=float), np.asarray(w0, dtype=float)
    qp, wp = ref.perturb(q, w, d0 * DIRECTION)
    total, running = 0.0, []
    for k in range(n):
        span = [k * tau, (k + 1) * tau]
        a = rf.run(q, w, span, t0=span[0], rtol=1e-12, atol=1e-14)
        b = rf.run(qp, wp, span, t0=span[0], rtol=1e-12, atol=1e-14)
        q, w, qp, wp = a["q"][-1], a["omega"][-1], b["q"][-1], b["omega"][-1]
        diff = ref.difference(q, w, qp, wp)
        dist = float(np.linalg.norm(diff))
        total += math.log(dist / d0)
        running.append(total / ((k + 1) * tau))
        qp, wp = ref.perturb(q, w, diff * (d0 / dist))
    return np.array(running)


def test_shaken_top_lyapunov_matches_the_reference_while_the_motions_agree():
    """Over the first 12 s the two integrations (both at rtol 1e-12) stay within ~1e-8 of
    each other, so the running estimates agree closely (they part later: chaos)."""
    top = chaos_top()
    st = top.state_from_quaternion(*CHAOS_START)
    est = top.lyapunov(st, 12.0, tau=1.0, rtol=1e-12, atol=1e-14)
    expected = reference_lyapunov(chaos_reference(), *CHAOS_START, 1.0, 12)
    assert_allclose(est.t, np.arange(1.0, 13.0), rtol=1e-15)
    assert_allclose(est.running, expected, rtol=1e-4)


def test_shaken_top_is_chaotic_and_the_still_one_regular():
    """The shaken top's exponent settles positive; the same top on a fixed pivot is a
    Lagrange top (integrable): its separations grow linearly, so its running estimate
    decays like ln(t)/t."""
    chaotic = chaos_top().lyapunov(chaos_top().state_from_quaternion(*CHAOS_START), 300.0)
    assert chaotic.exponent > 0.1, chaotic.exponent
    tail = chaotic.running[chaotic.t > 200.0]
    assert np.ptp(tail) < 0.25 * chaotic.exponent
    still = chaos_top(shaken=False)
    regular = still.lyapunov(still.state_from_quaternion(*CHAOS_START), 300.0)
    r = regular.running
    assert regular.exponent < 0.05, regular.exponent
    assert regular.exponent < 0.6 * r[29]  # at 300 s against 30 s: ln(t)/t falls by ~5
    print(
        f"Lyapunov exponents over 300 s: shaken {chaotic.exponent:.3f} /s, "
        f"still {regular.exponent:.4f} /s (at 30 s: {r[29]:.4f})"
    )


# --------------------------------------------------------------------------------------
# stroboscopic sections
# --------------------------------------------------------------------------------------


def test_poincare_section_is_the_state_once_per_period():
    top = chaos_top()
    st = top.state_from_quaternion(*CHAOS_START)
    period = 2 * math.pi / CHAOS_PIVOT[1]
    section = kreisel.poincare(top, st, 6)
    assert len(section) == 7
    assert_allclose(section.t, period * np.arange(7), rtol=1e-14, atol=0)
    out = chaos_reference().run(*CHAOS_START, period * np.arange(7))
    assert rotation_gap(section.quaternion, out["q"]) < 1e-7
    assert np.abs(section.omega - out["omega"]).max() < 1e-7 * np.abs(out["omega"]).max()
    # an explicit period
    half = kreisel.poincare(top, st, 4, period=period / 2)
    assert_allclose(half.t, period / 2 * np.arange(5), rtol=1e-14, atol=0)


def test_poincare_on_an_event_and_without_a_period():
    still = chaos_top(shaken=False)
    st = still.state_from_quaternion(*CHAOS_START)
    with pytest.raises(kreisel.ParameterError, match="period"):
        kreisel.poincare(still, st, 5)
    ev = kreisel.Event(lambda t, s: s.omega[0], name="omega1_up", direction=1)
    section = kreisel.poincare(still, st, 5, event=ev, t_end=60.0)
    crossings = section.t > 0
    assert crossings.sum() == 5
    assert np.abs(section.omega[crossings, 0]).max() < 1e-8
    # the same crossings from the Reference: omega1 at those times is zero there too
    out = chaos_reference(shaken=False).run(*CHAOS_START, np.concatenate([[0.0],
                                            section.t[crossings]]))  # fmt: skip
    assert np.abs(out["omega"][1:, 0]).max() < 1e-7


def test_poincare_figure_draws_the_section():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import kreisel.plot

    top = chaos_top()
    section = kreisel.poincare(top, top.state_from_quaternion(*CHAOS_START), 20)
    drawn = kreisel.plot.poincare(section)
    fig = drawn if hasattr(drawn, "savefig") else drawn.figure
    points = []
    for ax in fig.axes:
        points += [c.get_offsets() for c in ax.collections]
        points += [np.column_stack(line.get_data()) for line in ax.lines]
    assert any(len(p) == 21 and np.allclose(p[:, 0], section.theta) for p in points)
    plt.close(fig)


# --------------------------------------------------------------------------------------
# dry friction at the pivot
# --------------------------------------------------------------------------------------

# a pendulum-like top: centre of mass 0.5 m down its figure axis; released from rest it
# swings in a vertical plane about a horizontal axis through the pivot
PENDULUM = {"I1": 1.0, "I2": 1.0, "I3": 0.5, "m": 1.0, "com": (0.0, 0.0, 0.5), "g": 9.81}
DRY = {"dry": 0.5, "pivot_radius": 0.1}  # the torque bound is 0.05 |R|: 0.05 m g at rest


def pendulum(tilt):
    """The pendulum at rest with its centre of mass ``tilt`` from straight down."""
    top = kreisel.HeavyTop(**PENDULUM, damping=kreisel.PivotDamping(**DRY))
    return top, top.state(math.pi - tilt)


def test_dry_friction_holds_a_top_where_the_torque_is_within_its_bound():
    """At rest the pivot carries the weight, |R| = m g; gravity's torque m g |c| sin(tilt)
    is within dry * pivot_radius * m g where |c| sin(tilt) <= dry * pivot_radius = 0.05 m."""
    tilt = math.asin(0.9 * 0.05 / 0.5)
    top, st = pendulum(tilt)
    traj = kreisel.simulate(top, st, 5.0, t_eval=np.linspace(0.0, 5.0, 51))
    assert traj.stuck.all()
    assert np.abs(traj.omega).max() == 0.0
    assert np.ptp(traj.energy) == 0.0 and np.abs(traj.dissipated).max() == 0.0
    assert_allclose(traj.theta, math.pi - tilt, rtol=0, atol=1e-14)
    assert_allclose(traj.reaction_force, np.tile([0.0, 0.0, 9.81], (51, 1)), atol=1e-12)


def test_dry_friction_stops_a_swinging_top_with_its_energy_accounted():
    """Tilted 0.6 rad (|c| sin(tilt) = 0.28 m > 0.05 m) the top swings; sliding friction
    takes dry * pivot_radius * |R| * |omega| (R the pivot's force, which varies along the
    swing) until it sticks where gravity's torque is within the bound."""
    top, st = pendulum(0.6)
    traj = kreisel.simulate(top, st, 15.0, t_eval=np.linspace(0.0, 15.0, 15001))
    speed = np.linalg.norm(traj.omega, axis=1)
    assert speed.max() > 1.0  # it swung
    assert traj.stuck[-1] and speed[-1] == 0.0  # and came to rest
    assert not traj.stuck[1]
    tilt = math.pi - traj.theta[-1]
    assert 0.5 * math.sin(tilt) <= 0.05 * (1 + 1e-9), tilt
    scale = energy_scale(traj)
    assert np.ptp(traj.balance) < 1e-8 * scale
    assert_allclose(traj.balance, traj.energy + traj.dissipated, rtol=0, atol=1e-13 * scale)
    assert traj.dissipated[-1] > 0.5 * (traj.energy[0] - traj.energy.min())
    sliding = ~traj.stuck
    bound = 0.05 * np.linalg.norm(traj.reaction_force, axis=1)
    assert_allclose(traj.power_dissipated[sliding], (bound * speed)[sliding], rtol=1e-10)
    assert np.array_equal(traj.power_dissipated[traj.stuck], np.zeros(traj.stuck.sum()))
    # once stuck it stays stuck (nothing moves it any more)
    first = int(np.argmax(traj.stuck & (np.arange(len(traj)) > 0)))
    assert traj.stuck[first:].all()


def test_dry_friction_lets_go_when_the_shaken_pivot_asks_too_much():
    """The pendulum held at rest (|c| sin(tilt) = 0.02 m < 0.05 m) on a pivot shaken
    sideways, y_O = -A sin(omega t), in the plane of its tilt. Held, it moves with the pivot:
    the torque needed about O is m |r_G x (g e_z + a_O)| and the bound dry * pivot_radius *
    m |g e_z + a_O|; it lets go where the first exceeds the second (found here by root
    finding, for the start's orientation and for every later one it is held at), and the
    balance holds through the switches."""
    tilt = math.asin(0.02 / 0.5)
    amp, omega = 0.08, 5.0  # peak acceleration 2 m/s^2
    shaker = pivots.Harmonic([0.0, amp, 0.0], omega, phase=math.pi / 2)
    top = kreisel.HeavyTop(**PENDULUM, pivot=shaker, damping=kreisel.PivotDamping(**DRY))

    def margin(r_g):
        def f(t):
            g_eff = np.array([0.0, amp * omega**2 * math.sin(omega * t), 9.81])
            return np.linalg.norm(np.cross(r_g, g_eff)) - 0.05 * np.linalg.norm(g_eff)

        return f

    start = margin(0.5 * np.array([0.0, -math.sin(tilt), -math.cos(tilt)]))  # theta = pi - tilt
    assert start(0.0) < 0.0
    t_break = brentq(start, 0.0, 0.2, xtol=1e-14)
    t = np.linspace(0.0, 1.5, 15001)
    traj = kreisel.simulate(top, top.state(math.pi - tilt), 1.5, t_eval=t)
    held = traj.stuck
    switches = np.flatnonzero(np.diff(held.astype(int)))
    assert held[0] and t[switches[0]] < t_break <= t[switches[0] + 1]
    assert np.abs(traj.omega[: switches[0] + 1]).max() == 0.0
    # every later hold: at rest at its orientation until that orientation's margin turns
    assert len(switches) >= 3, t[switches]
    com = np.asarray(PENDULUM["com"])
    for i, j in zip(switches[1::2], switches[2::2]):
        assert held[i + 1] and not held[j + 1]
        assert np.abs(traj.omega[i + 1 : j + 1]).max() == 0.0
        f = margin(ref.quat_to_matrix(traj.quaternion[i + 1]) @ com)
        assert f(t[i + 1]) <= 1e-9 and f(t[j + 1]) > 0.0
        assert t[j] <= brentq(f, t[i + 1], t[j + 1], xtol=1e-14) <= t[j + 1] + 1e-12
    assert np.ptp(traj.balance) < 1e-8 * energy_scale(traj)


def test_dry_friction_spins_down_a_sleeping_top_linearly():
    """Upright and spinning, the top sleeps (this one is exactly upright: no torque tilts
    it); |R| = m g and the friction torque dry * pivot_radius * m g opposes the spin, so
    omega3 falls linearly at dry * pivot_radius * m g / I3 = 0.981 rad/s^2 and the top sticks
    when it stops, at omega3(0) I3 / (dry * pivot_radius * m g)."""
    top = kreisel.HeavyTop(**PENDULUM, damping=kreisel.PivotDamping(**DRY))
    w0 = 6.0
    st = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, w0])
    rate = 0.05 * 9.81 / 0.5
    t_stop = w0 / rate
    t = np.linspace(0.0, 8.0, 801)
    traj = kreisel.simulate(top, st, 8.0, t_eval=t)
    expected = np.maximum(w0 - rate * t, 0.0)
    assert_allclose(traj.omega[:, 2], expected, rtol=0, atol=1e-9)
    assert np.abs(traj.omega[:, :2]).max() < 1e-12
    assert_allclose(traj.theta, 0.0, rtol=0, atol=1e-9)
    assert traj.stuck[t > t_stop + 1e-6].all() and not traj.stuck[t < t_stop - 1e-6].any()
    # the kinetic energy went into friction: dissipated = 1/2 I3 omega3(0)^2 at the end
    assert traj.dissipated[-1] == pytest.approx(0.5 * 0.5 * w0**2, rel=1e-9)


# --------------------------------------------------------------------------------------
# which methods take which tops
# --------------------------------------------------------------------------------------

# the methods' rules for a moving pivot and each damping term (True: it takes the top)
TAKES = {
    "dop853": {"moving": True, "viscous": True, "drag": True, "dry": True},
    "rk4": {"moving": True, "viscous": True, "drag": True, "dry": False},
    "midpoint": {"moving": True, "viscous": True, "drag": True, "dry": False},
    "gauss4": {"moving": True, "viscous": True, "drag": True, "dry": False},
    "splitting": {"moving": True, "viscous": False, "drag": False, "dry": False},
    "splitting4": {"moving": True, "viscous": False, "drag": False, "dry": False},
    "splitting6": {"moving": True, "viscous": False, "drag": False, "dry": False},
    "verlet": {"moving": False, "viscous": False, "drag": False, "dry": False},
}


def test_every_method_is_listed():
    assert set(TAKES) == {m.name for m in kreisel.methods()}


@pytest.mark.parametrize("what", ["moving", "viscous", "drag", "dry"])
@pytest.mark.parametrize("method", list(TAKES))
def test_methods_take_or_refuse_driven_and_damped_tops(method, what):
    if what == "moving":
        top = kreisel.LagrangeTop(**LAGRANGE, pivot=harmonic("z"))
    else:
        top = kreisel.LagrangeTop(**LAGRANGE, damping=damping(what))
    st = top.state(1.0, theta_dot=0.3, phi_dot=0.7, psi_dot=5.0)
    dt = None if method == "dop853" else 0.01
    if TAKES[method][what]:
        traj = kreisel.simulate(top, st, 0.5, method=method, dt=dt)
        assert traj.status == "completed"
    else:
        with pytest.raises(kreisel.ParameterError, match=method) as info:
            kreisel.simulate(top, st, 0.5, method=method, dt=dt)
        reason = {"moving": "pivot", "viscous": "damp|viscous", "drag": "damp|drag",
                  "dry": "dry|friction|damp"}[what]  # fmt: skip
        assert info.match(reason)


@pytest.mark.parametrize("method", ["rk4", "midpoint", "gauss4", "splitting", "splitting4",
                                    "splitting6"])  # fmt: skip
def test_fixed_step_methods_keep_their_order_on_a_moving_pivot(method):
    """On the shaken general top (undamped, so the splittings take it): the error against
    the Reference at t = 2 s falls by 2^order when dt halves (explicit time handled at the
    method's order, e.g. by splitting in extended phase space)."""
    order = {m.name: m.order for m in kreisel.methods()}[method]
    top = general_top(harmonic("oblique"))
    st = top.state_from_quaternion(*GENERAL_START)
    exact = reference("general", "oblique").run(*GENERAL_START, [0.0, 2.0], rtol=1e-13,
                                                atol=1e-15)  # fmt: skip
    dts = {2: (0.01, 0.005), 4: (0.02, 0.01), 6: (0.05, 0.025), 8: (0.1, 0.05)}[order]
    errors = []
    for dt in dts:
        traj = kreisel.simulate(top, st, 2.0, method=method, dt=dt)
        errors.append(np.abs(traj.omega[-1] - exact["omega"][-1]).max())
    observed = math.log2(errors[0] / errors[1])
    assert abs(observed - order) < 0.35, (errors, observed)
    assert errors[1] > 1e-11  # above the reference's own error, so the ratio means something


@pytest.mark.parametrize("method", ["rk4", "midpoint", "gauss4", "splitting", "splitting4",
                                    "splitting6"])  # fmt: skip
def test_fixed_step_methods_keep_the_balance_at_their_order(method):
    """The pivot's work, and with it the balance E + dissipated - work_by_pivot, is as
    accurate as the motion: its error against the Reference's integral of R . v_O at t = 2 s
    falls by 2^order when dt halves, like the motion's (a quadrature of lower order than the
    method would make the balance report its own error instead of the integration's)."""
    order = {m.name: m.order for m in kreisel.methods()}[method]
    top = general_top(harmonic("oblique"))
    st = top.state_from_quaternion(*GENERAL_START)
    exact = reference("general", "oblique").run(*GENERAL_START, [0.0, 2.0], rtol=1e-13,
                                                atol=1e-15)  # fmt: skip
    dts = {2: (0.01, 0.005), 4: (0.02, 0.01), 6: (0.05, 0.025)}[order]
    work_errors, drifts = [], []
    for dt in dts:
        traj = kreisel.simulate(top, st, 2.0, method=method, dt=dt)
        work_errors.append(abs(traj.work_by_pivot[-1] - exact["work"][-1]))
        drifts.append(np.ptp(traj.balance) / energy_scale(traj))
    observed = math.log2(work_errors[0] / work_errors[1])
    assert observed > order - 0.5, (method, work_errors, observed)
    assert math.log2(drifts[0] / drifts[1]) > order - 0.5, (method, drifts)


# --------------------------------------------------------------------------------------
# batches, and what the exact Lagrange methods say of a driven or damped top
# --------------------------------------------------------------------------------------


def test_simulate_many_reports_the_drift_of_the_balance():
    """A batch of driven, damped tops: its energy_drift is the balance's (~1e-10), not the
    energy's, which the pivot and the damping change by tens of per cent; each run is the
    run simulate makes."""
    tops = [general_top(harmonic(name), damping("viscous+drag")) for name in ("x", "oblique")]
    st = tops[0].state_from_quaternion(*GENERAL_START)
    batch = kreisel.simulate_many(tops, [st, st], 4.0)
    assert all(e is None for e in batch.errors)
    assert np.all(batch.energy_drift < 1e-8), batch.energy_drift
    for k, top in enumerate(tops):
        traj = kreisel.simulate(top, st, 4.0)
        assert np.ptp(traj.energy) > 0.1 * np.abs(traj.energy).max()
        assert batch.theta_max[k] == pytest.approx(traj.theta.max(), rel=1e-12)
        assert batch.final_theta[k] == pytest.approx(traj.theta[-1], rel=1e-12)


@pytest.mark.parametrize("what", ["pivot", "damping"])
def test_exact_lagrange_methods_refuse_a_driven_or_damped_top(what):
    if what == "pivot":
        top = kreisel.LagrangeTop(**LAGRANGE, pivot=harmonic("z"))
    else:
        top = kreisel.LagrangeTop(**LAGRANGE, damping=damping("viscous"))
    st = top.state(1.0, theta_dot=0.3, phi_dot=0.7, psi_dot=5.0)
    calls = {
        "exact": lambda: top.exact(st, [0.0, 1.0]),
        "analyse": lambda: top.analyse(st),
        "motion_kind": lambda: top.motion_kind(st),
        "nutation_period": lambda: top.nutation_period(st),
        "turning_points": lambda: top.turning_points(st),
    }
    for name, call in calls.items():
        with pytest.raises(kreisel.ParameterError, match="fixed|undamped|pivot|damp") as info:
            call()
        assert info.type is not None, name
    # the simulation takes it
    assert kreisel.simulate(top, st, 0.5).status == "completed"


# --------------------------------------------------------------------------------------
# bad input: a ParameterError that names the parameter
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"amplitude": [math.nan, 0.0, 0.0]}, "amplitude"),
        ({"amplitude": [0.0, math.inf, 0.0]}, "amplitude"),
        ({"amplitude": [0.1, 0.0]}, "amplitude"),
        ({"amplitude": [[0.1, 0.0, 0.0]]}, "amplitude"),
        ({"amplitude": 0.1}, "amplitude"),
        ({"amplitude": "up"}, "amplitude"),
        ({"omega": -1.0}, "omega"),
        ({"omega": math.nan}, "omega"),
        ({"omega": math.inf}, "omega"),
        ({"phase": math.nan}, "phase"),
    ],
)
def test_bad_harmonic_pivot(kwargs, name):
    args = {"amplitude": [0.0, 0.0, 0.05], "omega": 20.0, **kwargs}
    with pytest.raises(kreisel.ParameterError, match=name):
        pivots.Harmonic(args.pop("amplitude"), args.pop("omega"), **args)


@pytest.mark.parametrize("name", ["viscous", "drag", "dry", "pivot_radius"])
@pytest.mark.parametrize("value", [-0.1, math.nan, math.inf])
def test_bad_damping(name, value):
    with pytest.raises(kreisel.ParameterError, match=name):
        kreisel.PivotDamping(**{name: value})


@pytest.mark.parametrize(
    ("t", "position", "name"),
    [
        ([0.0, 2.0, 1.0], np.zeros((3, 3)), r"\bt\b"),  # not sorted
        ([0.0, 1.0, 1.0], np.zeros((3, 3)), r"\bt\b"),  # repeated
        ([0.0, math.nan, 2.0], np.zeros((3, 3)), r"\bt\b"),
        ([0.0, 1.0, math.inf], np.zeros((3, 3)), r"\bt\b"),
        ([[0.0, 1.0, 2.0]], np.zeros((3, 3)), r"\bt\b"),
        ([0.0, 1.0, 2.0], [[0.0, 0.0, math.nan]] * 3, "position"),
        ([0.0, 1.0, 2.0], np.zeros((3, 2)), "position"),
        ([0.0, 1.0, 2.0], np.zeros(3), "position"),
        ([0.0, 1.0, 2.0], np.zeros((4, 3)), "position"),
    ],
)
def test_bad_path(t, position, name):
    with pytest.raises(kreisel.ParameterError, match=name):
        pivots.Path(t, position)


@pytest.mark.parametrize(("kwargs", "name"), [({"pivot": "shaker"}, "pivot"),
                                              ({"damping": 0.1}, "damping")])  # fmt: skip
def test_bad_pivot_or_damping_argument(kwargs, name):
    with pytest.raises(kreisel.ParameterError, match=name):
        kreisel.HeavyTop(**GENERAL, **kwargs)
    with pytest.raises(kreisel.ParameterError, match=name):
        kreisel.LagrangeTop(**LAGRANGE, **kwargs)
