//! Frequency-domain configs end to end: the stepped sine (one mode, its intervals and
//! their coverage over noise seeds), the hammer test on a two-mass chain and the UFF
//! file (two modes each), and every bad frequency-response input refused with its
//! location and exit status 2.

use msd_experiment::config::{Config, Spec};
use msd_experiment::frf::{self, FrfFit};
use msd_experiment::{RunOptions, run_experiment};
use msd_tests::{assert_results_file_is, config, decode_png, parse_svg, run_in_temp};
use serde_json::Value;
use std::path::Path;

#[test]
fn the_stepped_sine_config_has_m_c_k_inside_their_intervals() {
    let run = run_in_temp(&config("stepped-sine.toml"), None, None).expect("runs");
    for name in ["mass", "damping", "stiffness"] {
        let truth = run.number(&format!("truth.{name}"));
        let ci = &run.summary.results["estimate"][name]["ci95"];
        let (low, high) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
        assert!(
            low < truth && truth < high,
            "{name}: {truth} not in [{low}, {high}]"
        );
    }
    for name in ["natural_frequency_hz", "damping_ratio", "gain"] {
        let value = run.number(&format!("estimate.{name}.value"));
        let ci = &run.summary.results["estimate"][name]["ci95"];
        assert!(
            ci[0].as_f64() < Some(value) && Some(value) < ci[1].as_f64(),
            "{name}"
        );
    }
    // The truth's one mode comes from the state matrix: fn = √(k/m)/2π, ζ = c/(2√(km)).
    let mode = &run.summary.results["truth"]["modes"][0];
    let fn_hz = (120.0f64 / 2.5).sqrt() / std::f64::consts::TAU;
    assert!((mode["natural_frequency_hz"].as_f64().unwrap() / fn_hz - 1.0).abs() < 1e-12);
    let zeta = 1.8 / (2.0 * (2.5f64 * 120.0).sqrt());
    assert!((mode["damping_ratio"].as_f64().unwrap() / zeta - 1.0).abs() < 1e-12);
    assert_eq!(run.number("data.lines"), 40.0);
    assert!(run.summary.results["classroom"][0]["damping_ratio"].is_f64());
    assert_results_file_is(run.out(), &run.summary.results);
    for figure in ["frf_fit_bode", "frf_fit_nyquist"] {
        assert!(decode_png(&run.out().join(format!("{figure}.png"))).0 > 0);
        assert!(parse_svg(&run.out().join(format!("{figure}.svg"))) > 0);
    }
    let page = std::fs::read_to_string(run.out().join("report.html")).expect("html");
    assert!(msd_experiment::page::self_contained_problems(&page).is_empty());
}

/// The 95 % intervals of m, c and k cover the truth in 95 ± 3 % of 200 noise seeds
/// (binomial: σ = √(0.95·0.05/200) = 1.5 %, so ±3 % is two standard deviations). The
/// sweep is logarithmically spaced; on 40 evenly spaced lines (two in the half-power
/// band) the spread of m̂ and k̂ exceeds their Gauss–Newton standard errors by about 3 %
/// (a curvature effect, not the weights or the degrees of freedom), and their intervals
/// cover 94.3 % over 4000 seeds.
#[test]
fn the_stepped_sine_intervals_cover_the_truth_95_percent_of_the_time() {
    let path = config("stepped-sine.toml");
    let config = Config::load(&path).expect("valid");
    let seeds = 200u64;
    let mut covered = [0usize; 3];
    for seed in 1..=seeds {
        let options = RunOptions {
            seed: Some(seed),
            ..RunOptions::default()
        };
        let outcome = frf::run(
            Spec::new(config.clone()).expect("a frequency response"),
            &options,
        )
        .expect("fits");
        let FrfFit::OneMode(fit) = &outcome.fit else {
            panic!("one mode")
        };
        let u = &fit.uncertainty;
        for (i, (interval, truth)) in [(u.mass, 2.5), (u.damping, 1.8), (u.stiffness, 120.0)]
            .iter()
            .enumerate()
        {
            covered[i] += usize::from(interval.contains(*truth));
        }
    }
    let share = covered.map(|c| 100.0 * c as f64 / seeds as f64);
    println!("coverage of m, c, k over {seeds} seeds: {share:?} %");
    for (name, s) in ["m", "c", "k"].iter().zip(share) {
        assert!((s - 95.0).abs() <= 3.0, "{name}: {s} %");
    }
}

/// The modes of a run and the truth's, as (value, ci95) of fn and ζ.
fn modes(results: &Value, key: &str) -> Vec<[(f64, [f64; 2]); 2]> {
    let interval = |v: &Value| {
        let ci = &v["ci95"];
        (
            v["value"].as_f64().unwrap(),
            [ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap()],
        )
    };
    results[key]
        .as_array()
        .unwrap_or_else(|| panic!("no list `{key}`"))
        .iter()
        .map(|m| {
            [
                interval(&m["natural_frequency_hz"]),
                interval(&m["damping_ratio"]),
            ]
        })
        .collect()
}

fn truth_modes(results: &Value) -> Vec<[f64; 2]> {
    results["truth"]["modes"]
        .as_array()
        .expect("truth.modes")
        .iter()
        .map(|m| {
            [
                m["natural_frequency_hz"].as_f64().unwrap(),
                m["damping_ratio"].as_f64().unwrap(),
            ]
        })
        .collect()
}

fn assert_two_modes_cover_the_truth(results: &Value) {
    let fitted = modes(results, "modes");
    let truth = truth_modes(results);
    assert_eq!((fitted.len(), truth.len()), (2, 2));
    for (r, (fit, truth)) in fitted.iter().zip(&truth).enumerate() {
        for (q, name) in ["fn", "ζ"].iter().enumerate() {
            let (value, [low, high]) = fit[q];
            assert!(
                low <= truth[q] && truth[q] <= high,
                "mode {}: {name} = {value} ({low} … {high}) vs {}",
                r + 1,
                truth[q]
            );
        }
        assert!(results["modes"][r]["modal_constants"][0]["re"].is_f64());
    }
}

#[test]
fn the_hammer_test_finds_exactly_two_modes_and_takes_the_window_off() {
    let run = run_in_temp(&config("hammer-2dof.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    assert_two_modes_cover_the_truth(r);
    assert_eq!(run.number("data.averages"), 5.0);
    assert_eq!(run.number("data.exponential_decay"), 2.0);
    // The window added ζ = 1/(ωn·τ) to each mode (to first order; the exact shift
    // differs by O(ζ²)), which was taken off.
    for (r_, truth) in truth_modes(r).iter().enumerate() {
        let added = r["modes"][r_]["window_correction"]["damping_ratio_added"]
            .as_f64()
            .expect("a window correction");
        let first_order = 1.0 / (std::f64::consts::TAU * truth[0] * 2.0);
        assert!(
            (added / first_order - 1.0).abs() < 1e-2,
            "{added} vs {first_order}"
        );
    }
    for figure in ["frf_coherence", "frf_stabilization", "frf_fit_bode"] {
        assert!(
            parse_svg(&run.out().join(format!("{figure}.svg"))) > 0,
            "{figure}"
        );
    }
}

#[test]
fn the_uff_config_reads_the_shipped_file_and_fits_two_modes() {
    let run = run_in_temp(&config("frf-uff.toml"), None, None).expect("runs");
    let r = &run.summary.results;
    assert_two_modes_cover_the_truth(r);
    assert_eq!(run.number("data.lines"), 200.0);
    assert!(
        r["data"]["source"]
            .as_str()
            .unwrap()
            .contains("frf-2dof.uff")
    );
    // A transfer receptance: the two modes' constants have opposite signs, as the truth's.
    let a = |k: &str, i: usize| r[k][i]["modal_constants"][0]["re"].as_f64().unwrap();
    let b = |i: usize| r["truth"]["modes"][i]["modal_constant"].as_f64().unwrap();
    assert!(a("modes", 0) > 0.0 && a("modes", 1) < 0.0);
    assert!(b(0) > 0.0 && b(1) < 0.0);
}

/// A scratch folder with a bad config beside its data.
struct Case(tempfile::TempDir);

impl Case {
    fn new() -> Self {
        Self(tempfile::tempdir().expect("a folder"))
    }

    fn file(&self, name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let path = self.0.path().join(name);
        std::fs::write(&path, bytes).expect("written");
        path
    }

    /// Runs the config and checks the refusal: status 2, one line holding every
    /// fragment, no output folder.
    fn refuses(&self, config: &Path, expected: &[&str]) {
        let out = self.0.path().join("out");
        let options = RunOptions {
            out: Some(out.clone()),
            ..RunOptions::default()
        };
        let err = run_experiment(config, &options).expect_err("refused");
        let message = err.to_string();
        assert_eq!(err.exit_code(), 2, "{message}");
        assert!(!message.contains('\n'), "one line: {message}");
        for fragment in expected {
            assert!(message.contains(fragment), "`{message}` lacks `{fragment}`");
        }
        assert!(!out.exists(), "written for: {message}");
    }
}

const TABLE_CONFIG: &str = "name = \"t\"\n[frequency_response.table]\npath = \"sweep.csv\"\nfrequency = \"f\"\nreal = \"re\"\nimaginary = \"im\"\n";

#[test]
fn bad_frequency_response_inputs_are_refused_where_they_are() {
    let case = Case::new();
    // A missing file.
    let c = case.file(
        "missing.toml",
        b"name = \"m\"\n[frequency_response.uff]\npath = \"nowhere.uff\"\n",
    );
    case.refuses(&c, &["nowhere.uff", "cannot read"]);
    // An unknown column.
    case.file("sweep.csv", b"f,re,imag\n1,0.01,-0.001\n2,0.02,-0.01\n");
    let c = case.file("column.toml", TABLE_CONFIG.as_bytes());
    case.refuses(
        &c,
        &[
            "sweep.csv",
            "line 1",
            "no column named `im`",
            "frequency_response.table.imaginary",
            "`imag`",
        ],
    );
    // Frequencies that do not increase.
    case.file(
        "sweep.csv",
        b"f,re,im\n1,0.01,-0.001\n2,0.02,-0.01\n2,0.03,-0.02\n",
    );
    let c = case.file("order.toml", TABLE_CONFIG.as_bytes());
    case.refuses(
        &c,
        &[
            "sweep.csv",
            "line 4",
            "2 Hz is not above the previous line's 2 Hz",
        ],
    );
    // A UFF file without a dataset 58 (units only), and one whose 58 is a coherence.
    let units = "    -1\n   164\n         1                  SI         1\n    1.0D+00 1.0D+00 1.0D+00\n 0.0D+00\n    -1\n";
    case.file("units.uff", units.as_bytes());
    let c = case.file(
        "units.toml",
        b"name = \"u\"\n[frequency_response.uff]\npath = \"units.uff\"\n",
    );
    case.refuses(
        &c,
        &[
            "units.uff",
            "no frequency response function",
            "0 datasets 58",
            "units (164)",
        ],
    );
    let mut file = msd_uff::UffFile::default();
    file.functions.push(msd_uff::Function58::new(
        msd_uff::FunctionType::Coherence,
        msd_uff::Abscissa::Even {
            start: 1.0,
            step: 1.0,
        },
        msd_uff::Ordinate::Real(vec![0.9; 8]),
    ));
    case.file(
        "coherence.uff",
        &msd_uff::to_bytes(&file, &Default::default()).expect("bytes"),
    );
    let c = case.file(
        "coherence.toml",
        b"name = \"c\"\n[frequency_response.uff]\npath = \"coherence.uff\"\nfunction = 1\n",
    );
    case.refuses(
        &c,
        &[
            "coherence.uff",
            "dataset 58 #1",
            "a coherence (function type 6)",
            "expected a frequency response function",
        ],
    );
    // Two sources, and a simulated source without its plant: the config's line.
    let c = case.file(
        "two.toml",
        b"name = \"two\"\n[frequency_response.sweep]\nband_hz = [1.0, 2.0]\nlines = 8\n[frequency_response.uff]\npath = \"x.uff\"\n",
    );
    case.refuses(&c, &["two.toml:5", "a second source beside `sweep`"]);
    let c = case.file(
        "plantless.toml",
        b"name = \"p\"\n[frequency_response.sweep]\nband_hz = [1.0, 2.0]\nlines = 8\n",
    );
    case.refuses(&c, &["plantless.toml", "frequency_response.plant: missing"]);
}

/// A roving-accelerometer test exported as four tables (accelerance, coherence, 16
/// averages), one force record read with every response (its noise, v = 3e-3 a line,
/// the same in every table): `[[frequency_response.set]]` finds the force's noise common
/// to the members (κ̂ more than two of its standard errors above 0), says so in the
/// summary, the report and `results.json`, and widens the poles' intervals by it. The
/// same tables with each member's own force noise (measured one after another) find
/// none evident. (Coverage is tested in msd-modal's `set_noise`.)
#[test]
fn a_set_sharing_one_force_record_is_found_and_said() {
    let run = |shared: bool| {
        let dir = tempfile::tempdir().unwrap();
        let mut config = String::from("name = \"roving\"\n");
        for point in 1..=4u32 {
            let text = roving_table(point, shared);
            std::fs::write(dir.path().join(format!("p{point}.csv")), text).unwrap();
            config.push_str(&format!(
                "[[frequency_response.set]]\npath = \"p{point}.csv\"\nfrequency = \"f\"\nreal = \"re\"\nimaginary = \"im\"\ncoherence = \"coh\"\naverages = 16\nkind = \"accelerance\"\nresponse = {{ node = {point}, direction = 3 }}\nreference = {{ node = 1, direction = 3 }}\n"
            ));
        }
        let path = dir.path().join("roving.toml");
        std::fs::write(&path, config).unwrap();
        let run = run_in_temp(&path, None, None).expect("runs");
        (dir, run)
    };
    let (_keep, shared) = run(true);
    let found = &shared.summary.results["modal_set"]["shared_force"];
    let (fraction, se) = (
        found["fraction"].as_f64().unwrap(),
        found["standard_error"].as_f64().unwrap(),
    );
    assert!(fraction > 0.5 && fraction > 2.0 * se, "{found}");
    assert!(
        shared.summary.summary.contains("common errors"),
        "{}",
        shared.summary.summary
    );
    let report = std::fs::read_to_string(shared.out().join("report.md")).unwrap();
    assert!(report.contains("common to them"), "{report}");
    let (_keep, own) = run(false);
    let found = &own.summary.results["modal_set"]["shared_force"];
    let (fraction, se) = (
        found["fraction"].as_f64().unwrap(),
        found["standard_error"].as_f64().unwrap(),
    );
    assert!(fraction <= 2.0 * se || fraction < 0.2, "{found}");
    // The poles' standard errors: wider where the members share the force's noise.
    let se_of = |run: &msd_tests::Run| {
        (0..2)
            .map(|r| {
                run.summary.results["modes"][r]["natural_frequency_hz"]["standard_error"]
                    .as_f64()
                    .unwrap()
            })
            .collect::<Vec<f64>>()
    };
    // With κ = 1 and the force's noise dominant at the peaks, four members know the
    // poles as one does: √4 = 2 times the independent members' SE; κ̂ and the force's
    // share below 1 make it less. More than √2.
    for (s, o) in se_of(&shared).iter().zip(se_of(&own)) {
        assert!(s / o > 2f64.sqrt(), "fn SE {s} shared, {o} own");
    }
    eprintln!("{}", shared.summary.summary);
}

/// Point `point`'s accelerance table of a two-mode structure (see [`roving_frf`]).
fn roving_table(point: u32, shared: bool) -> String {
    let (f, h, coherence) = roving_frf(point, shared);
    let mut text = String::from("f,re,im,coh\n");
    for ((f, h), g) in f.iter().zip(&h).zip(&coherence) {
        text.push_str(&format!("{f},{:e},{:e},{g}\n", h.re, h.im));
    }
    text
}

/// Point `point`'s accelerance of a two-mode structure (12 Hz, ζ 2 %; 31 Hz, ζ 1.5 %),
/// the force at point 1: H1 over 16 averages with the force's noise v = 3e-3 a line
/// (`shared`: the same draw at every point) and flat response noise, with the coherence
/// both give: lines, values, coherence.
fn roving_frf(point: u32, shared: bool) -> (Vec<f64>, Vec<msd_signal::Complex64>, Vec<f64>) {
    use msd_signal::{Complex64, gaussian_noise};
    use std::f64::consts::TAU;
    let modes = [
        (12.0, 0.02, [1.0, 0.8, 0.5, 0.2]),
        (31.0, 0.015, [1.0, -0.4, -0.9, -0.6]),
    ];
    let (v, sigma, k): (f64, f64, f64) = (3e-3, 0.01, 16.0);
    let f: Vec<f64> = (8..=240).map(|i| 0.25 * f64::from(i)).collect();
    let noise = |stream: u64, name: &str| gaussian_noise(stream, name, 1.0, f.len()).unwrap();
    let force_stream = if shared { 7 } else { 7 + u64::from(point) };
    let (fre, fim) = (
        noise(force_stream, "force.re"),
        noise(force_stream, "force.im"),
    );
    let (re, im) = (
        noise(100 + u64::from(point), "re"),
        noise(100 + u64::from(point), "im"),
    );
    let (mut h, mut coherence) = (Vec::new(), Vec::new());
    for (j, &fj) in f.iter().enumerate() {
        let w = TAU * fj;
        let exact: Complex64 = (modes.iter())
            .map(|&(fn_hz, zeta, shape)| {
                let wn = TAU * fn_hz;
                -w * w * shape[0] * shape[point as usize - 1]
                    / Complex64::new(wn * wn - w * w, 2.0 * zeta * wn * w)
            })
            .sum();
        let force = (v / 2.0).sqrt() * Complex64::new(fre[j], fim[j]);
        let response = sigma / 2f64.sqrt() * Complex64::new(re[j], im[j]);
        let line = exact / (1.0 + (k - 1.0) * v) + exact * force + response;
        let total = sigma * sigma + v * exact.norm_sqr();
        coherence.push(line.norm_sqr() / (line.norm_sqr() + (k - 1.0) * total));
        h.push(line);
    }
    (f, h, coherence)
}

/// The roving-accelerometer set of [`a_set_sharing_one_force_record_is_found_and_said`]
/// exported as one UFF file, each FRF (dataset 58, type 4) followed by its coherence
/// (type 6, same DOFs): `set = true` with `averages = 16` weights every member by its
/// coherence, checks the residuals and finds the shared force; one FRF with `function`
/// takes its coherence too; `msd inspect` says the key; a coherence on other lines and
/// one above 1 are refused naming the datasets.
#[test]
fn a_universal_file_s_coherence_functions_weight_its_frfs() {
    use msd_uff::{Abscissa, Function58, FunctionType, Ordinate};
    let dir = tempfile::tempdir().unwrap();
    let mut file = msd_uff::UffFile::default();
    for point in 1..=4u32 {
        let (f, h, coherence) = roving_frf(point, true);
        let lines = Abscissa::Uneven(f);
        let values = h.iter().map(|h| (h.re, h.im)).collect();
        let mut frf = Function58::new(
            FunctionType::FrequencyResponse,
            lines.clone(),
            Ordinate::Complex(values),
        );
        let mut gamma = Function58::new(FunctionType::Coherence, lines, Ordinate::Real(coherence));
        for d in [&mut frf, &mut gamma] {
            (d.response_node, d.response_direction) = (i64::from(point), 3);
            (d.reference_node, d.reference_direction) = (1, 3);
        }
        frf.ordinate_axis.data_type = 12;
        file.functions.extend([frf, gamma]);
    }
    let uff = dir.path().join("roving.uff");
    msd_uff::write(&uff, &file, &Default::default()).unwrap();
    let config = dir.path().join("roving.toml");
    let run = |lines: &str| {
        std::fs::write(
            &config,
            format!("name = \"roving\"\n[frequency_response.uff]\npath = \"roving.uff\"\n{lines}"),
        )
        .unwrap();
        run_in_temp(&config, None, None)
    };
    let set = run("set = true\naverages = 16\n").expect("the set runs");
    let results = &set.summary.results;
    assert_eq!(results["modal_set"]["weighting"], "coherence", "{results}");
    assert!(results["modal_set"]["noise_check"].is_object(), "{results}");
    let fraction = results["modal_set"]["shared_force"]["fraction"]
        .as_f64()
        .unwrap();
    assert!(fraction > 0.5, "{results}");
    let source = results["data"]["source"].as_str().unwrap();
    assert!(
        source.contains("each with its coherence function"),
        "{source}"
    );
    let one = run("function = 3\naverages = 16\n").expect("one FRF runs");
    let fit = &one.summary.results["estimate"];
    assert_eq!(fit["weighting"], "coherence", "{fit}");
    let source = one.summary.results["data"]["source"].as_str().unwrap();
    assert!(source.contains("its coherence dataset 58 #4"), "{source}");
    let listing = msd_experiment::inspect::inspect(&uff).unwrap();
    assert!(listing.contains("# averages = 16"), "{listing}");
    // A coherence on other lines, then one above 1.
    let Ordinate::Real(good) = file.functions[1].ordinate.clone() else {
        panic!("real")
    };
    file.functions[1].ordinate = Ordinate::Real(good[1..].to_vec());
    file.functions[1].abscissa =
        Abscissa::Uneven(file.functions[0].abscissa_values()[1..].to_vec());
    msd_uff::write(&uff, &file, &Default::default()).unwrap();
    let message = run("set = true\n").err().expect("refused").to_string();
    assert!(
        message.contains("dataset 58 #2 (the coherence of #1)") && message.contains("232 lines"),
        "{message}"
    );
    let mut high = good.clone();
    high[9] = 1.2;
    file.functions[1].ordinate = Ordinate::Real(high);
    file.functions[1].abscissa = file.functions[0].abscissa.clone();
    msd_uff::write(&uff, &file, &Default::default()).unwrap();
    let message = run("set = true\n").err().expect("refused").to_string();
    assert!(
        message.contains("value 10") && message.contains("1.2") && message.contains("[0, 1]"),
        "{message}"
    );
}
