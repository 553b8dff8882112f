"""Independent reference physics for the Lagrange-top tests.

Nothing in here uses kreisel: every reference value is computed from the Lagrangian

    L = 1/2 I1 (thetadot^2 + phidot^2 sin^2 theta) + 1/2 I3 (psidot + phidot cos theta)^2
        - m g l cos theta

either by mpmath quadrature of the reduced (u = cos theta) problem, or by tight scipy
integration of the Euler-Lagrange equations, or of the rigid-body (Euler + quaternion)
equations.  The helpers are handed to the tests through the ``ref`` fixture.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp

RTOL = 1e-13
ATOL = 1e-13


@dataclass(frozen=True)
class Params:
    I1: float
    I3: float
    m: float
    l: float  # noqa: E741 - the physics name
    g: float = 9.81

    @property
    def mgl(self) -> float:
        return self.m * self.g * self.l

    def kwargs(self) -> dict:
        return {"I1": self.I1, "I3": self.I3, "m": self.m, "l": self.l, "g": self.g}


@dataclass(frozen=True)
class Start:
    theta: float
    theta_dot: float = 0.0
    phi_dot: float = 0.0
    psi_dot: float = 0.0
    phi: float = 0.0
    psi: float = 0.0

    def kwargs(self) -> dict:
        return {
            "theta": self.theta,
            "phi": self.phi,
            "psi": self.psi,
            "theta_dot": self.theta_dot,
            "phi_dot": self.phi_dot,
            "psi_dot": self.psi_dot,
        }


# --------------------------------------------------------------------------------------
# conserved quantities and effective potential (plain float / numpy)
# --------------------------------------------------------------------------------------


def invariants(p: Params, theta, theta_dot, phi_dot, psi_dot):
    """(E, Mz, M3) from the Lagrangian; numpy-vectorised."""
    s = np.sin(theta)
    c = np.cos(theta)
    omega3 = psi_dot + phi_dot * c
    m3 = p.I3 * omega3
    mz = p.I1 * phi_dot * s * s + m3 * c
    kinetic = 0.5 * p.I1 * (theta_dot**2 + (phi_dot * s) ** 2) + 0.5 * p.I3 * omega3**2
    potential = p.mgl * c
    return kinetic + potential, mz, m3, abs(kinetic) + abs(potential)


def veff(p: Params, theta, mz, m3):
    s = np.sin(theta)
    c = np.cos(theta)
    return p.mgl * c + (mz - m3 * c) ** 2 / (2.0 * p.I1 * s * s) + m3**2 / (2.0 * p.I3)


# --------------------------------------------------------------------------------------
# mpmath reference: quadrature of the reduced problem in u = cos(theta)
# --------------------------------------------------------------------------------------


class MpMotion:
    """High-precision solution of udot^2 = f(u) for one initial state.

    Uses u = u1 + (u2 - u1) sin^2(s); then f(u) = (u - u1)(u2 - u) g(u) with g smooth and
    positive, ds/dt = sqrt(g(u)) / 2 > 0, so the motion is monotone in s and

        t(s) = int_{s0}^{s} 2 ds / sqrt(g(u(s)))

    (and likewise for phi and psi with the extra factors phidot(u), psidot(u)).
    """

    def __init__(self, p: Params, st: Start, dps: int = 30):
        self.p = p
        self.dps = dps
        with mpmath.workdps(dps):
            mpf = mpmath.mpf
            i1, i3, mgl = mpf(p.I1), mpf(p.I3), mpf(p.m) * mpf(p.g) * mpf(p.l)
            th, thd, phd, psd = (mpf(x) for x in (st.theta, st.theta_dot, st.phi_dot, st.psi_dot))
            u0 = mpmath.cos(th)
            s0 = mpmath.sin(th)
            omega3 = psd + phd * u0
            m3 = i3 * omega3
            mz = i1 * phd * s0**2 + m3 * u0
            energy = i1 / 2 * (thd**2 + phd**2 * s0**2) + i3 / 2 * omega3**2 + mgl * u0
            self.a = a = m3 / i1
            self.b = b = mz / i1
            self.beta = beta = 2 * mgl / i1
            self.alpha = alpha = 2 * (energy - m3**2 / (2 * i3)) / i1
            self.i1_over_i3 = i1 / i3
            self.u0 = u0
            udot0 = -s0 * thd
            # f(u) = beta u^3 - (alpha + a^2) u^2 + (2 a b - beta) u + (alpha - b^2)
            c3, c2, c1, c0 = beta, -(alpha + a**2), 2 * a * b - beta, alpha - b**2
            if beta != 0:
                roots = mpmath.polyroots([c0, c1, c2, c3], maxsteps=200, extraprec=200, asc=True)
            else:
                roots = mpmath.polyroots([c0, c1, c2], maxsteps=200, extraprec=200, asc=True)
            assert all(abs(mpmath.im(r)) < mpf(10) ** (-dps // 2) for r in roots), roots
            roots = sorted(mpmath.re(r) for r in roots)
            if beta > 0:
                u1, u2 = roots[0], roots[1]
                self.u3 = roots[2]
            elif beta < 0:
                u1, u2 = roots[1], roots[2]
                self.u3 = roots[0]
            else:
                u1, u2 = roots[0], roots[1]
                self.u3 = None
            self.c2 = c2
            self.u1, self.u2 = u1, u2
            tol = mpf(10) ** (-dps + 8)
            assert u1 - tol <= u0 <= u2 + tol, (u1, u0, u2)
            assert -1 - tol <= u1 and u2 <= 1 + tol
            ratio = (u0 - u1) / (u2 - u1)
            ratio = min(max(ratio, mpf(0)), mpf(1))
            sa = mpmath.asin(mpmath.sqrt(ratio))
            self.s0 = sa if udot0 >= 0 else mpmath.pi - sa

    # -- pieces -------------------------------------------------------------------------
    def u_of_s(self, s):
        return self.u1 + (self.u2 - self.u1) * mpmath.sin(s) ** 2

    def _g(self, u):
        if self.beta == 0:
            return -self.c2  # alpha + a^2
        return self.beta * (self.u3 - u)

    def _rates(self, s):
        u = self.u_of_s(s)
        dt = 2 / mpmath.sqrt(self._g(u))
        phidot = (self.b - self.a * u) / (1 - u * u)
        psidot = self.i1_over_i3 * self.a - u * phidot
        return u, dt, phidot, psidot

    def _quad(self, fn, s_from, s_to):
        with mpmath.workdps(self.dps):
            s_from = mpmath.mpf(s_from)
            s_to = mpmath.mpf(s_to)
            if s_from == s_to:
                return mpmath.mpf(0)
            lo, hi = min(s_from, s_to), max(s_from, s_to)
            half = mpmath.pi / 2
            k0 = int(mpmath.floor(lo / half)) + 1
            k1 = int(mpmath.ceil(hi / half)) - 1
            pts = [lo] + [k * half for k in range(k0, k1 + 1)] + [hi]
            pts = sorted(set(pts))
            val = mpmath.quad(fn, pts)
            return val if s_to >= s_from else -val

    # -- public -------------------------------------------------------------------------
    def _dt(self, s):
        return 2 / mpmath.sqrt(self._g(self.u_of_s(s)))

    def time(self, s):
        """Time (from the initial state) at which the motion reaches phase s."""
        return self._quad(self._dt, self.s0, s)

    def phi_advance(self, s):
        return self._quad(lambda x: self._rates(x)[1] * self._rates(x)[2], self.s0, s)

    def psi_advance(self, s):
        return self._quad(lambda x: self._rates(x)[1] * self._rates(x)[3], self.s0, s)

    def period(self):
        return self._quad(self._dt, 0, mpmath.pi)

    def period_advances(self):
        """(T, delta phi, delta psi) over one full nutation period."""
        return (
            self.period(),
            self._quad(lambda x: self._rates(x)[1] * self._rates(x)[2], 0, mpmath.pi),
            self._quad(lambda x: self._rates(x)[1] * self._rates(x)[3], 0, mpmath.pi),
        )

    def udot(self, s):
        """du/dt at phase s: (u2 - u1) sin(2 s) ds/dt with ds/dt = sqrt(g(u)) / 2."""
        with mpmath.workdps(self.dps):
            return (self.u2 - self.u1) * mpmath.sin(2 * s) / self._dt(s)

    def phidot_at(self, u):
        return (self.b - self.a * u) / (1 - u * u)

    def theta_range(self):
        """(theta_min, theta_max) as floats."""
        return float(mpmath.acos(min(self.u2, 1))), float(mpmath.acos(max(self.u1, -1)))


# --------------------------------------------------------------------------------------
# scipy references
# --------------------------------------------------------------------------------------


def integrate_euler_lagrange(p: Params, st: Start, t_end: float, max_step=np.inf):
    """Euler-Lagrange equations reduced with the conserved momenta Mz = p_phi, M3 = p_psi.

    d/dt (I1 thetadot) = I1 phidot^2 sin cos - M3 phidot sin + m g l sin
    phidot = (Mz - M3 cos)/(I1 sin^2),  psidot = M3/I3 - phidot cos.
    Integrated in (theta, p_theta, phi, psi); returns the accepted steps only (no dense
    interpolation) as (t, theta, theta_dot, phi, psi, phi_dot, psi_dot).
    """
    _, mz, m3, _ = invariants(p, st.theta, st.theta_dot, st.phi_dot, st.psi_dot)
    on_separatrix = mz == m3

    def phidot_of(th):
        s, c = math.sin(th), math.cos(th)
        if on_separatrix:
            return m3 / (p.I1 * (1.0 + c))
        return (mz - m3 * c) / (p.I1 * s * s)

    def rhs(_t, y):
        th, pth = y[0], y[1]
        s, c = math.sin(th), math.cos(th)
        phd = phidot_of(th)
        return [
            pth / p.I1,
            p.I1 * phd * phd * s * c - m3 * phd * s + p.mgl * s,
            phd,
            m3 / p.I3 - phd * c,
        ]

    y0 = [st.theta, p.I1 * st.theta_dot, st.phi, st.psi]
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL, max_step=max_step)
    assert sol.success, sol.message
    th = sol.y[0]
    phd = np.array([phidot_of(x) for x in th])
    return SimpleNamespace(
        t=sol.t,
        theta=th,
        theta_dot=sol.y[1] / p.I1,
        phi=sol.y[2],
        psi=sol.y[3],
        phi_dot=phd,
        psi_dot=m3 / p.I3 - phd * np.cos(th),
    )


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    one, zero = np.ones_like(a), np.zeros_like(a)
    return np.stack(
        [np.stack([one, zero, zero], -1), np.stack([zero, c, -s], -1), np.stack([zero, s, c], -1)],
        -2,
    )


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    one, zero = np.ones_like(a), np.zeros_like(a)
    return np.stack(
        [np.stack([c, -s, zero], -1), np.stack([s, c, zero], -1), np.stack([zero, zero, one], -1)],
        -2,
    )


def euler_matrix(phi, theta, psi):
    """Body-to-space rotation R = Rz(phi) Rx(theta) Rz(psi) (z-x-z), vectorised."""
    phi, theta, psi = (np.asarray(x, dtype=float) for x in (phi, theta, psi))
    return rot_z(phi) @ rot_x(theta) @ rot_z(psi)


def body_omega(theta, psi, theta_dot, phi_dot, psi_dot):
    """Body-frame angular velocity for z-x-z Euler angles."""
    return np.array(
        [
            phi_dot * math.sin(theta) * math.sin(psi) + theta_dot * math.cos(psi),
            phi_dot * math.sin(theta) * math.cos(psi) - theta_dot * math.sin(psi),
            psi_dot + phi_dot * math.cos(theta),
        ]
    )


def quat_to_matrix(q):
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=0)
    w, x, y, z = q
    return np.moveaxis(
        np.array(
            [
                [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
            ]
        ),
        -1,
        0,
    )


def matrix_to_quat(r):
    # Shepperd; fine for the well-conditioned initial matrices used here
    tr = np.trace(r)
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return np.array(
            [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
        )
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k]) * 2
    q = np.empty(4)
    q[0] = (r[k, j] - r[j, k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (r[j, i] + r[i, j]) / s
    q[1 + k] = (r[k, i] + r[i, k]) / s
    return q


def integrate_rigid_body(p: Params, st: Start, t_eval):
    """Heavy symmetric top as a rigid body: Euler's equations in the body frame with the
    gravity torque, and the attitude as a quaternion.  Independent of Euler angles, so it
    is regular through the vertical.  Returns rotation matrices at t_eval (t_eval >= 0,
    increasing)."""
    r0 = euler_matrix(st.phi, st.theta, st.psi)
    q0 = matrix_to_quat(r0)
    w0 = body_omega(st.theta, st.psi, st.theta_dot, st.phi_dot, st.psi_dot)

    i1, i3, mgl = p.I1, p.I3, p.mgl

    def rhs(_t, y):
        w1, w2, w3, qw, qx, qy, qz = y
        # space vertical in body coordinates (third row of R), normalised
        n = qw * qw + qx * qx + qy * qy + qz * qz
        g1 = 2 * (qx * qz - qw * qy) / n
        g2 = 2 * (qy * qz + qw * qx) / n
        # gravity torque about the pivot: (l e3) x (-m g gamma) = m g l (g2, -g1, 0)
        # Euler: I wdot = torque - w x (I w)
        return [
            (mgl * g2 - (i3 - i1) * w2 * w3) / i1,
            (-mgl * g1 - (i1 - i3) * w3 * w1) / i1,
            0.0,
            # qdot = 1/2 q (x) (0, w)
            0.5 * (-qx * w1 - qy * w2 - qz * w3),
            0.5 * (qw * w1 + qy * w3 - qz * w2),
            0.5 * (qw * w2 + qz * w1 - qx * w3),
            0.5 * (qw * w3 + qx * w2 - qy * w1),
        ]

    t_eval = np.asarray(t_eval, dtype=float)
    sol = solve_ivp(
        rhs,
        (0.0, float(t_eval[-1])),
        np.concatenate([w0, q0]),
        method="DOP853",
        rtol=RTOL,
        atol=ATOL,
        t_eval=t_eval,
    )
    assert sol.success, sol.message
    return quat_to_matrix(sol.y[3:])


def free_top_matrices(p: Params, st: Start, t):
    """Closed-form free symmetric top (l = 0 or g = 0).

    The angular momentum L is fixed in space; omega = L/I1 + (1/I3 - 1/I1) M3 e3, so
    R(t) = Rot(L, |L| t / I1) R0 Rot(e3, lambda t) with lambda = M3 (1/I3 - 1/I1):
    the figure axis precesses uniformly about L at rate |L|/I1.
    """
    r0 = euler_matrix(st.phi, st.theta, st.psi)
    w0 = body_omega(st.theta, st.psi, st.theta_dot, st.phi_dot, st.psi_dot)
    lb = np.array([p.I1, p.I1, p.I3]) * w0
    ls = r0 @ lb
    lnorm = float(np.linalg.norm(ls))
    lam = lb[2] * (1.0 / p.I3 - 1.0 / p.I1)
    t = np.asarray(t, dtype=float)
    return axis_angle(ls / lnorm, lnorm / p.I1 * t) @ r0 @ rot_z(lam * t), ls, lnorm


def axis_angle(axis, angle):
    angle = np.asarray(angle, dtype=float)
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    s = np.sin(angle)[..., None, None]
    c = np.cos(angle)[..., None, None]
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def steady_precession_rates(p: Params, theta0: float, omega3: float):
    """Roots of I1 cos(theta0) W^2 - I3 omega3 W + m g l = 0, ascending (stable formula)."""
    qa = p.I1 * math.cos(theta0)
    qb = -p.I3 * omega3
    qc = p.mgl
    if qa == 0.0:
        return (qc / -qb,) if qb != 0 else ()
    disc = qb * qb - 4 * qa * qc
    if disc < 0:
        return ()
    sq = math.sqrt(disc)
    q = -0.5 * (qb + math.copysign(sq, qb))
    roots = sorted([q / qa, qc / q])
    return tuple(roots)


@pytest.fixture(scope="session")
def ref():
    return SimpleNamespace(
        Params=Params,
        Start=Start,
        MpMotion=MpMotion,
        invariants=invariants,
        veff=veff,
        integrate_euler_lagrange=integrate_euler_lagrange,
        integrate_rigid_body=integrate_rigid_body,
        free_top_matrices=free_top_matrices,
        euler_matrix=euler_matrix,
        body_omega=body_omega,
        steady_precession_rates=steady_precession_rates,
    )
