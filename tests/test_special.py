"""The core's special functions against mpmath at 30 digits (reference values computed here)."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

import kreisel
from kreisel import special

mp.mp.dps = 30

MODULI = [0.0, 1e-10, 0.3, 0.7, 0.99, 1.0 - 1e-9, 1.0 - 1e-13]


@pytest.mark.parametrize("m", MODULI)
def test_jacobi_functions_match_mpmath(m):
    u = np.linspace(-30.0, 30.0, 61) + 0.0137
    sn, cn, dn, am = special.ellipj(u, m)
    for i, x in enumerate(u):
        ref = [float(mp.ellipfun(f, x, m=m)) for f in ("sn", "cn", "dn")]
        assert sn[i] == pytest.approx(ref[0], abs=2e-14 * max(1.0, abs(x)))
        assert cn[i] == pytest.approx(ref[1], abs=2e-14 * max(1.0, abs(x)))
        assert dn[i] == pytest.approx(ref[2], rel=1e-13, abs=2e-14 * max(1.0, abs(x)))
    # am is continuous, and equals the unwrapped angle of (cn, sn) from mpmath.
    assert np.all(np.diff(am) > 0)
    ref_am = np.unwrap(
        [float(mp.atan2(mp.ellipfun("sn", x, m=m), mp.ellipfun("cn", x, m=m))) for x in u]
    )
    ref_am += 2 * np.pi * np.round((am[30] - ref_am[30]) / (2 * np.pi))
    np.testing.assert_allclose(am, ref_am, rtol=0, atol=1e-13 * 30)


@pytest.mark.parametrize("m", [0.0, 0.5, 0.9, 1.0 - 1e-8, 1.0 - 1e-14])
def test_complete_first_kind_keeps_precision_near_one(m):
    assert special.ellipk(m) == pytest.approx(float(mp.ellipk(mp.mpf(m))), rel=1e-14)


@pytest.mark.parametrize("m", [0.1, 0.8])
def test_incomplete_first_kind(m):
    phi = np.linspace(-4.0, 4.0, 17)
    f = special.ellipf(phi, m)
    ref = [float(mp.ellipf(p, m)) for p in phi]
    np.testing.assert_allclose(f, ref, rtol=1e-14, atol=1e-15)


@pytest.mark.parametrize("n", [-50.0, -2.0, -0.3, 0.2, 0.95])
@pytest.mark.parametrize("m", [0.0, 0.4, 0.97])
def test_third_kind_every_characteristic_below_one(n, m):
    phi = np.linspace(-3.0, 3.0, 13)
    got = special.ellippi(n, phi, m)
    ref = [float(mp.ellippi(n, p, m)) for p in phi]
    np.testing.assert_allclose(got, ref, rtol=1e-13, atol=1e-15)
    assert special.ellippi(n, m) == pytest.approx(float(mp.ellippi(n, m)), rel=1e-13)


@pytest.mark.parametrize("n", [1.5, 4.0, 30.0])
def test_third_kind_above_one(n):
    m = 0.3
    # Below the pole (n sin^2 phi < 1) the integral is ordinary.
    phi = np.linspace(0.0, 0.95 * np.arcsin(1 / np.sqrt(n)), 7)
    got = special.ellippi(n, phi, m)
    ref = [float(mp.ellippi(n, p, m)) for p in phi]
    np.testing.assert_allclose(got, ref, rtol=1e-13, atol=1e-15)
    # Complete, principal value: Pi(n | m) = K(m) - Pi(m/n | m) (DLMF 19.6.5).
    pv = float(mp.ellipk(m) - mp.ellippi(m / n, m))
    assert special.ellippi(n, m) == pytest.approx(pv, rel=1e-12)


def test_cubic_roots_match_mpmath():
    rng = np.random.default_rng(3)
    for _ in range(50):
        r = np.sort(rng.normal(size=3) * 3)
        c = np.poly(r)[::-1] * rng.uniform(0.5, 2)
        got = special.cubic_roots(*c)
        roots = mp.polyroots(list(c), maxsteps=500, extraprec=60, asc=True)
        ref = sorted(float(x.real) for x in roots)
        np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-12)


def test_cubic_near_double_root_in_shifted_form():
    # (x - d)(x + d)(x - 5): in this shifted form the tiny roots keep full relative
    # precision; a sqrt(eps) loss would leave ~1e-8.
    d = 1e-9
    got = special.cubic_roots(5 * d * d, -d * d, -5.0, 1.0)
    # The roots of the product form, exact up to the rounding of d*d (1e-16 relative).
    np.testing.assert_allclose(got, [-d, d, 5.0], rtol=1e-12)


def test_bad_input_names_the_argument():
    with pytest.raises(kreisel.ParameterError, match="m = 1.5"):
        special.ellipj(0.3, 1.5)
    with pytest.raises(kreisel.ParameterError, match="n = 1.0"):
        special.ellippi(1.0, 0.3)
    with pytest.raises(kreisel.ParameterError, match="m = nan"):
        special.ellipk(float("nan"))
