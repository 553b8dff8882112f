//! Many trajectories at once, in parallel, each reduced to a few numbers.
//!
//! A batch is a slice of independent runs. Each run is simulated exactly as a single call
//! would do it (same code, same settings), so a run's summary does not depend on the batch
//! it is in, on the number of threads or on the order of completion: results are equal bit
//! for bit however the work is split. That is what lets a sweep be cut into chunks and
//! spread over threads, processes or machines.

use crate::chaos::{self, LyapunovSettings};
use crate::error::{KreiselError, Result};
use crate::models::heavy_top::{HeavyTop, RigidState};
use crate::models::play_top::{PlayTop, DIM};
use crate::rotation::euler_from_quaternion;
use crate::simulate::{self, Settings};
use crate::simulate_play::{self, PlaySettings, Summary};

/// Runs `f` over `items` on `threads` threads (None: rayon's global pool, all cores).
pub fn par_map<T, R, F>(items: &[T], threads: Option<usize>, f: F) -> Result<Vec<R>>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync + Send,
{
    use rayon::prelude::*;
    match threads {
        None => Ok(items.par_iter().map(&f).collect()),
        Some(0) => Err(KreiselError::invalid(
            "threads",
            0.0,
            "it must be >= 1 (or None for all cores)",
        )),
        Some(1) => Ok(items.iter().map(&f).collect()),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| KreiselError::invalid("threads", n as f64, format!("no pool: {e}")))?;
            Ok(pool.install(|| items.par_iter().map(&f).collect()))
        }
    }
}

/// Play tops: every run simulated with the same settings and summarised.
pub fn play_many(
    runs: &[(PlayTop, [f64; DIM])],
    settings: &PlaySettings,
    threads: Option<usize>,
) -> Result<Vec<Result<Summary>>> {
    par_map(runs, threads, |(top, y0)| {
        simulate_play::simulate_play(top, *y0, settings).map(|o| simulate_play::summarise(top, &o))
    })
}

/// What is kept of one heavy-top run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeavySummary {
    /// theta at the end (rad).
    pub final_theta: f64,
    /// Smallest theta over the recorded states (rad).
    pub theta_min: f64,
    /// Largest theta over the recorded states (rad).
    pub theta_max: f64,
    /// Largest |E - E0| over the run, relative to the energy scale T0 + m g |c|.
    pub energy_drift: f64,
    /// Largest |Mz - Mz0| over the run, relative to |M0| (absolute if M0 = 0).
    pub mz_drift: f64,
    /// Largest |M3 - M3_0| relative to |M0| where M3 is an integral (symmetric tops), else NaN.
    pub m3_drift: f64,
    /// Largest |K - K0| relative to |K0| where Kovalevskaya's K is an integral, else NaN.
    pub kovalevskaya_drift: f64,
    /// Accepted steps.
    pub steps: u64,
}

fn relative(d: f64, scale: f64) -> f64 {
    if scale > 0.0 {
        d / scale
    } else {
        d
    }
}

/// The running summary of a heavy-top run, fed one state at a time.
struct HeavyAcc<'a> {
    top: &'a HeavyTop,
    e0: f64,
    mz0: f64,
    m30: Option<f64>,
    k0: Option<f64>,
    m_norm: f64,
    e_scale: f64,
    theta: f64,
    th_min: f64,
    th_max: f64,
    de: f64,
    dmz: f64,
    dm3: f64,
    dk: f64,
}

impl<'a> HeavyAcc<'a> {
    fn new(top: &'a HeavyTop, s0: &RigidState) -> Self {
        let mom = top.momentum(s0.omega);
        let c = top.com();
        let kinetic = 0.5 * (mom[0] * s0.omega[0] + mom[1] * s0.omega[1] + mom[2] * s0.omega[2]);
        HeavyAcc {
            top,
            e0: top.energy(s0),
            mz0: top.mz(s0),
            m30: top.m3(s0),
            k0: top.kovalevskaya(s0),
            m_norm: (mom[0] * mom[0] + mom[1] * mom[1] + mom[2] * mom[2]).sqrt(),
            e_scale: kinetic + top.m() * top.g() * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt(),
            theta: f64::NAN,
            th_min: f64::INFINITY,
            th_max: f64::NEG_INFINITY,
            de: 0.0,
            dmz: 0.0,
            dm3: 0.0,
            dk: 0.0,
        }
    }

    fn push(&mut self, s: &RigidState) {
        let top = self.top;
        self.theta = euler_from_quaternion(s.q).1;
        self.th_min = self.th_min.min(self.theta);
        self.th_max = self.th_max.max(self.theta);
        self.de = self.de.max((top.energy(s) - self.e0).abs());
        self.dmz = self.dmz.max((top.mz(s) - self.mz0).abs());
        if let (Some(a), Some(b)) = (self.m30, top.m3(s)) {
            self.dm3 = self.dm3.max((b - a).abs());
        }
        if let (Some(a), Some(b)) = (self.k0, top.kovalevskaya(s)) {
            self.dk = self.dk.max((b - a).abs());
        }
    }

    fn finish(&self, steps: u64) -> HeavySummary {
        HeavySummary {
            final_theta: self.theta,
            theta_min: self.th_min,
            theta_max: self.th_max,
            energy_drift: relative(self.de, self.e_scale),
            mz_drift: relative(self.dmz, self.m_norm),
            m3_drift: self
                .m30
                .map_or(f64::NAN, |_| relative(self.dm3, self.m_norm)),
            kovalevskaya_drift: self.k0.map_or(f64::NAN, |k| relative(self.dk, k.abs())),
            steps,
        }
    }
}

/// Summarises one heavy-top run from its recorded states (every step or `t_eval`).
pub fn summarise_heavy(top: &HeavyTop, states: &[RigidState], steps: u64) -> HeavySummary {
    let mut acc = HeavyAcc::new(top, &states[0]);
    for s in states {
        acc.push(s);
    }
    acc.finish(steps)
}

/// Simulates and summarises one heavy-top run in constant memory (no states kept).
pub fn run_heavy(top: &HeavyTop, s0: &RigidState, settings: &Settings) -> Result<HeavySummary> {
    let mut acc = HeavyAcc::new(top, s0);
    let stats = simulate::simulate_each(top, s0, settings, &mut |_, s| acc.push(s))?;
    Ok(acc.finish(stats.steps))
}

/// Heavy tops: every run simulated with the same settings (any method, no events) and
/// summarised. The settings are checked once, before any run starts.
pub fn heavy_many(
    runs: &[(HeavyTop, RigidState)],
    settings: &Settings,
    threads: Option<usize>,
) -> Result<Vec<Result<HeavySummary>>> {
    simulate::check(settings, &simulate::method(&settings.method)?)?;
    par_map(runs, threads, |(top, s0)| run_heavy(top, s0, settings))
}

/// Heavy tops: the largest Lyapunov exponent of every run (see [`chaos::lyapunov`]).
pub fn lyapunov_many(
    runs: &[(HeavyTop, RigidState)],
    settings: &LyapunovSettings,
    threads: Option<usize>,
) -> Result<Vec<Result<f64>>> {
    par_map(runs, threads, |(top, s0)| {
        chaos::lyapunov(top, s0, settings).map(|l| l.exponent)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lagrange() -> HeavyTop {
        HeavyTop::new(6.8e-4, 6.8e-4, 1.5e-4, 0.3, [0.0, 0.0, 0.04], 9.81).unwrap()
    }

    fn start(theta: f64, spin: f64) -> RigidState {
        let h = 0.5 * theta;
        RigidState::new([h.cos(), h.sin(), 0.0, 0.0], [0.0, 0.0, spin]).unwrap()
    }

    fn settings(method: &str, dt: Option<f64>) -> Settings {
        Settings {
            method: method.into(),
            t_end: 2.0,
            rtol: 1e-10,
            atol: 1e-12,
            dt,
            t_eval: None,
        }
    }

    #[test]
    fn batch_equals_single_runs_bit_for_bit_for_any_thread_count() {
        let runs: Vec<_> = (0..7)
            .map(|i| {
                (
                    lagrange(),
                    start(0.2 + 0.1 * i as f64, 80.0 + 10.0 * i as f64),
                )
            })
            .collect();
        let st = settings("dop853", None);
        let one = heavy_many(&runs, &st, Some(1)).unwrap();
        let two = heavy_many(&runs, &st, Some(2)).unwrap();
        let all = heavy_many(&runs, &st, None).unwrap();
        for (i, (top, s0)) in runs.iter().enumerate() {
            let o = simulate::simulate(top, s0, &st, &mut [], false, &mut |_| true).unwrap();
            let single = summarise_heavy(top, &o.states, o.stats.steps);
            for batch in [&one, &two, &all] {
                let b = batch[i].as_ref().unwrap();
                assert_eq!(b.final_theta.to_bits(), single.final_theta.to_bits());
                assert_eq!(b.energy_drift.to_bits(), single.energy_drift.to_bits());
                assert_eq!(b.steps, single.steps);
            }
        }
    }

    #[test]
    fn streamed_states_are_the_recorded_ones_for_every_method() {
        let top = lagrange();
        let s0 = start(0.4, 90.0);
        for info in simulate::METHODS {
            let dt = (!info.adaptive).then_some(1e-3);
            let mut st = settings(info.name, dt);
            st.t_end = 0.5;
            let out = simulate::simulate(&top, &s0, &st, &mut [], false, &mut |_| true).unwrap();
            let mut seen = Vec::new();
            let stats =
                simulate::simulate_each(&top, &s0, &st, &mut |t, s| seen.push((t, *s))).unwrap();
            assert_eq!(stats, out.stats, "{}", info.name);
            assert_eq!(seen.len(), out.t.len(), "{}", info.name);
            for ((t, s), (t2, s2)) in seen.iter().zip(out.t.iter().zip(&out.states)) {
                assert_eq!(t.to_bits(), t2.to_bits(), "{}", info.name);
                assert_eq!(s.q.0, s2.q.0, "{}", info.name);
                assert_eq!(s.omega, s2.omega, "{}", info.name);
            }
        }
    }

    #[test]
    fn summary_of_a_lagrange_top_sees_its_integrals() {
        let runs = [(lagrange(), start(0.3, 100.0))];
        let s = heavy_many(&runs, &settings("splitting", Some(1e-3)), None).unwrap()[0]
            .clone()
            .unwrap();
        // The splitting keeps Mz and M3 to round-off and E to O(dt^2).
        assert!(s.mz_drift < 1e-13 && s.m3_drift < 1e-13, "{s:?}");
        assert!(s.energy_drift < 1e-4 && s.energy_drift > 0.0, "{s:?}");
        assert!(s.kovalevskaya_drift.is_nan());
        assert!(s.theta_min >= 0.3 - 1e-12 && s.theta_max > 0.3, "{s:?}");
        assert_eq!(s.steps, 2000);
    }

    #[test]
    fn settings_are_checked_before_any_run_and_zero_threads_is_refused() {
        let runs = [(lagrange(), start(0.3, 100.0))];
        let e = heavy_many(&runs, &settings("rk4", None), None).unwrap_err();
        assert!(e.to_string().contains("dt"), "{e}");
        let e = heavy_many(&runs, &settings("dop853", None), Some(0)).unwrap_err();
        assert!(e.to_string().contains("threads"), "{e}");
    }
}
