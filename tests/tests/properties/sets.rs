//! A set file of complex FRF lines (issue 46 §5), damaged at one line — cut short at any
//! character, its decimal points turned to commas, a parenthesis dropped, text put in —
//! is fitted with finite numbers or refused naming the file and that line (exit 2): a
//! damaged line is never read as another number.

use crate::scaled_cases;
use msd_experiment::{ExperimentError, RunOptions, run_experiment};
use proptest::prelude::*;

/// One accelerance of a single mode (fn ≈ 50 Hz, ζ ≈ 2 %) at 1 Hz lines, 1 … 200 Hz,
/// each line `(re+imj)`.
fn lines() -> Vec<String> {
    (1..=200)
        .map(|f| {
            let w = std::f64::consts::TAU * f64::from(f);
            let den = msd_signal::Complex64::new(98_696.0 - w * w, 12.57 * w);
            let h = msd_signal::Complex64::new(-w * w, 0.0) / den;
            format!("({:e}{:+e}j)", h.re, h.im)
        })
        .collect()
}

const CONFIG: &str = "name = \"set\"\n[[frequency_response.set]]\npath = \"frf.txt\"\nheader = false\nfrequency_step_hz = 1.0\ncomplex = 0\nkind = \"accelerance\"\nresponse = { node = 1, direction = 1 }\nreference = { node = 1, direction = 1 }\n";

/// `line` damaged by `how` at character `at` (modulo its length).
fn damaged(line: &str, how: u8, at: usize) -> String {
    let at = at % line.len();
    match how {
        0 => line[..at.max(1)].to_string(),
        1 => line.replace('.', ","),
        2 => line.replacen(')', "", 1),
        _ => format!("{}x{}", &line[..at], &line[at..]),
    }
}

proptest! {
    #![proptest_config(scaled_cases(12, 20))]

    #[test]
    fn a_damaged_set_line_is_refused_at_its_line_or_read_as_written(
        row in 0usize..200, how in 0u8..4, at in 0usize..64,
    ) {
        let mut all = lines();
        all[row] = damaged(&all[row], how, at);
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("frf.txt"), all.join("\n") + "\n").unwrap();
        let path = dir.path().join("c.toml");
        std::fs::write(&path, CONFIG).unwrap();
        let options = RunOptions { out: Some(dir.path().join("out")), ..RunOptions::default() };
        match run_experiment(&path, &options) {
            // Only a damage that leaves a complex number as written may run: the cut
            // keeps the closing parenthesis only when nothing was cut.
            Ok(_) => prop_assert!(all[row] == lines()[row], "read `{}`", all[row]),
            Err(e) => {
                let text = e.to_string();
                prop_assert!(matches!(e, ExperimentError::Data { .. }), "{text}");
                prop_assert_eq!(e.exit_code(), 2);
                prop_assert!(text.contains("frf.txt"), "{text}");
                let line = format!("line {}", row + 1);
                prop_assert!(text.contains(&line), "`{text}` lacks `{line}`");
                prop_assert!(!dir.path().join("out").exists());
            }
        }
    }
}
