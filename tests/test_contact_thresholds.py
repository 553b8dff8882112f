"""The contact model's thresholds are the model's, not the integration's (theory: play top,
contact thresholds): a ball sliding without spin sticks where its slip falls to
``stick_threshold`` of the speed scale at the start of its sliding, whatever ``rtol``."""

from __future__ import annotations

import math

import pytest

import kreisel
from kreisel import Coulomb, ParameterError, PlayTop
from kreisel.shapes import Sphere

MU, R, M, V0, G = 0.2, 0.01, 0.05, 1.0, 9.81


def _ball(**kw) -> PlayTop:
    inertia = 0.4 * M * R * R
    return PlayTop(M, inertia, inertia, shape=[Sphere(R, z=0.0)], friction=Coulomb(MU), **kw)


def _stick_time(eps: float) -> float:
    """The closed form: a uniform ball centred at G (reach R) sliding without spin loses slip
    at (7/2) mu g; its speed scale at the start is V0 + sqrt(g R) (no rotation yet), so it
    sticks where V0 - (7/2) mu g t = eps (V0 + sqrt(g R))."""
    return (V0 - eps * (V0 + math.sqrt(G * R))) / (3.5 * MU * G)


@pytest.mark.parametrize("rtol", [1e-8, 1e-11])
def test_the_stick_time_follows_the_models_threshold_not_rtol(rtol):
    eps = 1e-4
    top = _ball(stick_threshold=eps)
    st = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0], vx=V0)
    tr = kreisel.simulate(top, st, 0.2, t_eval=[0.2], rtol=rtol, atol=rtol * 1e-3)
    sticks = [e.t for e in tr.events if e.name == "slip_to_roll"]
    expected = _stick_time(eps)
    # The threshold moves the stick by eps V / a (about 1.9e-5 s here), a hundred times the
    # tolerance the check allows: 10 rtol of the speed scale (the rule before the threshold
    # was the model's) would put it 1e-7 .. 1e-10 of the speed scale off instead.
    assert abs(_stick_time(0.0) - expected) > 1e-5
    assert sticks and abs(sticks[0] - expected) < 1e-9, (sticks, expected)


def test_the_default_threshold_is_a_billionth_of_the_speed_scale():
    top = _ball()
    assert top.stick_threshold == 1e-9
    assert top._native.stick_threshold == 1e-9
    st = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0], vx=V0)
    tr = kreisel.simulate(top, st, 0.2, t_eval=[0.2], rtol=1e-11, atol=1e-14)
    sticks = [e.t for e in tr.events if e.name == "slip_to_roll"]
    assert sticks and abs(sticks[0] - _stick_time(1e-9)) < 1e-10


def test_a_threshold_shows_in_the_repr_and_reaches_the_core():
    top = _ball(stick_threshold=1e-6)
    assert "stick_threshold=1e-06" in repr(top)
    assert "stick_threshold" not in repr(_ball())
    assert top._native.stick_threshold == 1e-6


@pytest.mark.parametrize("bad", [0.0, -1e-9, 1e-2, math.inf, math.nan])
def test_a_threshold_outside_its_range_is_refused_by_name(bad):
    with pytest.raises(ParameterError, match="stick_threshold"):
        _ball(stick_threshold=bad)
