"""The compiled module ``kreisel._core`` (crates/kreisel-py): conversion only, no physics.

Private: the public API is the Python package around it. SI units and radians throughout;
quaternions are scalar-first (w, x, y, z) and rotate body-frame vectors into space; omega
is in the body frame. A "packed" play-top state is (q, omega, com, com_velocity). Every
error is a ``kreisel.ParameterError`` (bad input, naming the argument) or a
``kreisel.NumericalError``.
"""

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from typing_extensions import TypeAlias

__version__: str

F64: TypeAlias = NDArray[np.float64]
Quaternion: TypeAlias = tuple[float, float, float, float] | Sequence[float]
Vector3: TypeAlias = tuple[float, float, float] | Sequence[float]
EulerTuple: TypeAlias = tuple[float, float, float, float, float, float]  # theta, phi, psi and rates
Packed: TypeAlias = tuple[Sequence[float], Sequence[float], Sequence[float], Sequence[float]]
# (name, kind, user function of (t, q, omega) or None, level, direction, terminal)
EventTuple: TypeAlias = tuple[str, str, Callable[[float, F64, F64], float] | None, float, int, bool]

class LagrangeTop:
    def __new__(cls, i1: float, i3: float, m: float, l: float, g: float) -> LagrangeTop: ...
    def analyse(self, s: EulerTuple) -> dict[str, Any]: ...
    def effective_potential(self, theta: ArrayLike, mz: float, m3: float) -> F64: ...
    def exact(
        self, s: EulerTuple, t: ArrayLike, direct: bool = False
    ) -> tuple[F64, F64, F64, F64, F64, F64]: ...
    def invariants(self, s: EulerTuple) -> tuple[float, float, float]: ...
    def nutation_frequency(self, theta0: float, omega3: float, rate: float) -> float: ...
    def sleeping_threshold(self) -> float: ...
    def steady_precession(self, theta0: float, omega3: float) -> tuple[float, float]: ...

class HeavyTop:
    def __new__(
        cls, i1: float, i2: float, i3: float, m: float, com: Vector3, g: float
    ) -> HeavyTop: ...
    @property
    def kind(self) -> str: ...
    def check_rigid(self, q: Quaternion, omega: Vector3) -> tuple[list[float], list[float]]: ...
    def invariants(self, q: Quaternion, omega: Vector3) -> dict[str, float]: ...
    def lyapunov(
        self,
        q: Quaternion,
        omega: Vector3,
        t_end: float,
        tau: float,
        d0: float,
        direction: Sequence[float],
        rtol: float,
        atol: float,
    ) -> dict[str, Any]: ...

class DrivenTop:
    """A heavy top on a moving pivot with damping at it (pivot "fixed", "harmonic" or
    "path"; a path as scipy's PPoly breakpoints and coefficients, shape (6, n, 3))."""

    def __new__(
        cls,
        top: HeavyTop,
        pivot: str,
        amplitude: Vector3,
        omega: float,
        phase: Vector3,
        breaks: Sequence[float],
        coef: Sequence[float],
        viscous: float,
        drag: float,
        dry: float,
        pivot_radius: float,
    ) -> DrivenTop: ...
    def invariants(self, q: Quaternion, omega: Vector3, t: float) -> dict[str, float]: ...
    def stick_margin(self, q: Quaternion, t: float) -> float: ...
    def lyapunov(
        self,
        q: Quaternion,
        omega: Vector3,
        t_end: float,
        tau: float,
        d0: float,
        direction: Sequence[float],
        rtol: float,
        atol: float,
    ) -> dict[str, Any]: ...

class SymmetricTop:
    """The quantum symmetric top (I1, I3, hbar), its (K, M) blocks and EBK levels."""

    def __new__(cls, i1: float, i3: float, hbar: float) -> SymmetricTop: ...
    @property
    def b(self) -> float: ...
    @property
    def k_constant(self) -> float: ...
    def free_energy(self, j: int, k: int) -> float: ...
    def levels(self, k: int, m: int, j_max: int, strengths: ArrayLike) -> NDArray[np.float64]: ...
    def block(self, k: int, m: int, j_max: int) -> tuple[int, F64, F64, F64]: ...
    def nutation_action(self, k: int, m: int, energy: float, strength: float) -> float: ...
    def ebk_energy(self, k: int, m: int, n: int, strengths: ArrayLike) -> F64: ...

class Friction:
    """A friction law, its coefficient checked by the core."""

    @staticmethod
    def coulomb(mu: float) -> Friction: ...
    @staticmethod
    def viscous(mu: float) -> Friction: ...
    @staticmethod
    def none() -> Friction: ...
    @staticmethod
    def coulomb_contensou(mu: float, radius: float) -> Friction: ...
    @property
    def law(self) -> str: ...
    @property
    def mu(self) -> float: ...

class PlayTop:
    def __new__(
        cls,
        m: float,
        a: float,
        c: float,
        s: float,
        rho: float,
        g: float,
        friction: Friction,
        restitution: float,
        rolling: float,
        drilling: float,
        air: float,
    ) -> PlayTop: ...
    @property
    def alpha(self) -> float: ...
    @property
    def gamma(self) -> float: ...
    @property
    def j_beta(self) -> float: ...
    def state(
        self, q: Quaternion, omega: Vector3, vx: float, vy: float, height: float | None = None
    ) -> Packed: ...
    def state_from_euler(
        self, euler: Sequence[float], vx: float, vy: float, height: float | None = None
    ) -> Packed: ...
    def invariants(self, s: Packed) -> tuple[float, float]: ...
    def slip_coefficient(self, s: Packed, dir: tuple[float, float]) -> float: ...
    @staticmethod
    def with_parts(
        m: float,
        a: float,
        c: float,
        parts: list[tuple[str, float, float, float]],
        g: float,
        friction: Friction,
        restitution: float,
        rolling: float,
        drilling: float,
        air: float,
    ) -> PlayTop: ...
    def with_stick_threshold(self, stick: float) -> PlayTop: ...
    @property
    def stick_threshold(self) -> float: ...

class Run:
    """The rows of a run of any model, kept natively; diagnostics on first read."""

    def columns(self) -> dict[str, F64]: ...

class PlayStability:
    def __new__(cls, top: PlayTop) -> PlayStability: ...
    def j_r(self, u: ArrayLike) -> F64: ...
    def regular_precession(self, u: float) -> tuple[float, float, float, float]: ...
    def stationary_motions(
        self, j: float
    ) -> list[tuple[str, float, bool, float, float, float]]: ...
    def stationary_energy(self, j: float, u: ArrayLike) -> F64: ...
    def predict(self, j: float, energy: float, u: float) -> tuple[Any, Any, Any]: ...
    def frictionless_nutation(self, state: Packed) -> tuple[float, float, float, float]: ...

# batches: the GIL is released while the runs go; columns NaN and a message where one fails
# one stack for every model: a native HeavyTop or PlayTop and a flat state, (q, omega) for a
# heavy top, (q, omega, com, com_velocity) for a play top
def simulate(
    model: HeavyTop | DrivenTop | PlayTop,
    state: Sequence[float],
    t_end: float,
    method: str,
    rtol: float,
    atol: float,
    dt: float | None = None,
    t_eval: Sequence[float] | F64 | None = None,
    events: Sequence[EventTuple] = ...,
    reduced: bool = False,
) -> dict[str, Any]: ...
def simulate_sensitivities(
    model: HeavyTop | DrivenTop | PlayTop,
    state: Sequence[float],
    t_end: float,
    method: str,
    rtol: float,
    atol: float,
    dt: float | None,
    t_eval: Sequence[float] | F64 | None,
    events: Sequence[EventTuple],
    reduced: bool,
    names: Sequence[str],
    lagrange: bool,
    euler: Sequence[float] | None = None,
    control: bool = False,
) -> dict[str, Any]:
    """A heavy top's (or a play top's) run with DOP853 and forward sensitivities: what
    ``simulate`` returns and ``sensitivities``, per name a dict of ``omega`` (n, 3),
    ``orientation`` (n, 3), ``quaternion`` (n, 4), ``theta``, ``phi``, ``psi`` (n,); for a
    play top also ``com``, ``com_velocity`` (n, 3), ``dissipated`` and ``u`` (n,), across
    its touchdowns. ``control`` puts them into the step-size
    control (heavy tops)."""

def many(
    models: Sequence[HeavyTop | DrivenTop | PlayTop],
    states: Sequence[Sequence[float]],
    t_end: float,
    method: str,
    rtol: float,
    atol: float,
    dt: float | None = None,
    inversion_level: float = 0.9,
    threads: int | None = None,
) -> dict[str, Any]: ...
def names() -> dict[str, Any]: ...
def lagrange_columns(
    i1: float,
    i3: float,
    m: float,
    l: float,
    g: float,
    theta: F64,
    theta_dot: F64,
    phi_dot: F64,
    psi_dot: F64,
) -> dict[str, F64]: ...
def rotation_matrices(q: F64) -> NDArray[np.float64]: ...
def quaternions_from_euler(phi: F64, theta: F64, psi: F64) -> F64: ...
def check_event(event: EventTuple) -> None: ...
def check_settings(
    model: HeavyTop | DrivenTop | PlayTop,
    t_end: float,
    method: str,
    rtol: float,
    atol: float,
    dt: float | None = None,
    events: Sequence[EventTuple] = ...,
    reduced: bool = False,
) -> None: ...
def lyapunov_many(
    tops: Sequence[HeavyTop | DrivenTop],
    states: Sequence[tuple[Quaternion, Vector3]],
    t_end: float,
    tau: float,
    d0: float,
    direction: Sequence[float],
    rtol: float,
    atol: float,
    threads: int | None = None,
) -> dict[str, Any]: ...

# states and methods
def check_euler_state(s: EulerTuple) -> None: ...
def check_rate(name: str, value: float) -> float: ...
def rigid_from_euler(
    theta: float, phi: float, psi: float, theta_dot: float, phi_dot: float, psi_dot: float
) -> tuple[list[float], list[float]]: ...
def methods() -> list[tuple[str, int, bool, bool, bool, str]]: ...

# special functions (kreisel.special)
def ellipj(u: ArrayLike, m: float) -> tuple[F64, F64, F64, F64]: ...
def ellipk(m: float) -> float: ...
def ellipf(phi: ArrayLike, m: float) -> F64: ...
def ellippi(n: float, m: float) -> float: ...
def ellippiinc(n: float, phi: ArrayLike, m: float) -> F64: ...
def cubic_roots(c0: float, c1: float, c2: float, c3: float) -> list[float]: ...

# the atlas of play tops
def play_u_m(alpha: float, gamma: float) -> float | None: ...
def play_classify(alpha: float, gamma: float) -> tuple[str, int, str]: ...
def play_zones(alpha: ArrayLike, gamma: ArrayLike) -> NDArray[np.int64]: ...
def play_zone_boundaries(alpha: ArrayLike) -> tuple[F64, F64, F64, F64]: ...
