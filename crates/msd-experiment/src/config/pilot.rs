//! `[pilot]`: the section that points a sequential design at its pilot test (the pilot
//! itself is run or read by [`crate::design::Pilot`]).

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// `[pilot]`: where a sequential design takes its prior from. Exactly one key; the path
/// is relative to the design config's folder.
///
/// ```
/// use msd_experiment::config::PilotSection;
/// let section: PilotSection = toml::from_str(r#"results = "pilot/results.json""#).unwrap();
/// assert_eq!(section.results.unwrap().to_str(), Some("pilot/results.json"));
/// assert!(toml::from_str::<PilotSection>(r#"file = "pilot.toml""#).is_err()); // unknown key
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PilotSection {
    /// A pilot experiment's config (synthetic or measured, force and displacement): its
    /// identification data are generated or read and m, c, k estimated before the
    /// design.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub config: Option<PathBuf>,
    /// The `results.json` of a pilot run already made (`cargo xtask experiment`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub results: Option<PathBuf>,
}

impl PilotSection {
    /// Checks that exactly one source is given: the field and the rest of the message,
    /// as [`Config`]'s checks return them.
    pub(crate) fn validate(&self) -> std::result::Result<(), (String, String)> {
        match (&self.config, &self.results) {
            (Some(p), None) | (None, Some(p)) if !p.as_os_str().is_empty() => Ok(()),
            (Some(_), Some(_)) => Err((
                "pilot".into(),
                ": both `config` and `results` given: expected exactly one".into(),
            )),
            _ => Err((
                "pilot".into(),
                ": expected `config = \"pilot.toml\"` (run first) or `results = \"…/results.json\"` (a run already made)".into(),
            )),
        }
    }
}
