"""A run that the process's memory cannot hold ends with a clear error, never an abort.

Each case runs in a child process whose address space is capped (``RLIMIT_AS``) a little
above what it already uses, so that keeping the run's rows, or computing its diagnostics
columns (about 400 bytes a row), cannot fit. Before, the allocator's failure aborted the
process (``memory allocation of 134217728 bytes failed``: floor campaign case 2330 of seed 2,
3.6 million rows, under the campaign's 4 GiB cap); now the rows' growth and every column are
allocated fallibly and the user gets a ``ParameterError`` naming ``t_end`` (rows) or a
``MemoryError`` (columns), each saying to pass ``t_eval`` or a shorter ``t_end``.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS and /proc: Linux")

PRELUDE = textwrap.dedent(
    """
    import resource
    import numpy as np
    import kreisel
    from kreisel import Coulomb, PlayTop

    def vm_bytes():
        for line in open("/proc/self/status"):
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
        raise RuntimeError("no VmSize")

    def cap(extra):
        limit = vm_bytes() + extra
        resource.setrlimit(resource.RLIMIT_AS, (limit, resource.RLIM_INFINITY))

    m, r = 0.05, 0.01
    top = PlayTop(m, 0.4 * m * r * r, 0.4 * m * r * r, s=0.0, rho=r, friction=Coulomb(0.3))
    st = top.state_from_quaternion([1.0, 0.0, 0.0, 0.0], [0.0, 20.0, 3.0], vx=0.1)
    """
)


def _run(body: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", PRELUDE + textwrap.dedent(body)],
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_columns_that_do_not_fit_are_a_memory_error():
    p = _run(
        """
        tr = kreisel.simulate(top, st, 1.0, t_eval=np.linspace(0.0, 1.0, 1_500_000))
        assert len(tr.t) == 1_500_000
        cap(64 * 2**20)  # 64 MB more: the columns need about 600 MB
        try:
            tr.part_friction_force
        except MemoryError as e:
            print("MemoryError:", e)
        """
    )
    assert p.returncode == 0, p.stderr[-2000:]
    assert "MemoryError: the process ran out of memory keeping" in p.stdout
    assert "t_eval" in p.stdout


def test_rows_that_do_not_fit_are_refused_naming_t_end():
    p = _run(
        """
        cap(64 * 2**20)  # 64 MB more: 3 million rows need about 400 MB
        try:
            kreisel.simulate(top, st, 1.0, t_eval=np.linspace(0.0, 1.0, 3_000_000))
        except kreisel.ParameterError as e:
            print("ParameterError:", e)
        """
    )
    assert p.returncode == 0, p.stderr[-2000:]
    assert "ParameterError: t_end = 1.0 is not allowed: the process ran out of memory" in p.stdout
    assert "t_eval" in p.stdout
