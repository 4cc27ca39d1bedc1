//! Number and unit formatting shared by the summary, the report and the figures.

/// `v` with `digits` significant digits: fixed notation for moderate magnitudes,
/// scientific otherwise.
///
/// ```
/// use msd_experiment::fmt::sig;
/// assert_eq!(sig(2.503149, 5), "2.5031");
/// assert_eq!(sig(120.0, 5), "120.00");
/// assert_eq!(sig(0.0519621, 4), "0.05196");
/// assert_eq!(sig(1.5e-7, 3), "1.50e-7");
/// assert_eq!(sig(0.0, 3), "0");
/// ```
pub fn sig(v: f64, digits: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let digits = digits.max(1);
    let e = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&e) {
        return format!("{:.*e}", digits - 1, v);
    }
    let decimals = (digits as i32 - 1 - e).max(0) as usize;
    format!("{v:.decimals$}")
}

/// Units of m, c and k for data with these input and output units: kg, N·s/m and
/// N/m for newtons and metres, else the general `in·s²/out`, `in·s/out`, `in/out`.
///
/// ```
/// assert_eq!(msd_experiment::fmt::parameter_units("N", "m"), ["kg", "N·s/m", "N/m"]);
/// assert_eq!(msd_experiment::fmt::parameter_units("V", "V"), ["V·s²/V", "V·s/V", "V/V"]);
/// ```
pub fn parameter_units(input: &str, output: &str) -> [String; 3] {
    if input == "N" && output == "m" {
        return ["kg".into(), "N·s/m".into(), "N/m".into()];
    }
    [
        format!("{input}·s²/{output}"),
        format!("{input}·s/{output}"),
        format!("{input}/{output}"),
    ]
}

/// The rows of every parameter table: name with unit, the true value (synthetic data only)
/// and the estimate with its interval, for m, c, k, fn and ζ.
pub fn parameter_rows<'a>(
    u: &'a msd_ident::Uncertainty,
    truth: Option<msd_ident::Parameters>,
    units: &[String; 3],
) -> [(String, Option<f64>, &'a msd_ident::Interval); 5] {
    [
        (format!("m [{}]", units[0]), truth.map(|t| t.mass), &u.mass),
        (
            format!("c [{}]", units[1]),
            truth.map(|t| t.damping),
            &u.damping,
        ),
        (
            format!("k [{}]", units[2]),
            truth.map(|t| t.stiffness),
            &u.stiffness,
        ),
        (
            "fn [Hz]".into(),
            truth.map(|t| t.natural_frequency_hz()),
            &u.natural_frequency_hz,
        ),
        (
            "ζ [-]".into(),
            truth.map(|t| t.damping_ratio()),
            &u.damping_ratio,
        ),
    ]
}

/// The displayed output unit and the factor to it: millimetres for metres, else as is.
pub fn display_output(unit: &str) -> (f64, String) {
    if unit == "m" {
        (1e3, "mm".into())
    } else {
        (1.0, unit.to_string())
    }
}

/// Milliseconds of a duration, with one decimal below 10 ms.
pub fn millis(d: std::time::Duration) -> String {
    let ms = d.as_secs_f64() * 1e3;
    if ms < 10.0 {
        format!("{ms:.1}")
    } else {
        format!("{ms:.0}")
    }
}

/// The shortest form of `v` after rounding to 9 significant digits ("0.002", "15").
///
/// ```
/// assert_eq!(msd_experiment::fmt::short(0.0020000000000000005), "0.002");
/// assert_eq!(msd_experiment::fmt::short(15.0), "15");
/// ```
pub fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let scale = 10f64.powi(8 - v.abs().log10().floor() as i32);
    format!("{}", (v * scale).round() / scale)
}

/// A count where there is one, "—" where there is none.
///
/// ```
/// assert_eq!(msd_experiment::fmt::count(Some(7)), "7");
/// assert_eq!(msd_experiment::fmt::count(None), "—");
/// ```
pub fn count(n: Option<usize>) -> String {
    n.map_or("—".into(), |n| n.to_string())
}

/// The optimiser's proper name.
pub fn method_name(method: msd_ident::Method) -> &'static str {
    match method {
        msd_ident::Method::NelderMead => "Nelder–Mead",
        msd_ident::Method::LevenbergMarquardt => "Levenberg–Marquardt",
    }
}

/// "Nelder–Mead on ode45 from θ0 = (2.000, 1.000, 100.0)": the optimiser, the simulator
/// and the start of an estimate, as the summary and the report both say it.
///
/// ```
/// # fn main() -> Result<(), msd_ident::IdentError> {
/// let paper = msd_ident::PaperExperiment::generate(1)?;
/// let fit = msd_ident::estimate(&paper.identification, &msd_ident::EstimationOptions::fast())?;
/// assert_eq!(msd_experiment::fmt::solver_start(&fit), "Levenberg–Marquardt on exact from θ0 = (2.000, 1.000, 100.0)");
/// # Ok(())
/// # }
/// ```
pub fn solver_start(e: &msd_ident::Estimate) -> String {
    let g = &e.initial_guess.0;
    format!(
        "{} on {} from θ0 = ({}, {}, {})",
        method_name(e.method),
        e.backend.name(),
        sig(g.mass, 4),
        sig(g.damping, 4),
        sig(g.stiffness, 4)
    )
}

/// The residual tests' two table cells — the Ljung–Box p and the largest residual–drive
/// correlation, marked ✗ beyond its band — and whether that correlation failed; "—"
/// without tests.
pub fn residual_cells(tests: Option<&msd_ident::ResidualAnalysis>) -> (String, String, bool) {
    match tests {
        None => ("—".into(), "—".into(), false),
        Some(a) => {
            let failed = !a.cross_correlation_passed;
            let mark = if failed { " ✗" } else { "" };
            let cross = format!("{}{mark}", sig(a.cross_correlation.max_abs, 2));
            (sig(a.ljung_box.p_value, 2), cross, failed)
        }
    }
}

/// `s` with its first letter upper-case, to open a sentence with a library's phrase.
///
/// ```
/// assert_eq!(msd_experiment::fmt::capitalised("the last 20 %"), "The last 20 %");
/// ```
pub fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or_else(String::new, |f| f.to_uppercase().chain(c).collect())
}
