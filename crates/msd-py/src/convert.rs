//! Conversions between Python objects and the crates' types.

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
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
/// unknown keys and values of the wrong type are refused with serde's message.
pub fn options<T: DeserializeOwned>(what: &str, json: &str) -> PyResult<T> {
    let mut v: Value =
        serde_json::from_str(json).map_err(|e| PyValueError::new_err(format!("{what}: {e}")))?;
    drop_nulls(&mut v);
    serde_json::from_value(v)
        .map_err(|e| PyValueError::new_err(format!("{what}: {}", strip_position(&e))))
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
