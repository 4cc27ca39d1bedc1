//! One memory and work budget for every size a config or a flag sets (records, samples,
//! cycles, hits, lines, plants, verify draws), checked before anything is allocated: a
//! size past it is refused naming the key, the value, what it would need and the
//! largest accepted (the Monte Carlo band has its own, finer budget in msd-mc).
//!
//! ```
//! use msd_experiment::budget::{Budget, check};
//! // 1e9 repeats of a 7,501-sample record with one channel: far past what is held.
//! let (key, message) = check("setup.records", 1e9, 2.0 * 7501.0, Budget::Held).unwrap_err();
//! assert_eq!(key, "setup.records");
//! assert!(message.contains("the largest accepted is 3332"), "{message}");
//! assert!(check("setup.records", 5.0, 2.0 * 7501.0, Budget::Held).is_ok());
//! ```

/// Samples held in memory at once by a run: every record's channels (a run keeps a few
/// copies of them: the data, the model, the residuals, the sensitivities), about 400 MB
/// a copy.
pub const SAMPLES_HELD: f64 = 5e7;

/// Samples fitted by a command in all: a `--verify` draw or a robust design's plant
/// costs the samples of one experiment each (a fit simulates them a few dozen times).
/// At this budget a check of a short test runs minutes, not hours.
pub const SAMPLES_FITTED: f64 = 2e8;

/// Samples fitted by a `--verify` in all, a chain's weighted by its simulation's size
/// ([`ChainSection::work_per_sample`](crate::config::ChainSection::work_per_sample)):
/// the largest check accepted runs about half a minute on the two threads a verify
/// uses (release build, measured: the paper's largest, 1999 draws, 26.5 s wall; the
/// two-storey rig's 856, 17.4 s; eight masses' 14, 13.2 s; see BENCHMARKS.md).
pub const SAMPLES_VERIFIED: f64 = 3e7;

/// Which budget a size counts against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Budget {
    /// [`SAMPLES_HELD`].
    Held,
    /// [`SAMPLES_FITTED`].
    Fitted,
    /// [`SAMPLES_VERIFIED`].
    Verified,
}

impl Budget {
    /// The budget's samples and what they are, in words.
    fn limit(self) -> (f64, &'static str) {
        match self {
            Budget::Held => (SAMPLES_HELD, "samples held in memory at once"),
            Budget::Fitted => (SAMPLES_FITTED, "samples fitted in all"),
            Budget::Verified => (SAMPLES_VERIFIED, "samples fitted in all"),
        }
    }
}

/// Checks `key = value` whose every unit costs `per_unit` samples of `budget`: an error
/// (key, message after the key) naming what it would need and the largest value
/// accepted when `value × per_unit` is past the budget (or not finite).
pub fn check(
    key: &str,
    value: f64,
    per_unit: f64,
    budget: Budget,
) -> std::result::Result<(), (String, String)> {
    check_beside(key, value, per_unit, 0.0, budget)
}

/// As [`check`], with `fixed` samples beside the `value × per_unit` (e.g. a settling
/// time before the records).
pub fn check_beside(
    key: &str,
    value: f64,
    per_unit: f64,
    fixed: f64,
    budget: Budget,
) -> std::result::Result<(), (String, String)> {
    let (limit, what) = budget.limit();
    let need = fixed + value * per_unit;
    if need.is_finite() && need <= limit {
        return Ok(());
    }
    let largest = ((limit - fixed) / per_unit).floor().max(0.0);
    let each = crate::fmt::sig(per_unit, 6);
    let beside = if fixed > 0.0 {
        format!(" beside {} fixed", crate::fmt::sig(fixed, 4))
    } else {
        String::new()
    };
    Err((
        key.to_string(),
        format!(
            " = {value}: needs {need:.3e} {what} ({each} each{beside}); the budget is {limit:.0e}, so the largest accepted is {largest}"
        ),
    ))
}

/// The samples of one experiment of `config` (every record's channels and drive, or a
/// test machine's conditions; a chain's weighted by its simulation's size), as simulated for `plan --verify`, `design --verify` and
/// each plant of a robust design; 0 when the config has no time grid (measured data).
pub fn samples_per_experiment(config: &crate::config::Config) -> f64 {
    let Some(time) = &config.time else {
        return 0.0;
    };
    if let Some(chain) = &config.chain {
        // The state's steps cost the time, not the few channels read from it.
        return time.samples() as f64 * chain.work_per_sample();
    }
    let Some(setup) = &config.setup else {
        return 2.0 * time.samples() as f64;
    };
    let channels = setup.channels().len() as f64 + 1.0;
    if setup.excitation == crate::config::ExcitationKind::ImposedDisplacement {
        let cycles = setup.cycles as f64;
        return channels
            * setup
                .conditions
                .iter()
                .map(|c| cycles / (c.frequency * time.dt))
                .sum::<f64>();
    }
    channels * setup.records as f64 * time.samples() as f64
}
