"""Tops on a floor, property-based: random valid runs (``floor_properties.py``) keep what any
run on an impenetrable, energy-taking floor must keep.

- The gap formula of the checks (``z_G + z u - phi(u)``, each part's support function) is
  verified first against the geometry alone (the lowest of many points of each part's
  surface, turned by a rotation matrix written here) and then against runs whose parts are
  known to touch (kreisel's own contact flag, its one-sphere classic, the egg, the disk).
- The generator draws only valid tops and starts (checked without running anything).
- A derandomised share of random runs (``RUNS`` runs of ``T_END`` s, seed ``SEED``; the long
  campaign is ``tests/fuzz/floor_campaign.py``) runs in a worker process, one run at a time,
  with a time and a memory limit, so that a hang or a crash is reported, not fatal; no run may
  violate a property (``floor_properties.check_run``), raise anything but a refusal that says
  what to change, hang or crash. The assertion message gives a Python one-liner per failing
  run.
"""

from __future__ import annotations

import collections
import math
import os
import sys

import numpy as np
import pytest

import kreisel
from kreisel import Coulomb, CoulombContensou, PlayTop, bodies
from kreisel.shapes import Sphere, Spheroid, Torus

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "fuzz"))

import floor_campaign  # noqa: E402
import floor_properties as fp  # noqa: E402

SEED = 0
RUNS = 250
T_END = 0.2
TIMEOUT = 5.0  # s per run: a 0.2-s motion of a centimetre top needs far less


# --------------------------------------------------------------------------------------
# the gap formula
# --------------------------------------------------------------------------------------


def _surface(part, n=721):
    """Points (k, 3) of a part's surface in the body frame (centred on the axis at z)."""
    a = np.linspace(0.0, 2 * np.pi, n)
    b = np.linspace(-np.pi / 2, np.pi / 2, n // 2 + 1)
    aa, bb = np.meshgrid(a, b)
    if isinstance(part, Sphere):
        r = part.radius
        x, y, z = r * np.cos(bb) * np.cos(aa), r * np.cos(bb) * np.sin(aa), r * np.sin(bb)
    elif isinstance(part, Spheroid):
        p, q = part.equatorial, part.axial
        x, y, z = p * np.cos(bb) * np.cos(aa), p * np.cos(bb) * np.sin(aa), q * np.sin(bb)
    else:
        bb = 2 * bb  # the tube's angle, all the way round
        ring = part.major + part.minor * np.cos(bb)
        x, y, z = ring * np.cos(aa), ring * np.sin(aa), part.minor * np.sin(bb)
    return np.stack([x.ravel(), y.ravel(), z.ravel() + part.z], axis=1)


def _rotation(phi, theta, psi):
    """Rz(phi) Rx(theta) Rz(psi), written out."""

    def rz(t):
        return np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])

    rx = np.array(
        [[1, 0, 0], [0, math.cos(theta), -math.sin(theta)], [0, math.sin(theta), math.cos(theta)]]
    )
    return rz(phi) @ rx @ rz(psi)


@pytest.mark.parametrize(
    "part",
    [
        Sphere(0.01, z=-0.004),
        Sphere(0.0, z=-0.02),
        Spheroid(0.02, 0.03, z=0.005),
        Spheroid(0.03, 0.01, z=-0.01),
        Torus(0.03, 0.0, z=0.006),
        Torus(0.02, 0.008, z=-0.01),
    ],
)
def test_the_gap_formula_is_the_lowest_point_of_the_surface(part):
    """``part_gaps`` against brute force: the lowest of ~2.6e5 surface points of the part,
    turned by Euler angles (upright, tilted, lying, upside down, exactly flat) with G at a
    height of 5 cm. The sampling resolves the lowest point to ~1e-5 of the part's size."""
    rng = np.random.default_rng(7)
    pts = _surface(part)
    size = max(getattr(part, a, 0.0) for a in ("radius", "equatorial", "axial", "major")) + 1e-3
    thetas = [0.0, np.pi, np.pi / 2, 1e-3, np.pi - 1e-3, *rng.uniform(0, np.pi, 6)]
    z_g = 0.05
    us, gaps = [], []
    for th in thetas:
        r = _rotation(rng.uniform(0, 2 * np.pi), th, rng.uniform(0, 2 * np.pi))
        gaps.append(z_g + (pts @ r.T)[:, 2].min())
        us.append(r[2, 2])
    traj = type("T", (), {"u": np.array(us), "com": np.tile([0.0, 0.0, z_g], (len(us), 1))})
    formula = fp.part_gaps([part], traj)[0]
    np.testing.assert_allclose(formula, gaps, atol=2e-5 * size, rtol=0)


def _contact_gaps(top, traj):
    """The gaps of the parts in the rows kreisel has them in contact."""
    gaps = fp.part_gaps(top.shape, traj)
    contact = np.asarray(traj.part_in_contact, dtype=bool).T
    return [g[c] for g, c in zip(gaps, contact)]


@pytest.mark.parametrize(
    "name", ["classic", "ball_and_peg", "egg", "thin_disk", "thick_disk", "point_and_rim"]
)
def test_the_gap_formula_is_zero_where_a_part_touches(name):
    """Runs where a part is known to touch the floor: the tippe top on its ball (classic
    one-sphere form: ``Sphere(rho, z=-s)``), Leine & Glocker's ball and peg, the egg spun on
    its side, a thin disk on its steady rolling (sharp rim), a thick disk (two rims), and a
    top on a sharp point with a rounded rim, lying on both. Where ``part_in_contact`` says a
    part touches, its gap from the formula is 0 within 1e-9 m."""
    if name == "classic":
        top = PlayTop(0.015, 4e-6, 5e-6, s=0.003, rho=0.015)
        st = top.state(theta=0.1, psi_dot=150.0)
    elif name == "ball_and_peg":
        top = PlayTop(
            6e-3,
            8e-7,
            7e-7,
            shape=[Sphere(0.015, z=-0.003), Sphere(0.005, z=-0.016)],
            friction=CoulombContensou(0.3, 5e-4),
        )
        st = top.state(theta=np.pi - 0.1, psi_dot=180.0)
    elif name == "egg":
        top = bodies.egg()
        st = top.state(theta=np.pi / 2 - 0.05, phi_dot=40.0)
    elif name == "thin_disk":
        a, m = 0.0375, 0.1
        top = PlayTop(
            m, m * a * a / 4, m * a * a / 2, shape=[Torus(a, 0.0, 0.0)], friction=Coulomb(0.5)
        )
        om = math.sqrt(4 * 9.81 / a / math.sin(0.8))
        st = top.state(theta=0.8, phi_dot=om, psi_dot=-om * math.cos(0.8))
    elif name == "thick_disk":
        top = bodies.disk(0.0375, 0.0125, 0.434, friction=Coulomb(0.3))
        st = bodies.disk_rolling_state(top, 0.5)
    else:
        top = PlayTop(
            0.05,
            2.4e-5,
            2.0e-5,
            shape=[Sphere(0.0, z=-0.02), Torus(0.03, 0.002, z=0.0)],
            friction=Coulomb(0.4),
        )
        # lying on the point and the rim: the axis tilted until both touch
        theta = math.atan2(0.03, 0.02 - 0.002)  # close enough to let it settle onto both
        st = top.state(theta=theta + 0.05, phi_dot=5.0)
    traj = kreisel.simulate(top, st, 0.3)
    touched = _contact_gaps(top, traj)
    assert any(len(g) for g in touched), "no part ever touched"
    for part, g in zip(top.part_names, touched):
        if len(g):
            assert np.abs(g).max() <= 1e-9, (part, np.abs(g).max())
    # and no part is ever below the floor
    assert fp.part_gaps(top.shape, traj).min() >= -1e-9


# --------------------------------------------------------------------------------------
# the generator
# --------------------------------------------------------------------------------------


def test_the_random_cases_are_valid_and_varied():
    """200 drawn cases (nothing run): 1 to 4 parts; 0 < C <= 2 A; G inside the parts' hull
    (every orientation puts G on or above the floor); an explicit start on or above the
    floor; and
    among them every kind of part, sharp points and rims, the classic form, every friction
    law, starts exactly upright and upside down, drops and explicit states."""
    seen = collections.Counter()
    for i in range(200):
        case = fp.random_floor_case(np.random.default_rng([SEED, i]))
        top, st, spec = case["top"], case["state"], case["spec"]
        assert 1 <= len(top.shape) <= 4
        assert 0 < top.C <= 2 * top.A * (1 + 1e-12) and top.A > 0
        assert 1e-3 <= top.m <= 3.0
        us = np.linspace(-1, 1, 201)
        assert min(fp.resting_height(top.shape, u) for u in us) >= 0.0
        if spec["state"]["form"] == "explicit":  # (kreisel places the others: checked in runs)
            u0 = float(fp.u_of_quaternion(st.quaternion))
            gap0 = min(float(st.com[2] + p.z * u0 - fp.support(p, u0)) for p in top.shape)
            assert gap0 >= -1e-12, (i, gap0)
        seen.update(type(p).__name__ for p in top.shape)
        seen.update({"sharp point" for p in top.shape if isinstance(p, Sphere) and p.radius == 0})
        seen.update({"sharp rim" for p in top.shape if isinstance(p, Torus) and p.minor == 0})
        seen[spec["top"]["form"]] += 1
        seen[spec["top"]["friction"][0]] += 1
        seen[spec["state"]["form"]] += 1
        if spec["state"]["form"] == "euler":
            seen.update({f"theta={spec['state']['theta']}"} & {"theta=0.0", f"theta={math.pi}"})
            seen.update({"drop"} if spec["state"]["height"] else set())
    for k in (
        "Sphere",
        "Spheroid",
        "Torus",
        "sharp point",
        "sharp rim",
        "classic",
        "parts",
        "Frictionless",
        "Viscous",
        "Coulomb",
        "CoulombContensou",
        "euler",
        "explicit",
        "theta=0.0",
        f"theta={math.pi}",
        "drop",
    ):
        assert seen[k] > 0, (k, seen)


# --------------------------------------------------------------------------------------
# the derandomised share
# --------------------------------------------------------------------------------------


def test_random_floor_runs_keep_their_properties():
    """``RUNS`` random valid runs (seed ``SEED``) of ``T_END`` s, ending early at rest: each
    is ok (every property of ``floor_properties.check_run``) or refused with a message that
    says what to change. A violation, any other exception, a hang (no answer within
    ``TIMEOUT`` s) or a crash fails, with each failing run's reproducer."""
    results = floor_campaign.run(SEED, list(range(RUNS)), t_end=T_END, timeout=TIMEOUT)
    assert len(results) == RUNS
    bad = {i: r for i, r in results.items() if r["verdict"] in floor_campaign.BAD}
    if bad:
        by_kind = collections.Counter(k for r in bad.values() for k in floor_campaign.kinds(r))
        lines = [f"{len(bad)} of {RUNS} runs fail: {dict(by_kind)}"]
        for i, r in sorted(bad.items()):
            spec = (r.get("spec") or {}).get("spec")
            lines.append(f"- case {i}: " + "; ".join(d[:300] for d in r["details"][:3]))
            lines.append("  " + (fp.reproducer(spec, T_END) if spec else "(not drawn)"))
        raise AssertionError("\n".join(lines))


def test_sin_theta_of_a_quaternion_is_that_of_its_euler_angles_and_zero_lying_flat():
    """``sin_theta_of_quaternion`` against ``sin(theta)`` of the Euler angles it was built
    from, and exactly 0 for a top lying flat on either face (where ``sqrt(1 - u^2)`` of a
    rounded ``u`` is 1.5e-8 per ulp)."""
    rng = np.random.default_rng(3)
    for _ in range(50):
        phi, theta, psi = rng.uniform(0, 2 * np.pi), rng.uniform(0, np.pi), rng.uniform(0, 7)
        q = fp._quat_zxz(phi, theta, psi)
        assert abs(fp.sin_theta_of_quaternion(q) - math.sin(theta)) < 1e-15
    flat = np.array([[0.0, 0.77165178, -0.63604523, 0.0], [0.6, 0.0, 0.0, 0.8]])
    assert np.all(fp.sin_theta_of_quaternion(flat) == 0.0)
