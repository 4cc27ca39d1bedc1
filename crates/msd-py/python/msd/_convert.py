"""Conversions between Python values and what the compiled core takes (no computation)."""

from __future__ import annotations

import json
import math
import operator
import os
from typing import Any, List, Mapping, Optional

import numpy as np


class MissingKeyError(ValueError, KeyError):
    """A key a dict argument needs is missing (``Interval.from_dict({})``, a UFF dataset
    without its 'data'), or a name asked for is not there (a channel of a fit). A
    ValueError, and a KeyError as well (what such a miss raised before)."""

    __module__ = "msd"

    def __str__(self) -> str:
        return ValueError.__str__(self)  # the message, not KeyError's repr of it


class OutOfRangeError(ValueError, IndexError):
    """An index argument outside its range (``fit.time(record=3)`` of a one-record
    fit). A ValueError, and an IndexError as well (what it raised before)."""

    __module__ = "msd"


def _shown(v: Any) -> str:
    """A non-finite sample as the toolkit writes it: NaN, inf, -inf."""
    if isinstance(v, (complex, np.complexfloating)):
        return str(complex(v))
    v = float(v)
    return "NaN" if math.isnan(v) else ("inf" if v > 0 else "-inf")


def check_finite(name: str, a: np.ndarray, role: Optional[str] = None) -> None:
    """ValueError naming `name` (and its `role`: input, output, time) and the first
    sample that is NaN or infinite."""
    if a.dtype.kind not in "fc" or a.size == 0:
        return
    bad = ~np.isfinite(a)
    if bad.any():
        i = int(np.flatnonzero(bad.ravel())[0])
        where = np.unravel_index(i, a.shape)
        index = where[0] if a.ndim == 1 else where
        what = f"{role} sample" if role else "sample"
        raise ValueError(f"{name}: {what} {index} is {_shown(a.ravel()[i])}: expected a finite number")


def vector(name: str, x: Any, role: Optional[str] = None, finite: bool = True) -> np.ndarray:
    """`x` as a contiguous 1-D float64 array (ints and float32 converted), its samples
    finite unless `finite` is False; ValueError naming `name` else."""
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
    a = np.ascontiguousarray(a, dtype=np.float64)
    if finite:
        check_finite(name, a, role)
    return a


def complex_vector(name: str, x: Any, finite: bool = True) -> np.ndarray:
    """`x` as a contiguous 1-D complex128 array, its samples finite unless `finite` is
    False; ValueError naming `name` else."""
    if x is None:
        raise ValueError(f"{name}: missing or None (expected a 1-D array of numbers)")
    try:
        a = np.asarray(x)
    except Exception as e:
        raise ValueError(f"{name}: expected a 1-D array of numbers ({e})") from None
    if a.dtype.kind not in "iufc":
        raise ValueError(f"{name}: expected numbers, got dtype {a.dtype}")
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array, got shape {a.shape}")
    a = np.ascontiguousarray(a, dtype=np.complex128)
    if finite:
        check_finite(name, a)
    return a


def rows(name: str, x: Any, complex_: bool = False, role: Optional[str] = None) -> list:
    """A 1-D array (one record) or a 2-D array / list of 1-D arrays (one per record) as
    a list of contiguous 1-D arrays, each finite (`role` as for `vector`)."""

    def convert(label: str, r: Any) -> np.ndarray:
        return complex_vector(label, r) if complex_ else vector(label, r, role)

    if x is None:
        raise ValueError(f"{name}: missing or None (expected an array of numbers)")
    if isinstance(x, (list, tuple)) and x and not np.isscalar(x[0]):
        return [convert(f"{name}[{i}]", r) for i, r in enumerate(x)]
    try:
        a = np.asarray(x)
    except Exception as e:
        raise ValueError(f"{name}: expected an array of numbers ({e})") from None
    if a.ndim == 2:
        return [convert(f"{name}[{i}]", r) for i, r in enumerate(a)]
    return [convert(name, a)]


def _kind(value: Any) -> str:
    return type(value).__name__


def mapping(name: str, value: Any, expected: str = "a dict") -> Mapping[str, Any]:
    """`value` when it is a mapping; TypeError naming `name` else."""
    if not isinstance(value, Mapping):
        raise TypeError(f"{name}: expected {expected}, got {_kind(value)} {value!r:.60}")
    return value


def items(name: str, value: Any, expected: str) -> List[Any]:
    """The items of the sequence (or other iterable, not a string or a dict) `value`;
    TypeError naming `name` else."""
    if isinstance(value, (str, bytes, Mapping)) or value is None:
        raise TypeError(f"{name}: expected {expected}, got {_kind(value)} {value!r:.60}")
    try:
        return list(value)
    except TypeError:
        raise TypeError(f"{name}: expected {expected}, got {_kind(value)} {value!r:.60}") from None


def field(owner: str, d: Any, key: str, expected: str = "") -> Any:
    """`d[key]`: TypeError when `d` is not a dict, MissingKeyError (a ValueError) naming
    the key when it has none."""
    mapping(owner, d)
    try:
        return d[key]
    except KeyError:
        keys = ", ".join(repr(k) for k in d) or "none"
        hint = f" ({expected})" if expected else ""
        raise MissingKeyError(f"{owner}: missing key {key!r}{hint}; its keys are {keys}") from None


def integer(name: str, value: Any, low: Optional[int] = 0, high: Optional[int] = None) -> int:
    """The integer argument `name` within [low, high] (None: unbounded): an int, a
    NumPy integer or a float with a whole value. ValueError naming it when out of range
    or not whole, TypeError for any other type (a bool, a string, None)."""

    def refuse() -> ValueError:
        if low is not None and high is not None:
            span = f" from {low} to {high}"
        elif low is not None:
            span = f" ≥ {low}"
        elif high is not None:
            span = f" ≤ {high}"
        else:
            span = ""
        return ValueError(f"{name} = {value!r:.60}: expected an integer{span}")

    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} = {value!r}: expected an integer, got bool")
    try:
        n = operator.index(value)
    except TypeError:
        if isinstance(value, (float, np.floating)):
            if not (math.isfinite(value) and float(value).is_integer()):
                raise refuse() from None
            n = int(value)
        else:
            raise TypeError(f"{name} = {value!r:.60}: expected an integer, got {_kind(value)}") from None
    if (low is not None and n < low) or (high is not None and n > high):
        raise refuse()
    return n


def number(name: str, value: Any) -> float:
    """The real-number argument `name` as a float: TypeError (not a number) or
    ValueError (a string that is not one) naming it (NaN and infinities pass: the
    toolkit says what range it expects)."""
    try:
        return float(value)
    except TypeError:
        raise TypeError(f"{name} = {value!r:.60}: expected a number, got {_kind(value)}") from None
    except ValueError:
        raise ValueError(f"{name} = {value!r:.60}: expected a number") from None


def text(name: str, value: Any) -> str:
    """The string argument `name`; TypeError naming it for anything else."""
    if not isinstance(value, str):
        raise TypeError(f"{name} = {value!r:.60}: expected a string, got {_kind(value)}")
    return value


def path(name: str, value: Any) -> str:
    """A path argument as a string; TypeError naming it for anything else."""
    try:
        return os.fspath(value)
    except TypeError:
        raise TypeError(f"{name}: expected a path (str or os.PathLike), got {_kind(value)} {value!r:.60}") from None


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
        if isinstance(value, int) and not isinstance(value, bool):
            try:
                float(value)
            except OverflowError:  # beyond what the JSON reader takes (1.8e308)
                raise ValueError(f"{path} = {value!r:.24}…: expected a number below 1.8e308") from None
        if isinstance(value, dict):
            for k, v in value.items():
                check(v, f"{path}.{k}")
        elif isinstance(value, (list, tuple)):
            for i, v in enumerate(value):
                check(v, f"{path}[{i}]")

    plain = {}
    for key, value in options.items():
        try:
            plain[key] = json.loads(json.dumps(value, default=_plain))
        except (TypeError, ValueError) as e:
            raise type(e)(f"{key}: {e}") from None
        check(plain[key], key)
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
