//! One local optimisation's outcome, as the estimators rank it under multistart.

use crate::stop::StopReason;
use msd_opt::{LevenbergMarquardtResult, NelderMeadResult, OptError, RankedCost};

/// One local run: its point, cost, counts and why it stopped, or the error that ended
/// it (a start that fails ranks last, with an infinite cost).
pub(crate) struct Local {
    /// The final point, in the estimator's own coordinates.
    pub(crate) x: Vec<f64>,
    /// Its cost Σr² (+∞ for a failed run).
    pub(crate) cost: f64,
    /// Iterations.
    pub(crate) iterations: usize,
    /// Cost (residual) evaluations by the optimiser.
    pub(crate) evaluations: usize,
    /// Jacobian evaluations.
    pub(crate) jacobians: usize,
    /// Residual evaluations spent on finite differences.
    pub(crate) finite_differences: usize,
    /// Why it stopped, or the error that ended it.
    pub(crate) stop: Result<StopReason, OptError>,
}

impl Local {
    pub(crate) fn nelder_mead(r: NelderMeadResult) -> Self {
        Self {
            x: r.x,
            cost: r.cost,
            iterations: r.iterations,
            evaluations: r.evaluations,
            jacobians: 0,
            finite_differences: 0,
            stop: Ok(r.exit.into()),
        }
    }

    pub(crate) fn levenberg_marquardt(r: LevenbergMarquardtResult) -> Self {
        Self {
            x: r.x,
            cost: r.cost,
            iterations: r.iterations,
            evaluations: r.evaluations,
            jacobians: r.jacobian_evaluations,
            finite_differences: r.finite_difference_evaluations,
            stop: Ok(r.exit.into()),
        }
    }

    /// A run from `x` that failed with `error`: it ranks last.
    pub(crate) fn failed(x: &[f64], error: OptError) -> Self {
        Self {
            x: x.to_vec(),
            cost: f64::INFINITY,
            iterations: 0,
            evaluations: 0,
            jacobians: 0,
            finite_differences: 0,
            stop: Err(error),
        }
    }

    /// Residual evaluations in all: the optimiser's and the finite differences'.
    pub(crate) fn simulations(&self) -> usize {
        self.evaluations + self.finite_differences
    }

    /// Why a run that reached a finite cost stopped; otherwise why it did not, in words
    /// (the optimiser's reason, or "the local run failed: …").
    pub(crate) fn finished(&self) -> Result<StopReason, String> {
        match &self.stop {
            Ok(stop) if self.cost.is_finite() => Ok(stop.clone()),
            Ok(stop) => Err(stop.to_string()),
            Err(e) => Err(format!("the local run failed: {e}")),
        }
    }
}

impl RankedCost for Local {
    fn ranked_cost(&self) -> f64 {
        self.cost
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use msd_opt::{NelderMeadExit, NelderMeadOptions, nelder_mead};

    #[test]
    fn a_converged_run_is_finished_and_a_failed_one_says_why() -> Result<(), OptError> {
        let r = nelder_mead(
            |x| (x[0] - 1.0).powi(2),
            &[0.0],
            &NelderMeadOptions::default(),
        )?;
        let evaluations = r.evaluations;
        let run = Local::nelder_mead(r);
        assert_eq!(run.evaluations, evaluations);
        assert_eq!(
            run.finished(),
            Ok(StopReason::NelderMead(NelderMeadExit::Converged))
        );
        let failed = Local::failed(&[2.0], OptError::EmptyStart);
        assert_eq!(failed.ranked_cost(), f64::INFINITY);
        assert_eq!(
            failed.finished(),
            Err(format!("the local run failed: {}", OptError::EmptyStart))
        );
        Ok(())
    }

    #[test]
    fn a_run_without_a_finite_cost_is_not_finished() {
        let run = Local {
            cost: f64::INFINITY,
            stop: Ok(NelderMeadExit::NonFiniteCost.into()),
            ..Local::failed(&[0.0], OptError::EmptyStart)
        };
        assert_eq!(
            run.finished(),
            Err(NelderMeadExit::NonFiniteCost.to_string())
        );
    }
}
