//! Many trajectories at once, in parallel, each reduced to a few numbers.
//!
//! A batch is a slice of independent runs. Each run is simulated exactly as a single call
//! would do it (same code, same settings), so a run's summary does not depend on the batch
//! it is in, on the number of threads or on the order of completion: results are equal bit
//! for bit however the work is split. That is what lets a sweep be cut into chunks and
//! spread over threads, processes or machines.

use super::{Model, Settings};
use crate::chaos::{self, LyapunovSettings};
use crate::error::{KreiselError, Result};
use crate::models::heavy_top::RigidState;
use crate::simulate;

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

/// Every run simulated with the same settings and summarised as it goes (no rows kept).
/// The settings are checked once, before any run starts (against the first model).
pub fn many<M: Model>(
    runs: &[(M, M::State)],
    settings: &Settings,
    threads: Option<usize>,
) -> Result<Vec<Result<M::Summary>>> {
    if let Some((model, _)) = runs.first() {
        simulate::check(model, settings, 0)?;
    } else {
        settings.check()?;
    }
    par_map(runs, threads, |(model, s0)| {
        simulate::run_summary(model, s0, settings)
    })
}

/// Heavy tops: the largest Lyapunov exponent of every run (see [`chaos::lyapunov`]).
pub fn lyapunov_many<M: chaos::Segments>(
    runs: &[(M, RigidState)],
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
    use crate::models::heavy_top::simulate::HeavySummary;
    use crate::models::heavy_top::HeavyTop;
    use crate::simulate::Accumulate;

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
            ..Settings::default()
        }
    }

    /// The summary of a run whose rows were all kept, then fed to the accumulator.
    fn from_rows(top: &HeavyTop, s0: &RigidState, st: &Settings) -> HeavySummary {
        let o = simulate::simulate(top, s0, st, &mut [], &mut |_| true).unwrap();
        let mut acc = top.summary(s0, st);
        for (t, s) in o.t.iter().zip(&o.rows) {
            acc.push(*t, s);
        }
        acc.finish(&o.info)
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
        let one = many(&runs, &st, Some(1)).unwrap();
        let two = many(&runs, &st, Some(2)).unwrap();
        let all = many(&runs, &st, None).unwrap();
        for (i, (top, s0)) in runs.iter().enumerate() {
            let single = from_rows(top, s0, &st);
            for batch in [&one, &two, &all] {
                let b = batch[i].as_ref().unwrap();
                assert_eq!(b.final_theta.to_bits(), single.final_theta.to_bits());
                assert_eq!(b.energy_drift.to_bits(), single.energy_drift.to_bits());
                assert_eq!(b.steps, single.steps);
            }
        }
    }

    #[test]
    fn streamed_summaries_are_those_of_the_recorded_states_for_every_method() {
        let top = lagrange();
        let s0 = start(0.4, 90.0);
        for info in simulate::METHODS {
            let dt = (!info.adaptive).then_some(1e-3);
            let mut st = settings(info.name, dt);
            st.t_end = 0.5;
            let kept = from_rows(&top, &s0, &st);
            let streamed = simulate::summarise(&top, &s0, &st).unwrap();
            assert_eq!(
                format!("{kept:?}"),
                format!("{streamed:?}"),
                "{}",
                info.name
            );
        }
    }

    #[test]
    fn summary_of_a_lagrange_top_sees_its_integrals() {
        let runs = [(lagrange(), start(0.3, 100.0))];
        let s = many(&runs, &settings("splitting", Some(1e-3)), None).unwrap()[0]
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
        let e = many(&runs, &settings("rk4", None), None).unwrap_err();
        assert!(e.to_string().contains("dt"), "{e}");
        let e = many(&runs, &settings("dop853", None), Some(0)).unwrap_err();
        assert!(e.to_string().contains("threads"), "{e}");
    }
}
