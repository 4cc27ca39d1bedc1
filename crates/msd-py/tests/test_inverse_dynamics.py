"""msd.inverse_dynamics: a test machine under any stroke, from Python."""
import numpy as np
import pytest

import msd


def _record(phase: float, n: int = 20_000):
    t = np.arange(n) * 1e-3
    w1, w2 = 2 * np.pi * 0.7, 2 * np.pi * 3.1
    x = 0.05 * np.sin(w1 * t) + 0.01 * np.sin(w2 * t + phase)
    v = 0.05 * w1 * np.cos(w1 * t) + 0.01 * w2 * np.cos(w2 * t + phase)
    a = -0.05 * w1**2 * np.sin(w1 * t) - 0.01 * w2**2 * np.sin(w2 * t + phase)
    return t, x, 20 * a + 150 * v + 12 * np.sign(v) - 2


def test_the_coefficients_come_back_and_a_fresh_record_is_predicted():
    t, x, f = _record(0.0)
    tv, xv, fv = _record(1.0)
    fit = msd.inverse_dynamics([{"t": t, "stroke": x, "force": f}], [{"dt": 1e-3, "stroke": xv, "force": fv, "name": "check"}])
    best = fit.data["laws"][fit.data["best"]]
    assert best["law"] == "coulomb_viscous"
    values = {c["name"]: c["estimate"]["value"] for c in best["coefficients"]}
    for name, truth in {"mass": 20.0, "damping": 150.0, "coulomb_force": 12.0, "force_offset": -2.0}.items():
        assert values[name] == pytest.approx(truth, rel=2e-3), name
    check = fit.data["validation"][0]
    assert check["name"] == "check"
    assert check["rms_error"] < 0.01 * check["rms_force"]
    assert len(check["measured"]) == len(check["predicted"])
    assert "coulomb_viscous" in fit.summary


def test_a_record_without_its_force_is_refused_by_name():
    t, x, _ = _record(0.0, 2000)
    with pytest.raises(ValueError, match=r"records\[0\]: missing 'force'"):
        msd.inverse_dynamics([{"t": t, "stroke": x}])
    with pytest.raises(ValueError, match="cutoff_hz"):
        msd.inverse_dynamics([{"t": t, "stroke": x, "force": x}], cutoff_hz=-1.0)
