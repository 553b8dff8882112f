"""Every part's contact state (``Trajectory.part_modes``, the column ``part_mode``) and the
top's ``mode`` built from them, against evidence the test computes itself from the state:
each part's gap from the geometry of its sphere (centre on the figure axis, lowest point one
radius below), its slip velocity ``v_G + omega x r`` from the centre of mass's velocity and
the body rates turned into space, the Coulomb-Contensou patch's effective radius ``rbar = 3 pi
R / 16`` (theory: several parts), free fall ``t = sqrt(2 h / g)``, and Newton's second law
for the friction forces (the floor's friction is the only horizontal force).
"""

from __future__ import annotations

import numpy as np
import pytest

import kreisel
from kreisel import Coulomb, PlayTop, bodies
from kreisel._config import from_tables, preset
from kreisel.shapes import Sphere

STATES = {"flight", "rolling", "drilling", "sliding", "flat"}


def rotations(q):
    """Body-to-space matrices of unit quaternions (w, x, y, z), written out here."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=1)[:, None]
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def sphere_evidence(tr, part):
    """(gap, lowest point, slip velocity, space omega) of a sphere part at every sample."""
    rot = rotations(tr.quaternion)
    w = np.einsum("nij,nj->ni", rot, tr.omega)
    centre = tr.com + rot[:, :, 2] * part.z
    lowest = centre - np.array([0.0, 0.0, part.radius])
    r = lowest - tr.com
    v = tr.com_velocity + np.cross(w, r)
    return lowest[:, 2], lowest, v, w


@pytest.fixture(scope="module")
def tippe():
    p = from_tables(preset("tippe"))
    return p.model, kreisel.simulate(p.model, p.state, 3.0, rtol=1e-9)


def test_the_tippe_tops_parts_touch_where_their_geometry_says(tippe):
    top, tr = tippe
    modes = tr.part_modes
    assert list(modes) == ["ball", "peg"]
    assert set(np.unique(tr.part_mode)) <= STATES
    # the peg's first touchdown, found by the engine's event and checked on the geometry
    t_peg = next(e.t for e in tr.events if e.name == "touchdown" and e.part == "peg")
    assert t_peg == pytest.approx(1.3710433, abs=1e-6)
    before, after = tr.t < t_peg - 1e-6, (tr.t > t_peg + 1e-3) & (tr.t < 2.5)
    assert before.sum() > 100 and after.sum() > 100
    assert set(modes["peg"][before]) == {"flight"}
    assert "flight" not in set(modes["ball"][before])
    assert "flight" not in set(modes["peg"][after])
    for part in top.shape:
        gap = sphere_evidence(tr, part)[0]
        touching = modes[part.name] != "flight"
        assert np.abs(gap[touching]).max() < 1e-9, part.name
        assert gap[~touching].min() > -1e-9, part.name
    # turned over onto its peg, the ball is off the floor (its gap opens: no label by rule)
    ball_gap = sphere_evidence(tr, top.shape[0])[0]
    assert ball_gap[after].min() > 1e-6 and set(modes["ball"][after]) == {"flight"}


def test_the_tippe_tops_labels_follow_its_slip_and_spin(tippe):
    """Sliding where the contact point slips faster than the patch spins (|v| > rbar |w_z|,
    the friction mostly tangential), rolling or drilling where it pivots; drilling where the
    top turns mainly about the vertical."""
    top, tr = tippe
    rbar = 3 * np.pi * top.friction.radius / 16
    seen = set()
    for part in top.shape:
        label = tr.part_modes[part.name]
        _, _, v, w = sphere_evidence(tr, part)
        slip = np.hypot(v[:, 0], v[:, 1])
        spin = rbar * np.abs(w[:, 2])
        on = label != "flight"
        slides = on & (slip > 1.5 * spin + 1e-7)
        pivots = on & (slip < spin / 1.5)
        assert slides.any() and pivots.any(), part.name
        assert set(label[slides]) == {"sliding"}, part.name
        assert "sliding" not in set(label[pivots]), part.name
        vertical = np.abs(w[:, 2]) > 1.5 * np.hypot(w[:, 0], w[:, 1])
        assert set(label[pivots & vertical]) <= {"drilling"}, part.name
        seen |= {(part.name, s) for s in set(label)}
    # the ball slides before the turn-over, the peg drills (spins) after it
    assert {("ball", "sliding"), ("peg", "drilling"), ("peg", "flight")} <= seen
    # the top's mode: slip where a part slides, roll where parts touch and none slides
    any_slide = (tr.part_mode == "sliding").any(axis=1)
    touching = (tr.part_mode != "flight").any(axis=1)
    np.testing.assert_array_equal(tr.mode == "slip", any_slide)
    np.testing.assert_array_equal(tr.mode == "roll", touching & ~any_slide)
    np.testing.assert_array_equal(tr.mode == "flight", ~touching)
    assert {"slip", "roll"} <= set(tr.mode)


def test_the_contact_points_and_friction_forces_are_the_parts_own(tippe):
    top, tr = tippe
    for i, part in enumerate(top.shape):
        on = tr.part_mode[:, i] != "flight"
        lowest = sphere_evidence(tr, part)[1]
        np.testing.assert_allclose(tr.part_contact_point[:, i], lowest, atol=1e-12)
        assert np.all(tr.part_friction_force[~on, i] == 0.0)
        # |F_t| <= mu N (the friction cone)
        f = np.hypot(*tr.part_friction_force[on, i].T)
        assert np.all(f <= 0.3 * tr.part_normal_force[on, i] * (1 + 1e-9) + 1e-15)
    # Newton: m dv_h/dt = sum of the friction forces (the floor's is the only horizontal
    # force), by differences on fine samples about a time on the ball and one on the peg
    p = from_tables(preset("tippe"))
    for t0, part in ((0.5, 0), (2.0, 1)):
        te = np.linspace(t0, t0 + 2e-4, 21)
        fine = kreisel.simulate(p.model, p.state, t0 + 1e-3, rtol=1e-11, atol=1e-14, t_eval=te)
        assert set(fine.part_mode[:, part]) - {"flight"}
        assert len(set(map(tuple, fine.part_mode))) == 1
        a = np.gradient(fine.com_velocity[:, :2], fine.t, axis=0)[2:-2]
        force = fine.part_friction_force.sum(axis=1)[2:-2]
        assert np.abs(force).max() > 1e-3
        np.testing.assert_allclose(top.m * a, force, rtol=0, atol=1e-5 * np.abs(force).max())


def test_the_part_states_export_to_xarray_and_pandas(tippe):
    _, tr = tippe
    ds = tr.to_xarray()
    assert ds["part_mode"].dims == ("t", "part")
    assert list(ds["part"].values) == ["ball", "peg"]
    assert ds["part_contact_point"].dims == ("t", "part", "space_axis")
    assert ds["part_friction_force"].dims == ("t", "part", "horizontal_axis")
    np.testing.assert_array_equal(ds["part_mode"].sel(part="peg").values, tr.part_modes["peg"])
    df = tr.to_pandas()
    assert list(df["part_mode_ball"]) == list(tr.part_modes["ball"])
    assert "part_contact_point_peg_z" in df


def test_a_disk_rolling_with_its_centre_at_rest_rolls():
    disk = bodies.disk(0.0375, 0.0125, 0.434)
    tr = kreisel.simulate(disk, bodies.disk_rolling_state(disk, 0.3), 0.5)
    rot = rotations(tr.quaternion)
    w = np.einsum("nij,nj->ni", rot, tr.omega)
    # the evidence: the rim's lowest point slips less than the patch spins (rbar |w_z|), and
    # omega, along the line from the contact to G (G nearly at rest), is mostly horizontal
    rim = disk.shape[1]
    e3 = rot[:, :, 2]
    down = np.array([0.0, 0.0, 1.0]) - e3[:, 2:3] * e3
    down /= np.linalg.norm(down, axis=1)[:, None]
    r = e3 * rim.z - rim.major * down
    assert np.abs(tr.com[:, 2] + r[:, 2]).max() < 1e-9  # the rim's lowest point touches
    v = tr.com_velocity + np.cross(w, r)
    rbar = 3 * np.pi * disk.friction.radius / 16
    assert np.all(np.hypot(v[:, 0], v[:, 1]) < 0.5 * rbar * np.abs(w[:, 2]))
    steep = np.abs(r[:, 2]) / np.hypot(r[:, 0], r[:, 1])
    np.testing.assert_allclose(np.abs(w[:, 2]) / np.hypot(w[:, 0], w[:, 1]), steep, rtol=0.05)
    assert steep.max() < 0.6
    assert set(tr.part_modes["lower_rim"]) == {"rolling"}
    assert set(tr.part_modes["upper_rim"]) == {"flight"}
    assert set(tr.mode) == {"roll"}


@pytest.mark.parametrize("friction", [None, Coulomb(0.3)], ids=["contensou", "coulomb"])
def test_a_sleeping_toy_top_drills_on_its_tip(friction):
    top = bodies.toy_top() if friction is None else bodies.toy_top(friction=friction)
    tr = kreisel.simulate(top, top.state(theta=0.0, psi_dot=400.0), 0.5)
    rot = rotations(tr.quaternion)
    w = np.einsum("nij,nj->ni", rot, tr.omega)
    assert np.all(np.abs(w[:, 2]) > 100 * np.hypot(w[:, 0], w[:, 1]) + 1.0)
    assert set(tr.part_modes["tip"]) == {"drilling"}
    assert set(tr.part_modes["shoulder"]) == set(tr.part_modes["handle"]) == {"flight"}
    assert set(tr.mode) == {"roll"}


def test_a_dropped_ball_flies_then_touches():
    h, g = 0.05, 9.81
    ball = PlayTop(0.1, 1.6e-5, 1.6e-5, shape=[Sphere(0.02, z=0.0, name="ball")],
                   friction=Coulomb(0.3))  # fmt: skip
    te = np.linspace(0, 0.3, 301)
    tr = kreisel.simulate(ball, ball.state(theta=0.0, height=h), 0.3, t_eval=te)
    t_fall = np.sqrt(2 * h / g)
    label = tr.part_modes["ball"]
    assert set(label[tr.t < t_fall - 1e-3]) == {"flight"}
    assert "flight" not in set(label[tr.t > t_fall + 1e-3])
    assert set(tr.mode[tr.t < t_fall - 1e-3]) == {"flight"}
    # at rest on the floor, sticking: not sliding (nothing turns: rolling, at rest included)
    assert set(label[tr.t > t_fall + 1e-3]) == {"rolling"}


def test_a_one_part_top_without_parts_has_no_part_modes():
    top = kreisel.LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    tr = kreisel.simulate(top, top.state(theta=0.5, psi_dot=150.0), 0.1)
    assert tr.part_modes is None


def test_the_figure_draws_one_band_per_part_and_the_titles_name_the_parts(tippe):
    import matplotlib

    matplotlib.use("Agg")
    from kreisel import animate, plot

    top, tr = tippe
    fig = plot.play_time_series(tr)
    strip = fig.axes[0]
    assert [t.get_text() for t in strip.get_yticklabels()] == ["peg", "ball"]
    legend = {t.get_text() for t in strip.get_legend().get_texts()}
    assert legend == set(np.unique(tr.part_mode))
    # the GIF titles: at a time on the ball alone and at one on the peg alone
    frames = animate.sample(tr, 5, model=top, t_start=1.0, t_stop=2.0)
    first = animate._contact_label(frames, 0)
    last = animate._contact_label(frames, 4)
    assert first == f"{frames.modes[0]}: ball {tr.part_modes['ball'][tr.t <= 1.0][-1]}"
    assert last.endswith(f"peg {tr.part_modes['peg'][tr.t <= 2.0][-1]}") and "ball" not in last


def test_the_interactive_animations_frames_name_the_parts_states(tippe):
    pytest.importorskip("plotly")
    from kreisel import animate

    top, tr = tippe
    fig = animate.figure(tr, frames=3, model=top, t_start=1.0, t_stop=2.0)
    titles = [fr.layout.title.text for fr in fig.frames]
    ball = tr.part_modes["ball"][tr.t <= 1.0][-1]
    peg = tr.part_modes["peg"][tr.t <= 2.0][-1]
    mode = tr.mode[tr.t <= 1.0][-1]
    assert titles[0].endswith(f"t = 1.000 s ({mode}: ball {ball})")
    assert titles[-1].endswith(f"peg {peg})") and "ball" not in titles[-1].split("(")[-1]
