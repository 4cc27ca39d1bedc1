//! Conversions between Python objects and the crates' types.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList};
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;

/// The values of a 1-D float64 array (any strides) as a vector.
pub fn vec_f64(a: &PyReadonlyArray1<'_, f64>) -> Vec<f64> {
    match a.as_slice() {
        Ok(s) => s.to_vec(),
        Err(_) => a.as_array().iter().copied().collect(),
    }
}

/// Options from their JSON text (written by the Python layer from keyword arguments):
/// unknown keys and values of the wrong type are refused with serde's message and the
/// key it refused (`frf options: welch.segment_length = -1: expected an integer from 0
/// to 18446744073709551615`).
pub fn options<T: DeserializeOwned>(what: &str, json: &str) -> PyResult<T> {
    let mut v: Value =
        serde_json::from_str(json).map_err(|e| PyValueError::new_err(format!("{what}: {e}")))?;
    drop_nulls(&mut v);
    serde_path_to_error::deserialize(v).map_err(|e| {
        let path = e.path().to_string();
        PyValueError::new_err(refusal(what, &path, &strip_position(e.inner())))
    })
}

/// serde's refusal of the value at `path` (`.` or empty: the whole value) in words: a
/// value of the wrong type or range as `what: path = value: expected …`, anything else
/// (an unknown field or variant, a missing field) as `what: message (key `path`)`.
fn refusal(what: &str, path: &str, message: &str) -> String {
    if path.is_empty() || path == "." {
        return format!("{what}: {}", in_words(message));
    }
    match refused_value(message) {
        Some((value, expected)) => {
            format!(
                "{what}: {path} = {value}: expected {}",
                type_in_words(expected)
            )
        }
        None => format!("{what}: {} (key `{path}`)", in_words(message)),
    }
}

/// The value and the expectation of serde's `invalid value: integer `-1`, expected usize`
/// or `invalid type: string "x", expected f64`.
fn refused_value(message: &str) -> Option<(&str, &str)> {
    let rest = message
        .strip_prefix("invalid value: ")
        .or_else(|| message.strip_prefix("invalid type: "))?;
    let (value, after) = if let Some(i) = rest.find('`') {
        let tail = &rest[i + 1..];
        let j = tail.find('`')?;
        (&tail[..j], &tail[j + 1..])
    } else if let Some(tail) = rest.strip_prefix("string ") {
        let j = tail.rfind("\", expected ")?;
        (&tail[..=j], &tail[j + 1..])
    } else {
        return None;
    };
    let expected = after.strip_prefix(", expected ")?;
    Some((value, expected))
}

/// A message whose trailing `expected usize` (`u32`, `f64`, …) is said in words.
fn in_words(message: &str) -> String {
    match message.rfind(", expected ") {
        Some(i) => {
            let (head, expected) = (&message[..i], &message[i + ", expected ".len()..]);
            format!("{head}, expected {}", type_in_words(expected))
        }
        None => message.to_string(),
    }
}

/// A Rust number type's name in words (`usize`: an integer from 0 to 2⁶⁴ − 1), any
/// other expectation unchanged.
fn type_in_words(expected: &str) -> String {
    let (min, max): (i128, i128) = match expected {
        "usize" | "u64" => (0, u64::MAX.into()),
        "u32" => (0, u32::MAX.into()),
        "u16" => (0, u16::MAX.into()),
        "u8" => (0, u8::MAX.into()),
        "isize" | "i64" => (i64::MIN.into(), i64::MAX.into()),
        "i32" => (i32::MIN.into(), i32::MAX.into()),
        "i16" => (i16::MIN.into(), i16::MAX.into()),
        "i8" => (i8::MIN.into(), i8::MAX.into()),
        "f64" | "f32" => return "a number".into(),
        other => return other.into(),
    };
    integer_range(min, max)
}

fn integer_range(min: i128, max: i128) -> String {
    format!("an integer from {min} to {max}")
}

/// An integer type an argument converts to, with its range.
pub trait Integer: TryFrom<i128> {
    /// The smallest value.
    const MIN: i128;
    /// The largest value.
    const MAX: i128;
}

macro_rules! integer_types {
    ($($t:ty),*) => {
        $(impl Integer for $t {
            const MIN: i128 = <$t>::MIN as i128;
            const MAX: i128 = <$t>::MAX as i128;
        })*
    };
}
integer_types!(u32, i32, u64, usize);

/// The integer argument `name` as `T`: see [`integer_in`].
pub fn integer<T: Integer>(name: &str, value: &Bound<'_, PyAny>) -> PyResult<T> {
    integer_in(name, value, T::MIN, T::MAX)
}

/// The integer argument `name` within `min..=max` (and `T`'s range): a Python int (or
/// NumPy integer, or a float with a whole value). A value out of range or not whole is
/// a `ValueError`, any other type (a bool, a string, None) a `TypeError`, each naming
/// the argument (where pyo3 would raise an `OverflowError` naming nothing).
pub fn integer_in<T: Integer>(
    name: &str,
    value: &Bound<'_, PyAny>,
    min: i128,
    max: i128,
) -> PyResult<T> {
    let (min, max) = (min.max(T::MIN), max.min(T::MAX));
    let py = value.py();
    let shown = || {
        value
            .repr()
            .map(|r| r.to_string())
            .unwrap_or_else(|_| "?".into())
    };
    let refuse = || {
        PyValueError::new_err(format!(
            "{name} = {}: expected {}",
            shown(),
            integer_range(min, max)
        ))
    };
    let wrong_type = || {
        let kind = value
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".into());
        PyTypeError::new_err(format!(
            "{name} = {}: expected an integer, got {kind}",
            shown()
        ))
    };
    if value.is_instance_of::<PyBool>() {
        return Err(wrong_type());
    }
    let n: i128 = match value.extract::<i128>() {
        Ok(n) => n,
        Err(e) if e.is_instance_of::<PyOverflowError>(py) => return Err(refuse()),
        Err(_) => match value.extract::<f64>() {
            Ok(x) if x.is_finite() && x.fract() == 0.0 && x.abs() < 1e38 => x as i128,
            Ok(_) => return Err(refuse()),
            Err(_) => return Err(wrong_type()),
        },
    };
    if !(min..=max).contains(&n) {
        return Err(refuse());
    }
    T::try_from(n).map_err(|_| refuse())
}

/// serde_json's message without " at line 1 column 42" (the JSON is ours, not the user's).
fn strip_position(e: &serde_json::Error) -> String {
    let text = e.to_string();
    match text.rfind(" at line ") {
        Some(i) => text[..i].to_string(),
        None => text,
    }
}

/// Removes the null members of every object (serde writes `None` as null, and some
/// options read an absent key as `None` but refuse null).
fn drop_nulls(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|_, item| !item.is_null());
            map.values_mut().for_each(drop_nulls);
        }
        Value::Array(items) => items.iter_mut().for_each(drop_nulls),
        _ => {}
    }
}

/// A JSON object's text merged onto `base` (its keys replace base's, one level deep),
/// null members dropped (an absent key takes the default).
pub fn merged(base: Value, json: &str) -> PyResult<Value> {
    let given: Value =
        serde_json::from_str(json).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let (Value::Object(mut base), Value::Object(given)) = (base, given) else {
        return Err(PyValueError::new_err("options must be a mapping"));
    };
    for (k, v) in given {
        base.insert(k, v);
    }
    let mut v = Value::Object(base);
    drop_nulls(&mut v);
    Ok(v)
}

/// A serde value as Python objects: objects as dicts, arrays as lists, null as None.
pub fn value_to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(value_to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, item) in map {
                dict.set_item(k, value_to_py(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// A serializable result as a Python dict, the top-level keys in `arrays` (lists of
/// numbers) as float64 NumPy arrays (a null, serde's NaN, as NaN).
pub fn result_dict<'py, T: Serialize>(
    py: Python<'py>,
    value: &T,
    arrays: &[&str],
) -> PyResult<Bound<'py, PyDict>> {
    let mut v = serde_json::to_value(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    let mut taken = Vec::new();
    if let Value::Object(map) = &mut v {
        for key in arrays {
            if let Some(Value::Array(items)) = map.remove(*key) {
                let numbers: Vec<f64> = items
                    .iter()
                    .map(|x| x.as_f64().unwrap_or(f64::NAN))
                    .collect();
                taken.push((*key, numbers));
            }
        }
    }
    let dict = value_to_py(py, &v)?.cast_into::<PyDict>()?;
    for (key, numbers) in taken {
        dict.set_item(key, PyArray1::from_vec(py, numbers))?;
    }
    Ok(dict)
}

/// A float64 NumPy array of `v`.
pub fn array<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// A DOF as Python gives it: (node, direction).
pub type PyDof<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>);

/// The DOF `name` (e.g. `dofs[2] response`) of an FRF: a node from 0 and a direction
/// ±1 … ±6 (UFF's: translations 1–3, rotations 4–6), each refused naming it.
pub fn dof(name: &str, pair: &PyDof<'_>) -> PyResult<msd_modal::Dof> {
    let dof = any_dof(name, pair)?;
    if !dof.is_valid() {
        return Err(PyValueError::new_err(format!(
            "{name} direction = {}: expected ±1, ±2, ±3 (translations x, y, z) or ±4, ±5, ±6 (rotations)",
            dof.direction
        )));
    }
    Ok(dof)
}

/// The DOF `name` of an output-only channel: as [`dof`], and direction 0 for a channel
/// that measures along no axis (oblique: msd-experiment's reading of pyOMA's setups,
/// its unit vector in `directions`).
pub fn channel_dof(name: &str, pair: &PyDof<'_>) -> PyResult<msd_modal::Dof> {
    let dof = any_dof(name, pair)?;
    if !(dof.is_valid() || dof.direction == 0) {
        return Err(PyValueError::new_err(format!(
            "{name} direction = {}: expected ±1, ±2, ±3 (translations x, y, z), ±4, ±5, ±6 (rotations) or 0 (oblique: along its directions entry)",
            dof.direction
        )));
    }
    Ok(dof)
}

fn any_dof(name: &str, (node, direction): &PyDof<'_>) -> PyResult<msd_modal::Dof> {
    Ok(msd_modal::Dof {
        node: integer(&format!("{name} node"), node)?,
        direction: integer(&format!("{name} direction"), direction)?,
    })
}
