"""msd.estimate against the Rust workflow on the same arrays, and the result object."""

import json
import threading
import time

import numpy as np
import pytest

import msd
from conftest import write_csv

FIELDS = ("mass", "damping", "stiffness", "natural_frequency_hz", "damping_ratio")


def lab_config(tmp_path, paper, estimation: str):
    """A measured-data config over the paper's two records in one CSV file, and the
    estimation range the Rust run reports."""
    i, v = paper["identification"], paper["validation"]
    t = np.concatenate([i["t"], v["t"][1:] + i["t"][-1]])
    force = np.concatenate([i["force"], v["force"][1:]])
    x = np.concatenate([i["displacement"], v["displacement"][1:]])
    write_csv(tmp_path / "rec.csv", {"t": t, "force": force, "displacement": x})
    (tmp_path / "lab.toml").write_text(
        f"""name = "lab"
seed = 1
[data]
path = "rec.csv"
input = "force"
output = "displacement"
time = "t"
[data.estimation]
time = [0.0, 15.0]
[data.validation]
time = [15.0, 30.0]
[estimation]
{estimation}
[monte_carlo]
enabled = false
"""
    )
    return t, force, x


@pytest.mark.parametrize(
    "estimation, preset",
    [
        ('method = "levenberg_marquardt"', "default"),
        (
            'method = "nelder_mead"\nbackend = { kind = "ode45", rel_tol = 1e-6, abs_tol = 1e-9 }\n'
            "initial_guess = { mass = 2.0, damping = 1.0, stiffness = 100.0 }",
            "paper",
        ),
    ],
)
def test_estimate_equals_the_rust_run_bit_for_bit(tmp_path, paper, estimation, preset):
    t, force, x = lab_config(tmp_path, paper, estimation)
    results = msd.run(tmp_path / "lab.toml", out=tmp_path / "out")
    start, end = results["data"]["source"]["estimation_range"]
    fit = msd.estimate(t[start:end], force[start:end], x[start:end], preset=preset)
    rust = results["estimate"]
    for name in FIELDS:
        ours = getattr(fit, name)
        assert ours.value == rust[name]["value"], name
        assert ours.standard_error == rust[name]["standard_error"], name
        assert list(ours.ci95) == rust[name]["ci95"], name
    assert fit.iterations == rust["iterations"]
    assert fit.evaluations == rust["evaluations"]
    assert fit.method == rust["method"]
    assert fit.converged and rust["converged"]
    # the validation stage: the estimate's prediction of the second record
    start, end = results["data"]["source"]["validation_range"]
    validation = msd.validate(
        fit.parameters, t[start:end], force[start:end], x[start:end], backend=results["validation"]["backend"]
    )
    for key in ("r2", "fit_percent", "residual_rms"):
        assert validation.fit[key] == results["validation"][key], key
    assert validation.residual_analysis["ljung_box"]["q"] == results["validation"]["residuals"]["ljung_box"]["q"]
    assert "validation on" in repr(validation)


def test_paper_preset_is_the_papers_method(ident):
    fit = msd.estimate(*ident, preset="paper")
    assert fit.method == "nelder_mead"
    assert fit.data["backend"]["kind"] == "ode45"
    assert fit.data["initial_guess"][0] == {"mass": 2.0, "damping": 1.0, "stiffness": 100.0}
    for name, truth in (("mass", 2.5), ("damping", 1.8), ("stiffness", 120.0)):
        q = getattr(fit, name)
        assert abs(q.value - truth) < 4 * q.standard_error, (name, q)


def test_options_replace_the_presets(ident):
    fixed = msd.estimate(*ident, fixed={"mass": 2.5})
    assert fixed.mass.value == 2.5
    assert fixed.mass.standard_error == 0.0 or np.isnan(fixed.mass.standard_error)
    guess = msd.estimate(*ident, initial_guess=msd.Plant(2.0, 1.0, 100.0))
    same = msd.estimate(*ident, preset="fast")
    assert guess.stiffness.value == same.stiffness.value
    exact = msd.estimate(*ident, preset="paper", backend="exact")
    assert exact.data["backend"]["kind"] == "exact" and exact.method == "nelder_mead"


def test_result_object(ident):
    fit = msd.estimate(*ident)
    assert fit.mass.ci95[0] < fit.mass.value < fit.mass.ci95[1]
    assert fit.parameters.mass == fit.mass.value
    assert fit.r_squared > 0.99
    assert fit.model_output.shape == ident[0].shape and fit.model_output.dtype == np.float64
    np.testing.assert_array_equal(fit.residuals, ident[2] - fit.model_output)
    text = repr(fit)
    assert "m = " in text and "95 % CI" in text and "R²" in text
    page = fit._repr_html_()
    assert page.startswith("<table") and "k [N/m]" in page and f"{fit.stiffness.value:.6g}" in page
    assert fit.covariance.shape == (3, 3)


def test_to_dict_json_round_trip(ident):
    fit = msd.estimate(*ident)
    text = json.dumps(fit.to_dict(), allow_nan=False)
    back = msd.Estimate.from_dict(json.loads(text))
    assert back == fit
    assert back.mass == fit.mass
    np.testing.assert_array_equal(back.model_output, fit.model_output)
    assert repr(back) == repr(fit)


def test_simulate_is_the_fits_model_output(ident):
    t, force, x = ident
    fit = msd.estimate(t, force, x)
    again = msd.simulate(fit.parameters, t, force)
    np.testing.assert_array_equal(again, fit.model_output)


def test_simulate_against_scipy(ident):
    from scipy.integrate import solve_ivp

    t, force, _ = ident
    m, c, k = 2.5, 1.8, 120.0
    x = msd.simulate({"mass": m, "damping": c, "stiffness": k}, t, force, backend="ode45")
    f = lambda s: np.interp(s, t, force)  # noqa: E731 (linear between samples, as msd's ode45)
    sol = solve_ivp(
        lambda s, y: [y[1], (f(s) - c * y[1] - k * y[0]) / m],
        (t[0], t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-12, max_step=0.002,
    )
    assert np.max(np.abs(x - sol.y[0])) < 1e-6
    exact = msd.simulate((m, c, k), t, force, backend={"kind": "exact", "hold": "first"})
    assert np.max(np.abs(exact - sol.y[0])) < 1e-6


def test_simulate_initial_state(ident):
    t, force, _ = ident
    x = msd.simulate((2.5, 1.8, 120.0), t, np.zeros_like(t), initial_state=(0.01, 0.0))
    assert x[0] == 0.01 and abs(x[-1]) < 0.01


def test_the_gil_is_released(ident):
    """A thread keeps running while estimations run in another."""
    counts = []
    done = threading.Event()

    def work():
        for _ in range(20):
            msd.estimate(*ident, preset="paper")
        done.set()

    worker = threading.Thread(target=work)
    start = time.perf_counter()
    worker.start()
    while not done.is_set():
        counts.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    elapsed = time.perf_counter() - start
    # With the GIL held for each whole estimation, the loop could run only between
    # estimations (about 40 ticks at most); released, it ticks every millisecond or so
    # through 20 estimations of 10 ms or more.
    assert len(counts) > 100, (len(counts), elapsed)
