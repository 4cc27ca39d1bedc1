"""Universal File Format files (msd-uff): dataset 58 and 58b functions (FRFs, spectra,
coherences, time records), 55 data at nodes (mode shapes), the 151 header, the 164 units
and the 15/2411 nodes, as dicts keyed as pyuff keys them, with NumPy arrays.

`read(path)` returns a list of dicts like ``pyuff.UFF(path).read_sets()``; `write(path,
datasets)` writes such dicts. Other datasets are skipped on reading (`read_skipped`
lists them with their byte offsets).
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Mapping, Sequence, Union

import numpy as np

from . import _msd
from ._convert import MissingKeyError, check_finite, integer, items, path as _path

__all__ = ["read", "read_skipped", "write"]

PathLike = Union[str, "os.PathLike[str]"]


def read(path: PathLike) -> List[Dict[str, Any]]:
    """Read a UFF file: one dict per dataset (151, 164, the nodes of 15 or 2411, every
    55, then every 58/58b function), with pyuff's keys ('type', 'x', 'data', 'id1'…'id5',
    'func_type', 'rsp_node', 'rsp_dir', 'ref_node', 'ref_dir', 'ord_data_type',
    'abscissa_spacing', 'binary', the four axes' '*_spec_data_type', '*_axis_lab', …).
    'data' is float64 for real and complex128 for complex functions.

    Raises FileNotFoundError/OSError when the file cannot be read, ValueError with the
    byte offset, line and dataset when it is malformed.
    """
    datasets, _ = _msd.uff_read(_path("path", path))
    return datasets


def read_skipped(path: PathLike) -> List[Dict[str, Any]]:
    """The datasets `read` skips (types other than 15, 55, 58, 151, 164, 2411), each
    with its 'type', byte 'offset', 'line' and a 'note'."""
    _, skipped = _msd.uff_read(_path("path", path))
    return skipped


def _function(i: int, d: Mapping[str, Any]) -> Dict[str, Any]:
    """A dataset 58 dict normalised for the core: 'data' as float64 or complex128,
    'x' as float64, the abscissa spacing decided when not given."""
    out = dict(d)
    if "data" not in d:
        raise MissingKeyError(f"datasets[{i}] (type 58) needs the field 'data'")
    data = np.asarray(d["data"])
    if data.ndim != 1 or data.dtype.kind not in "iufc":
        raise ValueError(f"datasets[{i}]['data']: expected a 1-D array of numbers, got {data.dtype} {data.shape}")
    complex_ = data.dtype.kind == "c"
    out["data"] = np.ascontiguousarray(data, dtype=np.complex128 if complex_ else np.float64)
    out["_complex"] = complex_
    x = d.get("x")
    if x is not None:
        x = np.ascontiguousarray(np.asarray(x), dtype=np.float64)
        if x.ndim != 1 or len(x) != len(data):
            raise ValueError(f"datasets[{i}]['x']: expected {len(data)} abscissa values, got shape {x.shape}")
        out["x"] = x
    spacing = d.get("abscissa_spacing")
    if spacing is None:
        if x is None:
            spacing = 1
        else:
            step = (x[-1] - x[0]) / (len(x) - 1) if len(x) > 1 else 1.0
            spacing = int(len(x) < 2 or bool(np.allclose(np.diff(x), step, rtol=1e-9, atol=0.0)))
    out["abscissa_spacing"] = integer(f"datasets[{i}]['abscissa_spacing']", spacing, 0, 1)
    if out["abscissa_spacing"] == 1:
        if "abscissa_min" not in d or d.get("abscissa_min") is None:
            if x is None or len(x) == 0:
                raise MissingKeyError(f"datasets[{i}]: give 'x' or 'abscissa_min' and 'abscissa_inc'")
            out["abscissa_min"] = float(x[0])
        if "abscissa_inc" not in d or d.get("abscissa_inc") is None:
            if x is None or len(x) < 2:
                raise MissingKeyError(f"datasets[{i}]: give 'x' (2 values or more) or 'abscissa_inc'")
            out["abscissa_inc"] = float(x[1] - x[0])
    elif x is None:
        raise MissingKeyError(f"datasets[{i}]: an uneven abscissa (abscissa_spacing 0) needs 'x'")
    return out


def _nodes(i: int, d: Mapping[str, Any]) -> Dict[str, Any]:
    out = dict(d)
    if d.get("node_nums") is None:
        raise MissingKeyError(f"datasets[{i}] (type {d.get('type')}) needs the field 'node_nums'")
    for key in ("node_nums", "def_cs", "disp_cs", "color", "x", "y", "z"):
        if d.get(key) is not None:
            a = np.asarray(d[key])
            if a.ndim != 1 or a.dtype.kind not in "iuf":
                raise ValueError(f"datasets[{i}][{key!r}]: expected a 1-D array of numbers")
            out[key] = np.ascontiguousarray(a, dtype=np.float64)
    return out


def _data55(i: int, d: Mapping[str, Any]) -> Dict[str, Any]:
    """A dataset 55 dict normalised for the core: 'node_nums' as ints, 'r1'…'rN' as
    float64 or complex128 (complex when any is)."""
    out = dict(d)
    if "node_nums" not in d:
        raise MissingKeyError(f"datasets[{i}] (type 55) needs the field 'node_nums'")
    nodes = np.asarray(d["node_nums"])
    if nodes.ndim != 1 or nodes.dtype.kind not in "iuf" or (nodes.size and np.any(nodes != np.round(nodes))):
        raise ValueError(f"datasets[{i}]['node_nums']: expected a 1-D array of integers")
    out["node_nums"] = [int(n) for n in nodes]
    given = d.get("n_data_per_node")
    per_node = integer(f"datasets[{i}]['n_data_per_node']", given, 1) if given is not None else (6 if "r4" in d else 3)
    columns = []
    for k in range(1, per_node + 1):
        if f"r{k}" not in d:
            told = "" if given is None else f" (n_data_per_node = {per_node})"
            raise MissingKeyError(f"datasets[{i}] (type 55) needs the field 'r{k}'{told}")
        a = np.asarray(d[f"r{k}"])
        if a.ndim != 1 or a.dtype.kind not in "iufc":
            raise ValueError(f"datasets[{i}]['r{k}']: expected a 1-D array of numbers")
        columns.append(a)
    complex_ = any(a.dtype.kind == "c" for a in columns) or d.get("data_type") == 5
    for k, a in enumerate(columns, 1):
        out[f"r{k}"] = np.ascontiguousarray(a, dtype=np.complex128 if complex_ else np.float64)
    out["n_data_per_node"] = per_node
    out["_complex"] = complex_
    return out


def _finite(i: int, d: Mapping[str, Any]) -> None:
    """ValueError naming the field of dataset `i` that holds a NaN or an infinity (UFF
    has no such numbers: written, they read back as garbage or not at all)."""
    for key, value in d.items():
        if isinstance(value, (str, bytes)) or value is None:
            continue
        if isinstance(value, (float, complex, np.floating, np.complexfloating)):
            if not np.isfinite(value):
                raise ValueError(f"datasets[{i}][{key!r}] = {value}: expected a finite number")
        elif isinstance(value, (np.ndarray, list, tuple)):
            try:
                a = np.asarray(value)
            except Exception:  # ragged: the field's own check says so
                continue
            if a.dtype.kind in "fc":
                check_finite(f"datasets[{i}][{key!r}]", a)


def write(path: PathLike, datasets: Sequence[Mapping[str, Any]], *, exact: bool = False) -> None:
    """Write dataset dicts (as `read` returns them, or as written for pyuff) to a UFF
    file: 151, 164, 15/2411, 55, then 58 (58b when 'binary' is 1). Missing fields take the
    format's "unused" values; for a 58 only 'data' and the abscissa ('x', or
    'abscissa_min' and 'abscissa_inc') are needed; 'abscissa_spacing' (1 even, 0 uneven)
    is decided from 'x' when not given. `exact`: every ASCII number in 25 columns that
    reads back identically (readers that split on blanks read these; pyuff's
    fixed-column reader does not); by default the format's columns.

    Raises ValueError naming the dataset and field: a value that is NaN or infinite, a
    missing field (MissingKeyError, also a KeyError), a value of the wrong type or range.
    """
    if isinstance(datasets, Mapping):
        datasets = [datasets]
    ready = []
    for i, d in enumerate(items("datasets", datasets, "a list of dataset dicts")):
        if not isinstance(d, Mapping):
            raise ValueError(f"datasets[{i}]: expected a dict")
        if d.get("type") is None:
            raise MissingKeyError(f"datasets[{i}] needs the field 'type' (58, 55, 151, 164, 15 or 2411)")
        _finite(i, d)
        kind = d.get("type")
        if kind == 58:
            ready.append(_function(i, d))
        elif kind in (15, 2411):
            ready.append(_nodes(i, d))
        elif kind == 55:
            ready.append(_data55(i, d))
        else:
            ready.append(dict(d))
    _msd.uff_write(_path("path", path), ready, bool(exact))
