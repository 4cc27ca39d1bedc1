"""msd.oma (output-only modal analysis) on a shear building simulated here with scipy —
independently of msd's own simulator — against its exact modes; on the real steel frame
against the run of configs/steel-frame.toml and against pyOMA2 where it is installed; the
ten setups merged against the origin's merged shapes; bad records refused."""

import numpy as np
import pytest

import msd
from conftest import require


def shear_building(floors=5, m=25.91, k=10_000.0, zeta=0.02, fs=100.0, n=30_001, noise=0.1, seed=3):
    """Accelerations of a shear building under white forces on every floor (scipy's
    zero-order-hold discretisation), with white noise of `noise` × each channel's rms;
    and its exact natural frequencies."""
    from scipy import linalg, signal

    K = k * (2 * np.eye(floors) - np.eye(floors, k=1) - np.eye(floors, k=-1))
    K[-1, -1] = k
    M = m * np.eye(floors)
    w2, phi = linalg.eigh(K, M)
    C = M @ phi @ np.diag(2 * zeta * np.sqrt(w2)) @ phi.T @ M
    Mi = np.linalg.inv(M)
    A = np.block([[np.zeros((floors, floors)), np.eye(floors)], [-Mi @ K, -Mi @ C]])
    B = np.vstack([np.zeros((floors, floors)), Mi])
    Cy = np.hstack([-Mi @ K, -Mi @ C])
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(n, floors))
    _, y, _ = signal.dlsim(signal.cont2discrete((A, B, Cy, Mi), 1 / fs)[:4] + (1 / fs,), u)
    y = y + noise * y.std(axis=0) * rng.normal(size=y.shape)
    return y, fs, np.sqrt(w2) / (2 * np.pi)


def test_every_mode_of_an_independently_simulated_building_is_found():
    pytest.importorskip("scipy")
    y, fs, truth = shear_building()
    fit = msd.oma(y, fs)
    assert len(fit.modes) == 5, fit
    for mode, f in zip(fit.modes, truth):
        assert abs(mode.natural_frequency_hz.value / f - 1) < 0.005
        lo, hi = mode.damping_ratio.ci95
        assert 0.0 < lo < hi
        assert mode.shape is not None and mode.shape.shape == (5,)
        assert mode.shape_standard_error is not None
    assert "SSI-cov/ref" in repr(fit)


def test_data_driven_ssi_finds_the_independently_simulated_building():
    pytest.importorskip("scipy")
    y, fs, truth = shear_building()
    fit = msd.oma(y, fs, method="ssi-dat")
    assert len(fit.modes) == 5, fit
    for mode, f in zip(fit.modes, truth):
        assert abs(mode.natural_frequency_hz.value / f - 1) < 0.005
    assert "SSI-dat/ref" in repr(fit)


def test_efdd_finds_the_independently_simulated_building():
    # EFDD, the quick look: every mode within 1 % (the upper pair, 13 % apart, pull each
    # other by up to 0.4 %: msd-modal's tests/modal/efdd.rs); the singular values and the
    # peaks picked come with the result.
    pytest.importorskip("scipy")
    y, fs, truth = shear_building()
    fit = msd.oma(y, fs, method="efdd")
    assert len(fit.modes) == 5, fit
    for mode, f in zip(fit.modes, truth):
        assert abs(mode.natural_frequency_hz.value / f - 1) < 0.01
        lo, hi = mode.damping_ratio.ci95
        assert 0.0 < lo < hi
        assert mode.shape_standard_error is not None
    spectrum = fit.data["spectrum"]
    assert len(spectrum["peaks_hz"]) == 5
    assert len(spectrum["singular_values"][0]) == len(spectrum["frequency_hz"])
    assert "EFDD" in repr(fit)
    with pytest.raises(ValueError, match="method"):
        msd.oma(y, fs, method="fdd-plain")
    with pytest.raises(ValueError, match="orders"):
        msd.oma(y, fs, method="efdd", orders=[2, 40])


def test_bad_records_are_refused():
    y, fs, _ = np.random.default_rng(1).normal(size=(20_000, 3)), 100.0, None
    bad = y.copy()
    bad[17, 1] = np.nan
    with pytest.raises(ValueError, match="channel 1.*sample 17 is NaN"):
        msd.oma(bad, fs)
    dead = y.copy()
    dead[:, 2] = 0.25
    with pytest.raises(ValueError, match="channel 2.*constant"):
        msd.oma(dead, fs)
    with pytest.raises(ValueError, match="at least two channels"):
        msd.oma(y[:, :1], fs)
    with pytest.raises(ValueError, match="references"):
        msd.oma(y, fs, references=[0, 5])
    with pytest.raises(ValueError, match="band_hz"):
        msd.oma(y, fs, band_hz=[60.0, 70.0])
    with pytest.raises(ValueError, match="2-D"):
        msd.oma(y[:, 0], fs)
    with pytest.raises(ValueError, match="ordres"):
        msd.oma(y, fs, ordres=[2, 10])


def steel_frame(root, setup=1):
    folder = root / "data/steel-frame" / f"measurement_{setup}"
    require(folder, "cargo xtask fetch-data steel-frame", "MSD_REQUIRE_REAL_DATA")
    y = np.load(folder / f"measurement_{setup}.npy")[:, :5]
    dofs = [(5, 0), (5, 0), (5, 0), (24, -1), (24, -2)]
    return y, dofs


def test_the_steel_frame_gives_the_config_runs_modes(root, tmp_path):
    """msd.oma on the array equals the [operational] config's run of the same file."""
    y, dofs = steel_frame(root)
    rust = msd.run(root / "configs/steel-frame.toml", out=tmp_path / "out")["modes"]
    fit = msd.oma(y, 256.0, references=[3, 4], dofs=dofs, quantities=["velocity"] * 3 + ["acceleration"] * 2)
    assert len(fit.modes) == len(rust) >= 10
    for mine, theirs in zip(fit.modes, rust):
        assert mine.natural_frequency_hz.value == pytest.approx(theirs["natural_frequency_hz"]["value"], rel=1e-12)
        assert mine.damping_ratio.ci95[1] == pytest.approx(theirs["damping_ratio"]["ci95"][1], rel=1e-12)


def test_pyoma2_finds_the_same_frequencies_on_the_same_array(root):
    """pyOMA2's SSI-cov with msd's block rows (106: lags one period of the lowest
    mode; at pyOMA's usual 45 neither finds the three lowest modes), orders to 80, its
    order-80 poles picked at msd's frequencies, agrees with msd's automatic selection
    within 0.5 % on every mode."""
    pytest.importorskip("pyoma2")
    from pyoma2.algorithms import SSI
    from pyoma2.setup import SingleSetup

    y, dofs = steel_frame(root)
    fit = msd.oma(y, 256.0, references=[3, 4], dofs=dofs, quantities=["velocity"] * 3 + ["acceleration"] * 2)
    setup = SingleSetup(y, fs=256.0)
    ssi = SSI(name="SSIcov", method="cov", br=fit.data["block_rows"], ordmax=80, ref_ind=[3, 4])
    setup.add_algorithms(ssi)
    setup.run_by_name("SSIcov")
    mine = [m.natural_frequency_hz.value for m in fit.modes]
    setup.mpe("SSIcov", sel_freq=mine, order_in=80)
    theirs = np.ravel(ssi.result.Fn)
    np.testing.assert_allclose(theirs, mine, rtol=0.005)


def test_the_ten_steel_frame_setups_merge_into_pyomas_merged_shapes(root):
    """The ten shared setups, each read as pyOMA ships it (oblique beams by azimuth and
    elevation, references at node 24), merged by msd.oma_setups: every one of the
    origin's eleven merged modes within 0.5 %, and its shape within MAC 0.9 of the origin's
    (`merged_setups_poser.npz`, fourteen setups) on the DOFs both have — each node's
    oblique beams turned into x, y, z components the same way on both sides."""
    folder = root / "data/steel-frame"
    require(folder, "cargo xtask fetch-data steel-frame", "MSD_REQUIRE_REAL_DATA")

    def unit(az, el):
        az, el = np.radians(az), np.radians(el)
        return (np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el))

    setups = []
    for k in range(1, 11):
        rows = [l.split() for l in (folder / f"measurement_{k}/channel_dofs.txt").read_text().splitlines()[1:] if l.strip()][:5]
        dofs, directions = [], []
        for r in rows:
            if r[4] in ("ref_x", "ref_y"):  # along −x and −y (azimuth 0 with elevation 180, azimuth −90)
                dofs.append((24, -1 if r[4] == "ref_x" else -2))
                directions.append(None)
            else:
                dofs.append((int(r[1]), 0))
                directions.append(unit(float(r[2]), float(r[3])))
        data = np.load(folder / f"measurement_{k}/measurement_{k}.npy")[:, :5]
        setups.append(dict(data=data, sample_rate_hz=256.0, references=[3, 4], dofs=dofs, directions=directions,
                           quantities=["velocity"] * 3 + ["acceleration"] * 2))
    merged = msd.oma_setups(setups)
    assert len(merged.setups) == 10
    ref = np.load(folder / "merged_setups_poser.npz", allow_pickle=True)
    frequencies = np.ravel(ref["self.mean_frequencies"])
    shapes = ref["self.merged_mode_shapes"][:, 0, :]
    channels = {}
    for j, d in enumerate(ref["self.merged_chan_dofs"]):
        channels.setdefault(int(d[1]), []).append((j, unit(float(d[2]), float(d[3]))))

    def xyz(column):
        out = {}
        for node, beams in channels.items():
            if len(beams) >= 3:
                a = np.array([u for _, u in beams])
                x = np.linalg.lstsq(a, np.array([shapes[j, column] for j, _ in beams]), rcond=None)[0]
                out.update({(node, axis + 1): x[axis] for axis in range(3)})
            else:
                for j, u in beams:
                    axis = int(np.argmax(np.abs(u)))
                    out[(node, axis + 1)] = shapes[j, column] * np.sign(u[axis])
        return out

    for column, f in enumerate(frequencies):
        mine = min(merged.modes, key=lambda m: abs(m.natural_frequency_hz.value - f))
        assert abs(mine.natural_frequency_hz.value / f - 1) < 0.005, (f, mine.natural_frequency_hz)
        ours = {(node, abs(d)): v * np.sign(d) for (node, d), v in zip(mine.shape_dofs, mine.shape) if d != 0}
        theirs = xyz(column)
        shared = [k for k in ours if k in theirs]
        assert len(shared) >= 30
        a, b = np.array([ours[k] for k in shared]), np.array([theirs[k] for k in shared])
        mac = abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)
        assert mac >= 0.9, (f, mac)
