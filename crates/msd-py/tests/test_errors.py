"""Every bad input class gives a Python exception with the toolkit's message, never a
crash; int and float32 arrays are converted, non-contiguous arrays read correctly."""

import numpy as np
import pytest

import msd


def test_nan_is_refused_with_its_index(ident):
    t, force, x = ident
    bad = x.copy()
    bad[17] = np.nan
    with pytest.raises(ValueError, match="output sample 17 is NaN: expected a finite number"):
        msd.estimate(t, force, bad)
    bad_force = force.copy()
    bad_force[3] = np.inf
    with pytest.raises(ValueError, match="input sample 3 is inf"):
        msd.estimate(t, bad_force, x)


def test_empty_and_short_arrays():
    with pytest.raises(ValueError, match="too few samples: 0"):
        msd.estimate([], [], [])
    with pytest.raises(ValueError, match="too few samples: 3"):
        msd.estimate([0.0, 0.1, 0.2], [1.0, 2.0, 3.0], [0.0, 0.0, 0.0])


def test_lengths_must_match(ident):
    t, force, x = ident
    with pytest.raises(ValueError, match="length mismatch"):
        msd.estimate(t, force[:-1], x)
    with pytest.raises(ValueError, match="length mismatch"):
        msd.estimate(t, force, x[:-1])


def test_wrong_shapes_and_dtypes(ident):
    t, force, x = ident
    with pytest.raises(ValueError, match="expected a 1-D array, got shape"):
        msd.estimate(t, np.vstack([force, force]), x)
    with pytest.raises(ValueError, match="expected real numbers"):
        msd.estimate(t, force.astype(complex), x)
    with pytest.raises(ValueError, match="expected real numbers"):
        msd.estimate(t, ["a"] * len(t), x)
    with pytest.raises(ValueError, match="expected a 1-D array of numbers"):
        msd.estimate(None, force, x)
    with pytest.raises(ValueError, match="expected a 1-D array, got shape"):
        msd.estimate(1.0, force, x)
    with pytest.raises(ValueError):
        msd.estimate(t, [[1.0], [1.0, 2.0]], x)


def test_non_uniform_time(ident):
    t, force, x = ident
    bad = t.copy()
    bad[100] += 1e-4
    with pytest.raises(ValueError, match="uniform"):
        msd.estimate(bad, force, x)


def test_int_float32_and_strided_arrays_are_converted(ident):
    t, force, x = ident
    reference = msd.estimate(t, force, x)
    # float32 and int are converted to float64 (the values change, the call works).
    f32 = msd.estimate(t, force.astype(np.float32), x.astype(np.float32))
    assert abs(f32.stiffness.value / reference.stiffness.value - 1) < 1e-3
    # float32 time stamps are uniform only to 1e-7 or so: refused with the toolkit's words.
    with pytest.raises(ValueError, match="time stamps are not uniform"):
        msd.estimate(t.astype(np.float32), force, x)
    ints = np.arange(len(t))
    as_float = msd.simulate((2.5, 1.8, 120.0), ints, (force * 10).astype(int))
    np.testing.assert_array_equal(
        as_float, msd.simulate((2.5, 1.8, 120.0), ints.astype(float), (force * 10).astype(int).astype(float))
    )
    # A non-contiguous view reads the same values as its copy.
    wide = np.zeros((len(t), 3))
    wide[:, 0], wide[:, 1], wide[:, 2] = t, force, x
    strided = msd.estimate(wide[:, 0], wide[:, 1], wide[:, 2])
    assert strided.mass == reference.mass
    reversed_view = x[::-1][::-1]
    assert msd.estimate(t, force, reversed_view).mass == reference.mass


def test_unknown_and_bad_options(ident):
    with pytest.raises(ValueError, match="unknown field `metod`"):
        msd.estimate(*ident, metod="nelder_mead")
    with pytest.raises(ValueError, match="unknown variant `newton`"):
        msd.estimate(*ident, method="newton")
    with pytest.raises(ValueError, match="initial_guess.mass"):
        msd.estimate(*ident, initial_guess=(-1.0, 1.0, 100.0))
    with pytest.raises(ValueError, match="expected a finite number"):
        msd.estimate(*ident, offset=float("nan"))
    with pytest.raises(ValueError, match="preset"):
        msd.estimate(*ident, preset="fastest")
    with pytest.raises(ValueError, match="backend"):
        msd.estimate(*ident, backend="rk4")
    with pytest.raises(ValueError, match="not supported"):
        msd.estimate(*ident, offset=object())


def test_bad_plants():
    t = np.arange(100) * 0.01
    with pytest.raises(ValueError, match="invalid mass = -1"):
        msd.simulate((-1.0, 1.0, 1.0), t, np.ones(100))
    with pytest.raises(ValueError, match="invalid damping = NaN"):
        msd.simulate((1.0, float("nan"), 1.0), t, np.ones(100))
    with pytest.raises(ValueError, match="missing 'stiffness'"):
        msd.simulate({"mass": 1.0, "damping": 1.0}, t, np.ones(100))
    with pytest.raises(ValueError, match="initial_state"):
        msd.simulate((1.0, 1.0, 1.0), t, np.ones(100), initial_state=(float("nan"), 0.0))


def test_a_fit_that_cannot_identify_raises_identification_error(paper):
    """A stabilization diagram without a stable mode: IdentificationError, a ValueError."""
    assert issubclass(msd.IdentificationError, ValueError)
    d = paper["identification"]
    frf = msd.frf(d["t"], d["force"], d["displacement"])
    with pytest.raises(msd.IdentificationError, match="not identifiable"):
        msd.modal_fit(frf, band_hz=[0.3, 3.0], orders=[2, 10])


def test_unfittable_time_record_raises_identification_error():
    """No force at all: nothing to identify m, c, k from."""
    t = np.arange(2000) * 0.01
    rng = np.random.default_rng(0)
    with pytest.raises(msd.IdentificationError):
        msd.estimate(t, np.zeros_like(t), rng.normal(size=t.size), preset="fast")


def test_identification_error_is_msds():
    assert msd.IdentificationError.__module__ == "msd"
    assert msd.IdentificationError.__doc__ and "ValueError" in msd.IdentificationError.__doc__
    import pickle

    e = pickle.loads(pickle.dumps(msd.IdentificationError("not identifiable")))
    assert isinstance(e, msd.IdentificationError) and str(e) == "not identifiable"
