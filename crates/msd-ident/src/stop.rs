//! Why an estimator stopped: the optimiser's own reason, or a check after it.
//!
//! ```
//! use msd_ident::{estimate, EstimationOptions, PaperExperiment, StopReason};
//! use msd_opt::LmExit;
//! let experiment = PaperExperiment::generate(1)?;
//! let fit = estimate(&experiment.identification, &EstimationOptions::fast())?;
//! assert!(fit.stop.converged(), "{}", fit.stop);
//! assert!(matches!(fit.stop, StopReason::LevenbergMarquardt(exit) if exit.is_success()));
//! # Ok::<(), msd_ident::IdentError>(())
//! ```

use msd_opt::{LmExit, NelderMeadExit};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Why an estimation stopped, and whether that counts as converged
/// ([`StopReason::converged`]).
///
/// Displays as the optimiser's own words (fminsearch's message for Nelder–Mead,
/// MINPACK's for Levenberg–Marquardt); a [`StopReason::StoppedShort`] adds why the
/// estimate is not at a minimum.
///
/// ```
/// use msd_ident::StopReason;
/// use msd_opt::{LmExit, NelderMeadExit};
/// let nm = StopReason::NelderMead(NelderMeadExit::MaxIterations);
/// assert!(!nm.converged());
/// assert!(nm.to_string().starts_with("Exiting: Maximum number of iterations"));
/// let lm = StopReason::LevenbergMarquardt(LmExit::XTolerance);
/// assert!(lm.converged());
/// let short = StopReason::StoppedShort {
///     exit: Box::new(lm.clone()),
///     quantity: "damping".into(),
///     standard_errors: 3.25,
/// };
/// assert!(!short.converged());
/// assert_eq!(short.optimiser_reason(), &lm);
/// assert!(short.to_string().ends_with("moves damping by 3.2 standard errors"));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// Nelder–Mead (fminsearch) stopped; converged for [`NelderMeadExit::Converged`]
    /// (fminsearch's exitflag 1).
    NelderMead(NelderMeadExit),
    /// Levenberg–Marquardt stopped; converged for MINPACK's info 1–4
    /// ([`LmExit::is_success`]).
    LevenbergMarquardt(LmExit),
    /// The optimiser stopped for `exit`, but not at a minimum of the squared error: a
    /// Gauss–Newton step from the estimate moves `quantity` by `standard_errors` (> 1)
    /// of its standard errors. Never converged.
    StoppedShort {
        /// The optimiser's own reason.
        exit: Box<StopReason>,
        /// The estimated quantity the step moves most, e.g. "damping".
        quantity: String,
        /// How far it moves, in its standard errors.
        standard_errors: f64,
    },
}

impl StopReason {
    /// Whether the estimator met its convergence test (and, for
    /// [`StopReason::StoppedShort`], whether the estimate passed the check after it:
    /// never).
    ///
    /// ```
    /// use msd_ident::StopReason;
    /// use msd_opt::NelderMeadExit;
    /// assert!(StopReason::NelderMead(NelderMeadExit::Converged).converged());
    /// assert!(!StopReason::NelderMead(NelderMeadExit::NonFiniteCost).converged());
    /// ```
    pub fn converged(&self) -> bool {
        match self {
            Self::NelderMead(exit) => *exit == NelderMeadExit::Converged,
            Self::LevenbergMarquardt(exit) => exit.is_success(),
            Self::StoppedShort { .. } => false,
        }
    }

    /// The optimiser's own reason: `self`, or the `exit` inside a
    /// [`StopReason::StoppedShort`].
    ///
    /// ```
    /// use msd_ident::StopReason;
    /// use msd_opt::LmExit;
    /// let lm = StopReason::LevenbergMarquardt(LmExit::Gradient);
    /// assert_eq!(lm.optimiser_reason(), &lm);
    /// ```
    pub fn optimiser_reason(&self) -> &StopReason {
        match self {
            Self::StoppedShort { exit, .. } => exit.optimiser_reason(),
            other => other,
        }
    }
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NelderMead(exit) => exit.fmt(f),
            Self::LevenbergMarquardt(exit) => exit.fmt(f),
            Self::StoppedShort {
                exit,
                quantity,
                standard_errors,
            } => write!(
                f,
                "{exit}; not at a minimum: a Gauss–Newton step from the estimate moves {quantity} by {standard_errors:.1} standard errors"
            ),
        }
    }
}

impl From<NelderMeadExit> for StopReason {
    fn from(exit: NelderMeadExit) -> Self {
        Self::NelderMead(exit)
    }
}

impl From<LmExit> for StopReason {
    fn from(exit: LmExit) -> Self {
        Self::LevenbergMarquardt(exit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converged_follows_each_optimisers_test() {
        let nm = [
            (NelderMeadExit::Converged, true),
            (NelderMeadExit::MaxIterations, false),
            (NelderMeadExit::MaxEvaluations, false),
            (NelderMeadExit::NonFiniteCost, false),
        ];
        for (exit, converged) in nm {
            assert_eq!(StopReason::from(exit).converged(), converged, "{exit:?}");
            assert_eq!(StopReason::from(exit).to_string(), exit.to_string());
        }
        for exit in [
            LmExit::FTolerance,
            LmExit::MaxEvaluations,
            LmExit::NonFiniteJacobian,
        ] {
            assert_eq!(StopReason::from(exit).converged(), exit.is_success());
            assert_eq!(StopReason::from(exit).to_string(), exit.to_string());
        }
    }

    #[test]
    fn stopped_short_keeps_the_optimisers_words_first() {
        let short = StopReason::StoppedShort {
            exit: Box::new(NelderMeadExit::Converged.into()),
            quantity: "k".into(),
            standard_errors: 12.04,
        };
        assert!(!short.converged());
        assert_eq!(
            short.to_string(),
            format!(
                "{}; not at a minimum: a Gauss–Newton step from the estimate moves k by 12.0 standard errors",
                NelderMeadExit::Converged
            )
        );
        assert_eq!(
            short.optimiser_reason(),
            &StopReason::NelderMead(NelderMeadExit::Converged)
        );
    }

    #[test]
    fn serializes_with_snake_case_tags() -> Result<(), serde_json::Error> {
        let lm = serde_json::to_value(StopReason::LevenbergMarquardt(LmExit::XTolerance))?;
        assert_eq!(lm["levenberg_marquardt"], "XTolerance");
        let short = serde_json::to_value(StopReason::StoppedShort {
            exit: Box::new(NelderMeadExit::MaxIterations.into()),
            quantity: "m".into(),
            standard_errors: 2.0,
        })?;
        assert_eq!(
            short["stopped_short"]["exit"]["nelder_mead"],
            "MaxIterations"
        );
        assert_eq!(short["stopped_short"]["quantity"], "m");
        Ok(())
    }
}
