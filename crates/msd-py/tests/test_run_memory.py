"""msd.run on a config dict and data held in memory (NumPy columns, or a file's bytes),
for every experiment kind, against the same config run from its TOML file as the `msd`
command runs it: the same results.json, number for number.

Each case writes its data files into a folder and its config (the shipped one, with the
data paths pointed there) beside them, runs that file (`run_experiment`, the command's
path), then runs the config as a dict with every data file given in memory under a
short name that exists nowhere on disk."""

import csv
import io
import os
import pathlib
import shutil
import tomllib

import numpy as np
import pytest

import msd
from conftest import require


def columns_of(path: pathlib.Path) -> dict:
    """A CSV file with a header as named float columns (`#` comments and unnamed
    columns, as a trailing comma makes, skipped)."""
    lines = [l for l in path.read_text().splitlines() if l.strip() and not l.startswith("#")]
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    names, body = rows[0], rows[1:]
    return {n.strip(): np.array([float(r[i]) for r in body]) for i, n in enumerate(names) if n.strip()}


def leaves(tree, path=""):
    """Every leaf of a results tree by its path, timings left out."""
    if isinstance(tree, dict):
        for k, v in tree.items():
            if k != "timings_ms":
                yield from leaves(v, f"{path}/{k}")
    elif isinstance(tree, list):
        for i, v in enumerate(tree):
            yield from leaves(v, f"{path}[{i}]")
    else:
        yield path, tree


def compare(from_file: dict, in_memory: dict, folder: pathlib.Path) -> list:
    """Where the two results differ; the file run's strings name the files by their
    folder, the memory run's by the bare name."""
    prefix = str(folder) + os.sep
    a = {k: v.replace(prefix, "") if isinstance(v, str) else v for k, v in leaves(from_file)}
    b = dict(leaves(in_memory))
    return [f"{k}: {a.get(k)!r} != {b.get(k)!r}" for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]


def run_both(root, tmp_path, config, files, arrays=True):
    """Runs `config` (a shipped config's path) with its data `files` ({key path: the file
    to give}) from disk and from memory; returns both results."""
    folder = tmp_path / "files"
    folder.mkdir()
    text = (root / config).read_text()
    cfg = tomllib.loads(text)
    on_disk = {}
    in_memory = {}
    for keys, source in files.items():
        name = pathlib.Path(source).name
        shutil.copy(source, folder / name)
        on_disk[keys] = str(folder / name)
        given = columns_of(folder / name) if arrays and name.endswith(".csv") else (folder / name).read_bytes()
        in_memory[name] = given
        set_path(cfg, keys, name)
    disk_cfg = tomllib.loads(text)
    for keys, path in on_disk.items():
        set_path(disk_cfg, keys, path)
    file_config = folder / "config.toml"
    file_config.write_text(toml_of(disk_cfg))
    a = msd.run(file_config, out=tmp_path / "file")
    b = msd.run(cfg, out=tmp_path / "memory", data=in_memory)
    return a, b, folder


def set_path(cfg: dict, keys: str, value: str) -> None:
    """Sets `cfg`'s dotted `keys` (`data.path[2]` for a list entry) to `value`."""
    *parents, last = keys.split(".")
    for k in parents:
        cfg = cfg[k]
    if last.endswith("]"):
        name, index = last[:-1].split("[")
        cfg[name][int(index)] = value
    else:
        cfg[last] = value


def toml_of(cfg: dict, prefix: str = "") -> str:
    """A config dict as TOML (tables, lists, strings, numbers, booleans, inline tables)."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, float):
            return repr(v) if np.isfinite(v) else ("inf" if v > 0 else "-inf")
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + "}"
        return str(v)

    plain = {k: v for k, v in cfg.items() if not isinstance(v, dict)}
    out = "".join(f"{k} = {value(v)}\n" for k, v in plain.items())
    for k, v in cfg.items():
        if isinstance(v, dict):
            out += f"\n[{prefix}{k}]\n" + toml_of(v, f"{prefix}{k}.")
    return out


@pytest.mark.parametrize(
    "kind", ["accelerometer", "base-excitation", "free-decay", "repeats", "damper-test-machine"]
)
def test_setups_run_on_columns_in_memory(root, tmp_path, kind):
    """The lab setups (force, base, free decay, repeats, the test machine): each record
    that the synthetic config's run writes given as NumPy columns to its template."""
    out = tmp_path / "synthetic"
    msd.run(root / f"configs/{kind}.toml", out=out)
    config = f"configs/templates/{kind}.toml"
    given = tomllib.loads((root / config).read_text())["data"]["path"]
    paths = [given] if isinstance(given, str) else given
    keys = ["data.path"] if isinstance(given, str) else [f"data.path[{i}]" for i in range(len(given))]
    records = [out / pathlib.Path(p).name for p in paths]
    a, b, folder = run_both(root, tmp_path, config, dict(zip(keys, records)))
    assert compare(a, b, folder) == []
    assert b["experiment"]["kind"] == a["experiment"]["kind"]


def test_the_paper_kind_runs_on_columns_in_memory(root, tmp_path):
    """A measured force and displacement (the paper's kind, with residual tests,
    validation and the Monte Carlo band): the Silverbox record as columns."""
    silverbox = root / "data/silverbox/SNLS80mV.csv"
    require(silverbox, "cargo xtask fetch-data silverbox", "MSD_REQUIRE_REAL_DATA")
    a, b, folder = run_both(root, tmp_path, "configs/silverbox.toml", {"data.path": silverbox})
    assert compare(a, b, folder) == []
    assert a["estimate"]["mass"]["value"] == b["estimate"]["mass"]["value"]


@pytest.mark.parametrize(
    "config, keys, file, arrays",
    [
        ("configs/frf-table.toml", "frequency_response.table.path", "configs/data/stepped-sine-table.csv", True),
        ("configs/frf-uff.toml", "frequency_response.uff.path", "configs/data/frf-2dof.uff", False),
        ("configs/roving-hammer-beam.toml", "frequency_response.uff.path", "configs/data/roving-hammer-beam.uff", False),
    ],
)
def test_frequency_responses_run_from_memory(root, tmp_path, config, keys, file, arrays):
    """A table of an FRF as columns; a UFF file (one FRF, a roving-hammer set) as bytes."""
    cfg = tomllib.loads((root / config).read_text())
    files = {keys: root / file}
    # The roving-hammer beam also reads its model's shapes.
    if "reference_shapes" in cfg.get("frequency_response", {}):
        files["frequency_response.reference_shapes"] = root / "configs" / cfg["frequency_response"]["reference_shapes"]
    a, b, folder = run_both(root, tmp_path, config, files, arrays)
    assert compare(a, b, folder) == []
    assert len(b["modes"] if "modes" in b else [b["estimate"]]) >= 1


def test_a_chain_runs_from_a_dict(root, tmp_path):
    """A chain of masses (synthetic: no data file) from its config as a dict."""
    a, b, folder = run_both(root, tmp_path, "configs/two-storey.toml", {})
    assert compare(a, b, folder) == []
    assert len(b["fit"]["modes"]) == 2


def test_a_measured_chain_runs_on_columns_in_memory(root, tmp_path):
    """A chain's measured record (the drive's column and each sensor's): the synthetic
    two-storey run's record.csv given as NumPy columns to its template."""
    out = tmp_path / "synthetic"
    msd.run(root / "configs/two-storey.toml", out=out)
    a, b, folder = run_both(root, tmp_path, "configs/templates/two-storey.toml", {"data.path": out / "record.csv"})
    assert compare(a, b, folder) == []
    assert a["experiment"]["kind"] == b["experiment"]["kind"] == "measured"
    assert len(b["fit"]["modes"]) == 2


def test_output_only_analysis_runs_from_memory(root, tmp_path):
    """Output-only modal analysis: a simulated building from its dict alone, and the real
    steel frame's pyOMA setup (the `.npy` record, its channel and setup files, the
    geometry) given as bytes."""
    a, b, folder = run_both(root, tmp_path, "configs/shear-building.toml", {})
    assert compare(a, b, folder) == []
    frame = root / "data/steel-frame"
    require(frame / "measurement_1/measurement_1.npy", "cargo xtask fetch-data steel-frame", "MSD_REQUIRE_REAL_DATA")
    files = {
        "operational.record.path": frame / "measurement_1/measurement_1.npy",
        "operational.record.channel_dofs": frame / "measurement_1/channel_dofs.txt",
        "operational.record.setup_info": frame / "measurement_1/setup_info.txt",
        "operational.geometry.nodes": frame / "grid.txt",
        "operational.geometry.lines": frame / "lines.txt",
    }
    (tmp_path / "frame").mkdir()
    a, b, folder = run_both(root, tmp_path / "frame", "configs/steel-frame.toml", files)
    assert compare(a, b, folder) == []
    assert len(b["modes"]) == len(a["modes"]) >= 5


def test_memory_errors_name_the_file_and_key(root, tmp_path):
    cfg = tomllib.loads((root / "configs/templates/accelerometer.toml").read_text())
    cfg["data"]["path"] = "shaker.csv"
    t = np.arange(1000) / 500.0
    data = {"shaker.csv": {"t": t, "force": np.sin(t), "displacement": 0 * t}}
    with pytest.raises(ValueError, match=r"shaker.csv.*setup.responses\[1\].column = `acceleration`: no such column"):
        msd.run(cfg, out=tmp_path / "x", data=data)
    data["shaker.csv"]["acceleration"] = np.where(t > 1, np.nan, 0 * t)
    with pytest.raises(ValueError, match=r"acceleration`, row 501 \(0-based\): NaN: expected a finite number"):
        msd.run(cfg, out=tmp_path / "x", data=data)
    with pytest.raises(ValueError, match=r"data\['shaker.csv'\]: expected the file's bytes"):
        msd.run(cfg, out=tmp_path / "x", data={"shaker.csv": "t,force"})
    cfg["monte_carlo"] = {"sampels": 3}
    with pytest.raises(ValueError, match="sampels"):
        msd.run(cfg, out=tmp_path / "x", data=data)
    assert not (tmp_path / "x").exists()
