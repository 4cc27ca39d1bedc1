"""msd.frf against scipy's Welch estimates; msd.modal_fit against the Rust run of the
impact-frf config on the same FRFs."""

import numpy as np
import pytest

import msd
from conftest import require


@pytest.fixture(scope="module")
def random_test():
    """A random force on the paper's plant, the response with noise."""
    rng = np.random.default_rng(7)
    t = np.arange(2**14) * 0.01
    force = rng.normal(size=t.size)
    x = msd.simulate((2.5, 1.8, 120.0), t, force) + 1e-5 * rng.normal(size=t.size)
    return t, force, x


def test_h1_and_coherence_equal_scipys(random_test):
    from scipy import signal

    t, force, x = random_test
    f, h, coherence = msd.frf(t, force, x, "H1", segment_length=1024, overlap=0.5)
    fs = 100.0
    sf, pxx = signal.welch(force, fs, window="hann", nperseg=1024, noverlap=512, detrend="constant")
    _, pxy = signal.csd(force, x, fs, window="hann", nperseg=1024, noverlap=512, detrend="constant")
    _, cxy = signal.coherence(force, x, fs, window="hann", nperseg=1024, noverlap=512, detrend="constant")
    np.testing.assert_allclose(f, sf, rtol=1e-12)
    lines = slice(1, None)  # the 0 Hz line is detrended away in both
    np.testing.assert_allclose(h[lines], (pxy / pxx)[lines], rtol=1e-9)
    np.testing.assert_allclose(coherence[lines], cxy[lines], rtol=1e-9, atol=1e-12)


def test_frf_result_object(random_test):
    t, force, x = random_test
    r = msd.frf(t, force, x, "Hv", segment_length=2048, kind="displacement")
    assert r.kind == "receptance" and r.data["averages"] == 15
    assert r.h.dtype == np.complex128 and r.frequency.shape == r.h.shape == r.coherence.shape
    k = np.argmin(np.abs(r.frequency - 1.1027))
    assert abs(abs(r.h[k]) * 1.8 * 2 * np.pi * 1.1027 - 1) < 0.2  # |H| ≈ 1/(c ω) at resonance
    assert "<table" in r._repr_html_() and "receptance" in r._repr_html_()
    back = msd.FrequencyResponse.from_dict(r.to_dict())
    np.testing.assert_array_equal(back.h, r.h)
    # two records averaged, as a 2-D array
    two = msd.frf(t[:8192], np.vstack([force[:8192], force[8192:]]), np.vstack([x[:8192], x[8192:]]))
    assert two.data["averages"] == 2


def test_frf_errors(random_test):
    t, force, x = random_test
    with pytest.raises(ValueError, match="unknown variant `H3`"):
        msd.frf(t, force, x, "H3")
    with pytest.raises(ValueError, match="longer than the 16384 samples"):
        msd.frf(t, force, x, segment_length=10**6)
    with pytest.raises(ValueError):
        msd.frf(t, force, x[:-5])


def impact_frfs(root):
    require(root / "data/impact-frf/meas_point_1.txt", "cargo xtask fetch-data impact-frf", "MSD_REQUIRE_REAL_DATA")
    h1 = np.loadtxt(root / "data/impact-frf/meas_point_1.txt", dtype=complex)
    h2 = np.loadtxt(root / "data/impact-frf/meas_point_2.txt", dtype=complex)
    return np.arange(h1.size) * 1.0, h1, h2


def test_modal_fit_of_the_impact_set_equals_the_rust_run(root, tmp_path):
    f, h1, h2 = impact_frfs(root)
    fit = msd.modal_fit(
        f, [h1, h2], kind="accelerance", dofs=[((1, 1), (1, 1)), ((1, 1), (2, 1))], band_hz=[10.0, 1000.0]
    )
    run = msd.run(root / "configs/impact-frf.toml", out=tmp_path / "impact")
    rust_modes = run["modes"] if "modes" in run else run["set"]["modes"]
    assert len(fit.modes) == len(rust_modes) == 6
    for ours, theirs in zip(fit.modes, rust_modes):
        assert ours.natural_frequency_hz.value == theirs["natural_frequency_hz"]["value"]
        assert ours.damping_ratio.value == theirs["damping_ratio"]["value"]
        assert list(ours.damping_ratio.ci95) == theirs["damping_ratio"]["ci95"]
    assert fit.is_set and fit.mac.shape == (6, 6)
    assert fit.modes[0].shape_dofs == [(1, 1), (2, 1)]
    assert "<table" in fit._repr_html_() and "mode 6" in repr(fit)


def test_modal_fit_of_one_frf(root):
    f, h1, _ = impact_frfs(root)
    fit = msd.modal_fit(f, h1, kind="accelerance", band_hz=[10.0, 1000.0])
    assert not fit.is_set and len(fit.modes) >= 5
    assert abs(fit.modes[1].natural_frequency_hz.value - 142.18) < 0.1
    assert isinstance(fit.modes[0].modal_constant, complex)
    with pytest.raises(ValueError, match="DOFs"):
        msd.modal_fit(f, [h1, h1], kind="accelerance")
    with pytest.raises(ValueError, match="coherence line 3"):
        msd.modal_fit(f, h1, coherence=np.where(np.arange(f.size) == 3, 2.0, 1.0))
    with pytest.raises(ValueError, match="unknown field `order`"):
        msd.modal_fit(f, h1, order=[2, 4])


def test_a_force_without_power_is_refused(random_test):
    t, force, x = random_test
    with pytest.raises(ValueError):
        msd.frf(t, np.zeros_like(force), x)


def test_one_mode_fit_equals_the_rust_run_of_the_stepped_sine_table(root, tmp_path):
    results = msd.run(root / "configs/frf-table.toml", out=tmp_path / "table")
    f, magnitude, phase = np.loadtxt(root / "configs/data/stepped-sine-table.csv", delimiter=",", skiprows=3).T
    h = magnitude * np.exp(1j * np.deg2rad(phase))  # as msd-signal's from_magnitude_phase
    fit = msd.one_mode_fit(f, h, weighting="relative")
    rust = results["estimate"]
    for name in ("mass", "damping", "stiffness", "natural_frequency_hz", "damping_ratio"):
        ours = getattr(fit, name)
        # equal to the bit on this machine; NumPy's exp and Rust's from_polar may round
        # the table's H differently elsewhere
        assert abs(ours.value / rust[name]["value"] - 1) < 1e-12, name
        assert abs(ours.ci95[1] / rust[name]["ci95"][1] - 1) < 1e-9, name
    assert "classroom estimate" in repr(fit) and "<table" in fit._repr_html_()


def test_one_mode_fit_of_an_exact_receptance():
    f = 0.25 + 0.0577 * np.arange(40)
    w = 2 * np.pi * f
    h = 1 / (120.0 - 2.5 * w**2 + 1j * 1.8 * w)
    fit = msd.one_mode_fit(f, h)
    assert abs(fit.mass.value - 2.5) < 1e-9 and abs(fit.stiffness.value - 120.0) < 1e-7
    assert fit.parameters.damping == fit.damping.value
    with pytest.raises(ValueError, match="unknown variant `weird`"):
        msd.one_mode_fit(f, h, weighting="weird")
    with pytest.raises(ValueError, match="frequenc"):
        msd.one_mode_fit(f[::-1], h)


def test_modal_fit_to_dict_round_trip(root):
    f, h1, h2 = impact_frfs(root)
    fit = msd.modal_fit(f, [h1, h2], kind="accelerance", dofs=[((1, 1), (1, 1)), ((1, 1), (2, 1))],
                        band_hz=[10.0, 1000.0])
    import json

    back = msd.ModalFit.from_dict(json.loads(json.dumps(fit.to_dict())))
    assert back == fit and back.modes[2].natural_frequency_hz == fit.modes[2].natural_frequency_hz
    np.testing.assert_array_equal(back.modes[0].shape, fit.modes[0].shape)


def _multisine_records(seed, force_noise, records=8, length=1000, dt=0.02):
    """Whole periods of a flat multisine (249 lines) driving the paper's plant, the
    response with 0.2 % noise, the force as a load cell with `force_noise` (of its rms)
    reads it; and N_x/S_uu of that noise at the multisine's lines."""
    rng = np.random.default_rng(seed)
    t = np.arange(length) * dt
    lines = np.arange(1, 250)
    phases = rng.uniform(0, 2 * np.pi, lines.size)
    period = np.sum(np.cos(2 * np.pi * lines[:, None] * t[None, :] / (length * dt) + phases[:, None]), axis=0)
    period /= np.std(period)
    settle = 4
    force = np.tile(period, records + settle)
    x = msd.simulate((2.5, 1.8, 120.0), np.arange(force.size) * dt, force)[settle * length:]
    x = x.reshape(records, length)
    x = x + 0.002 * np.std(x) * rng.normal(size=x.shape)
    measured = force[settle * length:].reshape(records, length) + force_noise * rng.normal(size=x.shape)
    nu = np.mean(length * force_noise**2 / np.abs(np.fft.rfft(period)[lines]) ** 2)
    return t, measured, x, nu


def test_a_noisy_load_cell_is_taken_off_h1():
    """10 % noise on a repeating force: H1 is low by (K − 1)/K·N_x/S_uu (K = 8 records;
    the coherence's noise model finds it within its scatter, a few per cent here), and the
    fit made on the corrected lines holds m within 4 standard errors."""
    for seed in range(3):
        t, force, x, nu = _multisine_records(seed, 0.1)
        fr = msd.frf(t, force, x, "H1", window="rectangular")
        assert (fr.averages, fr.estimator) == (8, "H1")
        fit = msd.one_mode_fit(fr)
        found = fit.input_noise
        assert found is not None and found["corrected"], found
        expected = 7 / 8 * nu
        assert abs(found["h1_bias"] / expected - 1) < 0.15, (found, expected)
        assert abs(fit.mass.value - 2.5) < 4 * fit.mass.standard_error, fit.mass
        # Told nothing of how the FRF was made, the fit cannot take the noise apart.
        bare = msd.one_mode_fit(fr.frequency, fr.h, coherence=fr.coherence)
        assert bare.input_noise is None


def test_under_a_hann_window_the_force_noise_is_a_warning(random_test):
    """A random force read with 30 % noise, Hann segments: leakage lowers the coherence
    at the resonance as force noise does, so the bias is said and not taken off."""
    t, force, x = random_test
    noisy = force + 0.3 * np.random.default_rng(3).normal(size=force.size)
    fit = msd.one_mode_fit(msd.frf(t, noisy, x, "H1", segment_length=2048))
    assert fit.input_noise is not None and not fit.input_noise["corrected"]
    assert "warning: the coherence's noise model puts noise on the force" in str(fit)
    fr = msd.frf(t, noisy, x, "H1", segment_length=2048)
    with pytest.raises(ValueError, match="averages"):
        msd.one_mode_fit(fr, averages=0)
    with pytest.raises(ValueError, match="estimator"):
        msd.one_mode_fit(fr, estimator="H3")


def test_an_impact_frf_carries_its_line_correlation_into_the_fits():
    """Five hits on the paper's plant under an exponential window (τ = 2 s of 8 s): the
    estimate says how the window correlates neighbouring lines' errors (about
    1/(1 − jπdτ/T), T/τ = 4 lines), the kernels survive a JSON round trip, and a fit of
    the FrequencyResponse uses them: its intervals are those of the same FRF given the
    kernels, and not those of the same lines taken as independent."""
    rng = np.random.default_rng(11)
    t = np.arange(8 * 128) / 128.0
    pulse = np.where((t >= 0.1) & (t < 0.12), np.sin(np.pi * (t - 0.1) / 0.02), 0.0)
    forces = np.vstack([a * pulse for a in 1.0 + 0.2 * rng.normal(size=5)])
    responses = np.vstack([msd.simulate((2.5, 1.8, 120.0), t, f) for f in forces])
    responses += 0.02 * np.abs(responses).max() * rng.normal(size=responses.shape)
    fr = msd.frf(t, forces, responses, "H1", impact={"force_width": 0.5, "decay_time": 2.0})
    response_kernel, force_kernel = fr.data["line_correlation"]
    assert response_kernel[0] == 1 and force_kernel[0] == 1
    near = 1 / (1 - 1j * np.pi * 2.0 / 8.0)
    assert abs(abs(response_kernel[1]) - abs(near)) < 0.02, response_kernel[1]
    back = msd.FrequencyResponse.from_dict(fr.to_dict())
    np.testing.assert_array_equal(back.data["line_correlation"][0], response_kernel)
    fit = msd.one_mode_fit(fr)
    same = msd.one_mode_fit(back)
    assert same.natural_frequency_hz.standard_error == fit.natural_frequency_hz.standard_error
    independent = msd.one_mode_fit(
        fr.frequency, fr.h, coherence=fr.coherence, exponential_decay=2.0, averages=5, estimator="H1"
    )
    assert independent.damping_ratio.value == fit.damping_ratio.value
    assert independent.damping_ratio.standard_error != fit.damping_ratio.standard_error


def test_an_impact_frf_carries_its_measured_force_noise_into_the_fits():
    """Hits with noise on the force channel: the estimate measures that noise after the
    force window and gives each line's variance from it (about σ²·Σw²/Σ|F_k|²); the
    array survives a JSON round trip and a fit of the FrequencyResponse takes it (the
    force's noise said as measured), where the same lines without it do not."""
    rng = np.random.default_rng(5)
    t = np.arange(8 * 128) / 128.0
    pulse = np.where((t >= 0.1) & (t < 0.12), 100 * np.sin(np.pi * (t - 0.1) / 0.02), 0.0)
    clean = np.vstack([a * pulse for a in 1.0 + 0.2 * rng.normal(size=5)])
    responses = np.vstack([msd.simulate((2.5, 1.8, 120.0), t, f) for f in clean])
    responses += 0.002 * np.abs(responses).max() * rng.normal(size=responses.shape)
    forces = clean + 0.5 * rng.normal(size=clean.shape)
    fr = msd.frf(t, forces, responses, "H1", impact={"force_width": 0.5, "decay_time": 2.0})
    v = fr.data["input_noise_variance"]
    assert v.shape == fr.frequency.shape
    # At 1 Hz: σ² = 0.25 over the force window's 65 samples, against Σ|F|² of five hits.
    k = int(np.argmin(np.abs(fr.frequency - 1.0)))
    power = sum(abs(np.fft.rfft(f * np.where(t <= 0.5, np.exp(-t / 2.0), 0.0))[k]) ** 2 for f in forces)
    window = np.where(t <= 0.5, np.exp(-t / 2.0), 0.0)
    assert abs(v[k] / (0.25 * np.sum(window**2) / power) - 1) < 0.15, v[k]
    back = msd.FrequencyResponse.from_dict(fr.to_dict())
    np.testing.assert_array_equal(back.data["input_noise_variance"], v)
    fit = msd.one_mode_fit(fr)
    assert fit.input_noise is not None and fit.input_noise["measured"], fit.input_noise
    modes = msd.modal_fit(fr, band_hz=[0.5, 6.0], orders=[2, 20])
    check = modes.noise_check
    assert check is not None and check["degrees_of_freedom"] > 1, check
    assert "measured on the force channel" in str(fit)
    given = msd.one_mode_fit(
        fr.frequency, fr.h, coherence=fr.coherence, exponential_decay=2.0, averages=5,
        estimator="H1", input_noise_variance=v,
    )
    assert given.input_noise is not None and given.input_noise["measured"]
    with pytest.raises(ValueError, match="input_noise_variance"):
        msd.one_mode_fit(fr, input_noise_variance=v[:-1])
    without = dict(fr.data)
    without["input_noise_variance"] = None
    other = msd.one_mode_fit(msd.FrequencyResponse(without))
    assert other.input_noise is None or not other.input_noise["measured"]


def test_a_set_with_coherence_checks_its_residual_against_its_members_noise():
    """Three FRFs of two modes with flat noise on the response and the coherence it
    gives over 20 averages: the set's residual passes its check against that noise; fitted
    with one mode too few it fails it."""
    rng = np.random.default_rng(3)
    f = np.arange(1, 601) * 0.05
    s = 2j * np.pi * f
    shapes = np.array([[1.0, 0.8, 0.4], [1.0, -0.5, -1.0]])
    poles = [(10.0, 0.01), (24.0, 0.02)]
    sigma, k = 2e-6, 20
    frfs, coherences = [], []
    for point in range(3):
        h = np.zeros_like(s)
        for r, (fn, zeta) in enumerate(poles):
            wn = 2 * np.pi * fn
            h += shapes[r][0] * shapes[r][point] / (s**2 + 2 * zeta * wn * s + wn**2)
        h += sigma / np.sqrt(2) * (rng.normal(size=f.size) + 1j * rng.normal(size=f.size))
        power = np.abs(h) ** 2
        frfs.append(h)
        coherences.append(power / (power + (k - 1) * sigma**2))
    dofs = [((p + 1, 3), (1, 3)) for p in range(3)]
    fit = msd.modal_fit(f, frfs, coherence=coherences, averages=k, dofs=dofs)
    assert fit.is_set and len(fit.modes) == 2
    assert fit.noise_check is not None and fit.noise_check["passed"], fit.noise_check
    short = msd.modal_fit(f, frfs, coherence=coherences, averages=k, dofs=dofs, mode_count=1)
    assert not short.noise_check["passed"], short.noise_check
    assert msd.modal_fit(f, frfs, dofs=dofs).noise_check is None
