"""Conversions between Python values and what the compiled core takes (no computation)."""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np


def vector(name: str, x: Any) -> np.ndarray:
    """`x` as a contiguous 1-D float64 array (ints and float32 converted); ValueError else."""
    if x is None:
        raise ValueError(f"{name}: missing or None (expected a 1-D array of numbers)")
    try:
        a = np.asarray(x)
    except Exception as e:  # ragged lists and the like
        raise ValueError(f"{name}: expected a 1-D array of numbers ({e})") from None
    if a.dtype.kind not in "iuf":
        raise ValueError(
            f"{name}: expected real numbers (int or float), got dtype {a.dtype}"
        )
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array, got shape {a.shape}")
    return np.ascontiguousarray(a, dtype=np.float64)


def complex_vector(name: str, x: Any) -> np.ndarray:
    """`x` as a contiguous 1-D complex128 array; ValueError else."""
    try:
        a = np.asarray(x)
    except Exception as e:
        raise ValueError(f"{name}: expected a 1-D array of numbers ({e})") from None
    if a.dtype.kind not in "iufc":
        raise ValueError(f"{name}: expected numbers, got dtype {a.dtype}")
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array, got shape {a.shape}")
    return np.ascontiguousarray(a, dtype=np.complex128)


def rows(name: str, x: Any, complex_: bool = False) -> list:
    """A 1-D array (one record) or a 2-D array / list of 1-D arrays (one per record) as
    a list of contiguous 1-D arrays."""
    convert = complex_vector if complex_ else vector
    if isinstance(x, (list, tuple)) and x and not np.isscalar(x[0]):
        return [convert(f"{name}[{i}]", r) for i, r in enumerate(x)]
    try:
        a = np.asarray(x)
    except Exception as e:
        raise ValueError(f"{name}: expected an array of numbers ({e})") from None
    if a.ndim == 2:
        return [convert(f"{name}[{i}]", r) for i, r in enumerate(a)]
    return [convert(name, a)]


def _plain(value: Any) -> Any:
    """JSON-ready values: NumPy scalars and arrays, tuples, objects with to_dict."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if hasattr(value, "to_dict"):
        return value.to_dict()
    raise ValueError(f"option value {value!r} of type {type(value).__name__} is not supported")


def options_json(options: dict) -> str:
    """Keyword options as the JSON the Rust options types read (unknown keys are refused
    there, with their names)."""

    def check(value: Any, path: str) -> None:
        if isinstance(value, float) and not math.isfinite(value):
            raise ValueError(f"{path} = {value}: expected a finite number")
        if isinstance(value, dict):
            for k, v in value.items():
                check(v, f"{path}.{k}")
        elif isinstance(value, (list, tuple)):
            for i, v in enumerate(value):
                check(v, f"{path}[{i}]")

    plain = json.loads(json.dumps(options, default=_plain))
    for key, value in plain.items():
        check(value, key)
    return json.dumps(plain, allow_nan=False)


def value_json(name: str, value: Any) -> str:
    """One option's value as JSON."""
    return json.dumps(json.loads(options_json({name: value}))[name])


def jsonable(value: Any) -> Any:
    """A result's data as plain JSON types: float arrays as lists, complex numbers as
    {"re": …, "im": …}, NaN as None."""
    if isinstance(value, dict):
        return {k: jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        if np.iscomplexobj(value):
            return {"re": jsonable(value.real), "im": jsonable(value.imag), "complex": True}
        return [None if isinstance(v, float) and math.isnan(v) else v for v in value.tolist()]
    if isinstance(value, (complex, np.complexfloating)):
        return {"re": float(value.real), "im": float(value.imag)}
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and math.isnan(value):
        return None
    return value
