"""The share of the fuzz campaign that `make test` runs: a few thousand derandomised calls of
every public function (see ``campaign.py``; `make fuzz` runs 10^5), each in a worker process
with a time limit, so a crash or a hang is counted, not fatal.

No call may end unclear, in a NaN (other than those documented, by name), a panic, a crash
or a hang, inside the simulation stack (simulate, simulate_many, the play top's states and
invariants, lyapunov) or outside it. The share is derandomised: the same calls every run.
"""

from __future__ import annotations

import collections
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import campaign  # noqa: E402

CALLS = 3000


@pytest.fixture(scope="module")
def run():
    targets, calls, results = campaign.campaign(CALLS, derandomize=True, calm=True, timeout=10.0)
    by_target = collections.defaultdict(collections.Counter)
    bad = collections.defaultdict(list)
    for (ti, args), (outcome, detail) in zip(calls, results):
        t = targets[ti]
        by_target[t.name][outcome] += 1
        if outcome in campaign.BAD:
            bad[t.name].append((outcome, detail, args))
    return targets, calls, results, by_target, bad


def test_every_public_callable_is_driven(run):
    targets = run[0]
    missing = campaign.public_surface() - {t.name for t in targets}
    assert not missing, f"public callables the fuzz campaign does not drive: {sorted(missing)}"


def test_every_call_ends_in_a_known_outcome(run):
    _, calls, results, by_target, _ = run
    assert len(results) >= 0.9 * CALLS
    assert all(r is not None and r[0] in campaign.OUTCOMES for r in results)
    # Each function is driven into both a result and an error somewhere.
    for name, c in by_target.items():
        assert sum(c.values()) > 0, name


def test_no_nan_panic_crash_hang_or_unclear_error_outside_the_simulation_stack(run):
    targets, _, _, _, bad = run
    stack = {t.name for t in targets if t.stack}
    found = {n: v for n, v in bad.items() if n not in stack}
    lines = [f"{n} {o}: {d}\n    {a!r}" for n, v in found.items() for o, d, a in v[:3]]
    assert not found, "\n".join(lines)


def test_simulation_stack_defects(run):
    """Inside the simulation stack too, no call may end in a NaN (other than the summaries
    NaN by design, campaign.BATCH_NAN_BY_DESIGN), a panic, a crash, a hang or an unclear
    error."""
    targets, _, _, _, bad = run
    stack = {t.name for t in targets if t.stack}
    found = {n: v for n, v in bad.items() if n in stack}
    lines = [f"{n} {o}: {d}\n    {a!r}" for n, v in found.items() for o, d, a in v[:3]]
    assert not found, "\n".join(lines)


DRAW = """
import hashlib, sys
sys.path[:0] = [{fuzz!r}, {extra!r}]
if {load_extra}:
    import local_constants  # noqa: F401
import campaign
calls = campaign.draw_calls(campaign.all_targets(True), {n}, derandomize=True)
print(len(calls), hashlib.sha256(repr(calls).encode()).hexdigest())
"""


def test_the_derandomised_share_is_the_same_in_every_run(tmp_path):
    """The same calls whatever else is loaded: Hypothesis would otherwise draw some numbers
    from the constants of the local modules imported at the time (other test files under
    `make test`, or an edited module), and the share `make test` runs would change."""
    import subprocess

    (tmp_path / "local_constants.py").write_text(
        "ODD = [0.123456789, 31415.9265, -2718.28, 1.5e-7, 'kreisel-fuzz', 987654321]\n"
    )
    fuzz = os.path.dirname(os.path.abspath(__file__))
    out = []
    for load_extra in (False, True):
        code = DRAW.format(fuzz=fuzz, extra=str(tmp_path), load_extra=load_extra, n=400)
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              timeout=300, cwd=tmp_path)  # fmt: skip
        assert proc.returncode == 0, proc.stderr[-2000:]
        out.append(proc.stdout.split())
    assert int(out[0][0]) >= 300
    assert out[0] == out[1]


def test_a_nan_of_a_batch_is_a_defect_unless_it_is_nan_by_design():
    """A play-top batch whose top neither lies flat nor comes to rest has flat_time and
    rest_time NaN (by design, allowed by name); a NaN in any other summary of a run that went
    through is classed "nan", a bad outcome, not an expected failure."""
    import dataclasses

    import numpy as np

    import kreisel

    pt = kreisel.PlayTop(m=0.015, A=4e-6, C=5e-6, s=0.003, rho=0.015)
    runs = kreisel.simulate_many(pt, [pt.state(theta=0.1, psi_dot=150.0)] * 2, 0.05, threads=1)
    summary = dataclasses.asdict(runs)
    assert np.isnan(summary["flat_time"]).all() and np.isnan(summary["rest_time"]).all()
    assert campaign.classify("simulate_many", None, lambda _: summary) == ("clean", "")
    summary["final_u"] = np.array([0.99, np.nan])
    outcome, detail = campaign.classify("simulate_many", None, lambda _: summary)
    assert outcome == "nan" and "final_u[1]" in detail
    assert outcome in campaign.BAD
