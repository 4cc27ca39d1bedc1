//! The plan as the command prints it.

use super::{Plan, PlannedQuantity};
use std::fmt::{Formatter, Result};

impl std::fmt::Display for Plan {
    fn fmt(&self, f: &mut Formatter<'_>) -> Result {
        header(self, f)?;
        table(self, f)?;
        correlation(self, f)?;
        for note in &self.notes {
            writeln!(f, "  note: {note}")?;
        }
        let short: Vec<&PlannedQuantity> = self
            .quantities
            .iter()
            .filter(|q| q.relative_half_width.is_finite() && q.relative_half_width > self.target)
            .collect();
        for q in &short {
            writeln!(f, "  {}", reaching(self, q))?;
        }
        let absolute: Vec<&str> = self
            .quantities
            .iter()
            .filter(|q| !q.relative_half_width.is_finite())
            .map(|q| q.name)
            .collect();
        if short.is_empty() {
            let which = if absolute.is_empty() {
                "every quantity"
            } else {
                "every other quantity"
            };
            writeln!(f, "  {which} within ±{} % (95 %)", 100.0 * self.target)?;
        }
        if !absolute.is_empty() {
            writeln!(
                f,
                "  {}: a prior of 0 has no relative width (its standard error above is absolute)",
                absolute.join(", ")
            )?;
        }
        Ok(())
    }
}

fn header(plan: &Plan, f: &mut Formatter<'_>) -> Result {
    let t = &plan.test;
    let records = match t.records {
        1 => String::new(),
        n if t.repeats == "cycles" => format!("{n} conditions, "),
        n => format!("{n} records of "),
    };
    writeln!(
        f,
        "plan `{}` ({}): {records}{} samples over {:.4} s, peak {} {:.4} {}",
        plan.name, t.excitation, t.samples, t.duration_s, t.drive, t.peak_drive, t.drive_unit
    )?;
    let channels: Vec<String> = t
        .channels
        .iter()
        .map(|(name, sigma, unit)| format!("{name} σ = {sigma:.3e} {unit}"))
        .collect();
    writeln!(f, "  noise: {}", channels.join(", "))
}

fn table(plan: &Plan, f: &mut Formatter<'_>) -> Result {
    write!(
        f,
        "  {:<22} {:>12} {:>11} {:>9}",
        "quantity", "prior", "std error", "±95 %"
    )?;
    if plan.verified_with > 0 {
        write!(f, " {:>13}", format!("sd of {}", plan.verified_with))?;
        if plan.quantities.iter().any(|q| q.coverage.is_some()) {
            write!(f, " {:>9}", "coverage")?;
        }
    }
    writeln!(f)?;
    for q in &plan.quantities {
        let width = match q.relative_half_width {
            w if w.is_finite() => format!("{:>8.3} %", 100.0 * w),
            _ => format!("{:>10}", "—"),
        };
        write!(
            f,
            "  {:<22} {:>12.6} {:>11.3e} {width}",
            q.name, q.value, q.standard_error
        )?;
        if let Some(sd) = q.simulated_standard_deviation {
            write!(f, " {sd:>13.3e}")?;
        }
        if let Some(c) = q.coverage {
            write!(f, " {:>7.1} %", 100.0 * c)?;
        }
        writeln!(f)?;
    }
    Ok(())
}

fn correlation(plan: &Plan, f: &mut Formatter<'_>) -> Result {
    let c = &plan.correlation;
    if c.names.len() < 2 {
        return Ok(());
    }
    write!(f, "  {:<22}", "correlation")?;
    for name in &c.names {
        write!(f, " {:>9}", abbreviation(name))?;
    }
    writeln!(f)?;
    for (name, row) in c.names.iter().zip(&c.matrix) {
        write!(f, "  {name:<22}")?;
        for v in row {
            write!(f, " {v:>9.3}")?;
        }
        writeln!(f)?;
    }
    Ok(())
}

/// A short column heading.
fn abbreviation(name: &str) -> &str {
    match name {
        "natural_frequency_hz" => "fn",
        "damping_ratio" => "ζ",
        "quadratic_damping" => "c₂",
        "coulomb_force" => "F_c",
        "force_offset" => "F₀",
        other => other,
    }
}

/// What reaches the target for `q`: a stronger drive, a longer record, more repeats.
fn reaching(plan: &Plan, q: &PlannedQuantity) -> String {
    let t = &plan.test;
    let mut ways = Vec::new();
    if let Some(factor) = q.amplitude_factor {
        ways.push(match q.duration_needed_s {
            Some(d) => format!("record {d:.3} s at this {}", t.drive),
            None if t.drive == "initial state" => {
                "a longer record does not get there (the ring-down has died out)".into()
            }
            None => "a longer record of this input does not get there".into(),
        });
        let peak = format!("{:.4} {}", factor * t.peak_drive, t.drive_unit);
        ways.push(match t.drive {
            "initial state" => format!("release from {factor:.2}× the initial state ({peak})"),
            drive => format!("raise the {drive} {factor:.2}× (peak {peak})"),
        });
    }
    if let Some(n) = q.repeats_needed {
        ways.push(match t.repeats {
            "cycles" => format!("{n} cycles per condition (now {})", t.repeats_planned),
            _ => format!("{n} records (now {})", t.repeats_planned),
        });
    }
    format!(
        "{} to ±{} %: {}",
        q.name,
        100.0 * plan.target,
        ways.join(", or ")
    )
}
