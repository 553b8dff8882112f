"""Independent reference physics for the play-top tests (nothing in here uses kreisel).

A symmetric top with a spherical tip of radius rho on a horizontal plane (theory: play
top): Z is the sphere centre, G the centre of mass, e3 the unit figure axis from Z to
G, s = |ZG|, A and C the moments about G, u = e3 . ez. The contact point is T = Z - rho ez,
a = GT = -s e3 - rho ez. Newton-Euler about G with the contact force F acting at T:

    m dv/dt = F - m g ez,    dL/dt = a x F,    L = A omega + (C - A)(omega . e3) e3

The attitude is a unit quaternion q = (w, x, y, z) rotating body vectors into space, the
angular velocity is integrated in the body frame (Euler's equations with the torque).

Three modes are integrated with scipy's DOP853:

* ``slide`` -- in contact with F = N (ez + f) where f is the friction force per unit
  normal force (viscous: -mu v_T, Coulomb while slipping: -mu v_T/|v_T|, frictionless: 0).
  The state holds only the horizontal position and velocity of G; its height and vertical
  velocity follow from the contact, z_G = rho + s u and dz_G/dt = s du/dt, so the
  constraint cannot drift. N follows from d^2 z_G/dt^2 = s d^2u/dt^2, which is affine in N
  (derived below in ``_slide_rhs``). The dissipated energy D is integrated alongside
  (dD/dt = -F_t . v_T).
* ``roll`` -- in contact without slip, v = -omega x a. The contact force is eliminated:
  (I_s + m (|a|^2 1 - a a^T)) domega/dt = -omega x I_s omega + m g a x ez - m a x (omega x da/dt)
  with da/dt = -s omega x e3 and I_s the inertia about G in space; F = m dv/dt + m g ez.
* flight -- ballistic, torque free (closed form in the tests).

Euler angles are z-x-z, R = Rz(phi) Rx(theta) Rz(psi), theta from the upward vertical.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

import mpmath
import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-12
ATOL = 1e-14


@dataclass(frozen=True)
class Top:
    """Play-top parameters (SI units)."""

    m: float
    A: float
    C: float
    s: float
    rho: float
    g: float = 9.81

    @property
    def alpha(self) -> float:
        return self.s / self.rho

    @property
    def gamma(self) -> float:
        return self.A / self.C

    @property
    def J_beta(self) -> float:  # noqa: N802 - the physics name
        return self.rho * math.sqrt(self.C * self.m * self.g * self.s)

    def kwargs(self) -> dict:
        return {"m": self.m, "A": self.A, "C": self.C, "s": self.s, "rho": self.rho, "g": self.g}

    # -- stationary motions (theory: play top; verified in test_play_physics.py) -------
    def N_of(self, u):  # noqa: N802
        return (self.alpha + u) ** 2 + self.gamma * (1 - u * u)

    def D_of(self, u):  # noqa: N802
        return self.alpha + (1 - self.gamma) * u

    def J_R(self, u):  # noqa: N802
        return self.J_beta * self.N_of(u) / math.sqrt(self.D_of(u))

    def precession(self, u):
        """(Omega, omega3, psidot) of the rolling regular precession at inclination u."""
        om = math.sqrt(self.m * self.g * self.s / (self.C * self.D_of(u)))
        return om, om * (u + self.alpha), self.alpha * om


def tippe_t1() -> Top:
    """docs/benchmarks.md case T1: m = 0.02, rho = 0.02, s = 0.006, C = 0.4 m rho^2, A = 0.8 C."""
    m, rho = 0.02, 0.02
    c = 0.4 * m * rho**2
    return Top(m=m, A=0.8 * c, C=c, s=0.006, rho=rho)


# --------------------------------------------------------------------------------------
# rotations
# --------------------------------------------------------------------------------------


def quat_matrix(q):
    """Rotation matrix (body -> space) of a quaternion (w, x, y, z); normalises."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quat_matrices(q):
    """Rotation matrices of an (n, 4) array of quaternions, shape (n, 3, 3)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=1)[:, None]
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def euler_quat(phi, theta, psi):
    """Quaternion of R = Rz(phi) Rx(theta) Rz(psi)."""
    cp, sp = math.cos(phi / 2), math.sin(phi / 2)
    ct, stt = math.cos(theta / 2), math.sin(theta / 2)
    cs, ss = math.cos(psi / 2), math.sin(psi / 2)
    # qz(phi) * qx(theta) * qz(psi)
    return np.array(
        [
            ct * (cp * cs - sp * ss),
            stt * (cp * cs + sp * ss),
            stt * (sp * cs - cp * ss),
            ct * (cp * ss + sp * cs),
        ]
    )


def body_omega(theta, psi, theta_dot, phi_dot, psi_dot):
    """Body-frame angular velocity for z-x-z Euler angles."""
    return np.array(
        [
            phi_dot * math.sin(theta) * math.sin(psi) + theta_dot * math.cos(psi),
            phi_dot * math.sin(theta) * math.cos(psi) - theta_dot * math.sin(psi),
            phi_dot * math.cos(theta) + psi_dot,
        ]
    )


# --------------------------------------------------------------------------------------
# invariants from a (quaternion, body omega, com velocity) state, vectorised over rows
# --------------------------------------------------------------------------------------


def space_quantities(top: Top, quaternion, omega_body):
    """(R, e3, omega_space, L_space) for (n, 4) and (n, 3) arrays."""
    r = quat_matrices(np.atleast_2d(quaternion))
    w = np.atleast_2d(omega_body)
    lb = w * np.array([top.A, top.A, top.C])
    e3 = r[:, :, 2]
    om = np.einsum("nij,nj->ni", r, w)
    ls = np.einsum("nij,nj->ni", r, lb)
    return r, e3, om, ls


def jellett(top: Top, quaternion, omega_body):
    """J = L . (s e3 + rho ez)."""
    _, e3, _, ls = space_quantities(top, quaternion, omega_body)
    return np.einsum("ni,ni->n", ls, top.s * e3) + top.rho * ls[:, 2]


def energy(top: Top, quaternion, omega_body, com_velocity, com_z):
    """E = 1/2 m v^2 + 1/2 omega . L + m g z_G."""
    w = np.atleast_2d(omega_body)
    v = np.atleast_2d(com_velocity)
    rot = 0.5 * (top.A * (w[:, 0] ** 2 + w[:, 1] ** 2) + top.C * w[:, 2] ** 2)
    return 0.5 * top.m * np.sum(v * v, axis=1) + rot + top.m * top.g * np.asarray(com_z)


def tip_velocity(top: Top, quaternion, omega_body, com_velocity):
    """Velocity of the material point of the sphere at T: v + omega x a, a = -s e3 - rho ez."""
    _, e3, om, _ = space_quantities(top, quaternion, omega_body)
    a = -top.s * e3
    a[:, 2] -= top.rho
    return np.atleast_2d(com_velocity) + np.cross(om, a)


# --------------------------------------------------------------------------------------
# right-hand sides (plain floats: scipy calls them one state at a time)
# --------------------------------------------------------------------------------------


def _frame(qw, qx, qy, qz):
    n = qw * qw + qx * qx + qy * qy + qz * qz
    qw, qx, qy, qz = (c / math.sqrt(n) for c in (qw, qx, qy, qz))
    r = (
        (1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)),
        (2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)),
        (2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)),
    )
    return r


def _qdot(qw, qx, qy, qz, w1, w2, w3):
    """dq/dt = 1/2 q (x) (0, omega_body)."""
    return (
        0.5 * (-qx * w1 - qy * w2 - qz * w3),
        0.5 * (qw * w1 + qy * w3 - qz * w2),
        0.5 * (qw * w2 + qz * w1 - qx * w3),
        0.5 * (qw * w3 + qx * w2 - qy * w1),
    )


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def slide_forces(top: Top, friction: str, mu: float, y, rbar: float = 0.0):
    """Contact analysis of a ``slide`` state y = (x, y, vx, vy, q(4), omega_body(3), D).

    Returns (N, f, v_T, omega_space, e3, wdot0, wdot1, mz): the contact force is N (ez + f),
    the drilling torque N mz about ez, the body angular acceleration is wdot0 + N wdot1.
    ``friction="contensou"`` is Coulomb-Contensou friction over a patch of effective radius
    ``rbar`` (Leine and Glocker's ellipse): with ``d = sqrt(|v_T|^2 + rbar^2 w_n^2)``,
    ``f = -mu v_T / d`` and ``mz = -mu rbar^2 w_n / d``.
    """
    m, big_a, big_c, s, rho, g = top.m, top.A, top.C, top.s, top.rho, top.g
    _, _, vx, vy, qw, qx, qy, qz, w1, w2, w3 = y[:11]
    r = _frame(qw, qx, qy, qz)
    e3 = (r[0][2], r[1][2], r[2][2])
    om = tuple(r[i][0] * w1 + r[i][1] * w2 + r[i][2] * w3 for i in range(3))
    e3dot = _cross(om, e3)
    vz = s * e3dot[2]
    a = (-s * e3[0], -s * e3[1], -s * e3[2] - rho)
    oxa = _cross(om, a)
    # v_T is horizontal in contact: vz + (omega x a)_z = s udot - s udot = 0 identically
    vtx, vty = vx + oxa[0], vy + oxa[1]
    mz = 0.0
    if friction == "viscous":
        fx, fy = -mu * vtx, -mu * vty
    elif friction == "coulomb":
        sp = math.hypot(vtx, vty)
        fx, fy = (-mu * vtx / sp, -mu * vty / sp) if sp > 0 else (0.0, 0.0)
    elif friction == "frictionless":
        fx, fy = 0.0, 0.0
    elif friction == "contensou":
        dd = math.sqrt(vtx * vtx + vty * vty + (rbar * om[2]) ** 2)
        fx, fy = 0.0, 0.0
        if dd > 0:
            fx, fy, mz = -mu * vtx / dd, -mu * vty / dd, -mu * rbar * rbar * om[2] / dd
    else:
        raise ValueError(friction)
    d = (fx, fy, 1.0)
    # body angular acceleration: I wdot = -w x I w + R^T (a x F + M ez), F = N d, M = N mz
    torque_s = _cross(a, d)
    torque_s = (torque_s[0], torque_s[1], torque_s[2] + mz)
    tb = tuple(
        r[0][i] * torque_s[0] + r[1][i] * torque_s[1] + r[2][i] * torque_s[2] for i in range(3)
    )
    wdot0 = (
        -(big_c - big_a) * w2 * w3 / big_a,
        (big_c - big_a) * w1 * w3 / big_a,
        0.0,
    )
    wdot1 = (tb[0] / big_a, tb[1] / big_a, tb[2] / big_c)
    # u'' = (omega' x e3 + omega x e3dot)_z with omega' = R wdot: z-component of the cross
    # product (omega' x e3)_z = om'_x e3_y - om'_y e3_x
    od0 = tuple(r[i][0] * wdot0[0] + r[i][1] * wdot0[1] + r[i][2] * wdot0[2] for i in range(2))
    od1 = tuple(r[i][0] * wdot1[0] + r[i][1] * wdot1[1] + r[i][2] * wdot1[2] for i in range(2))
    cc = om[0] * e3dot[1] - om[1] * e3dot[0]
    u2_0 = od0[0] * e3[1] - od0[1] * e3[0] + cc
    u2_1 = od1[0] * e3[1] - od1[1] * e3[0]
    # m z_G'' = N - m g with z_G'' = s u'' = s (u2_0 + N u2_1)
    n = (g + s * u2_0) / (1.0 / m - s * u2_1)
    return SimpleNamespace(
        N=n, f=(fx, fy), vT=(vtx, vty), omega=om, e3=e3, vz=vz, wdot0=wdot0, wdot1=wdot1, mz=mz
    )


def slide_rhs(top: Top, friction: str, mu: float, rbar: float = 0.0):
    def rhs(_t, y):
        c = slide_forces(top, friction, mu, y, rbar)
        n = c.N
        fx, fy = c.f
        w1, w2, w3 = y[8:11]
        wd = [c.wdot0[i] + n * c.wdot1[i] for i in range(3)]
        return [
            y[2],
            y[3],
            n * fx / top.m,
            n * fy / top.m,
            *_qdot(*y[4:8], w1, w2, w3),
            *wd,
            -n * (fx * c.vT[0] + fy * c.vT[1] + c.mz * c.omega[2]),
        ]

    return rhs


def roll_rhs(top: Top):
    """y = (x, y, q(4), omega_body(3)); G's velocity is -omega x a."""
    m, big_a, big_c, s, rho, g = top.m, top.A, top.C, top.s, top.rho, top.g
    inertia_b = np.diag([big_a, big_a, big_c])
    ez = np.array([0.0, 0.0, 1.0])

    def parts(y):
        r = quat_matrix(y[2:6])
        w = np.asarray(y[6:9])
        e3 = r[:, 2]
        om = r @ w
        a = -s * e3 - rho * ez
        adot = -s * np.cross(om, e3)
        i_s = r @ inertia_b @ r.T
        lhs = i_s + m * (a @ a * np.eye(3) - np.outer(a, a))
        rhs_v = (
            -np.cross(om, i_s @ om) + m * g * np.cross(a, ez) - m * np.cross(a, np.cross(om, adot))
        )
        omd = np.linalg.solve(lhs, rhs_v)
        v = -np.cross(om, a)
        vdot = -(np.cross(omd, a) + np.cross(om, adot))
        force = m * vdot + m * g * ez
        return r, w, om, omd, v, force

    def rhs(_t, y):
        r, w, _, omd, v, _ = parts(y)
        return [v[0], v[1], *_qdot(*y[2:6], *w), *(r.T @ omd)]

    rhs.parts = parts
    return rhs


# --------------------------------------------------------------------------------------
# drivers
# --------------------------------------------------------------------------------------


def initial(
    top: Top, theta, phi=0.0, psi=0.0, theta_dot=0.0, phi_dot=0.0, psi_dot=0.0, vx=0.0, vy=0.0
):
    """(q, omega_body, com, com_velocity) of a state in contact (the API's documented map)."""
    q = euler_quat(phi, theta, psi)
    w = body_omega(theta, psi, theta_dot, phi_dot, psi_dot)
    com = np.array([0.0, 0.0, top.rho + top.s * math.cos(theta)])
    vel = np.array([vx, vy, -top.s * math.sin(theta) * theta_dot])
    return q, w, com, vel


def integrate_slide(
    top: Top, friction: str, mu: float, start: dict, t_end: float, t_eval=None,
    rtol=RTOL, atol=ATOL,
):  # fmt: skip
    """Integrate the sliding-contact equations; returns columns like a trajectory."""
    q, w, com, vel = initial(top, **start)
    y0 = [com[0], com[1], vel[0], vel[1], *q, *w, 0.0]
    rhs = slide_rhs(top, friction, mu)
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, t_eval=t_eval)
    assert sol.success, sol.message
    return slide_columns(top, friction, mu, sol.t, sol.y.T)


def slide_columns(top: Top, friction: str, mu: float, t, ys):
    normal, speed, vz = [], [], []
    for y in ys:
        c = slide_forces(top, friction, mu, y)
        normal.append(c.N)
        speed.append(math.hypot(*c.vT))
        vz.append(c.vz)
    q = ys[:, 4:8] / np.linalg.norm(ys[:, 4:8], axis=1)[:, None]
    w = ys[:, 8:11]
    _, e3, _, _ = space_quantities(top, q, w)
    u = e3[:, 2]
    com = np.column_stack([ys[:, 0], ys[:, 1], top.rho + top.s * u])
    vel = np.column_stack([ys[:, 2], ys[:, 3], vz])
    return SimpleNamespace(
        t=np.asarray(t),
        quaternion=q,
        omega=w,
        u=u,
        com=com,
        com_velocity=vel,
        normal_force=np.array(normal),
        slip_speed=np.array(speed),
        jellett=jellett(top, q, w),
        energy=energy(top, q, w, vel, com[:, 2]),
        dissipated=ys[:, 11],
    )


def integrate_roll(top: Top, start: dict, t_end: float, t_eval=None):
    q, w, com, _ = initial(top, **start)
    rhs = roll_rhs(top)
    sol = solve_ivp(
        rhs, (0.0, t_end), [com[0], com[1], *q, *w], method="DOP853", rtol=RTOL, atol=ATOL,
        t_eval=t_eval,
    )  # fmt: skip
    assert sol.success, sol.message
    rows = [rhs.parts(y) for y in sol.y.T]
    q = sol.y[2:6].T
    w = sol.y[6:9].T
    _, e3, _, _ = space_quantities(top, q, w)
    force = np.array([p[5] for p in rows])
    vel = np.array([p[4] for p in rows])
    return SimpleNamespace(
        t=sol.t,
        quaternion=q,
        omega=w,
        u=e3[:, 2],
        com_velocity=vel,
        force=force,
        jellett=jellett(top, q, w),
        energy=energy(top, q, w, vel, top.rho + top.s * e3[:, 2]),
    )


# --------------------------------------------------------------------------------------
# frictionless contact: mpmath quadrature of the reduced equation
# --------------------------------------------------------------------------------------


class FrictionlessMotion:
    """udot^2 = F(u) / (1 + k (1 - u^2)), k = m s^2 / A, for a frictionless play top,
    F(u) = (1 - u^2)(2E' - 2 m g s u)/A - (b - a u)^2 (theory: play top; the energy
    identity behind it is re-derived in test_play_physics.py).

    F = beta (u - u1)(u2 - u)(u3 - u) with beta = 2 m g s / A; with u = u1 + (u2 - u1)
    sin^2(sigma), dt = 2 sqrt(1 + k (1 - u^2)) / sqrt(beta (u3 - u)) dsigma, smooth and
    monotone in sigma.
    """

    def __init__(self, top: Top, start: dict, dps: int = 30):
        self.dps = dps
        with mpmath.workdps(dps):
            mpf = mpmath.mpf
            m, big_a, big_c, s, g = (mpf(x) for x in (top.m, top.A, top.C, top.s, top.g))
            th = mpf(start["theta"])
            thd = mpf(start.get("theta_dot", 0.0))
            phd = mpf(start.get("phi_dot", 0.0))
            psd = mpf(start.get("psi_dot", 0.0))
            u0 = mpmath.cos(th)
            s0 = mpmath.sin(th)
            omega3 = psd + phd * u0
            lz = big_a * phd * s0**2 + big_c * omega3 * u0
            # energy without the horizontal motion of G, the axial spin and m g rho
            e_red = (
                m / 2 * (s * s0 * thd) ** 2
                + big_a / 2 * (thd**2 + (phd * s0) ** 2)
                + m * g * s * u0
            )
            self.a = a = big_c * omega3 / big_a
            self.b = b = lz / big_a
            self.k = m * s * s / big_a
            beta = 2 * m * g * s / big_a
            ee = 2 * e_red / big_a
            # F(u) = (1 - u^2)(ee - beta u) - (b - a u)^2
            c3, c2, c1, c0 = beta, -(ee + a * a), 2 * a * b - beta, ee - b * b
            roots = mpmath.polyroots([c0, c1, c2, c3], maxsteps=200, extraprec=200, asc=True)
            assert all(abs(mpmath.im(x)) < mpf(10) ** (-dps // 2) for x in roots), roots
            roots = sorted(mpmath.re(x) for x in roots)
            self.u1, self.u2, self.u3 = roots
            self.beta = beta
            self.u0 = u0
            tol = mpf(10) ** (-dps + 8)
            assert self.u1 - tol <= u0 <= self.u2 + tol and -1 <= self.u1 and self.u2 <= 1
            ratio = min(max((u0 - self.u1) / (self.u2 - self.u1), mpf(0)), mpf(1))
            sa = mpmath.asin(mpmath.sqrt(ratio))
            # udot = -sin(theta) theta_dot
            self.sigma0 = sa if -s0 * thd >= 0 else mpmath.pi - sa

    def u_of(self, sigma):
        return self.u1 + (self.u2 - self.u1) * mpmath.sin(sigma) ** 2

    def _dt(self, sigma):
        u = self.u_of(sigma)
        return 2 * mpmath.sqrt(1 + self.k * (1 - u * u)) / mpmath.sqrt(self.beta * (self.u3 - u))

    def time(self, sigma):
        """Time from the start (phase sigma0) to phase sigma >= sigma0; the turning points
        are at sigma = 0 (u1), pi/2 (u2), pi (u1), ..."""
        with mpmath.workdps(self.dps):
            sigma = mpmath.mpf(sigma)
            half = mpmath.pi / 2
            pts = [self.sigma0]
            k = int(mpmath.floor(self.sigma0 / half)) + 1
            while k * half < sigma:
                pts.append(k * half)
                k += 1
            pts.append(sigma)
            return mpmath.quad(self._dt, pts)


# --------------------------------------------------------------------------------------
# Coulomb friction: the sliding phase up to the instant the slip stops
# --------------------------------------------------------------------------------------


def slide_until(top: Top, friction: str, mu: float, start: dict, t_end: float, stop: str,
                delta: float = 1e-8):  # fmt: skip
    """Integrate the sliding equations until ``stop`` happens (terminal, located by scipy):
    ``"roll"`` -- the slip speed falls to ``delta`` (m/s); ``"lift_off"`` -- N falls to 0.
    Returns (t_stop or None, columns of the accepted steps, state vector at the stop)."""
    q, w, com, vel = initial(top, **start)
    y0 = [com[0], com[1], vel[0], vel[1], *q, *w, 0.0]
    if stop == "roll":

        def event(_t, y):
            return math.hypot(*slide_forces(top, friction, mu, y).vT) - delta

    elif stop == "lift_off":

        def event(_t, y):
            return slide_forces(top, friction, mu, y).N

    else:
        raise ValueError(stop)
    event.terminal = True
    event.direction = -1
    sol = solve_ivp(
        slide_rhs(top, friction, mu), (0.0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL,
        events=event,
    )  # fmt: skip
    assert sol.success, sol.message
    t_stop = float(sol.t_events[0][0]) if len(sol.t_events[0]) else None
    return t_stop, slide_columns(top, friction, mu, sol.t, sol.y.T), sol.y[:, -1]


def roll_force(top: Top, quaternion, omega_body):
    """Contact force (space frame) that keeps a top rolling without slip, from its attitude
    and body angular velocity (G's velocity is then -omega x a)."""
    y = np.concatenate([[0.0, 0.0], np.asarray(quaternion, float), np.asarray(omega_body, float)])
    return roll_rhs(top).parts(y)[5]


# --------------------------------------------------------------------------------------
# flight: ballistic centre of mass, torque-free symmetric top (closed form)
# --------------------------------------------------------------------------------------


def axis_angle(axis, angle):
    """Rotation matrices about a unit axis, for an array of angles, shape (n, 3, 3)."""
    angle = np.atleast_1d(np.asarray(angle, dtype=float))
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    s = np.sin(angle)[:, None, None]
    c = np.cos(angle)[:, None, None]
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def free_flight(top: Top, quaternion, omega_body, com, com_velocity, dt):
    """State of a top in flight dt (array, s) after (quaternion, omega, com, com_velocity).

    The angular momentum L about G is fixed in space and omega = L/A + (1/C - 1/A) L3 e3, so
    R(dt) = Rot(L, |L| dt / A) R0 Rot(e3, lambda dt), lambda = L3 (1/C - 1/A); G falls
    freely. Returns (R (n, 3, 3), com (n, 3), L (3,))."""
    dt = np.atleast_1d(np.asarray(dt, dtype=float))
    r0 = quat_matrix(quaternion)
    w = np.asarray(omega_body, dtype=float)
    lb = w * np.array([top.A, top.A, top.C])
    ls = r0 @ lb
    lnorm = float(np.linalg.norm(ls))
    lam = lb[2] * (1.0 / top.C - 1.0 / top.A)
    rz = axis_angle(np.array([0.0, 0.0, 1.0]), lam * dt)
    rot = axis_angle(ls / lnorm, lnorm / top.A * dt) @ r0 @ rz
    pos = (
        np.asarray(com, float)[None, :]
        + np.asarray(com_velocity, float)[None, :] * dt[:, None]
        - 0.5 * top.g * np.outer(dt**2, [0.0, 0.0, 1.0])
    )
    return rot, pos, ls


def flight_gap(top: Top, quaternion, omega_body, com, com_velocity, dt):
    """Gap between the lowest point of the sphere and the floor, z_G - s u - rho."""
    rot, pos, _ = free_flight(top, quaternion, omega_body, com, com_velocity, dt)
    return pos[:, 2] - top.s * rot[:, 2, 2] - top.rho
