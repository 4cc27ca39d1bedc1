"""Odd inputs to every function: an exception derived from Exception (ValueError,
IdentificationError, OSError, …) or a result, never a Rust panic (pyo3's PanicException
derives from BaseException) and never a crash of the interpreter."""

import itertools

import numpy as np
import pytest

import msd

ODD_ARRAYS = {
    "empty": np.array([]),
    "one": np.array([1.0]),
    "two": np.array([0.0, 1.0]),
    "zeros": np.zeros(64),
    "huge": np.full(64, 1e308),
    "tiny": np.full(64, 1e-308),
    "alternating inf": np.where(np.arange(64) % 2 == 0, np.inf, -np.inf),
    "nan": np.full(64, np.nan),
    "int": np.arange(64),
    "float32": np.linspace(0, 1, 64, dtype=np.float32),
    "bool": np.ones(64, dtype=bool),
    "strided": np.linspace(0, 1, 128)[::2],
    "2-D": np.ones((8, 8)),
    "object": np.array([1.0, "a"], dtype=object),
}

ODD_TIMES = {
    "uniform": np.arange(64) * 0.01,
    "huge step": np.arange(64) * 1e300,
    "tiny step": np.arange(64) * 1e-300,
    "decreasing": -np.arange(64) * 0.01,
    "constant": np.zeros(64),
}


def survives(f, *args, **kwargs):
    try:
        f(*args, **kwargs)
    except Exception:
        pass  # any ordinary exception is fine; a BaseException (panic) propagates


@pytest.mark.parametrize("t_name, a_name", list(itertools.product(ODD_TIMES, ODD_ARRAYS)))
def test_time_domain_functions(t_name, a_name):
    t, a = ODD_TIMES[t_name], ODD_ARRAYS[a_name]
    survives(msd.estimate, t, a, a)
    survives(msd.estimate, t, a, np.sin(t), preset="paper", nelder_mead={"max_iter": 5})
    survives(msd.simulate, (1.0, 0.1, 10.0), t, a)
    survives(msd.validate, (1.0, 0.1, 10.0), t, a, a)
    survives(msd.simulate, (1e300, 1e-300, 1e300), t, a, backend="ode45")
    survives(msd.frf, t, a, a)
    survives(msd.frf, t, a, a, segment_length=2, impact={})
    survives(msd.free_decay, t, a)
    survives(msd.fit_records, {"t": t, "drive": a, "displacement": a})
    survives(msd.dynamometer, [{"t": t, "displacement": a, "force": a}])
    dt = t[1] - t[0]
    one = {"masses": [1.0], "dampers": [0.1], "springs": [10.0]}
    survives(msd.simulate_chain, one, a, dt, sensors=[{"delay": 0.05, "low_pass": {"cutoff_hz": 5.0, "order": 2}}])
    survives(msd.simulate_chain, {"masses": [1e300, 1e-300], "dampers": [1e-300, 1e300], "springs": [1e300, 1.0]}, a, dt)
    survives(msd.fit_chain, a, a, dt, one, sensors=[{"estimate_delay": True, "low_pass": {"cutoff_hz": 5.0}}])
    survives(msd.fit_chain, a, [a, a], dt, one, drive="base_acceleration",
             sensors=[{"quantity": "acceleration"}, {"quantity": "velocity", "delay": 1e300}])
    survives(msd.predict_chain, one, a, dt, a, sensors=[{"estimate_delay": True, "low_pass": {"cutoff_hz": 5.0}}])
    survives(msd.predict_chain, one, a, dt, [1e-300], sensors=[{"estimate_delay": True, "delay": 1e-3}])
    survives(msd.predict_chain, {"masses": [1e300, 1e-300], "dampers": [1e-300, 1e300], "springs": [1e300, 1.0]},
             a, dt, [0.1, 1e300], drive="base_acceleration", known_masses=[1],
             sensors=[{"quantity": "acceleration"}, {"at": 2, "quantity": "velocity", "low_pass": {"cutoff_hz": 1e300, "order": 2}}])


@pytest.mark.parametrize("a_name", ODD_ARRAYS)
def test_frequency_domain_functions(a_name):
    a = ODD_ARRAYS[a_name]
    f = np.arange(len(a)) * 1.0 if a.ndim == 1 else np.arange(8.0)
    survives(msd.modal_fit, f, a)
    survives(msd.modal_fit, f, a * (1 + 1j) if a.dtype.kind in "iuf" else a, orders=[1, 400])
    survives(msd.modal_fit, f, [a, a], dofs=[((1, 1), (1, 1)), ((2, 1), (1, 1))], mode_count=3)


def test_odd_uff_datasets(tmp_path):
    path = tmp_path / "x.uff"
    for d in (
        {"type": 58, "data": np.array([]), "x": np.array([])},
        {"type": 58, "data": np.array([np.nan, np.inf]), "x": np.array([0.0, 1.0])},
        {"type": 58, "data": np.array([1.0]), "abscissa_min": 0.0, "abscissa_inc": np.nan},
        {"type": 58, "data": np.ones(3), "x": np.ones(3), "rsp_node": 2**40},
        {"type": 58, "data": np.ones(3), "x": np.arange(3.0), "rsp_dir": "z"},
        {"type": 15, "node_nums": [1.5], "x": [0.0]},
        {"type": 2411, "node_nums": [1, 2], "x": [0.0]},
        {"type": "58"},
    ):
        survives(msd.uff.write, path, [d])
        survives(msd.uff.read, path)
    for garbage in (b"", b"    -1\n", b"    -1\n    58b     1     1          11         600         0\n", bytes(range(256)) * 10):
        path.write_bytes(garbage)
        survives(msd.uff.read, path)
