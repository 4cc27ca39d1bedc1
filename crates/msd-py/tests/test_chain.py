"""msd.simulate_chain, msd.fit_chain and msd.predict_chain: a simulated two-storey rig
fitted back, its uncertainty predicted before the test, the result objects, the setup
given as a dict or by keys, and bad input named by its key."""

import json

import numpy as np
import pytest

import msd

TRUTH = msd.ChainParameters(masses=(2.0, 1.0), dampers=(4.0, 2.0), springs=(2e4, 1e4))
GUESS = {"masses": [2.4, 0.8], "dampers": [3.0, 3.0], "springs": [2.5e4, 0.8e4]}
SENSORS = [{"at": 1, "quantity": "acceleration"}, {"at": 2, "quantity": "acceleration"}]
DT = 2e-3


def rig_record(seed):
    """5000 samples of a white force (1 N) on mass 2, both accelerations with σ = 0.02 m/s²."""
    rng = np.random.default_rng(seed)
    force = rng.normal(size=5000)
    clean = msd.simulate_chain(TRUTH, force, DT, force_at=2, sensors=SENSORS)
    return force, clean + 0.02 * rng.normal(size=clean.shape)


@pytest.fixture(scope="module")
def rig():
    force, outputs = rig_record(11)
    return force, outputs, msd.fit_chain(force, outputs, DT, GUESS, force_at=2, sensors=SENSORS)


def test_simulate_chain_gives_one_row_per_sensor():
    force = np.random.default_rng(0).normal(size=300)
    y = msd.simulate_chain(TRUTH, force, DT, force_at=2, sensors=SENSORS + [{"at": 2}])
    assert y.shape == (3, 300) and y.dtype == np.float64
    # The force on mass 2 reaches its acceleration at once (F/m₂), mass 1's not.
    assert y[1, 0] == pytest.approx(force[0] / 1.0, rel=1e-12) and y[0, 0] == 0.0
    assert y[2, 0] == 0.0
    # The defaults: one displacement sensor on mass 1, the force on mass 1.
    one = msd.simulate_chain({"masses": [2.5], "dampers": [1.8], "springs": [120.0]}, np.ones(20_000), 0.01)
    assert one.shape == (1, 20_000)
    assert one[0, -1] == pytest.approx(1.0 / 120.0, rel=1e-9)
    assert msd.simulate_chain(TRUTH, [], DT, force_at=2, sensors=SENSORS).shape == (2, 0)


def test_one_mass_is_the_single_degree_of_freedom_simulation(ident):
    """One mass, displacement on it: msd.simulate's exact solution with the force linear
    between samples (the same model, computed by another route)."""
    t, force, _ = ident
    chain = msd.simulate_chain({"masses": [2.5], "dampers": [1.8], "springs": [120.0]}, force, t[1] - t[0])
    single = msd.simulate((2.5, 1.8, 120.0), t, force, backend={"kind": "exact", "hold": "first"})
    assert np.max(np.abs(chain[0] - single)) < 1e-9 * np.max(np.abs(single))


def test_two_storey_rig_round_trip(rig):
    _, _, fit = rig
    iv = fit.intervals
    assert fit.identified and iv is not None and fit.unidentifiable == []
    for estimates, truths in ((iv.masses, TRUTH.masses), (iv.dampers, TRUTH.dampers), (iv.springs, TRUTH.springs)):
        for e, x in zip(estimates, truths):
            # 4 SE: a miss has probability 6e-5 per parameter.
            assert abs(e.value - x) < 4 * e.standard_error, (e, x)
            assert e.contains(e.value) and e.standard_error > 0
    # ωn² = 5000 and 20000 (det(K − ω²M) = 0).
    assert len(fit.modes) == 2
    for mode, w2 in zip(fit.modes, (5000.0, 20000.0)):
        fn = mode.natural_frequency_hz
        assert abs(fn.value - np.sqrt(w2) / (2 * np.pi)) < 4 * fn.standard_error, fn
        assert len(mode.shape) == 2 and max(abs(mode.shape.real)) == 1.0
    # σ̂ per channel: 0.02 within 5 % (5000 residuals each: SD 1 %).
    assert fit.noise.shape == (2,)
    np.testing.assert_allclose(fit.noise, 0.02, rtol=0.05)
    assert fit.delays == [None, None]
    assert fit.degrees_of_freedom == 2 * 5000 - 6
    assert fit.exit in ("FTolerance", "XTolerance", "FAndXTolerance", "Gradient")
    assert fit.evaluations > 0 and 1.0 <= fit.condition_number < 1e8
    assert fit.parameters.masses == tuple(e.value for e in iv.masses)


@pytest.mark.parametrize("seed", [4, 38, 64])
def test_records_where_the_fit_stalled_before_the_prefix_stages(seed):
    """From this guess about 3 records in 100 (these seeds) ended with a damper at 0 and
    σ̂ far above the noise until msd-ident fitted the record's first sixteenth and quarter
    before the whole: now every one of seeds 0–199 is fitted within 4 SE (checked when
    this test was written)."""
    force, outputs = rig_record(seed)
    fit = msd.fit_chain(force, outputs, DT, GUESS, force_at=2, sensors=SENSORS)
    iv = fit.intervals
    assert fit.identified and iv is not None
    for estimates, truths in ((iv.masses, TRUTH.masses), (iv.dampers, TRUTH.dampers), (iv.springs, TRUTH.springs)):
        for e, x in zip(estimates, truths):
            assert abs(e.value - x) < 4 * e.standard_error, (seed, e, x)
    np.testing.assert_allclose(fit.noise, 0.02, rtol=0.05)


def test_a_noisy_load_cell_widens_the_chains_intervals():
    """The rig's force read by a load cell with 3 % noise (the chain felt the exact one):
    the default noise model finds it (σ̂_u within 25 % of 0.03 N) and widens the
    intervals; ``noise_model="white"`` keeps the narrow ones and leaves the residuals
    coloured."""
    rng = np.random.default_rng(1005)  # not the record's own stream
    force, outputs = rig_record(5)
    measured = force + 0.03 * rng.normal(size=force.shape)
    fit = msd.fit_chain(measured, outputs, DT, GUESS, force_at=2, sensors=SENSORS)
    model = fit.noise_model
    assert model["treatment"] == "input_noise" and model["p_value"] < 1e-6
    assert model["input_noise_sigma"] == pytest.approx(0.03, rel=0.25)
    assert any("drive's own noise" in note for note in fit.notes)
    white = msd.fit_chain(measured, outputs, DT, GUESS, force_at=2, sensors=SENSORS, noise_model="white")
    assert white.noise_model["treatment"] == "white"
    assert fit.intervals.dampers[0].standard_error > 2 * white.intervals.dampers[0].standard_error
    with pytest.raises(ValueError, match="noise_model"):
        msd.fit_chain(measured, outputs, DT, GUESS, force_at=2, sensors=SENSORS, noise_model="pink")


def test_mode_shapes_keep_their_sign(rig):
    """Each shape is scaled so that its largest magnitude is 1 and the first mass moving at
    least half as much is positive: the same signs on every record (mode 1: both floors
    in phase, [0.5, 1]; mode 2: in opposition, [1, −1], where the two magnitudes tie)."""
    _, _, fit = rig
    other = msd.fit_chain(*rig_record(4), DT, GUESS, force_at=2, sensors=SENSORS)
    for result in (fit, other):
        shapes = [list(mode.shape.real) for mode in result.modes]
        for shape in shapes:
            first = next(v for v in shape if abs(v) >= 0.5 * max(abs(w) for w in shape))
            assert first > 0, shapes
        assert shapes[0] == pytest.approx([0.5, 1.0], abs=2e-3)
        assert shapes[1] == pytest.approx([1.0, -1.0], abs=2e-3)


def test_a_fit_that_runs_a_parameter_away_is_an_identification_error(rig):
    """Springs guessed 100 times too soft: the fit sends c2 to 0 (a wrong minimum), which
    msd-ident reports instead of an estimate."""
    force, outputs, _ = rig
    far = dict(GUESS, springs=[2.5e2, 0.8e2])
    with pytest.raises(msd.IdentificationError, match=r"c2 ran from the guess .* start from a closer guess"):
        msd.fit_chain(force, outputs, DT, far, force_at=2, sensors=SENSORS)


def test_the_fit_is_deterministic(rig):
    force, outputs, fit = rig
    again = msd.fit_chain(force, outputs, DT, GUESS, force_at=2, sensors=SENSORS)
    assert again == fit
    assert again.to_dict() == fit.to_dict()


def test_setup_as_a_dict_list_outputs_and_parameters_objects(rig):
    force, outputs, fit = rig
    setup = {"masses": 2, "drive": "force", "force_at": 2, "sensors": SENSORS}
    as_dict = msd.fit_chain(force, [outputs[0], outputs[1]], DT, msd.ChainParameters.from_dict(GUESS), setup=setup)
    assert as_dict == fit
    # Keys given by name replace the dict's.
    replaced = msd.fit_chain(force, outputs, DT, GUESS, setup=dict(setup, force_at=1), force_at=2)
    assert replaced == fit
    # Strided views read the same values.
    wide = np.zeros((4, outputs.shape[1]))
    wide[::2] = outputs
    assert msd.fit_chain(force, wide[::2], DT, GUESS, setup=setup) == fit


def test_result_object(rig):
    _, _, fit = rig
    text = repr(fit)
    assert text == fit.summary.rstrip("\n")
    assert "m1 = " in text and "k2 = " in text and "mode 2: fn = " in text and "σ̂ per channel" in text
    page = fit._repr_html_()
    assert page.startswith("<table") and "k2 [N/m]" in page and f"{fit.intervals.springs[1].value:.6g}" in page
    assert "fn = " in repr(fit.modes[0])
    back = msd.ChainFit.from_dict(json.loads(json.dumps(fit.to_dict(), allow_nan=False)))
    assert back == fit and repr(back) == repr(fit)
    np.testing.assert_array_equal(back.noise, fit.noise)
    assert back.intervals == fit.intervals and back.modes == fit.modes
    assert back.names == fit.names and np.array_equal(back.correlation, fit.correlation)
    assert msd.ChainParameters.from_dict(fit.parameters.to_dict()) == fit.parameters
    # The statistics are a ChainUncertainty's (msd-ident flattens them into the fit).
    assert isinstance(fit, msd.ChainUncertainty)
    assert fit.names == ["m1", "m2", "c1", "c2", "k1", "k2"]
    r = fit.correlation
    assert r.shape == (6, 6) and r.dtype == np.float64
    np.testing.assert_allclose(np.diag(r), 1.0, rtol=1e-12)
    np.testing.assert_allclose(r, r.T, atol=1e-12)
    assert np.all(np.abs(r) <= 1.0 + 1e-12)
    # k2 and m1 move together (the first mode's frequency fixes k/m).
    assert r[0, 5] > 0.9


def test_known_masses_are_held(rig):
    force, outputs, _ = rig
    fit = msd.fit_chain(force, outputs, DT, TRUTH, force_at=2, sensors=SENSORS, known_masses=[2], passes=2)
    iv = fit.intervals
    assert iv.masses[1].value == 1.0 and iv.masses[1].standard_error == 0.0
    assert fit.degrees_of_freedom == 2 * 5000 - 5
    assert fit.names == ["m1", "c1", "c2", "k1", "k2"] and fit.correlation.shape == (5, 5)
    assert abs(iv.masses[0].value - 2.0) < 4 * iv.masses[0].standard_error


def test_a_delayed_sensor_is_fitted_with_its_delay():
    """One mass, its displacement read 6 ms late through a 50 Hz low-pass: the delay is
    found within 4 SE from a start at 0."""
    rng = np.random.default_rng(3)
    dt = 2e-3
    t = np.arange(7501) * dt
    force = 6.0 * (t >= 0.5) + np.where(t >= 9.0, 2.5 * np.sin(2 * np.pi * 1.4 * t), 3.0 * np.sin(np.pi * t))
    sensor = {"delay": 3 * dt, "low_pass": {"cutoff_hz": 50.0}}
    paper = {"masses": [2.5], "dampers": [1.8], "springs": [120.0]}
    y = msd.simulate_chain(paper, force, dt, sensors=[sensor])[0] + 2.5e-3 * rng.normal(size=t.size)
    fit = msd.fit_chain(
        force, y, dt, {"masses": [2.0], "dampers": [1.0], "springs": [100.0]},
        sensors=[{"estimate_delay": True, "low_pass": {"cutoff_hz": 50.0}}],
    )
    delay = fit.delays[0]
    assert delay is not None and abs(delay.value - 3 * dt) < 4 * delay.standard_error, delay
    assert abs(fit.intervals.dampers[0].value - 1.8) < 4 * fit.intervals.dampers[0].standard_error
    assert "delay of sensor 1 = " in repr(fit) and "delay of sensor 1" in fit._repr_html_()
    assert fit.names == ["m1", "c1", "k1", "delay1"]


def test_a_base_driven_chain_with_one_sensor_is_not_identified():
    """Scaling every m, c, k together leaves a base-driven chain's motion unchanged: no
    intervals, the lost combination in words, the modes still given."""
    rng = np.random.default_rng(5)
    truth = {"masses": [3.0, 2.0, 1.0], "dampers": [6.0, 4.0, 2.0], "springs": [3e4, 2e4, 1e4]}
    start = {"masses": [3.3, 1.9, 1.0], "dampers": [5.0, 5.0, 2.5], "springs": [3.2e4, 1.9e4, 1.05e4]}
    setup = {"masses": 3, "drive": "base_acceleration", "sensors": [{"at": 3, "quantity": "acceleration"}]}
    ground = rng.normal(size=5000)
    y = msd.simulate_chain(truth, ground, DT, setup=setup) + 0.01 * rng.normal(size=(1, 5000))
    fit = msd.fit_chain(ground, y, DT, start, setup=setup)
    assert fit.intervals is None and not fit.identified
    assert "scaled by one factor" in fit.unidentifiable[0]
    assert "not identified" in repr(fit) and "not identified" in fit._repr_html_()
    assert len(fit.modes) == 3 and all(m.natural_frequency_hz.standard_error > 0 for m in fit.modes)
    assert msd.ChainFit.from_dict(json.loads(json.dumps(fit.to_dict()))) == fit
    # The lost directions are found before the fit, each holding one parameter at its
    # guess (a mass first): the correlation is over the quantities still fitted.
    n = fit.correlation.shape[0]
    assert fit.correlation.shape == (n, n) and n < 9
    assert fit.parameters.masses[0] == start["masses"][0]


@pytest.mark.parametrize(
    "change, message",
    [
        ({"sensors": [SENSORS[0], {"at": 4, "quantity": "acceleration"}]}, r"sensors\[1\]\.at = 4: expected a mass from 1 to 2"),
        (
            {"sensors": [dict(SENSORS[0], low_pass={"cutoff_hz": -50.0}), SENSORS[1]]},
            r"sensors\[0\]\.low_pass\.cutoff_hz = -50: expected a finite frequency > 0",
        ),
        ({"sensors": [dict(SENSORS[0], low_pass={"cutoff_hz": np.inf}), SENSORS[1]]}, r"sensors\[0\]\.low_pass\.cutoff_hz = inf"),
        ({"sensors": [dict(SENSORS[0], place=1), SENSORS[1]]}, r"sensors\[0\]: unknown field `place`"),
        ({"sensors": [SENSORS[0], dict(SENSORS[1], quantity="jerk")]}, r"sensors\[1\]: unknown variant `jerk`"),
        ({"sensors": SENSORS[0]}, r"sensors = .*expected a list of sensors"),
        ({"force_at": 3}, r"force_at = 3: expected a mass from 1 to 2"),
        ({"drive": "ground"}, r"setup: unknown variant `ground`"),
        ({"setup": {"mases": 2}}, r"setup: unknown field `mases`"),
        ({"masses": 3}, r"masses has 2 values: expected one per mass \(3\)"),
        ({"known_masses": [5]}, r"known_masses contains 5"),
    ],
)
def test_bad_setups_name_the_key(rig, change, message):
    force, outputs, _ = rig
    keys = dict({"force_at": 2, "sensors": SENSORS}, **change)
    with pytest.raises(ValueError, match=message):
        msd.fit_chain(force, outputs, DT, GUESS, **keys)
    with pytest.raises(ValueError, match=message):
        msd.predict_chain(TRUTH, force, DT, [0.02, 0.02], **keys)
    if "known_masses" not in change:
        with pytest.raises(ValueError, match=message):
            msd.simulate_chain(TRUTH, force, DT, **keys)


def test_delays_are_shorter_than_the_record(rig):
    """A fit (and a prediction) needs a delay shorter than half the record; a simulation
    one shorter than the record (the channel reads 0 until the delay has passed)."""
    force, outputs, _ = rig
    late = [SENSORS[0], dict(SENSORS[1], delay=6.0)]
    half = r"sensors\[1\]\.delay = 6 s: expected less than half the record \(5 s\)"
    with pytest.raises(ValueError, match=half):
        msd.fit_chain(force, outputs, DT, GUESS, force_at=2, sensors=late)
    with pytest.raises(ValueError, match=half):
        msd.predict_chain(TRUTH, force, DT, [0.02, 0.02], force_at=2, sensors=late)
    y = msd.simulate_chain(TRUTH, force, DT, force_at=2, sensors=late)
    now = msd.simulate_chain(TRUTH, force, DT, force_at=2, sensors=SENSORS)
    assert np.all(y[1, :3000] == 0.0)
    np.testing.assert_allclose(y[1, 3000:], now[1, :2000], rtol=1e-9, atol=1e-12 * np.max(np.abs(now[1])))
    with pytest.raises(ValueError, match=r"sensors\[1\]\.delay = 20 s: expected less than the record \(10 s\)"):
        msd.simulate_chain(TRUTH, force, DT, force_at=2, sensors=[SENSORS[0], dict(SENSORS[1], delay=20.0)])


def test_bad_records_and_parameters(rig):
    force, outputs, _ = rig
    fit = lambda *a, **k: msd.fit_chain(*a, **dict({"force_at": 2, "sensors": SENSORS}, **k))  # noqa: E731
    with pytest.raises(ValueError, match="1 output series: expected one per sensor"):
        fit(force, outputs[0], DT, GUESS)
    with pytest.raises(ValueError, match="channel `mass 1 acceleration` has 4999 samples, `force` has 5000"):
        fit(force, outputs[:, :-1], DT, GUESS)
    bad = outputs.copy()
    bad[1, 7] = np.nan
    with pytest.raises(ValueError, match="output sample 7 is NaN"):
        fit(force, bad, DT, GUESS)
    with pytest.raises(ValueError, match="input sample 3 is inf"):
        fit(np.where(np.arange(force.size) == 3, np.inf, force), outputs, DT, GUESS)
    with pytest.raises(ValueError, match="dt = -0.002: expected a finite sampling interval > 0"):
        fit(force, outputs, -DT, GUESS)
    with pytest.raises(ValueError, match="dt = 'fast'"):
        fit(force, outputs, "fast", GUESS)
    with pytest.raises(ValueError, match="guess: missing field `springs`"):
        fit(force, outputs, DT, {"masses": [2.0, 1.0], "dampers": [4.0, 2.0]})
    with pytest.raises(ValueError, match=r"dampers\[1\] = -2: expected a finite number > 0"):
        fit(force, outputs, DT, dict(GUESS, dampers=[4.0, -2.0]))
    with pytest.raises(ValueError, match="guess: expected msd.ChainParameters"):
        fit(force, outputs, DT, [2.0, 1.0])
    # An empty record: msd-ident checks the drive before the record's length, so it
    # says that the (empty) drive is zero throughout.
    with pytest.raises(ValueError, match="too few samples|the drive is zero throughout"):
        fit([], [[], []], DT, GUESS)
    with pytest.raises(ValueError, match="too few samples"):
        fit(force[:3], outputs[:, :3], DT, GUESS)
    with pytest.raises(ValueError, match="the drive is zero throughout"):
        fit(np.zeros_like(force), outputs, DT, GUESS)
    with pytest.raises(ValueError, match=r"sensors\[1\]: its series has RMS 0"):
        fit(force, [outputs[0], np.zeros_like(force)], DT, GUESS)
    with pytest.raises(ValueError, match=r"sensors\[0\]: its series has RMS inf"):
        fit(force, [np.full_like(force, 1e300), outputs[1]], DT, GUESS)
    with pytest.raises(ValueError, match=r"masses = 9: expected 1 to 8"):
        msd.simulate_chain({k: [1.0] * 9 for k in ("masses", "dampers", "springs")}, force, DT)
    with pytest.raises(ValueError, match="parameters: unknown field `mass`"):
        msd.simulate_chain({"mass": [1.0], "dampers": [1.0], "springs": [1.0]}, force, DT)
    with pytest.raises(ValueError, match="known_masses"):
        fit(force, outputs, DT, GUESS, known_masses=None)


# ---------------------------------------------------------------- predict_chain


def standard_errors(result):
    """Every m, c, k's standard error, then each mode's fn and ζ."""
    iv = result.intervals
    out = [e.standard_error for e in iv.masses + iv.dampers + iv.springs]
    for mode in result.modes:
        out += [mode.natural_frequency_hz.standard_error, mode.damping_ratio.standard_error]
    return np.array(out)


def test_predict_chain_gives_the_fits_standard_errors(rig):
    """The prediction before the test (σ and the truth) and the fit's own report (σ̂ and
    the estimate) are the same linearisation: within 15 % (measured: 0.4 %). The
    prediction takes the drive as exact, so the fit compared is the white-noise one (the
    default also estimates the drive's noise; on this exact drive it finds a chance
    0.04 % of its rms, p = 0.2, which widens the intervals up to 14 %)."""
    force, outputs, _ = rig
    fit = msd.fit_chain(force, outputs, DT, GUESS, force_at=2, sensors=SENSORS, noise_model="white")
    plan = msd.predict_chain(TRUTH, force, DT, [0.02, 0.02], force_at=2, sensors=SENSORS)
    assert type(plan) is msd.ChainUncertainty and plan.identified and plan.unidentifiable == []
    predicted, reported = standard_errors(plan), standard_errors(fit)
    assert predicted.shape == (10,) and np.all(predicted > 0)
    ratio = predicted / reported
    print(f"predicted/reported standard errors: {ratio.min():.4f} … {ratio.max():.4f}")
    np.testing.assert_allclose(predicted, reported, rtol=0.15)
    # The intervals are about the truth (through its logarithm: to rounding); the
    # correlations are the fit's.
    iv = plan.intervals
    assert [e.value for e in iv.masses + iv.dampers + iv.springs] == pytest.approx(
        TRUTH.masses + TRUTH.dampers + TRUTH.springs, rel=1e-14
    )
    assert plan.names == fit.names
    np.testing.assert_allclose(plan.correlation, fit.correlation, atol=0.02)
    assert plan.degrees_of_freedom == fit.degrees_of_freedom
    assert plan.condition_number == pytest.approx(fit.condition_number, rel=0.05)
    assert plan.delays == [None, None] and plan.cutoffs == [None, None]
    # The same setup as a dict, the truth as a dict, σ as an array.
    again = msd.predict_chain(
        TRUTH.to_dict(), list(force), DT, np.array([0.02, 0.02]), setup={"masses": 2, "force_at": 2, "sensors": SENSORS}
    )
    assert again == plan


def test_predict_chain_scales_with_the_noise(rig):
    """σ(JᵀJ)⁻¹ᐟ²: twice the noise on every channel, twice every standard error."""
    force, _, _ = rig
    one = msd.predict_chain(TRUTH, force, DT, [0.02, 0.02], force_at=2, sensors=SENSORS)
    two = msd.predict_chain(TRUTH, force, DT, [0.04, 0.04], force_at=2, sensors=SENSORS)
    np.testing.assert_allclose(standard_errors(two), 2 * standard_errors(one), rtol=1e-9)


def test_predict_chain_result_object(rig):
    force, _, _ = rig
    plan = msd.predict_chain(TRUTH, force, DT, [0.02, 0.02], force_at=2, sensors=SENSORS)
    text = repr(plan)
    assert text == plan.summary.rstrip("\n")
    assert text.startswith("m1 = 2.000000") and "mode 2: fn = " in text
    assert text.splitlines()[-1].startswith("9994 degrees of freedom, condition number")
    assert "σ̂" not in text
    page = plan._repr_html_()
    assert page.startswith("<table") and "msd.predict_chain" in page and "k2 [N/m]" in page
    back = msd.ChainUncertainty.from_dict(json.loads(json.dumps(plan.to_dict(), allow_nan=False)))
    assert back == plan and repr(back) == repr(plan)
    assert back.intervals == plan.intervals and back.modes == plan.modes
    assert set(plan.to_dict()) == {
        "intervals", "unidentifiable", "modes", "delays", "cutoffs", "names", "correlation",
        "condition_number", "degrees_of_freedom", "summary",
    }
    assert plan.cutoffs == [None, None] and plan.intervals.ground_springs == []


def test_predict_chain_with_a_delay_and_known_masses():
    """One mass read 6 ms late through a 50 Hz low-pass, the delay to be estimated: its
    interval is predicted about the true delay, and close to what a fit of such a record
    reports (as the two-storey rig's, the same linearisation)."""
    rng = np.random.default_rng(3)
    dt = 2e-3
    t = np.arange(7501) * dt
    force = 6.0 * (t >= 0.5) + np.where(t >= 9.0, 2.5 * np.sin(2 * np.pi * 1.4 * t), 3.0 * np.sin(np.pi * t))
    paper = {"masses": [2.5], "dampers": [1.8], "springs": [120.0]}
    sensor = {"delay": 3 * dt, "estimate_delay": True, "low_pass": {"cutoff_hz": 50.0}}
    plan = msd.predict_chain(paper, force, dt, 2.5e-3, sensors=[sensor])
    delay = plan.delays[0]
    assert delay is not None and delay.value == pytest.approx(3 * dt, rel=1e-12) and delay.standard_error > 0
    assert plan.names == ["m1", "c1", "k1", "delay1"] and plan.correlation.shape == (4, 4)
    y = msd.simulate_chain(paper, force, dt, sensors=[sensor])[0] + 2.5e-3 * rng.normal(size=t.size)
    fit = msd.fit_chain(force, y, dt, {"masses": [2.0], "dampers": [1.0], "springs": [100.0]},
                        sensors=[dict(sensor, delay=None)])
    assert fit.delays[0].standard_error == pytest.approx(delay.standard_error, rel=0.15)
    np.testing.assert_allclose(standard_errors(plan), standard_errors(fit), rtol=0.15)
    # A known mass is not estimated.
    known = msd.predict_chain(paper, force, dt, [2.5e-3], sensors=[sensor], known_masses=[1])
    assert known.names == ["c1", "k1", "delay1"] and known.intervals.masses[0].standard_error == 0.0


def test_predict_chain_says_what_a_test_cannot_separate():
    """A base-driven chain read by one accelerometer: no intervals, the lost scale in
    words, the modes still predicted."""
    truth = {"masses": [3.0, 2.0, 1.0], "dampers": [6.0, 4.0, 2.0], "springs": [3e4, 2e4, 1e4]}
    setup = {"masses": 3, "drive": "base_acceleration", "sensors": [{"at": 3, "quantity": "acceleration"}]}
    ground = np.random.default_rng(5).normal(size=5000)
    plan = msd.predict_chain(truth, ground, DT, 0.01, setup=setup)
    assert plan.intervals is None and not plan.identified
    assert "scaled by one factor" in plan.unidentifiable[0]
    assert "not identified" in repr(plan) and "not identified" in plan._repr_html_()
    assert len(plan.modes) == 3 and all(m.natural_frequency_hz.standard_error > 0 for m in plan.modes)
    assert msd.ChainUncertainty.from_dict(json.loads(json.dumps(plan.to_dict()))) == plan


def test_a_ground_spring_and_a_filter_cutoff_fitted_and_predicted():
    """The two-storey rig with an extra 3 kN/m spring from mass 2 to the ground (guessed
    at 2 kN/m: estimated), and the same rig read through a 40 Hz first-order low-pass on
    mass 2 whose cut-off is estimated from 60 Hz: each within 4 SE of the truth, its name
    among the estimated quantities, its standard error predicted within 15 %."""
    rng = np.random.default_rng(21)
    force = rng.normal(size=5000)
    grounded = msd.ChainParameters(TRUTH.masses, TRUTH.dampers, TRUTH.springs, ground_springs=(0.0, 3e3))
    y = msd.simulate_chain(grounded, force, DT, force_at=2, sensors=SENSORS)
    y += 0.02 * rng.normal(size=y.shape)
    fit = msd.fit_chain(force, y, DT, dict(GUESS, ground_springs=[0.0, 2e3]), force_at=2, sensors=SENSORS)
    kg = fit.intervals.ground_springs
    assert fit.names == ["m1", "m2", "c1", "c2", "k1", "k2", "kg2"]
    assert kg[0].value == 0.0 and kg[0].standard_error == 0.0 and fit.intervals.ground_dampers == []
    assert abs(kg[1].value - 3e3) < 4 * kg[1].standard_error, kg[1]
    assert fit.parameters.ground_springs == (0.0, kg[1].value) and fit.parameters.ground_dampers == ()
    assert "kg2 = " in repr(fit) and "kg2 [N/m] (to the ground)" in fit._repr_html_()
    back = msd.ChainFit.from_dict(json.loads(json.dumps(fit.to_dict())))
    assert back == fit and back.intervals == fit.intervals
    assert msd.ChainParameters.from_dict(fit.parameters.to_dict()) == fit.parameters
    plan = msd.predict_chain(grounded, force, DT, [0.02, 0.02], force_at=2, sensors=SENSORS)
    assert plan.names == fit.names
    np.testing.assert_allclose(standard_errors(plan), standard_errors(fit), rtol=0.15)
    assert plan.intervals.ground_springs[1].standard_error == pytest.approx(kg[1].standard_error, rel=0.15)

    filtered = [SENSORS[0], dict(SENSORS[1], low_pass={"cutoff_hz": 40.0})]
    y = msd.simulate_chain(TRUTH, force, DT, force_at=2, sensors=filtered)
    y += 0.02 * rng.normal(size=y.shape)
    start = [SENSORS[0], dict(SENSORS[1], low_pass={"cutoff_hz": 60.0}, estimate_cutoff=True)]
    fit = msd.fit_chain(force, y, DT, GUESS, force_at=2, sensors=start)
    fc = fit.cutoffs[1]
    assert fit.cutoffs[0] is None and fc is not None and abs(fc.value - 40.0) < 4 * fc.standard_error, fc
    assert fit.names[-1] == "cutoff2" and "filter cut-off of sensor 2" in fit._repr_html_()
    plan = msd.predict_chain(TRUTH, force, DT, [0.02, 0.02], force_at=2,
                             sensors=[SENSORS[0], dict(SENSORS[1], low_pass={"cutoff_hz": 40.0}, estimate_cutoff=True)])
    assert plan.cutoffs[1].value == pytest.approx(40.0, rel=1e-12)
    assert plan.cutoffs[1].standard_error == pytest.approx(fc.standard_error, rel=0.15)
    with pytest.raises(ValueError, match=r"sensors\[1\]\.estimate_cutoff = true: expected a low_pass"):
        msd.fit_chain(force, y, DT, GUESS, force_at=2, sensors=[SENSORS[0], dict(SENSORS[1], estimate_cutoff=True)])
    with pytest.raises(ValueError, match=r"ground_springs has 1 values: expected none or one per mass \(2\)"):
        msd.predict_chain(dict(GUESS, ground_springs=[1.0]), force, DT, [0.02, 0.02], force_at=2, sensors=SENSORS)


@pytest.mark.parametrize(
    "noise, message",
    [
        ([0.02], r"1 noise levels: expected one per sensor \(2\)"),
        (0.02, r"1 noise levels: expected one per sensor \(2\)"),
        ([0.02, 0.02, 0.02], r"3 noise levels: expected one per sensor \(2\)"),
        ([0.02, 0.0], r"sensors\[1\] noise σ = 0: expected a finite number > 0"),
        ([-0.02, 0.02], r"sensors\[0\] noise σ = -0.02: expected a finite number > 0"),
        ([0.02, np.nan], r"sensors\[1\] noise σ = NaN: expected a finite number > 0"),
        ([0.02, np.inf], r"sensors\[1\] noise σ = inf: expected a finite number > 0"),
        (["0.02", "0.02"], r"noise: expected real numbers"),
        ([[0.02, 0.02]], r"noise: expected a 1-D array"),
        (None, r"noise: missing or None \(expected a 1-D array of numbers\)"),
        ([0.02, 1e-310], r"sensors\[1\] noise σ = 1e-310: expected at least 1e-300"),
        ([1e-120, 0.02], r"sensors\[0\] noise σ = 1e-120 beside an RMS reading of .*: expected a signal-to-noise ratio below 1e100"),
    ],
)
def test_predict_chain_refuses_bad_noise(rig, noise, message):
    force, _, _ = rig
    with pytest.raises(ValueError, match=message):
        msd.predict_chain(TRUTH, force, DT, noise, force_at=2, sensors=SENSORS)


def test_predict_chain_bad_input(rig):
    force, _, _ = rig
    predict = lambda *a, **k: msd.predict_chain(*a, **dict({"force_at": 2, "sensors": SENSORS}, **k))  # noqa: E731
    with pytest.raises(ValueError, match="too few samples"):
        predict(TRUTH, force[:3], DT, [0.02, 0.02])
    with pytest.raises(ValueError, match="input sample 3 is NaN"):
        predict(TRUTH, np.where(np.arange(force.size) == 3, np.nan, force), DT, [0.02, 0.02])
    with pytest.raises(ValueError, match="invalid dt = 0"):
        predict(TRUTH, force, 0.0, [0.02, 0.02])
    with pytest.raises(ValueError, match=r"masses\[1\] = -1: expected a finite number > 0"):
        predict(dict(TRUTH.to_dict(), masses=[2.0, -1.0]), force, DT, [0.02, 0.02])
    with pytest.raises(ValueError, match="truth: expected msd.ChainParameters"):
        predict([2.0, 1.0], force, DT, [0.02, 0.02])
    with pytest.raises(ValueError, match="truth: missing field `springs`"):
        predict({"masses": [2.0, 1.0], "dampers": [4.0, 2.0]}, force, DT, [0.02, 0.02])
    with pytest.raises(ValueError, match="known_masses contains 3: expected masses from 1 to 2"):
        predict(TRUTH, force, DT, [0.02, 0.02], known_masses=[3])
    with pytest.raises(ValueError, match="known_masses = None"):
        predict(TRUTH, force, DT, [0.02, 0.02], known_masses=None)
    # What fit_chain would refuse in the record (checked by the binding before
    # msd-ident's predict_chain, which would report a drive of zeros as not identified and
    # not return from readings that overflow).
    with pytest.raises(ValueError, match="the drive is zero throughout"):
        predict(TRUTH, np.zeros_like(force), DT, [0.02, 0.02])
    with pytest.raises(ValueError, match=r"sensors\[0\]: its noise-free reading has RMS \d.*e\d{3}: expected a test"):
        predict(TRUTH, force * 1e200, DT, [0.02, 0.02])
    with pytest.raises(ValueError, match=r"sensors\[0\]: its noise-free reading overflows \(sample \d+ is (NaN|inf|-inf)\)"):
        predict(TRUTH, force * (1e307 / np.max(np.abs(force))), DT, [0.02, 0.02])
    with pytest.raises(ValueError, match=r"sensors\[0\]: its noise-free reading has RMS 0e0"):
        # The force comes in the last 0.8 s; the sensor reads 4.9 s late.
        predict(TRUTH, np.where(np.arange(force.size) >= 4600, force, 0.0), DT, [0.02], sensors=[{"at": 1, "delay": 4.9}])


def test_predict_chain_returns_where_the_sensitivities_overflow():
    """m = 1e128, c = 1e111, k = 1e-125: the readings are finite (the binding's checks
    pass them), the exact sensitivities are not (fit_chain from this point says so at
    once). Run in a subprocess with a deadline: it must return or raise within 20 s."""
    import subprocess
    import sys

    code = (
        "import numpy as np, msd\n"
        "try:\n"
        "    msd.predict_chain({'masses': [1e128], 'dampers': [1e111], 'springs': [1e-125]},"
        " np.sin(np.arange(64.0)), 1e-3, 1.0)\n"
        "except ValueError:\n"
        "    pass\n"
    )
    try:
        done = subprocess.run([sys.executable, "-c", code], timeout=20, capture_output=True, text=True)
    except subprocess.TimeoutExpired:
        pytest.fail("predict_chain did not return within 20 s")
    assert done.returncode == 0, done.stderr
