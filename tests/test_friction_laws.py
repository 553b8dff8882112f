"""What each friction law does to Euler's disk and the toy top, as their docstrings state it
(kreisel.bodies.disk, kreisel.bodies.toy_top): each number there is measured here."""

from __future__ import annotations

import numpy as np
import pytest

from kreisel import Coulomb, _core, bodies, events, simulate

EULER_DISK = (0.0375, 0.0125, 0.434)


def _disk_run(t_end, friction=None, rolling=0.0, samples=2001):
    top = bodies.disk(*EULER_DISK, friction=friction, rolling_resistance=rolling)
    st = bodies.disk_rolling_state(top, 0.3)
    return simulate(top, st, t_end, rtol=1e-8, t_eval=np.linspace(0.0, t_end, samples),
                    events=[events.rest()])  # fmt: skip


def _flat(run):
    return next(e.t for e in run.events if e.name == "flat")


def test_point_coulomb_friction_alone_dissipates_nothing_on_the_rolling_disk():
    run = _disk_run(5.0, Coulomb(0.3))
    assert run.dissipated[-1] < 1e-9 * run.energy[0]
    assert np.abs(run.theta - 0.3).max() < 1e-4


def test_drilling_alone_brings_the_disk_down_slowly():
    run = _disk_run(20.0)  # the default Coulomb-Contensou, no rolling resistance
    assert round(float(run.theta[-1]), 2) == 0.22
    assert not any(e.name == "flat" for e in run.events)
    assert "0.3 rad -> 0.22 rad in 20 s, flat after 243 s" in bodies.disk.__doc__


def test_rolling_resistance_brings_the_disk_down_and_drilling_takes_little():
    contensou = _disk_run(3.0, rolling=2e-3, samples=30001)
    point = _disk_run(3.0, Coulomb(0.3), rolling=2e-3)
    assert round(_flat(contensou), 3) == 0.963 and round(_flat(point), 3) == 0.965
    # the drilling torque of a patch of radius r is at most (2/3) mu N r (pure drilling)
    rot = _core.rotation_matrices(np.ascontiguousarray(contensou.quaternion))
    spin = np.einsum("nij,nj->ni", rot, contensou.omega)[:, 2]
    n = np.nan_to_num(contensou.normal_force)
    bound = np.trapezoid(2 / 3 * 0.3 * n * 2e-4 * np.abs(spin), contensou.t)
    assert round(100 * bound / contensou.dissipated[-1], 2) == 0.52
    assert "drilling takes at most 0.52 % of the energy dissipated" in bodies.disk.__doc__


def _tilt_growth(spin: float, theta0: float = 0.05) -> float:
    top = bodies.toy_top()
    run = simulate(top, top.state(theta=theta0, psi_dot=spin), 2.0, rtol=1e-9,
                   t_eval=np.linspace(0.0, 2.0, 201))  # fmt: skip
    return float(run.theta[150:].mean() / run.theta[:50].mean())


def test_the_toy_top_tips_well_above_rouths_threshold_under_its_friction():
    top = bodies.toy_top()
    tip = top.shape[0]
    a_tip = top.A + top.m * tip.z**2
    routh = 2 * np.sqrt(a_tip * top.m * 9.81 * -tip.z) / top.C
    assert round(routh, 1) == 126.5
    growth = {w: _tilt_growth(w) for w in (180.0, 200.0, 205.0, 220.0)}
    assert growth[180.0] == pytest.approx(1.015, abs=5e-4)
    assert 1.0 < growth[200.0] < 1.001
    assert growth[205.0] < 1.0 and growth[220.0] < growth[205.0]
    assert "tilt grows over 2 s below about 201 rad/s" in bodies.toy_top.__doc__
