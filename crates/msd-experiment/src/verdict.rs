//! The verdict every fit of measured records opens with (setups, chains), as the paper's
//! "In short" does: whether the estimates can be trusted, and why — what the data could
//! not identify, whether the residuals are white under the noise model the intervals
//! assume, whether the plant predicts data it was not fitted to, and what the drive's own
//! noise did to the intervals.

use crate::fmt::sig;
use msd_ident::records::{NoiseModelFit, ResidualWhiteness};
use serde::Serialize;
use std::fmt::Write;

/// The level at which the drive's noise counts as shown (the noise model's own test).
const DETECTED: f64 = 0.01;

/// Whether the estimates can be trusted, with one finding per check.
///
/// Displays one line: "trustworthy", "unchecked" (nothing failed, but a check the
/// intervals rest on could not be made) or "use with care", then the findings that
/// failed (or, when none did, every finding).
///
/// ```
/// use msd_experiment::verdict::{Finding, Verdict};
/// let white = Finding::passed("the residuals are white");
/// assert_eq!(Verdict::of(vec![white.clone()]).to_string(), "trustworthy: the residuals are white");
/// let v = Verdict::of(vec![white, Finding::unchecked("no coherence to test the residual against")]);
/// assert!(!v.trustworthy && v.unchecked);
/// assert_eq!(v.to_string(), "unchecked: no coherence to test the residual against; the residuals are white");
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    /// Every check passed, and every check the intervals rest on was made.
    pub trustworthy: bool,
    /// No check failed, but one the intervals rest on could not be made (its finding
    /// says which and why).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub unchecked: bool,
    /// One sentence per check, the failed ones first, then those not made.
    pub findings: Vec<Finding>,
}

/// One check's outcome, in words.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Finding {
    /// The check passed (or only informs, or could not be made).
    pub passed: bool,
    /// What it found and, when it failed, what to do.
    pub text: String,
    /// False where the check could not be made (the data lack what it needs).
    #[serde(skip_serializing_if = "std::clone::Clone::clone")]
    pub checked: bool,
}

impl Finding {
    /// A check that passed (or only informs).
    pub fn passed(text: impl Into<String>) -> Self {
        Self {
            passed: true,
            text: text.into(),
            checked: true,
        }
    }

    /// A check that failed.
    pub fn failed(text: impl Into<String>) -> Self {
        Self {
            passed: false,
            ..Self::passed(text)
        }
    }

    /// A check that could not be made, and why.
    pub fn unchecked(text: impl Into<String>) -> Self {
        Self {
            checked: false,
            ..Self::passed(text)
        }
    }

    /// 0 failed, 1 not made, 2 passed: the order the findings are told in.
    fn rank(&self) -> u8 {
        match (self.passed, self.checked) {
            (false, _) => 0,
            (true, false) => 1,
            (true, true) => 2,
        }
    }
}

impl Verdict {
    /// The verdict of `findings`: trustworthy when every one passed and was made; the
    /// failed ones first, then those not made.
    pub fn of(mut findings: Vec<Finding>) -> Self {
        findings.sort_by_key(Finding::rank);
        let ranks = findings.iter().map(Finding::rank);
        let worst = ranks.min().unwrap_or(2);
        Verdict {
            trustworthy: worst == 2,
            unchecked: worst == 1,
            findings,
        }
    }

    /// The verdict's word: "trustworthy", "unchecked" or "use with care".
    pub fn word(&self) -> &'static str {
        match (self.trustworthy, self.unchecked) {
            (true, _) => "trustworthy",
            (false, true) => "unchecked",
            (false, false) => "use with care",
        }
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let failed = !(self.trustworthy || self.unchecked);
        let shown: Vec<&str> = self
            .findings
            .iter()
            .filter(|x| !failed || !x.passed)
            .map(|x| x.text.as_str())
            .collect();
        write!(f, "{}: {}", self.word(), shown.join("; "))
    }
}

/// The predictions of fresh data, as the verdict reads them.
pub(crate) struct Fresh {
    /// What was predicted, in a few words ("the held-out end").
    pub what: String,
    /// The worst channel's R² and fit %.
    pub worst: Option<(f64, f64)>,
    /// The channels the plant does not predict (R² < 0.5 with an error above 1.5 σ̂ of
    /// the channel's noise: the quiet end of a decay has a low R² and nothing wrong).
    pub unpredicted: Vec<String>,
    /// The channels whose fresh residual correlates with the drive.
    pub correlated: Vec<String>,
}

/// What a fit offers the verdict.
pub(crate) struct Evidence<'a> {
    /// Why some parameters are not identified (empty when all are).
    pub unidentified: Vec<String>,
    /// Each channel's whiteness under the model the intervals assume.
    pub whiteness: &'a [ResidualWhiteness],
    /// What the noise model found.
    pub noise_model: &'a NoiseModelFit,
    /// The predictions of fresh data, or why there are none.
    pub fresh: Result<Fresh, String>,
}

/// The verdict on `e`.
pub(crate) fn verdict(e: &Evidence<'_>) -> Verdict {
    let mut findings = Vec::new();
    match e.unidentified.as_slice() {
        [] => {}
        [reason] => findings.push(Finding::failed(format!("not everything is identified: {reason}"))),
        reasons => findings.push(Finding::failed(format!(
            "not everything is identified: {} combinations of the parameters leave the records unchanged (listed with the estimates)",
            reasons.len()
        ))),
    }
    let coloured: Vec<String> = (e.whiteness.iter())
        .filter(|c| !c.passed)
        .map(|c| format!("`{}`", c.channel))
        .collect();
    findings.push(if coloured.is_empty() {
        Finding::passed("the residuals are white under the noise model the intervals assume")
    } else {
        Finding::failed(format!(
            "the residual of {} is not white under the noise model: the model leaves structure unexplained (a missing mode, a delay, a nonlinearity) and the intervals may be too narrow",
            coloured.join(", ")
        ))
    });
    findings.extend(fresh(&e.fresh));
    if let Some(finding) = drive_noise(e.noise_model) {
        findings.push(finding);
    }
    Verdict::of(findings)
}

/// The fresh data's findings: the worst prediction, and each channel correlated with
/// the drive.
fn fresh(fresh: &Result<Fresh, String>) -> Vec<Finding> {
    let f = match fresh {
        Ok(f) => f,
        Err(reason) => {
            return vec![Finding::passed(format!(
                "not checked on fresh data: {reason}"
            ))];
        }
    };
    let mut out = Vec::new();
    if let Some((r2, fit)) = f.worst {
        let text = format!(
            "on fresh data ({}) the worst channel's R² is {} (fit {} %)",
            f.what,
            sig(r2, 4),
            sig(fit, 3)
        );
        out.push(Finding::passed(text));
    }
    if !f.unpredicted.is_empty() {
        out.push(Finding::failed(format!(
            "on fresh data the plant does not predict {}: its error is well above the channel's noise",
            f.unpredicted.join(", ")
        )));
    }
    if !f.correlated.is_empty() {
        out.push(Finding::failed(format!(
            "on fresh data the residual of {} correlates with the drive: part of its effect is not explained",
            f.correlated.join(", ")
        )));
    }
    out
}

/// What the drive's own noise did, when it shows.
fn drive_noise(m: &NoiseModelFit) -> Option<Finding> {
    let fraction = m.input_noise_fraction?;
    if m.p_value? >= DETECTED {
        return None;
    }
    let mut text = format!(
        "the drive's own noise shows ({} % of its rms) and the intervals account for it (×{} the white-noise ones)",
        sig(100.0 * fraction, 2),
        sig(m.interval_ratio, 3)
    );
    if let Some(low) = m.output_error_efficiency.values().copied().reduce(f64::min) {
        let gain = (1.0 / low).sqrt();
        text += &if gain < 1.05 {
            "; the estimate weights each frequency line by that noise, its intervals within 5 % of the output-error fit's".to_string()
        } else {
            format!(
                "; the estimate weights each frequency line by that noise, with intervals up to {}× narrower than the output-error fit's",
                sig(gain, 2)
            )
        };
    } else if let Some(low) = (m.efficiency.values().copied())
        .reduce(f64::min)
        .filter(|low| *low < 0.5)
    {
        text += &format!(
            "; a fit weighting each frequency line by its noise could narrow some up to {}×",
            sig((1.0 / low).sqrt(), 2)
        );
    }
    Some(Finding::passed(text))
}

/// The report's "In short" section: the verdict in bold, then its findings.
pub(crate) fn section(s: &mut String, v: &Verdict) -> std::fmt::Result {
    let (failed, passed): (Vec<&Finding>, Vec<&Finding>) =
        v.findings.iter().partition(|f| !f.passed);
    let sentence = |list: &[&Finding]| {
        let texts: Vec<&str> = list.iter().map(|f| f.text.as_str()).collect();
        crate::fmt::capitalised(&texts.join("; "))
    };
    writeln!(s, "## In short\n")?;
    if failed.is_empty() {
        let word = crate::fmt::capitalised(v.word());
        writeln!(s, "**{word}.** {}.\n", sentence(&passed))
    } else if passed.is_empty() {
        writeln!(s, "**Use with care.** {}.\n", sentence(&failed))
    } else {
        writeln!(
            s,
            "**Use with care.** {}. Otherwise: {}.\n",
            sentence(&failed),
            sentence(&passed)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use msd_ident::residuals::ljung_box;

    fn whiteness(passed: bool) -> ResidualWhiteness {
        ResidualWhiteness {
            record: "run".into(),
            channel: "acc".into(),
            ljung_box: ljung_box(&[1.0, 0.0], 1000),
            ljung_box_under_noise_model: None,
            input_correlation: None,
            spectrum: None,
            passed,
        }
    }

    fn fresh(r2: f64, correlated: &[&str]) -> Result<Fresh, String> {
        Ok(Fresh {
            what: "the held-out end".into(),
            worst: Some((r2, 90.0)),
            unpredicted: Vec::new(),
            correlated: correlated.iter().map(|c| c.to_string()).collect(),
        })
    }

    #[test]
    fn every_check_passed_is_trustworthy_and_says_each() {
        let model = NoiseModelFit::white();
        let checks = [whiteness(true)];
        let v = verdict(&Evidence {
            unidentified: Vec::new(),
            whiteness: &checks,
            noise_model: &model,
            fresh: fresh(0.99, &[]),
        });
        assert!(v.trustworthy);
        assert_eq!(v.findings.len(), 2, "{v:?}");
        assert!(
            v.to_string()
                .starts_with("trustworthy: the residuals are white")
        );
    }

    #[test]
    fn any_failed_check_asks_for_care_and_names_it_first() {
        let model = NoiseModelFit::white();
        let checks = [whiteness(false)];
        for (unidentified, checks, correlated) in [
            (
                vec!["c and k are confounded".to_string()],
                &[] as &[_],
                &[] as &[&str],
            ),
            (Vec::new(), &checks[..], &[]),
            (Vec::new(), &[], &["`acc`"]),
        ] {
            let v = verdict(&Evidence {
                unidentified,
                whiteness: checks,
                noise_model: &model,
                fresh: fresh(0.99, correlated),
            });
            assert!(!v.trustworthy, "{v}");
            assert!(!v.findings[0].passed, "{v:?}");
            assert!(v.to_string().starts_with("use with care: "), "{v}");
            assert!(
                !v.to_string().contains("R²"),
                "passed findings are not repeated: {v}"
            );
        }
    }

    /// The weighted estimate's gain over the output-error one is given as a factor only
    /// where it is one: an efficiency near 1 reads as "within 5 %", not "1.0× narrower".
    #[test]
    fn the_weighted_estimates_gain_is_said_as_it_is() {
        for (efficiency, expected) in [
            (
                0.25,
                "with intervals up to 2.0× narrower than the output-error fit's",
            ),
            (0.95, "its intervals within 5 % of the output-error fit's"),
        ] {
            let model = NoiseModelFit {
                input_noise_fraction: Some(0.003),
                p_value: Some(1e-4),
                interval_ratio: 1.8,
                output_error_efficiency: [("damping".to_string(), efficiency)].into(),
                ..NoiseModelFit::white()
            };
            let text = drive_noise(&model).expect("the drive's noise shows").text;
            assert!(text.ends_with(expected), "{text}");
        }
        let quiet = NoiseModelFit {
            input_noise_fraction: Some(0.003),
            p_value: Some(0.2),
            ..NoiseModelFit::white()
        };
        assert!(drive_noise(&quiet).is_none());
    }

    #[test]
    fn the_section_leads_with_the_verdict_in_bold() {
        let model = NoiseModelFit::white();
        let checks = [whiteness(false)];
        let v = verdict(&Evidence {
            unidentified: Vec::new(),
            whiteness: &checks,
            noise_model: &model,
            fresh: Err("no part held out".into()),
        });
        let mut s = String::new();
        section(&mut s, &v).unwrap();
        assert!(
            s.starts_with("## In short\n\n**Use with care.** The residual of `acc`"),
            "{s}"
        );
        assert!(
            s.contains("Otherwise: Not checked on fresh data: no part held out."),
            "{s}"
        );
    }
}
