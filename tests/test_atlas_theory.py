"""The play top's stationary-motion theory checked independently: the energy V(u) at fixed
J by a constrained minimisation of the kinetic energy, J_R by the stationary points of V,
stability by minimising V and by the sign of V'', u_m by minimising J_R, and the zones and
their boundary curves against the definitions of theory: play top, evaluated
here from scratch.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq, minimize, minimize_scalar

import kreisel
from kreisel import _atlas

M, RHO, G = 0.1, 0.02, 9.81
C = 2e-5

# (alpha, gamma) in every zone, as numbered on the theory page (play top).
TOPS = {
    1: [(0.3, 1.0), (0.6, 0.7), (1.2, 1.5)],
    2: [(0.3, 1.5), (0.6, 1.8)],
    3: [(0.03, 0.985), (0.05, 0.965)],
    4: [(0.3, 0.72), (0.1, 0.93)],
    5: [(0.3, 0.8), (0.4, 0.69)],
    6: [(0.3, 0.88), (0.5, 0.72)],
    7: [(0.3, 0.6), (0.1, 0.85)],
    8: [(0.03, 0.93), (0.05, 0.9)],
}
ALL = [(z, a, g) for z, tops in TOPS.items() for a, g in tops]


def play_top(alpha, gamma):
    return kreisel.PlayTop(m=M, A=gamma * C, C=C, s=alpha * RHO, rho=RHO, g=G)


# --- The definitions, written out here from the theory page ---------------------------


def jr_line(alpha, gamma, u, jb=1.0):
    """J_R on the real line, nan where D <= 0."""
    n = (alpha + u) ** 2 + gamma * (1 - u**2)
    d = alpha + (1 - gamma) * u
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(d > 0, jb * n / np.sqrt(np.where(d > 0, d, 1.0)), np.nan)


def v_energy(pt, j, u):
    n = (pt.alpha + u) ** 2 + pt.gamma * (1 - u**2)
    return j**2 / (2 * pt.rho**2 * pt.C * n) + pt.m * pt.g * (pt.rho + pt.s * u)


def u_m_numerical(alpha, gamma):
    """The minimum of J_R on the real line by scipy, or None if J_R is monotone there."""
    # D > 0 on (lo, hi); J_R -> infinity at a finite end where D = 0.
    k = 1 - gamma
    lo, hi = (-alpha / k, 50.0) if k > 0 else (-50.0, alpha / -k) if k < 0 else (-50, 50)
    eps = 1e-9 * (hi - lo)
    r = minimize_scalar(
        lambda u: jr_line(alpha, gamma, u),
        bounds=(lo + eps, hi - eps),
        method="bounded",
        options={"xatol": 1e-12},
    )
    if r.x < lo + 1e-6 * (hi - lo) or r.x > hi - 1e-6 * (hi - lo):
        return None
    return r.x


def zone_by_definition(alpha, gamma, um):
    if gamma >= 1 - alpha**2:
        return 1 if gamma < 1 + alpha else 2
    if gamma > 1 - alpha:
        if um > 1:
            return 3
        if um < -1:
            return 6
        return 4 if jr_line(alpha, gamma, -1.0) > jr_line(alpha, gamma, 1.0) else 5
    return 8 if um > 1 else 7


# --- V(u) and J_R --------------------------------------------------------------------


@pytest.mark.parametrize("zone,alpha,gamma", ALL[::3])
def test_V_is_the_least_energy_at_fixed_J_and_u(zone, alpha, gamma):
    """Minimise the rotational energy over every angular velocity with the given J (scipy,
    SLSQP), G at rest: the least total energy is V(u)."""
    pt = play_top(alpha, gamma)
    inertia = np.array([pt.A, pt.A, pt.C])
    rng = np.random.default_rng(zone)
    for _ in range(4):
        u = rng.uniform(-0.95, 0.95)
        j = rng.uniform(-3, 3) * pt.J_beta
        up = np.array([np.sqrt(1 - u * u), 0.0, u])  # the vertical in the body frame
        b = pt.s * np.array([0, 0, 1.0]) + pt.rho * up
        res = minimize(
            lambda w: 0.5 * w @ (inertia * w),
            x0=np.ones(3),
            jac=lambda w: inertia * w,
            constraints={"type": "eq", "fun": lambda w, b=b, j=j: (inertia * w) @ b - j},
            method="SLSQP",
            options={"ftol": 1e-16, "maxiter": 500},
        )
        e_min = res.fun + pt.m * pt.g * (pt.rho + pt.s * u)
        assert _atlas.stationary_energy(pt, u, j) == pytest.approx(e_min, rel=1e-7)


@pytest.mark.parametrize("zone,alpha,gamma", ALL)
def test_regular_precessions_are_where_V_is_stationary(zone, alpha, gamma):
    """The stationary points of V inside (-1, 1), found by scanning V' (central differences
    of V written out here) and refining with brentq, are the precessions kreisel lists, and
    J_R there is |J|."""
    pt = play_top(alpha, gamma)
    u = np.linspace(-1, 1, 40001)[1:-1]
    h = 1e-7
    for f in (0.5, 0.9, 1.3, 1.8, 2.5, 4.0, 8.0):
        j = f * pt.J_beta

        def dv(x, j=j):
            return (v_energy(pt, j, x + h) - v_energy(pt, j, x - h)) / (2 * h)

        s = np.sign(dv(u))
        idx = np.where(s[:-1] * s[1:] < 0)[0]
        roots = [brentq(dv, u[i], u[i + 1], xtol=1e-14) for i in idx]
        got = [m.u for m in pt.stationary_motions(j) if m.kind == "precession"]
        assert len(got) == len(roots), (f, roots, got)
        assert np.allclose(got, roots, atol=1e-7)
        for x in got:
            assert pt.J_R(x) == pytest.approx(j, rel=1e-12)


@pytest.mark.parametrize("zone,alpha,gamma", ALL)
def test_regular_precession_is_a_rolling_motion_of_the_top(zone, alpha, gamma):
    """The state with kreisel's precession rate and spin rolls without slip with u fixed
    under the full equations of motion; its Jellett integral is J_R(u) and its energy V(u)."""
    pt = kreisel.PlayTop(
        m=M, A=gamma * C, C=C, s=alpha * RHO, rho=RHO, friction=kreisel.Viscous(1.0)
    )
    for u in np.linspace(-0.9, 0.9, 7):
        if alpha + (1 - gamma) * u <= 0:
            with pytest.raises(kreisel.ParameterError, match="no regular precession"):
                pt.regular_precession(u)
            assert np.isnan(pt.J_R(u))
            continue
        rp = pt.regular_precession(u)
        d = alpha + (1 - gamma) * u
        assert rp.Omega == pytest.approx(np.sqrt(pt.m * pt.g * pt.s / (pt.C * d)), rel=1e-14)
        assert rp.omega3 == pytest.approx(rp.Omega * (u + alpha), rel=1e-14)
        assert rp.psi_dot == pytest.approx(alpha * rp.Omega, rel=1e-14)
        st = pt.state(theta=np.arccos(u), phi_dot=rp.Omega, psi_dot=rp.psi_dot)
        assert pt.jellett(st) == pytest.approx(rp.J, rel=1e-12)
        assert rp.J == pytest.approx(jr_line(alpha, gamma, u, pt.J_beta), rel=1e-13)
        assert pt.energy(st) == pytest.approx(v_energy(pt, rp.J, u), rel=1e-12)
        tr = kreisel.simulate(pt, st, 0.5, rtol=1e-11)
        assert np.abs(tr.u - u).max() < 1e-9
        assert tr.slip_speed.max() < 1e-9 * pt.rho * abs(rp.Omega)


def test_J_R_is_vectorised_and_nan_where_no_precession_exists():
    pt = play_top(0.3, 1.5)  # D(u) = 0.3 - 0.5 u: precessions only below u = 0.6
    u = np.array([[-1.0, 0.0], [0.59, 0.61]])
    j = pt.J_R(u)
    assert j.shape == (2, 2)
    assert np.isfinite(j[0]).all() and np.isfinite(j[1, 0]) and np.isnan(j[1, 1])
    # Outside the inclinations, an error: u = cos(theta) lies in [-1, 1].
    for u in (1.2, -1.01, np.nan):
        with pytest.raises(kreisel.ParameterError, match="^u = "):
            pt.J_R(u)
    assert isinstance(pt.J_R(0.1), float)
    assert pt.J_R(-1.0) == pytest.approx(pt.J_beta * 0.7**2 / np.sqrt(0.8), rel=1e-14)


# --- stability ------------------------------------------------------------------------


def stable_by_table(pt, m, j):
    """The table of theory: play top."""
    a, g = pt.alpha, pt.gamma
    if m.kind == "upright":
        return g < 1 + a and abs(j) > jr_line(a, g, 1.0, pt.J_beta)
    if m.kind == "hanging":
        return g <= 1 - a or abs(j) < jr_line(a, g, -1.0, pt.J_beta)
    um = u_m_numerical(a, g) if g < 1 - a**2 else None
    return g > 1 - a**2 or m.u > um


def local_minimum(pt, j, u, width=0.02):
    """Whether V has a local minimum at u on [-1, 1], by scipy's bounded minimisation from
    a bracket around u: it returns u itself, or moves away."""
    lo, hi = max(-1.0, u - width), min(1.0, u + width)
    r = minimize_scalar(
        lambda x: v_energy(pt, j, x), bounds=(lo, hi), method="bounded",
        options={"xatol": 1e-10},
    )  # fmt: skip
    return abs(r.x - u) < 0.1 * width


@pytest.mark.parametrize("zone,alpha,gamma", ALL)
def test_stable_motions_are_the_minima_of_V(zone, alpha, gamma):
    pt = play_top(alpha, gamma)
    checked = {True: 0, False: 0}
    for f in np.geomspace(0.05, 20, 61):
        for sign in (1, -1):
            j = sign * f * pt.J_beta
            motions = pt.stationary_motions(j)
            for m in motions:
                # Skip the degenerate thresholds where V'' (or V' at the ends) vanishes.
                h = 1e-5
                if m.kind == "precession":
                    curv = (
                        v_energy(pt, j, m.u + h) - 2 * v_energy(pt, j, m.u)
                        + v_energy(pt, j, m.u - h)
                    ) / h**2  # fmt: skip
                else:
                    # At the vertical E(theta) has E'' = -u V'(u).
                    side = m.u
                    curv = -(v_energy(pt, j, side) - v_energy(pt, j, side - side * h)) / h
                if abs(curv) < 1e-4 * pt.m * pt.g * pt.s:
                    continue
                assert m.stable == (curv > 0), (j, m)
                # Search no further than halfway to the next stationary point.
                gap = min([abs(o.u - m.u) for o in motions if o is not m] + [0.04])
                assert m.stable == local_minimum(pt, j, m.u, gap / 2), (j, m)
                assert m.stable == stable_by_table(pt, m, j), (j, m)
                assert m.energy == pytest.approx(v_energy(pt, j, m.u), rel=1e-13)
                checked[m.stable] += 1
    assert checked[True] > 0 and checked[False] > 0


def test_the_counts_of_precessions_per_zone():
    """theory: the atlas of play tops (the division of the alpha-gamma plane): two precessions
    (the less inclined stable) for |J| between J_Rm and min(J_R(-1), J_R(1)) in zones 4 and
    5; in zone 7 one unstable precession for every |J| > J_R(1) and two between J_Rm and
    J_R(1); in zone 8 one, unstable, for |J| > J_R(1); in type I at most one, stable."""
    for alpha, gamma in TOPS[4] + TOPS[5]:
        pt = play_top(alpha, gamma)
        um = _atlas.u_m(pt)
        lo, hi = pt.J_R(um), min(pt.J_R(-1.0), pt.J_R(1.0))
        for j in np.linspace(lo, hi, 12)[1:-1]:
            ps = [m for m in pt.stationary_motions(j) if m.kind == "precession"]
            assert len(ps) == 2
            assert ps[0].u < um < ps[1].u and not ps[0].stable and ps[1].stable
    for alpha, gamma in TOPS[7]:
        pt = play_top(alpha, gamma)
        j1 = pt.J_R(1.0)
        for j in (1.01 * j1, 2 * j1, 50 * j1):
            ps = [m for m in pt.stationary_motions(j) if m.kind == "precession"]
            assert len(ps) == 1 and not ps[0].stable
        jm = pt.J_R(_atlas.u_m(pt))
        ps = [m for m in pt.stationary_motions(0.5 * (jm + j1)) if m.kind == "precession"]
        assert [m.stable for m in ps] == [False, True]
        assert [m for m in pt.stationary_motions(0.99 * jm) if m.kind == "precession"] == []
    for alpha, gamma in TOPS[8]:
        pt = play_top(alpha, gamma)
        for j in (1.01 * pt.J_R(1.0), 10 * pt.J_R(1.0)):
            ps = [m for m in pt.stationary_motions(j) if m.kind == "precession"]
            assert len(ps) == 1 and not ps[0].stable
        below = pt.stationary_motions(0.99 * pt.J_R(1.0))
        assert [m.kind for m in below] == ["hanging", "upright"]
    for alpha, gamma in TOPS[1] + TOPS[2]:
        pt = play_top(alpha, gamma)
        for f in np.geomspace(0.1, 50, 40):
            ps = [m for m in pt.stationary_motions(f * pt.J_beta) if m.kind == "precession"]
            assert len(ps) <= 1 and all(m.stable for m in ps)


def test_vertical_spins_carry_J_and_the_hanging_one_is_missing_when_G_is_at_the_contact():
    pt = play_top(0.3, 0.8)
    j = 2.0 * pt.J_beta
    up, hang = pt.stationary_motions(j)[-1], pt.stationary_motions(j)[0]
    # A spin omega3 about the vertical has J = C omega3 rho (alpha + u).
    assert up.omega3 * pt.C * pt.rho * (pt.alpha + 1) == pytest.approx(j, rel=1e-14)
    assert hang.omega3 * pt.C * pt.rho * (pt.alpha - 1) == pytest.approx(j, rel=1e-14)
    st = pt.state(theta=0.0, psi_dot=up.omega3)
    assert pt.jellett(st) == pytest.approx(j, rel=1e-14)
    assert pt.energy(st) == pytest.approx(up.energy, rel=1e-14)
    # alpha = 1: G sits at the contact point when hanging, and no spin about it carries J.
    pt1 = play_top(1.0, 1.2)
    assert [m.kind for m in pt1.stationary_motions(j)][0] != "hanging"
    assert pt1.stationary_motions(0.0)[0].kind == "hanging"
    assert pt1.stationary_motions(0.0)[0].stable


# --- u_m, zones and their boundaries ----------------------------------------------------


@pytest.mark.parametrize("zone,alpha,gamma", ALL)
def test_u_m_minimises_J_R_on_the_real_line(zone, alpha, gamma):
    pt = play_top(alpha, gamma)
    got, ref = _atlas.u_m(pt), u_m_numerical(alpha, gamma)
    if gamma >= 1 - alpha**2:
        assert got is None and ref is None
    else:
        assert got == pytest.approx(ref, abs=1e-6)


@pytest.mark.parametrize("zone,alpha,gamma", ALL)
def test_classify_follows_the_definitions(zone, alpha, gamma):
    pt = play_top(alpha, gamma)
    c = pt.classify()
    um = u_m_numerical(alpha, gamma)
    assert c.zone == zone == zone_by_definition(alpha, gamma, um)
    assert c.type == {1: "Ia", 2: "Ib", 7: "IIb", 8: "IIb"}.get(zone, "IIa")
    assert c.fig3 == ("a" if gamma >= 1 + alpha else "b" if gamma <= 1 - alpha else "c")
    assert repr(c) == f"Classification(type={c.type!r}, zone={zone}, fig3={c.fig3!r})"


def zones_by_definition_on_grid(a, g):
    """Zones of a grid by the definitions, with u_m's side of +-1 read from the slope of
    J_R at +-1 (J_R has one minimum on the real line in type II, so u_m > 1 iff J_R falls
    at 1); nan where a defining quantity is within round-off of its threshold."""
    h = 1e-6
    slope_p = (jr_line(a, g, 1 + h) - jr_line(a, g, 1 - h)) / (2 * h)
    slope_m = (jr_line(a, g, -1 + h) - jr_line(a, g, -1 - h)) / (2 * h)
    jp, jm = jr_line(a, g, 1.0), jr_line(a, g, -1.0)
    z = np.full(a.shape, np.nan)
    type1 = g >= 1 - a**2
    z[type1 & (g < 1 + a)] = 1
    z[type1 & (g >= 1 + a)] = 2
    iia = ~type1 & (g > 1 - a)
    iib = ~type1 & (g <= 1 - a)
    z[iia & (slope_p < 0)] = 3
    z[iia & (slope_m > 0)] = 6
    mid = iia & (slope_p > 0) & (slope_m < 0)
    z[mid & (jm > jp)] = 4
    z[mid & (jm < jp)] = 5
    z[iib & (slope_p < 0)] = 8
    z[iib & (slope_p > 0)] = 7
    near = (
        (np.abs(g - (1 - a**2)) < 1e-9)
        | (np.abs(g - (1 - a)) < 1e-9)
        | (np.abs(g - (1 + a)) < 1e-9)
        | (np.abs(slope_p) < 1e-5)
        | (np.abs(slope_m) < 1e-5)
        | (np.abs(jm - jp) < 1e-9 * jp)
    )
    z[near] = np.nan
    return z


@pytest.mark.parametrize(
    "a_range,g_range,zones",
    [
        ((0.002, 1.4), (0.5, 2.6), {1, 2, 4, 5, 6, 7}),
        ((0.0005, 0.08), (0.7, 1.01), set(range(1, 9))),
    ],
    ids=["plane", "zones-3-and-8"],
)
def test_zones_on_dense_grids_match_the_definitions(a_range, g_range, zones):
    a, g = np.meshgrid(np.linspace(*a_range, 700), np.linspace(*g_range, 700))
    ref = zones_by_definition_on_grid(a, g)
    got = _atlas.zones(a, g)
    ok = ~np.isnan(ref)
    assert ok.mean() > 0.99
    wrong = ok & (got != np.nan_to_num(ref))
    assert not wrong.any(), list(zip(a[wrong][:5], g[wrong][:5], got[wrong][:5], ref[wrong][:5]))
    assert set(np.unique(got[ok])) >= zones


def test_zones_of_random_tops_match_a_numerical_u_m():
    rng = np.random.default_rng(3)
    a = np.concatenate([rng.uniform(0.001, 0.75, 300), rng.uniform(0.001, 0.072, 100)])
    g = np.concatenate([rng.uniform(0.5, 0.999, 300), rng.uniform(0.75, 0.999, 100)])
    got = _atlas.zones(a, g)
    seen = set()
    for ai, gi, zi in zip(a, g, got):
        um = u_m_numerical(ai, gi) if gi < 1 - ai**2 else None
        if um is not None and min(abs(um - 1), abs(um + 1)) < 1e-5:
            continue
        assert zi == zone_by_definition(ai, gi, um), (ai, gi)
        seen.add(int(zi))
    assert seen >= {1, 3, 4, 5, 6, 7, 8}


def test_boundary_curves_are_exact():
    """On each curve its defining equality holds (u_m = 1, u_m = -1 by scipy's minimisation
    of J_R; J_R(1) = J_R(-1) to round-off), and the zones change across it."""
    alpha = np.linspace(0.001, 0.7, 300)
    b = _atlas.zone_boundaries(alpha)
    lo, hi, um1, eq = b["u_m=1 lower"], b["u_m=1 upper"], b["u_m=-1"], b["J_R(1)=J_R(-1)"]
    lens = ~np.isnan(lo)
    assert alpha[lens].max() == pytest.approx(7 - 4 * np.sqrt(3), abs=0.003)
    for ai, gl, gh, gm, ge in zip(alpha, lo, hi, um1, eq):
        for gc in (gl, gh):
            if np.isfinite(gc):
                assert u_m_numerical(ai, gc) == pytest.approx(1.0, abs=1e-5)
        if np.isfinite(gm):
            assert u_m_numerical(ai, gm) == pytest.approx(-1.0, abs=1e-5)
            z = _atlas.zones([ai, ai], [gm - 1e-11, gm + 1e-11])
            # (At alpha = 0.001 the band of zones 4 and 5 is about 1e-6 wide.)
            assert z[0] in (4, 5) and z[1] == 6
        if np.isfinite(ge):
            assert jr_line(ai, ge, 1.0) == pytest.approx(jr_line(ai, ge, -1.0), rel=1e-12)
            assert list(_atlas.zones([ai, ai], [ge - 1e-11, ge + 1e-11])) == [4, 5]
    assert np.isfinite(um1[alpha < 0.7]).all() and np.isfinite(eq[alpha < 0.7]).all()
    for name, f in (("1+alpha", 1 + alpha), ("1-alpha", 1 - alpha), ("1-alpha^2", 1 - alpha**2)):
        assert np.array_equal(b[name], f)


# --- prediction -------------------------------------------------------------------------


def test_a_state_at_a_stable_stationary_motion_ends_there():
    pt = play_top(0.3, 0.8)
    for u in (-0.3, 0.2, 0.7):
        rp = pt.regular_precession(u)
        st = pt.state(theta=np.arccos(u), phi_dot=rp.Omega, psi_dot=rp.psi_dot)
        p = pt.predict(st)
        assert p.J == pt.jellett(st)
        if u > _atlas.u_m(pt):
            assert p.ending.kind == "precession" and p.ending.u == pytest.approx(u, abs=1e-12)
        assert all(m.stable for m in p.stable)


def test_prediction_follows_the_energy_wells():
    """Zone 5 with |J| between J_Rm and J_R(-1): the hanging spin and a precession are both
    stable, with an unstable precession between them. Below the barrier a state stays in
    its own well; above it the ending is not unique."""
    pt = play_top(0.3, 0.8)
    j = 0.5 * (pt.J_R(_atlas.u_m(pt)) + pt.J_R(-1.0))
    hang, bar, rp, _up = pt.stationary_motions(j)
    assert hang.stable and not bar.stable and rp.stable

    def state_at(u, extra):
        # The least-energy state at (J, u); theta_dot adds energy and nothing to J.
        om = j / (pt.rho * pt.C * ((pt.alpha + u) ** 2 + pt.gamma * (1 - u * u)))
        return pt.state(theta=np.arccos(u), phi_dot=om, psi_dot=pt.alpha * om, theta_dot=extra)

    for u, target in ((rp.u, rp), (-0.99, hang)):
        st = state_at(u, 0.0)
        assert pt.energy(st) < bar.energy
        end = pt.predict(st).ending
        assert end.kind == target.kind and end.u == pytest.approx(target.u, abs=1e-9)
    st = state_at(rp.u, 40.0)
    assert pt.energy(st) > bar.energy
    p = pt.predict(st)
    assert p.ending is None and len(p.stable) == 2


def test_errors_name_the_argument():
    pt = play_top(0.3, 0.8)
    with pytest.raises(kreisel.ParameterError, match="u = 1.5"):
        pt.regular_precession(1.5)
    with pytest.raises(kreisel.ParameterError, match="J = nan"):
        pt.stationary_motions(float("nan"))
    with pytest.raises(TypeError, match="PlayState"):
        pt.predict("not a state")
    flat = kreisel.PlayTop(m=M, A=C, C=C, s=0.0, rho=RHO)
    with pytest.raises(kreisel.ParameterError, match="s = 0"):
        flat.J_R(0.3)
    dropped = pt.state(theta=0.3, psi_dot=100.0, height=0.01)
    with pytest.raises(kreisel.ParameterError, match="touches the floor"):
        pt.frictionless_turning_points(dropped)
    with pytest.raises(kreisel.ParameterError, match="alpha"):
        _atlas.classify_alpha_gamma(0.0, 0.9)


# --- figures --------------------------------------------------------------------------


def test_figures_draw_with_labelled_axes():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import kreisel.plot as kp

    pt = play_top(0.3, 0.8)
    for ax in (
        kp.atlas(pt),
        kp.atlas(),
        kp.atlas(play_top(0.03, 0.985), small_alpha=True),
        kp.vertical_axis_diagram(pt),
        kp.J_R_plot(pt, J=1.5 * pt.J_beta),
        kp.J_R_plot(play_top(0.3, 1.5)),
    ):
        assert ax.get_xlabel() and ax.get_ylabel() and ax.get_title()
        ax.figure.canvas.draw()
    plt.close("all")
