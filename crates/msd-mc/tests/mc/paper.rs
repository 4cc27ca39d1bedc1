//! The paper's Figure 4: the 90 % band around the validation response.

use crate::{exact, paper};
use msd_mc::monte_carlo_band;

#[test]
fn band_contains_most_validation_data_and_widens_around_the_peaks() {
    let (experiment, fit) = paper();
    let v = &experiment.validation;
    let band = monte_carlo_band(
        &fit.parameters,
        &v.excitation,
        Some(&v.output),
        &exact(1000),
    )
    .unwrap();
    assert_eq!((band.samples, band.failed_samples), (1000, 0));
    // "Most" measurements inside the 90 % band (the band is 0 wide at t = 0, where the
    // noise puts points outside).
    let coverage = band.coverage.unwrap();
    assert!(coverage > 0.8, "coverage {coverage}");
    // ±10 % uniform in m and k keeps fn = √(k/m)/2π within √(0.9/1.1)..√(1.1/0.9) of θ̂'s.
    let fnat = fit.parameters.natural_frequency_hz();
    let spread = &band.natural_frequency_hz;
    assert!(
        spread.min >= (0.9f64 / 1.1).sqrt() * fnat && spread.max <= (1.1f64 / 0.9).sqrt() * fnat
    );
    // Widening around the peaks: where |x| is at least half its maximum the band is on
    // average at least 1.5 times as wide as where |x| is below a tenth of it, and the
    // widest point follows the largest peak within 2 s (the ringing after resonance).
    let peak = band.nominal.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let mean_width = |keep: &dyn Fn(f64) -> bool| {
        let (sum, count) = band
            .width
            .iter()
            .zip(&band.nominal)
            .filter(|(_, x)| keep(x.abs()))
            .fold((0.0, 0), |(s, c), (w, _)| (s + w, c + 1));
        sum / count as f64
    };
    let near_peaks = mean_width(&|x| x >= 0.5 * peak);
    let quiet = mean_width(&|x| x <= 0.1 * peak);
    assert!(near_peaks > 1.5 * quiet, "{near_peaks} vs {quiet}");
    let argmax =
        |v: &[f64]| (0..v.len()).fold(0, |b, i| if v[i].abs() > v[b].abs() { i } else { b });
    let t_peak = band.times[argmax(&band.nominal)];
    let t_widest = band.times[argmax(&band.width)];
    assert!(
        (0.0..2.0).contains(&(t_widest - t_peak)),
        "peak {t_peak} s, widest {t_widest} s"
    );
}
