"""The defects a fuzz campaign found, each as its reproducer, exactly as reported.

Each call must end in a finite result, checked against an independent computation, or in a
:class:`kreisel.ParameterError` that names the argument; never a crash, a panic or a NaN. The
property-based campaign that keeps them fixed is in ``tests/fuzz``.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import mpmath
import numpy as np
import pytest

import kreisel
from kreisel import special
from kreisel._cli import main as cli_main

# --------------------------------------------------------------------------------------
# 1. the segfault: an elliptic integral with m > 1 and a huge amplitude
# --------------------------------------------------------------------------------------


def test_ellippi_with_m_above_one_and_huge_phi_is_an_error_not_a_segfault():
    # In a child process: before the fix this killed the interpreter (SIGSEGV, unbounded
    # recursion in Carlson's R_J with a negative argument).
    code = (
        "import kreisel\n"
        "from kreisel import special\n"
        "try:\n"
        "    special.ellippi(1.5, 1e17, 1.5)\n"
        "except kreisel.ParameterError as e:\n"
        "    print(e)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("phi = 1e+17 is not allowed")
    assert "asin(1/sqrt(m))" in proc.stdout


@pytest.mark.parametrize("phi", [1e17, -1e17, 3.0, 1e300])
def test_every_incomplete_integral_with_m_above_one_beyond_its_real_range_names_phi(phi):
    for call in (
        lambda: special.ellippi(1.5, phi, 1.5),
        lambda: special.ellippi(0.5, phi, 2.0),
        lambda: special.ellipf(phi, 1.5),
    ):
        with pytest.raises(kreisel.ParameterError, match=r"^phi = "):
            call()


@pytest.mark.parametrize("phi", [1e17, -3e16, 1e300])
def test_huge_amplitudes_give_the_integrals_of_so_many_periods(phi):
    # mpmath reduces phi by pi at 400 digits: an independent computation.
    with mpmath.workdps(400):
        big = mpmath.mpf(phi)
        f_ref = float(mpmath.ellipf(big, mpmath.mpf("0.5")))
        pi_ref = float(mpmath.ellippi(mpmath.mpf("0.5"), big, mpmath.mpf("0.5")))
    assert special.ellipf(phi, 0.5) == pytest.approx(f_ref, rel=1e-14)
    assert special.ellippi(0.5, phi, 0.5) == pytest.approx(pi_ref, rel=1e-14)
    # sn, cn, dn have the period 4K(m), irrational: beyond 2^53 K(m) a double u carries no
    # digit of its place in the period, so the value would be noise: an error naming u.
    with pytest.raises(kreisel.ParameterError, match=r"^u = .*2\^53 K\(m\)"):
        special.ellipj(phi, 0.5)


def test_jacobi_functions_of_large_arguments_agree_with_mpmath_up_to_the_limit():
    """Inside 2^53 K(m) the reduction by the half period is exact enough: the functions match
    mpmath's (at 60 digits) to the digits the argument's place keeps; at the limit itself they
    are still Jacobi functions (sn^2 + cn^2 = 1, dn^2 + m sn^2 = 1)."""
    m = 0.5
    k = float(mpmath.ellipk(m))
    # (at 0.9 * 2^53 K the tolerance below would exceed 1 and test nothing: up to 1e13)
    for u in (1e6, 1e10, 1e13):
        sn, cn, dn, _ = special.ellipj(u, m)
        with mpmath.workdps(60):
            ref = [float(f(mpmath.mpf(u), m)) for f in (mpmath.ellipfun("sn"),
                   mpmath.ellipfun("cn"), mpmath.ellipfun("dn"))]  # fmt: skip
        # u's last bit is u * 2^-53 of the period's length 4K: that much phase is unknown
        tol = max(1e-12, 8 * u * 2.0**-52 / k)
        for got, want in zip((sn, cn, dn), ref):
            assert abs(got - want) <= tol, (u, got, want, tol)
    sn, cn, dn, _ = special.ellipj(0.9 * 2.0**53 * k, m)
    assert sn * sn + cn * cn == pytest.approx(1.0, abs=1e-15)
    assert dn * dn + m * sn * sn == pytest.approx(1.0, abs=1e-15)


def test_the_complete_integrals_reject_m_above_one_and_nan():
    for call, name in (
        (lambda: special.ellipk(1.5), "m"),
        (lambda: special.ellippi(0.5, 1.5), "m"),
        (lambda: special.ellippi(1.0, 0.5), "n"),
        (lambda: special.ellippi(0.5, 1.0, 1.5), "phi"),
        (lambda: special.ellipk(math.nan), "m"),
        (lambda: special.ellippi(math.nan, 0.5), "n"),
    ):
        with pytest.raises(kreisel.ParameterError, match=rf"^{name} = "):
            call()


# --------------------------------------------------------------------------------------
# 4. and 10. cubic roots: no panic, no inf root
# --------------------------------------------------------------------------------------


def test_cubic_with_huge_coefficients_has_its_scaled_root():
    # 1e300 + 4.9 x + 1e300 x^2 + 4.9 x^3 = (x^2 + 1)(4.9 x + 1e300): one real root,
    # -1e300/4.9. Before the fix: PanicException (Option::unwrap() on None).
    roots = special.cubic_roots(1e300, 4.9, 1e300, 4.9)
    assert roots == pytest.approx((-1e300 / 4.9,), rel=1e-15)


@pytest.mark.parametrize("k", [-340, -300, -100, 0, 100, 300, 340])
def test_cubic_roots_scale_with_their_polynomial(k):
    # (x - 1)(x + 2)(x - 3.5) with x scaled by 2^k: the coefficients span 2^(3k).
    s = 2.0**k
    r = np.array([-2.0, 1.0, 3.5]) * s
    c = [-r[0] * r[1] * r[2], r[0] * r[1] + r[0] * r[2] + r[1] * r[2], -r.sum(), 1.0]
    np.testing.assert_allclose(special.cubic_roots(*c), r, rtol=1e-14)


def test_cubic_roots_never_inf():
    # A root beyond the range of floats is an error naming the leading coefficient.
    with pytest.raises(kreisel.ParameterError, match=r"^c3 = 5e-324 .*beyond the range"):
        special.cubic_roots(1.0, 1.0, 1e300, 5e-324)
    with pytest.raises(kreisel.ParameterError, match=r"^c0 = inf"):
        special.cubic_roots(math.inf, 1.0, 1.0, 1.0)
    with pytest.raises(kreisel.ParameterError, match="zero polynomial"):
        special.cubic_roots(0.0, 0.0, 0.0, 0.0)
    # Tiny leading coefficient, representable roots: x^3 1e-300 + x^2 1e-300 + x + 1e300.
    (root,) = special.cubic_roots(1e300, 1.0, 1e-300, 1e-300)
    assert root == pytest.approx(-1e200, rel=1e-14)


# --------------------------------------------------------------------------------------
# 7. quaternions of any finite size are normalised
# --------------------------------------------------------------------------------------

H = 1.0 / math.sqrt(2.0)


def _tops():
    return [
        kreisel.HeavyTop(1.0, 1.2, 1.5, 1.0, [0.0, 0.05, 0.1]),
        kreisel.LagrangeTop(1.0, 0.5, 1.0, 0.1),
        kreisel.PlayTop(0.02, 5e-6, 7e-6, 0.001, 0.004),
    ]


@pytest.mark.parametrize("top", _tops(), ids=["heavy", "lagrange", "play"])
@pytest.mark.parametrize(
    ("q", "unit"),
    [
        ([1e300, 1e300, 0.0, 0.0], [H, H, 0.0, 0.0]),
        ([1e-300, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]),
        ([0.0, 0.0, -5e-324, 0.0], [0.0, 0.0, -1.0, 0.0]),
        ([3e-170, 0.0, -4e-170, 0.0], [0.6, 0.0, -0.8, 0.0]),
    ],
)
def test_state_from_quaternion_normalises_with_scaling(top, q, unit):
    st = top.state_from_quaternion(q, [0.0, 0.0, 1.0])
    np.testing.assert_allclose(st.quaternion, unit, rtol=0, atol=2e-16)


@pytest.mark.parametrize("top", _tops(), ids=["heavy", "lagrange", "play"])
def test_zero_quaternion_is_an_error_naming_q(top):
    with pytest.raises(kreisel.ParameterError, match=r"^q = "):
        top.state_from_quaternion([0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0])


# --------------------------------------------------------------------------------------
# 8. mean precession rate of motions through (or next to) the vertical
# --------------------------------------------------------------------------------------


def _mean_rate_reference(ref, p, st, dps=60):
    """Mean phidot over a nutation period by mpmath quadrature in the phase s of
    u = u1 + (u2 - u1) sin^2 s, split geometrically towards the turning points, where a
    passage close to the vertical makes phidot a narrow peak."""
    mo = ref.MpMotion(p, st, dps=dps)
    with mpmath.workdps(dps):
        half = mpmath.pi / 2
        eps = [mpmath.mpf(10) ** -k for k in range(1, 40)]
        pts = sorted(
            {mpmath.mpf(0), half, mpmath.pi}
            | {e for e in eps}
            | {half - e for e in eps}
            | {half + e for e in eps}
            | {mpmath.pi - e for e in eps}
        )
        period = mpmath.quad(mo._dt, pts)
        dphi = mpmath.quad(lambda x: mo._rates(x)[1] * mo._rates(x)[2], pts)
    return float(dphi / period)


@pytest.mark.parametrize("l_com", [0.0, 0.2, -0.2])
@pytest.mark.parametrize("psi_dot", [1e-3, 1e-8, 1e-14])
def test_mean_precession_rate_near_the_vertical_matches_quadrature(ref, l_com, psi_dot):
    p = ref.Params(I1=0.509, I3=0.86, m=4.1, l=l_com, g=9.12)
    top = kreisel.LagrangeTop(**p.kwargs())
    st = top.state(1.787, theta_dot=-28.27, psi_dot=psi_dot)
    got = top.mean_precession_rate(st)
    want = _mean_rate_reference(ref, p, ref.Start(1.787, -28.27, 0.0, psi_dot))
    # 28.27 rad/s is the scale of the rates: round-off of the elliptic integrals.
    assert got == pytest.approx(want, rel=1e-9, abs=1e-12 * 28.27)


@pytest.mark.parametrize("l_com", [0.0, 0.2])
@pytest.mark.parametrize("psi_dot", [1e-263, 1e-20, -1e-263])
def test_mean_precession_rate_with_a_tiny_spin_is_finite(l_com, psi_dot):
    # The axis passes within ~psi_dot rad of both verticals, where phi swings by pi, once
    # each way: the mean rate tends to 0 (about 0.03 psi_dot here) as psi_dot -> 0, as the
    # quadrature above shows. Before the fix: inf (and NaN with l != 0).
    top = kreisel.LagrangeTop(0.509, 0.86, 4.1, l_com, 9.12)
    a = top.analyse(top.state(1.787, theta_dot=-28.27, psi_dot=psi_dot))
    assert math.isfinite(a.mean_precession_rate) and abs(a.mean_precession_rate) < 1e-12
    assert a.kind == "through_vertical"
    traj = top.exact(top.state(1.787, theta_dot=-28.27, psi_dot=psi_dot), np.linspace(0, 1, 201))
    for k in ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot"):
        assert np.all(np.isfinite(traj[k])), k


def test_mean_precession_rate_of_the_reported_state_is_finite():
    top = kreisel.LagrangeTop(0.509, 0.86, 4.1, 0.0, 9.12)
    rate = top.mean_precession_rate(top.state(1.787, theta_dot=-28.27, psi_dot=1e-263))
    assert rate == pytest.approx(0.0, abs=1e-12)


def test_exact_solution_next_to_the_vertical_follows_the_rigid_body(ref):
    # The axis passes 7e-9 rad from the vertical: the elliptic integrals of the third kind
    # with n -> 1 and n -> -inf. Compared on the figure axis (continuous through the
    # passage, unlike phi) with an integration of the rigid-body equations.
    p = ref.Params(I1=0.509, I3=0.86, m=4.1, l=0.2, g=9.12)
    st = ref.Start(1.787, -28.27, 0.0, 1e-7)
    top = kreisel.LagrangeTop(**p.kwargs())
    t = np.linspace(0.0, 0.5, 101)
    traj = top.exact(top.state(1.787, theta_dot=-28.27, psi_dot=1e-7), t)
    mats = ref.integrate_rigid_body(p, st, t)
    axis_ref = mats[:, :, 2]
    th, ph = traj.theta, traj.phi
    axis = np.stack([np.sin(th) * np.sin(ph), -np.sin(th) * np.cos(ph), np.cos(th)], axis=1)
    np.testing.assert_allclose(axis, axis_ref, rtol=0, atol=1e-9)


# --------------------------------------------------------------------------------------
# 9. subnormal and too small parameters
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: kreisel.LagrangeTop(0.509, 0.86, 4.1, 5e-324, 9.12), "l"),
        (lambda: kreisel.LagrangeTop(1e-320, 1e-320, 1.0, 0.0), "I1"),
        (lambda: kreisel.PlayTop(0.02, 5e-6, 5e-324, 0.001, 0.004), "C"),
        (lambda: kreisel.PlayTop(0.02, 5e-6, 7e-6, 0.001, 1e-320), "rho"),
        (lambda: kreisel.HeavyTop(1.0, 1.0, 0.5, 1e-300, [0.0, 0.0, 0.1]), "m"),
        (lambda: kreisel.LagrangeTop(1.0, 0.5, 1.0, 0.1, g=1e-200), "g"),
    ],
)
def test_subnormal_and_tiny_parameters_are_rejected_with_the_range(make, name):
    with pytest.raises(kreisel.ParameterError, match=rf"^{name} = .*\[1e-100, 1e\+100\]"):
        make()


def test_exact_solution_with_the_smallest_l_is_the_free_top():
    # l = 1e-100 is allowed: m g l / I1 is then far below the other coefficients of the
    # gyro function, the limit of a free top (l = 0). Before: NaN phi for tiny l.
    t = np.linspace(0.0, 3.0, 31)
    tiny = kreisel.LagrangeTop(0.509, 0.86, 4.1, 1e-100, 9.12)
    free = kreisel.LagrangeTop(0.509, 0.86, 4.1, 0.0, 9.12)
    st = free.state(1.0, theta_dot=1.0, psi_dot=3.0)
    a, b = tiny.exact(st, t), free.exact(st, t)
    for k in ("theta", "phi", "psi"):
        np.testing.assert_allclose(a[k], b[k], rtol=1e-13, atol=1e-13)


def test_kovalevskaya_integral_with_a_tiny_centre_of_mass_is_finite():
    from kreisel._heavy import rigid_state

    h = kreisel.HeavyTop(2.0, 2.0, 1.0, 1.0, [1e-200, 0.0, 0.0])
    st = h.state(1.0, theta_dot=1.0, psi_dot=3.0)
    inv = h.invariants(st)
    # K = (w1^2 - w2^2 - nu G1)^2 + (2 w1 w2 - nu G2)^2 with nu = m g |c| / I3 ~ 1e-199:
    # the torque-free value (w1^2 + w2^2)^2
    w1, w2, _ = rigid_state(st).omega
    assert inv["kovalevskaya"] == pytest.approx((w1 * w1 + w2 * w2) ** 2, rel=1e-14)


# --------------------------------------------------------------------------------------
# 10. NaN in, NaN out: errors instead
# --------------------------------------------------------------------------------------


def test_J_R_outside_the_inclinations_or_nan_names_u():
    pt = kreisel.PlayTop(0.02, 5e-6, 7e-6, 0.001, 0.004)
    for u in (2.0, -1.5, math.nan, [0.3, math.nan]):
        with pytest.raises(kreisel.ParameterError, match=r"^u = "):
            pt.J_R(u)
    # Inside [-1, 1]: J_beta N(u)/sqrt(D(u)) from the parameters (theory: play top),
    # nan where D(u) = alpha + (1 - gamma) u <= 0 (no regular precession; documented).
    alpha, gamma = 0.001 / 0.004, 5e-6 / 7e-6
    jb = 0.004 * math.sqrt(7e-6 * 0.02 * 9.81 * 0.001)
    assert math.isnan(pt.J_R(-1.0))
    for u in (-0.5, 0.3, 1.0):
        n = (alpha + u) ** 2 + gamma * (1 - u * u)
        assert pt.J_R(u) == pytest.approx(jb * n / math.sqrt(alpha + (1 - gamma) * u), rel=1e-14)


def test_effective_potential_and_ellipj_reject_nan_and_inf():
    top = kreisel.LagrangeTop(1.0, 0.5, 1.0, 0.1)
    with pytest.raises(kreisel.ParameterError, match=r"^theta = nan"):
        top.effective_potential(math.nan, 0.1, 0.2)
    with pytest.raises(kreisel.ParameterError, match=r"^u = inf"):
        special.ellipj(math.inf, 0.5)


def test_huge_inputs_are_errors_naming_the_parameter_not_inf_energies():
    with pytest.raises(kreisel.ParameterError, match=r"^I1 = 1e\+300"):
        kreisel.LagrangeTop(1e300, 1e300, 1.0, 0.1)
    top = kreisel.LagrangeTop(1e100, 1e100, 1.0, 0.1)
    with pytest.raises(kreisel.ParameterError, match=r"^psi_dot = 1e\+300"):
        top.state(1.0, psi_dot=1e300)
    with pytest.raises(kreisel.ParameterError, match=r"^M3 = 1e\+300"):
        top.effective_potential(1.0, 0.0, 1e300)
    # The largest allowed rates and moments: finite energies (1/2 I w^2 = 1e300 J here).
    st = top.state(1.0, theta_dot=1e100, psi_dot=1e100)
    inv = top.invariants(st)
    assert all(math.isfinite(x) for x in (inv.E, inv.Mz, inv.M3))
    assert inv.E == pytest.approx(0.5e100 * 1e200 + 0.5e100 * 1e200, rel=1e-12)


# --------------------------------------------------------------------------------------
# 11. and 12. the command line
# --------------------------------------------------------------------------------------

LAGRANGE = '[top]\nkind = "lagrange"\nI1 = 1.0\nI3 = 0.5\nm = 1.0\nl = 0.1\n'
PLAY = '[top]\nkind = "play"\nm = 0.02\nA = 5e-6\nC = 7e-6\ns = 0.001\n'


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ("top = 3\n", "[top]"),
        ('[[top]]\nkind = "lagrange"\n', "[top]"),
        (PLAY + "rho = 1e-320\n[state]\ntheta = 0.1\n", "rho = 1e-320"),
        ("x = " + "[" * 5000 + "]" * 5000 + "\n", "field x"),
        ("x = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n", "field x"),
        (LAGRANGE + "[state]\ntheta = [" + "[" * 3000 + "]" * 3000 + "]\n", "line 8"),
    ],
    ids=[
        "top-int",
        "array-of-tables",
        "subnormal-rho",
        "nested-arrays",
        "nested-tables",
        "nested-field",
    ],  # fmt: skip
)
@pytest.mark.parametrize("command", ["run", "sweep"])
def test_malformed_files_end_with_exit_2_and_one_line(tmp_path, capsys, text, field, command):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    args = [command, str(path), "--out" if command == "run" else "--store", str(tmp_path / "o")]
    code = cli_main([*args, "--no-figures" if command == "run" else "--no-figure"])
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert field in lines[0], err


@pytest.mark.parametrize(("theta", "kind"), [(0.0, "sleeping"), (math.pi, "hanging")])
def test_sleeping_and_hanging_tops_are_analysed_not_refused(tmp_path, capsys, theta, kind):
    path = tmp_path / "top.toml"
    path.write_text(LAGRANGE + f"[state]\ntheta = {theta!r}\npsi_dot = 5.0\n"
                    "[simulation]\nsamples = 50\n")  # fmt: skip
    code = cli_main(["run", str(path), "--out", str(tmp_path / "o"), "--no-figures"])
    out = capsys.readouterr()
    assert code == 0, out.err
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    a = summary["analysis"]
    assert a["motion"] == kind
    assert a["steady_precession_rates"] is None  # it needs 0 < theta < pi
    # The sleeping threshold sqrt(4 I1 m g l)/I3 is what applies at the vertical.
    assert a["sleeping_threshold"] == pytest.approx(math.sqrt(4 * 1.0 * 1.0 * 9.81 * 0.1) / 0.5)


# --------------------------------------------------------------------------------------
# the bodies' helpers and numbers too large for a float: an error naming the argument
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, names",
    [
        (lambda b: b.egg_rising_thresholds(1e-100, 0.03), ("axial = 0.03", "equatorial = 1e-100")),
        (lambda b: b.egg_rising_thresholds(0.0225, 1e100), ("axial = 1e+100",)),
        (lambda b: b.egg_settled_inclination(50, 0.0225, 1e100), ("axial = 1e+100",)),
        (lambda b: b.egg_rising_thresholds(0.0225, 0.03, 1e308), ("g = 1e+308",)),
        (
            lambda b: b.disk(1e100, 1e100, 1e100),
            ("radius = 1e+100", "thickness = 1e+100", "mass = 1e+100"),
        ),
        (
            lambda b: b.disk_rolling_rates(b.disk(0.01213, 0.00175, 0.00567), 1e-300),
            ("alpha = 1e-300",),
        ),  # fmt: skip
        (
            lambda b: b.disk_rolling_state(b.disk(0.01213, 0.00175, 0.00567), 1e-300),
            ("alpha = 1e-300",),
        ),  # fmt: skip
    ],
)
def test_the_bodies_helpers_name_the_argument_that_leaves_the_floats(call, names):
    """Each was a ZeroDivisionError, an OverflowError, a silent inf, or an error blaming a
    derived quantity (A, phi_dot) the caller never gave."""
    from kreisel import bodies

    with pytest.raises(kreisel.ParameterError) as e:
        call(bodies)
    message = str(e.value)
    for name in names:
        assert name in message
    assert not message.startswith(("A =", "phi_dot ="))


def test_the_egg_thresholds_hold_over_the_range_they_accept():
    """Where they are allowed, the thresholds scale as sqrt(g / a) at a fixed shape (the mass
    and the size drop out of 5 g / a): the tiniest and largest eggs give the default egg's
    numbers times that factor, finite and not zero."""
    from kreisel import bodies

    base = bodies.egg_rising_thresholds(0.0225, 0.03, 9.81)
    for a, g in ((0.0225e-90, 9.81e90), (0.0225e90, 9.81e-90), (0.0225e-98, 9.81e-98)):
        scaled = bodies.egg_rising_thresholds(a, a * 0.03 / 0.0225, g)
        factor = math.sqrt((g / a) / (9.81 / 0.0225))
        for x, y in zip(scaled, base):
            assert math.isfinite(x) and x > 0
            assert x == pytest.approx(y * factor, rel=1e-12)


@pytest.mark.parametrize(
    "make, name",
    [
        (lambda v: kreisel.LagrangeTop(v, 1, 1, 0.1), "I1"),
        (lambda v: kreisel.LagrangeTop(1, v, 1, 0.1), "I3"),
        (lambda v: __import__("kreisel.shapes").shapes.Sphere(v, 0), "radius"),
        (lambda v: kreisel.PlayTop(v, 1e-5, 1e-5, s=0.01, rho=0.02), "m"),
    ],
)
@pytest.mark.parametrize(
    "value", [2**1100, -(2**1100), 10**5000], ids=["2^1100", "-2^1100", "10^5000"]
)
def test_an_integer_too_large_for_a_float_is_an_error_naming_the_argument(make, name, value):
    """Not a bare OverflowError, and not Python's advice to call sys.set_int_max_str_digits()
    (a 5000-digit integer cannot be printed)."""
    with pytest.raises(kreisel.ParameterError) as e:
        make(value)
    message = str(e.value)
    assert f"{name} = <an integer of about" in message
    assert "set_int_max_str_digits" not in message and "1.8e+308" in message
