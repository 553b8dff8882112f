"""Play top: the invariants and closed-form motions the model must keep.

References: Jellett's integral and the energy balance (theory: play top: any force
at the contact point keeps J; friction only dissipates), the rolling regular precession
(Omega^2 = m g s / (C D(u)), omega3 = Omega (u + alpha), psi_dot = alpha Omega), and the
frictionless top (Lz, L3, E and the horizontal velocity of G conserved).
"""

from __future__ import annotations

import numpy as np
import pytest

import kreisel

M, RHO, S = 0.02, 0.02, 0.006
C = 0.4 * M * RHO**2
A = 0.8 * C
G = 9.81


def tippe(friction, **kw):
    return kreisel.PlayTop(M, A, C, S, RHO, friction=friction, **kw)


@pytest.mark.parametrize("friction", [kreisel.Viscous(1.0), kreisel.Coulomb(0.3)])
def test_jellett_kept_and_energy_only_dissipated(friction):
    pt = tippe(friction)
    tr = kreisel.simulate(pt, pt.state(np.pi - 0.1, psi_dot=150.0), 6.0)
    assert np.abs(tr.jellett / tr.jellett[0] - 1).max() < 1e-9
    total = tr.energy + tr.dissipated
    assert np.abs(total / total[0] - 1).max() < 1e-9
    assert np.all(np.diff(tr.dissipated) >= -1e-15)
    # The energy only falls (up to the integration tolerance while rolling, where it is
    # constant).
    assert np.diff(tr.energy).max() <= 1e-9 * tr.energy[0]


def test_coulomb_run_both_slips_and_rolls():
    pt = tippe(kreisel.Coulomb(0.3))
    tr = kreisel.simulate(pt, pt.state(np.pi - 0.1, psi_dot=150.0), 1.0)
    assert {"slip", "roll"} <= set(tr.mode)
    assert any(e.name == "slip_to_roll" for e in tr.events)
    roll = tr.mode == "roll"
    # Rolling: the contact point does not slip and no energy is dissipated.
    assert tr.slip_speed[roll].max() < 1e-9
    # (up to the projection's booking of the integration's drift, within the tolerance)
    d = tr.dissipated[roll]
    assert np.ptp(d) < 1e-10 * tr.energy[0]


def test_resistances_consume_jellett():
    pt = tippe(kreisel.Viscous(1.0), rolling_resistance=1e-4, drilling_resistance=1e-4)
    tr = kreisel.simulate(pt, pt.state(np.pi - 0.1, psi_dot=150.0), 2.0)
    assert abs(tr.jellett[-1]) < abs(tr.jellett[0]) * (1 - 1e-4)


@pytest.mark.parametrize("u", [-0.5, 0.3, 0.9])
def test_rolling_regular_precession_stays(u):
    pt = tippe(kreisel.Coulomb(1.0))
    alpha, gamma = S / RHO, A / C
    d = alpha + (1 - gamma) * u
    omega = np.sqrt(M * G * S / (C * d))
    st = pt.state(np.arccos(u), phi_dot=omega, psi_dot=alpha * omega)
    tr = kreisel.simulate(pt, st, 3.0, t_eval=np.linspace(0, 3, 301))
    assert np.abs(tr.u - u).max() < 1e-9
    assert set(tr.mode) == {"roll"}
    assert tr.slip_speed[0] < 1e-12
    # Its Jellett integral is J_R(u) = J_beta N(u) / sqrt(D(u)).
    n = (alpha + u) ** 2 + gamma * (1 - u * u)
    assert tr.jellett[0] == pytest.approx(pt.J_beta * n / np.sqrt(d), rel=1e-12)


def test_viscous_tippe_top_turns_over():
    pt = tippe(kreisel.Viscous(1.0))
    tr = kreisel.simulate(
        pt, pt.state(np.pi - 0.1, psi_dot=150.0), 6.0, events=[kreisel.events.inversion(0.9)]
    )
    inv = [e.t for e in tr.events if e.name == "inversion"]
    assert inv and 1.0 < inv[0] < 4.0
    assert tr.u[-1] > 0.999


def test_frictionless_keeps_lz_l3_energy_and_horizontal_velocity():
    pt = tippe(kreisel.Frictionless())
    tr = kreisel.simulate(pt, pt.state(0.7, theta_dot=0.5, phi_dot=3.0, psi_dot=100.0, vx=0.1), 3.0)
    l3 = C * tr.omega[:, 2]
    assert np.ptp(l3) < 1e-12 * abs(l3[0])
    assert np.abs(tr.energy / tr.energy[0] - 1).max() < 1e-9
    assert np.ptp(tr.com_velocity[:, 0]) < 1e-12 and np.ptp(tr.com_velocity[:, 1]) < 1e-12
    # Lz: the space-frame angular momentum about G, vertical component.
    q = tr.quaternion
    w, x, y, z = q.T
    r20, r21, r22 = 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)
    lb = tr.omega * np.array([A, A, C])
    lz = r20 * lb[:, 0] + r21 * lb[:, 1] + r22 * lb[:, 2]
    assert np.ptp(lz) < 1e-9 * np.abs(lz).max()


@pytest.mark.parametrize("restitution", [0.0, 0.5])
def test_lift_off_flight_and_landing(restitution):
    pt = tippe(kreisel.Coulomb(0.3), restitution=restitution)
    tr = kreisel.simulate(pt, pt.state(1.2, theta_dot=-60.0, psi_dot=20.0), 0.4)
    names = [e.name for e in tr.events]
    assert names[0] == "lift_off" and "touchdown" in names
    height = tr.com[:, 2] - RHO - S * tr.u
    assert height.min() > -1e-12
    # In flight G falls freely: its vertical velocity changes at -g.
    fl = np.flatnonzero(tr.mode == "flight")
    seg = fl[: np.argmax(np.diff(fl) > 1) or len(fl)]
    dt = np.diff(tr.t[seg])
    a = np.diff(tr.com_velocity[seg, 2])[dt > 0] / dt[dt > 0]
    assert len(a) > 3 and np.allclose(a, -G, rtol=1e-6)
    # Energy never increases across impacts.
    assert np.diff(tr.energy).max() <= 1e-9 * tr.energy[0]


def test_simulate_many_equals_single_runs():
    pt = tippe(kreisel.Viscous(1.0))
    states = [pt.state(np.pi - 0.1, psi_dot=w) for w in (60.0, 150.0)]
    many = kreisel.simulate_many(pt, states, 4.0)
    for i, st in enumerate(states):
        one = kreisel.simulate(pt, st, 4.0)
        assert many.final_u[i] == one.u[-1]
        assert many.final_mode[i] == one.mode[-1]


@pytest.mark.parametrize(
    ("kw", "name"),
    [
        ({"s": -0.1}, "s"),
        ({"rho": 0.0}, "rho"),
        ({"restitution": 1.5}, "restitution"),
        ({"C": 3 * A}, "C"),
    ],
)
def test_bad_parameters_name_the_argument(kw, name):
    p = dict(m=M, A=A, C=C, s=S, rho=RHO)
    p.update(kw)
    with pytest.raises(kreisel.ParameterError, match=name):
        kreisel.PlayTop(**p)


def test_bad_friction_and_state():
    with pytest.raises(kreisel.ParameterError, match="mu"):
        kreisel.Coulomb(-0.1)
    pt = tippe(kreisel.Coulomb(0.3))
    with pytest.raises(kreisel.ParameterError, match="height"):
        pt.state(1.0, height=-0.01)
