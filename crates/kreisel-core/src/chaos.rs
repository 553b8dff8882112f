//! The largest Lyapunov exponent of a heavy top, by Benettin's renormalisation.
//!
//! Two motions start a distance `d0` apart and are integrated side by side; every `tau`
//! seconds their separation d is measured, ln(d / d0) is added to a sum, and the second
//! motion is pulled back along the separation to distance `d0`. The running estimate is
//! the sum over the time elapsed. The separation is the 6-vector (body rotation vector of
//! R1^T R2, omega2 - omega1): a metric on the state space (SO(3) x R^3) whose choice does
//! not change the limit. For an integrable top (Euler, Lagrange, Kovalevskaya) separations
//! grow only linearly and the estimate decays like ln(t) / t; for a chaotic one it settles
//! at a positive value.

use crate::error::{KreiselError, Result};
use crate::models::heavy_top::driven::{DrivenRow, DrivenTop};
use crate::models::heavy_top::{HeavyTop, RigidState};
use crate::rotation::Quat;
use crate::simulate::{self, Model, Settings};

/// A top whose motion can be followed segment by segment: the model that continues a run
/// from time `t0` (the same for an autonomous top; a driven top's pivot clock moves on),
/// and the state of an output row.
pub trait Segments: Model<State = RigidState> + Sized {
    /// The model for a run that starts at time `t0`.
    fn starting_at(&self, t0: f64) -> Self;
    /// The rigid state of a row.
    fn state_of(row: &Self::Row) -> RigidState;
}

impl Segments for HeavyTop {
    fn starting_at(&self, _t0: f64) -> Self {
        *self
    }
    fn state_of(row: &RigidState) -> RigidState {
        *row
    }
}

impl Segments for DrivenTop {
    fn starting_at(&self, t0: f64) -> Self {
        self.later(t0)
    }
    fn state_of(row: &DrivenRow) -> RigidState {
        row.state()
    }
}

/// How to estimate the exponent.
#[derive(Debug, Clone)]
pub struct LyapunovSettings {
    /// Total time (s), > 0.
    pub t_end: f64,
    /// Renormalisation interval (s), in (0, t_end].
    pub tau: f64,
    /// Initial (and renormalised) separation, in (0, 1e-3].
    pub d0: f64,
    /// Direction of the first separation (normalised here; not zero).
    pub direction: [f64; 6],
    /// Tolerances of the DOP853 integration of both motions.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

/// The estimate and its history.
#[derive(Debug, Clone, Default)]
pub struct Lyapunov {
    /// The estimate at t_end (1/s).
    pub exponent: f64,
    /// Times of the renormalisations (s).
    pub t: Vec<f64>,
    /// Running estimates at those times (1/s).
    pub running: Vec<f64>,
}

fn conj(q: Quat) -> Quat {
    Quat([q.0[0], -q.0[1], -q.0[2], -q.0[3]])
}

/// Rotation vector (rad) of a unit quaternion, the shorter way round.
fn rotation_vector(q: Quat) -> [f64; 3] {
    let [mut w, mut x, mut y, mut z] = q.0;
    if w < 0.0 {
        (w, x, y, z) = (-w, -x, -y, -z);
    }
    let s = (x * x + y * y + z * z).sqrt();
    if s == 0.0 {
        return [0.0; 3];
    }
    let k = 2.0 * s.atan2(w) / s;
    [k * x, k * y, k * z]
}

/// The separation of `b` from `a`.
pub fn separation(a: &RigidState, b: &RigidState) -> [f64; 6] {
    let r = rotation_vector(conj(a.q) * b.q);
    [
        r[0],
        r[1],
        r[2],
        b.omega[0] - a.omega[0],
        b.omega[1] - a.omega[1],
        b.omega[2] - a.omega[2],
    ]
}

/// `a` displaced by the separation `d`.
pub fn displace(a: &RigidState, d: &[f64; 6]) -> RigidState {
    RigidState {
        q: (a.q * Quat::from_rotation_vector([d[0], d[1], d[2]])).normalized(),
        omega: [a.omega[0] + d[3], a.omega[1] + d[4], a.omega[2] + d[5]],
    }
}

fn norm6(d: &[f64; 6]) -> f64 {
    d.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn check(s: &LyapunovSettings) -> Result<()> {
    if !(s.t_end.is_finite() && s.t_end > 0.0) {
        return Err(KreiselError::invalid(
            "t_end",
            s.t_end,
            "it must be a finite number > 0",
        ));
    }
    if !(s.tau.is_finite() && s.tau > 0.0 && s.tau <= s.t_end) {
        return Err(KreiselError::invalid(
            "tau",
            s.tau,
            format!("it must lie in (0, t_end = {}]", s.t_end),
        ));
    }
    if s.t_end / s.tau > 1e7 {
        return Err(KreiselError::invalid(
            "tau",
            s.tau,
            "t_end / tau must not exceed 1e7 renormalisations",
        ));
    }
    if !(s.d0.is_finite() && s.d0 > 0.0 && s.d0 <= 1e-3) {
        return Err(KreiselError::invalid(
            "d0",
            s.d0,
            "it must lie in (0, 1e-3]: the separation must stay small",
        ));
    }
    let n = norm6(&s.direction);
    if !(n.is_finite() && n > 0.0) {
        return Err(KreiselError::InvalidParameter {
            name: "direction".into(),
            value: format!("{:?}", s.direction),
            allowed: "six finite numbers, not all zero".into(),
        });
    }
    Ok(())
}

/// Estimates the largest Lyapunov exponent of the motion from `s0`.
pub fn lyapunov<M: Segments>(
    top: &M,
    s0: &RigidState,
    settings: &LyapunovSettings,
) -> Result<Lyapunov> {
    lyapunov_with(top, s0, settings, &mut |_| true)
}

/// [`lyapunov`], asking `keep_going(t)` now and then (within each segment's run) whether to
/// go on; an interrupted estimate is an error.
pub fn lyapunov_with<M: Segments>(
    top: &M,
    s0: &RigidState,
    settings: &LyapunovSettings,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<Lyapunov> {
    check(settings)?;
    let n = (settings.t_end / settings.tau).round().max(1.0) as usize;
    let tau = settings.t_end / n as f64;
    let seg = Settings {
        method: "dop853".into(),
        t_end: tau,
        rtol: settings.rtol,
        atol: settings.atol,
        t_eval: Some(vec![tau]),
        ..Settings::default()
    };
    simulate::check(top, &seg, 0)?;
    let mut advance = |s: &RigidState, t0: f64| -> Result<RigidState> {
        let out = simulate::simulate(&top.starting_at(t0), s, &seg, &mut [], keep_going)?;
        if out.info.status == simulate::Status::Interrupted {
            return Err(KreiselError::Numerical(
                "Lyapunov estimate interrupted".into(),
            ));
        }
        out.rows
            .last()
            .map(M::state_of)
            .ok_or_else(|| KreiselError::Numerical("no state at the segment's end".into()))
    };
    let k = settings.d0 / norm6(&settings.direction);
    let mut a = *s0;
    let mut b = displace(&a, &settings.direction.map(|x| x * k));
    let mut sum = 0.0;
    let mut res = Lyapunov {
        t: Vec::with_capacity(n),
        running: Vec::with_capacity(n),
        ..Default::default()
    };
    for i in 1..=n {
        let t0 = (i - 1) as f64 * tau;
        a = advance(&a, t0)?;
        b = advance(&b, t0)?;
        let d = separation(&a, &b);
        let dist = norm6(&d);
        if !(dist.is_finite() && dist > 0.0) {
            return Err(KreiselError::Numerical(format!(
                "Lyapunov estimate: the two motions' separation is {dist} at t = {}; use a \
                 shorter tau or a larger d0",
                i as f64 * tau
            )));
        }
        sum += (dist / settings.d0).ln();
        let t = i as f64 * tau;
        let running = sum / t;
        if !running.is_finite() {
            // ln(d / d0) is a rounding's size over a time too short to divide by
            return Err(KreiselError::invalid(
                "tau",
                tau,
                format!(
                    "the estimate over {tau:e} s is {running}: the separation does not grow                      measurably in so short a time; give a longer tau and t_end"
                ),
            ));
        }
        res.t.push(t);
        res.running.push(running);
        b = displace(&a, &d.map(|x| x * settings.d0 / dist));
    }
    res.exponent = *res.running.last().expect("n >= 1");
    Ok(res)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn separation_and_displacement_are_inverse() {
        let a = RigidState::new([0.9, 0.1, -0.3, 0.2], [1.0, -2.0, 0.5]).unwrap();
        let d = [1e-4, -2e-4, 3e-5, 1e-3, 0.0, -5e-4];
        let b = displace(&a, &d);
        let back = separation(&a, &b);
        for (x, y) in d.iter().zip(&back) {
            assert!((x - y).abs() < 1e-15, "{d:?} {back:?}");
        }
    }

    fn settings(t_end: f64) -> LyapunovSettings {
        LyapunovSettings {
            t_end,
            tau: 1.0,
            d0: 1e-9,
            direction: [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            rtol: 1e-10,
            atol: 1e-12,
        }
    }

    #[test]
    fn chaotic_top_positive_lagrange_top_decaying() {
        let chaos = HeavyTop::new(1.0, 0.75, 0.5, 1.0, [0.3, 0.2, 0.4], 9.81).unwrap();
        let s0 = RigidState::new(
            crate::rotation::quaternion_from_euler(0.0, 1.2, 0.3).0,
            [2.0, 1.0, 3.0],
        )
        .unwrap();
        let lam = lyapunov(&chaos, &s0, &settings(200.0)).unwrap();
        assert!(lam.exponent > 0.2 && lam.exponent < 1.0, "{}", lam.exponent);
        let lag = HeavyTop::new(1.0, 1.0, 0.5, 1.0, [0.0, 0.0, 0.3], 1.0).unwrap();
        let s1 = RigidState::new([0.9, 0.4, 0.0, 0.0], [0.3, 0.7, 5.0]).unwrap();
        let l = lyapunov(&lag, &s1, &settings(200.0)).unwrap();
        assert!(
            l.exponent < 0.05 && l.exponent < 0.7 * l.running[49],
            "{}",
            l.exponent
        );
    }

    #[test]
    fn bad_settings_are_named() {
        let top = HeavyTop::new(1.0, 1.0, 0.5, 1.0, [0.0, 0.0, 0.3], 1.0).unwrap();
        let s = RigidState::new([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0]).unwrap();
        let mut st = settings(10.0);
        st.tau = 20.0;
        assert!(lyapunov(&top, &s, &st)
            .unwrap_err()
            .to_string()
            .contains("tau"));
        let mut st = settings(10.0);
        st.d0 = 0.1;
        assert!(lyapunov(&top, &s, &st)
            .unwrap_err()
            .to_string()
            .contains("d0"));
        // a free asymmetric top whose separation after 5e-324 s is d0 less a rounding: the
        // estimate ln(d / d0) / t would be -inf
        let free = HeavyTop::new(1.0, 1.2, 1.5, 1.0, [0.1, 0.0, 0.2], 0.0).unwrap();
        let tilted = RigidState::new(
            crate::rotation::quaternion_from_euler(0.0, 0.5, 0.0).0,
            [0.0, 0.0, 3.0],
        )
        .unwrap();
        let mut st = settings(5e-324);
        st.tau = 5e-324;
        st.direction = [1.0; 6];
        assert!(lyapunov(&free, &tilted, &st)
            .unwrap_err()
            .to_string()
            .starts_with("tau = 5e-324"));
        let mut st = settings(10.0);
        st.direction = [0.0; 6];
        assert!(lyapunov(&top, &s, &st)
            .unwrap_err()
            .to_string()
            .contains("direction"));
    }
}
