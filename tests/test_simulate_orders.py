"""Convergence orders of every integrator of kreisel.simulate, measured on the exact solution.

The reference is the exact Lagrange-top motion (``LagrangeTop.exact``, tested on its own
against mpmath). The error is the largest entry of R_numerical(t) - R_exact(t) over all
output rows, R the body-to-space rotation matrix, so Euler-angle wrapping plays no part and
both the figure axis and the spin about it are measured.

Fixed-step methods: the slope of log(max error) against log(dt) must match the declared
order within +-0.3 (+-0.5 for order >= 6). The step counts are chosen per method so that
every error lies in the asymptotic range, well above round-off; the test checks that too.
"""

from __future__ import annotations

import _sim_reference as ref
import numpy as np
import pytest

import kreisel

PARAMS = {"I1": 1.0, "I3": 0.5, "m": 1.0, "l": 0.3, "g": 1.0}
START = {"theta": 1.0, "theta_dot": 0.3, "phi_dot": 0.7, "psi_dot": 5.0}
T_END = 2.0

# declared orders (the brief), checked against kreisel.methods() below
ORDER = {
    "rk4": 4,
    "splitting": 2,
    "splitting4": 4,
    "splitting6": 6,
    "verlet": 2,
    "midpoint": 2,
    "gauss4": 4,
}

# numbers of steps over T_END, per method, geometric, in the asymptotic range: errors
# between ~1e-3 and ~1e-10 (splitting4 and splitting6 are accurate, so they take few steps)
STEPS = {
    "rk4": (40, 80, 160, 320, 640),
    "splitting": (100, 200, 400, 800, 1600),
    "splitting4": (10, 20, 40, 80, 160),
    "splitting6": (8, 12, 16, 24, 32),
    "verlet": (100, 200, 400, 800, 1600),
    "midpoint": (100, 200, 400, 800, 1600),
    "gauss4": (40, 80, 160, 320, 640),
}

ERR_MAX = 1e-2  # beyond this the step is not small
ERR_MIN = 1e-11  # below this round-off (~1e-14 per step, ~1e-13 accumulated) is too close


@pytest.fixture(scope="module")
def lagrange():
    top = kreisel.LagrangeTop(**PARAMS)
    return top, top.state(**START)


def max_error(top, state, traj) -> float:
    ex = top.exact(state, traj.t)
    r_exact = ref.euler_matrix(ex.phi, ex.theta, ex.psi)
    return float(np.abs(ref.quat_to_matrix(traj.quaternion) - r_exact).max())


def test_every_method_is_covered():
    declared = {info.name: info.order for info in kreisel.methods()}
    assert declared == {**ORDER, "dop853": 8}


@pytest.mark.parametrize("method", sorted(ORDER))
def test_order_fixed_step(method, lagrange):
    top, state = lagrange
    dts, errs = [], []
    for n in STEPS[method]:
        dt = T_END / n
        traj = kreisel.simulate(top, state, T_END, method=method, dt=dt)
        assert len(traj) == n + 1
        assert abs(traj.t[-1] - T_END) < 1e-12
        dts.append(dt)
        errs.append(max_error(top, state, traj))
    errs = np.array(errs)
    table = ", ".join(f"dt={d:.4g}: {e:.3e}" for d, e in zip(dts, errs))
    assert np.all((errs > ERR_MIN) & (errs < ERR_MAX)), f"{method}: outside the window: {table}"
    assert np.all(np.diff(errs) < 0), f"{method}: error not decreasing: {table}"
    slope = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    tol = 0.5 if ORDER[method] >= 6 else 0.3
    assert abs(slope - ORDER[method]) <= tol, f"{method}: slope {slope:.3f}; {table}"
    # the last halving alone is also in line (no flattening at the fine end)
    local = np.log(errs[-2] / errs[-1]) / np.log(dts[-2] / dts[-1])
    assert abs(local - ORDER[method]) <= tol + 0.2, f"{method}: last slope {local:.3f}; {table}"


def test_dop853_tolerance_proportionality(lagrange):
    """Adaptive DOP853: the error falls with the tolerance, roughly in proportion."""
    top, state = lagrange
    errs = []
    for rtol in (1e-5, 1e-7, 1e-9, 1e-11):
        traj = kreisel.simulate(top, state, T_END, method="dop853", rtol=rtol, atol=rtol * 1e-2)
        errs.append(max_error(top, state, traj))
    errs = np.array(errs)
    assert np.all(errs[1:] < errs[:-1] / 10), errs  # each 100x tighter: >= 10x smaller
    assert errs[0] < 1e-3, errs
    traj = kreisel.simulate(top, state, T_END, method="dop853", rtol=1e-10, atol=1e-12)
    assert max_error(top, state, traj) < 1e-8
    # the default tolerances are rtol = 1e-10, atol = 1e-12
    default = kreisel.simulate(top, state, T_END)
    np.testing.assert_array_equal(default.t, traj.t)
    np.testing.assert_array_equal(default.quaternion, traj.quaternion)


def test_dop853_order_with_step_count(lagrange):
    """Error against the number of accepted steps over 20 s (~8 nutation periods): slope ~ -8
    (DOP853 is 8th order, so doubling the steps gains ~2^8 in accuracy)."""
    top, state = lagrange
    steps, errs = [], []
    for rtol in (1e-6, 1e-8, 1e-10):
        traj = kreisel.simulate(top, state, 20.0, method="dop853", rtol=rtol, atol=rtol * 1e-2)
        steps.append(traj.stats["steps"])
        errs.append(max_error(top, state, traj))
    slope = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    assert -8.0 - 1.5 <= slope <= -8.0 + 1.5, (steps, errs, slope)
