"""msd.run, msd.plan and msd.design against the Rust command's results."""

import json
import os

import pytest

import msd
from conftest import require


def differences(a, b, path=""):
    """Paths where two results.json trees differ, timings left out."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            if k == "timings_ms":
                continue
            if k not in a or k not in b:
                out.append(f"{path}/{k} (only in one)")
            else:
                out += differences(a[k], b[k], f"{path}/{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path} (lengths {len(a)}, {len(b)})"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, f"{path}[{i}]")]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


def test_run_equals_cargo_xtask_experiment(root, tmp_path):
    """`cargo xtask experiment configs/paper.toml` (which CI runs before these tests)
    and msd.run of the same config and seed give the same results.json, timings aside."""
    reference = root / "target/experiments/paper/results.json"
    require(reference, "cargo xtask experiment configs/paper.toml", "MSD_REQUIRE_RUST_RESULTS")
    results = msd.run(root / "configs/paper.toml", out=tmp_path / "paper")
    rust = json.loads(reference.read_text())
    assert differences(results, rust) == []
    written = json.loads((tmp_path / "paper/results.json").read_text())
    assert differences(written, results) == []


def test_run_writes_the_folder_and_takes_seed_and_threads(root, tmp_path):
    results = msd.run(str(root / "configs/paper-fast.toml"), out=tmp_path / "fast", seed=5, threads=1)
    assert results["experiment"]["seed"] == 5
    assert results["experiment"]["threads"] == 1
    assert results.out_dir == str(tmp_path / "fast")
    for name in ("report.html", "report.md", "results.json", ".msd-results", "identification.csv"):
        assert (tmp_path / "fast" / name).exists(), name
    assert "experiment `paper-fast`" in results.summary
    assert "<pre>" in results._repr_html_() and str(tmp_path / "fast") in results._repr_html_()
    other = msd.run(root / "configs/paper-fast.toml", out=tmp_path / "fast", seed=6)
    assert other["estimate"]["mass"]["value"] != results["estimate"]["mass"]["value"]


def test_run_errors(root, tmp_path):
    with pytest.raises(ValueError, match="missing.toml"):
        msd.run(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "bad"\n[plant]\nmass = -1.0\ndamping = 1.0\nstiffness = 1.0\n')
    with pytest.raises(ValueError, match="bad.toml"):
        msd.run(bad, out=tmp_path / "out")
    unknown = tmp_path / "unknown.toml"
    unknown.write_text('name = "x"\nnoise_level = 3\n')
    with pytest.raises(ValueError, match="noise_level"):
        msd.run(unknown, out=tmp_path / "out")
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("my measurement")
    with pytest.raises(ValueError, match="mine"):
        msd.run(root / "configs/paper-fast.toml", out=mine)
    assert (mine / "notes.txt").read_text() == "my measurement"


def test_plan(root):
    plan = msd.plan(root / "configs/free-decay.toml")
    names = [q["name"] for q in plan.data["quantities"]]
    assert "damping" in names and "mass" not in names
    assert "mass known" in repr(plan)
    with pytest.raises(ValueError, match="--target"):
        msd.plan(root / "configs/free-decay.toml", target=-1.0)


def test_design(root, tmp_path):
    report = msd.design(root / "configs/design-paper.toml", out=tmp_path / "design")
    assert report.data["out_dir"] == str(tmp_path / "design")
    assert (tmp_path / "design/designed.toml").exists()
    assert "D-optimal" in repr(report)
    again = msd.design(root / "configs/design-paper.toml", write=False)
    assert again.data["out_dir"] is None
    assert again.data["design"] == report.data["design"]
    with pytest.raises(ValueError, match="design needs a \\[design\\] section"):
        msd.design(root / "configs/paper.toml", write=False)
