"""HeavyTop.lyapunov and the Lyapunov exponent in batches and sweeps.

Reference: the same Benettin renormalisation written in Python (tests/_sim_reference.py)
with scipy's DOP853 at rtol 1e-12 as the integrator and its own rotation-vector geometry.
Before the two integrations part (chaos amplifies their ~1e-12 differences by e^(0.4 t)),
the running estimates must agree closely; afterwards only statistically.
"""

import numpy as np
import pytest
from _sim_reference import Body, euler_to_quat, integrate_quaternion, lyapunov_renormalised

import kreisel

CHAOS = Body(1.0, 0.75, 0.5, 1.0, (0.3, 0.2, 0.4), 9.81)
Q0, W0 = euler_to_quat(0.0, 1.2, 0.3), np.array([2.0, 1.0, 3.0])
DIRECTION = np.ones(6) / np.sqrt(6.0)


def chaos_top():
    return kreisel.HeavyTop(CHAOS.I1, CHAOS.I2, CHAOS.I3, CHAOS.m, list(CHAOS.com), CHAOS.g)


def scipy_step(q, w, tau):
    qs, ws = integrate_quaternion(CHAOS, q, w, [0.0, tau], rtol=1e-12, atol=1e-14)
    return qs[-1], ws[-1]


def test_chaotic_top_matches_the_python_reference_while_the_motions_agree():
    top = chaos_top()
    est = top.lyapunov(top.state_from_quaternion(Q0, W0), 20.0, tau=0.5, rtol=1e-12, atol=1e-14)
    ref = lyapunov_renormalised(scipy_step, Q0, W0, DIRECTION, 1e-9, 0.5, 40)
    np.testing.assert_allclose(est.t, 0.5 * np.arange(1, 41), rtol=1e-15)
    np.testing.assert_allclose(est.running, ref, rtol=1e-4)
    assert est.exponent == est.running[-1]


def test_chaotic_top_exponent_settles_positive_and_independent_of_the_direction():
    top = chaos_top()
    st = top.state_from_quaternion(Q0, W0)
    a = top.lyapunov(st, 400.0)
    b = top.lyapunov(st, 400.0, direction=[0, 0, 0, 0.3, -1.0, 0.5], tau=0.5)
    # scipy reference over 300 s: ~0.4 /s; the two estimates share their limit
    assert 0.25 < a.exponent < 0.6 and 0.25 < b.exponent < 0.6
    assert abs(a.exponent - b.exponent) < 0.2 * a.exponent
    # settled: the last quarter moves little
    tail = a.running[a.t > 300.0]
    assert np.ptp(tail) < 0.1 * a.exponent


@pytest.mark.parametrize("kind", ["lagrange", "euler", "kovalevskaya"])
def test_integrable_tops_have_a_vanishing_exponent(kind):
    if kind == "lagrange":
        top = kreisel.LagrangeTop(1.0, 0.5, 1.0, 0.3, g=1.0)
        st = top.state(1.0, theta_dot=0.3, phi_dot=0.7, psi_dot=5.0)
    elif kind == "euler":
        top = kreisel.HeavyTop(1.0, 1.6, 2.1, 1.0, [0.0, 0.0, 0.0])
        st = top.state_from_quaternion([1, 0, 0, 0], [0.1, 2.0, 0.2])  # near the middle axis
    else:
        top = kreisel.HeavyTop(2.0, 2.0, 1.0, 1.0, [0.5, 0.0, 0.0], g=1.0)
        st = top.state(1.0, psi_dot=1.0, phi_dot=0.3)
    est = top.lyapunov(st, 400.0)
    # separations grow linearly: the estimate decays like ln(t)/t
    assert est.exponent < 0.05, est.exponent
    assert est.exponent < 0.6 * est.running[99], (est.running[99], est.exponent)


@pytest.mark.parametrize(
    ("kw", "name"),
    [
        ({"tau": 0.0}, "tau"),
        ({"d0": 0.1}, "d0"),
        ({"direction": [0] * 6}, "direction"),
        ({"direction": [1, 2]}, "direction"),
        ({"rtol": 2.0}, "rtol"),
        ({"t_end": -1.0}, "t_end"),
    ],
)
def test_bad_arguments_are_named(kw, name):
    top = chaos_top()
    st = top.state_from_quaternion(Q0, W0)
    args = {"t_end": 10.0, **kw}
    with pytest.raises(kreisel.ParameterError, match=name):
        top.lyapunov(st, **args)


def test_sweeps_keep_the_exponent_on_request(tmp_path):
    tables = {
        "top": {"kind": "heavy", "I1": 1.0, "I2": 0.75, "I3": 0.5, "m": 1.0},
        "state": {"theta": 1.2, "psi": 0.3, "psi_dot": 3.0},
        "simulation": {"t_end": 60.0},
        "grid": {"com_x": [0.0, 0.3], "com_z": [0.0, 0.4]},
        "output": {"keep": ["lyapunov", "energy_drift"], "lyapunov_tau": 0.5},
    }
    ds = kreisel.sweep(tables, tmp_path / "chaos.zarr", progress=False)
    for i, cx in enumerate((0.0, 0.3)):
        for j, cz in enumerate((0.0, 0.4)):
            top = kreisel.HeavyTop(1.0, 0.75, 0.5, 1.0, [cx, 0.0, cz])
            est = top.lyapunov(top.state(1.2, psi=0.3, psi_dot=3.0), 60.0, tau=0.5)
            assert ds["lyapunov"].values[i, j] == est.exponent
    # no torque: an Euler top, integrable
    assert ds["lyapunov"].values[0, 0] < 0.1
    assert np.all(ds["energy_drift"].values < 1e-8)
    del tables["output"]["keep"]
    with pytest.raises(kreisel.ParameterError, match="lyapunov_tau is given but lyapunov"):
        kreisel.sweep(tables, None, progress=False)
