"""msd.uff against pyuff: pyuff's files read by msd.uff, msd.uff's files read by pyuff."""

import numpy as np
import pytest

import msd

pyuff = pytest.importorskip("pyuff")

FIELDS_58 = (
    "func_type", "rsp_node", "rsp_dir", "ref_node", "ref_dir", "id1", "id2", "id4",
    "ord_data_type", "abscissa_spacing", "binary", "load_case_id", "rsp_ent_name",
    "abscissa_spec_data_type", "ordinate_spec_data_type", "ordinate_axis_units_lab",
    "abscissa_axis_lab", "orddenom_spec_data_type", "ordinate_len_unit_exp",
)


def pyuff_sets(path):
    sets = pyuff.UFF(str(path)).read_sets()
    return sets if isinstance(sets, list) else [sets]


def same_function(ours, theirs):
    for key in FIELDS_58:
        if key in theirs:
            a, b = ours[key], theirs[key]
            if isinstance(b, str):
                a, b = a.strip(), b.strip()
            assert a == b, (key, a, b)
    np.testing.assert_array_equal(ours["x"], theirs["x"])
    np.testing.assert_array_equal(ours["data"], theirs["data"])


def fixtures(root):
    return sorted((root / "crates/msd-uff/fixtures/pyuff").glob("*.uff"))


def test_pyuffs_files_read_by_msd_uff(root):
    files = fixtures(root)
    assert len(files) >= 10
    compared = 0
    for path in files:
        ours = [d for d in msd.uff.read(path) if d["type"] == 58]
        try:
            theirs = [d for d in pyuff_sets(path) if d["type"] == 58]
        except Exception:
            # pyuff before 2.5 (the newest on Python 3.9 is 2.4) fails on some of the
            # files pyuff 2.5.8 wrote; msd.uff reads them all.
            assert pyuff.__version__ < "2.5", path
            continue
        assert len(ours) == len(theirs), path
        for a, b in zip(ours, theirs):
            same_function(a, b)
            compared += 1
    assert compared >= 10


def test_header_units_and_nodes_as_pyuff_reads_them(root):
    path = root / "crates/msd-uff/fixtures/pyuff/mixed.uff"
    ours = {d["type"]: d for d in msd.uff.read(path)}
    theirs = {d["type"]: d for d in pyuff_sets(path)}
    for key in ("model_name", "description", "program"):
        assert ours[151][key].strip() == theirs[151][key].strip()
    for key in ("units_code", "length", "force", "temp", "temp_offset"):
        assert ours[164][key] == theirs[164][key], key
    nodes = ours.get(15, ours.get(2411))
    their_nodes = theirs.get(15, theirs.get(2411))
    np.testing.assert_array_equal(nodes["node_nums"], their_nodes["node_nums"])
    np.testing.assert_allclose(nodes["x"], their_nodes["x"], rtol=1e-6)
    assert [s["type"] for s in msd.uff.read_skipped(path)] == [82]


@pytest.mark.parametrize("binary", [0, 1])
@pytest.mark.parametrize("complex_", [False, True])
def test_msd_uff_files_read_by_pyuff(tmp_path, binary, complex_):
    rng = np.random.default_rng(3)
    n = 257
    data = rng.normal(size=n) + (1j * rng.normal(size=n) if complex_ else 0)
    frf = {
        "type": 58, "binary": binary, "func_type": 4, "rsp_node": 3, "rsp_dir": 3,
        "ref_node": 1, "ref_dir": -2, "id1": "msd.uff test", "x": 0.5 * np.arange(n), "data": data,
        "abscissa_spec_data_type": 18, "ordinate_spec_data_type": 12, "ordinate_axis_units_lab": "m/s^2",
    }
    uneven = {"type": 58, "binary": binary, "func_type": 6, "x": np.array([1.0, 2.0, 4.5, 8.0]),
              "data": np.array([0.9, 0.95, 0.5, 0.99]), "rsp_node": 7, "rsp_dir": 1}
    header = {"type": 151, "model_name": "beam", "description": "msd.uff", "program": "msd"}
    units = {"type": 164, "units_code": 1, "units_description": "SI", "length": 1.0, "force": 1.0, "temp": 1.0, "temp_offset": 273.15}
    path = tmp_path / "ours.uff"
    msd.uff.write(path, [header, units, frf, uneven])
    theirs = pyuff_sets(path)
    assert [d["type"] for d in theirs] == [151, 164, 58, 58]
    functions = [d for d in theirs if d["type"] == 58]
    ours = [d for d in msd.uff.read(path) if d["type"] == 58]
    for a, b in zip(ours, functions):
        same_function(a, b)
    assert functions[0]["rsp_node"] == 3 and functions[0]["ref_dir"] == -2
    assert functions[1]["abscissa_spacing"] == 0
    if binary:  # exact in binary
        np.testing.assert_array_equal(functions[0]["data"], data)
    else:  # E20.12 in ASCII: 14 significant digits
        np.testing.assert_allclose(functions[0]["data"], data, rtol=1e-12)
    assert theirs[0]["model_name"].strip() == "beam" and theirs[1]["temp_offset"] == 273.15


def test_pyuff_written_file_read_by_msd_uff(tmp_path):
    n = 100
    data = np.exp(1j * np.linspace(0, 3, n)) / (1 + np.arange(n))
    path = tmp_path / "theirs.uff"
    def full(**given):
        d = dict(type=58, func_id=1, ver_num=0, load_case_id=0, rsp_ent_name="beam", ref_ent_name="beam",
                 id1="NONE", id2="NONE", id3="NONE", id4="NONE", id5="NONE", z_axis_value=0.0)
        for axis in ("abscissa", "ordinate", "orddenom", "z_axis"):
            d.update({f"{axis}_spec_data_type": 0, f"{axis}_len_unit_exp": 0, f"{axis}_force_unit_exp": 0,
                      f"{axis}_temp_unit_exp": 0, f"{axis}_axis_lab": "NONE", f"{axis}_axis_units_lab": "NONE"})
        d.update(given)
        return d

    sets = [
        full(binary=0, id1="pyuff", func_type=4, rsp_node=2, rsp_dir=1, ref_node=1, ref_dir=1,
             data=data, x=np.arange(n) * 0.25, abscissa_spacing=1, ord_data_type=6, abscissa_spec_data_type=18),
        full(binary=1, id1="pyuff b", func_type=1, rsp_node=5, rsp_dir=3, ref_node=1, ref_dir=1,
             data=np.sin(np.arange(n) * 0.1), x=np.arange(n) * 1e-3, abscissa_spacing=1, ord_data_type=4),
    ]
    pyuff.UFF(str(path)).write_sets(sets, mode="overwrite")
    ours = msd.uff.read(path)
    theirs = pyuff_sets(path)
    assert len(ours) == len(theirs) == 2
    for a, b in zip(ours, theirs):
        same_function(a, b)
    assert ours[0]["data"].dtype == np.complex128 and ours[1]["binary"] == 1


def test_round_trip_exact_and_errors(tmp_path):
    x = np.arange(10) / 3.0
    data = np.pi * np.arange(10) / 7.0
    path = tmp_path / "exact.uff"
    msd.uff.write(path, [{"type": 58, "x": x, "data": data}], exact=True)
    back = msd.uff.read(path)[0]
    np.testing.assert_array_equal(back["data"], data)
    with pytest.raises(FileNotFoundError):
        msd.uff.read(tmp_path / "missing.uff")
    (tmp_path / "bad.uff").write_text("    -1\n    58\nnot a header\n")
    with pytest.raises(ValueError, match="line"):
        msd.uff.read(tmp_path / "bad.uff")
    with pytest.raises(ValueError, match="at most 10 characters"):
        msd.uff.write(tmp_path / "x.uff", [{"type": 58, "x": x, "data": data, "rsp_ent_name": "far too long a name"}])
    with pytest.raises(KeyError, match="'data'"):
        msd.uff.write(tmp_path / "x.uff", [{"type": 58, "x": x}])
    with pytest.raises(ValueError, match="type 99"):
        msd.uff.write(tmp_path / "x.uff", [{"type": 99}])
    with pytest.raises(ValueError, match="ord_data_type"):
        msd.uff.write(tmp_path / "x.uff", [{"type": 58, "x": x, "data": data, "ord_data_type": 6}])


def same_keys(ours, theirs):
    """Every key pyuff gives has the same value in msd.uff's dict."""
    for key, value in theirs.items():
        assert key in ours, key
        if isinstance(value, str):
            assert ours[key].strip() == value.strip(), key
        else:
            np.testing.assert_array_equal(np.asarray(ours[key]), np.asarray(value), err_msg=key)


@pytest.mark.parametrize("name", ["modes_real", "modes_complex"])
def test_mode_shapes_55_read_as_pyuff_reads_them(root, name):
    path = root / f"crates/msd-uff/fixtures/pyuff/{name}.uff"
    ours = [d for d in msd.uff.read(path) if d["type"] == 55]
    theirs = [d for d in pyuff_sets(path) if d["type"] == 55]
    assert len(ours) == len(theirs) >= 2
    for a, b in zip(ours, theirs):
        same_keys(a, b)


def test_mode_shapes_55_written_for_pyuff(tmp_path):
    nodes = np.array([1, 2, 3, 10])
    normal = {"type": 55, "id1": "mode 1", "analysis_type": 2, "mode_n": 1, "freq": 51.5, "modal_m": 6.3,
              "modal_damp_vis": 0.0005, "node_nums": nodes, "r1": np.zeros(4), "r2": np.zeros(4),
              "r3": np.array([1.0, 0.7, -0.2, 0.05])}
    complex_ = {"type": 55, "analysis_type": 3, "mode_n": 2, "eig": complex(-0.3, 893.0),
                "modal_a": complex(1.0, 0.1), "modal_b": complex(0.0, 0.0), "node_nums": nodes,
                "r1": np.zeros(4, dtype=complex), "r2": np.zeros(4, dtype=complex),
                "r3": np.array([1.0, 0.5 + 0.1j, -0.3j, 0.02])}
    path = tmp_path / "shapes.uff"
    msd.uff.write(path, [normal, complex_])
    theirs = pyuff_sets(path)
    ours = msd.uff.read(path)
    assert [d["type"] for d in theirs] == [55, 55]
    for a, b in zip(ours, theirs):
        same_keys(a, b)
    assert theirs[0]["freq"] == 51.5 and list(theirs[0]["node_nums"]) == [1, 2, 3, 10]
    np.testing.assert_allclose(theirs[1]["r3"], complex_["r3"], rtol=1e-5)
    assert theirs[1]["eig"] == complex(-0.3, 893.0)
    with pytest.raises(ValueError, match="integers"):
        msd.uff.write(path, [dict(normal, node_nums=[1.5, 2, 3, 4])])
    with pytest.raises(ValueError, match="'r3' has 3 values for 4 nodes"):
        msd.uff.write(path, [dict(normal, r3=np.ones(3))])
