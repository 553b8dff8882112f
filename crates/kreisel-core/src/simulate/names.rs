//! Every public name of the simulation results, declared once: contact modes, kinds of
//! motion, and the summaries a batch or a sweep keeps of a run, with units and descriptions.
//! The bindings export them; Python, the command line and the sweeps read them from there.

use crate::models::lagrange::MotionKind;
use crate::models::play_top::Mode;

/// The contact modes of a play top, by code.
pub const MODES: [&str; 3] = [
    Mode::ALL[0].name(),
    Mode::ALL[1].name(),
    Mode::ALL[2].name(),
];

/// The kinds of motion of a Lagrange top, by code.
pub const MOTION_KINDS: [&str; 8] = [
    MotionKind::ALL[0].name(),
    MotionKind::ALL[1].name(),
    MotionKind::ALL[2].name(),
    MotionKind::ALL[3].name(),
    MotionKind::ALL[4].name(),
    MotionKind::ALL[5].name(),
    MotionKind::ALL[6].name(),
    MotionKind::ALL[7].name(),
];

/// A summary of a run: its name, unit, what it is, which model has it, and whether it is a
/// category (stored as the code of one of a few names) or a count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SummaryField {
    /// Public name.
    pub name: &'static str,
    /// Unit ("1" for pure numbers, "" for categories and counts).
    pub unit: &'static str,
    /// One line on what it is.
    pub description: &'static str,
    /// "play", "heavy" (integrated heavy and Lagrange tops) or "exact" (the Lagrange top's
    /// analysis, without integration).
    pub model: &'static str,
    /// The names a category takes ("modes", "motion_kinds"); "" for numbers.
    pub category: &'static str,
    /// Kept by default (else on request: it costs more runs).
    pub default: bool,
}

const fn field(
    model: &'static str,
    name: &'static str,
    unit: &'static str,
    description: &'static str,
) -> SummaryField {
    SummaryField {
        name,
        unit,
        description,
        model,
        category: "",
        default: true,
    }
}

/// Every summary, by model, in the order they are stored.
pub const SUMMARY_FIELDS: [SummaryField; 27] = [
    field("play", "final_u", "1", "u = cos(theta) at the end"),
    SummaryField {
        category: "modes",
        ..field("play", "final_mode", "", "contact mode at the end")
    },
    field(
        "play",
        "inversion_time",
        "s",
        "first upward crossing of the inversion level (s), NaN if none",
    ),
    field(
        "play",
        "jellett_drift",
        "1",
        "largest relative change of Jellett's integral",
    ),
    field(
        "play",
        "energy_drift",
        "1",
        "largest relative change of the energy (E + dissipated for play tops)",
    ),
    field("play", "steps", "", "accepted steps"),
    field(
        "play",
        "final_parts_in_contact",
        "",
        "the parts touching at the end, as a bit mask (bit i: part i; 0 in flight)",
    ),
    field(
        "play",
        "first_touchdown_time_0",
        "s",
        "first touchdown of part 0 (s), NaN if none",
    ),
    field(
        "play",
        "first_touchdown_time_1",
        "s",
        "first touchdown of part 1 (s), NaN if none",
    ),
    field(
        "play",
        "first_touchdown_time_2",
        "s",
        "first touchdown of part 2 (s), NaN if none",
    ),
    field(
        "play",
        "first_touchdown_time_3",
        "s",
        "first touchdown of part 3 (s), NaN if none",
    ),
    field(
        "play",
        "flat_time",
        "s",
        "the time a ring part came down flat and ended the run (s), NaN if none",
    ),
    field(
        "play",
        "rest_time",
        "s",
        "the time the top came to rest and the run ended (s), NaN if none",
    ),
    field("heavy", "final_theta", "rad", "theta at the end (rad)"),
    field(
        "heavy",
        "theta_min",
        "rad",
        "smallest theta over the steps (rad)",
    ),
    field(
        "heavy",
        "theta_max",
        "rad",
        "largest theta over the steps (rad)",
    ),
    field(
        "heavy",
        "energy_drift",
        "1",
        "largest relative change of the energy (E + dissipated for play tops)",
    ),
    field(
        "heavy",
        "Mz_drift",
        "1",
        "largest change of Mz relative to |M0|",
    ),
    field(
        "heavy",
        "M3_drift",
        "1",
        "largest change of M3 relative to |M0| (NaN unless symmetric)",
    ),
    field(
        "heavy",
        "kovalevskaya_drift",
        "1",
        "largest relative change of Kovalevskaya's K (NaN unless such a top)",
    ),
    field("heavy", "steps", "", "accepted steps"),
    SummaryField {
        default: false,
        ..field(
            "heavy",
            "lyapunov",
            "1/s",
            "largest Lyapunov exponent (1/s), Benettin's renormalisation over t_end",
        )
    },
    SummaryField {
        category: "motion_kinds",
        ..field(
            "exact",
            "motion_kind",
            "",
            "kind of motion of the exact solution",
        )
    },
    field(
        "exact",
        "theta_min",
        "rad",
        "smallest theta over the steps (rad)",
    ),
    field(
        "exact",
        "theta_max",
        "rad",
        "largest theta over the steps (rad)",
    ),
    field(
        "exact",
        "nutation_period",
        "s",
        "period of theta (s), inf on the separatrix",
    ),
    field(
        "exact",
        "mean_precession_rate",
        "rad/s",
        "mean of phi_dot over a nutation period (rad/s)",
    ),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_model_names_each_summary_once_with_one_description_per_name() {
        for model in ["play", "heavy", "exact"] {
            let names: Vec<_> = SUMMARY_FIELDS
                .iter()
                .filter(|f| f.model == model)
                .map(|f| f.name)
                .collect();
            let mut unique = names.clone();
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), names.len(), "{model}");
        }
        // a name shared by two models means the same thing there (one column in a sweep
        // store has one description)
        for a in SUMMARY_FIELDS {
            for b in SUMMARY_FIELDS {
                if a.name == b.name {
                    assert_eq!(a.description, b.description, "{}", a.name);
                    assert_eq!(a.unit, b.unit, "{}", a.name);
                }
            }
        }
    }
}
