//! Seeded noise: reproducibility, moments within bounds derived from N, independent streams.

use msd_signal::{NoiseStream, SignalError, gaussian_noise, stream_id};

const N: usize = 20_000;
/// Bounds are 5 standard errors: a correct generator fails one with probability < 6e-7.
const Z: f64 = 5.0;

#[test]
fn same_seed_and_stream_give_identical_samples() {
    let a = gaussian_noise(2024, "identification", 0.0025, 1000).expect("valid sigma");
    let b = gaussian_noise(2024, "identification", 0.0025, 1000).expect("valid sigma");
    assert_eq!(a, b);
    assert_ne!(
        a,
        gaussian_noise(2025, "identification", 0.0025, 1000).expect("valid")
    );
    assert_ne!(
        a,
        gaussian_noise(2024, "validation", 0.0025, 1000).expect("valid")
    );
    // Streaming in pieces gives the same samples as one call.
    let mut s = NoiseStream::new(2024, "identification", 0.0025).expect("valid");
    let mut first = vec![0.0; 300];
    let mut rest = vec![1.0; 700];
    s.fill(&mut first);
    s.add_to(&mut rest);
    assert_eq!(&first[..], &a[..300]);
    for (r, x) in rest.iter().zip(&a[300..]) {
        assert_eq!(*r, 1.0 + x);
    }
    // Drawing from another stream in between changes nothing.
    let _other = gaussian_noise(2024, "new_stream", 1.0, 5000).expect("valid");
    assert_eq!(
        a,
        gaussian_noise(2024, "identification", 0.0025, 1000).expect("valid")
    );
}

#[test]
fn sample_mean_and_standard_deviation_within_bounds() {
    let sigma = 0.7;
    for seed in 0..4u64 {
        let x = gaussian_noise(seed, "moments", sigma, N).expect("valid");
        let n = N as f64;
        let mean = x.iter().sum::<f64>() / n;
        // Standard error of the mean: σ/√N.
        assert!(
            mean.abs() < Z * sigma / n.sqrt(),
            "seed {seed}: mean {mean}"
        );
        let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
        // For Gaussian data Var(s²) = 2σ⁴/(N − 1).
        let se_var = sigma * sigma * (2.0 / (n - 1.0)).sqrt();
        assert!(
            (var - sigma * sigma).abs() < Z * se_var,
            "seed {seed}: var {var}"
        );
        // Fourth moment: kurtosis 3 with standard error ≈ √(24/N).
        let m4 = x.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / n;
        let kurtosis = m4 / (var * var);
        assert!(
            (kurtosis - 3.0).abs() < Z * (24.0 / n).sqrt(),
            "seed {seed}: kurtosis {kurtosis}"
        );
    }
}

#[test]
fn different_streams_are_uncorrelated() {
    let names = ["identification", "validation", "monte_carlo", "a", "b"];
    let draws: Vec<Vec<f64>> = names
        .iter()
        .map(|s| gaussian_noise(9, s, 1.0, N).expect("valid"))
        .collect();
    for i in 0..names.len() {
        for j in i + 1..names.len() {
            let r = draws[i]
                .iter()
                .zip(&draws[j])
                .map(|(a, b)| a * b)
                .sum::<f64>()
                / N as f64;
            // Under independence the sample correlation has standard error 1/√N.
            assert!(
                r.abs() < Z / (N as f64).sqrt(),
                "{} vs {}: r = {r}",
                names[i],
                names[j]
            );
        }
    }
    // Lag-1 autocorrelation of one stream: white.
    let x = &draws[0];
    let r1 = x.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / N as f64;
    assert!(r1.abs() < Z / (N as f64).sqrt());
}

#[test]
fn stream_id_is_fnv1a_64() {
    // Published FNV-1a 64 test vectors.
    assert_eq!(stream_id(""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(stream_id("a"), 0xaf63_dc4c_8601_ec8c);
    assert_eq!(stream_id("foobar"), 0x8594_4171_f739_67e8);
}

#[test]
fn invalid_sigma_is_refused() {
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            gaussian_noise(1, "x", bad, 3),
            Err(SignalError::InvalidParameter { ref parameter, .. }) if parameter == "sigma"
        ));
    }
    assert_eq!(
        gaussian_noise(1, "x", 0.0, 3).expect("sigma 0 is allowed"),
        vec![0.0; 3]
    );
}
