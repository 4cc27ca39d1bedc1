"""The setup fits (fit_records, free_decay, dynamometer) against the Rust run of the
shipped configs, on the records those runs write."""

import json

import numpy as np
import pytest

import msd


def csv(path):
    return np.genfromtxt(path, delimiter=",", names=True)


@pytest.fixture(scope="module")
def free_decay_run(root, tmp_path_factory):
    out = tmp_path_factory.mktemp("free-decay") / "out"
    results = msd.run(root / "configs/free-decay.toml", out=out)
    return results, csv(out / "record-1.csv")


def test_fit_records_equals_the_rust_setup_run(free_decay_run):
    results, record = free_decay_run
    fit = msd.fit_records(
        {"t": record["t"], "displacement": record["displacement"]}, drive="none", known={"mass": 2.5}
    )
    rust = results["estimate"]
    for name in ("damping", "stiffness", "natural_frequency_hz", "damping_ratio"):
        ours = getattr(fit, name)
        assert ours.value == rust[name]["value"], name
        assert list(ours.ci95) == rust[name]["ci95"], name
    assert fit.mass.value == 2.5 and fit.mass.standard_error == 0.0
    page = fit._repr_html_()
    assert page.startswith("<table") and "c [N·s/m]" in page and f"{fit.damping.value:.6g}" in page
    assert json.loads(json.dumps(fit.to_dict()))["damping"]["value"] == fit.damping.value


def test_fit_records_validates_a_single_record_on_its_held_out_end(free_decay_run):
    results, record = free_decay_run
    fit = msd.fit_records(
        {"t": record["t"], "displacement": record["displacement"]}, drive="none", known={"mass": 2.5}
    )
    held = fit.validation
    assert "last 20 %" in held["source"]
    channel = held["predictions"][0]["channels"][0]
    assert channel["fit"]["samples"] == round(0.2 * len(record["t"]))
    # The same numbers as the Rust run of the same config.
    rust = results["validation"]["predictions"][0]["channels"][0]["fit"]
    assert channel["fit"]["r2"] == rust["r2"]
    off = msd.fit_records(
        {"t": record["t"], "displacement": record["displacement"]}, drive="none", known={"mass": 2.5}, hold_out=0
    )
    assert off.validation is None


def test_free_decay_equals_the_rust_setup_run(free_decay_run):
    results, record = free_decay_run
    fd = msd.free_decay(record["t"], record["displacement"], known_mass=2.5)
    assert fd.data["classroom"] == results["free_decay"]["classroom"]
    assert abs(fd.data["damping_ratio"]["value"] / results["estimate"]["damping_ratio"]["value"] - 1) < 1e-9
    assert "classroom" in repr(fd) and "<pre>" in fd._repr_html_()
    with pytest.raises(ValueError, match="not both"):
        msd.free_decay(record["t"], record["displacement"], known_mass=2.5, known_stiffness=120.0)
    with pytest.raises(ValueError, match="known mass"):
        msd.free_decay(record["t"], record["displacement"], known_mass=-1.0)


def test_fit_records_with_a_force_and_two_sensors(paper):
    d = paper["identification"]
    t, force = d["t"], d["force"]
    rng = np.random.default_rng(2)
    velocity = np.gradient(d["true_displacement"], t) + 1e-3 * rng.normal(size=t.size)
    fit = msd.fit_records(
        {"t": t, "force": force, "laser": d["displacement"], "tacho": velocity},
        responses={"laser": "displacement", "tacho": ("velocity", "absolute")},
    )
    for name, truth in (("mass", 2.5), ("damping", 1.8), ("stiffness", 120.0)):
        q = getattr(fit, name)
        assert abs(q.value - truth) < 5 * q.standard_error + 0.01 * truth, (name, q)
    assert len(fit.data["noise"]) == 2
    with pytest.raises(ValueError, match="no channel 'laser'"):
        msd.fit_records({"t": t, "force": force}, responses={"laser": "displacement"})
    with pytest.raises(ValueError, match="unknown variant `position`"):
        msd.fit_records({"t": t, "force": force, "x": d["displacement"]}, responses={"x": "position"})
    with pytest.raises(ValueError, match="needs its samples"):
        msd.fit_records({"t": t, "displacement": d["displacement"]})


def test_dynamometer_equals_the_rust_machine_run(root, tmp_path):
    out = tmp_path / "machine"
    results = msd.run(root / "configs/damper-test-machine.toml", out=out)
    conditions = []
    for c in results["dynamometer"]["conditions"]:
        rec = csv(out / f"{c['name']}.csv")
        conditions.append(
            {"name": c["name"], "t": rec["t"], "displacement": rec["stroke"], "force": rec["force"],
             "frequency_hz": c["frequency_hz"]}
        )
    fit = msd.dynamometer(conditions)
    for ours, theirs in zip(fit.data["conditions"], results["dynamometer"]["conditions"]):
        assert ours["equivalent_damping"] == theirs["equivalent_damping"], ours["name"]
        assert ours["storage_stiffness"] == theirs["storage_stiffness"], ours["name"]
    assert fit.data["best"] == results["dynamometer"]["best"]
    with pytest.raises(ValueError, match="give 'dt' or 't'"):
        msd.dynamometer([{"displacement": [0.0], "force": [0.0]}])
    bad = dict(conditions[0], t=conditions[0]["t"] ** 1.01)
    with pytest.raises(ValueError, match="time stamps are not uniform"):
        msd.dynamometer([bad])
    by_dt = [dict({k: v for k, v in c.items() if k != "t"}, dt=0.001) for c in conditions]
    c_eq = msd.dynamometer(by_dt).data["conditions"][0]["equivalent_damping"]
    assert c_eq == pytest.approx(fit.data["conditions"][0]["equivalent_damping"], rel=1e-12)
