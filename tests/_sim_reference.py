"""Independent reference physics for the simulation tests (no kreisel inside).

A heavy top on a fixed pivot, body frame = principal axes about the pivot, inertia
diag(I1, I2, I3), centre of mass ``com`` (body frame, from the pivot), Gamma = the upward
unit vertical seen in the body frame, M = I omega:

    dM/dt = M x omega + m g (Gamma x com),    dGamma/dt = Gamma x omega

Two formulations are integrated with scipy's DOP853 and checked against each other in
``test_simulate_invariants.py``: (quaternion q, body omega) and the Euler-Poisson variables
(M, Gamma). The quaternion q = (w, x, y, z) rotates body vectors into space:
v_space = R(q) v_body and dq/dt = 1/2 q (x) (0, omega).

Euler angles are z-x-z, R = Rz(phi) Rx(theta) Rz(psi), theta from the upward vertical.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-13
ATOL = 1e-14


@dataclass(frozen=True)
class Body:
    """Parameters of a heavy top (SI units)."""

    I1: float
    I2: float
    I3: float
    m: float
    com: tuple[float, float, float]
    g: float = 9.81

    @property
    def inertia(self) -> np.ndarray:
        return np.array([self.I1, self.I2, self.I3])

    @property
    def mgc(self) -> np.ndarray:
        """m g com (N m): the gravity torque is Gamma x mgc."""
        return self.m * self.g * np.asarray(self.com, dtype=float)


# --------------------------------------------------------------------------------------
# rotations
# --------------------------------------------------------------------------------------


def quat_mul(a, b):
    """Hamilton product of quaternions (scalar first), broadcasting over leading axes."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )


def quat_axis_angle(axis, angle):
    axis = np.asarray(axis, dtype=float)
    half = 0.5 * angle
    return np.concatenate([[math.cos(half)], math.sin(half) * axis])


def euler_to_quat(phi, theta, psi):
    """q for R = Rz(phi) Rx(theta) Rz(psi)."""
    qz1 = quat_axis_angle([0.0, 0.0, 1.0], phi)
    qx = quat_axis_angle([1.0, 0.0, 0.0], theta)
    qz2 = quat_axis_angle([0.0, 0.0, 1.0], psi)
    return quat_mul(quat_mul(qz1, qx), qz2)


def quat_to_matrix(q):
    """Rotation matrices (..., 3, 3) of quaternions (..., 4) (normalised first)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    r = np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )
    return r


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    one, zero = np.ones_like(c), np.zeros_like(c)
    return np.stack(
        [np.stack([c, -s, zero], -1), np.stack([s, c, zero], -1), np.stack([zero, zero, one], -1)],
        -2,
    )


def _rx(a):
    c, s = np.cos(a), np.sin(a)
    one, zero = np.ones_like(c), np.zeros_like(c)
    return np.stack(
        [np.stack([one, zero, zero], -1), np.stack([zero, c, -s], -1), np.stack([zero, s, c], -1)],
        -2,
    )


def euler_matrix(phi, theta, psi):
    """Body-to-space R = Rz(phi) Rx(theta) Rz(psi), vectorised over equal-shaped inputs."""
    phi, theta, psi = (np.asarray(x, dtype=float) for x in (phi, theta, psi))
    return _rz(phi) @ _rx(theta) @ _rz(psi)


def figure_axis(theta, phi):
    """e3 in space from Euler angles: (sin th sin phi, -sin th cos phi, cos th), shape (n, 3)."""
    theta = np.asarray(theta, dtype=float)
    phi = np.asarray(phi, dtype=float)
    return np.stack(
        [np.sin(theta) * np.sin(phi), -np.sin(theta) * np.cos(phi), np.cos(theta)], axis=-1
    )


def body_omega(theta, psi, theta_dot, phi_dot, psi_dot):
    """Body angular velocity from z-x-z Euler angles and rates (vectorised)."""
    theta, psi, theta_dot, phi_dot, psi_dot = (
        np.asarray(x, dtype=float) for x in (theta, psi, theta_dot, phi_dot, psi_dot)
    )
    return np.stack(
        [
            phi_dot * np.sin(theta) * np.sin(psi) + theta_dot * np.cos(psi),
            phi_dot * np.sin(theta) * np.cos(psi) - theta_dot * np.sin(psi),
            phi_dot * np.cos(theta) + psi_dot,
        ],
        axis=-1,
    )


def rotation_vector(r):
    """Log map of rotation matrices (..., 3, 3) near the identity -> (..., 3)."""
    r = np.asarray(r, dtype=float)
    v = 0.5 * np.stack(
        [r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0], r[..., 1, 0] - r[..., 0, 1]],
        -1,
    )
    s = np.linalg.norm(v, axis=-1, keepdims=True)
    c = 0.5 * (np.trace(r, axis1=-2, axis2=-1)[..., None] - 1.0)
    angle = np.arctan2(s, c)
    with np.errstate(invalid="ignore", divide="ignore"):
        fac = np.where(s > 1e-300, angle / np.where(s > 1e-300, s, 1.0), 1.0)
    return v * fac


def gamma_of(q):
    """Upward vertical in the body frame, Gamma = R(q)^T e_z: the third row of R."""
    return quat_to_matrix(q)[..., 2, :]


# --------------------------------------------------------------------------------------
# equations of motion
# --------------------------------------------------------------------------------------


def rhs_quaternion(body: Body):
    """f(t, y) for y = (q (4), omega (3))."""
    inertia = body.inertia
    mgc = body.mgc

    def rhs(_t, y):
        qw, qx, qy, qz = y[:4]
        w = y[4:7]
        n = qw * qw + qx * qx + qy * qy + qz * qz  # ~1; divided out to stay on the sphere
        gam = np.array(
            [
                2 * (qx * qz - qw * qy) / n,
                2 * (qy * qz + qw * qx) / n,
                1 - 2 * (qx * qx + qy * qy) / n,
            ]
        )
        big_m = inertia * w
        dw = (np.cross(big_m, w) + np.cross(gam, mgc)) / inertia
        dq = 0.5 * np.array(
            [
                -qx * w[0] - qy * w[1] - qz * w[2],
                qw * w[0] + qy * w[2] - qz * w[1],
                qw * w[1] + qz * w[0] - qx * w[2],
                qw * w[2] + qx * w[1] - qy * w[0],
            ]
        )
        return np.concatenate([dq, dw])

    return rhs


def rhs_poisson(body: Body):
    """f(t, y) for y = (M (3), Gamma (3)): the Euler-Poisson equations."""
    inertia = body.inertia
    mgc = body.mgc

    def rhs(_t, y):
        big_m, gam = y[:3], y[3:]
        w = big_m / inertia
        return np.concatenate([np.cross(big_m, w) + np.cross(gam, mgc), np.cross(gam, w)])

    return rhs


def integrate_quaternion(body: Body, q0, omega0, t_eval, rtol=RTOL, atol=ATOL, **kw):
    """Tight DOP853 integration in (q, omega); returns (q (n,4) normalised, omega (n,3))."""
    t_eval = np.asarray(t_eval, dtype=float)
    q0 = np.asarray(q0, dtype=float)
    y0 = np.concatenate([q0 / np.linalg.norm(q0), np.asarray(omega0, dtype=float)])
    sol = solve_ivp(
        rhs_quaternion(body),
        (0.0, float(t_eval[-1])),
        y0,
        method="DOP853",
        rtol=rtol,
        atol=atol,
        t_eval=t_eval,
        **kw,
    )
    assert sol.success, sol.message
    q = sol.y[:4].T
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    return q, sol.y[4:].T


def integrate_poisson(body: Body, big_m0, gamma0, t_eval, rtol=RTOL, atol=ATOL):
    """Tight DOP853 integration in (M, Gamma); returns (M (n,3), Gamma (n,3))."""
    t_eval = np.asarray(t_eval, dtype=float)
    y0 = np.concatenate([np.asarray(big_m0, dtype=float), np.asarray(gamma0, dtype=float)])
    sol = solve_ivp(
        rhs_poisson(body),
        (0.0, float(t_eval[-1])),
        y0,
        method="DOP853",
        rtol=rtol,
        atol=atol,
        t_eval=t_eval,
    )
    assert sol.success, sol.message
    return sol.y[:3].T, sol.y[3:].T


# --------------------------------------------------------------------------------------
# integrals of the motion, vectorised over rows
# --------------------------------------------------------------------------------------


def energy(body: Body, omega, gamma):
    omega = np.asarray(omega, dtype=float)
    return 0.5 * np.sum(body.inertia * omega * omega, axis=-1) + gamma @ body.mgc


def vertical_momentum(body: Body, omega, gamma):
    return np.sum(body.inertia * np.asarray(omega) * np.asarray(gamma), axis=-1)


def space_momentum(body: Body, q, omega):
    """Angular momentum in the space frame, R(q) (I omega), shape (n, 3)."""
    r = quat_to_matrix(q)
    return np.einsum("...ij,...j->...i", r, body.inertia * np.asarray(omega))


def kovalevskaya(body: Body, omega, gamma):
    """K = (w1^2 - w2^2 - nu G1)^2 + (2 w1 w2 - nu G2)^2, nu = m g x0 / I3, com = (x0, 0, 0)."""
    nu = body.m * body.g * body.com[0] / body.I3
    w1, w2 = omega[..., 0], omega[..., 1]
    g1, g2 = gamma[..., 0], gamma[..., 1]
    return (w1 * w1 - w2 * w2 - nu * g1) ** 2 + (2 * w1 * w2 - nu * g2) ** 2


def lagrange_invariants(i1, i3, mgl, theta, theta_dot, phi_dot, psi_dot):
    """(E, Mz, M3) of a Lagrange top from Euler angles and rates."""
    s, c = math.sin(theta), math.cos(theta)
    omega3 = psi_dot + phi_dot * c
    m3 = i3 * omega3
    mz = i1 * phi_dot * s * s + m3 * c
    e = 0.5 * i1 * (theta_dot**2 + (phi_dot * s) ** 2) + 0.5 * i3 * omega3**2 + mgl * c
    return e, mz, m3


# --------------------------------------------------------------------------------------
# distances and Lyapunov exponents
# --------------------------------------------------------------------------------------


def perturb(q, omega, delta):
    """State displaced by a 6-vector delta = (body rotation vector, d omega)."""
    delta = np.asarray(delta, dtype=float)
    angle = float(np.linalg.norm(delta[:3]))
    if angle > 0:
        dq = quat_axis_angle(delta[:3] / angle, angle)
    else:
        dq = np.array([1.0, 0.0, 0.0, 0.0])
    return quat_mul(np.asarray(q, dtype=float), dq), np.asarray(omega, dtype=float) + delta[3:]


def difference(q_ref, omega_ref, q, omega):
    """6-vector (body rotation vector of R_ref^T R, omega - omega_ref), vectorised."""
    r_ref = quat_to_matrix(q_ref)
    r = quat_to_matrix(q)
    rel = np.swapaxes(r_ref, -1, -2) @ r
    return np.concatenate([rotation_vector(rel), np.asarray(omega) - np.asarray(omega_ref)], -1)


def lyapunov_renormalised(step, q0, omega0, direction, d0, tau, n_segments):
    """Largest Lyapunov exponent by Benettin's renormalisation.

    ``step(q, omega, tau) -> (q, omega)`` advances a state by ``tau`` (any integrator).
    Returns the running estimates (n_segments,) in 1/s.
    """
    direction = np.asarray(direction, dtype=float)
    direction = direction / np.linalg.norm(direction)
    q, w = np.asarray(q0, dtype=float), np.asarray(omega0, dtype=float)
    qp, wp = perturb(q, w, d0 * direction)
    total = 0.0
    out = np.empty(n_segments)
    for k in range(n_segments):
        q, w = step(q, w, tau)
        qp, wp = step(qp, wp, tau)
        diff = difference(q, w, qp, wp)
        dist = float(np.linalg.norm(diff))
        total += math.log(dist / d0)
        out[k] = total / ((k + 1) * tau)
        qp, wp = perturb(q, w, diff * (d0 / dist))
    return out
