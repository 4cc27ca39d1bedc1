"""msd.init: a config for the user's own file, written beside it, that msd.run runs.

The record is made outside this project (scipy's DOP853 on the continuous force), as a
lab's logger writes it: two metadata lines, a units line, semicolons and decimal commas,
the accelerometer in g. "Holds the truth" is |estimate - truth| <= 4 standard errors (a
correct interval misses that with probability 6e-5)."""

import math
import os

import numpy as np
import pytest

import msd

scipy_integrate = pytest.importorskip("scipy.integrate")

M, C, K = 1.7, 3.1, 950.0


def _shaker_csv(path, seed=5):
    fs, duration = 1000.0, 12.0
    t = np.arange(0.0, duration, 1.0 / fs)
    rng = np.random.default_rng(seed)
    lines = np.arange(0.2, 15.01, 0.2)
    phases = rng.uniform(0.0, 2.0 * np.pi, lines.size)
    amplitude = 5.0 * math.sqrt(2.0 / lines.size)

    def force(tt):
        return amplitude * np.sum(np.sin(2.0 * np.pi * lines * tt + phases))

    sol = scipy_integrate.solve_ivp(
        lambda tt, y: [y[1], (force(tt) - C * y[1] - K * y[0]) / M],
        (0.0, duration),
        [0.0, 0.0],
        t_eval=t,
        method="DOP853",
        rtol=1e-10,
        atol=1e-12,
    )
    f = np.array([force(tt) for tt in t])
    a = (f - C * sol.y[1] - K * sol.y[0]) / M + rng.normal(0.0, 0.05, t.size)
    with open(path, "w", encoding="utf-8") as out:
        out.write("Rig 2 shaker test\nOperator: A. N. Other\ntime;force;accel\ns;N;g\n")
        for row in zip(t, f, a / 9.80665):
            out.write(("%.4f;%.6f;%.7e\n" % row).replace(".", ","))


def test_init_writes_a_config_that_runs_and_holds_the_truth(tmp_path):
    data = tmp_path / "shaker.csv"
    _shaker_csv(data)
    config = msd.init(data)
    assert config == os.fspath(tmp_path / "shaker.toml")
    text = open(config, encoding="utf-8").read()
    assert "scale = 9.80665" in text and 'decimal = ","' in text
    results = msd.run(config, out=tmp_path / "out")
    truth = {
        "mass": M,
        "damping": C,
        "stiffness": K,
        "natural_frequency_hz": math.sqrt(K / M) / (2.0 * math.pi),
        "damping_ratio": C / (2.0 * math.sqrt(K * M)),
    }
    for name, value in truth.items():
        q = results["estimate"][name]
        assert abs(q["value"] - value) <= 4.0 * q["standard_error"], (name, q, value)
    with pytest.raises(ValueError, match="overwrite"):
        msd.init(data)


def test_init_asks_for_the_columns_it_cannot_place(tmp_path):
    data = tmp_path / "daq.csv"
    data.write_text("t,ch1,ch2\n" + "".join(f"{i / 100},{i % 7},{i % 5}\n" for i in range(300)))
    with pytest.raises(ValueError, match="--input"):
        msd.init(data)
    assert not (tmp_path / "daq.toml").exists()


def test_an_acceleration_given_to_estimate_points_to_fit_records(tmp_path):
    """Issue 45: a newcomer hands msd.estimate an accelerometer's record; the error says
    estimate takes a displacement and names the call that fits an acceleration, and that
    call recovers the rig."""
    data = tmp_path / "shaker.csv"
    _shaker_csv(data)
    rows = [line.replace(",", ".").split(";") for line in data.read_text().splitlines()[4:]]
    t, force, accel_g = (np.array([float(r[k]) for r in rows]) for k in range(3))
    accel = accel_g * 9.80665
    with pytest.raises(msd.IdentificationError, match="fit_records"):
        msd.estimate(t, force, accel)
    fit = msd.fit_records({"t": t, "force": force, "acceleration": accel})
    for q, value in ((fit.mass, M), (fit.damping, C), (fit.stiffness, K)):
        assert abs(q.value - value) <= 4.0 * q.standard_error, (q, value)


def test_a_record_without_t_names_the_missing_key_and_its_keys():
    with pytest.raises(ValueError, match=r"records\[0\]: no key 't'.*'time', 'force'"):
        msd.fit_records({"time": np.arange(10.0), "force": np.zeros(10), "displacement": np.zeros(10)})


def test_the_namespace_shows_the_api_only():
    names = dir(msd)
    assert "fit_records" in names and "init" in names
    for imported in ("Any", "Dict", "np", "os", "rows", "vector"):
        assert imported not in names


def test_the_correlation_of_a_records_fit_is_labelled_and_round_trips():
    p = msd.paper_data(1)["identification"]
    fit = msd.fit_records({"t": p["t"], "force": p["force"], "displacement": p["displacement"]})
    c = fit.correlation
    assert list(c) == fit.data["identifiable"]
    assert c["mass"]["mass"] == pytest.approx(1.0)
    assert c["mass"]["stiffness"] == pytest.approx(c["stiffness"]["mass"], abs=1e-12)
    d = fit.to_dict()
    assert d["correlation"]["damping"]["natural_frequency_hz"] == c["damping"]["natural_frequency_hz"]
    assert type(fit).from_dict(d) == fit


def test_a_records_fit_carries_its_model_and_residuals_and_plots():
    p = msd.paper_data(1)["identification"]
    fit = msd.fit_records({"t": p["t"], "force": p["force"], "displacement": p["displacement"]})
    model, residual = fit.model("displacement"), fit.residual()
    np.testing.assert_allclose(model + residual, p["displacement"], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(fit.time(), p["t"])
    # The model is the plant's noise-free response: its error against the truth is far
    # below the noise (σ = 2.5 mm), the residual's rms about the noise.
    assert np.sqrt(np.mean((model - p["true_displacement"]) ** 2)) < 0.1 * 2.5e-3
    assert abs(np.std(residual) / 2.5e-3 - 1.0) < 0.05
    with pytest.raises(KeyError, match="'displacement'"):
        fit.model("acceleration")
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    fig = fit.plot()
    assert len(fig.axes) == 2 and fig.axes[1].get_ylabel() == "residual [m]"


def test_simulate_gives_every_quantity():
    """The velocity and acceleration of the exact simulator against the displacement's
    own: the acceleration is the equation of motion's value, (F - c v - k x) / m, and the
    velocity integrates to the displacement (within the trapezoid rule's error bound)."""
    t = np.arange(0.0, 4.0, 1e-3)
    force = np.sin(2 * np.pi * 1.3 * t) + 0.5 * np.sin(2 * np.pi * 5.1 * t)
    plant = (1.7, 3.1, 950.0)
    motion = msd.simulate(plant, t, force, quantity="all")
    x, v, a = motion["displacement"], motion["velocity"], motion["acceleration"]
    np.testing.assert_allclose(x, msd.simulate(plant, t, force), rtol=0, atol=1e-12)
    np.testing.assert_allclose(a, (force - 3.1 * v - 950.0 * x) / 1.7, rtol=0, atol=1e-9)
    integrated = np.concatenate(([0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * 1e-3)))
    jerk = np.max(np.abs(np.diff(a))) / 1e-3
    # The trapezoid rule's global error bound, (T / 12)·dt²·max|v″|, with 10 % for the
    # jerk's estimate from differences.
    assert np.max(np.abs(integrated - x)) <= 1.1 * t[-1] / 12 * 1e-3 ** 2 * jerk
    np.testing.assert_array_equal(msd.simulate(plant, t, force, quantity="velocity"), v)
    with pytest.raises(ValueError, match="quantity = 'jerk'"):
        msd.simulate(plant, t, force, quantity="jerk")


def test_an_estimate_is_labelled_and_plots():
    p = msd.paper_data(1)["identification"]
    e = msd.estimate(p["t"], p["force"], p["displacement"])
    assert list(e.correlation) == list(e.data["uncertainty"]["names"])
    assert e.correlation["mass"]["mass"] == pytest.approx(1.0)
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    fig = e.plot()
    assert [a.get_ylabel() for a in fig.axes] == ["displacement [m]", "residual [m]"]
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), p["displacement"], rtol=0, atol=1e-12)
    assert type(e).from_dict(e.to_dict()) == e
