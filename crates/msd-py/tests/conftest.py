"""Shared fixtures: the repository's root, the paper's records, skips for missing data."""

import os
import pathlib

import numpy as np
import pytest

import msd

ROOT = pathlib.Path(__file__).resolve().parents[3]


def require(path: pathlib.Path, why: str, variable: str) -> None:
    """Skip when `path` is missing, or fail when the environment variable says it must
    be there (CI sets them)."""
    if path.exists():
        return
    message = f"{path} is missing ({why})"
    if os.environ.get(variable) == "1":
        pytest.fail(message + f"; {variable}=1 requires it")
    pytest.skip(message)


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def paper():
    """The paper's records, seed 1."""
    return msd.paper_data(1)


@pytest.fixture(scope="session")
def ident(paper):
    d = paper["identification"]
    return d["t"], d["force"], d["displacement"]


def write_csv(path: pathlib.Path, columns: dict) -> None:
    """Columns as CSV with every float's shortest exact text (read back bit for bit)."""
    names = list(columns)
    values = [np.asarray(columns[n], dtype=float).tolist() for n in names]
    with open(path, "w") as fh:
        fh.write(",".join(names) + "\n")
        for row in zip(*values):
            fh.write(",".join(repr(v) for v in row) + "\n")
