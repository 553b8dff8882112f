"""Forward sensitivities of ``kreisel.simulate``: every name against three references.

References, each computed here and independently of the core's variational equations:

- central finite differences of ``kreisel.simulate`` itself at tight tolerances;
- complex-step differentiation (Squire & Trapp, SIAM Rev. 40 (1998) 110) of the heavy top
  written in this file in a second form, the rotation matrix and the body rates
  (R' = R [omega]x, Euler's equations with the torque Gamma x m g c, Gamma the third row of
  R), integrated by scipy's DOP853 with complex y;
- fourth-order differences of the exact elliptic-function solution of the Lagrange top
  (``LagrangeTop.exact``, tested on its own against mpmath).

A sensitivity is compared as a whole array over the run: the largest deviation relative to
the largest reference value, which must stay below 1e-6. A reference whose values all stay
below ``FLOOR`` times the size of the quantity (its largest value over the run, at least 1;
a sensitivity that vanishes, such as that of the body rates to phi) is compared absolutely
against ``1e-6`` of that: the differences of a run that spins 120 times a second carry its
round-off divided by the step.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

import kreisel

TIGHT = {"rtol": 1e-13, "atol": 1e-14}
FLOOR = 1e-2
T_EVAL = np.linspace(0.0, 1.0, 6)

# asymmetric, centre of mass off every axis
GENERAL = {"I1": 1.0, "I2": 0.75, "I3": 0.5, "m": 1.0, "com": [0.3, 0.2, 0.4], "g": 9.81}
GENERAL_START = {
    "theta": 0.8,
    "phi": 0.3,
    "psi": -0.4,
    "theta_dot": 0.5,
    "phi_dot": 1.0,
    "psi_dot": 8.0,
}
LAG = {"I1": 0.0125, "I3": 0.005, "m": 0.5, "l": 0.1, "g": 9.81}
LAG_START = {
    "theta": 0.6,
    "phi": 0.2,
    "psi": 0.1,
    "theta_dot": 0.4,
    "phi_dot": 2.0,
    "psi_dot": 120.0,
}
HEAVY_NAMES = ["I1", "I2", "I3", "m", "g", "com[0]", "com[1]", "com[2]"]
LAG_NAMES = ["I1", "I3", "m", "l", "g"]
EULER_NAMES = list(GENERAL_START)
RIGID_NAMES = [f"orientation[{i}]" for i in range(3)] + [f"omega[{i}]" for i in range(3)]
KEYS = ("omega", "orientation", "quaternion", "theta", "phi", "psi")


def close(got, ref, what, size=1.0):
    got, ref = np.asarray(got), np.asarray(ref)
    assert got.shape == ref.shape, what
    scale = max(np.max(np.abs(ref)), FLOOR * size)
    err = np.max(np.abs(got - ref)) / scale
    assert err < 1e-6, f"{what}: deviation {err:.2e} of the reference's scale {scale:.3e}"


def hat(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def vee(a):
    return np.array([a[2, 1], a[0, 2], a[1, 0]])


def qmul(a, b):
    return np.array(
        [
            a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
        ]
    )


def conj(q):
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def matrix(q):
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def euler_matrix(phi, theta, psi):
    """R = Rz(phi) Rx(theta) Rz(psi) (z-x-z), in any (also complex) arithmetic."""

    def rz(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[c, -s, 0 * c], [s, c, 0 * c], [0 * c, 0 * c, 1 + 0 * c]])

    def rx(a):
        c, s = np.cos(a), np.sin(a)
        return np.array([[1 + 0 * c, 0 * c, 0 * c], [0 * c, c, -s], [0 * c, s, c]])

    return rz(phi) @ rx(theta) @ rz(psi)


def body_rates(theta, psi, theta_dot, phi_dot, psi_dot):
    """Goldstein's z-x-z body angular velocity from the Euler rates."""
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    return np.array(
        [
            phi_dot * st * sp + theta_dot * cp,
            phi_dot * st * cp - theta_dot * sp,
            phi_dot * ct + psi_dot,
        ]
    )


# ---------------------------------------------------------------------------- finite differences


def general_run(p, state_kind="euler", **kw):
    top = kreisel.HeavyTop(p["I1"], p["I2"], p["I3"], p["m"], p["com"], p["g"])
    s = p["state"]
    if state_kind == "euler":
        state = top.state(**s)
    else:
        state = top.state_from_quaternion(s["q"], s["omega"])
    return kreisel.simulate(top, state, 1.0, t_eval=T_EVAL, **TIGHT, **kw)


def perturbed(p, name, h):
    """A copy of the parameters `p` with `name` moved by h (a rigid state's orientation by
    the body-frame rotation h e_i: q -> q exp(h e_i / 2))."""
    p = {**p, "com": list(p["com"]) if "com" in p else None, "state": dict(p["state"])}
    if name.startswith("com["):
        p["com"][int(name[4])] += h
    elif name.startswith("orientation["):
        e = np.zeros(3)
        e[int(name[12])] = h
        half = np.concatenate([[np.cos(h / 2)], np.sin(h / 2) * e / h])
        p["state"]["q"] = qmul(np.asarray(p["state"]["q"]), half)
    elif name.startswith("omega["):
        w = np.array(p["state"]["omega"], dtype=float)
        w[int(name[6])] += h
        p["state"]["omega"] = w
    elif name in p["state"]:
        p["state"][name] += h
    else:
        p[name] += h
    return p


def differences(run, p, name, h):
    """Central differences of every sensitivity key of `run` in `name`."""
    a, b = run(perturbed(p, name, h)), run(perturbed(p, name, -h))
    q0 = run(p).quaternion
    dq = (a.quaternion - b.quaternion) / (2 * h)
    xi = np.array([2 * qmul(conj(q), d)[1:] for q, d in zip(q0, dq)])
    return {
        "omega": (a.omega - b.omega) / (2 * h),
        "orientation": xi,
        "quaternion": dq,
        "theta": (a.theta - b.theta) / (2 * h),
        "phi": (a.phi - b.phi) / (2 * h),
        "psi": (a.psi - b.psi) / (2 * h),
    }


def agree_with_differences(run, p, traj, names):
    """Every sensitivity of `traj` (a run of `run` from `p`) against central differences:
    steps relative to a parameter's value (I1 is 0.0125), absolute ones of 1e-5 (rad, rad/s;
    1e-5 of values above 1) for the state."""
    for name in names:
        if name.startswith("com["):
            h = 1e-5 * abs(p["com"][int(name[4])])
        elif name in p:
            h = 1e-5 * abs(p[name])
        else:
            h = 1e-5 * max(abs(p["state"].get(name, 1.0)), 1.0)
        ref = differences(run, p, name, h)
        for key in KEYS:
            size = 1.0 if key == "orientation" else max(np.abs(traj[key]).max(), 1.0)
            close(traj.sensitivities[name][key], ref[key], f"{name} {key}", size)


def general_params():
    return {**GENERAL, "state": dict(GENERAL_START)}


def test_general_top_sensitivities_are_the_finite_differences_of_its_runs():
    p = general_params()
    names = HEAVY_NAMES + EULER_NAMES
    traj = general_run(p, sensitivities=names)
    assert list(traj.sensitivities) == names
    agree_with_differences(general_run, p, traj, names)


def test_rigid_state_sensitivities_are_the_finite_differences_of_its_runs():
    q = np.array([0.9, 0.3, -0.2, 0.25])
    p = {**GENERAL, "state": {"q": q / np.linalg.norm(q), "omega": [0.5, -0.3, 8.0]}}
    run = lambda p, **kw: general_run(p, "rigid", **kw)  # noqa: E731
    traj = run(p, sensitivities=RIGID_NAMES)
    agree_with_differences(run, p, traj, RIGID_NAMES)


def lagrange_run(p, **kw):
    top = kreisel.LagrangeTop(p["I1"], p["I3"], p["m"], p["l"], p["g"])
    return kreisel.simulate(top, top.state(**p["state"]), 1.0, t_eval=T_EVAL, **TIGHT, **kw)


def test_lagrange_top_sensitivities_are_the_finite_differences_of_its_runs():
    p = {**LAG, "state": dict(LAG_START)}
    names = LAG_NAMES + EULER_NAMES
    traj = lagrange_run(p, sensitivities=names)
    agree_with_differences(lagrange_run, p, traj, names)


def test_a_run_with_sensitivities_is_the_run_without_bit_for_bit():
    top = kreisel.HeavyTop(**GENERAL)
    s = top.state(**GENERAL_START)
    plain = kreisel.simulate(top, s, 2.0)
    sens = kreisel.simulate(top, s, 2.0, sensitivities=["I1", "theta", "com[2]"])
    assert plain.sensitivities is None
    np.testing.assert_array_equal(sens.t, plain.t)
    np.testing.assert_array_equal(sens.quaternion, plain.quaternion)
    np.testing.assert_array_equal(sens.omega, plain.omega)
    np.testing.assert_array_equal(sens.energy, plain.energy)
    assert sens.stats == plain.stats
    for d in sens.sensitivities.values():
        for key in KEYS:
            assert len(d[key]) == len(plain.t)


def test_exact_solutions_and_other_trajectories_have_no_sensitivities():
    top = kreisel.LagrangeTop(**LAG)
    assert top.exact(top.state(**LAG_START), [0.0, 0.1]).sensitivities is None


# ---------------------------------------------------------------------------- complex step


def complex_step(p, start, *, name, h=1e-30, damping=(0.0, 0.0)):
    """The sensitivities (omega and body-frame xi) of the heavy top in `name` by the complex
    step: the equations in (R, omega) with the pivot's torque -(c + k |omega|) omega
    (|omega| as sqrt(omega . omega), analytic in complex numbers), integrated by scipy's
    DOP853 with complex y."""
    inertia = np.array([p["I1"], p["I2"], p["I3"]], dtype=complex)
    m, g = complex(p["m"]), complex(p["g"])
    c, k = complex(damping[0]), complex(damping[1])
    if name == "viscous":
        c += 1j * h
    elif name == "drag":
        k += 1j * h
    com = np.array(p["com"], dtype=complex)
    e = dict(start)
    if name in ("I1", "I2", "I3"):
        inertia[int(name[1]) - 1] += 1j * h
    elif name == "m":
        m += 1j * h
    elif name == "g":
        g += 1j * h
    elif name.startswith("com["):
        com[int(name[4])] += 1j * h
    elif name in e:
        e = {key: complex(v) for key, v in e.items()}
        e[name] += 1j * h
    r0 = euler_matrix(e["phi"], e["theta"], e["psi"])
    w0 = body_rates(e["theta"], e["psi"], e["theta_dot"], e["phi_dot"], e["psi_dot"])
    mgc = m * g * com

    def rhs(t, y):
        r, w = y[:9].reshape(3, 3), y[9:]
        gamma = r[2]
        torque = np.array(
            [
                gamma[1] * mgc[2] - gamma[2] * mgc[1],
                gamma[2] * mgc[0] - gamma[0] * mgc[2],
                gamma[0] * mgc[1] - gamma[1] * mgc[0],
            ]
        )
        mom = inertia * w
        gyro = np.array(
            [
                mom[1] * w[2] - mom[2] * w[1],
                mom[2] * w[0] - mom[0] * w[2],
                mom[0] * w[1] - mom[1] * w[0],
            ]
        )
        rw = r @ np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        damp = -(c + k * np.sqrt(w @ w)) * w
        return np.concatenate([rw.ravel(), (gyro + torque + damp) / inertia])

    y0 = np.concatenate([np.asarray(r0, dtype=complex).ravel(), np.asarray(w0, dtype=complex)])
    sol = solve_ivp(rhs, (0.0, 1.0), y0, method="DOP853", t_eval=T_EVAL, rtol=1e-13, atol=1e-14)
    assert sol.success
    ys = sol.y.T
    xi = np.array([vee(y[:9].real.reshape(3, 3).T @ (y[:9].imag.reshape(3, 3) / h)) for y in ys])
    return {"omega": ys[:, 9:].imag / h, "orientation": xi}


@pytest.mark.parametrize("name", HEAVY_NAMES + EULER_NAMES)
def test_general_top_sensitivities_are_the_complex_step_of_a_second_formulation(name):
    traj = general_run(general_params(), sensitivities=[name])
    ref = complex_step(GENERAL, GENERAL_START, name=name)
    for key in ("omega", "orientation"):
        size = 1.0 if key == "orientation" else max(np.abs(traj[key]).max(), 1.0)
        close(traj.sensitivities[name][key], ref[key], f"{name} {key}", size)


DAMPING = {"viscous": 0.05, "drag": 0.02}


@pytest.mark.parametrize("name", ["viscous", "drag", "I2", "com[0]", "theta", "psi_dot"])
def test_damped_top_sensitivities_are_the_complex_step_of_a_second_formulation(name):
    top = kreisel.HeavyTop(**GENERAL, damping=kreisel.PivotDamping(**DAMPING))
    traj = kreisel.simulate(
        top, top.state(**GENERAL_START), 1.0, t_eval=T_EVAL, **TIGHT, sensitivities=[name]
    )
    ref = complex_step(GENERAL, GENERAL_START, name=name, damping=tuple(DAMPING.values()))
    for key in ("omega", "orientation"):
        close(traj.sensitivities[name][key], ref[key], f"{name} {key}")


def damped_lagrange_run(p, **kw):
    damping = kreisel.PivotDamping(viscous=p["viscous"], drag=p["drag"])
    top = kreisel.LagrangeTop(p["I1"], p["I3"], p["m"], p["l"], p["g"], damping=damping)
    return kreisel.simulate(top, top.state(**p["state"]), 1.0, t_eval=T_EVAL, **TIGHT, **kw)


def test_damped_lagrange_top_sensitivities_are_the_finite_differences_of_its_runs():
    p = {**LAG, "viscous": 1e-4, "drag": 2e-6, "state": dict(LAG_START)}
    names = ["viscous", "drag", "I1", "l", "theta", "psi_dot"]
    traj = damped_lagrange_run(p, sensitivities=names)
    plain = damped_lagrange_run(p)
    np.testing.assert_array_equal(traj.quaternion, plain.quaternion)
    np.testing.assert_array_equal(traj.dissipated, plain.dissipated)
    agree_with_differences(damped_lagrange_run, p, traj, names)


# ---------------------------------------------------------------------------- exact solution


def test_lagrange_top_sensitivities_are_the_derivatives_of_the_exact_solution():
    t = np.linspace(0.0, 2.0, 9)
    p = {**LAG, **LAG_START}
    top = kreisel.LagrangeTop(**LAG)
    names = LAG_NAMES + EULER_NAMES
    traj = kreisel.simulate(
        top, top.state(**LAG_START), 2.0, t_eval=t, **TIGHT, sensitivities=names
    )

    def exact(q):
        top = kreisel.LagrangeTop(*(q[k] for k in LAG_NAMES))
        return top.exact(top.state(**{k: q[k] for k in LAG_START}), t)

    for name in names:
        # fourth-order differences: the exact solution is smooth and exact to round-off, so
        # a larger step leaves both truncation (h^4) and round-off (1/h) below 1e-8
        h = 1e-4 * (abs(p[name]) if name in LAG_NAMES else max(abs(p[name]), 1.0))
        f = {k: exact({**p, name: p[name] + k * h}) for k in (-2, -1, 1, 2)}
        for key in ("theta", "phi", "psi"):
            ref = (f[-2][key] - 8 * f[-1][key] + 8 * f[1][key] - f[2][key]) / (12 * h)
            close(traj.sensitivities[name][key], ref, f"{name} {key}")


# ---------------------------------------------------------------------------- the rotation group


def test_orientation_sensitivity_is_a_body_frame_rotation():
    """R(p + h) = R(p) exp(h [xi]x) + O(h^2); the same xi in the space frame is off by O(h)."""
    p = general_params()
    traj = general_run(p, sensitivities=["I3", "theta"])
    for name in ("I3", "theta"):
        h = 1e-4
        moved = general_run(perturbed(p, name, h))
        xi = traj.sensitivities[name]["orientation"]
        body, space, step = [], [], []
        for q, q1, x in zip(traj.quaternion[1:], moved.quaternion[1:], xi[1:]):
            r, r1, turn = matrix(q), matrix(q1), expm(h * hat(x))
            body.append(np.abs(r1 - r @ turn).max())
            space.append(np.abs(r1 - turn @ r).max())
            step.append(np.abs(r1 - r).max())
        # the change is first order, the body-frame remainder second order, the space-frame one not
        assert min(step) > 1e2 * max(body), (name, step, body)
        assert min(space) > 1e2 * max(body), (name, space, body)


# ---------------------------------------------------------------------------- bad input


def lagrange_case():
    top = kreisel.LagrangeTop(**LAG)
    return top, top.state(**LAG_START)


@pytest.mark.parametrize(
    "value, words",
    [
        (["I2"], ['"I2"', "I1, I3, m, l, g", "theta, phi, psi"]),
        (["m", "m"], ['"m"', "at most once"]),
        (["orientation[0]"], ['"orientation[0]"', "theta_dot"]),
        ("I3", ["sensitivities = 'I3'", "list of names"]),
        ([3], ["sensitivities contains 3", "str"]),
        ([], ["sensitivities = []", "at least one"]),
    ],
)
def test_bad_sensitivity_names_are_refused_by_name(value, words):
    top, s = lagrange_case()
    with pytest.raises(kreisel.ParameterError) as e:
        kreisel.simulate(top, s, 0.1, sensitivities=value)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_state_names_follow_the_kind_of_state():
    top = kreisel.HeavyTop(**GENERAL)
    rigid = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.1, 0.0, 5.0])
    with pytest.raises(kreisel.ParameterError, match=r'"theta".*orientation\[0\]'):
        kreisel.simulate(top, rigid, 0.1, sensitivities=["theta"])
    traj = kreisel.simulate(top, rigid, 0.1, sensitivities=["orientation[1]", "omega[2]"])
    assert traj.sensitivities["omega[2]"]["omega"][0].tolist() == [0.0, 0.0, 1.0]
    assert traj.sensitivities["orientation[1]"]["orientation"][0].tolist() == [0.0, 1.0, 0.0]


def test_sensitivities_refuse_other_methods_events_and_models():
    top, s = lagrange_case()
    with pytest.raises(kreisel.ParameterError, match=r'method = "rk4".*"dop853"'):
        kreisel.simulate(top, s, 0.1, method="rk4", dt=1e-3, sensitivities=["m"])
    ev = kreisel.events.turning_points()
    with pytest.raises(kreisel.ParameterError, match="events = 1 event.*no events"):
        kreisel.simulate(top, s, 0.1, events=[ev], sensitivities=["m"])
    with pytest.raises(kreisel.ParameterError, match='"viscous".*damping=PivotDamping'):
        kreisel.simulate(top, s, 0.1, sensitivities=["viscous"])
    dry = kreisel.LagrangeTop(**LAG, damping=kreisel.PivotDamping(dry=0.1, pivot_radius=1e-3))
    with pytest.raises(kreisel.ParameterError, match="dry friction at the pivot have none"):
        kreisel.simulate(dry, s, 0.1, sensitivities=["m"])
    shaken = kreisel.LagrangeTop(**LAG, pivot=kreisel.pivots.Harmonic([0, 0, 1e-3], 100.0))
    with pytest.raises(kreisel.ParameterError, match="a moving pivot"):
        kreisel.simulate(shaken, s, 0.1, sensitivities=["m"])
    play = kreisel.PlayTop(m=0.03, A=4e-6, C=5e-6, s=0.004, rho=0.025, g=9.7)
    # a top on a floor has its own names (tests/test_play_sensitivities.py)
    with pytest.raises(kreisel.ParameterError, match="a play top has the parameters"):
        kreisel.simulate(play, play.state(theta=0.2, psi_dot=100.0), 0.1, sensitivities=["I1"])
