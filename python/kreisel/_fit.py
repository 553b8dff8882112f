"""``kreisel.fit``: a top's parameters and initial state from recordings, with honest errors."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _fit_model as fm
from ._errors import FitWarning, KreiselError, ParameterError
from ._observations import Observations
from ._play import PlayTop
from ._simulate import simulate
from ._validate import real

if TYPE_CHECKING:
    from ._trajectory import Trajectory

JACOBIANS = ("auto", "sensitivities", "finite-differences")
# relative step of the central differences (in log coordinates: the relative change)
FD_STEP = 1e-5
# a direction of the scaled Jacobian with a singular value below this share of the largest
# is one the data cannot see
NULL_RCOND = 1e-6

# How many standard deviations of chi2/dof above 1 a fit's misfit may lie before the fit
# warns that its errors are not to be trusted.
MISFIT_SIGMAS = 5.0


class FitResult:
    """What :func:`fit` found: estimates, their errors and correlations, and the fitted run.

    Attributes
    ----------
    values, errors : dict
        Free name -> estimate and standard error, in the units of the top and state (a vector
        name such as ``"com"`` or ``"omega"`` maps to an array). Where the data tell only
        combinations apart, the names involved have error ``inf`` and the identifiable
        combinations (``"m g l / I1"``) are entries of their own.
    parameters : list of str
        The scalar parameters in the order of ``covariance`` (``"com[2]"``, ...).
    covariance, correlation : ndarray, shape (p, p)
        Of the scalar parameters (NaN along directions the data cannot see).
    residuals : list of ndarray
        model - data for each observation set, shape (n, k), in its units (NaN where the data
        are missing).
    trajectory : Trajectory
        The fitted run, sampled at every observation time.
    chi2 : float
        Sum of the squared residuals over sigma (sigma = 1 where it was not given).
    dof : int
        Samples minus free parameters.
    top, state
        The fitted top and initial state.
    notes : list of str
        How the errors were obtained and what the data cannot tell.
    observations : list of Observations
    jacobian : str
        ``"sensitivities"`` or ``"finite-differences"``.
    success : bool, nfev : int
        The solver's report.

    Examples
    --------
    A heavy top whose centre of mass is sought from its body rates (the data fix only
    m com / I, so the mass is kept as given):

    >>> import numpy as np
    >>> from kreisel import HeavyTop, Observations, fit, simulate
    >>> true = HeavyTop(I1=1.0, I2=2.0, I3=3.0, m=1.0, com=[0.0, 0.0, 0.1])
    >>> state = true.state(theta=0.3, psi_dot=5.0)
    >>> run = simulate(true, state, 2.0, t_eval=np.linspace(0.0, 2.0, 41))
    >>> guess = HeavyTop(I1=1.0, I2=2.0, I3=3.0, m=1.0, com=[0.0, 0.0, 0.12])
    >>> res = fit(guess, state, Observations(run.t, run.omega, "body_rates", sigma=1e-3),
    ...           free=["com"])
    >>> (np.round(res.values["com"], 6) + 0.0).tolist(), res.parameters
    ([0.0, 0.0, 0.1], ['com[0]', 'com[1]', 'com[2]'])
    """

    def __init__(self, **kw: Any) -> None:
        self.values: dict[str, Any] = kw["values"]
        self.errors: dict[str, Any] = kw["errors"]
        self.parameters: list[str] = kw["parameters"]
        self.covariance: np.ndarray = kw["covariance"]
        self.correlation: np.ndarray = kw["correlation"]
        self.residuals: list[np.ndarray] = kw["residuals"]
        self.trajectory: Trajectory = kw["trajectory"]
        self.chi2: float = kw["chi2"]
        self.dof: int = kw["dof"]
        self.top = kw["top"]
        self.state = kw["state"]
        self.notes: list[str] = kw["notes"]
        self.observations: list[Observations] = kw["observations"]
        self.jacobian: str = kw["jacobian"]
        self.success: bool = kw["success"]
        self.nfev: int = kw["nfev"]
        self._predictions: list[np.ndarray] = kw["predictions"]

    def __repr__(self) -> str:
        parts = []
        for k, v in self.values.items():
            e = self.errors[k]
            if np.ndim(v):
                parts.append(f"{k}=[{', '.join(f'{a:.6g}±{b:.2g}' for a, b in zip(v, e))}]")
            else:
                parts.append(f"{k}={v:.6g}±{e:.2g}")
        return f"FitResult({', '.join(parts)}, chi2={self.chi2:.4g}, dof={self.dof})"

    def summary(self) -> str:
        """The estimates with their standard errors, chi^2 / dof and the notes, as text.

        Examples
        --------
        >>> import numpy as np
        >>> import kreisel
        >>> top = kreisel.LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
        >>> t = np.linspace(0.0, 0.5, 51)
        >>> s = top.state(theta=0.5, psi_dot=150.0)
        >>> obs = kreisel.Observations(t, kreisel.simulate(top, s, 0.5, t_eval=t).theta,
        ...                            "euler_angles", columns=["theta"], sigma=1e-3)
        >>> print(kreisel.fit(top, s, obs, free=["theta"]).summary().splitlines()[0])
        theta = 0.5 +- 0.000... (1 sigma)
        """
        lines = []
        for k, v in self.values.items():
            e = self.errors[k]
            if np.ndim(v):
                for i, (a, b) in enumerate(zip(v, e)):
                    lines.append(f"{k}[{i}] = {a:.6g} +- {b:.2g} (1 sigma)")
            else:
                lines.append(f"{k} = {v:.6g} +- {e:.2g} (1 sigma)")
        lines.append(f"chi2 = {self.chi2:.6g}, dof = {self.dof}")
        return "\n".join(lines + self.notes)

    def plot(self, axes: Any = None) -> np.ndarray:
        """Data, fit and residuals of each observation set: one column of two axes per set
        (top: data as dots, the fitted model as lines; bottom: model - data). Returns the
        axes, shape (2, number of sets).

        Examples
        --------
        >>> import numpy as np
        >>> from kreisel import HeavyTop, Observations, fit, simulate
        >>> top = HeavyTop(I1=1.0, I2=2.0, I3=3.0, m=1.0, com=[0.0, 0.0, 0.1])
        >>> s = top.state(theta=0.3, psi_dot=5.0)
        >>> run = simulate(top, s, 1.0, t_eval=np.linspace(0.0, 1.0, 21))
        >>> obs = Observations(run.t, run.omega, "body_rates")
        >>> fit(top, s, obs, free=["psi_dot"]).plot().shape
        (2, 1)
        """
        from ._plot_base import _pyplot

        n = len(self.observations)
        if axes is None:
            plt = _pyplot()
            fig, axes = plt.subplots(2, n, figsize=(5.5 * n, 5.5), sharex="col", squeeze=False,
                                     gridspec_kw={"height_ratios": [3, 1.3]})  # fmt: skip
        axes = np.asarray(axes).reshape(2, n)
        for j, (obs, pred, res) in enumerate(
            zip(self.observations, self._predictions, self.residuals)
        ):
            top, bottom = axes[0, j], axes[1, j]
            for c, name in enumerate(obs.columns):
                color = f"C{c}"
                top.plot(obs.t, obs.values[:, c], ".", ms=2.5, color=color, alpha=0.5,
                         label=f"{name} (data)")  # fmt: skip
                top.plot(obs.t, pred[:, c], "-", lw=1.0, color=color, label=f"{name} (fit)")
                bottom.plot(obs.t, res[:, c], ".", ms=2.0, color=color)
            bottom.axhline(0.0, color="0.3", lw=0.8)
            top.set(title=obs.name, ylabel=f"{obs.kind.replace('_', ' ')} ({obs.unit})")
            bottom.set(xlabel="t (s)", ylabel=f"model - data ({obs.unit})")
            top.legend(fontsize="small", ncol=2)
        return axes


def fit(
    top: Any,
    state: Any,
    observations: Observations | Sequence[Observations],
    free: Sequence[str],
    bounds: dict[str, Any] | None = None,
    loss: str = "linear",
    *,
    jacobian: str = "auto",
    start: dict[str, Any] | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_nfev: int | None = None,
) -> FitResult:
    """Fits a top's parameters and initial state to recordings by least squares.

    The residuals are (model - data) / sigma at every sample that is not NaN, the model a
    run of :func:`simulate` from ``state`` at t = 0; ``scipy.optimize.least_squares``
    (trust-region reflective) minimises their sum of squares. Positive quantities (moments of
    inertia, m, g, rho, mu) are fitted as their logarithms and reported in the top's units.

    Parameters
    ----------
    top : HeavyTop, LagrangeTop or PlayTop
        The top, with every fixed parameter as it is and the free ones at their start values.
    state : EulerState, RigidState or PlayState
        The initial state (an EulerState for a PlayTop gives it through ``top.state``).
    observations : Observations or list of Observations
    free : sequence of str
        What to fit: constructor parameters of the top (HeavyTop ``I1 I2 I3 m com g``;
        LagrangeTop ``I1 I3 m l g``; PlayTop ``m A C s rho g mu restitution ...``; the
        ``viscous drag dry`` coefficients of a top's :class:`PivotDamping`), fields of the
        state (EulerState ``theta phi psi theta_dot phi_dot psi_dot``; RigidState
        ``orientation``, a body-frame rotation vector, and ``omega``), and
        ``sensor_rotation`` for body rates given in a sensor frame. A vector name takes all
        its components; ``"com[2]"`` takes one.
    bounds : dict, optional
        Name -> (low, high) in the name's units (arrays for vector names). Bounds change the
        solver to its reflective variant, which can stop in a local minimum: prefer a good
        start. (theta and -theta, with phi and psi turned by pi, are one orientation: a fit
        may return either.)
    loss : str
        ``least_squares``' loss: ``"linear"`` (default: Gaussian errors) or a robust one
        (``"soft_l1"``, ``"huber"``, ``"cauchy"``, ``"arctan"``); the covariance is the
        Gauss-Newton one either way.
    jacobian : str
        ``"auto"`` (the core's forward sensitivities where :func:`simulate` offers them for
        a top on a pivot, else finite differences), ``"sensitivities"`` (also a PlayTop
        started from an EulerState: its run must not reach a tangential impact or a ring
        lying flat) or ``"finite-differences"`` (central, relative step 1e-5).
    start : dict, optional
        Start values of free names, overriding those of ``top``, ``state`` and the
        observations' ``rotation`` (e.g. ``{"sensor_rotation": earlier.values[...]}`` to go on
        from a fit of a shorter window).
    rtol, atol : float
        Tolerances of the runs (DOP853).
    max_nfev : int, optional
        Most evaluations of the residuals.

    Returns
    -------
    FitResult

    The covariance of the estimate is (J^T J)^-1 with J the Jacobian of the residuals at the
    solution, scaled by chi^2 / dof when some sigma was not given. Directions of J that the
    data cannot see (singular values below 1e-6 of the largest, in log coordinates) are
    reported with a :class:`FitWarning` that names the combinations which are identifiable
    (for a Lagrange top seen through its angles: ``m g l / I1`` and ``I3 / I1``).
    Source: theory: fitting a top to a recording.

    Examples
    --------
    >>> import numpy as np
    >>> import kreisel
    >>> top = kreisel.LagrangeTop(I1=0.0125, I3=0.005, m=0.5, l=0.1)
    >>> s = top.state(theta=0.5, psi_dot=150.0)
    >>> t = np.linspace(0.0, 0.5, 51)
    >>> obs = kreisel.Observations(t, kreisel.simulate(top, s, 0.5, t_eval=t).omega,
    ...                            "body_rates", sigma=0.01)
    >>> guess = kreisel.LagrangeTop(I1=0.0125, I3=0.0045, m=0.5, l=0.1)
    >>> res = kreisel.fit(guess, s, obs, free=["I3", "theta"])
    >>> round(res.values["I3"], 6), res.chi2 < 1e-6
    (0.005, True)
    """
    from scipy.optimize import least_squares

    obs_list = _observation_list(observations)
    if jacobian not in JACOBIANS:
        raise ParameterError(
            f"jacobian = {jacobian!r} is not allowed: use one of {', '.join(map(repr, JACOBIANS))}"
        )
    rtol, atol = real("rtol", rtol), real("atol", atol)
    spec = fm.top_spec(top)
    s_sizes, s_vals, make_state, s_sens = fm.state_spec(top, state)
    rot0 = np.array(next((o.rotation for o in obs_list if o.frame == "sensor"), np.zeros(3)))
    params = _params(free, spec, s_sizes, s_vals, obs_list, rot0)
    if start:
        _apply_start(start, params, spec, s_vals, rot0)
        params = _params(free, spec, s_sizes, s_vals, obs_list, rot0)
    problem = _Problem(top, spec, make_state, s_vals, params, obs_list, rtol, atol)
    problem.rot0 = rot0
    mode = _jacobian_mode(jacobian, top, spec, s_sens, params)
    problem.mode = mode
    problem.loss = loss

    x0 = np.array([np.log(p.value) if p.log else p.value for p in params])
    lo, hi = _bounds(bounds, params, x0)
    problem.residuals(x0)  # a start that cannot be simulated fails here, with its message
    sol = least_squares(
        problem.residuals, x0, jac=problem.jacobian, bounds=(lo, hi), loss=loss,
        x_scale="jac", max_nfev=max_nfev, method="trf",
    )  # fmt: skip
    return problem.result(sol)


def _observation_list(observations) -> list[Observations]:
    items = [observations] if isinstance(observations, Observations) else observations
    try:
        items = list(items)
    except TypeError:
        items = [items]
    bad = [o for o in items if not isinstance(o, Observations)]
    if not items or bad:
        raise ParameterError(
            f"observations = {observations!r} is not allowed: give a kreisel.Observations or a "
            "non-empty list of them"
        )
    return items


def _free_dict(what: str, mapping, params, value: str):
    """The items of ``mapping`` (an argument named ``what``: free name -> ``value``), each
    name checked against the free names."""
    if not isinstance(mapping, dict):
        raise ParameterError(f"{what} = {mapping!r} is not allowed: give a dict name -> {value}")
    names = {p.key for p in params} | {p.name for p in params}
    for name in mapping:
        if name not in names:
            raise ParameterError(
                f"{what} names {name!r}, which is not allowed: it is not a free name ("
                f"{', '.join(sorted(names))})"
            )
    return mapping.items()


def _apply_start(start, params, spec, s_vals, rot0) -> None:
    """Puts the start values of free names into the top's and state's values (in place)."""
    for name, value in _free_dict("start", start, params, "value"):
        key = name.partition("[")[0]
        target = spec.kwargs if key in spec.kwargs else (s_vals if key in s_vals else None)
        comps = [p for p in params if p.key == key and (p.name == name or name == key)]
        for p in comps:
            v = value if p.index is None or name != key else np.asarray(value, float)[p.index]
            v = real(f"start[{name!r}]", v)
            if target is None:
                rot0[p.index] = v
            elif p.index is None:
                target[key] = v
            else:
                target[key][p.index] = v


def _params(free, spec: fm.TopSpec, s_sizes, s_vals, obs_list, rotation) -> list[fm.Param]:
    if isinstance(free, str) or not isinstance(free, Sequence) or not free:
        raise ParameterError(
            f"free = {free!r} is not allowed: give a non-empty list of names, e.g. ['I3', 'theta']"
        )
    sizes = {**{k: ("top", n) for k, n in spec.sizes.items()},
             **{k: ("state", n) for k, n in s_sizes.items()}}  # fmt: skip
    if any(o.kind == "body_rates" and o.frame == "sensor" for o in obs_list):
        sizes["sensor_rotation"] = ("sensor", 3)
    allowed = []
    for k, (_, n) in sizes.items():
        allowed.append(k)
        if n is not None:
            allowed.extend(f"{k}[{i}]" for i in range(n))
    out: list[fm.Param] = []
    for name in free:
        if not isinstance(name, str) or name not in allowed:
            raise ParameterError(
                f"free contains {name!r}, which is not allowed: the free names here are "
                f"{', '.join(a for a in allowed if '[' not in a)} (a vector's component as "
                "'com[2]')"
            )
        key, _, rest = name.partition("[")
        group, n = sizes[key]
        indices: list[int | None] = [None]
        if n is not None:
            indices = [int(rest[:-1])] if rest else list(range(n))
        for i in indices:
            label = key if i is None else f"{key}[{i}]"
            if any(p.name == label for p in out):
                raise ParameterError(f"free names {label!r} twice, which is not allowed")
            if group == "top":
                v = spec.kwargs[key] if i is None else spec.kwargs[key][i]
                sens = label if key in spec.sensitive else None
            elif group == "state":
                v = s_vals[key] if i is None else s_vals[key][i]
                sens = label if key in s_sizes else None
            else:
                v, sens = float(rotation[i]), None
            log = key in fm.POSITIVE and v > 0
            out.append(fm.Param(label, key, i, group, float(v), log, sens))
    return out


def _jacobian_mode(jacobian, top, spec, s_sens, params) -> str:
    dynamic = [p for p in params if p.group != "sensor"]
    supported = all(p.key in spec.sensitive or p.key in s_sens for p in dynamic)
    if jacobian == "sensitivities" and not supported:
        why = ("the core's sensitivities cover heavy and Lagrange tops on a fixed pivot "
               "(viscous and drag damping included) and tops on a floor started from an "
               "EulerState, not moving pivots, dry friction at a pivot or a PlayState's "
               "omega")  # fmt: skip
        raise ParameterError(
            f"jacobian = 'sensitivities' is not allowed here: {why}; use 'finite-differences'"
        )
    if jacobian == "auto":
        # a top on a floor keeps finite differences unless asked: its sensitivities stop at
        # events they do not cross (a tangential impact, a ring lying flat)
        play = isinstance(top, PlayTop)
        return "sensitivities" if supported and not play else "finite-differences"
    return jacobian


def _bounds(bounds, params, x0):
    lo, hi = np.full(len(x0), -np.inf), np.full(len(x0), np.inf)
    if bounds is None:
        return lo, hi
    for name, pair in _free_dict("bounds", bounds, params, "(low, high)"):
        try:
            a, b = pair
        except (TypeError, ValueError):
            raise ParameterError(
                f"bounds[{name!r}] = {pair!r} is not allowed: give (low, high)"
            ) from None
        for j, p in enumerate(params):
            if name not in (p.key, p.name):
                continue
            comp = p.index if (name == p.key and p.index is not None) else None
            aa = float(np.asarray(a)[comp] if comp is not None and np.ndim(a) else a)
            bb = float(np.asarray(b)[comp] if comp is not None and np.ndim(b) else b)
            if not aa < bb:
                raise ParameterError(
                    f"bounds[{name!r}] = ({aa}, {bb}) is not allowed: low must be < high"
                )
            if p.log:
                lo[j] = np.log(aa) if aa > 0 else -np.inf
                hi[j] = np.log(bb) if bb > 0 else -np.inf
            else:
                lo[j], hi[j] = aa, bb
            if not lo[j] <= x0[j] <= hi[j]:
                raise ParameterError(
                    f"bounds[{name!r}] = ({aa}, {bb}) is not allowed: the start {p.name} = "
                    f"{p.value} lies outside"
                )
    return lo, hi


class _Failed(Exception):
    """A trial point the model refuses (a parameter out of its range, a run that stops)."""


class _Problem:
    """The residuals and their Jacobian in the fit's coordinates (logs of positive
    quantities), with the last run kept (least_squares asks for both at one point)."""

    def __init__(self, top, spec, make_state, s_vals, params, obs_list, rtol, atol):
        self.top, self.spec, self.make_state, self.s_vals = top, spec, make_state, s_vals
        self.params, self.obs, self.rtol, self.atol = params, obs_list, rtol, atol
        self.times = np.unique(np.concatenate([o.t for o in obs_list]))
        self.rows = [np.asarray(np.searchsorted(self.times, o.t)) for o in obs_list]
        self.masks = [~np.isnan(o.values) for o in obs_list]
        self.play = isinstance(top, PlayTop)
        need = {
            "body_rates": ["omega"],
            "axis_tip": ["theta", "phi"] + (["com"] if self.play else []),
        }
        self.columns = sorted({c for o in obs_list for c in need.get(o.kind, o.columns)})
        self.mode = "finite-differences"
        self.loss = "linear"
        self.rot0 = np.zeros(3)
        self._size: int | None = None
        self._cache: dict[bytes, tuple] = {}
        self.nfev = 0

    # -- the model at a point x -----------------------------------------------------------
    def user_values(self, x: np.ndarray) -> np.ndarray:
        return np.array([np.exp(v) if p.log else v for p, v in zip(self.params, x)])

    def build(self, x):
        """(top, state, sensor rotation) at x."""
        v = self.user_values(x)
        tkw = {k: (list(val) if isinstance(val, list) else val)
               for k, val in self.spec.kwargs.items()}  # fmt: skip
        skw = {k: (list(val) if isinstance(val, list) else val) for k, val in self.s_vals.items()}
        rot = self.rot0.copy()
        for p, val in zip(self.params, v):
            target = {"top": tkw, "state": skw}.get(p.group)
            if target is None:
                rot[p.index] = val
            elif p.index is None:
                target[p.key] = float(val)
            else:
                target[p.key][p.index] = float(val)
        try:
            trial = self.spec.make(tkw)
            return trial, self.make_state(skw, trial), rot
        except KreiselError as e:
            raise _Failed(str(e)) from None

    def run(self, x, with_sens: bool):
        key = x.tobytes() + bytes([with_sens])
        if key in self._cache:
            return self._cache[key]
        top, state, rot = self.build(x)
        kw: dict[str, Any] = dict(t_eval=self.times, rtol=self.rtol, atol=self.atol)
        names = [p.sens for p in self.params if p.group != "sensor"]
        if with_sens:
            kw["sensitivities"] = names
        try:
            traj = simulate(top, state, float(self.times[-1]), **kw)
        except KreiselError as e:
            raise _Failed(str(e)) from None
        if len(traj.t) != len(self.times):
            raise _Failed(f"the run stopped at t = {traj.t[-1]:g} s ({traj.status})")
        # only the columns the observations need: the Euler angles are derived on request
        cols = {c: np.asarray(traj[c]) for c in self.columns}
        sens = traj.sensitivities if with_sens else None
        out = (traj, cols, sens, rot, top, state)
        self._cache = {key: out}  # one point at a time
        self.nfev += 1
        return out

    def _residual_from(self, cols, rot) -> np.ndarray:
        out = []
        for o, idx, mask in zip(self.obs, self.rows, self.masks):
            r = fm.difference(fm.predict(cols, o, idx, rot, self.play), o) / o.sigma
            out.append(r[mask])
        return np.concatenate(out)

    def residuals(self, x: np.ndarray) -> np.ndarray:
        try:
            _, cols, _, rot, _, _ = self.run(x, self.mode == "sensitivities")
        except _Failed:
            if self._size is None:
                raise
            # a point the model refuses costs more than any it accepts
            return np.full(self._size, 1e10)
        r = self._residual_from(cols, rot)
        self._size = len(r)
        return r

    # -- the Jacobian ------------------------------------------------------------------------
    def jacobian(self, x: np.ndarray) -> np.ndarray:
        if self.mode == "sensitivities":
            return self._jacobian_sensitivities(x)
        return self._jacobian_differences(x)

    def _jacobian_sensitivities(self, x):
        _, cols, sens, rot, _, _ = self.run(x, True)
        v = self.user_values(x)
        J = np.empty((self._size, len(self.params)))
        for j, p in enumerate(self.params):
            if p.group == "sensor":
                J[:, j] = self._rotation_column(x, j, cols, rot)
                continue
            col = []
            for o, idx, mask in zip(self.obs, self.rows, self.masks):
                d = fm.predict_derivative(sens[p.sens], cols, o, idx, rot, self.play)
                d = d / o.sigma
                col.append(d[mask])
            J[:, j] = np.concatenate(col) * (v[j] if p.log else 1.0)
        return J

    def _rotation_column(self, x, j, cols, rot):
        h = 1e-6
        r1, r2 = rot.copy(), rot.copy()
        r1[self.params[j].index] += h
        r2[self.params[j].index] -= h
        return (self._residual_from(cols, r1) - self._residual_from(cols, r2)) / (2 * h)

    def step(self, x, j) -> float:
        """The central-difference step of parameter j (relative to its size)."""
        p = self.params[j]
        if p.log:
            return FD_STEP
        if p.group == "top":
            ref = self.spec.kwargs[p.key]
            size = float(np.linalg.norm(ref)) if p.index is not None else abs(ref)
            return FD_STEP * max(abs(x[j]), size, 1e-3)
        return FD_STEP * max(abs(x[j]), 1.0)

    def _jacobian_differences(self, x):
        _, cols, _, rot, _, _ = self.run(x, False)
        base = self._residual_from(cols, rot)
        J = np.empty((len(base), len(self.params)))
        for j, p in enumerate(self.params):
            if p.group == "sensor":
                J[:, j] = self._rotation_column(x, j, cols, rot)
                continue
            h = self.step(x, j)
            sides: list[np.ndarray | None] = []
            for sign in (1.0, -1.0):
                xs = x.copy()
                xs[j] += sign * h
                try:
                    _, c, _, r, _, _ = self.run(xs, False)
                    sides.append(self._residual_from(c, r))
                except _Failed:
                    sides.append(None)
            if sides[0] is not None and sides[1] is not None:
                J[:, j] = (sides[0] - sides[1]) / (2 * h)
            elif sides[0] is not None:
                J[:, j] = (sides[0] - base) / h
            elif sides[1] is not None:
                J[:, j] = (base - sides[1]) / h
            else:
                raise ParameterError(
                    f"{p.name} = {p.value} cannot be varied here: the model refuses both "
                    "neighbours of the current point"
                )
        return J

    # -- the result ---------------------------------------------------------------------------
    def result(self, sol) -> FitResult:
        x = sol.x
        J = self.jacobian(x)
        traj, cols, _, rot, top, state = self.run(x, False)
        r = self._residual_from(cols, rot)
        chi2 = float(r @ r)
        m, n = len(r), len(x)
        dof = m - n
        notes: list[str] = [f"Jacobian: {self.mode}; solver: {sol.message}"]
        values_x = self.user_values(x)
        if self.loss != "linear":
            notes.append(
                f"loss = {self.loss!r}: the covariance is the Gauss-Newton one of the plain "
                "squared residuals at the robust solution (approximate where points were "
                "down-weighted)"
            )
        if not sol.success:
            warnings.warn(f"the fit did not converge: {sol.message}", FitWarning, stacklevel=3)

        # covariance in the fit's coordinates, through the SVD (directions the data cannot
        # see are left out of the inverse and reported)
        norms = np.linalg.norm(J, axis=0)
        norms[norms == 0] = 1.0
        U, s, Vt = np.linalg.svd(J / norms, full_matrices=False)
        null = s < NULL_RCOND * s[0] if len(s) else np.zeros(0, bool)
        inv_s2 = np.where(null, 0.0, 1.0 / np.where(null, 1.0, s) ** 2)
        cov_x = (Vt.T * inv_s2) @ Vt / np.outer(norms, norms)
        unknown = [o.name for o in self.obs if not o.sigma_given]
        if unknown:
            factor = chi2 / dof if dof > 0 else np.nan
            cov_x = cov_x * factor
            notes.append(
                f"sigma not given for {', '.join(unknown)}: the covariance (J^T J)^-1 is scaled "
                f"by chi2/dof = {factor:.4g} (errors estimated from the scatter of the residuals)"
            )
        else:
            notes.append(
                "covariance (J^T J)^-1 with the given sigma (not scaled); chi2/dof = "
                f"{chi2 / dof if dof > 0 else float('nan'):.4g}"
            )
            # chi2/dof of a fit whose sigma and model are right is 1 +- sqrt(2/dof): far above
            # it, the errors (which assume both) are not to be trusted.
            spread = np.sqrt(2.0 / dof) if dof > 0 else np.inf
            if dof > 0 and chi2 / dof > 1.0 + MISFIT_SIGMAS * spread:
                text = (
                    f"the misfit is larger than the given sigma explains: chi2/dof = "
                    f"{chi2 / dof:.4g}, against 1 +- {spread:.2g} for the right model and "
                    "sigma: the fit may have stopped in a local minimum (start closer to the "
                    "data), or the model or sigma does not describe the data; the errors "
                    "assume both do"
                )
                notes.append(text)
                warnings.warn(text, FitWarning, stacklevel=3)
        # in the user's units: d v = v d(log v) for the positive quantities
        D = np.array([v if p.log else 1.0 for p, v in zip(self.params, values_x)])
        cov = cov_x * np.outer(D, D)
        err = np.sqrt(np.clip(np.diag(cov), 0, None))

        combos: dict[str, tuple[float, float]] = {}
        if null.any():
            null_dirs = (Vt[null].T / norms[:, None]).T  # rows: null directions in x
            involved = np.abs(null_dirs).max(axis=0) > 1e-3 * np.abs(null_dirs).max()
            for j in np.flatnonzero(involved):
                err[j] = np.inf
                cov[j, :] = cov[:, j] = np.nan
            combos = self._combinations(null_dirs, involved, x, values_x, cov_x)
            names = [self.params[j].name for j in np.flatnonzero(involved)]
            text = (
                f"the data cannot tell {', '.join(names)} apart ({int(null.sum())} direction(s) "
                "of the Jacobian are null): their values stay where the fit left them and their "
                "errors are inf; "
            )
            text += (
                "identifiable are " + ", ".join(combos) if combos
                else "no combination of them is identifiable"
            )  # fmt: skip
            notes.append(text)
            warnings.warn(text, FitWarning, stacklevel=3)
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = cov / np.outer(err, err)
        values: dict[str, Any] = {}
        errors: dict[str, Any] = {}
        sizes = {**self.spec.sizes, "orientation": 3, "omega": 3, "sensor_rotation": 3}
        for key in dict.fromkeys(p.key for p in self.params):
            comps = [j for j, p in enumerate(self.params) if p.key == key]
            whole = self.params[comps[0]].index is None or (
                [self.params[j].index for j in comps] == list(range(sizes.get(key) or 0))
            )
            if self.params[comps[0]].index is None:
                values[key], errors[key] = float(values_x[comps[0]]), float(err[comps[0]])
            elif whole:
                values[key], errors[key] = values_x[comps].copy(), err[comps].copy()
            else:
                for j in comps:
                    values[self.params[j].name] = float(values_x[j])
                    errors[self.params[j].name] = float(err[j])
        for name, (val, e) in combos.items():
            values[name], errors[name] = val, e

        preds = [fm.predict(cols, o, idx, rot, self.play) for o, idx in zip(self.obs, self.rows)]
        res = []
        for o, pr in zip(self.obs, preds):
            d = fm.difference(pr, o)
            d[np.isnan(o.values)] = np.nan
            res.append(d)
        return FitResult(
            values=values, errors=errors, parameters=[p.name for p in self.params],
            covariance=cov, correlation=corr, residuals=res, trajectory=traj, chi2=chi2,
            dof=dof, top=top, state=state, notes=notes, observations=self.obs,
            jacobian=self.mode, success=bool(sol.success), nfev=self.nfev, predictions=preds,
        )  # fmt: skip

    def _combinations(self, null_dirs, involved, x, values_x, cov_x):
        """The identifiable combinations of the names involved in the null directions, as
        monomials (log coordinates: a null direction of the logs is a product the data keep),
        with their value and standard error."""
        idx = np.flatnonzero(involved)
        # every involved parameter in relative (log) terms: d log|v| = dx for a log one,
        # dx / v for a linear one
        rel = []
        for j in idx:
            p = self.params[j]
            if p.log:
                rel.append(1.0)
            elif values_x[j] != 0:
                rel.append(values_x[j])
            else:
                return {}
        N = null_dirs[:, idx] / np.array(rel)  # null directions in log coordinates
        # the identifiable exponent vectors: the orthogonal complement of N
        _, s, vt = np.linalg.svd(N)
        rank = int((s > 1e-8 * s.max()).sum())
        A = vt[rank:]
        if len(A) == 0:
            return {}
        names = [self.params[j].name for j in idx]
        # denominators last: the transverse moment, else the free order
        order = sorted(range(len(idx)), key=lambda c: (names[c] in ("I1", "A"), c))
        A = _rref(A[:, order])
        out = {}
        for row in A:
            exps = np.zeros(len(idx))
            exps[order] = row
            fr = [Fraction(float(e)).limit_denominator(6) for e in exps]
            if any(abs(float(f) - e) > 1e-3 for f, e in zip(fr, exps)):
                continue
            label, g_power = _monomial(names, fr, self.top, {p.key for p in self.params})
            a = np.array([float(f) for f in fr])
            logv = float(np.sum(a * np.log(np.abs(values_x[idx]))))
            logv += g_power * float(np.log(self.top.g)) if g_power else 0.0
            # variance of sum a_j log|v_j| = sum a_j dx_j / rel_j
            g = np.zeros(len(x))
            g[idx] = a / np.array(rel)
            var = float(g @ cov_x @ g)
            val = float(np.exp(logv))
            out[label] = (val, val * np.sqrt(max(var, 0.0)))
        return out


def _rref(A: np.ndarray) -> np.ndarray:
    A = A.copy()
    rows, cols = A.shape
    r = 0
    for c in range(cols):
        if r == rows:
            break
        piv = r + int(np.argmax(np.abs(A[r:, c])))
        if abs(A[piv, c]) < 1e-9:
            continue
        A[[r, piv]] = A[[piv, r]]
        A[r] /= A[r, c]
        for i in range(rows):
            if i != r:
                A[i] -= A[i, c] * A[r]
        r += 1
    return A[:r]


def _monomial(names, exps, top, free_keys) -> tuple[str, float]:
    """``m g l / I1`` from names and exponents, and the power of the fixed g put into it: for
    a top on a pivot, a product of m and l (or com) is shown with the g it comes with (the
    torque m g l), and its value includes g."""
    num = [(n, e) for n, e in zip(names, exps) if e > 0]
    den = [(n, -e) for n, e in zip(names, exps) if e < 0]
    g_power = 0.0
    if "g" not in free_keys and hasattr(top, "g") and not isinstance(top, PlayTop):
        ns = [n for n, _ in num]
        if "m" in ns and ("l" in ns or any(n.startswith("com") for n in ns)):
            e = dict(num)["m"]
            num.insert(ns.index("m") + 1, ("g", e))
            g_power = float(e)

    def part(items):
        out = []
        for n, e in items:
            if e == 1:
                out.append(n)
            elif e.denominator == 1:
                out.append(f"{n}^{e.numerator}")
            else:
                out.append(f"{n}^({e})")
        return " ".join(out)

    if not num:
        return f"1 / ({part(den)})", g_power
    if len(den) > 1:
        return part(num) + f" / ({part(den)})", g_power
    return part(num) + (f" / {part(den)}" if den else ""), g_power
