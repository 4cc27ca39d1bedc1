//! The linearised statistics of every fit come from msd-opt's
//! [`statistics`](msd_opt::statistics); this module adds the one error of a fit that
//! cannot identify what it was asked.

use crate::error::IdentError;
use msd_opt::statistics::Singular;

/// The error of a fit whose Jacobian is singular: `data` is what was fitted ("the
/// output", "the records", …), `names` the columns' names.
pub(crate) trait SingularError {
    /// [`IdentError::NotIdentifiable`] with the reason in words.
    fn error(self, data: &str, names: &[&str]) -> IdentError;
}

impl SingularError for Singular {
    fn error(self, data: &str, names: &[&str]) -> IdentError {
        IdentError::NotIdentifiable {
            reason: self.reason(data, names),
        }
    }
}
