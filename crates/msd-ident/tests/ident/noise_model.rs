//! The errors-in-variables noise model of the joint fit: a load cell's noise is found,
//! widens the intervals as it should, and leaves an exact drive's intervals alone.

use msd_ident::records::{NoiseModel, simulate_channels};
use msd_ident::{
    Channel, Drive, Excitation, Frame, InitialState, Parameters, Quantity, Record, RecordsFit,
    RecordsOptions, ResponseQuantity, fit_records,
};
use msd_signal::{Multisine, MultisineSpec, PhaseScheme, Signal, gaussian_noise};

const PLANT: Parameters = Parameters {
    mass: 1.7,
    damping: 3.1,
    stiffness: 950.0,
};
const FORCE_RMS: f64 = 5.0;

/// 20 s at 1 kHz of a 0.2–15 Hz multisine force (5 N rms) whose load cell reads it with
/// white noise of `fraction` × its rms; the sensors' white noise as given, plus offsets.
fn load_cell_record(seed: u64, fraction: f64, sensors: &[(ResponseQuantity, f64)]) -> Record {
    let (dt, n) = (1e-3, 20_000);
    let spec = MultisineSpec {
        base_frequency: 0.1,
        f_min: 0.2,
        f_max: 15.0,
        rms: FORCE_RMS,
        phases: PhaseScheme::Random,
        seed,
        ..MultisineSpec::default()
    };
    let force = Signal::Multisine(Multisine::new(spec).expect("valid")).sample(0.0, dt, n);
    let exact = Excitation::from_samples(0.0, dt, force.clone()).expect("valid");
    let kinds: Vec<_> = sensors.iter().map(|s| (s.0, Frame::Absolute)).collect();
    let clean = simulate_channels(
        &PLANT,
        InitialState::REST,
        Drive::Force,
        Some(&exact),
        n,
        dt,
        &kinds,
    )
    .expect("simulated");
    let channels = sensors
        .iter()
        .zip(clean)
        .enumerate()
        .map(|(i, (&(quantity, sigma), clean))| {
            let noise = gaussian_noise(seed, &format!("sensor {i}"), sigma, n).expect("noise");
            Channel::new(
                format!("sensor {i}"),
                quantity.into(),
                clean
                    .iter()
                    .zip(&noise)
                    .map(|(x, e)| x + e + 2.0 * sigma)
                    .collect(),
            )
        })
        .collect();
    let drive_noise = gaussian_noise(seed, "load cell", fraction * FORCE_RMS, n).expect("noise");
    let measured = force.iter().zip(&drive_noise).map(|(f, e)| f + e).collect();
    Record {
        name: "run".into(),
        excitation: Excitation::from_samples(0.0, dt, measured).expect("valid"),
        channels,
    }
}

const ACCELEROMETER: (ResponseQuantity, f64) = (ResponseQuantity::Acceleration, 0.05);

fn fit(record: Record, noise_model: NoiseModel) -> RecordsFit {
    let options = RecordsOptions {
        noise_model,
        ..RecordsOptions::default()
    };
    fit_records(&[record], &options).expect("fitted")
}

/// The promise: with an exact drive, today's intervals within 1 %.
#[test]
fn an_exact_drive_keeps_the_white_noise_intervals_within_one_per_cent() {
    for seed in 1..=3 {
        let f = fit(
            load_cell_record(seed, 0.0, &[ACCELEROMETER]),
            NoiseModel::InputNoise,
        );
        let m = &f.noise_model;
        assert_eq!(m.treatment, "input_noise");
        assert!((m.interval_ratio - 1.0).abs() < 0.01, "seed {seed}: {m}");
        let white = f.white_noise_plant.as_ref().expect("both reported");
        let (a, b) = (f.plant.damping.unwrap(), white.damping.unwrap());
        assert_eq!(a.value, b.value, "the estimate is the same");
        assert!(
            (a.standard_error / b.standard_error - 1.0).abs() < 0.01,
            "seed {seed}"
        );
        assert!(
            f.whiteness.iter().all(|c| c.ljung_box.p_value > 1e-3),
            "seed {seed}: white residuals"
        );
        // Under white noise the output-error fit is efficient: its variances are the
        // Cramér–Rao bound's, to the few lines the Whittle sum leaves out.
        assert_eq!(m.efficiency.len(), 5, "{m}");
        assert!(
            m.efficiency.values().all(|e| (0.97..=1.01).contains(e)),
            "seed {seed}: {:?}",
            m.efficiency
        );
    }
}

/// 1 % force noise: the model finds it (σ̂_u near 1 % of the rms, the likelihood ratio
/// far past its 1 % point) and the intervals widen several times, as the probe of the
/// issue measured the spread (2–5× the white-noise SE).
#[test]
fn a_noisy_load_cell_is_found_and_widens_the_intervals() {
    let f = fit(
        load_cell_record(7, 0.01, &[ACCELEROMETER]),
        NoiseModel::InputNoise,
    );
    let m = &f.noise_model;
    let fraction = m.input_noise_fraction.expect("fitted");
    assert!((fraction / 0.01 - 1.0).abs() < 0.3, "{m}");
    assert!(m.p_value.expect("tested") < 1e-6, "{m}");
    assert!(m.interval_ratio > 2.0, "{m}");
    assert!(
        f.whiteness.iter().all(|c| c.passed),
        "the model explains the colour: {:?}",
        f.whiteness
    );
    assert!(
        f.whiteness[0].ljung_box.p_value < 1e-3,
        "as fitted the residual is coloured"
    );
    assert!(
        f.notes.iter().any(|n| n.contains("drive's own noise")),
        "{:?}",
        f.notes
    );
    assert!(f.to_string().contains("noise model: input_noise"), "{f}");
    // The output-error fit counts the resonance's lines as the sensor's noise alone;
    // there the drive's noise makes them worth less: its efficiency is below 1, and the
    // weighted estimate that replaces it reaches the bound (its sandwich is F⁻¹ to
    // the Whittle lines' approximation).
    assert_eq!(m.estimator, "weighted", "{m}");
    let mass = m.output_error_efficiency["mass"];
    assert!(mass > 0.0 && mass < 0.8, "{:?}", m.output_error_efficiency);
    assert!(
        m.efficiency.values().all(|e| (0.95..=1.05).contains(e)),
        "{:?}",
        m.efficiency
    );
    assert!((m.cost_ratio.expect("weighted") - 1.0).abs() < 0.05, "{m}");
    // Narrower than the output-error estimate's intervals, by √(its efficiency), and
    // both hold the truth.
    let oe = f.output_error_plant.as_ref().expect("both reported");
    for (ours, theirs, truth) in [
        (f.plant.mass, oe.mass, PLANT.mass),
        (f.plant.stiffness, oe.stiffness, PLANT.stiffness),
    ] {
        let (ours, theirs) = (ours.unwrap(), theirs.unwrap());
        let ratio = ours.standard_error / theirs.standard_error;
        assert!((ratio / mass.sqrt() - 1.0).abs() < 0.2, "{ratio} {mass}");
        assert!(
            ours.contains(truth) && theirs.contains(truth),
            "{ours} {theirs}"
        );
    }
}

/// What the model found, to be seen: the residual's spectrum follows σ²_a plus the
/// drive's noise through the plant, peaked at the resonance, inside each band's 95 %
/// range; the white level alone leaves the resonance's bands far above it.
#[test]
fn the_residual_spectrum_follows_the_noise_model() {
    let natural = (PLANT.stiffness / PLANT.mass).sqrt() / std::f64::consts::TAU;
    let inside = |s: &msd_ident::records::ResidualSpectrum| {
        (s.residual.iter().zip(s.lower.iter().zip(&s.upper)))
            .filter(|(r, (lo, hi))| lo <= r && r <= hi)
            .count()
    };
    let (mut held, mut bands) = (0, 0);
    for seed in 1..=4 {
        let f = fit(
            load_cell_record(seed, 0.01, &[ACCELEROMETER]),
            NoiseModel::InputNoise,
        );
        let s = f.whiteness[0].spectrum.as_ref().expect("computed");
        // Far above the resonance an accelerometer sees the force's noise as 1/m of it:
        // the level 2·(σ²_a + σ²_u/m²)·dt (σ_a 0.05 m/s², σ_u 0.05 N, dt 1 ms), which
        // the ten thousand lines there fix to about 1 %.
        let sigma_u = 0.01 * FORCE_RMS;
        let level = 2.0 * (ACCELEROMETER.1.powi(2) + (sigma_u / PLANT.mass).powi(2)) * 1e-3;
        let high = s.model()[s.drive.len() - 1];
        assert!((high / level - 1.0).abs() < 0.05, "{high} {level}");
        let peak = (0..s.drive.len())
            .max_by(|&a, &b| s.drive[a].total_cmp(&s.drive[b]))
            .expect("bands");
        assert!((s.frequency_hz[peak] / natural - 1.0).abs() < 0.1, "{peak}");
        held += inside(s);
        bands += s.residual.len();
    }
    // 95 % expected, a little less where the fit absorbed its degrees of freedom at
    // the resonance (its band's residual about half the model); 268 bands, standard
    // error 0.013: 0.88 is five of them below.
    let fraction = held as f64 / bands as f64;
    assert!(fraction > 0.88, "{fraction} of {bands} bands");
    let white = fit(
        load_cell_record(1, 0.01, &[ACCELEROMETER]),
        NoiseModel::White,
    );
    let w = white.whiteness[0].spectrum.as_ref().expect("computed");
    assert!(w.drive.iter().all(|d| *d == 0.0));
    let above = (w.frequency_hz.iter().zip(w.residual.iter().zip(&w.upper)))
        .filter(|(f, (r, hi))| (*f / natural - 1.0).abs() < 0.1 && r > hi)
        .count();
    assert!(above >= 1, "the resonance stands above the white level");
}

/// The white model says what it assumed, and the whiteness test flags the colour it
/// leaves, with the hint to the model that explains it.
#[test]
fn the_white_model_flags_the_coloured_residual_it_leaves() {
    let f = fit(
        load_cell_record(7, 0.01, &[ACCELEROMETER]),
        NoiseModel::White,
    );
    assert_eq!(f.noise_model.treatment, "white");
    assert!(f.noise_model.input_noise_sigma.is_none() && f.white_noise_plant.is_none());
    assert!(!f.whiteness[0].passed, "{:?}", f.whiteness);
    assert!(
        f.notes
            .iter()
            .any(|n| n.contains("noise_model = \"input_noise\"")),
        "{:?}",
        f.notes
    );
}

/// Two sensors of one record see the same drive noise: each keeps its own white level
/// (σ̂ within 10 %: 20 000 samples give σ̂ to 0.5 %, the drive's share near resonance
/// moves it by a few per cent at most).
#[test]
fn two_sensors_keep_their_own_white_noise_levels() {
    let displacement = (ResponseQuantity::Displacement, 1e-5);
    let f = fit(
        load_cell_record(3, 0.01, &[displacement, ACCELEROMETER]),
        NoiseModel::InputNoise,
    );
    let sigmas = &f.noise_model.sensor_sigmas;
    assert!((sigmas[0] / 1e-5 - 1.0).abs() < 0.1, "{sigmas:?}");
    assert!((sigmas[1] / 0.05 - 1.0).abs() < 0.1, "{sigmas:?}");
    assert!(f.noise_model.interval_ratio > 1.5, "{}", f.noise_model);
}

/// A displacement sensor beside an accelerometer under 3 % load-cell noise: the
/// residuals are white under the noise model, as they are. The state the drive's noise
/// leaves at the record's end wraps round in the DFT (a 1/ω term where a displacement's
/// drive noise falls as 1/ω²); unless its two free responses are projected out, 8 of
/// these 20 displacement channels failed the test with Q in the hundreds. At the 1 %
/// level 40 tests fail more than twice with probability under 1 %.
#[test]
fn a_displacement_sensor_under_a_noisy_drive_is_white_under_the_model() {
    let displacement = (ResponseQuantity::Displacement, 1e-5);
    let mut failed = Vec::new();
    for seed in 1..=20 {
        let f = fit(
            load_cell_record(seed * 16, 0.03, &[displacement, ACCELEROMETER]),
            NoiseModel::InputNoise,
        );
        for check in &f.whiteness {
            let under = check.ljung_box_under_noise_model.expect("under the model");
            if under.p_value < 0.01 {
                failed.push((seed, check.channel.clone(), under.q));
            }
        }
    }
    assert!(failed.len() <= 2, "{failed:?}");
}

/// A free decay has no drive: white, said so.
#[test]
fn a_free_decay_is_white() {
    let grid = Excitation::from_samples(0.0, 0.002, vec![0.0; 3000]).expect("valid");
    let released = InitialState {
        displacement: 0.01,
        velocity: 0.0,
    };
    let x = simulate_channels(
        &PLANT,
        released,
        Drive::None,
        None,
        3000,
        0.002,
        &[(ResponseQuantity::Displacement, Frame::Absolute)],
    )
    .expect("simulated");
    let noise = gaussian_noise(1, "laser", 1e-5, 3000).expect("noise");
    let samples = x[0].iter().zip(&noise).map(|(x, e)| x + e).collect();
    let record = Record {
        name: "pluck".into(),
        excitation: grid,
        channels: vec![Channel::new("laser", Quantity::Displacement, samples)],
    };
    let options = RecordsOptions {
        drive: Drive::None,
        ..RecordsOptions::default()
    };
    let f = fit_records(&[record], &options).expect("fitted");
    assert_eq!(f.noise_model.treatment, "white");
    assert!(f.noise_model.input_noise_sigma.is_none());
    assert_eq!(f.whiteness.len(), 1);
}
