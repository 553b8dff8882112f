"""Defects of the simulation stack that the fuzz campaign found, each as its
minimal reproducer, fixed by the one-stack rewrite. Each runs in a child process with a time
limit: before the fix some hung, some panicked.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

HEAD = "import math, kreisel\nfrom kreisel import events\n"


def outcome(code: str, timeout: float = 20.0) -> str:
    """'ok', 'error: <type>: <message>' (a KreiselError naming the argument is fine), 'hang'
    or 'crash'; the child prints what happened."""
    body = textwrap.indent(textwrap.dedent(code), "    ")
    script = (
        HEAD + "try:\n" + body + "\n    print('ok')\n"
        "except kreisel.KreiselError as e:\n    print('error: KreiselError:', e)\n"
        "except BaseException as e:\n    print('error:', type(e).__name__ + ':', e)\n"
    )
    try:
        proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                              timeout=timeout)  # fmt: skip
    except subprocess.TimeoutExpired:
        return "hang"
    if proc.returncode != 0:
        return f"crash {proc.returncode}"
    return proc.stdout.strip().splitlines()[-1] if proc.stdout.strip() else "no output"


def clean(result: str) -> bool:
    return result == "ok" or result.startswith("error: KreiselError:")


def test_a_coulomb_drop_with_restitution_zero_finishes():
    """A dropped Coulomb top with restitution 0 never gets past
    touchdown (restitution 0.5 or Viscous finish in 0.1 s)."""
    r = outcome("""
        top = kreisel.PlayTop(0.021293769673452253, 5.188850311006383e-08, 7.854825969180615e-08,
            0.0013372848346967627, 0.0037032559063929988,
            friction=kreisel.Coulomb(0.7108188378633866), restitution=0.0)
        st = top.state(3.041592653589793, theta_dot=2.6405147716224566,
            psi_dot=-203.3919680591968, height=0.00825595785269577)
        kreisel.simulate(top, st, 0.05, rtol=1e-10, atol=1e-12)
    """)
    assert clean(r), r


@pytest.mark.parametrize("method", ["rk4", "splitting", "verlet", "midpoint", "gauss4"])
def test_fixed_steps_of_1e300_are_refused_not_run(method):
    """A fixed-step run with dt = 1e-300 never returns; the step count
    t_end/dt must be bounded with a clear error."""
    r = outcome(f"""
        top = kreisel.LagrangeTop(1.0, 0.5, 1.0, 0.1)
        kreisel.simulate(top, top.state(1.0, psi_dot=5.0), 0.01, method={method!r}, dt=1e-300)
    """)
    assert clean(r), r


@pytest.mark.parametrize("event", ["rest()", "inversion(0.9)"])
def test_play_top_events_on_a_pivot_top_are_errors_not_panics(event):
    """(Found again by the campaign on heavy tops.) A play-top event on a
    top on a pivot raises PanicException ('built-in events only ... unknown event kind')."""
    r = outcome(f"""
        top = kreisel.LagrangeTop(1.75e-4, 2e-5, 0.1, 0.04)
        st = top.state(0.3, psi_dot=300.0)
        kreisel.simulate(top, st, 0.01, events=[events.{event}])
    """)
    assert clean(r), r


@pytest.mark.parametrize("kind", ["heavy", "play"])
def test_empty_output_times_give_empty_columns_or_an_error(kind):
    """t_eval=[] lets a heavy-top run succeed and then reading a column
    raises KeyError; a play top raises IndexError."""
    make = {
        "heavy": "top = kreisel.LagrangeTop(1.0, 0.5, 1.0, 0.1)\n"
                 "st = top.state(1.0, psi_dot=5.0)",
        "play": "top = kreisel.PlayTop(0.02, 3.5e-6, 7e-6, 0.0, 0.004)\n"
                "st = top.state(1e-300, height=0.0)",
    }[kind]  # fmt: skip
    r = outcome(
        f"kind = {kind!r}\n"
        + make
        + """
        traj = kreisel.simulate(top, st, 0.01, t_eval=[])
        [traj[k] for k in ("t", "theta", "energy", "M3" if kind == "heavy" else "u")]
    """.replace("\n        ", "\n")
    )
    assert clean(r), r


def test_kovalevskaya_integral_of_a_tiny_centre_of_mass_is_finite():
    """models/heavy_top.rs: r = sqrt(c1^2 + c2^2) underflows for
    |com| = 1e-200 and the Kovalevskaya integral is NaN (hypot would keep it)."""
    r = outcome("""
        h = kreisel.HeavyTop(2.0, 2.0, 1.0, 1.0, [1e-200, 0.0, 0.0])
        k = h.invariants(h.state(1.0, theta_dot=1.0, psi_dot=3.0))["kovalevskaya"]
        assert math.isfinite(k), k
    """)
    # _heavy.py now turns the NaN into a ParameterError; the integral itself should be finite.
    assert r == "ok", r


def test_play_state_with_huge_velocity_is_an_error_not_an_inf_energy():
    """models/play_top.rs: vx and vy are only checked finite, so a state with vx = 1e300 has
    an infinite energy (PlayTop.energy) without a word; the rule for rates (at most 1e100,
    error.rs RATE_MAX) would do for velocities too. Likewise omega from
    state_from_quaternion is not checked at all."""
    r = outcome("""
        pt = kreisel.PlayTop(0.02, 5e-6, 7e-6, 0.001, 0.004)
        e = pt.energy(pt.state(0.1, vx=1e300))
        assert math.isfinite(e), e
    """)
    assert clean(r), r


def test_wrong_state_type_for_play_and_simulate_is_a_kreisel_error():
    """_play.py and _simulate.py raise a bare TypeError for a state of the wrong type; the
    rest of kreisel raises kreisel._errors.ParameterTypeError (a ParameterError that is
    also a TypeError), so callers can catch every bad input as a KreiselError."""
    r = outcome("""
        pt = kreisel.PlayTop(0.02, 5e-6, 7e-6, 0.001, 0.004)
        pt.jellett(1.0)
    """)
    assert clean(r), r
