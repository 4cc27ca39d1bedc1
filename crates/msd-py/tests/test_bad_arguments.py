"""Issue 46 §7: a bad argument to any public function raises ValueError or TypeError (or
one of the package's documented subclasses: IdentificationError, MissingKeyError,
OutOfRangeError), never OverflowError, KeyError, IndexError or RuntimeError, and the
message names the argument. Integer arguments, direct or inside options, are refused
the same way whether negative or beyond 64 bits; NaN in any array names the array."""

import re

import numpy as np
import pytest

import msd
from msd import _msd

N = 256
DT = 0.01
T = np.arange(N) * DT
RNG = np.random.default_rng(7)
FORCE = RNG.normal(size=N)
X = RNG.normal(size=N) * 1e-3
RECORD = {"t": T, "force": FORCE, "displacement": X}
CHAIN = {"masses": [1.0], "dampers": [0.5], "springs": [100.0]}
Y = RNG.normal(size=(N, 3))
FREQUENCY = np.linspace(1.0, 50.0, 64)
H = 1.0 / (100.0 - (2 * np.pi * FREQUENCY) ** 2 + 2j * np.pi * FREQUENCY)
STROKES = [{"dt": DT, "stroke": np.sin(T * 5), "force": np.cos(T * 5)}]
CONDITIONS = [{"dt": DT, "displacement": np.sin(T * 5), "force": np.cos(T * 5)}]
UFF_58 = {"type": 58, "x": FREQUENCY, "data": H}
UFF_55 = {"type": 55, "node_nums": [1, 2], "r1": np.ones(2), "r2": np.ones(2), "r3": np.ones(2)}


@pytest.fixture(autouse=True)
def in_tmp_path(tmp_path, monkeypatch):
    """Nothing a call might write (a UFF file, a result folder) lands in the checkout."""
    monkeypatch.chdir(tmp_path)


def fitted():
    """A fit_records result of one record (built from its dict: no fit needed)."""
    return msd.RecordsFit(
        {"records": [{"t": T, "channels": [{"channel": "displacement", "model": X, "residual": X * 0}]}]}
    )


def modal_set(node=1, direction=1):
    return msd.modal_fit(FREQUENCY, [H, H], dofs=[((node, direction), (1, 1)), ((2, 1), (1, 1))])


# Every integer argument of the public API: (id, call taking the value, the name the
# message must give). Direct arguments, keys of options dicts, items of lists, DOFs.
INTEGER_ARGUMENTS = [
    ("frf segment_length", lambda v: msd.frf(T, FORCE, X, segment_length=v), "segment_length"),
    ("modal_fit mode_count", lambda v: msd.modal_fit(FREQUENCY, H, mode_count=v), "mode_count"),
    ("modal_fit orders", lambda v: msd.modal_fit(FREQUENCY, H, orders=[v, 20]), "orders"),
    ("modal_fit order_step", lambda v: msd.modal_fit(FREQUENCY, H, order_step=v), "order_step"),
    ("modal_fit dofs node", lambda v: modal_set(node=v), r"dofs\[0\] response node"),
    # −1 is a direction (UFF's negative x): −7 instead.
    ("modal_fit dofs direction", lambda v: modal_set(direction=-7 if v == -1 else v), r"dofs\[0\] response direction"),
    ("oma references", lambda v: msd.oma(Y, 100.0, references=[0, v]), r"references\[1\]"),
    ("oma dofs node", lambda v: msd.oma(Y, 100.0, dofs=[(1, 1), (v, 1), (3, 1)]), r"dofs\[1\] node"),
    ("oma dofs direction", lambda v: msd.oma(Y, 100.0, dofs=[(1, 1), (2, -7 if v == -1 else v), (3, 1)]), r"dofs\[1\] direction"),
    ("oma orders", lambda v: msd.oma(Y, 100.0, orders=[2, v]), "orders"),
    ("oma order_step", lambda v: msd.oma(Y, 100.0, order_step=v), "order_step"),
    ("oma block_rows", lambda v: msd.oma(Y, 100.0, block_rows=v), "block_rows"),
    ("oma blocks", lambda v: msd.oma(Y, 100.0, blocks=v), "blocks"),
    ("efdd lags", lambda v: msd.oma(Y, 100.0, method="efdd", lags=v), "lags"),
    ("efdd max_extremes", lambda v: msd.oma(Y, 100.0, method="efdd", max_extremes=v), "max_extremes"),
    (
        "oma_setups dofs",
        lambda v: msd.oma_setups([{"data": Y, "sample_rate_hz": 100.0, "dofs": [(1, 1), (2, 1), (v, 1)]}]),
        r"setups\[0\]\.dofs\[2\] node",
    ),
    (
        "oma_setups references",
        lambda v: msd.oma_setups([{"data": Y, "sample_rate_hz": 100.0, "references": [v]}]),
        r"setups\[0\]\.references\[0\]",
    ),
    ("fit_records max_passes", lambda v: msd.fit_records(RECORD, max_passes=v), "max_passes"),
    ("fit_records residuals.max_lag", lambda v: msd.fit_records(RECORD, residuals={"max_lag": v}), "max_lag"),
    ("estimate multistart.starts", lambda v: msd.estimate(T, FORCE, X, multistart={"starts": v}), "starts"),
    ("estimate multistart.threads", lambda v: msd.estimate(T, FORCE, X, multistart={"threads": v}), "threads"),
    ("estimate multistart.seed", lambda v: msd.estimate(T, FORCE, X, multistart={"seed": v}), "seed"),
    (
        "validate residuals.max_lag",
        lambda v: msd.validate((1.0, 0.5, 100.0), T, FORCE, X, residuals={"max_lag": v}),
        "max_lag",
    ),
    ("dynamometer harmonics", lambda v: msd.dynamometer(CONDITIONS, harmonics=v), "harmonics"),
    ("inverse_dynamics blocks", lambda v: msd.inverse_dynamics(STROKES, blocks=v), "blocks"),
    ("simulate_chain masses", lambda v: msd.simulate_chain(CHAIN, FORCE, DT, masses=v), "masses"),
    ("simulate_chain force_at", lambda v: msd.simulate_chain(CHAIN, FORCE, DT, force_at=v), "force_at"),
    ("simulate_chain sensors.at", lambda v: msd.simulate_chain(CHAIN, FORCE, DT, sensors=[{"at": v}]), r"at"),
    (
        "simulate_chain low_pass.order",
        lambda v: msd.simulate_chain(CHAIN, FORCE, DT, sensors=[{"low_pass": {"cutoff_hz": 5.0, "order": v}}]),
        "order",
    ),
    ("fit_chain passes", lambda v: msd.fit_chain(FORCE, X, DT, CHAIN, passes=v), "passes"),
    ("fit_chain known_masses", lambda v: msd.fit_chain(FORCE, X, DT, CHAIN, known_masses=[v]), "known_masses"),
    ("predict_chain known_masses", lambda v: msd.predict_chain(CHAIN, FORCE, DT, 0.01, known_masses=[v]), "known_masses"),
    ("run seed", lambda v: msd.run({"name": "x"}, seed=v), "seed"),
    ("run threads", lambda v: msd.run({"name": "x"}, threads=v), "threads"),
    ("plan verify", lambda v: msd.plan("missing.toml", verify=v), "verify"),
    ("design verify", lambda v: msd.design("missing.toml", verify=v), "verify"),
    ("paper_data seed", lambda v: msd.paper_data(v), "seed"),
    ("RecordsFit.time record", lambda v: fitted().time(v), "record"),
    ("RecordsFit.model record", lambda v: fitted().model(record=v), "record"),
    ("RecordsFit.residual record", lambda v: fitted().residual(record=v), "record"),
    ("uff.write n_data_per_node", lambda v: msd.uff.write("never.uff", [dict(UFF_55, n_data_per_node=v)]), "n_data_per_node"),
    ("uff.write abscissa_spacing", lambda v: msd.uff.write("never.uff", [dict(UFF_58, abscissa_spacing=v)]), "abscissa_spacing"),
    # Signed in UFF (−1 is written as such): ±10**20 instead.
    ("uff.write rsp_node", lambda v: msd.uff.write("never.uff", [dict(UFF_58, rsp_node=-(10**20) if v == -1 else v)]), "rsp_node"),
    ("uff.write ref_dir", lambda v: msd.uff.write("never.uff", [dict(UFF_58, ref_dir=-(10**20) if v == -1 else v)]), "ref_dir"),
    ("uff.write type", lambda v: msd.uff.write("never.uff", [dict(UFF_58, type=v)]), "type"),
]


def refused(call, name, kinds=(ValueError, TypeError)):
    """The call raises one of `kinds` (nothing else) with `name` in its message."""
    with pytest.raises(Exception) as caught:
        call()
    e = caught.value
    assert isinstance(e, kinds), f"{type(e).__name__}: {e}"
    assert not isinstance(e, (OverflowError, RuntimeError)), f"{type(e).__name__}: {e}"
    assert re.search(name, str(e)), f"{name!r} not named in {type(e).__name__}: {e}"
    return e


@pytest.mark.parametrize("value", [-1, 10**20], ids=["-1", "10**20"])
@pytest.mark.parametrize("case", INTEGER_ARGUMENTS, ids=[c[0] for c in INTEGER_ARGUMENTS])
def test_integer_arguments_out_of_range_name_the_argument(case, value):
    _, call, name = case
    refused(lambda: call(value), name)


DIRECT = [c for c in INTEGER_ARGUMENTS if c[0].startswith(("run", "plan", "design", "paper_data", "modal_fit dofs", "oma dofs", "oma references", "RecordsFit"))]
WRONG_TYPES = [
    (case, value)
    for case in DIRECT
    for value in (2.5, "3", True, None)
    # None is the default of these (no override).
    if not (value is None and case[0].startswith(("run", "plan", "design")))
]


@pytest.mark.parametrize("case, value", WRONG_TYPES, ids=[f"{c[0]}-{v!r}" for c, v in WRONG_TYPES])
def test_direct_integer_arguments_of_the_wrong_type_name_the_argument(case, value):
    """Integers passed straight to the core (not through an options dict): a float with
    a fraction is a ValueError, a string, a bool or None a TypeError, each naming it."""
    _, call, name = case
    e = refused(lambda: call(value), name)
    assert isinstance(e, ValueError if value == 2.5 else TypeError), f"{type(e).__name__}: {e}"


def test_the_overflow_errors_of_the_issue_are_value_errors():
    """Each was an OverflowError that named nothing."""
    assert "seed = -1" in str(refused(lambda: msd.run({"name": "x"}, seed=-1), "seed", ValueError))
    refused(lambda: msd.plan("missing.toml", verify=-1), "verify", ValueError)
    refused(lambda: msd.plan("missing.toml", verify=10**20), "verify", ValueError)
    refused(lambda: msd.design("missing.toml", verify=-1), "verify", ValueError)
    refused(lambda: msd.paper_data(seed=-1), "seed", ValueError)
    refused(lambda: modal_set(node=-2), r"dofs\[0\] response node = -2", ValueError)
    refused(lambda: msd.oma(Y, 100.0, dofs=[(-2, 1), (2, 1), (3, 1)]), r"dofs\[0\] node = -2", ValueError)
    # The core's own entry points say the same (the package only passes the values on).
    refused(lambda: _msd.paper_data(-1), "seed", ValueError)
    refused(lambda: _msd.plan("missing.toml", 0.01, 10**20), "verify", ValueError)
    # In range they still work: a NumPy integer and a float with a whole value.
    assert msd.paper_data(np.int64(3))["identification"]["t"].size > 0
    np.testing.assert_array_equal(msd.paper_data(3.0)["identification"]["force"], msd.paper_data(3)["identification"]["force"])


def test_run_threads_zero_is_a_value_error_not_a_runtime_error():
    e = refused(lambda: msd.run({"name": "x"}, threads=0), "threads = 0", ValueError)
    assert "from 1 to" in str(e)


def test_option_integers_name_their_key():
    """serde's "invalid value: integer `-1`, expected usize" named no key."""
    e = refused(lambda: msd.frf(T, FORCE, X, segment_length=-1), "segment_length = -1", ValueError)
    assert "usize" not in str(e) and "expected an integer from 0" in str(e)
    refused(lambda: msd.modal_fit(FREQUENCY, H, mode_count=-1), "mode_count = -1", ValueError)
    refused(lambda: msd.fit_records(RECORD, max_passes=-1), "max_passes = -1", ValueError)
    refused(lambda: msd.estimate(T, FORCE, X, multistart={"starts": -1}), r"multistart\.starts = -1", ValueError)
    refused(lambda: msd.simulate_chain(CHAIN, FORCE, DT, masses=-1), "masses = -1", ValueError)
    refused(lambda: msd.frf(T, FORCE, X, segment_length=2.5), "segment_length = 2.5", ValueError)


def test_missing_keys_are_value_errors_naming_the_key():
    """Each was a KeyError; MissingKeyError is a ValueError (and still a KeyError)."""
    assert issubclass(msd.MissingKeyError, ValueError) and issubclass(msd.MissingKeyError, KeyError)
    assert msd.MissingKeyError.__module__ == "msd"
    cases = [
        (lambda: msd.uff.write("never.uff", [{"type": 58, "data": H}]), "abscissa_min"),
        (lambda: msd.uff.write("never.uff", [{"type": 58, "data": H, "abscissa_spacing": 0}]), "'x'"),
        (lambda: msd.uff.write("never.uff", [{"type": 58, "x": FREQUENCY}]), "'data'"),
        (lambda: msd.uff.write("never.uff", [{"type": 55}]), "'node_nums'"),
        (lambda: msd.uff.write("never.uff", [{"type": 55, "node_nums": [1, 2]}]), "'r1'"),
        (lambda: msd.uff.write("never.uff", [{"type": 2411}]), "'node_nums'"),
        (lambda: msd.uff.write("never.uff", [{"data": H}]), "'type'"),
        (lambda: msd.Interval.from_dict({}), "'value'"),
        (lambda: msd.Interval.from_dict({"value": 1.0, "standard_error": 0.1}), "'ci95'"),
        (lambda: msd.ChainParameters.from_dict({}), "'masses'"),
        (lambda: msd.ChainParameters.from_dict({"masses": [1.0], "dampers": [1.0]}), "'springs'"),
        (lambda: msd.Mode.from_dict({}), "'natural_frequency_hz'"),
        (lambda: msd.FrequencyResponse.from_dict({}), "'h'"),
        (lambda: msd.oma_setups([{"data": Y}]), "'sample_rate_hz'"),
        (lambda: msd.simulate({"mass": 1.0, "damping": 1.0}, T, FORCE), "'stiffness'"),
        (lambda: fitted().model("acceleration"), "'acceleration'"),
    ]
    for call, key in cases:
        e = refused(call, re.escape(key), msd.MissingKeyError)
        assert not str(e).startswith('"'), "the message itself, not KeyError's repr of it"


def test_an_index_out_of_range_is_a_value_error():
    assert issubclass(msd.OutOfRangeError, ValueError) and issubclass(msd.OutOfRangeError, IndexError)
    refused(lambda: fitted().time(1), r"record = 1: the fit has 1 record", msd.OutOfRangeError)


def test_wrong_types_of_containers_name_the_argument():
    """An int where a dict or a list belongs: named (was "'int' object is not iterable")."""
    cases = [
        (lambda: msd.frf(T, FORCE, X, impact=3), "impact"),
        (lambda: msd.fit_records(3), "records"),
        (lambda: msd.fit_records([3]), r"records\[0\]"),
        (lambda: msd.fit_records(RECORD, responses=3), "responses"),
        (lambda: msd.dynamometer(3), "conditions"),
        (lambda: msd.dynamometer([3]), r"conditions\[0\]"),
        (lambda: msd.inverse_dynamics(3), "records"),
        (lambda: msd.inverse_dynamics(STROKES, 3), "validation"),
        (lambda: msd.oma_setups(3), "setups"),
        (lambda: msd.oma_setups([3]), r"setups\[0\]"),
        (lambda: msd.oma(Y, 100.0, references=3), "references"),
        (lambda: msd.oma(Y, 100.0, dofs=3), "dofs"),
        (lambda: msd.oma(Y, 100.0, dofs=[(1,), (2, 1), (3, 1)]), r"dofs\[0\]"),
        (lambda: msd.oma(Y, 100.0, names=3), "names"),
        (lambda: msd.oma(Y, 100.0, quantities=3), "quantities"),
        (lambda: msd.oma(Y, 100.0, directions=3), "directions"),
        (lambda: msd.oma(Y, 100.0, directions=[(1.0, 0.0), None, None]), r"directions\[0\]"),
        (lambda: msd.modal_fit(FREQUENCY, [H, H], dofs=3), "dofs"),
        (lambda: msd.modal_fit(FREQUENCY, [H, H], dofs=[(1, 1), (2, 1)]), r"dofs\[0\]"),
        (lambda: msd.one_mode_fit(FREQUENCY, H, band_hz=3), "band_hz"),
        (lambda: msd.one_mode_fit(FREQUENCY, H, exponential_decay="long"), "exponential_decay"),
        (lambda: msd.oma(Y, "fast"), "sample_rate_hz"),
        (lambda: msd.oma_setups([{"data": Y, "sample_rate_hz": 100.0}], tolerance=[1]), "tolerance"),
        (lambda: msd.plan("missing.toml", target="tight"), "target"),
        (lambda: msd.run(3), "config"),
        (lambda: msd.run({"name": "x"}, out=3), "out"),
        (lambda: msd.run({"name": "x"}, data=3), "data"),
        (lambda: msd.design(3), "config"),
        (lambda: msd.read_file(3), "path"),
        (lambda: msd.inspect(3), "path"),
        (lambda: msd.init(3), "path"),
        (lambda: msd.init("missing.csv", outputs=3), "outputs"),
        (lambda: msd.init("missing.csv", sample_rate="fast"), "sample_rate"),
        (lambda: msd.uff.read(3), "path"),
        (lambda: msd.uff.write("never.uff", 3), "datasets"),
        (lambda: msd.uff.write("never.uff", [3]), r"datasets\[0\]"),
        (lambda: msd.uff.write("never.uff", [dict(UFF_58, rsp_dir="x")]), "rsp_dir"),
        (lambda: msd.simulate({"mass": "heavy", "damping": 1.0, "stiffness": 1.0}, T, FORCE), "mass"),
        (lambda: msd.simulate(("heavy", 1.0, 1.0), T, FORCE), r"plant\[0\]"),
        (lambda: msd.dynamometer([dict(CONDITIONS[0], dt="fast")]), "dt"),
        (lambda: msd.inverse_dynamics([dict(STROKES[0], dt=None)]), "dt"),
        (lambda: msd.Interval.from_dict(3), "Interval"),
        (lambda: msd.Interval.from_dict({"value": 1.0, "standard_error": 0.1, "ci95": 3}), "ci95"),
        (lambda: msd.Interval.from_dict({"value": "one", "standard_error": 0.1, "ci95": [0, 2]}), "value"),
        (lambda: msd.ChainParameters.from_dict({"masses": 3, "dampers": [1.0], "springs": [1.0]}), "masses"),
        (lambda: msd.Estimate.from_dict(3), "Estimate"),
        (lambda: msd.estimate(T, FORCE, X, offset=object()), "offset"),
        (lambda: msd.estimate(T, FORCE, X, offset=10**400), "offset"),
        (lambda: msd.estimate(T, FORCE, X, preset=3), "preset"),
        (lambda: msd.modal_fit(FREQUENCY, H, kind=3), "kind"),
        (lambda: msd.one_mode_fit(FREQUENCY, H, kind=3), "kind"),
        (lambda: msd.oma(Y, 100.0, method=3), "method"),
        (lambda: msd.oma_setups([{"data": Y, "sample_rate_hz": 100.0}], method=3), "method"),
        (lambda: msd.init("missing.csv", input=3), "input"),
        (lambda: msd.uff.write("never.uff", [dict(UFF_58, binary=10**20)]), "binary"),
        (lambda: msd.uff.write("never.uff", [{"type": 151, "model_name": 3}]), "model_name"),
    ]
    for call, name in cases:
        refused(call, name)


def nan_at(a, i=5):
    a = np.array(a, copy=True)
    a[i] = np.nan
    return a


# Every array argument with a NaN: (id, call, the name the message must give).
NAN_ARGUMENTS = [
    ("estimate t", lambda: msd.estimate(nan_at(T), FORCE, X), r"^t: time sample 5 is NaN"),
    ("estimate force", lambda: msd.estimate(T, nan_at(FORCE), X), r"^force: input sample 5 is NaN"),
    ("estimate displacement", lambda: msd.estimate(T, FORCE, nan_at(X)), r"^displacement: output sample 5"),
    ("simulate force", lambda: msd.simulate((1.0, 0.5, 100.0), T, nan_at(FORCE)), r"^force: input sample 5"),
    ("simulate all force", lambda: msd.simulate((1.0, 0.5, 100.0), T, nan_at(FORCE), quantity="all"), r"^force:"),
    ("validate displacement", lambda: msd.validate((1.0, 0.5, 100.0), T, FORCE, nan_at(X)), r"^displacement:"),
    ("frf force", lambda: msd.frf(T, nan_at(FORCE), X), r"^force: input sample 5"),
    ("frf second force", lambda: msd.frf(T, [FORCE, nan_at(FORCE)], [X, X]), r"^force\[1\]: input sample 5"),
    ("frf response", lambda: msd.frf(T, FORCE, nan_at(X)), r"^response: output sample 5"),
    ("modal_fit frequencies", lambda: msd.modal_fit(nan_at(FREQUENCY), H), r"^frequencies: sample 5"),
    ("modal_fit frfs", lambda: msd.modal_fit(FREQUENCY, nan_at(H)), r"^frfs: sample 5"),
    ("modal_fit coherence", lambda: msd.modal_fit(FREQUENCY, H, coherence=nan_at(np.ones(64))), r"^coherence"),
    ("one_mode_fit frf", lambda: msd.one_mode_fit(FREQUENCY, nan_at(H)), r"^frf: sample 5"),
    ("oma data", lambda: msd.oma(np.where(np.arange(N)[:, None] == 5, np.nan, Y), 100.0), r"^data\[:, 0\]"),
    (
        "oma_setups data",
        lambda: msd.oma_setups([{"data": np.where(np.arange(N)[:, None] == 5, np.nan, Y), "sample_rate_hz": 100.0}]),
        r"^setups\[0\]\.data\[:, 0\]",
    ),
    ("fit_records t", lambda: msd.fit_records(dict(RECORD, t=nan_at(T))), r"^records\[0\]\['t'\]"),
    ("fit_records force", lambda: msd.fit_records(dict(RECORD, force=nan_at(FORCE))), r"^records\[0\]\['force'\]"),
    ("fit_records channel", lambda: msd.fit_records(dict(RECORD, displacement=nan_at(X))), r"^records\[0\]\['displacement'\]"),
    ("free_decay response", lambda: msd.free_decay(T, nan_at(X)), r"^response: sample 5"),
    ("dynamometer force", lambda: msd.dynamometer([dict(CONDITIONS[0], force=nan_at(FORCE))]), r"^conditions\[0\]\['force'\]"),
    ("inverse_dynamics stroke", lambda: msd.inverse_dynamics([dict(STROKES[0], stroke=nan_at(X))]), r"^records\[0\]\['stroke'\]"),
    (
        "inverse_dynamics validation",
        lambda: msd.inverse_dynamics(STROKES, [dict(STROKES[0], force=nan_at(FORCE))]),
        r"^validation\[0\]\['force'\]",
    ),
    ("simulate_chain input", lambda: msd.simulate_chain(CHAIN, nan_at(FORCE), DT), r"^input: input sample 5"),
    ("fit_chain outputs", lambda: msd.fit_chain(FORCE, nan_at(X), DT, CHAIN), r"^outputs: output sample 5"),
    ("predict_chain noise", lambda: msd.predict_chain(CHAIN, FORCE, DT, [np.nan]), r"noise σ = NaN"),
    ("uff.write data", lambda: msd.uff.write("never.uff", [dict(UFF_58, data=nan_at(H))]), r"^datasets\[0\]\['data'\]: sample 5"),
    ("uff.write x", lambda: msd.uff.write("never.uff", [dict(UFF_58, x=nan_at(FREQUENCY))]), r"^datasets\[0\]\['x'\]"),
    ("uff.write r2", lambda: msd.uff.write("never.uff", [dict(UFF_55, r2=np.array([1.0, np.inf]))]), r"'r2'\]: sample 1 is inf"),
    ("uff.write freq", lambda: msd.uff.write("never.uff", [dict(UFF_55, freq=float("nan"))]), r"'freq'\] = nan"),
]


@pytest.mark.parametrize("case", NAN_ARGUMENTS, ids=[c[0] for c in NAN_ARGUMENTS])
def test_nan_names_the_array(case):
    _, call, name = case
    refused(call, name, ValueError)


def test_nan_in_force_names_force_not_the_input_sample():
    e = refused(lambda: msd.estimate(T, nan_at(FORCE, 250), X), "force", ValueError)
    assert str(e) == "force: input sample 250 is NaN: expected a finite number"


def test_uff_write_refuses_nan_and_writes_nothing(tmp_path):
    target = tmp_path / "nan.uff"
    refused(lambda: msd.uff.write(target, [dict(UFF_58, data=nan_at(H, 0))]), r"'data'\]: sample 0 is", ValueError)
    assert not target.exists()
    msd.uff.write(target, [UFF_58])  # the same without the NaN is written
    assert target.exists()


def test_fit_chain_refuses_zero_passes():
    refused(lambda: msd.fit_chain(FORCE, X, DT, CHAIN, passes=0), "passes = 0", ValueError)
    refused(lambda: _msd.fit_chain('{"masses": 1}', FORCE, [X], DT, '{"masses": [1.0], "dampers": [0.5], "springs": [100.0]}', '{"passes": 0}'), "passes", ValueError)


@pytest.mark.parametrize("direction", [0, 7, -7, 100])
def test_frf_dof_directions_outside_one_to_six_are_refused(direction):
    """A direction of 0 (or beyond ±6) was accepted: the fit ran on a DOF UFF has not."""
    refused(lambda: modal_set(direction=direction), rf"dofs\[0\] response direction = {direction}: expected ±1", ValueError)
    refused(
        lambda: msd.modal_fit(FREQUENCY, [H, H], dofs=[((1, 1), (1, 1)), ((2, 1), (1, direction))]),
        rf"dofs\[1\] reference direction = {direction}",
        ValueError,
    )


@pytest.mark.parametrize("direction", [7, -7, 100])
def test_channel_dof_directions_outside_one_to_six_are_refused(direction):
    """An output-only channel's direction is ±1 … ±6, or 0 for an oblique one (along no
    axis: msd-experiment reads pyOMA's setups so, and test_oma's steel frame passes
    (5, 0)); anything else is refused, naming the channel's DOF."""
    refused(lambda: msd.oma(Y, 100.0, dofs=[(1, 1), (2, 1), (3, direction)]), rf"dofs\[2\] direction = {direction}", ValueError)
    refused(
        lambda: msd.oma_setups([{"data": Y, "sample_rate_hz": 100.0, "dofs": [(1, direction), (2, 1), (3, 1)]}]),
        rf"setups\[0\]\.dofs\[0\] direction = {direction}",
        ValueError,
    )


def test_an_oblique_channel_keeps_direction_zero():
    try:
        msd.oma(Y, 100.0, dofs=[(5, 0), (5, 0), (24, -1)], directions=[(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), None])
    except ValueError as e:  # noise has no modes: anything but the DOF check
        assert "direction" not in str(e), str(e)


def test_valid_negative_directions_still_pass_the_check():
    """−1 … −6 are UFF's negative directions: not refused by the DOF check."""
    for direction in (-1, -3, -6, 4):
        try:
            modal_set(direction=direction)
        except ValueError as e:
            assert "direction" not in str(e), str(e)
