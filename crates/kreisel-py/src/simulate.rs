//! Bindings of the one simulation stack: `simulate` and `many` take any native model the
//! same way, and `names` exports every public name the Python layer reads. Conversion only:
//! the rules are the core's.

use crate::driven::PyDrivenTop;
use crate::errors::IntoPyResult;
use crate::heavy::PyHeavyTop;
use crate::play::PyPlayTop;
use kreisel_core::models::heavy_top::driven::{Damping, DrivenRow, DrivenTop, Pivot};
use kreisel_core::models::heavy_top::HeavyTop;
use kreisel_core::models::heavy_top::RigidState;
use kreisel_core::models::play_top::simulate::{PartState, PlayRow};
use kreisel_core::models::play_top::{PlayTop, DIM};
use kreisel_core::simulate as core;
use kreisel_core::simulate::{
    batch, EventDef, EventKind, Model, RunInfo, Settings, Solution, UserFn, MODES, MOTION_KINDS,
    SUMMARY_FIELDS,
};
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::cell::RefCell;

/// A native model: what `simulate` and `many` accept.
#[derive(Clone)]
pub(crate) enum Native {
    Heavy(HeavyTop),
    Driven(DrivenTop),
    Play(PlayTop),
}

pub(crate) fn native(model: &Bound<'_, PyAny>) -> PyResult<Native> {
    if let Ok(t) = model.cast::<PyHeavyTop>() {
        return Ok(Native::Heavy(t.get().inner));
    }
    if let Ok(t) = model.cast::<PyDrivenTop>() {
        return Ok(Native::Driven(t.get().inner.clone()));
    }
    if let Ok(t) = model.cast::<PyPlayTop>() {
        return Ok(Native::Play(t.get().inner));
    }
    Err(pyo3::exceptions::PyTypeError::new_err(format!(
        "model must be a native HeavyTop, DrivenTop or PlayTop, not {}",
        model.get_type().name()?
    )))
}

/// A state of `model` from its flat numbers: (q, omega) for a heavy top, (q, omega, com,
/// com_velocity) for a play top.
pub(crate) fn heavy_state(py: Python<'_>, x: &[f64]) -> PyResult<RigidState> {
    let v: [f64; 7] = x.try_into().map_err(|_| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "a heavy top's state has 7 numbers (q, omega), not {}",
            x.len()
        ))
    })?;
    RigidState::new([v[0], v[1], v[2], v[3]], [v[4], v[5], v[6]]).py(py)
}

pub(crate) fn play_state(x: &[f64]) -> PyResult<[f64; DIM]> {
    if x.len() != DIM - 1 {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "a play top's state has {} numbers (q, omega, com, com_velocity), not {}",
            DIM - 1,
            x.len()
        )));
    }
    let mut y = [0.0; DIM];
    y[..DIM - 1].copy_from_slice(x);
    Ok(y)
}

/// An event as Python hands it: (name, kind, callable or None, value, direction, terminal).
pub(crate) type EventTuple = (String, String, Option<Py<PyAny>>, f64, i8, bool);

fn event_def((name, kind, _, value, direction, terminal): &EventTuple) -> PyResult<EventDef> {
    let kind = match kind.as_str() {
        "turning_points" => EventKind::TurningPoints,
        "theta_crossing" => EventKind::ThetaCrossing(*value),
        "inversion" => EventKind::Inversion(*value),
        "rest" => EventKind::Rest,
        "user" => EventKind::User,
        other => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "unknown event kind {other:?}"
            )))
        }
    };
    Ok(EventDef {
        name: name.clone(),
        kind,
        direction: *direction,
        terminal: *terminal,
    })
}

/// Asks Python now and then (every 256 calls) whether a signal (Ctrl-C) came in; a run
/// released from the interpreter stops at the next step when one did.
pub(crate) struct Signals {
    calls: u32,
    pub(crate) error: Option<PyErr>,
}

impl Signals {
    pub(crate) fn new() -> Self {
        Signals {
            calls: 0,
            error: None,
        }
    }
    pub(crate) fn keep_going(&mut self) -> bool {
        self.calls = self.calls.wrapping_add(1);
        if self.calls % 256 == 0 && self.error.is_none() {
            self.error = Python::attach(|py| py.check_signals().err());
        }
        self.error.is_none()
    }
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn settings(
    t_end: f64,
    method: String,
    rtol: f64,
    atol: f64,
    dt: Option<f64>,
    t_eval: Option<Vec<f64>>,
    events: &[EventTuple],
    reduced: bool,
) -> PyResult<Settings> {
    Ok(Settings {
        method,
        t_end,
        rtol,
        atol,
        dt,
        t_eval,
        events: events.iter().map(event_def).collect::<PyResult<_>>()?,
        reduced,
    })
}

/// Runs `model` from `s0`: with the interpreter held where Python event functions are
/// called (their exceptions end the run and are raised), else released.
fn run_model<M, F>(
    py: Python<'_>,
    model: M,
    s0: M::State,
    st: Settings,
    events: &[EventTuple],
    user_fn: F,
) -> PyResult<Solution<M::Row>>
where
    M: Model + Send,
    M::State: Send,
    M::Row: Send,
    F: Fn(Python<'_>, Py<PyAny>, f64, &M::State) -> PyResult<f64>,
{
    let funcs: Vec<Py<PyAny>> = events
        .iter()
        .filter(|e| e.1 == "user")
        .map(|e| {
            e.2.as_ref().map(|f| f.clone_ref(py)).ok_or_else(|| {
                pyo3::exceptions::PyValueError::new_err(format!("event {:?} has no function", e.0))
            })
        })
        .collect::<PyResult<_>>()?;
    if funcs.is_empty() {
        let (out, signals) = py.detach(move || {
            let mut signals = Signals::new();
            let out = core::simulate(&model, &s0, &st, &mut [], &mut |_| signals.keep_going());
            (out, signals)
        });
        if let Some(e) = signals.error {
            return Err(e);
        }
        return out.py(py);
    }
    let failure: RefCell<Option<PyErr>> = RefCell::new(None);
    let mut user: Vec<UserFn<'_, M::State>> = funcs
        .into_iter()
        .map(|f| {
            let (failure, user_fn) = (&failure, &user_fn);
            Box::new(move |t: f64, s: &M::State| {
                if failure.borrow().is_some() {
                    return 0.0;
                }
                match user_fn(py, f.clone_ref(py), t, s) {
                    Ok(v) => v,
                    Err(e) => {
                        *failure.borrow_mut() = Some(e);
                        0.0
                    }
                }
            }) as UserFn<'_, M::State>
        })
        .collect();
    let mut keep_going = |_t: f64| failure.borrow().is_none() && py.check_signals().is_ok();
    let out = core::simulate(&model, &s0, &st, &mut user, &mut keep_going);
    drop(user);
    if let Some(e) = failure.into_inner() {
        return Err(e);
    }
    py.check_signals()?;
    out.py(py)
}

/// The rows of a run, kept natively so that their diagnostics are computed only when asked
/// for (`columns`).
#[pyclass(name = "Run", module = "kreisel._core", frozen)]
pub struct PyRun {
    pub(crate) rows: Rows,
}

pub(crate) enum Rows {
    Heavy(HeavyTop, Vec<RigidState>),
    Driven(DrivenTop, Vec<DrivenRow>),
    Play(PlayTop, Vec<PlayRow>),
}

pub(crate) fn flat<const K: usize>(py: Python<'_>, v: &[[f64; K]]) -> PyResult<Py<PyAny>> {
    let n = v.len();
    let data = gather(n, K, v.iter().flat_map(|x| *x))?;
    Ok(data.into_pyarray(py).reshape([n, K])?.into_any().unbind())
}

/// The `rows * per_row` items of `it` in a vector: a `MemoryError` that says what to do,
/// not an abort, where the process cannot hold it (a long run under a limit on its memory).
pub(crate) fn gather<T>(
    rows: usize,
    per_row: usize,
    it: impl IntoIterator<Item = T>,
) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(rows * per_row).map_err(|_| {
        pyo3::exceptions::PyMemoryError::new_err(core::out_of_memory(
            "a column of the run",
            rows,
            per_row * std::mem::size_of::<T>(),
        ))
    })?;
    v.extend(it);
    Ok(v)
}

/// A per-part diagnostics column: `rows` rows of `parts` parts of `width` numbers each, as an
/// array of shape (rows, parts) or (rows, parts, width) ([`gather`]).
fn per_part<T: numpy::Element>(
    py: Python<'_>,
    rows: usize,
    parts: usize,
    width: usize,
    it: impl IntoIterator<Item = T>,
) -> PyResult<Py<PyAny>> {
    shaped(py, rows, parts, width, gather(rows, parts * width, it)?)
}

/// The values `v` of a per-part column ([`per_part`]), already gathered (the core's own
/// one-value-a-part columns are handed over without a copy).
fn shaped<T: numpy::Element>(
    py: Python<'_>,
    rows: usize,
    parts: usize,
    width: usize,
    v: Vec<T>,
) -> PyResult<Py<PyAny>> {
    let a = v.into_pyarray(py);
    Ok(if width == 1 {
        a.reshape([rows, parts])?.into_any().unbind()
    } else {
        a.reshape([rows, parts, width])?.into_any().unbind()
    })
}

#[pymethods]
impl PyRun {
    /// The diagnostics columns of the run's rows. Heavy tops: Euler angles (phi, psi
    /// unwrapped), energy, Mz, and M3 and Kovalevskaya's K where they are integrals. Play
    /// tops: Euler angles, u, contact point, slip velocity and speed, normal force,
    /// Jellett's J, the energy and its parts, and per part: contact, normal force, slip
    /// velocity, contact state (codes of `names()["part_modes"]`), contact point and
    /// friction force.
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match &self.rows {
            Rows::Heavy(top, states) => {
                let c = py.detach(|| top.columns(states));
                d.set_item("theta", c.theta.into_pyarray(py))?;
                d.set_item("phi", c.phi.into_pyarray(py))?;
                d.set_item("psi", c.psi.into_pyarray(py))?;
                d.set_item("energy", c.energy.into_pyarray(py))?;
                d.set_item("potential", c.potential.into_pyarray(py))?;
                d.set_item("Mz", c.mz.into_pyarray(py))?;
                if let Some(v) = c.m3 {
                    d.set_item("M3", v.into_pyarray(py))?;
                }
                if let Some(v) = c.kovalevskaya {
                    d.set_item("kovalevskaya", v.into_pyarray(py))?;
                }
            }
            Rows::Driven(top, rows) => {
                let c = py.detach(|| top.columns(rows));
                d.set_item("theta", c.theta.into_pyarray(py))?;
                d.set_item("phi", c.phi.into_pyarray(py))?;
                d.set_item("psi", c.psi.into_pyarray(py))?;
                d.set_item("energy", c.energy.into_pyarray(py))?;
                d.set_item("potential", c.potential.into_pyarray(py))?;
                d.set_item("Mz", c.mz.into_pyarray(py))?;
                d.set_item("pivot_position", flat(py, &c.pivot_position)?)?;
                d.set_item("pivot_velocity", flat(py, &c.pivot_velocity)?)?;
                d.set_item("reaction_force", flat(py, &c.reaction_force)?)?;
                d.set_item("power_pivot", c.power_pivot.into_pyarray(py))?;
                d.set_item("power_dissipated", c.power_dissipated.into_pyarray(py))?;
                d.set_item("work_by_pivot", c.work_by_pivot.into_pyarray(py))?;
                d.set_item("dissipated", c.dissipated.into_pyarray(py))?;
                d.set_item("balance", c.balance.into_pyarray(py))?;
                d.set_item("stuck", c.stuck.into_pyarray(py))?;
            }
            Rows::Play(top, rows) => {
                let c = py.detach(|| top.columns(rows)).map_err(|e| {
                    pyo3::exceptions::PyMemoryError::new_err(match e {
                        kreisel_core::KreiselError::Numerical(m) => m,
                        e => e.to_string(),
                    })
                })?;
                d.set_item("theta", c.theta.into_pyarray(py))?;
                d.set_item("phi", c.phi.into_pyarray(py))?;
                d.set_item("psi", c.psi.into_pyarray(py))?;
                d.set_item("u", c.u.into_pyarray(py))?;
                d.set_item("contact_point", flat(py, &c.contact)?)?;
                d.set_item("slip_velocity", flat(py, &c.slip_velocity)?)?;
                d.set_item("slip_speed", c.slip_speed.into_pyarray(py))?;
                d.set_item("normal_force", c.normal_force.into_pyarray(py))?;
                d.set_item("jellett", c.jellett.into_pyarray(py))?;
                let n = c.part_in_contact.len();
                let part = |i: usize| gather(n, 1, c.energy_parts.iter().map(|p| p[i]));
                let total = gather(n, 1, c.energy_parts.iter().map(|p| p[0] + p[1] + p[2]))?;
                d.set_item("energy_translation", part(0)?.into_pyarray(py))?;
                d.set_item("energy_rotation", part(1)?.into_pyarray(py))?;
                d.set_item("energy_potential", part(2)?.into_pyarray(py))?;
                d.set_item("energy", total.into_pyarray(py))?;
                // Per part: the top's `parts.n` values a row.
                let np = top.parts.n;
                // (part_mode: codes, see `names()["part_modes"]`, converted to names in Python.)
                let cols = [
                    (
                        "part_in_contact",
                        shaped(py, n, np, 1, c.part_in_contact.data)?,
                    ),
                    (
                        "part_normal_force",
                        shaped(py, n, np, 1, c.part_normal_force.data)?,
                    ),
                    (
                        "part_slip_velocity",
                        per_part(
                            py,
                            n,
                            np,
                            2,
                            c.part_slip_velocity.data.iter().flatten().copied(),
                        )?,
                    ),
                    (
                        "part_mode",
                        per_part(py, n, np, 1, c.part_state.data.iter().map(|s| s.code()))?,
                    ),
                    (
                        "part_contact_point",
                        per_part(
                            py,
                            n,
                            np,
                            3,
                            c.part_contact_point.data.iter().flatten().copied(),
                        )?,
                    ),
                    (
                        "part_friction_force",
                        per_part(
                            py,
                            n,
                            np,
                            2,
                            c.part_friction_force.data.iter().flatten().copied(),
                        )?,
                    ),
                ];
                for (key, v) in cols {
                    d.set_item(key, v)?;
                }
            }
        }
        Ok(d)
    }
}

pub(crate) fn info_into(py: Python<'_>, d: &Bound<'_, PyDict>, info: &RunInfo) -> PyResult<()> {
    let events = PyList::empty(py);
    for e in &info.events {
        let index: i64 = e.index.map_or(-1, |i| i as i64);
        let part: i64 = e.part.map_or(-1, |i| i as i64);
        events.append((e.name.as_ref(), e.t, index, part))?;
    }
    d.set_item("events", events)?;
    let stats = PyDict::new(py);
    stats.set_item("steps", info.stats.steps)?;
    stats.set_item("rejected", info.stats.rejected)?;
    stats.set_item("rhs_evals", info.stats.rhs_evals)?;
    d.set_item("stats", stats)?;
    d.set_item("status", info.status.name())?;
    Ok(())
}

/// Simulates a native model from a flat state; returns a dict of the state columns, the
/// names of the diagnostics columns (`derived`) and the `run` that computes them, the
/// events as (name, t, index: -1 for the model's own), stats and status.
#[pyfunction]
#[pyo3(signature = (model, state, t_end, method, rtol, atol, dt=None, t_eval=None, events=Vec::new(), reduced=false))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyAny>,
    state: Vec<f64>,
    t_end: f64,
    method: String,
    rtol: f64,
    atol: f64,
    dt: Option<f64>,
    t_eval: Option<PyReadonlyArray1<'py, f64>>,
    events: Vec<EventTuple>,
    reduced: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let te = match &t_eval {
        Some(a) => Some(a.as_slice()?.to_vec()),
        None => None,
    };
    let st = settings(t_end, method, rtol, atol, dt, te, &events, reduced)?;
    let d = PyDict::new(py);
    match native(model)? {
        Native::Heavy(top) => {
            let s0 = heavy_state(py, &state)?;
            let out = run_model(py, top, s0, st, &events, rigid_event)?;
            put_rigid(
                py,
                &d,
                out.rows.iter().copied(),
                top.column_names(),
                &out.info,
            )?;
            d.set_item("t", out.t.into_pyarray(py))?;
            let rows = Rows::Heavy(top, out.rows);
            d.set_item("run", PyRun { rows })?;
        }
        Native::Driven(top) => {
            let s0 = heavy_state(py, &state)?;
            let out = run_model(py, top.clone(), s0, st, &events, rigid_event)?;
            let states = out.rows.iter().map(|r| r.state());
            put_rigid(py, &d, states, top.column_names(), &out.info)?;
            d.set_item("t", out.t.into_pyarray(py))?;
            let rows = Rows::Driven(top, out.rows);
            d.set_item("run", PyRun { rows })?;
        }
        Native::Play(top) => {
            let y0 = play_state(&state)?;
            let out = run_model(py, top, y0, st, &events, |_, _, _, _: &[f64; DIM]| Ok(0.0))?;
            put_play(py, &d, top, out.t, out.rows, &out.info)?;
        }
    }
    Ok(d)
}

/// Puts a play top's run into `d`: its columns, counters, events and rows.
pub(crate) fn put_play(
    py: Python<'_>,
    d: &Bound<'_, PyDict>,
    top: PlayTop,
    t: Vec<f64>,
    rows: Vec<PlayRow>,
    info: &RunInfo,
) -> PyResult<()> {
    let n = rows.len();
    let part = |a: usize, k: usize| {
        gather(
            n,
            k,
            rows.iter().flat_map(|r| r.y[a..a + k].iter().copied()),
        )
    };
    d.set_item("quaternion", part(0, 4)?.into_pyarray(py).reshape([n, 4])?)?;
    d.set_item("omega", part(4, 3)?.into_pyarray(py).reshape([n, 3])?)?;
    d.set_item("com", part(7, 3)?.into_pyarray(py).reshape([n, 3])?)?;
    d.set_item(
        "com_velocity",
        part(10, 3)?.into_pyarray(py).reshape([n, 3])?,
    )?;
    let dissipated = gather(n, 1, rows.iter().map(|r| r.y[13]))?;
    d.set_item("dissipated", dissipated.into_pyarray(py))?;
    // Codes (see `names()["modes"]`): one array, not a Python string per output.
    // The top's mode from its parts' states (`PlayTop::contact_mode`).
    let modes = gather(n, 1, rows.iter().map(|r| top.contact_mode(r).code()))?;
    d.set_item("mode", modes.into_pyarray(py))?;
    d.set_item("derived", PlayTop::COLUMN_NAMES.to_vec())?;
    info_into(py, d, info)?;
    d.set_item("t", t.into_pyarray(py))?;
    d.set_item(
        "run",
        PyRun {
            rows: Rows::Play(top, rows),
        },
    )?;
    Ok(())
}

/// A Python event function of a top on a pivot, called with (t, q, omega).
fn rigid_event(py: Python<'_>, f: Py<PyAny>, t: f64, s: &RigidState) -> PyResult<f64> {
    f.call1(py, (t, s.q.0, s.omega))?.extract::<f64>(py)
}

/// A rigid top's run into `d`: its quaternions and body rates, the names of its diagnostics
/// columns, its events, stats and status.
pub(crate) fn put_rigid(
    py: Python<'_>,
    d: &Bound<'_, PyDict>,
    states: impl Iterator<Item = RigidState>,
    derived: Vec<&'static str>,
    info: &RunInfo,
) -> PyResult<()> {
    let (q, w): (Vec<[f64; 4]>, Vec<[f64; 3]>) = states.map(|s| (s.q.0, s.omega)).unzip();
    d.set_item("quaternion", flat(py, &q)?)?;
    d.set_item("omega", flat(py, &w)?)?;
    d.set_item("derived", derived)?;
    info_into(py, d, info)
}

/// The code a category summary has where a run failed.
const CATEGORY_ERROR: i8 = -2;

/// Puts one column per summary field of `model` ("play" or "heavy"), NaN where a run failed
/// (categories as int8 codes, [`CATEGORY_ERROR`] where a run failed), and the error messages.
fn summary_columns<'py, S>(
    py: Python<'py>,
    model: &str,
    res: &[kreisel_core::Result<S>],
    get: impl Fn(&S, &str) -> Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for f in SUMMARY_FIELDS
        .iter()
        .filter(|f| f.model == model && f.default)
    {
        let col: Vec<f64> = res
            .iter()
            .map(|r| {
                r.as_ref()
                    .ok()
                    .and_then(|s| get(s, f.name))
                    .unwrap_or(f64::NAN)
            })
            .collect();
        if f.category.is_empty() {
            d.set_item(f.name, col.into_pyarray(py))?;
        } else {
            let codes: Vec<i8> = col
                .iter()
                .map(|&c| if c.is_nan() { -2 } else { c as i8 })
                .collect();
            d.set_item(f.name, codes.into_pyarray(py))?;
        }
    }
    let errors: Vec<Option<String>> = res
        .iter()
        .map(|r| r.as_ref().err().map(|e| e.to_string()))
        .collect();
    d.set_item("errors", errors)?;
    Ok(d)
}

/// Many runs in parallel (the interpreter released): native models and flat states of
/// equal length, one kind of model per call, each run summarised as it goes; play tops'
/// inversion time is the first upward crossing of `inversion_level`.
#[pyfunction]
#[pyo3(signature = (models, states, t_end, method, rtol, atol, dt=None, inversion_level=0.9, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn many<'py>(
    py: Python<'py>,
    models: Vec<Bound<'py, PyAny>>,
    states: Vec<Vec<f64>>,
    t_end: f64,
    method: String,
    rtol: f64,
    atol: f64,
    dt: Option<f64>,
    inversion_level: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    if models.len() != states.len() {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{} models and {} states: give equally many",
            models.len(),
            states.len()
        )));
    }
    let mut st = settings(t_end, method, rtol, atol, dt, None, &[], false)?;
    let natives: Vec<Native> = models.iter().map(native).collect::<PyResult<_>>()?;
    match natives.first() {
        Some(Native::Play(_)) | None if natives.iter().all(|m| matches!(m, Native::Play(_))) => {
            let runs: Vec<(PlayTop, [f64; DIM])> = natives
                .iter()
                .zip(&states)
                .map(|(m, s)| match m {
                    Native::Play(t) => Ok((*t, play_state(s)?)),
                    _ => unreachable!(),
                })
                .collect::<PyResult<_>>()?;
            // A play top's summary has the time it first turns over past this level.
            st.events.push(EventDef {
                name: "inversion".into(),
                kind: EventKind::Inversion(inversion_level),
                direction: 1,
                terminal: false,
            });
            // and the time it comes to rest, where its run ends (nothing happens after)
            st.events.push(EventDef {
                name: "rest".into(),
                kind: EventKind::Rest,
                direction: -1,
                terminal: true,
            });
            let res = py.detach(move || batch::many(&runs, &st, threads)).py(py)?;
            summary_columns(py, "play", &res, |s, k| s.get(k))
        }
        Some(Native::Heavy(_)) if natives.iter().all(|m| matches!(m, Native::Heavy(_))) => {
            let runs: Vec<(HeavyTop, RigidState)> = natives
                .iter()
                .zip(&states)
                .map(|(m, s)| match m {
                    Native::Heavy(t) => Ok((*t, heavy_state(py, s)?)),
                    _ => unreachable!(),
                })
                .collect::<PyResult<_>>()?;
            let res = py.detach(move || batch::many(&runs, &st, threads)).py(py)?;
            summary_columns(py, "heavy", &res, |s, k| s.get(k))
        }
        _ if natives.iter().all(|m| !matches!(m, Native::Play(_))) => {
            let runs: Vec<(DrivenTop, RigidState)> = natives
                .into_iter()
                .zip(&states)
                .map(|(m, s)| Ok((driven(m), heavy_state(py, s)?)))
                .collect::<PyResult<_>>()?;
            let res = py.detach(move || batch::many(&runs, &st, threads)).py(py)?;
            summary_columns(py, "heavy", &res, |s, k| s.get(k))
        }
        _ => Err(pyo3::exceptions::PyValueError::new_err(
            "models mixes play tops and heavy tops: one kind per batch",
        )),
    }
}

/// A heavy top as a driven one (on a fixed pivot, undamped), so that a batch mixing both
/// runs as one kind.
pub(crate) fn driven(m: Native) -> DrivenTop {
    match m {
        Native::Driven(t) => t,
        Native::Heavy(t) => DrivenTop::new(t, Pivot::Fixed, Damping::default())
            .expect("an undamped top on a fixed pivot is valid"),
        Native::Play(_) => unreachable!("play tops are not heavy tops"),
    }
}

/// Checks one event as `simulate` would (its direction and the range of its value).
#[pyfunction]
pub fn check_event(py: Python<'_>, event: EventTuple) -> PyResult<()> {
    event_def(&event)?.check(None).py(py)
}

/// Checks settings for a native model exactly as `simulate` would (the core's one check and
/// the model's own rules), without running anything.
#[pyfunction]
#[pyo3(signature = (model, t_end, method, rtol, atol, dt=None, events=Vec::new(), reduced=false))]
#[allow(clippy::too_many_arguments)]
pub fn check_settings(
    py: Python<'_>,
    model: &Bound<'_, PyAny>,
    t_end: f64,
    method: String,
    rtol: f64,
    atol: f64,
    dt: Option<f64>,
    events: Vec<EventTuple>,
    reduced: bool,
) -> PyResult<()> {
    let st = settings(t_end, method, rtol, atol, dt, None, &events, reduced)?;
    let users = st.user_events();
    match native(model)? {
        Native::Heavy(top) => core::check(&top, &st, users).map(|_| ()).py(py),
        Native::Driven(top) => core::check(&top, &st, users).map(|_| ()).py(py),
        Native::Play(top) => core::check(&top, &st, users).map(|_| ()).py(py),
    }
}

/// Every public name the Python layer reads: methods, contact modes, kinds of motion,
/// the summaries with units and descriptions, and the run statuses.
#[pyfunction]
pub fn names(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("modes", MODES.to_vec())?;
    d.set_item("part_modes", PartState::ALL.map(|s| s.name()).to_vec())?;
    d.set_item("motion_kinds", MOTION_KINDS.to_vec())?;
    let fields = PyList::empty(py);
    for f in SUMMARY_FIELDS {
        let x = PyDict::new(py);
        x.set_item("name", f.name)?;
        x.set_item("unit", f.unit)?;
        x.set_item("description", f.description)?;
        x.set_item("model", f.model)?;
        x.set_item("category", f.category)?;
        x.set_item("default", f.default)?;
        fields.append(x)?;
    }
    d.set_item("summaries", fields)?;
    d.set_item(
        "statuses",
        [
            core::Status::Completed,
            core::Status::Event,
            core::Status::Interrupted,
        ]
        .map(|s| s.name()),
    )?;
    d.set_item("max_steps", core::MAX_STEPS)?;
    d.set_item("category_error", CATEGORY_ERROR)?;
    Ok(d)
}
