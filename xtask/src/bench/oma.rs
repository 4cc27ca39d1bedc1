//! Output-only modal analysis (issue 43): SSI-cov/ref with automatic selection and
//! jackknife intervals, and FDD/EFDD, on a simulated five-storey building at 10⁴, 10⁵ and
//! 10⁶ samples (the cost should grow linearly with the record: only the covariances see
//! every sample), and on the real steel frame's setup 1 where it is fetched (pyOMA2's SSI-cov
//! on the same array is timed by `examples/python/oma_steel_frame.py`).

use super::growth::few;
use super::harness::{Budget, measure};
use super::report::Row;
use super::rows::fail;
use crate::Result;
use msd_modal::{
    FddOptions, ModalError, OmaFit, OmaOptions, OutputRecord, ShearBuilding, efdd, ssi_cov,
};
use msd_signal::gaussian_noise;

/// The building's rows and, with the data fetched, the steel frame's.
pub fn oma_rows(budget: &Budget) -> Result<Vec<Row>> {
    let building = ShearBuilding {
        masses: vec![25.91; 5],
        stiffnesses: vec![10_000.0; 5],
        damping_ratio: 0.02,
    };
    let sizes = [10_000usize, 100_000, 1_000_000];
    let mut records = Vec::new();
    for samples in sizes {
        let mut draws = gaussian_noise(1, "bench/oma", 1.0, samples * 10)
            .map_err(fail("bench: oma noise"))?
            .into_iter();
        records.push(
            building
                .ambient_record(100.0, samples, 0.1, || draws.next().unwrap_or(0.0))
                .map_err(fail("bench: oma record"))?,
        );
    }
    // One block-row (and lag) setting for all three: the cost differs by the record alone.
    let ssi = OmaOptions {
        block_rows: Some(57),
        ..OmaOptions::default()
    };
    let fdd = FddOptions {
        lags: Some(2048),
        ..FddOptions::default()
    };
    let mut rows = growth(
        budget,
        &records,
        "SSI-cov/ref, automatic selection and jackknife intervals",
        "57 block rows, orders 2–80",
        |r| ssi_cov(r, &ssi),
    )?;
    rows.extend(growth(
        budget,
        &records,
        "FDD peak picking and EFDD with jackknife intervals",
        "2048 lags",
        |r| efdd(r, &fdd),
    )?);
    if let Some(record) = steel_frame()? {
        let fit = ssi_cov(&record, &OmaOptions::default()).map_err(fail("bench: steel frame"))?;
        rows.push(
            Row::new(
                "oma",
                "SSI-cov/ref at default settings on the steel frame's setup 1 (5 channels × 61,440 samples, 106 block rows)",
                measure(budget, || ssi_cov(&record, &OmaOptions::default()).ok()),
            )
            .note(format!("{} modes; pyOMA2: examples/python/oma_steel_frame.py", fit.modes.len())),
        );
        let fdd = FddOptions::default();
        let fit = efdd(&record, &fdd).map_err(fail("bench: steel frame EFDD"))?;
        rows.push(
            Row::new(
                "oma",
                "FDD/EFDD at default settings on the steel frame's setup 1 (5 channels × 61,440 samples)",
                measure(budget, || efdd(&record, &fdd).ok()),
            )
            .note(format!("{} modes, {}", fit.modes.len(), fit.settings())),
        );
    }
    Ok(rows)
}

/// Setup 1 of the steel frame as the `[operational]` kind reads it, if fetched.
fn steel_frame() -> Result<Option<OutputRecord>> {
    let path = crate::project_root().join("configs/steel-frame.toml");
    let data = crate::project_root().join("data/steel-frame/measurement_1/measurement_1.npy");
    if !data.exists() {
        return Ok(None);
    }
    let config = msd_experiment::config::Config::load(&path)?;
    let progress = msd_experiment::progress::Progress::new(false);
    let outcome = msd_experiment::operational::run(
        msd_experiment::config::Spec::new(config)?,
        &Default::default(),
        &progress,
    )?;
    Ok(Some(outcome.record))
}

/// One method's rows on the records of growing length, the last noting the marginal cost
/// per added sample.
fn growth(
    budget: &Budget,
    records: &[OutputRecord],
    what: &str,
    settings: &str,
    run: impl Fn(&OutputRecord) -> std::result::Result<OmaFit, ModalError>,
) -> Result<Vec<Row>> {
    let mut rows = Vec::new();
    let mut times = Vec::new();
    for record in records {
        let samples = record.len();
        let fit = run(record).map_err(fail("bench: oma"))?;
        let timed = measure(&few(budget), || run(record).ok());
        times.push((samples as f64, timed.median()));
        rows.push(
            Row::new(
                "oma",
                format!("{what}: 5 channels × {samples} samples ({settings})"),
                timed,
            )
            .note(format!("{} modes", fit.modes.len())),
        );
    }
    if let (Some(last), &[(n1, t1), (n2, t2), (n3, t3)]) = (rows.last_mut(), &times[..]) {
        // A fixed part (the SVDs and the eigenproblems) and a part per sample (the
        // covariances): the marginal cost per sample from 10⁴ to 10⁵ and from 10⁵ to 10⁶.
        let (low, high) = ((t2 - t1) / (n2 - n1), (t3 - t2) / (n3 - n2));
        last.note += &format!(
            "; per added sample {:.2} µs (10⁴→10⁵) and {:.2} µs (10⁵→10⁶): linear when equal",
            1e6 * low,
            1e6 * high
        );
    }
    Ok(rows)
}
