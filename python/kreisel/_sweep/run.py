"""One task of a sweep: the runs of some swept values simulated (or analysed), reduced to
their summaries. It runs on a Dask worker as well as here: it needs kreisel only."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import _config
from .._errors import ParameterError
from .spec import CATEGORIES, MODE_ERROR, MOTION_KINDS, _compose, _where, part_summary

LYAPUNOV_D0 = 1e-9
LYAPUNOV_DIRECTION = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0)


def compute_chunk(spec: dict, values: dict, threads=None) -> dict:
    """Simulates the runs of one chunk and returns their summaries as flat arrays, with
    ``errors`` {position: message} for runs that could not start or failed.

    ``spec`` is :meth:`SweepSpec.as_dict`, ``values`` the swept values of each run.
    """
    from .._batch import _lyapunov_many, _many_raw

    kind = spec["kind"]
    n = len(next(iter(values.values())))
    state_of = _play_packed if kind == "play" else (lambda m, s: _config._state(kind, m, s, ""))
    models, states, where, errors = [], [], [], {}
    # one top per combination of the swept top parameters
    cache = {}
    of_top = [k for k in values if _where(kind, k)[0] != "state"]
    of_state = [k for k in values if k not in of_top]
    for i in range(n):
        key = tuple(float(values[k][i]) for k in of_top)
        _, state = _compose(kind, {}, spec["state"], {k: values[k][i] for k in of_state})
        try:
            if key not in cache:
                top, _ = _compose(kind, spec["top"], {}, dict(zip(of_top, key)))
                cache[key] = _config._model(kind, top, "")
            model = cache[key]
            states.append(state_of(model, state))
            models.append(model)
            where.append(i)
        except ParameterError as e:
            errors[i] = str(e)
    sim = spec["simulation"]
    out: dict[str, Any] = {}
    kept = spec["keep"]
    for name in kept:
        out[name] = np.full(n, MODE_ERROR if name in CATEGORIES else np.nan)
    status: np.ndarray = np.full(n, 2, dtype=np.int8)
    if models and sim.get("exact"):
        for i, model, state in zip(where, models, states):
            try:
                a = model.analyse(state)
            except (ParameterError, ArithmeticError, RuntimeError) as e:
                errors[i] = str(e)
                continue
            for name in kept:
                v = getattr(a, "kind" if name == "motion_kind" else name)
                out[name][i] = MOTION_KINDS.index(v) if name == "motion_kind" else v
            status[i] = 1
    elif models:
        kw = dict(rtol=sim.get("rtol", 1e-10), atol=sim.get("atol", 1e-12),
                  method=sim.get("method", "dop853"), dt=sim.get("dt"))  # fmt: skip
        t_end = sim.get("t_end", _config.DEFAULT_T_END[kind])
        kept_here = [k for k in kept if k != "lyapunov"]
        res: Any = None
        if kept_here:
            # every model the same way: native models and flat states to the core's batch
            natives = [m._native_model() for m in models]
            flat = [_flat(m, st) for m, st in zip(models, states)]
            res = _many_raw(natives, flat, t_end, kw["method"], kw["rtol"], kw["atol"],
                            kw["dt"], spec["inversion_level"], threads, False)  # fmt: skip
        idx = np.array(where)
        # a run fails if any of its computations does (the first message is kept)
        messages = [res["errors"]] if res is not None else []
        if "lyapunov" in kept:
            lam, lam_errors = _lyapunov_many(
                models, states, t_end, tau=spec["lyapunov_tau"], d0=LYAPUNOV_D0,
                direction=LYAPUNOV_DIRECTION, rtol=kw["rtol"], atol=kw["atol"], threads=threads,
            )  # fmt: skip
            out["lyapunov"][idx] = lam
            messages.append(lam_errors)
        res_errors = [next((m for m in ms if m), None) for ms in zip(*messages)]
        for name in kept_here:
            # categories come as the core's codes (MODE_ERROR where a run failed); a part's
            # touchdown by its name is the core's by its position
            core = name if name in res else part_summary(name, spec["top"])
            out[name][idx] = res[core]
        for j, msg in enumerate(res_errors):
            if msg is None:
                status[where[j]] = 1
            else:
                errors[where[j]] = msg
    for name in kept:
        if name in CATEGORIES:
            out[name] = out[name].astype(np.int8)
        elif name == "steps":
            out[name] = np.nan_to_num(out[name], nan=-1).astype(np.int64)
    out["status"] = status
    out["errors"] = errors
    return out


def _flat(model, state):
    """The flat native state of a packed play-top state or of a heavy top's state object."""
    if isinstance(state, tuple):
        return [x for part in state for x in part]
    return model._native_state(state)


_PLAY_STATE = ("theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot")


def _play_packed(model, state: dict):
    """The packed contact (or dropped) state of a play top from a [state] table: what
    ``model.state(**state)`` gives, with the same checks, without the objects around it."""
    unknown = set(state) - {*_PLAY_STATE, "vx", "vy", "height"}
    if unknown or "theta" not in state:
        return model._check(_config._state("play", model, state, ""))  # its messages
    try:
        e = [float(state.get(k, 0.0)) for k in _PLAY_STATE]
        h = state.get("height")
        return model._native.state_from_euler(
            e, float(state.get("vx", 0.0)), float(state.get("vy", 0.0)),
            None if h is None else float(h),
        )  # fmt: skip
    except ParameterError:
        raise
    except (TypeError, ValueError) as err:
        raise ParameterError(str(err)) from None
