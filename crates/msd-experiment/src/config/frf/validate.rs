//! The checks of the `[frequency_response]` section: exactly one source, and every value
//! of the plant, the simulated sources and the estimator in range, each error naming its
//! key.

use super::{ChainPlant, Check, FrequencyResponseSection, HammerSource, ShakerSource};
use crate::config::{check_non_negative, check_positive, library_error};
use msd_signal::{FrfOptions, Window};

impl FrequencyResponseSection {
    /// The name of the one source given.
    pub fn source_name(&self) -> &'static str {
        self.sources()
            .into_iter()
            .find_map(|(name, given)| given.then_some(name))
            .unwrap_or("none")
    }

    /// The measured file the frequency responses come from (the first of a set); `None`
    /// for a simulated source.
    pub fn data_file(&self) -> Option<&std::path::Path> {
        (self.table.as_ref().map(|t| t.path.as_path()))
            .or_else(|| self.set.iter().flatten().next().map(|t| t.path.as_path()))
            .or_else(|| self.uff.as_ref().map(|u| u.path.as_path()))
            .or_else(|| self.records.as_ref().map(|r| r.path.as_path()))
    }

    fn sources(&self) -> [(&'static str, bool); 7] {
        [
            ("sweep", self.sweep.is_some()),
            ("hammer", self.hammer.is_some()),
            ("shaker", self.shaker.is_some()),
            ("table", self.table.is_some()),
            ("set", self.set.is_some()),
            ("uff", self.uff.is_some()),
            ("records", self.records.is_some()),
        ]
    }

    /// Checks every value; errors name the key.
    pub(crate) fn validate(&self) -> Check {
        let given: Vec<&str> = self
            .sources()
            .into_iter()
            .filter_map(|(n, g)| g.then_some(n))
            .collect();
        let expected = "expected exactly one of sweep, hammer, shaker, table, set, uff, records";
        match given.as_slice() {
            [] => return err("frequency_response", format!(": no source: {expected}")),
            [_] => {}
            [first, second, ..] => {
                return err(
                    &format!("frequency_response.{second}"),
                    format!(": a second source beside `{first}`: {expected}"),
                );
            }
        }
        if let Some(plant) = &self.plant {
            validate_chain(plant)?;
        } else if self.sweep.is_some() || self.hammer.is_some() || self.shaker.is_some() {
            return err(
                "frequency_response.plant",
                ": missing: a simulated source needs the plant { masses, springs, dampers }".into(),
            );
        }
        self.validate_sources()?;
        self.estimator
            .validate()
            .map_err(|e| ("frequency_response.estimator".into(), format!(": {e}")))?;
        match &self.modes {
            Some(m) => m
                .validate()
                .map_err(|e| library_error("frequency_response.modes", e.into())),
            None => self
                .one_mode
                .validate()
                .map_err(|e| library_error("frequency_response.one_mode", e)),
        }
    }

    fn validate_sources(&self) -> Check {
        if let Some(s) = &self.sweep {
            let [low, high] = s.band_hz;
            check_positive("frequency_response.sweep.band_hz", low)?;
            if !(high.is_finite() && high > low) {
                return err(
                    "frequency_response.sweep.band_hz",
                    format!(" = [{low}, {high}]: expected 0 < first < last (Hz)"),
                );
            }
            if s.lines < 4 {
                return err(
                    "frequency_response.sweep.lines",
                    format!(" = {}: expected at least 4", s.lines),
                );
            }
            // A line holds its frequency, the complex response and its noise.
            crate::budget::check(
                "frequency_response.sweep.lines",
                s.lines as f64,
                4.0,
                crate::budget::Budget::Held,
            )?;
            check_non_negative("frequency_response.sweep.relative_noise", s.relative_noise)?;
        }
        if let Some(h) = &self.hammer {
            h.validate()?;
            h.validate_windows(&self.estimator)?;
        }
        if let Some(s) = &self.shaker {
            s.validate()?;
            if self.estimator.impact.is_some() {
                // An exponential window on a continuous signal adds damping to every
                // line, and a force window cuts the force off.
                return err(
                    "frequency_response.estimator.impact",
                    ": given with a shaker: expected no impact windows (they are for hammer hits; a shaker's records take a rectangular or Hann window)".into(),
                );
            }
        }
        if let Some(t) = &self.table {
            check_table(t)?;
        }
        self.validate_set()?;
        if let Some(r) = &self.records {
            crate::config::check_decimal("frequency_response.records", r.decimal, r.delimiter)?;
            check_positive("frequency_response.records.sample_rate", r.sample_rate)?;
            if r.force.is_empty() || r.force.len() != r.response.len() {
                return err(
                    "frequency_response.records.response",
                    format!(
                        ": {} force and {} response columns: expected one pair per record",
                        r.force.len(),
                        r.response.len()
                    ),
                );
            }
        }
        if self
            .uff
            .as_ref()
            .is_some_and(|u| u.set && u.function.is_some())
        {
            return err(
                "frequency_response.uff.function",
                ": given with set = true: expected one or the other (a set takes every frequency response function of the file)".into(),
            );
        }
        self.validate_shapes()?;
        if self.uff.as_ref().and_then(|u| u.function) == Some(0) {
            return err(
                "frequency_response.uff.function",
                " = 0: expected a dataset number from 1".into(),
            );
        }
        match self.uff.as_ref().and_then(|u| u.averages) {
            Some(k) if k < 2 => err(
                "frequency_response.uff.averages",
                format!(
                    " = {k}: expected at least 2 (one average has a coherence of 1 on every line)"
                ),
            ),
            _ => Ok(()),
        }
    }

    /// Each FRF of a `set`: its table and its two DOFs.
    fn validate_set(&self) -> Check {
        for (i, t) in self.set.iter().flatten().enumerate() {
            check_table(t).map_err(|(key, why)| {
                (
                    key.replacen(
                        "frequency_response.table",
                        &format!("frequency_response.set[{i}]"),
                        1,
                    ),
                    why,
                )
            })?;
            for (name, dof) in [("response", t.response), ("reference", t.reference)] {
                let Some(dof) = dof else {
                    return err(
                        &format!("frequency_response.set[{i}].{name}"),
                        ": missing: each FRF of a set names its DOFs, e.g. { node = 1, direction = 3 }".into(),
                    );
                };
                if !dof.is_valid() {
                    return err(
                        &format!("frequency_response.set[{i}].{name}.direction"),
                        format!(
                            " = {}: expected ±1, ±2, ±3 (X, Y, Z) or ±4, ±5, ±6 (rotations about them), as UFF numbers directions",
                            dof.direction
                        ),
                    );
                }
            }
        }
        if self.set.as_ref().is_some_and(Vec::is_empty) {
            return err(
                "frequency_response.set",
                " = []: expected at least one FRF".into(),
            );
        }
        Ok(())
    }

    /// What is compared with a set's shapes: given only with a set, non-empty paths,
    /// reference modes that are modes.
    fn validate_shapes(&self) -> Check {
        let a_set = self.set.is_some() || self.uff.as_ref().is_some_and(|u| u.set);
        for (key, given) in [
            ("reference_modes", self.reference_modes.is_some()),
            ("reference_shapes", self.reference_shapes.is_some()),
            ("geometry", self.geometry.is_some()),
        ] {
            if given && !a_set {
                return err(
                    &format!("frequency_response.{key}"),
                    format!(
                        ": given with the `{}` source: expected a set of FRFs ([[frequency_response.set]], or [frequency_response.uff] with set = true), whose shapes it is about",
                        self.source_name()
                    ),
                );
            }
        }
        for (key, file) in [
            ("reference_shapes", &self.reference_shapes),
            ("geometry", &self.geometry),
        ] {
            if file.as_ref().is_some_and(|f| f.as_os_str().is_empty()) {
                return err(
                    &format!("frequency_response.{key}"),
                    " = \"\": expected a UFF file (datasets 55 or 15), relative to the config"
                        .into(),
                );
            }
        }
        for (i, mode) in self.reference_modes.iter().flatten().enumerate() {
            check_reference_mode(i, mode)?;
        }
        Ok(())
    }
}

/// A reference mode: a finite frequency > 0, a damping ratio in [0, 1), a shape of
/// finite numbers, not all zero, that a MAC can be computed with.
fn check_reference_mode(i: usize, mode: &super::ReferenceMode) -> Check {
    let key = |k: &str| format!("frequency_response.reference_modes[{i}].{k}");
    let f = mode.natural_frequency_hz;
    if !(f.is_finite() && f > 0.0) {
        return err(
            &key("natural_frequency_hz"),
            format!(
                " = {}: expected a finite frequency > 0",
                crate::config::show(f)
            ),
        );
    }
    let z = mode.damping_ratio;
    if !(z.is_finite() && (0.0..1.0).contains(&z)) {
        return err(
            &key("damping_ratio"),
            format!(
                " = {}: expected a number from 0 to below 1",
                crate::config::show(z)
            ),
        );
    }
    if let Some((j, v)) = (mode.shape.iter().enumerate()).find(|(_, v)| !v.is_finite()) {
        return err(
            &format!("{}[{j}]", key("shape")),
            format!(" = {v}: expected a finite number"),
        );
    }
    if mode.shape.iter().all(|&v| v == 0.0) {
        return err(
            &key("shape"),
            ": is zero throughout: expected a shape (a MAC with zero means nothing)".into(),
        );
    }
    Ok(())
}

/// A table source's columns and frequency axis; errors name `frequency_response.table.…`.
fn check_table(t: &super::TableSource) -> Check {
    crate::config::check_decimal("frequency_response.table", t.decimal, t.delimiter)?;
    let pairs = (
        t.magnitude.is_some() && t.phase.is_some(),
        t.real.is_some() && t.imaginary.is_some(),
    );
    let given = [
        t.magnitude.is_some() || t.phase.is_some(),
        t.real.is_some() || t.imaginary.is_some(),
        t.complex.is_some(),
    ];
    let complete = [pairs.0, pairs.1, t.complex.is_some()];
    if given.iter().filter(|&&g| g).count() != 1 || !complete.contains(&true) {
        return err(
            "frequency_response.table",
            ": expected either `magnitude` and `phase`, `real` and `imaginary`, or one `complex` column"
                .into(),
        );
    }
    if t.magnitude_in_db && t.magnitude.is_none() {
        return err(
            "frequency_response.table.magnitude_in_db",
            " = true: expected a `magnitude` column for it to apply to".into(),
        );
    }
    match (&t.frequency, t.frequency_step_hz) {
        (Some(_), Some(_)) | (None, None) => {
            return err(
                "frequency_response.table.frequency",
                ": expected either a `frequency` column or `frequency_step_hz` (and `frequency_start_hz`, by default 0) for a file without one".into(),
            );
        }
        (None, Some(step)) => {
            check_positive("frequency_response.table.frequency_step_hz", step)?;
            let start = t.frequency_start_hz;
            if !(start.is_finite() && start >= 0.0) {
                return err(
                    "frequency_response.table.frequency_start_hz",
                    format!(" = {start}: expected a finite frequency >= 0 Hz"),
                );
            }
        }
        (Some(_), None) => {}
    }
    match (&t.coherence, t.averages) {
        (None, Some(k)) => err(
            "frequency_response.table.averages",
            format!(
                " = {k}: expected with a `coherence` column only (the count of averages the coherence was estimated over)"
            ),
        ),
        (Some(_), Some(k)) if k < 2 => err(
            "frequency_response.table.averages",
            format!(" = {k}: expected at least 2 (one average has a coherence of 1 on every line)"),
        ),
        _ => Ok(()),
    }
}

/// A chain plant's sizes, values and force and response positions.
fn validate_chain(plant: &ChainPlant) -> Check {
    let key = |k: &str| format!("frequency_response.plant.{k}");
    let n = plant.masses.len();
    if !(1..=8).contains(&n) {
        return err(&key("masses"), format!(": {n} masses: expected 1 to 8"));
    }
    for (name, values) in [("springs", &plant.springs), ("dampers", &plant.dampers)] {
        if values.len() != n {
            return err(
                &key(name),
                format!(
                    ": {} values for {n} masses: expected one per mass",
                    values.len()
                ),
            );
        }
    }
    for i in 0..n {
        check_positive(&key(&format!("masses[{i}]")), plant.masses[i])?;
        check_positive(&key(&format!("springs[{i}]")), plant.springs[i])?;
        check_non_negative(&key(&format!("dampers[{i}]")), plant.dampers[i])?;
    }
    for (name, at) in [
        ("force_at", plant.force_at),
        ("response_at", plant.response_at),
    ] {
        if !(1..=n).contains(&at) {
            return err(
                &key(name),
                format!(" = {at}: expected a mass from 1 to {n}"),
            );
        }
    }
    Ok(())
}

impl HammerSource {
    fn validate(&self) -> Check {
        let key = |k: &str| format!("frequency_response.hammer.{k}");
        check_positive(&key("sample_rate"), self.sample_rate)?;
        check_positive(&key("duration"), self.duration)?;
        check_positive(&key("force_peak"), self.force_peak)?;
        for (name, v) in [
            ("trigger", self.trigger),
            ("force_spread", self.force_spread),
            ("force_noise", self.force_noise),
            ("response_noise", self.response_noise),
        ] {
            check_non_negative(&key(name), v)?;
        }
        if self.hits == 0 {
            return err(&key("hits"), " = 0: expected at least 1".into());
        }
        check_positive(&key("pulse_width"), self.pulse_width)?;
        if self.pulse_width * self.sample_rate < 2.0 {
            return err(
                &key("pulse_width"),
                format!(
                    " = {}: expected at least two samples (2/sample_rate)",
                    self.pulse_width
                ),
            );
        }
        if self.trigger + self.pulse_width >= self.duration {
            return err(
                &key("duration"),
                format!(" = {}: expected the pulse inside the record", self.duration),
            );
        }
        // Each hit: the force and the response. One hit past the budget: its duration is
        // the cause; else the hits.
        use crate::budget::{Budget, check};
        let per_hit = 2.0 * self.duration * self.sample_rate;
        check(
            &key("duration"),
            self.duration,
            2.0 * self.sample_rate,
            Budget::Held,
        )?;
        check(&key("hits"), self.hits as f64, per_hit, Budget::Held)
    }
}

impl HammerSource {
    /// Each hit is one record: the estimator's windows must keep the hit. Impact windows
    /// (the force window at least to the end of the pulse, within the record), or a
    /// rectangular window over the whole record; a Hann window would zero the hit at
    /// the record's start.
    fn validate_windows(&self, estimator: &FrfOptions) -> Check {
        let key = |k: &str| format!("frequency_response.estimator.{k}");
        let Some(impact) = &estimator.impact else {
            if estimator.welch.window != Window::Rectangular {
                return err(
                    &key("welch.window"),
                    format!(
                        " = \"{}\": expected `impact` windows or `welch.window = \"rectangular\"` with the hammer source (a Hann window zeroes the hit at the record's start)",
                        estimator.welch.window.name()
                    ),
                );
            }
            return match estimator.welch.segment_length {
                Some(l) => err(
                    &key("welch.segment_length"),
                    format!(
                        " = {l}: expected none with the hammer source (each hit is one record)"
                    ),
                ),
                None => Ok(()),
            };
        };
        let pulse_end = self.trigger + self.pulse_width;
        let width = impact.force_width.unwrap_or(self.duration / 10.0);
        if !(pulse_end..=self.duration).contains(&width) {
            return err(
                &key("impact.force_width"),
                format!(
                    " = {width} s{}: expected the force window to keep the pulse and end within the record: from trigger + pulse_width ({} + {} s) to duration ({} s)",
                    if impact.force_width.is_none() {
                        " (a tenth of the record)"
                    } else {
                        ""
                    },
                    self.trigger,
                    self.pulse_width,
                    self.duration
                ),
            );
        }
        Ok(())
    }
}

impl ShakerSource {
    fn validate(&self) -> Check {
        let key = |k: &str| format!("frequency_response.shaker.{k}");
        check_positive(&key("sample_rate"), self.sample_rate)?;
        check_positive(&key("duration"), self.duration)?;
        for (name, v) in [
            ("settle", self.settle),
            ("force_noise", self.force_noise),
            ("response_noise", self.response_noise),
        ] {
            check_non_negative(&key(name), v)?;
        }
        if self.records == 0 {
            return err(&key("records"), " = 0: expected at least 1".into());
        }
        let per_record = self.duration * self.sample_rate;
        if per_record < 8.0 {
            return err(
                &key("duration"),
                format!(
                    " = {}: expected at least 8 samples per record",
                    self.duration
                ),
            );
        }
        // The force is simulated 16 times finer than it is sampled (simulate.rs), beside
        // the two channels: 18 values a sample.
        use crate::budget::{Budget, check, check_beside};
        let settle = 18.0 * self.settle * self.sample_rate;
        let records = self.records as f64;
        // The settling alone past the budget: it is the cause; else one record past it:
        // its duration; else the records.
        check(
            &key("settle"),
            self.settle,
            18.0 * self.sample_rate,
            Budget::Held,
        )?;
        check_beside(
            &key("duration"),
            self.duration,
            18.0 * self.sample_rate,
            settle,
            Budget::Held,
        )?;
        check_beside(
            &key("records"),
            records,
            18.0 * per_record,
            settle,
            Budget::Held,
        )?;
        self.force
            .validate()
            .map_err(|e| (key("force"), format!(": {e}")))
    }
}

fn err(field: &str, message: String) -> Check {
    Err((field.to_string(), message))
}
