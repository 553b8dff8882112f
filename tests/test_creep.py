"""A part alone on the floor whose friction cannot hold it at zero slip creeps: the friction
takes the direction in which sliding is consistent (the slip accelerates along the slip)
instead of the direction of a round-off slip (docs: theory, "Contact thresholds").

The checks here are independent of the creep's own computation:

- the consistency itself, from the trajectory: between consecutive rows of a creep the slip
  velocity (the contact point's velocity, from the state columns) changes along minus the
  friction force, and the friction takes energy (F . v_slip <= 0) at its full value mu N;
- convergence: the story (the time Euler's disk lies flat, its stick-slip switches) is the
  same at two tolerances a hundred times apart;
- the campaign's reproducer: a top that rolled at its cone's edge took a million steps of a
  nanosecond (the slip relaxing at a rate of mu g / |slip|) and now runs in a few thousand.
"""

from __future__ import annotations

import math

import numpy as np

import kreisel
from kreisel import bodies

# Euler's disk of benchmark T4 (steel, radius 37.5 mm, 12.5 mm thick) under point Coulomb
# friction with rolling and drilling resistance, rolling from 0.3 rad.
RADIUS, THICKNESS, DENSITY, MU = 0.0375, 0.0125, 7850.0, 0.3


def _disk():
    mass = DENSITY * math.pi * RADIUS**2 * THICKNESS
    top = bodies.disk(RADIUS, THICKNESS, mass, friction=kreisel.Coulomb(MU),
                      rolling_resistance=2e-4, drilling_resistance=1e-4)  # fmt: skip
    omega, psi_dot = bodies.disk_rolling_rates(top, 0.3)
    return top, top.state(0.3, phi_dot=omega, psi_dot=psi_dot)


def _creep_rows(traj):
    """Pairs of consecutive row indices inside creeps (between a part's creep and creep_end
    or its stick)."""
    t = np.asarray(traj.t)
    spans, start = [], None
    for e in traj.events:
        if e.name == "creep":
            start = e.t
        elif e.name in ("creep_end", "slip_to_roll", "lift_off", "flat") and start is not None:
            spans.append((start, e.t))
            start = None
    pairs = []
    for a, b in spans:
        rows = np.flatnonzero((t > a) & (t < b))
        pairs += [(i, i + 1) for i in rows[:-1] if t[i + 1] < b]
    return pairs


def test_a_creeping_contact_slides_where_its_friction_pushes_it_and_takes_energy():
    top, state = _disk()
    traj = kreisel.simulate(top, state, 30.0, rtol=1e-8, atol=1e-10, events=[kreisel.events.rest()])
    pairs = _creep_rows(traj)
    assert len(pairs) > 100, "the disk should creep between its stick phases"
    t = np.asarray(traj.t)
    part = np.asarray(traj.part_in_contact)
    slip = np.asarray(traj.part_slip_velocity)  # (rows, parts, 2)
    force = np.asarray(traj.part_friction_force)
    normal = np.asarray(traj.part_normal_force)
    angles, worst_power, over, under = [], -np.inf, -np.inf, -np.inf
    unit = lambda v: v / np.linalg.norm(v)  # noqa: E731
    for i, j in pairs:
        k = int(np.flatnonzero(part[i])[0])
        f, dv = force[i, k], slip[j, k] - slip[i, k]
        worst_power = max(worst_power, np.dot(f, slip[i, k]))
        full = MU * normal[i, k]
        over = max(over, np.linalg.norm(f) - full)
        under = max(under, full - np.linalg.norm(f))
        if np.linalg.norm(dv) < 1e-12 or t[j] == t[i]:
            # (two rows at one time: the creep's slip turned back onto its direction by an
            # impulse, across it)
            continue
        # The force turns with the contact point (up to 0.7 rad between rows here): the
        # slip's change between two rows follows the mean of the two directions.
        mean = unit(force[i, k]) + unit(force[j, k])
        angles.append(math.acos(min(1.0, -np.dot(unit(mean), unit(dv)))))
    # Consistent: the slip's change follows -F (to second order in the rows' spacing).
    assert np.median(angles) < 0.03 and max(angles) < 0.15, (np.median(angles), max(angles))
    # Dissipative; never outside the cone, and the cone's full friction but where the force
    # sticking needs is back inside it (the band that ends the creep in sticking is 1e-3
    # mu m g at the state put on the stick's constraints, where the drilling resistance's
    # torque, regularised at a small drilling rate, vanishes).
    assert worst_power <= 0.0
    assert over < 1e-9 * MU * top.m * 9.81
    assert under < 1e-2 * MU * top.m * 9.81


def test_the_disks_story_under_point_coulomb_friction_converges():
    top, state = _disk()
    runs = [kreisel.simulate(top, state, 30.0, rtol=r, atol=r * 1e-2, t_eval=np.arange(0, 30, 0.5),
                             events=[kreisel.events.rest()]) for r in (1e-8, 1e-10)]  # fmt: skip
    flat = [next(e.t for e in r.events if e.name == "flat") for r in runs]
    sticks = [sum(e.name == "slip_to_roll" for e in r.events) for r in runs]
    # (a switch located at each tolerance moves the flat time by about 1e-5 s)
    assert abs(flat[0] - flat[1]) < 5e-5, flat
    assert abs(sticks[0] - sticks[1]) <= 2, sticks
    # The stick-slip cycles of the disk's last second, each resolved in a few hundred steps
    # (integrating the law through the creep took 1.4 million steps at rtol 1e-8; the creep
    # mode, 177 899; with the slides whose explicit steps are held by stability continued by
    # Radau IIA, 62 831).
    assert runs[0].stats["steps"] < 120_000


def test_a_top_rolling_at_its_cones_edge_creeps_instead_of_taking_nanosecond_steps():
    """Floor campaign, seed 1, case 9362: once on part 3 alone the top rolls with the friction
    it needs at the cone's edge; sliding at a slip of 1e-10 m/s it took steps of a nanosecond
    and hit the row budget (4 million rows) before 0.27 s."""
    from kreisel.shapes import Sphere, Torus

    top = kreisel.PlayTop(
        0.002928442291722109, 3.399128954025949e-08, 2.82381413518301e-08,
        shape=[Sphere(0.002115118542431544, z=0.006473589730336373),
               Sphere(0.004898505496025732, z=0.003593516471931603),
               Torus(0.004339142603685871, 0.0, z=0.006704170710116627),
               Sphere(0.00410501095942836, z=0.001929542662425115)],
        friction=kreisel.CoulombContensou(0.507007367360428, 0.0002951355148274268),
        drilling_resistance=4.633874637345423e-05,
    )  # fmt: skip
    st = top.state(theta=1.5707963267948966, phi=4.822034746205629, psi=6.177170731137129,
                   theta_dot=-0.2817840687184715, psi_dot=-4.732488691990712,
                   vy=0.10785687112250891, height=0.025366141766166608)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    assert any(e.name == "creep" for e in tr.events)
    assert len(tr.t) < 100_000
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    # the property suite's bounds (tests/floor_properties.py): 1e-9 of the energy
    assert np.diff(total).max() <= 1e-9 * total[0]
    assert np.diff(np.asarray(tr.dissipated)).min() >= -1e-9 * total[0]
    # no touching part pulls (two parts landing together were once resolved before their
    # projection onto the floor, which turned a push into a pull of 0.065 N)
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * 9.81


def test_a_part_that_cannot_stick_beside_a_sliding_one_creeps_and_nothing_pulls():
    """Floor campaign, seed 1, case 8180 (stop 36): a top of four parts under
    Coulomb-Contensou friction sliding on two of them. Part 2's slip stops but its friction
    cannot hold it while part 1 still slides: it creeps, its friction taken from the joint
    system (theory: "Creep: sliding at the edge of the cone", beside other parts). With the
    creep's friction part 1 would pull on the floor, so it lifts off at that instant; the
    first build of the joint creep left it touching and pulling (0.017 N) for 0.1 s, and its
    friction fed 2.6e-6 J into the top (the dissipated energy fell)."""
    from kreisel.shapes import Sphere, Spheroid, Torus

    top = kreisel.PlayTop(
        0.01471639907891148, 9.1576189691718e-07, 1.83152379383436e-06,
        shape=[Spheroid(0.011544226479644206, 0.005631879221942614, z=-0.014573395563317215),
               Torus(0.020329251523179544, 0.003969614930162909, z=-0.01172382097234238),
               Spheroid(0.012323426919155625, 0.006412249643273147, z=0.003594139989465832),
               Sphere(0.0, z=-0.015224488873041626)],
        friction=kreisel.CoulombContensou(0.9772207651715404, 6.218089078149321e-05),
        restitution=0.95,
    )  # fmt: skip
    st = top.state(theta=math.pi / 2, psi=0.5006261843423593, theta_dot=0.061568840317207066,
                   psi_dot=-2.4682284925566376, vx=0.0032392811798377507)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    assert len(tr.t) < 5000
    events = [(e.name, e.part, e.t) for e in tr.events]
    creep = next(e for e in events if e[:2] == ("creep", "part2"))
    assert ("lift_off", "part1", creep[2]) in events
    # the floor only pushes, in every row
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * 9.81
    # E + dissipated never rises, the dissipated energy never falls
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]
    assert np.diff(np.asarray(tr.dissipated)).min() >= -1e-9 * total[0]
    # the creeping part's friction takes energy
    t = np.asarray(tr.t)
    rows = t > creep[2]
    f = np.asarray(tr.part_friction_force)[rows, 2]
    v = np.asarray(tr.part_slip_velocity)[rows, 2]
    assert (np.einsum("ij,ij->i", f, v) <= 0.0).all()


def test_a_patch_that_drills_at_the_creep_speed_keeps_its_drilling_friction():
    """Floor campaign, seed 1, case 2279: two spheres under Coulomb-Contensou friction with a
    small patch (radius 54 µm). Part 1's slip has stopped while its patch still drills at
    about the creep speed, part 0 slides beside it. The creep (theory: "Creep: sliding at the
    edge of the cone") continues the law at the creep speed, its drilling torque kept; the
    first build took the full sliding friction there (from 0.1 mu N to mu N in a step), part
    0's normal force jumped to -0.48 N, and the part was lifted off and put back 2.8e-7 s
    later. Both parts stick together instead, the floor pushing in every row."""
    from kreisel.shapes import Sphere

    top = kreisel.PlayTop(
        0.175060457917812, 4.411100621647552e-05, 1.3476890453976162e-05,
        shape=[Sphere(0.014489147254574732, z=0.028023980720891427),
               Sphere(0.01780087216471503, z=-0.003242794458155396)],
        friction=kreisel.CoulombContensou(0.7096436957903701, 5.401702403007703e-05),
        restitution=0.95,
    )  # fmt: skip
    st = top.state(theta=1.553743395481875, psi=5.729865313379527,
                   phi_dot=-0.2471095866812016, psi_dot=-79.80588801671813,
                   vy=-0.05669289959293096, height=0.0)  # fmt: skip
    tr = kreisel.simulate(top, st, 0.3, events=[kreisel.events.rest()])
    assert tr.status == "completed"
    n = np.asarray(tr.part_normal_force)
    assert n.min() >= -1e-9 * top.m * 9.81
    late = [(e.name, e.part) for e in tr.events if e.t > 0.07]
    assert set(late) == {("slip_to_roll", "part0"), ("slip_to_roll", "part1")}
    total = np.asarray(tr.energy) + np.asarray(tr.dissipated)
    assert np.diff(total).max() <= 1e-9 * total[0]
