"""The Python examples run (examples/python/), each writing its figure."""

import os
import subprocess
import sys

import pytest

from conftest import require

pytest.importorskip("matplotlib")


def run_example(root, name, tmp_path):
    figure = tmp_path / f"{name}.png"
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run(
        [sys.executable, str(root / "examples/python" / f"{name}.py"), str(figure)],
        env=env, capture_output=True, text=True, timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert figure.stat().st_size > 10_000
    return done.stdout


def test_paper_example(root, tmp_path):
    out = run_example(root, "paper", tmp_path)
    assert "m = 2.49" in out


def test_impact_frf_example(root, tmp_path):
    require(root / "data/impact-frf/meas_point_1.txt", "cargo xtask fetch-data impact-frf", "MSD_REQUIRE_REAL_DATA")
    out = run_example(root, "impact_frf", tmp_path)
    assert "mode 6" in out


def test_a_fleet_on_dask_equals_the_serial_loop(root):
    """examples/python/oma_fleet_dask.py: six records on a two-worker local Dask cluster,
    the results equal to the serial loop's (the script asserts it)."""
    pytest.importorskip("dask.distributed")
    pytest.importorskip("scipy")
    done = subprocess.run(
        [sys.executable, str(root / "examples/python/oma_fleet_dask.py")],
        capture_output=True, text=True, timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "the cluster's results equal the serial loop's" in done.stdout
    assert done.stdout.count(" Hz") >= 6 * 5
