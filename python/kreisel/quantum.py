"""The quantum symmetric top, and its bridge to the classical Lagrange top.

A rigid symmetric top (moments I1 = I2 perpendicular to the figure axis, I3 about it) has the
free levels ``E(J, K) = hbar^2 J(J+1)/(2 I1) + hbar^2 K^2 (1/(2 I3) - 1/(2 I1))``,
``|K|, |M| <= J``.
In a potential ``P cos(theta)`` -- the heavy top with P = m g l, or a symmetric-top molecule
with dipole mu in a field E along z with P = -mu E (the Stark effect) -- K and M stay good
quantum numbers and each (K, M) block of the Hamiltonian in the basis ``|J K M>`` is tridiagonal
in J (theory: quantum top):

- :class:`SymmetricTop`: the top, from its moments or from spectroscopic constants
  (:meth:`SymmetricTop.from_constants`), its free levels and their degeneracies
  (:meth:`SymmetricTop.rotor_levels`), the pure rotational spectrum
  (:meth:`SymmetricTop.spectrum`), the levels in the potential
  (:meth:`SymmetricTop.levels`, :meth:`SymmetricTop.stark_map`), their convergence in the
  size of the basis (:meth:`SymmetricTop.convergence`), the pendular (strong-field) limit
  (:meth:`SymmetricTop.pendular_levels`) and the semiclassical (EBK) levels of the
  classical top (:meth:`SymmetricTop.ebk_levels`).
- :class:`RotorLevels`, :class:`Spectrum`, :class:`Convergence`, :class:`StarkMap`: the
  results, plain arrays with their labels.

SI units: energies and strengths in joules, moments in kg m^2, hbar in J s, frequencies in
Hz, temperatures in K. The eigenvalues, the matrix elements and the EBK actions are computed
by kreisel's core (``crates/kreisel-core/src/quantum``); bad input raises
:class:`kreisel.ParameterError` naming the argument, the value and what is allowed.

Examples
--------
>>> from kreisel.quantum import SymmetricTop
>>> top = SymmetricTop.from_constants(A=155352.7, B=25536.15, unit="MHz")  # CH3F
>>> top.kind
'prolate'
>>> E = top.levels(K=1, M=1, J_max=40, strength=-1e-24)
>>> E.shape
(40,)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Union

import numpy as np

from . import _core
from ._errors import NumericalError, ParameterError
from ._validate import floats, integer, real

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

    #: a float for a scalar argument, else an array
    FloatOrArray = Union[float, NDArray[np.float64]]

#: Planck's reduced constant (J s), CODATA 2018.
HBAR = 1.054571817e-34
#: Boltzmann's constant (J/K), exact in the SI since 2019.
K_B = 1.380649e-23
#: The speed of light (m/s), exact.
C_LIGHT = 299_792_458.0

# The largest dense block hamiltonian() forms: 11585^2 float64 are 1 GiB.
_DENSE_MAX = 11585

# Frequency (Hz) of one unit of a spectroscopic constant.
_UNITS = {"Hz": 1.0, "MHz": 1e6, "GHz": 1e9, "cm-1": 100.0 * C_LIGHT}


def _quantum_number(name: str, value: object) -> int:
    q = integer(name, value)
    if abs(q) >= 2**62:
        raise ParameterError(f"{name} = {q} is not allowed: it must be an integer below 2**62")
    return q


def _unit(unit: object) -> float:
    if not isinstance(unit, str) or unit not in _UNITS:
        raise ParameterError(f"unit = {unit!r} is not allowed: it must be one of {list(_UNITS)}")
    return _UNITS[unit]


def _strengths(value: object) -> tuple[np.ndarray, bool]:
    """(a contiguous 1-D array of strengths, whether the argument was a scalar)."""
    arr = floats("strength", value)
    scalar = arr.ndim == 0
    if arr.ndim > 1:
        raise ParameterError(
            f"strength has shape {arr.shape}, which is not allowed: it must be a number or 1-D"
        )
    return np.ascontiguousarray(arr.reshape(-1)), scalar


@dataclass(frozen=True)
class RotorLevels:
    """The free rotor's levels up to a J, lowest first: one entry per (J, ``|K|``).

    Attributes
    ----------
    J, K : ndarray of int, shape (n,)
        Quantum numbers, K >= 0 (the levels +K and -K coincide).
    energy : ndarray, shape (n,)
        E(J, K) (J).
    degeneracy : ndarray of int, shape (n,)
        ``(2J + 1)`` states of M, times 2 for K != 0 (+-K).

    Examples
    --------
    >>> from kreisel.quantum import SymmetricTop
    >>> lv = SymmetricTop(I1=2.0, I3=1.0, hbar=1.0).rotor_levels(J_max=2)
    >>> lv.J.tolist(), lv.K.tolist(), lv.degeneracy.tolist()
    ([0, 1, 1, 2, 2, 2], [0, 0, 1, 0, 1, 2], [1, 3, 6, 5, 10, 10])
    >>> lv.energy.tolist()
    [0.0, 0.5, 0.75, 1.5, 1.75, 2.5]
    """

    J: NDArray[np.int64]
    K: NDArray[np.int64]
    energy: NDArray[np.float64]
    degeneracy: NDArray[np.int64]


@dataclass(frozen=True)
class Spectrum:
    """The pure rotational (absorption) spectrum: one line per (J -> J+1, K), by frequency.

    Attributes
    ----------
    J, K : ndarray of int, shape (n,)
        Lower level of each line (K >= 0; +-K together).
    frequency : ndarray, shape (n,)
        Line position ``(E(J+1, K) - E(J, K)) / h`` (Hz): ``2 B (J+1)`` for every K of a rigid top.
    intensity : ndarray, shape (n,)
        Relative integrated absorption, the strongest line 1 (see :meth:`SymmetricTop.spectrum`).
    temperature : float
        (K).

    Examples
    --------
    >>> from kreisel.quantum import SymmetricTop
    >>> top = SymmetricTop.from_constants(A=155352.7, B=25536.15, unit="MHz")
    >>> sp = top.spectrum(J_max=3, temperature=300.0)
    >>> [round(float(f) / 1e6, 1) for f in sp.frequency[:3]]
    [51072.3, 102144.6, 102144.6]
    """

    J: NDArray[np.int64]
    K: NDArray[np.int64]
    frequency: NDArray[np.float64]
    intensity: NDArray[np.float64]
    temperature: float


@dataclass(frozen=True)
class Convergence:
    """How far the levels of a (K, M) block are from the infinite basis.

    The block is solved with ``J <= J_max`` and again with ``J <= J_check`` (> J_max). Each
    eigenvalue can only fall as the basis grows (the variational principle: Cauchy's
    interlacing theorem), and the errors fall faster than exponentially once J_max is past
    the levels' reach, so the change between the two is an estimate of the error at J_max.

    Attributes
    ----------
    J_max, J_check : int
        The two sizes of the basis (highest J).
    change : ndarray, shape (levels,)
        Largest change of each level (J, lowest first) over the strengths (J).
    tolerance : float
        A level is converged when its change is at most this (J).
    n_converged : int
        How many of the lowest levels are converged.

    Examples
    --------
    >>> from kreisel.quantum import SymmetricTop
    >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
    >>> c = top.convergence(K=0, M=0, J_max=30, strength=[10.0, 100.0])
    >>> c.n_converged >= 15, c.converged(5)
    (True, True)
    >>> print(c)
    J_max = 30: the lowest 19 of 31 levels changed by at most 1.01e-08 J when J_max was raised to 40
    """

    J_max: int
    J_check: int
    change: NDArray[np.float64]
    tolerance: float
    n_converged: int

    def converged(self, levels: int) -> bool:
        """Whether the lowest ``levels`` levels are all converged.

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> c = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0).convergence(0, 0, 12, 5.0)
        >>> c.converged(1), c.converged(13)
        (True, False)
        """
        return self.n_converged >= integer("levels", levels)

    def __str__(self) -> str:
        n = len(self.change)
        return (
            f"J_max = {self.J_max}: the lowest {self.n_converged} of {n} levels changed by at "
            f"most {self.tolerance:.3g} J when J_max was raised to {self.J_check}"
        )


@dataclass(frozen=True)
class StarkMap:
    """The levels J <= ``J`` of every (K, M) block against the strength of the potential.

    Attributes
    ----------
    strength : ndarray, shape (s,)
        P (J) of the potential P cos(theta) (P = -mu E for a dipole mu in a field E).
    J : int
        Every level that correlates with a free level J' <= J is here.
    blocks : dict
        ``{(K, M): levels}``, levels of shape ``(s, J - max(|K|, |M|) + 1)``, column i the level
        that starts (at P = 0) as ``J' = max(|K|, |M|) + i`` (levels of one block never cross).
    convergence : Convergence
        The worst block's convergence report (all of its levels here must be converged).

    Examples
    --------
    >>> import numpy as np
    >>> from kreisel.quantum import SymmetricTop
    >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
    >>> sm = top.stark_map(J=2, strength=np.linspace(0.0, 2.0, 5))
    >>> len(sm.blocks), sm.level(J=1, K=1, M=1).shape
    (25, (5,))
    """

    strength: NDArray[np.float64]
    J: int
    blocks: dict = field(repr=False)
    convergence: Convergence

    def level(self, J: int, K: int, M: int) -> NDArray[np.float64]:
        """The level that is (J, K, M) at zero strength, at every strength (J).

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> sm = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0).stark_map(J=1, strength=[0.0, 0.1])
        >>> [round(float(e), 6) for e in sm.level(J=1, K=1, M=1)]
        [1.5, 1.549237]
        """
        J, K, M = (_quantum_number(n, v) for n, v in (("J", J), ("K", K), ("M", M)))
        if (K, M) not in self.blocks or not max(abs(K), abs(M)) <= J <= self.J:
            raise ParameterError(
                f"(J, K, M) = ({J}, {K}, {M}) is not allowed: it must have |K|, |M| <= J <= "
                f"{self.J}, the map's J"
            )
        return self.blocks[(K, M)][:, J - max(abs(K), abs(M))]


class SymmetricTop:
    """A rigid symmetric top in quantum mechanics.

    Parameters
    ----------
    I1 : float
        Moment of inertia about an axis perpendicular to the figure axis (kg m^2), > 0: about
        the centre of mass for a free molecule, about the pivot for a top on a pivot.
    I3 : float
        Moment about the figure axis (kg m^2), 0 < I3 <= 2 I1 (I3 < I1: prolate, I3 > I1:
        oblate).
    hbar : float
        Planck's reduced constant (J s); another value gives a top in other units (hbar = 1:
        energies in units of hbar^2 / (kg m^2)).

    Levels of the free rotor (theory: quantum top; Townes and Schawlow, "Microwave
    Spectroscopy" (1955), ch. 4): ``E(J, K) = hbar^2 J(J+1)/(2 I1) + hbar^2 K^2 (1/(2 I3) -
    1/(2 I1))``, each (2J+1)-fold in M and twofold in +-K for K != 0.

    Examples
    --------
    >>> from kreisel.quantum import SymmetricTop
    >>> top = SymmetricTop(I1=2.0, I3=1.0, hbar=1.0)
    >>> top
    SymmetricTop(I1=2.0, I3=1.0, hbar=1.0)
    >>> top.energy(J=2, K=1)
    1.75
    """

    __slots__ = ("_I1", "_I3", "_hbar", "_native")

    def __init__(self, I1: float, I3: float, hbar: float = HBAR) -> None:
        self._I1, self._I3, self._hbar = real("I1", I1), real("I3", I3), real("hbar", hbar)
        self._native = _core.SymmetricTop(self._I1, self._I3, self._hbar)

    I1 = property(lambda self: self._I1, doc="Perpendicular moment of inertia (kg m^2).")
    I3 = property(lambda self: self._I3, doc="Axial moment of inertia (kg m^2).")
    hbar = property(lambda self: self._hbar, doc="Planck's reduced constant (J s).")

    def __repr__(self) -> str:
        return f"SymmetricTop(I1={self._I1!r}, I3={self._I3!r}, hbar={self._hbar!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SymmetricTop) and repr(self) == repr(other)

    def __hash__(self) -> int:
        return hash(repr(self))

    @property
    def kind(self) -> str:
        """``"prolate"`` (I3 < I1, a cigar), ``"oblate"`` (I3 > I1, a disc) or ``"spherical"``.

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> SymmetricTop(I1=1.0, I3=1.5).kind
        'oblate'
        """
        if self._I3 < self._I1:
            return "prolate"
        return "oblate" if self._I3 > self._I1 else "spherical"

    @property
    def energy_scale(self) -> float:
        """``B = hbar^2 / (2 I1)`` (J): the rotational constant as an energy.

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> SymmetricTop(I1=2.0, I3=1.0, hbar=1.0).energy_scale
        0.25
        """
        return self._native.b

    # -- spectroscopic constants -------------------------------------------------------------

    @classmethod
    def from_constants(
        cls, A: float, B: float, unit: str = "MHz", hbar: float = HBAR
    ) -> SymmetricTop:
        """The top with rotational constants ``A`` (about the figure axis) and ``B``.

        A constant is ``h / (8 pi^2 I)`` in frequency (``unit`` "Hz", "MHz" or "GHz") or
        ``h / (8 pi^2 c I)`` in wavenumbers ("cm-1"). ``A`` is the constant about the figure
        axis: A of a prolate top (A > B), C of an oblate one (C < B). A rigid body has
        ``A >= B / 2`` (I3 <= 2 I1).

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> ch3f = SymmetricTop.from_constants(A=155352.7, B=25536.15, unit="MHz")
        >>> ch3f.kind, f"{ch3f.I1:.4e}"
        ('prolate', '3.2863e-46')
        >>> nh3 = SymmetricTop.from_constants(A=6.2, B=9.94, unit="cm-1")  # C and B of NH3
        >>> nh3.kind
        'oblate'
        """
        scale = _unit(unit)
        a, b, hb = real("A", A), real("B", B), real("hbar", hbar)
        for name, v in (("A", a), ("B", b)):
            if not v > 0:
                raise ParameterError(f"{name} = {v!r} is not allowed: it must be > 0")
        # constant (Hz) = hbar / (4 pi I)
        i3, i1 = hb / (4 * math.pi * a * scale), hb / (4 * math.pi * b * scale)
        try:
            return cls(I1=i1, I3=i3, hbar=hb)
        except ParameterError as e:
            raise ParameterError(
                f"A = {a!r} {unit} with B = {b!r} {unit} is not allowed: it gives {e}"
            ) from None

    def constants(self, unit: str = "MHz") -> tuple[float, float]:
        """(A, B): the rotational constants about the figure axis and perpendicular to it, in
        ``unit`` (see :meth:`from_constants`).

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop.from_constants(A=155352.7, B=25536.15)
        >>> [round(x, 2) for x in top.constants("MHz")]
        [155352.7, 25536.15]
        >>> [round(x, 4) for x in top.constants("cm-1")]
        [5.182, 0.8518]
        """
        scale = _unit(unit)
        k = self._hbar / (4 * math.pi * scale)
        return (k / self._I3, k / self._I1)

    # -- the free rotor ------------------------------------------------------------------------

    def energy(self, J: ArrayLike, K: ArrayLike = 0) -> FloatOrArray:
        """Free-rotor energy E(J, K) (J); ``J`` and ``K`` integers or integer arrays (they
        broadcast), ``|K| <= J``.

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop(I1=2.0, I3=1.0, hbar=1.0)
        >>> top.energy(1), top.energy([1, 2, 3], 1).tolist()
        (0.5, [0.75, 1.75, 3.25])
        """
        e = self._energies(J, K)
        return float(e) if e.ndim == 0 else e

    def _energies(self, J: ArrayLike, K: ArrayLike) -> NDArray[np.float64]:
        j, k = np.asarray(J), np.asarray(K)
        for name, arr, given in (("J", j, J), ("K", k, K)):
            if arr.dtype.kind not in "iu":
                if arr.ndim == 0:
                    integer(name, given)
                raise ParameterError(f"{name} = {given!r} is not allowed: it must hold integers")
        j, k = np.broadcast_arrays(j.astype(np.int64), k.astype(np.int64))
        bad = (np.abs(k) > j) | (j < 0)
        if bad.any():  # the core's rule and its words
            i = np.unravel_index(int(np.argmax(bad)), bad.shape)
            self._native.free_energy(int(j[i]), int(k[i]))
        return self._native.b * j * (j + 1.0) + self._native.k_constant * k * k

    def rotor_levels(self, J_max: int) -> RotorLevels:
        """Every free level (J, ``|K|``) with J <= ``J_max``, lowest first, with its degeneracy.

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> lv = SymmetricTop(I1=2.0, I3=1.0, hbar=1.0).rotor_levels(1)
        >>> lv.J.tolist(), lv.K.tolist(), lv.degeneracy.tolist()
        ([0, 1, 1], [0, 0, 1], [1, 3, 6])
        """
        jm = _quantum_number("J_max", J_max)
        if not 0 <= jm <= 10_000:
            raise ParameterError(f"J_max = {jm} is not allowed: it must lie in [0, 10000]")
        j, k = np.tril_indices(jm + 1)
        e = self._energies(j, k)
        order = np.lexsort((k, j, e))
        deg = (2 * j + 1) * np.where(k > 0, 2, 1)
        return RotorLevels(J=j[order], K=k[order], energy=e[order], degeneracy=deg[order])

    @staticmethod
    def dipole_allowed(lower: tuple[int, int, int], upper: tuple[int, int, int]) -> bool:
        """Whether the dipole along the figure axis connects the states (J, K, M) ``lower`` and
        ``upper``: ``Delta K = 0``; ``Delta J = 0, +-1`` (not 0 <-> 0, and Delta J = 0 only
        for K != 0); ``Delta M = 0, +-1``. The pure rotational spectrum is Delta J = +1.
        Source: Townes and Schawlow (1955), ch. 4.

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> SymmetricTop.dipole_allowed((1, 1, 0), (2, 1, 1)), SymmetricTop.dipole_allowed(
        ...     (1, 1, 0), (2, 0, 0))
        (True, False)
        """
        (j, k, m), (j2, k2, m2) = (
            tuple(_quantum_number(f"{side}[{i}]", v) for i, v in enumerate(s))
            for side, s in (("lower", lower), ("upper", upper))
        )
        for side, (jj, kk, mm) in (("lower", (j, k, m)), ("upper", (j2, k2, m2))):
            if max(abs(kk), abs(mm)) > jj:
                raise ParameterError(
                    f"{side} = ({jj}, {kk}, {mm}) is not allowed: a state (J, K, M) has "
                    "|K|, |M| <= J"
                )
        if k != k2 or abs(j - j2) > 1 or abs(m - m2) > 1:
            return False
        if j == j2:
            return k != 0 and not (m == m2 == 0)
        return True

    def spectrum(
        self,
        J_max: int,
        temperature: float,
        spin_weight: Callable[[int], float] | None = None,
    ) -> Spectrum:
        """The pure rotational absorption spectrum: the lines J -> J+1 (Delta K = 0) from
        J = 0 to ``J_max`` - 1, each K >= 0, and their relative intensities at
        ``temperature`` (K).

        The integrated absorption of a line is proportional to (Townes and Schawlow (1955),
        ch. 1 and 4; Gordy and Cook, "Microwave Molecular Spectra" (1984), ch. 3)::

            nu * S(J, K) * g_K * w(K) * (exp(-E(J, K) / kT) - exp(-E(J+1, K) / kT))

        with the line strength ``S = ((J+1)^2 - K^2) / (J+1)`` (summed over M), ``g_K = 2``
        for K != 0 (+-K), and the nuclear-spin weight ``w(K) = spin_weight(K)`` (1 for every K
        when ``spin_weight`` is None: spin statistics ignored). Normalised to the strongest
        line. The rigid top's lines of one J coincide for every K (no centrifugal distortion).

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop.from_constants(A=155352.7, B=25536.15, unit="MHz")
        >>> sp = top.spectrum(J_max=30, temperature=300.0)
        >>> int(sp.J[sp.intensity.argmax()]), int(sp.K[sp.intensity.argmax()])
        (18, 1)
        """
        jm = _quantum_number("J_max", J_max)
        if not 1 <= jm <= 10_000:
            raise ParameterError(f"J_max = {jm} is not allowed: it must lie in [1, 10000]")
        t = real("temperature", temperature)
        if not t > 0:
            raise ParameterError(f"temperature = {t!r} is not allowed: it must be > 0 (K)")
        j, k = np.tril_indices(jm)
        e_lo, e_up = self._energies(j, k), self._energies(j + 1, k)
        nu = (e_up - e_lo) / (2 * math.pi * self._hbar)
        strength = ((j + 1.0) ** 2 - k**2) / (j + 1.0)
        g = np.where(k > 0, 2.0, 1.0)
        if spin_weight is not None:
            if not callable(spin_weight):
                raise ParameterError(
                    f"spin_weight = {spin_weight!r} is not allowed: it must be a function of K"
                )
            w = np.array([real(f"spin_weight({kk})", spin_weight(int(kk))) for kk in k])
            if (w < 0).any():
                raise ParameterError("spin_weight is not allowed to be negative")
            g = g * w
        kt = K_B * t
        e0 = e_lo.min()  # populations relative to the ground state: no overflow
        pop = np.exp(-(e_lo - e0) / kt) - np.exp(-(e_up - e0) / kt)
        inten = nu * strength * g * pop
        top = inten.max()
        if not top > 0:
            raise NumericalError(
                f"every line's intensity underflows at temperature = {t!r} K (kT is far below "
                "the first rotational spacing)"
            )
        order = np.lexsort((k, nu))
        return Spectrum(
            J=j[order], K=k[order], frequency=nu[order], intensity=inten[order] / top,
            temperature=t,
        )  # fmt: skip

    # -- the top in the potential P cos(theta) --------------------------------------------------

    def levels(self, K: int, M: int, J_max: int, strength: ArrayLike) -> NDArray[np.float64]:
        """The eigenvalues (J) of the (K, M) block of ``H = free rotor + strength * cos(theta)``
        in the basis ``|J K M>``, ``J = max(|K|, |M|)`` .. ``J_max``, ascending.

        Parameters
        ----------
        K, M : int
            Quantum numbers of the projections of the angular momentum on the figure axis and
            on the space z axis (the direction of the field).
        J_max : int
            The highest J of the basis, ``>= max(|K|, |M|)``. Only the lowest levels are converged:
            check with :meth:`convergence`.
        strength : float or array of shape (s,)
            P (J): ``m g l`` for a heavy top, ``-mu E`` for a dipole mu in a field E.

        Returns
        -------
        ndarray of shape ``(s, J_max - max(|K|, |M|) + 1)``, or (levels,) for a scalar strength.

        The matrix elements of cos(theta) are closed forms (Townes and Schawlow (1955), ch. 4,
        the direction cosines of the symmetric top; Zare, "Angular Momentum" (1988), ch. 3):

        - ``<J K M|cos|J K M> = K M / (J(J+1))``,
        - ``<J+1 K M|cos|J K M> = sqrt((J+1)^2 - K^2) sqrt((J+1)^2 - M^2) / ((J+1) c)``
          with ``c = sqrt((2J+1)(2J+3))``.

        The
        eigenvalues come from an implicit QL iteration on the tridiagonal block, the strengths
        spread over all cores.

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
        >>> top.levels(K=1, M=1, J_max=3, strength=0.0).tolist()  # free: J(J+1)/2 + K^2/2
        [1.5, 3.5, 6.5]
        >>> top.levels(K=1, M=1, J_max=20, strength=[-1.0, 0.0, 1.0]).shape
        (3, 20)
        """
        k, m = _quantum_number("K", K), _quantum_number("M", M)
        jm = _quantum_number("J_max", J_max)
        p, scalar = _strengths(strength)
        out = self._native.levels(k, m, jm, p)
        return out[0] if scalar else out

    def hamiltonian(self, K: int, M: int, J_max: int, strength: float) -> NDArray[np.float64]:
        """The (K, M) block of the Hamiltonian as a dense symmetric matrix (J), rows and
        columns ``J = max(|K|, |M|)`` .. ``J_max``: for inspection and for checks against a dense
        eigensolver (:meth:`levels` never forms it).

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel.quantum import SymmetricTop
        >>> H = SymmetricTop(I1=1.0, I3=1.0, hbar=1.0).hamiltonian(0, 0, 2, 3.0)
        >>> np.round(H, 4).tolist()
        [[0.0, 1.7321, 0.0], [1.7321, 1.0, 1.5492], [0.0, 1.5492, 3.0]]
        """
        k, m = _quantum_number("K", K), _quantum_number("M", M)
        jm = _quantum_number("J_max", J_max)
        if jm - max(abs(k), abs(m)) + 1 > _DENSE_MAX:
            raise ParameterError(
                f"J_max = {jm} is not allowed for a dense matrix: it would have more than "
                f"{_DENSE_MAX}^2 entries (1 GiB); use levels(), which never forms it"
            )
        _, free, cdiag, coff = self._native.block(k, m, jm)
        p = real("strength", strength)
        h = np.diag(free + p * cdiag)
        i = np.arange(len(coff))
        h[i, i + 1] = h[i + 1, i] = p * coff
        return h

    def convergence(
        self,
        K: int,
        M: int,
        J_max: int,
        strength: ArrayLike,
        *,
        J_check: int | None = None,
        rtol: float = 1e-10,
    ) -> Convergence:
        """How well the levels of :meth:`levels` at ``J_max`` are converged: they are computed
        again with ``J_check`` (default ``J_max + max(10, J_max // 4)``) and compared, level by
        level, at every strength. A level is converged when it moved by at most
        ``rtol * (B + max |strength|)`` (B = hbar^2/(2 I1)).

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
        >>> c = top.convergence(K=1, M=1, J_max=20, strength=20.0)
        >>> c.J_check, c.n_converged > 5, bool(c.change[0] < c.tolerance)
        (30, True, True)
        """
        p, _ = _strengths(strength)
        return self._convergence(K, M, J_max, p, J_check, rtol)[0]

    def stark_map(
        self,
        J: int,
        strength: ArrayLike,
        *,
        J_max: int | None = None,
        rtol: float = 1e-10,
    ) -> StarkMap:
        """Every level that starts (at zero strength) at J' <= ``J``, every (K, M) with
        ``|K|, |M| <= J``, at every strength (J): a Stark map for P = -mu E.

        ``J_max`` (the basis) is chosen when not given: from ``J + 10 + 4 sqrt(2 max|P| / B)``
        upward (the pendular states reach ``J ~ sqrt(2 |P| / B)``), raised by half each time
        (at most to 2000, else a NumericalError), until :meth:`convergence` finds every level
        J' <= J of every block converged to ``rtol``. A given ``J_max`` is checked too; the
        report is the map's ``convergence``. Blocks related by symmetry are solved once:
        (-K, -M) is (K, M), and (K, -M) at P is (K, M) at -P.

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
        >>> sm = top.stark_map(J=1, strength=np.linspace(0.0, 1.0, 3))
        >>> sorted(sm.blocks)[:3]
        [(-1, -1), (-1, 0), (-1, 1)]
        >>> sm.convergence.n_converged >= 2
        True
        """
        jj = _quantum_number("J", J)
        if not 0 <= jj <= 20:
            raise ParameterError(
                f"J = {jj} is not allowed: it must lie in [0, 20] (a map holds (J+1)^2 blocks, "
                "each solved twice per strength)"
            )
        p, _ = _strengths(strength)
        growing = J_max is None
        if J_max is None:
            # The pendular states reach J ~ sqrt(2 |P| / B); start a few widths beyond.
            reach = math.sqrt(2 * float(np.abs(p).max(initial=0.0)) / self._native.b)
            jm = jj + 10 + int(min(4 * reach, 2000))
        else:
            jm = _quantum_number("J_max", J_max)
        if jm < jj:
            raise ParameterError(f"J_max = {jm} is not allowed: it must be >= J = {jj}")
        both = np.concatenate([p, -p])  # (K, M) and (K, -M) in one call
        while True:
            blocks, reports = {}, []
            for k in range(jj + 1):
                for m in range(jj + 1):
                    keep = jj - max(k, m) + 1
                    report, lv = self._convergence(k, m, jm, both, None, rtol)
                    # the margin: levels converged beyond those kept, then the largest change
                    reports.append((report.n_converged - keep, -report.change[:keep].max(), report))
                    plus, minus = lv[: len(p), :keep], lv[len(p) :, :keep]
                    for kk, mm, arr in (
                        (k, m, plus),
                        (k, -m, minus),
                        (-k, -m, plus),
                        (-k, m, minus),
                    ):
                        blocks[(kk, mm)] = arr
            margin, _, worst = min(reports, key=lambda r: (r[0], r[1]))
            if margin >= 0 or not growing:
                break
            if jm >= 2000:
                raise NumericalError(
                    f"the Stark map up to J = {jj} did not converge to rtol = {rtol} with "
                    f"J_max = {jm}: the strengths are too large for the basis"
                )
            jm += max(10, jm // 2)
        return StarkMap(strength=p, J=jj, blocks=dict(sorted(blocks.items())), convergence=worst)

    # -- the strong-field limit and the classical top --------------------------------------------

    def pendular_levels(self, K: int, M: int, n: ArrayLike, strength: float) -> FloatOrArray:
        """The pendular (strong-field) limit of the levels of the (K, M) block (J): the top
        librates about the bottom of the potential as a two-dimensional harmonic oscillator,

        ``E = -|P| + hbar omega (2 n + |M - s K| + 1) + hbar^2 K^2 / (2 I3)``,
        ``omega = sqrt(|P| / I1)``,

        s = +1 where P < 0 (the bottom at theta = 0), -1 where P > 0 (at theta = pi); ``n`` =
        0, 1, ... numbers the levels of the block from the lowest. Exact to O(B) (B =
        hbar^2/(2 I1)): relatively ``~(B / |P|)^(1/2)``. Source: expand ``P cos(theta)`` and the
        centrifugal term ``(M - K cos theta)^2 / sin^2 theta`` about the bottom (Friedrich and
        Herschbach, Z. Phys. D 18 (1991) 153, for K = 0).

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
        >>> top.pendular_levels(K=1, M=1, n=[0, 1], strength=-1e4).tolist()
        [-9899.0, -9699.0]
        >>> [round(float(x), 1) for x in top.levels(1, 1, 400, -1e4)[:2]]
        [-9899.2, -9699.7]
        """
        k, m = _quantum_number("K", K), _quantum_number("M", M)
        p = real("strength", strength)
        if p == 0:
            raise ParameterError("strength = 0.0 is not allowed: the pendular limit needs P != 0")
        nn = np.asarray(n)
        if nn.dtype.kind not in "iu" or (nn < 0).any():
            raise ParameterError(f"n = {n!r} is not allowed: it must be integers >= 0")
        s = 1 if p < 0 else -1
        omega_hbar = self._hbar * math.sqrt(abs(p) / self._I1)
        e = (
            -abs(p)
            + omega_hbar * (2 * nn + abs(m - s * k) + 1)
            + self._hbar**2 * k * k / (2 * self._I3)
        )
        return float(e) if e.ndim == 0 else e.astype(np.float64)

    def nutation_action(self, K: int, M: int, energy: float, strength: float) -> float:
        """The classical nutation action ``(1/2 pi) closed-integral p_theta d theta`` (J s) of
        the Lagrange top in the potential ``strength * cos(theta)`` with ``Mz = M hbar``,
        ``M3 = K hbar`` at total ``energy`` (J); 0 below the bottom of the well.

        Computed from the exact classical solution: the turning points (roots of the gyro
        cubic) and complete elliptic integrals of the first, second and third kinds (core:
        ``quantum/ebk.rs``).

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
        >>> round(top.nutation_action(K=1, M=2, energy=20.0, strength=0.0), 12)  # L - max(|K|, |M|)
        4.244997998398
        """
        return self._native.nutation_action(
            _quantum_number("K", K), _quantum_number("M", M), real("energy", energy),
            real("strength", strength),
        )  # fmt: skip

    def ebk_levels(self, K: int, M: int, n: int, strength: ArrayLike) -> FloatOrArray:
        """Semiclassical (EBK) energy (J) of the level with ``n`` nutation quanta of the (K, M)
        block: ``nutation_action(K, M, E, strength) = (n + 1/2) hbar`` solved for E, at each
        strength. It correlates with the quantum level ``J = n + max(|K|, |M|)``, the n-th of
        :meth:`levels`. For the free top it is ``hbar^2 (J + 1/2)^2 / (2 I1) + ...``: the
        quantum level plus ``hbar^2 / (8 I1)``. ``|strength|`` may be at most ``10^12 B``
        (B = hbar^2/(2 I1)): beyond, the turning points come within round-off of the poles.

        Examples
        --------
        >>> from kreisel.quantum import SymmetricTop
        >>> top = SymmetricTop(I1=1.0, I3=0.5, hbar=1.0)
        >>> top.ebk_levels(K=0, M=0, n=3, strength=0.0)  # (3 + 1/2)^2 / 2
        6.125
        >>> q = top.levels(K=1, M=1, J_max=60, strength=50.0)[10]
        >>> e = top.ebk_levels(K=1, M=1, n=10, strength=50.0)
        >>> bool(abs(e - q) / abs(q) < 1e-3)
        True
        """
        k, m = _quantum_number("K", K), _quantum_number("M", M)
        nn = _quantum_number("n", n)
        p, scalar = _strengths(strength)
        out = self._native.ebk_energy(k, m, nn, p)
        return float(out[0]) if scalar else out

    def _convergence(self, K, M, J_max, p, J_check, rtol):
        """(the Convergence report, the levels at J_max)."""
        jm = _quantum_number("J_max", J_max)
        if J_check is None:
            jc = jm + max(10, jm // 4)
        else:
            jc = _quantum_number("J_check", J_check)
            if jc <= jm:
                raise ParameterError(f"J_check = {jc} is not allowed: it must be > J_max = {jm}")
        r = real("rtol", rtol)
        if not r > 0:
            raise ParameterError(f"rtol = {r!r} is not allowed: it must be > 0")
        small = self.levels(K, M, jm, p)
        big = self.levels(K, M, jc, p)[:, : small.shape[1]]
        change = np.abs(big - small).max(axis=0) if len(p) else np.zeros(small.shape[1])
        tol = r * (self._native.b + (float(np.abs(p).max()) if len(p) else 0.0))
        bad = change > tol
        n_ok = int(np.argmax(bad)) if bad.any() else len(change)
        report = Convergence(J_max=jm, J_check=jc, change=change, tolerance=tol, n_converged=n_ok)
        return report, small
