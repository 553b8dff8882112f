"""Generate src/integrate/dop853/coefficients.rs from scipy's DOP853 tables.

Run with the project's virtualenv interpreter (needs numpy + scipy):

    python tools/gen_dop853_coefficients.py > crates/kreisel-core/src/integrate/dop853/coefficients.rs
    rustfmt --edition 2021 src/integrate/dop853/coefficients.rs

Every value is printed with ``repr(float(x))`` (shortest round-trip decimal), so the
Rust `f64` constants are bit-identical to scipy's arrays.
"""

import sys

from scipy.integrate._ivp import dop853_coefficients as c

N_STAGES = c.N_STAGES  # 12
N_EXT = c.N_STAGES_EXTENDED  # 16


def lit(x):
    s = repr(float(x))
    if s in ("inf", "-inf", "nan"):
        raise ValueError(s)
    if "." not in s and "e" not in s:
        s += ".0"
    return s


def vec(name, doc, values):
    out = [f"/// {doc}", f"pub const {name}: [f64; {len(values)}] = ["]
    out += [f"    {lit(v)}," for v in values]
    out.append("];")
    return "\n".join(out)


def mat(name, doc, rows):
    ncol = len(rows[0])
    out = [f"/// {doc}", f"pub const {name}: [[f64; {ncol}]; {len(rows)}] = ["]
    for r in rows:
        out.append("    [")
        out += [f"        {lit(v)}," for v in r]
        out.append("    ],")
    out.append("];")
    return "\n".join(out)


assert c.A.shape == (N_EXT, N_EXT)
assert c.B.shape == (N_STAGES,)
assert c.E3.shape == (N_STAGES + 1,) and c.E5.shape == (N_STAGES + 1,)
assert c.D.shape == (c.INTERPOLATOR_POWER - 3, N_EXT)

parts = [
    "//! Butcher tableau, error estimators and dense-output coefficients of DOP853.",
    "//!",
    "//! Dormand–Prince 8(5,3) as published in E. Hairer, S. P. Nørsett, G. Wanner,",
    "//! *Solving Ordinary Differential Equations I: Nonstiff Problems*, 2nd ed.,",
    "//! Springer 1993, Sec. II.5 (the method) and II.6 (dense output), and in Hairer's",
    "//! Fortran code `dop853.f`.",
    "//!",
    "//! GENERATED FILE, do not edit by hand: produced by",
    "//! `tools/gen_dop853_coefficients.py` from SciPy's",
    "//! `scipy/integrate/_ivp/dop853_coefficients.py` (SciPy "
    + __import__("scipy").__version__
    + "), every value printed",
    "//! with Python's `repr` so that the constants round-trip bit-exactly.",
    "//!",
    "//! Stage layout (0-based, as in SciPy): stages `0..12` are the 12 stages of the",
    "//! method, stage `12` is `f(t + h, y_new)` (first-same-as-last), stages `13..16`",
    "//! are the three extra stages of the 7th-order dense output.",
    "",
    f"/// Number of stages of the 8th-order method.",
    f"pub const N_STAGES: usize = {N_STAGES};",
    f"/// Number of stages including the FSAL stage and the 3 dense-output stages.",
    f"pub const N_STAGES_EXTENDED: usize = {N_EXT};",
    "",
    vec("C", "Nodes `c_i` of all 16 stages.", c.C),
    "",
    mat(
        "A",
        "Runge–Kutta matrix `a_ij` (strictly lower triangular; row 12 equals `B`).",
        c.A,
    ),
    "",
    vec("B", "Weights `b_i` of the 8th-order solution.", c.B),
    "",
    vec(
        "E3",
        "3rd-order error estimator weights (`b_i - bhh_i`, last entry for stage 12).",
        c.E3,
    ),
    "",
    vec("E5", "5th-order error estimator weights (last entry for stage 12).", c.E5),
    "",
    mat(
        "D",
        "Dense-output coefficients for the polynomial terms 4..7 (`h * D @ K`).",
        c.D,
    ),
    "",
]
sys.stdout.write("\n".join(parts))
