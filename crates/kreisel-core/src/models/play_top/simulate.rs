//! The model behind [`crate::simulate::simulate`] for tops on a floor (the run is
//! [`super::driver`]'s): its rows, diagnostics columns and the running summary a batch
//! keeps.

use super::driver::{drive, Rules};
use super::parts::MAX_PARTS;
use super::{Contacts, Mode, PlayTop, DIM};
use crate::error::{KreiselError, Result};
use crate::simulate::{
    relative, Accumulate, EventKind, MethodInfo, Model, RunInfo, Settings, Sink, UserFn,
};

/// One output row of a play-top run: the state, and every part's contact mode and slip
/// direction in force at zero slip speed (a one-sphere top's in part 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayRow {
    /// State (see [`DIM`]).
    pub y: [f64; DIM],
    /// Every part's mode and slip direction.
    pub contacts: Contacts,
}

impl PlayRow {
    /// The one mode of the whole top ([`Contacts::overall`]): a one-sphere top's own.
    #[inline(always)]
    pub fn mode(&self) -> Mode {
        self.contacts.overall(MAX_PARTS)
    }

    /// The slip direction of the first touching part (of part 0 in flight).
    #[inline(always)]
    pub fn dir(&self) -> [f64; 3] {
        let c = &self.contacts;
        let first = (0..MAX_PARTS)
            .find(|&i| c.mode[i] != Mode::Flight)
            .unwrap_or(0);
        [c.dir[first][0], c.dir[first][1], 0.0]
    }
}

/// One part's contact state in a row ([`PlayTop::part_states`]): whether it touches and
/// sticks as the engine integrates it ([`Mode`]), whether its friction is mainly sliding
/// friction (by the engine's own law, [`PlayTop::friction_per_n`]), and how it turns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PartState {
    /// Not touching the floor.
    #[default]
    Flight,
    /// Its contact point does not slide (sticking, or a Coulomb-Contensou patch turning
    /// about its normal faster than it slips), the angular velocity at least as much along
    /// the floor as about its normal (at rest included).
    Rolling,
    /// As rolling, but turning mainly about the floor's normal (|w_z| > |w_h|: a top
    /// sleeping on its tip).
    Drilling,
    /// Sliding: the engine's [`Mode::Slip`] with a friction force that is mostly tangential
    /// (under point Coulomb or viscous friction every slipping part; under
    /// Coulomb-Contensou friction a part whose slip speed exceeds rbar |w_z|).
    Sliding,
    /// A ring lying flat on the floor, touching along its whole circle, or the pole a top
    /// lies flat on ([`PlayTop::flat_support`]) (sticking or sliding:
    /// [`PlayTop::contact_mode`] tells which).
    Flat,
}

impl PartState {
    /// Every state, by code.
    pub const ALL: [PartState; 5] = [
        PartState::Flight,
        PartState::Rolling,
        PartState::Drilling,
        PartState::Sliding,
        PartState::Flat,
    ];

    /// The public name.
    pub const fn name(&self) -> &'static str {
        match self {
            PartState::Flight => "flight",
            PartState::Rolling => "rolling",
            PartState::Drilling => "drilling",
            PartState::Sliding => "sliding",
            PartState::Flat => "flat",
        }
    }

    /// Small integer code: the position in [`PartState::ALL`].
    pub const fn code(&self) -> u8 {
        *self as u8
    }

    /// A touching part that does not slide, turning at `w` (space frame): drilling if it
    /// turns more about the vertical than about a horizontal axis, else rolling.
    fn turning(w: [f64; 3]) -> PartState {
        if w[2].abs() > w[0].hypot(w[1]) {
            PartState::Drilling
        } else {
            PartState::Rolling
        }
    }
}

impl PlayTop {
    /// Whether part `i`, in the engine's [`Mode::Slip`] with slip velocity `vp` and turning
    /// at `w`, slides: its friction ([`PlayTop::friction_per_n`], the law the engine
    /// integrates) is mostly a tangential force rather than a drilling torque,
    /// `|f_t| > |m_z| / rbar`. Under Coulomb-Contensou friction `|f_t| rbar / |m_z| = |v| /
    /// (rbar |w_z|)`: a patch that spins about the normal faster than it slips pivots on
    /// the floor (it rolls or drills); under every other law a slipping part slides.
    fn slides(&self, c: &Contacts, i: usize, vp: [f64; 3], w: [f64; 3]) -> bool {
        let rb = self.friction.rbar();
        if rb <= 0.0 {
            return true;
        }
        let (ft, mz) = self.friction_per_n(vp, w[2], c.dir[i], c.creep);
        ft[0].hypot(ft[1]) * rb > mz.abs()
    }

    /// Every part's contact state in a row (the first [`PlayTop::parts`]`.n` are used; the
    /// rest are flight).
    pub fn part_states(&self, r: &PlayRow) -> [PartState; MAX_PARTS] {
        let k = self.kin(&r.y);
        let c = &r.contacts;
        let mut out = [PartState::Flight; MAX_PARTS];
        for (i, s) in out.iter_mut().enumerate().take(self.parts.n) {
            *s = match c.mode[i] {
                Mode::Flight => PartState::Flight,
                _ if c.flat => PartState::Flat,
                Mode::Roll => PartState::turning(k.w),
                // A creeping part rolls at the cone's edge: its slip is of the order of the
                // stick speed ([`Contacts::creeping`]).
                Mode::Slip if c.creeping & (1 << i) != 0 => PartState::turning(k.w),
                Mode::Slip => {
                    let vp = self.parts.shape[i].point_velocity(k.v, k.w, k.e3);
                    if self.slides(c, i, vp, k.w) {
                        PartState::Sliding
                    } else {
                        PartState::turning(k.w)
                    }
                }
            };
        }
        out
    }

    /// The contact mode of the whole top in a row, from its parts' states: slip if a part
    /// slides (or a ring lying flat slips), roll if parts touch and none slides, else
    /// flight. Under point Coulomb or viscous friction the engine's own
    /// ([`PlayRow::mode`]); under Coulomb-Contensou friction a top whose patches pivot
    /// without sliding rolls.
    pub fn contact_mode(&self, r: &PlayRow) -> Mode {
        // Only a Coulomb-Contensou part in the engine's slip mode may pivot without sliding:
        // every other row is the engine's mode (no kinematics needed).
        let engine = r.mode();
        if engine != Mode::Slip
            || r.contacts.flat
            || (self.friction.rbar() <= 0.0 && r.contacts.creeping == 0)
        {
            return engine;
        }
        let states = self.part_states(r);
        let states = &states[..self.parts.n];
        if states.contains(&PartState::Sliding) {
            Mode::Slip
        } else if states.iter().any(|&s| s != PartState::Flight) {
            Mode::Roll
        } else {
            Mode::Flight
        }
    }
}

/// The events a play top has besides its contact switches.
const EVENTS: [EventKind; 2] = [EventKind::Inversion(0.0), EventKind::Rest];

impl Model for PlayTop {
    type State = [f64; DIM];
    type Row = PlayRow;
    type Summary = PlaySummary;
    type Acc<'a> = PlayAcc<'a>;
    const NAME: &'static str = "play top";

    fn check(&self, settings: &Settings, info: &MethodInfo) -> Result<()> {
        if info.name != "dop853" {
            return Err(KreiselError::InvalidParameter {
                name: "method".into(),
                value: format!("{:?}", info.name),
                allowed: "a play top's contact modes, events and impacts need the adaptive \
                          \"dop853\""
                    .into(),
            });
        }
        if settings.reduced {
            return Err(KreiselError::InvalidParameter {
                name: "reduced".into(),
                value: "True".into(),
                allowed: "the reduced route is the Lagrange top's".into(),
            });
        }
        settings.unsupported_event(Self::NAME, &EVENTS)
    }

    fn run(
        &self,
        y0: &[f64; DIM],
        settings: &Settings,
        _user: &mut [UserFn<'_, [f64; DIM]>],
        keep_going: &mut dyn FnMut(f64) -> bool,
        sink: Sink<'_, PlayRow>,
    ) -> Result<RunInfo> {
        drive(
            &Rules::for_run(self, settings.rtol),
            self,
            y0,
            settings,
            keep_going,
            sink,
        )
    }

    fn summary<'a>(&'a self, _y0: &[f64; DIM], settings: &Settings) -> PlayAcc<'a> {
        PlayAcc {
            top: self,
            inversion: settings
                .events
                .iter()
                .position(|e| matches!(e.kind, EventKind::Inversion(_))),
            first: None,
            jd: 0.0,
            ed: 0.0,
            last: None,
        }
    }

    /// An error where the process's memory cannot hold them ([`PlayTop::columns`]).
    type Columns = Result<PlayColumns>;

    fn column_names(&self) -> Vec<&'static str> {
        PlayTop::COLUMN_NAMES.to_vec()
    }

    fn columns(&self, rows: &[PlayRow]) -> Result<PlayColumns> {
        PlayTop::columns(self, rows)
    }
}

/// Diagnostics of a play-top motion, as columns.
#[derive(Debug, Clone, Default)]
pub struct PlayColumns {
    /// u = cos(theta).
    pub u: Vec<f64>,
    /// Euler angles (phi, psi unwrapped).
    pub theta: Vec<f64>,
    /// Precession angle.
    pub phi: Vec<f64>,
    /// Spin angle.
    pub psi: Vec<f64>,
    /// Contact point (the sphere's lowest point), space frame.
    pub contact: Vec<[f64; 3]>,
    /// Velocity of the material point at T.
    pub slip_velocity: Vec<[f64; 3]>,
    /// Horizontal slip speed.
    pub slip_speed: Vec<f64>,
    /// Normal force (0 in flight).
    pub normal_force: Vec<f64>,
    /// Jellett's integral.
    pub jellett: Vec<f64>,
    /// Energy parts: translation, rotation, potential.
    pub energy_parts: Vec<[f64; 3]>,
    /// Whether each part touches the floor.
    pub part_in_contact: PerPart<bool>,
    /// Each part's normal force (N).
    pub part_normal_force: PerPart<f64>,
    /// Each part's slip velocity (horizontal, space frame; m/s): the velocity of the
    /// material point at its lowest point.
    pub part_slip_velocity: PerPart<[f64; 2]>,
    /// Each part's contact state ([`PartState`]).
    pub part_state: PerPart<PartState>,
    /// Each part's contact point (space frame; m): its lowest point (a ring lying flat: the
    /// centre of its circle, on the floor).
    pub part_contact_point: PerPart<[f64; 3]>,
    /// Each part's friction force (horizontal, space frame; N), 0 for a part not touching.
    pub part_friction_force: PerPart<[f64; 2]>,
}

/// A column with one value per part of the top in each row, for the top's own parts only
/// (a ball's rows hold one value, a tippe top's two): row `i` is
/// `data[i * parts..(i + 1) * parts]`. Sized to the parts rather than to [`MAX_PARTS`], it
/// keeps a one-part run's diagnostics at about half the memory.
#[derive(Debug, Clone, Default)]
pub struct PerPart<T> {
    /// The top's number of parts: values a row.
    pub parts: usize,
    /// The values, row after row.
    pub data: Vec<T>,
}

impl<T> PerPart<T> {
    /// Row `i`'s values, one per part.
    pub fn row(&self, i: usize) -> &[T] {
        &self.data[i * self.parts..(i + 1) * self.parts]
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.data.len().checked_div(self.parts).unwrap_or(0)
    }

    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
}

impl PlayTop {
    /// The names of the diagnostics columns of a run ([`PlayTop::columns`]), the energy
    /// parts as three columns and their sum.
    pub const COLUMN_NAMES: [&'static str; 19] = [
        "theta",
        "phi",
        "psi",
        "u",
        "contact_point",
        "slip_velocity",
        "slip_speed",
        "normal_force",
        "jellett",
        "energy_translation",
        "energy_rotation",
        "energy_potential",
        "energy",
        "part_in_contact",
        "part_normal_force",
        "part_slip_velocity",
        "part_mode",
        "part_contact_point",
        "part_friction_force",
    ];

    /// The diagnostics of the rows of a play-top run: an error (not an abort) where the
    /// process's memory cannot hold them (about 190 bytes a row for one part, 70 more for
    /// each further part).
    pub fn columns(&self, rows: &[PlayRow]) -> Result<PlayColumns> {
        columns_of(self, rows)
    }
}

/// One row of the diagnostics columns.
#[derive(Clone, Copy, Default)]
struct Row {
    u: f64,
    euler: (f64, f64, f64),
    contact: [f64; 3],
    slip_velocity: [f64; 3],
    slip_speed: f64,
    normal_force: f64,
    jellett: f64,
    energy_parts: [f64; 3],
    part_in_contact: [bool; MAX_PARTS],
    part_normal_force: [f64; MAX_PARTS],
    part_slip_velocity: [[f64; 2]; MAX_PARTS],
    part_state: [PartState; MAX_PARTS],
    part_contact_point: [[f64; 3]; MAX_PARTS],
    part_friction_force: [[f64; 2]; MAX_PARTS],
}

/// The diagnostics of a row: the contact point, slip velocity and Jellett's integral are the first touching part's
/// (or the lowest part's in flight), the normal force is the parts' sum.
fn row_of(top: &PlayTop, r: &PlayRow, angles: &mut crate::simulate::Unwrapped) -> Row {
    use crate::rotation::euler_from_matrix;
    let y = &r.y;
    let n = top.parts.n;
    let k = top.kin(y);
    let (phi, theta, psi) = euler_from_matrix(k.r);
    let (phi, psi) = angles.next(phi, psi);
    let mut dy = [0.0; DIM];
    let f = top.dynamics(&r.contacts, y, &mut dy);
    let (a, b, p) = top.energy_parts(y);
    let states = top.part_states(r);
    let mut out = Row {
        u: k.e3[2],
        euler: (phi, theta, psi),
        energy_parts: [a, b, p],
        ..Row::default()
    };
    let lowest = (0..n)
        .min_by(|&i, &j| {
            let (gi, gj) = (
                top.parts.shape[i].gap(k.zg, k.e3),
                top.parts.shape[j].gap(k.zg, k.e3),
            );
            gi.total_cmp(&gj)
        })
        .unwrap_or(0);
    let main = (0..n)
        .find(|&i| r.contacts.mode[i] != Mode::Flight)
        .unwrap_or(lowest);
    for (i, &state) in states.iter().enumerate().take(n) {
        let part = &top.parts.shape[i];
        let vp = part.point_velocity(k.v, k.w, k.e3);
        out.part_in_contact[i] = r.contacts.mode[i] != Mode::Flight;
        out.part_normal_force[i] = f.n[i];
        out.part_slip_velocity[i] = [vp[0], vp[1]];
        out.part_state[i] = state;
        out.part_friction_force[i] = f.ft[i];
        let arm = part.arm(k.e3);
        out.part_contact_point[i] = if out.part_state[i] == PartState::Flat {
            let c = part.centre(k.e3);
            [y[7] + c[0], y[8] + c[1], y[9] + arm[2]]
        } else {
            [y[7] + arm[0], y[8] + arm[1], y[9] + arm[2]]
        };
        out.normal_force += f.n[i];
        if i == main {
            out.contact = [y[7] + arm[0], y[8] + arm[1], y[9] + arm[2]];
            out.slip_velocity = vp;
            out.slip_speed = (vp[0] * vp[0] + vp[1] * vp[1]).sqrt();
        }
    }
    out.jellett = top.jellett(y);
    out
}

/// [`PlayTop::columns`].
fn columns_of(top: &PlayTop, all: &[PlayRow]) -> Result<PlayColumns> {
    use crate::simulate::Unwrapped;
    // Rows in blocks, then the blocks' columns: pushing to ten columns per row costs more
    // than the row's arithmetic, and rows for the whole run would be a large allocation.
    const BLOCK: usize = 128;
    let n = all.len();
    let np = top.parts.n;
    fn column<T>(n: usize) -> Result<Vec<T>> {
        sized(n, n)
    }
    // `len` values for the run's `n` rows (its memory error counts rows).
    fn sized<T>(len: usize, n: usize) -> Result<Vec<T>> {
        let mut v = Vec::new();
        v.try_reserve_exact(len).map_err(|_| {
            KreiselError::Numerical(crate::simulate::out_of_memory(
                "the run's diagnostics columns",
                n,
                std::mem::size_of::<Row>(),
            ))
        })?;
        Ok(v)
    }
    fn per_part<T>(n: usize, parts: usize) -> Result<PerPart<T>> {
        Ok(PerPart {
            parts,
            data: sized(n * parts, n)?,
        })
    }
    let mut c = PlayColumns {
        u: column(n)?,
        theta: column(n)?,
        phi: column(n)?,
        psi: column(n)?,
        contact: column(n)?,
        slip_velocity: column(n)?,
        slip_speed: column(n)?,
        normal_force: column(n)?,
        jellett: column(n)?,
        energy_parts: column(n)?,
        part_in_contact: per_part(n, np)?,
        part_normal_force: per_part(n, np)?,
        part_slip_velocity: per_part(n, np)?,
        part_state: per_part(n, np)?,
        part_contact_point: per_part(n, np)?,
        part_friction_force: per_part(n, np)?,
    };
    let mut angles = Unwrapped::default();
    let mut rows = [Row::default(); BLOCK];
    for start in (0..n).step_by(BLOCK) {
        let end = n.min(start + BLOCK);
        for (row, r) in rows.iter_mut().zip(&all[start..end]) {
            *row = row_of(top, r, &mut angles);
        }
        let rows = &rows[..end - start];
        c.u.extend(rows.iter().map(|r| r.u));
        c.theta.extend(rows.iter().map(|r| r.euler.1));
        c.phi.extend(rows.iter().map(|r| r.euler.0));
        c.psi.extend(rows.iter().map(|r| r.euler.2));
        c.contact.extend(rows.iter().map(|r| r.contact));
        c.slip_velocity.extend(rows.iter().map(|r| r.slip_velocity));
        c.slip_speed.extend(rows.iter().map(|r| r.slip_speed));
        c.normal_force.extend(rows.iter().map(|r| r.normal_force));
        c.jellett.extend(rows.iter().map(|r| r.jellett));
        c.energy_parts.extend(rows.iter().map(|r| r.energy_parts));
        for r in rows {
            c.part_in_contact.data.extend(&r.part_in_contact[..np]);
            c.part_normal_force.data.extend(&r.part_normal_force[..np]);
            c.part_slip_velocity
                .data
                .extend(&r.part_slip_velocity[..np]);
            c.part_state.data.extend(&r.part_state[..np]);
            c.part_contact_point
                .data
                .extend(&r.part_contact_point[..np]);
            c.part_friction_force
                .data
                .extend(&r.part_friction_force[..np]);
        }
    }
    Ok(c)
}

/// What a batch run keeps of each simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaySummary {
    /// u at the end.
    pub final_u: f64,
    /// Mode at the end.
    pub final_mode: Mode,
    /// Time of the first upward crossing of the inversion level (NaN if none).
    pub inversion_time: f64,
    /// Largest |J - J0| / |J0| over the run.
    pub jellett_drift: f64,
    /// Largest |E + dissipated - E0| / |E0| over the run.
    pub energy_drift: f64,
    /// Accepted steps.
    pub steps: u64,
    /// The parts touching at the end, as a bit mask (bit i: part i).
    pub final_parts: u8,
    /// Each part's first touchdown (s), NaN if none.
    pub first_touchdown: [f64; MAX_PARTS],
    /// When a ring part came down flat (the run's end), NaN if none.
    pub flat_time: f64,
    /// When the top came to rest (the event `rest`), NaN if none.
    pub rest_time: f64,
}

impl PlaySummary {
    /// The summary's fields by their public names ([`crate::simulate::SUMMARY_FIELDS`]);
    /// a category as its code.
    pub fn get(&self, name: &str) -> Option<f64> {
        Some(match name {
            "final_u" => self.final_u,
            "final_mode" => self.final_mode.code() as f64,
            "inversion_time" => self.inversion_time,
            "jellett_drift" => self.jellett_drift,
            "energy_drift" => self.energy_drift,
            "steps" => self.steps as f64,
            "final_parts_in_contact" => self.final_parts as f64,
            "first_touchdown_time_0" => self.first_touchdown[0],
            "first_touchdown_time_1" => self.first_touchdown[1],
            "first_touchdown_time_2" => self.first_touchdown[2],
            "first_touchdown_time_3" => self.first_touchdown[3],
            "flat_time" => self.flat_time,
            "rest_time" => self.rest_time,
            _ => return None,
        })
    }
}

/// The running summary of a play-top run, fed one row at a time.
pub struct PlayAcc<'a> {
    top: &'a PlayTop,
    /// Position of the inversion event in the settings.
    inversion: Option<usize>,
    /// Jellett's integral and the energy of the first row.
    first: Option<(f64, f64)>,
    jd: f64,
    ed: f64,
    last: Option<PlayRow>,
}

impl Accumulate<PlayRow> for PlayAcc<'_> {
    type Summary = PlaySummary;

    fn push(&mut self, _t: f64, row: &PlayRow) {
        let top = self.top;
        let y = &row.y;
        let (j0, e0) = *self.first.get_or_insert_with(|| {
            let (a, b, c) = top.energy_parts(y);
            (top.jellett(y), a + b + c)
        });
        self.jd = self.jd.max((top.jellett(y) - j0).abs());
        let (a, b, c) = top.energy_parts(y);
        self.ed = self.ed.max((a + b + c + y[13] - e0).abs());
        self.last = Some(*row);
    }

    fn finish(self, info: &RunInfo) -> PlaySummary {
        let (j0, e0) = self.first.unwrap_or((f64::NAN, f64::NAN));
        let last = self.last;
        let at = |name: &str| {
            info.events
                .iter()
                .find(|e| e.name == name)
                .map_or(f64::NAN, |e| e.t)
        };
        PlaySummary {
            final_u: last.map_or(f64::NAN, |r| self.top.kin(&r.y).e3[2]),
            final_mode: last.map_or(Mode::Flight, |r| self.top.contact_mode(&r)),
            inversion_time: info
                .events
                .iter()
                .find(|e| e.index.is_some() && e.index == self.inversion)
                .map_or(f64::NAN, |e| e.t),
            jellett_drift: relative(self.jd, j0.abs()),
            energy_drift: relative(self.ed, e0.abs()),
            steps: info.stats.steps,
            final_parts: last.map_or(0, |r| r.contacts.mask(self.top.parts.n)),
            first_touchdown: std::array::from_fn(|i| {
                info.events
                    .iter()
                    .find(|e| e.index.is_none() && e.part == Some(i) && e.name == "touchdown")
                    .map_or(f64::NAN, |e| e.t)
            }),
            flat_time: at("flat"),
            rest_time: at("rest"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::parts::Shape;
    use super::super::Friction;
    use super::*;
    use crate::rotation::Quat;

    /// A ball on the floor, upright, turning at `omega` (body = space frame) with G at `v`.
    fn row(friction: Friction, mode: Mode, omega: [f64; 3], v: [f64; 2]) -> (PlayTop, PlayRow) {
        let parts = [Shape::Sphere {
            radius: 0.015,
            z: -0.003,
        }];
        let top = PlayTop::with_parts(
            0.006, 8e-7, 7e-7, &parts, 9.81, friction, 0.0, 0.0, 0.0, 0.0,
        )
        .unwrap();
        let y = top.state(Quat::IDENTITY, omega, v[0], v[1], None).unwrap();
        let mut contacts = Contacts::NONE;
        contacts.mode[0] = mode;
        (top, PlayRow { y, contacts })
    }

    #[test]
    fn a_contensou_patch_slides_only_where_it_slips_faster_than_it_spins() {
        let law = Friction::coulomb_contensou(0.3, 5e-4).unwrap();
        let rbar = law.rbar();
        // spinning at 100 rad/s about the vertical: the patch's spin speed is 100 rbar
        for (slip, want) in [
            (0.5 * 100.0 * rbar, PartState::Drilling),
            (2.0 * 100.0 * rbar, PartState::Sliding),
        ] {
            // the contact point of an upright ball turning about the vertical slips with G
            let (top, r) = row(law, Mode::Slip, [0.0, 0.0, 100.0], [slip, 0.0]);
            assert_eq!(top.part_states(&r)[0], want, "slip {slip}");
            let mode = if want == PartState::Sliding {
                Mode::Slip
            } else {
                Mode::Roll
            };
            assert_eq!(top.contact_mode(&r), mode);
        }
    }

    #[test]
    fn point_coulomb_friction_takes_the_engines_mode() {
        let law = Friction::Coulomb { mu: 0.3 };
        let (top, r) = row(law, Mode::Slip, [0.0, 0.0, 100.0], [1e-9, 0.0]);
        assert_eq!(top.part_states(&r)[0], PartState::Sliding);
        assert_eq!(top.contact_mode(&r), r.mode());
        let (top, r) = row(law, Mode::Roll, [0.0, 0.0, 100.0], [0.0, 0.0]);
        assert_eq!(top.part_states(&r)[0], PartState::Drilling);
        // rolling about a horizontal axis (G moving with it: no slip)
        let (top, r) = row(law, Mode::Roll, [0.0, 10.0, 1.0], [10.0 * 0.018, 0.0]);
        assert_eq!(top.part_states(&r)[0], PartState::Rolling);
        let (top, r) = row(law, Mode::Flight, [0.0, 10.0, 1.0], [0.0, 0.0]);
        assert_eq!(top.part_states(&r)[0], PartState::Flight);
        assert_eq!(top.contact_mode(&r), Mode::Flight);
        for (k, s) in PartState::ALL.iter().enumerate() {
            assert_eq!(s.code() as usize, k);
        }
    }
}
