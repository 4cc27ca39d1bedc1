//! The iteration trace, printed like fminsearch's `Display = 'iter'`.
//!
//! ```
//! use msd_opt::{nelder_mead, NelderMeadOptions, TRACE_HEADER};
//!
//! let options = NelderMeadOptions { trace: true, ..Default::default() };
//! let r = nelder_mead(|x| (x[0] - 1.0).powi(2), &[0.0], &options).unwrap();
//! println!("{TRACE_HEADER}");
//! for row in &r.trace {
//!     println!("{row}");
//! }
//! assert_eq!(r.trace[0].evaluations, 1);
//! assert_eq!(r.trace.len(), r.iterations + 1);
//! ```

use std::fmt;

use serde::{Deserialize, Serialize};

/// Column titles of fminsearch's iterative display.
pub const TRACE_HEADER: &str = " Iteration   Func-count     min f(x)         Procedure";

/// What one iteration did (fminsearch's "Procedure" column).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Step {
    /// Iteration 0: only x0 was evaluated (blank in fminsearch's display).
    Start,
    /// Iteration 1: the other n vertices of the initial simplex.
    InitialSimplex,
    /// The reflected point replaced the worst vertex.
    Reflect,
    /// The expanded point replaced the worst vertex.
    Expand,
    /// The inside contraction replaced the worst vertex.
    ContractInside,
    /// The outside contraction replaced the worst vertex.
    ContractOutside,
    /// All vertices but the best moved halfway towards it.
    Shrink,
}

impl fmt::Display for Step {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Step::Start => "",
            Step::InitialSimplex => "initial simplex",
            Step::Reflect => "reflect",
            Step::Expand => "expand",
            Step::ContractInside => "contract inside",
            Step::ContractOutside => "contract outside",
            Step::Shrink => "shrink",
        })
    }
}

/// One line of the trace.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TraceRow {
    /// Iteration count after the step (0 for x0 alone).
    pub iteration: usize,
    /// Function evaluations so far.
    pub evaluations: usize,
    /// Lowest cost in the simplex after the step.
    pub best_cost: f64,
    /// The step taken.
    pub step: Step,
}

impl fmt::Display for TraceRow {
    /// fminsearch's `' %5.0f        %5.0f     %12.6g         %s'`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            " {:>5}        {:>5}     {:>12}         {}",
            self.iteration,
            self.evaluations,
            format_g(self.best_cost, 6),
            self.step
        )
    }
}

/// C's `%.{precision}g`: `precision` significant digits, trailing zeros removed,
/// scientific notation when the exponent is below −4 or at least `precision`.
pub(crate) fn format_g(x: f64, precision: usize) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "NaN".into()
        } else if x > 0.0 {
            "Inf".into()
        } else {
            "-Inf".into()
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    let p = precision.max(1);
    let sci = format!("{:.*e}", p - 1, x);
    let (mantissa, exponent) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    if exponent < -4 || exponent >= p as i32 {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!(
            "{}e{}{:02}",
            trim_zeros(mantissa),
            sign,
            exponent.unsigned_abs()
        )
    } else {
        let decimals = (p as i32 - 1 - exponent).max(0) as usize;
        trim_zeros(&format!("{:.*}", decimals, x)).to_string()
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_g_matches_c() {
        assert_eq!(format_g(8.17766e-10, 6), "8.17766e-10");
        assert_eq!(format_g(24.2, 6), "24.2");
        assert_eq!(format_g(123456.0, 6), "123456");
        assert_eq!(format_g(1234567.0, 6), "1.23457e+06");
        assert_eq!(format_g(0.0001, 6), "0.0001");
        assert_eq!(format_g(-0.5, 6), "-0.5");
        assert_eq!(format_g(f64::INFINITY, 6), "Inf");
    }

    #[test]
    fn row_layout() {
        let row = TraceRow {
            iteration: 1,
            evaluations: 3,
            best_cost: 20.05,
            step: Step::InitialSimplex,
        };
        assert_eq!(
            row.to_string(),
            "     1            3            20.05         initial simplex"
        );
    }
}
