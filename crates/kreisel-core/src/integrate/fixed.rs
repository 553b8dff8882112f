//! The fixed-step driver: steps of `dt` from 0 to `t_end` (the last one shortened to land
//! on `t_end`), with output either at every step or at requested times. A requested time
//! between two grid points is reached by a partial step from the earlier one, taken on a
//! copy, so the grid trajectory itself is never disturbed (symplecticity is kept).

use crate::error::{KreiselError, Result};

/// A fixed-step scheme on its own internal state `Y`.
pub trait FixedScheme {
    /// The scheme's internal state.
    type Y: Copy;
    /// Advances `y` by `h`.
    fn step(&self, y: &mut Self::Y, h: f64) -> Result<()>;
}

/// How often (in steps) a fixed-step run asks whether to go on.
const ASK_EVERY: u64 = 1024;

/// Runs a scheme. `record(t, &y)` is called at t = 0 and at every output time.
/// `keep_going(t)` is asked every 1024 steps; false stops the run there. Returns the steps
/// taken and whether the run reached `t_end`.
pub fn run<S: FixedScheme>(
    scheme: &S,
    y0: S::Y,
    t_end: f64,
    dt: f64,
    t_eval: Option<&[f64]>,
    mut record: impl FnMut(f64, &S::Y),
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<(u64, bool)> {
    if t_end == 0.0 {
        record(0.0, &y0);
        return Ok((0, true));
    }
    let n = ((t_end / dt) * (1.0 - 1e-12)).ceil().max(1.0) as u64;
    let mut y = y0;
    let mut t = 0.0;
    let mut next = 0usize;
    match t_eval {
        None => record(0.0, &y),
        Some(te) => {
            while next < te.len() && te[next] <= 0.0 {
                record(te[next], &y);
                next += 1;
            }
        }
    }
    for k in 0..n {
        let t1 = if k + 1 == n {
            t_end
        } else {
            (k + 1) as f64 * dt
        };
        if let Some(te) = t_eval {
            while next < te.len() && te[next] < t1 {
                let mut yc = y;
                scheme.step(&mut yc, te[next] - t)?;
                record(te[next], &yc);
                next += 1;
            }
        }
        scheme.step(&mut y, t1 - t)?;
        t = t1;
        match t_eval {
            None => record(t, &y),
            Some(te) => {
                while next < te.len() && te[next] <= t1 {
                    record(te[next], &y);
                    next += 1;
                }
            }
        }
        if (k + 1) % ASK_EVERY == 0 && k + 1 < n && !keep_going(t) {
            return Ok((k + 1, false));
        }
    }
    if let Some(te) = t_eval {
        if next < te.len() {
            // (unreachable for checked settings)
            return Err(KreiselError::invalid(
                "t_eval",
                te[next],
                format!("output times must lie in [0, t_end = {t_end}]"),
            ));
        }
    }
    Ok((n, true))
}
