"""The Python examples of the READMEs run as written (from a folder that sees the
repository's configs/ and data/, so that their outputs land in a temporary folder)."""

import os
import re

import pytest

from conftest import require


def python_blocks(text: str):
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def run_in(folder, root, code):
    for name in ("configs", "data", "crates"):
        (folder / name).symlink_to(root / name)
    here = os.getcwd()
    os.chdir(folder)
    try:
        exec(compile(code, "README", "exec"), {})
    finally:
        os.chdir(here)


def test_the_packages_readme(root, tmp_path):
    require(root / "data/impact-frf/meas_point_1.txt", "cargo xtask fetch-data impact-frf", "MSD_REQUIRE_REAL_DATA")
    blocks = python_blocks((root / "crates/msd-py/README.md").read_text())
    assert len(blocks) == 1
    run_in(tmp_path, root, blocks[0])
    assert (tmp_path / "msd-results/paper/results.json").exists()


def test_the_python_section_of_the_root_readme(root, tmp_path):
    text = (root / "README.md").read_text()
    section = text[text.index("## Python\n"): text.index("\n## ", text.index("## Python\n") + 1)]
    blocks = python_blocks(section)
    assert len(blocks) == 1
    run_in(tmp_path, root, blocks[0])
    assert (tmp_path / "results/paper/results.json").exists()
    assert (tmp_path / "results/lab/results.json").exists()  # the dict config, data in memory
