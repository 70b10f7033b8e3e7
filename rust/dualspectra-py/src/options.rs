//! The localizer's options: Python keyword arguments -> core `Options` by name, and the
//! core's options table as Python objects. No option is named here: names, defaults, ranges
//! and docs are the core's (`dualspectra::localizer::OPTIONS`).

use crate::errors::to_py;
use dualspectra::Options;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};

/// The defaults with each `name=value` of `options` set by the core's `Options::set` (which
/// checks the name and the range: `ValueError` with its message), then validated together.
/// Values: `bool`, `int` (or anything with `__index__`, e.g. numpy integers), `float`, `str`.
pub fn from_kwargs(options: Option<&Bound<'_, PyDict>>) -> PyResult<Options> {
    let mut out = Options::default();
    if let Some(options) = options {
        for (name, value) in options.iter() {
            let name: String = name
                .extract()
                .map_err(|_| PyTypeError::new_err("option names must be strings"))?;
            let value = to_json(&name, &value)?;
            out.set(&name, value).map_err(to_py)?;
        }
    }
    out.validate().map_err(to_py)?;
    Ok(out)
}

/// A Python option value as JSON (`TypeError` for other types).
fn to_json(name: &str, value: &Bound<'_, PyAny>) -> PyResult<serde_json::Value> {
    if value.is_instance_of::<PyBool>() {
        return Ok(serde_json::Value::Bool(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(serde_json::Value::String(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        let x: f64 = value.extract()?;
        // NaN and infinities have no JSON number: pass them as text, the core's range
        // check names the option and its range.
        return Ok(serde_json::Number::from_f64(x)
            .map(serde_json::Value::Number)
            .unwrap_or_else(|| serde_json::Value::String(x.to_string())));
    }
    let index = if value.is_instance_of::<PyInt>() {
        Some(value.clone())
    } else if value.hasattr("__index__")? {
        Some(value.call_method0("__index__")?)
    } else {
        None
    };
    if let Some(i) = index {
        if let Ok(u) = i.extract::<u64>() {
            return Ok(u.into());
        }
        if let Ok(s) = i.extract::<i64>() {
            return Ok(s.into());
        }
        // Beyond 64 bits: out of every range; the text reaches the core's range message.
        return Ok(serde_json::Value::String(i.str()?.to_string()));
    }
    if let Ok(x) = value.call_method0("__float__").and_then(|f| f.extract::<f64>()) {
        // Other real numbers (numpy floats are `float` subclasses already; e.g. Fraction).
        return to_json(name, PyFloat::new(value.py(), x).as_any());
    }
    Err(PyTypeError::new_err(format!(
        "option {name}: expected int, float or str, got {}",
        value.get_type().name()?
    )))
}

/// A JSON value as a Python object (objects -> dict, arrays -> list).
pub fn to_python<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        serde_json::Value::Null => py.None().into_bound(py),
        serde_json::Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        serde_json::Value::Number(n) => match (n.as_u64(), n.as_i64()) {
            (Some(u), _) => u.into_pyobject(py)?.into_any(),
            (None, Some(i)) => i.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        serde_json::Value::String(s) => PyString::new(py, s).into_any(),
        serde_json::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_python(py, item)?)?;
            }
            list.into_any()
        }
        serde_json::Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, to_python(py, v)?)?;
            }
            dict.into_any()
        }
    })
}

/// These options as a dict `{name: value}` (the core's JSON form).
pub fn to_dict<'py>(py: Python<'py>, options: &Options) -> PyResult<Bound<'py, PyAny>> {
    let value: serde_json::Value = serde_json::from_str(&options.to_json())
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("options as JSON: {e}")))?;
    to_python(py, &value)
}

/// The core's options table: a list of dicts `{"name", "label", "type", "min"/"max" or
/// "choices", "default", "doc"}`, in the order front ends list them.
#[pyfunction]
pub fn options_schema(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let value: serde_json::Value = serde_json::from_str(&dualspectra::localizer::options_schema_json())
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("options schema as JSON: {e}")))?;
    to_python(py, &value)
}
