"""msd.simulate_chain and msd.fit_chain: a simulated two-storey rig fitted back, the
result object, the setup given as a dict or by keys, and bad input named by its key."""

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
        assert len(mode.shape) == 2 and max(abs(s.value) for s in mode.shape) == 1.0
    # σ̂ per channel: 0.02 within 5 % (5000 residuals each: SD 1 %).
    assert fit.noise.shape == (2,)
    np.testing.assert_allclose(fit.noise, 0.02, rtol=0.05)
    assert fit.delays == [None, None]
    assert fit.degrees_of_freedom == 2 * 5000 - 6
    assert fit.exit in ("FTolerance", "XTolerance", "FAndXTolerance", "Gradient")
    assert fit.evaluations > 0 and 1.0 <= fit.condition_number < 1e8
    assert fit.parameters.masses == tuple(e.value for e in iv.masses)


@pytest.mark.xfail(reason="msd-ident: from this guess about 3 records in 100 (seeds 4, 38, 64) end with a "
                   "damper at 0 and σ̂ far above the noise, reported as not identified", strict=False)
def test_a_record_where_the_fit_stalls_on_a_vanishing_damper():
    force, outputs = rig_record(4)
    fit = msd.fit_chain(force, outputs, DT, GUESS, force_at=2, sensors=SENSORS)
    assert fit.identified and np.all(np.array(fit.parameters.dampers) > 0)
    np.testing.assert_allclose(fit.noise, 0.02, rtol=0.05)


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
    assert msd.ChainParameters.from_dict(fit.parameters.to_dict()) == fit.parameters


def test_known_masses_are_held(rig):
    force, outputs, _ = rig
    fit = msd.fit_chain(force, outputs, DT, TRUTH, force_at=2, sensors=SENSORS, known_masses=[2], passes=2)
    iv = fit.intervals
    assert iv.masses[1].value == 1.0 and iv.masses[1].standard_error == 0.0
    assert fit.degrees_of_freedom == 2 * 5000 - 5
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


@pytest.mark.parametrize(
    "change, message",
    [
        ({"sensors": [SENSORS[0], {"at": 4, "quantity": "acceleration"}]}, r"sensors\[1\]\.at = 4: expected a mass from 1 to 2"),
        (
            {"sensors": [dict(SENSORS[0], low_pass={"cutoff_hz": -50.0}), SENSORS[1]]},
            r"sensors\[0\]\.low_pass\.cutoff_hz = -50: expected a finite frequency > 0",
        ),
        (
            {"sensors": [dict(SENSORS[0], delay=20.0), SENSORS[1]]},
            r"sensors\[0\]\.delay = 20 s: expected less than half the record \(5 s\)",
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
    if "known_masses" not in change:
        with pytest.raises(ValueError, match=message):
            msd.simulate_chain(TRUTH, force, DT, **keys)


def test_bad_records_and_parameters(rig):
    force, outputs, _ = rig
    fit = lambda *a, **k: msd.fit_chain(*a, **dict({"force_at": 2, "sensors": SENSORS}, **k))  # noqa: E731
    with pytest.raises(ValueError, match="1 output series: expected one per sensor"):
        fit(force, outputs[0], DT, GUESS)
    with pytest.raises(ValueError, match="length mismatch"):
        fit(force, outputs[:, :-1], DT, GUESS)
    bad = outputs.copy()
    bad[1, 7] = np.nan
    with pytest.raises(ValueError, match="output sample 7 is NaN"):
        fit(force, bad, DT, GUESS)
    with pytest.raises(ValueError, match="input sample 3 is inf"):
        fit(np.where(np.arange(force.size) == 3, np.inf, force), outputs, DT, GUESS)
    with pytest.raises(ValueError, match="invalid dt = -0.002"):
        fit(force, outputs, -DT, GUESS)
    with pytest.raises(ValueError, match="dt = 'fast'"):
        fit(force, outputs, "fast", GUESS)
    with pytest.raises(ValueError, match="guess: missing field `springs`"):
        fit(force, outputs, DT, {"masses": [2.0, 1.0], "dampers": [4.0, 2.0]})
    with pytest.raises(ValueError, match=r"dampers\[1\] = -2: expected a finite number > 0"):
        fit(force, outputs, DT, dict(GUESS, dampers=[4.0, -2.0]))
    with pytest.raises(ValueError, match="guess: expected msd.ChainParameters"):
        fit(force, outputs, DT, [2.0, 1.0])
    with pytest.raises(ValueError, match="too few samples"):
        fit([], [[], []], DT, GUESS)
    with pytest.raises(ValueError, match=r"masses = 9: expected 1 to 8"):
        msd.simulate_chain({k: [1.0] * 9 for k in ("masses", "dampers", "springs")}, force, DT)
    with pytest.raises(ValueError, match="parameters: unknown field `mass`"):
        msd.simulate_chain({"mass": [1.0], "dampers": [1.0], "springs": [1.0]}, force, DT)
    with pytest.raises(ValueError, match="known_masses"):
        fit(force, outputs, DT, GUESS, known_masses=None)
