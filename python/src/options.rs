//! The environments' keyword options, read by name into the library's
//! [`proleg::gym::EnvOptions`] and [`proleg::gym::VecOptions`]: their names, defaults and
//! meanings are the library's ([`proleg::gym::options::documented`], exported to Python as
//! `ENV_OPTIONS`), so this file holds none of them.

use proleg::gym::{EnvOptions, OptionValue, VecOptions};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt, PyString};

use crate::errors::gym_error;

/// The options given as keywords, over the defaults; `vector`: a vector environment's
/// (`threads`, `autoreset` too).
pub fn read(
    kwargs: Option<&Bound<'_, PyDict>>,
    vector: bool,
) -> PyResult<(EnvOptions, VecOptions)> {
    let (mut env, mut vec) = (EnvOptions::default(), VecOptions::default());
    for (key, value) in kwargs.into_iter().flat_map(|d| d.iter()) {
        let name: String = key.extract()?;
        let value = value_of(&name, &value)?;
        let set = if vector {
            vec.set(&mut env, &name, &value)
        } else {
            env.set(&name, &value)
        };
        set.map_err(gym_error)?;
    }
    env.check().map_err(gym_error)?;
    Ok((env, vec))
}

/// A keyword's value: `None`, a number or a name.
fn value_of(name: &str, v: &Bound<'_, PyAny>) -> PyResult<OptionValue> {
    if v.is_none() {
        Ok(OptionValue::Unset)
    } else if v.is_instance_of::<PyString>() {
        Ok(OptionValue::Text(v.extract()?))
    } else if v.is_instance_of::<PyFloat>() || v.is_instance_of::<PyInt>() {
        Ok(OptionValue::Number(v.extract()?))
    } else if let Ok(text) = v.getattr("value").and_then(|t| t.extract::<String>()) {
        // An enum member whose value is its name (Gymnasium's `AutoresetMode`).
        Ok(OptionValue::Text(text))
    } else {
        Err(PyValueError::new_err(format!(
            "{name} = {v}: give None, a number or a name"
        )))
    }
}

/// Every option as `(name, default, meaning)`, the default a Python literal.
pub fn documented() -> Vec<(&'static str, String, &'static str)> {
    proleg::gym::options::documented()
        .into_iter()
        .map(|d| (d.name, d.default, d.doc))
        .collect()
}
