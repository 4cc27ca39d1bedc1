"""msd.read_file against the libraries that define the formats: files written here by
scipy.io.savemat (levels 5 and 7), numpy.save/savez and npTDMS, read back by msd and by
scipy.io.loadmat, numpy.load and npTDMS; and msd.inspect on each."""
import numpy as np
import pytest
import scipy.io as sio

import msd

nptdms = pytest.importorskip("nptdms")

RNG = np.random.default_rng(7)
T = np.arange(500) / 250.0
FORCE = RNG.standard_normal(500)
X = RNG.standard_normal((500, 3))


@pytest.mark.parametrize("compress", [False, True])
def test_mat_files_read_as_scipy_reads_them(tmp_path, compress):
    path = tmp_path / "rig.mat"
    sio.savemat(path, {"t": T, "force": FORCE[:, None], "X": X, "H": FORCE + 1j * T,
                       "I": np.arange(7, dtype=np.int32), "note": "rig 2"}, do_compression=compress)
    ref = sio.loadmat(path)
    got = msd.read_file(path)
    np.testing.assert_array_equal(got["t"], ref["t"].ravel())
    np.testing.assert_array_equal(got["force"], ref["force"].ravel())
    for j in range(3):
        np.testing.assert_array_equal(got[f"X[{j}]"], ref["X"][:, j])
    np.testing.assert_array_equal(got["H.re"], ref["H"].real.ravel())
    np.testing.assert_array_equal(got["H.im"], ref["H"].imag.ravel())
    np.testing.assert_array_equal(got["I"], ref["I"].ravel().astype(float))
    assert "note" not in got
    text = msd.inspect(path)
    assert "MATLAB .mat" in text and 'time = "t"' in text


def test_npy_and_npz_read_as_numpy_reads_them(tmp_path):
    for order, name in [("C", "c.npy"), ("F", "f.npy")]:
        np.save(tmp_path / name, np.asarray(X, order=order).astype(np.float32))
        ref = np.load(tmp_path / name)
        got = msd.read_file(tmp_path / name)
        stem = name[:-4]
        for j in range(3):
            np.testing.assert_array_equal(got[f"{stem}[{j}]"], ref[:, j].astype(float))
    np.savez_compressed(tmp_path / "r.npz", t=T, force=FORCE, counts=np.arange(5, dtype=np.uint16))
    ref = np.load(tmp_path / "r.npz")
    got = msd.read_file(tmp_path / "r.npz")
    for k in ["t", "force", "counts"]:
        np.testing.assert_array_equal(got[k], ref[k].astype(float))
    assert "NumPy .npz" in msd.inspect(tmp_path / "r.npz")


def test_tdms_reads_as_nptdms_reads_it(tmp_path):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsFile, TdmsWriter

    path = tmp_path / "rig.tdms"
    with TdmsWriter(path) as w:
        w.write_segment([RootObject(properties={"title": "rig"}), GroupObject("Rig"),
                         ChannelObject("Rig", "Force", FORCE[:200], properties={"unit_string": "N", "wf_increment": 0.004}),
                         ChannelObject("Rig", "Count", np.arange(200, dtype=np.int16))])
        w.write_segment([ChannelObject("Rig", "Force", np.array([]), properties={"operator": "lab"})])
        w.write_segment([ChannelObject("Rig", "Force", FORCE[200:]),
                         ChannelObject("Rig", "Count", np.arange(200, 500, dtype=np.int16)),
                         ChannelObject("Other", "Force", X[:, 0])])
    ref = TdmsFile.read(path)
    got = {c["name"]: c for c in msd.read_file(path, details=True)}
    np.testing.assert_array_equal(got["Rig/Force"]["values"], ref["Rig"]["Force"][:])
    np.testing.assert_array_equal(got["Other/Force"]["values"], ref["Other"]["Force"][:])
    np.testing.assert_array_equal(got["Count"]["values"], ref["Rig"]["Count"][:].astype(float))
    assert got["Rig/Force"]["unit"] == "N"
    assert got["Rig/Force"]["sample_rate_hz"] == pytest.approx(250.0)
    assert "250 Hz" in msd.inspect(path)


def test_bad_files_are_refused_naming_the_file(tmp_path):
    path = tmp_path / "big.mat"
    path.write_bytes(b"MATLAB 7.3 MAT-file, Platform: GLNXA64".ljust(512, b" "))
    with pytest.raises(ValueError, match=r"big\.mat.*'-v7'"):
        msd.read_file(path)
    np.save(tmp_path / "cut.npy", X)
    data = (tmp_path / "cut.npy").read_bytes()
    (tmp_path / "cut.npy").write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match=r"cut\.npy.*truncated"):
        msd.read_file(tmp_path / "cut.npy")
    with pytest.raises(OSError, match="nothing.tdms"):
        msd.read_file(tmp_path / "nothing.tdms")
