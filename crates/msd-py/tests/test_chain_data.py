"""A chain of masses from the lab's own records: the two-storey rig simulated by scipy
(not by msd: state space, lsim with the force linear between samples), written as a CSV,
fitted through a [chain] config with [data]; every m, c, k within 4 SE of the truth."""
import numpy as np
import pytest
from scipy import signal

import msd

TRUTH = {"masses": [2.0, 1.5], "dampers": [3.0, 2.0], "springs": [8000.0, 6000.0]}


def _record(seed: int = 11, dt: float = 0.002, n: int = 5000):
    (m1, m2), (c1, c2), (k1, k2) = TRUTH["masses"], TRUTH["dampers"], TRUTH["springs"]
    # x = [x1, x2, v1, v2]; the force on mass 2; outputs the two accelerations.
    a = np.array([
        [0, 0, 1, 0],
        [0, 0, 0, 1],
        [-(k1 + k2) / m1, k2 / m1, -(c1 + c2) / m1, c2 / m1],
        [k2 / m2, -k2 / m2, c2 / m2, -c2 / m2],
    ])
    b = np.array([[0], [0], [0], [1 / m2]])
    c = a[2:, :]
    d = b[2:, :]
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    lines = np.arange(1, 401) * 0.1  # 0.1–40 Hz, one period of 10 s
    force = np.sum(np.sin(2 * np.pi * lines[:, None] * t + rng.uniform(0, 2 * np.pi, (400, 1))), axis=0)
    force *= 2.0 / np.sqrt(np.mean(force**2))
    _, y, _ = signal.lsim((a, b, c, d), force, t)
    y = y + 0.02 * rng.standard_normal(y.shape)
    return t, force, y


def test_a_two_storey_rig_from_a_csv_written_by_scipy(tmp_path):
    t, force, y = _record()
    table = np.column_stack([t, force, y])
    np.savetxt(tmp_path / "rig.csv", table, delimiter=",", header="t,F,a1,a2", comments="")
    config = {
        "name": "rig",
        "chain": {
            "drive": "force",
            "force_at": 2,
            "guess": {"masses": [2.5, 1.2], "dampers": [2.0, 3.0], "springs": [10000.0, 5000.0]},
            "sensors": [
                {"at": 1, "quantity": "acceleration", "column": "a1"},
                {"at": 2, "quantity": "acceleration", "column": "a2"},
            ],
        },
        "data": {"path": str(tmp_path / "rig.csv"), "time": "t", "input": "F"},
    }
    results = msd.run(config, out=tmp_path / "out")
    intervals = results["fit"]["intervals"]
    for name, truths in TRUTH.items():
        for i, truth in enumerate(truths):
            est = intervals[name][i]
            z = (est["value"] - truth) / est["standard_error"]
            assert abs(z) < 4, f"{name}[{i}] = {est['value']} ± {est['standard_error']}, truth {truth}"


def test_a_chain_on_data_names_what_is_missing(tmp_path):
    t, force, y = _record(n=500)
    np.savetxt(tmp_path / "rig.csv", np.column_stack([t, force, y]), delimiter=",", header="t,F,a1,a2", comments="")
    config = {
        "name": "rig",
        "chain": {
            "guess": {"masses": [2.5, 1.2], "dampers": [2.0, 3.0], "springs": [10000.0, 5000.0]},
            "force_at": 2,
            "sensors": [{"at": 1, "quantity": "acceleration"}],
        },
        "data": {"path": str(tmp_path / "rig.csv"), "time": "t", "input": "F"},
    }
    with pytest.raises(ValueError, match=r"chain\.sensors\[0\]\.column"):
        msd.run(config, out=tmp_path / "out")
