//! The damper test machine's rows (issue 20, setup 4): the default synthetic record, a
//! quadratic damper at 5 frequencies × 2 strokes (10 conditions, 34 534 samples), with
//! all three damping laws and with one (target: identification well under 5 ms).

use super::harness::{Budget, measure};
use super::report::{Row, Target};
use super::rows::fail;
use crate::Result;
use msd_ident::{
    dynamometer::{DynamometerOptions, SyntheticDynamometer, dynamometer, synthetic_dynamometer},
    law::DampingLaw,
};

/// The dynamometer identification of the default synthetic record.
pub fn dynamometer_rows(budget: &Budget) -> Result<Vec<Row>> {
    let conditions = synthetic_dynamometer(&SyntheticDynamometer::default())
        .map_err(fail("bench: dynamometer"))?;
    let samples: usize = conditions.iter().map(|c| c.force().len()).sum();
    let all = DynamometerOptions::default();
    let one = DynamometerOptions {
        laws: vec![DampingLaw::QuadraticViscous],
        ..DynamometerOptions::default()
    };
    let mut rows = Vec::new();
    for (options, what) in [(&all, "3 laws compared"), (&one, "quadratic law only")] {
        dynamometer(&conditions, options).map_err(fail("bench: dynamometer"))?;
        rows.push(
            Row::new(
                "setups",
                format!(
                    "dynamometer: {} conditions, {samples} samples, {what}",
                    conditions.len()
                ),
                measure(budget, || dynamometer(&conditions, options).ok()),
            )
            .target(Target::Seconds(5e-3)),
        );
    }
    Ok(rows)
}
