"""The public API: every function documented, stubs and py.typed shipped."""

import inspect
import pathlib

import pytest

import msd
from msd import _msd


def test_every_public_function_has_a_docstring():
    for name in msd.__all__:
        obj = getattr(msd, name)
        if callable(obj):
            assert inspect.getdoc(obj), name
    for name in ("read", "write", "read_skipped"):
        assert inspect.getdoc(getattr(msd.uff, name)), name
    for name in dir(_msd):
        obj = getattr(_msd, name)
        if callable(obj) and not name.startswith("_"):
            assert inspect.getdoc(obj), name


def test_stubs_and_py_typed_are_installed():
    package = pathlib.Path(msd.__file__).parent
    for name in ("py.typed", "__init__.pyi", "_msd.pyi", "uff.pyi"):
        assert (package / name).exists(), name


def test_stubs_name_every_public_function():
    package = pathlib.Path(msd.__file__).parent
    stub = (package / "__init__.pyi").read_text()
    for name in msd.__all__:
        if name != "uff":
            assert f"def {name}(" in stub or f"class {name}" in stub or f"{name} as {name}" in stub, name


def test_stubs_agree_with_the_runtime(tmp_path):
    """mypy's stubtest: every stub's signature matches the installed package's. The
    private modules have no stubs of their own (their public names are checked through
    `msd`'s stub); on Python 3.9 stubtest misreads their `typing` imports."""
    pytest.importorskip("mypy")
    import subprocess
    import sys

    allow = tmp_path / "allowlist.txt"
    allow.write_text("msd\\._convert\\..*\nmsd\\._results\\..*\n")
    done = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "msd", "--allowlist", str(allow), "--ignore-unused-allowlist"],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
