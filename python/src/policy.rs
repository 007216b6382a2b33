//! `PolicyNet`: a learned policy's network (`proleg::control::policy::PolicyNet`) from
//! Python: built from arrays (a trained torch or numpy MLP), written to and read from the
//! safetensors weights file proleg's policy module reads, and evaluated by the library's
//! own forward pass (so Python can check that proleg acts as its network does).

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use proleg::control::policy::{Activation, Layer, PolicyNet as Net};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::other;

/// A multilayer perceptron: layer `i` maps `weights[i]` (outputs x inputs) and
/// `biases[i]`; the hidden layers apply `activation` (`tanh`, `relu`, `linear`); the input
/// is normalized by `obs_mean` and `obs_std` first.
#[pyclass(module = "proleg._native")]
pub struct PolicyNet {
    net: Net,
}

/// `v` as a finite vector named `what`.
fn finite(what: &str, v: &[f64]) -> PyResult<Vec<f64>> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(PyValueError::new_err(format!(
            "{what}[{i}] is {}: give finite values",
            v[i]
        ))),
        None => Ok(v.to_vec()),
    }
}

#[pymethods]
impl PolicyNet {
    #[new]
    #[pyo3(signature = (weights, biases, activation="tanh", obs_mean=None, obs_std=None))]
    fn new(
        weights: Vec<PyReadonlyArray2<'_, f64>>,
        biases: Vec<PyReadonlyArray1<'_, f64>>,
        activation: &str,
        obs_mean: Option<PyReadonlyArray1<'_, f64>>,
        obs_std: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<PolicyNet> {
        let act = Activation::parse(activation).ok_or_else(|| {
            PyValueError::new_err(format!(
                "activation {activation:?}: give tanh, relu or linear"
            ))
        })?;
        if weights.len() != biases.len() {
            return Err(PyValueError::new_err(format!(
                "{} weight matrices and {} bias vectors",
                weights.len(),
                biases.len()
            )));
        }
        let mut layers = Vec::new();
        for (i, (w, b)) in weights.iter().zip(&biases).enumerate() {
            let [rows, _] = *w.shape() else {
                return Err(PyValueError::new_err(format!(
                    "weights[{i}] is not a matrix"
                )));
            };
            if b.len() != rows {
                return Err(PyValueError::new_err(format!(
                    "weights[{i}] has {rows} rows, biases[{i}] {} values",
                    b.len()
                )));
            }
            let weight = finite(
                &format!("weights[{i}]"),
                &w.as_array().iter().copied().collect::<Vec<_>>(),
            )?;
            let bias = finite(&format!("biases[{i}]"), &b.as_array().to_vec())?;
            layers.push(Layer { weight, bias });
        }
        let mut net = Net::new(layers, act).ok_or_else(|| {
            PyValueError::new_err(
                "the layers do not chain: each takes the previous one's outputs, none is empty",
            )
        })?;
        for (what, given, into) in [
            ("obs_mean", &obs_mean, &mut net.obs_mean),
            ("obs_std", &obs_std, &mut net.obs_std),
        ] {
            if let Some(v) = given {
                let v = finite(what, &v.as_array().to_vec())?;
                if v.len() != into.len() {
                    return Err(PyValueError::new_err(format!(
                        "{what} has {} values, the network {} inputs",
                        v.len(),
                        into.len()
                    )));
                }
                *into = v;
            }
        }
        if let Some(i) = net.obs_std.iter().position(|s| *s <= 0.0) {
            return Err(PyValueError::new_err(format!(
                "obs_std[{i}] must be positive"
            )));
        }
        Ok(PolicyNet { net })
    }

    /// Reads a weights file.
    #[staticmethod]
    fn read(path: PathBuf) -> PyResult<PolicyNet> {
        Ok(PolicyNet {
            net: Net::read(&path).map_err(other)?,
        })
    }

    /// Writes the weights file proleg's policy module reads (F32 values, as torch saves).
    fn write(&self, path: PathBuf) -> PyResult<()> {
        self.net.write(&path).map_err(other)
    }

    /// The network's outputs for one observation (inputs,) or a batch (n, inputs).
    fn forward<'py>(
        &mut self,
        py: Python<'py>,
        obs: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let [n, width] = *obs.shape() else {
            return Err(PyValueError::new_err(
                "observations: give an (n, inputs) array",
            ));
        };
        if width != self.net.inputs() {
            return Err(PyValueError::new_err(format!(
                "observations of {width} values, the network takes {}",
                self.net.inputs()
            )));
        }
        let rows = obs.as_array();
        let outputs = self.net.outputs();
        let mut out = vec![vec![0.0; outputs]; n];
        let mut input = vec![0.0; width];
        for (row, y) in rows.outer_iter().zip(out.iter_mut()) {
            for (x, v) in input.iter_mut().zip(row.iter()) {
                *x = *v;
            }
            self.net.forward(&input, y);
        }
        PyArray2::from_vec2(py, &out).map_err(other)
    }

    /// Values the network reads.
    #[getter]
    fn inputs(&self) -> usize {
        self.net.inputs()
    }

    /// Values the network writes.
    #[getter]
    fn outputs(&self) -> usize {
        self.net.outputs()
    }

    /// The hidden layers' nonlinearity.
    #[getter]
    fn activation(&self) -> &'static str {
        self.net.activation.name()
    }

    /// The layers' weight matrices (outputs x inputs) and bias vectors.
    #[allow(clippy::type_complexity)]
    fn layers<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Vec<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>)>> {
        self.net
            .layers
            .iter()
            .map(|l| {
                let rows: Vec<Vec<f64>> =
                    l.weight.chunks(l.inputs()).map(<[f64]>::to_vec).collect();
                Ok((
                    PyArray2::from_vec2(py, &rows).map_err(other)?,
                    PyArray1::from_slice(py, &l.bias),
                ))
            })
            .collect()
    }

    /// The observation statistics (mean, standard deviation).
    fn obs_stats<'py>(
        &self,
        py: Python<'py>,
    ) -> (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>) {
        (
            PyArray1::from_slice(py, &self.net.obs_mean),
            PyArray1::from_slice(py, &self.net.obs_std),
        )
    }
}
