//! A learned policy's network: a multilayer perceptron from an observation vector to joint
//! angle offsets, read from (and written to) a safetensors file, the format Python's
//! `safetensors` package and torch read and write. The file holds, per layer `i` from the
//! input, `layers.{i}.weight` (shape `[outputs, inputs]`, torch's `nn.Linear` layout) and
//! `layers.{i}.bias` (`[outputs]`), the observation statistics `obs.mean` and `obs.std`
//! (`[inputs]`; the network sees `(x - mean) / std`), as F32 or F64, and in its metadata
//! the hidden layers' `activation` (`tanh`, `relu` or `linear`; the output layer is
//! linear). [`PolicyNet::write`] writes F32 (as torch saves), [`PolicyNet::write_exact`]
//! F64 (an optimizer's best, to be run exactly as scored). [`PolicyNet::forward`]
//! allocates nothing: its buffers are sized when the file is read.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use safetensors::tensor::{Dtype, SafeTensors, TensorView};

/// Why a weights file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum PolicyError {
    /// The file could not be read or written.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The file is not a safetensors file.
    #[error("{file}: not a safetensors file: {cause}")]
    Format {
        /// The file.
        file: PathBuf,
        /// What the safetensors reader said.
        cause: String,
    },
    /// A tensor the network needs is missing.
    #[error("{file}: no tensor {tensor} (the file holds: {held})")]
    Missing {
        /// The file.
        file: PathBuf,
        /// The tensor's name.
        tensor: String,
        /// The tensors it holds.
        held: String,
    },
    /// A tensor of the wrong shape.
    #[error("{file}: tensor {tensor} has shape {given:?}, expected {want:?}")]
    Shape {
        /// The file.
        file: PathBuf,
        /// The tensor's name.
        tensor: String,
        /// Its shape.
        given: Vec<usize>,
        /// The shape the network needs there.
        want: Vec<usize>,
    },
    /// A tensor of another element type than F32 or F64.
    #[error("{file}: tensor {tensor} holds {dtype}, expected F32 or F64")]
    Dtype {
        /// The file.
        file: PathBuf,
        /// The tensor's name.
        tensor: String,
        /// Its element type.
        dtype: String,
    },
    /// A NaN or infinite value, or a standard deviation that is not positive.
    #[error("{file}: tensor {tensor}[{index}] is {value}: {want}")]
    Value {
        /// The file.
        file: PathBuf,
        /// The tensor's name.
        tensor: String,
        /// The flat index of the value.
        index: usize,
        /// The value.
        value: f64,
        /// What a value there must be.
        want: &'static str,
    },
    /// An activation the network does not know.
    #[error("{file}: activation {given:?}: give tanh, relu or linear")]
    Activation {
        /// The file.
        file: PathBuf,
        /// The name given.
        given: String,
    },
    /// The network does not fit the module that should run it.
    #[error("{file}: tensor {tensor}: {cause}")]
    Mismatch {
        /// The file.
        file: PathBuf,
        /// The tensor that does not fit.
        tensor: String,
        /// How.
        cause: NetworkMismatch,
    },
}

/// Two errors are equal when they say the same (the I/O cause compares by its message).
impl PartialEq for PolicyError {
    fn eq(&self, other: &Self) -> bool {
        self.to_string() == other.to_string()
    }
}

/// Why a module refused a network.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NetworkMismatch {
    /// The network writes another number of outputs than the module drives joints.
    #[error("the network writes {given} outputs but the module drives {want} joints")]
    Outputs {
        /// The network's outputs.
        given: usize,
        /// The module's joints.
        want: usize,
    },
    /// The network reads another number of inputs than the robot's observation holds.
    #[error(
        "the network reads {network} inputs but the observation has {observation} (the robot has {joints} joints, {pads} pads, {beams} laser beams and {generators} generators; the module's switches choose the parts observed)"
    )]
    Inputs {
        /// The network's inputs.
        network: usize,
        /// The observation's values.
        observation: usize,
        /// Robot joints.
        joints: usize,
        /// Tactile pads.
        pads: usize,
        /// Laser beams.
        beams: usize,
        /// Generators.
        generators: usize,
    },
    /// The module runs no network.
    #[error("module {module} runs no network (only Policy does)")]
    NotAPolicy {
        /// The module type.
        module: &'static str,
    },
    /// A flat parameter vector of the wrong length.
    #[error("{given} parameters given, the network has {want}")]
    Parameters {
        /// Values given.
        given: usize,
        /// The network's parameters.
        want: usize,
    },
}

/// The hidden layers' nonlinearity.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Activation {
    /// `tanh(x)`.
    Tanh,
    /// `max(x, 0)`.
    Relu,
    /// `x` (a linear policy).
    Linear,
}

impl Activation {
    /// Its name in the file's metadata.
    pub fn name(self) -> &'static str {
        match self {
            Activation::Tanh => "tanh",
            Activation::Relu => "relu",
            Activation::Linear => "linear",
        }
    }

    /// Reads a name (any case).
    pub fn parse(s: &str) -> Option<Activation> {
        match s.trim().to_ascii_lowercase().as_str() {
            "tanh" => Some(Activation::Tanh),
            "relu" => Some(Activation::Relu),
            "linear" | "identity" => Some(Activation::Linear),
            _ => None,
        }
    }

    fn apply(self, x: f64) -> f64 {
        match self {
            Activation::Tanh => x.tanh(),
            Activation::Relu => x.max(0.0),
            Activation::Linear => x,
        }
    }
}

/// One fully connected layer: `weight` row-major `[outputs][inputs]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// Row-major weights, `outputs * inputs` values.
    pub weight: Vec<f64>,
    /// One bias per output.
    pub bias: Vec<f64>,
}

impl Layer {
    /// Inputs of the layer.
    pub fn inputs(&self) -> usize {
        self.weight.len() / self.bias.len().max(1)
    }

    /// Outputs of the layer.
    pub fn outputs(&self) -> usize {
        self.bias.len()
    }
}

/// A multilayer perceptron with its observation statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct PolicyNet {
    /// The layers from the input.
    pub layers: Vec<Layer>,
    /// The hidden layers' nonlinearity.
    pub activation: Activation,
    /// Mean of each input.
    pub obs_mean: Vec<f64>,
    /// Standard deviation of each input (positive).
    pub obs_std: Vec<f64>,
    /// Two buffers as wide as the widest layer.
    scratch: [Vec<f64>; 2],
}

impl PolicyNet {
    /// A network of `layers` (checked: each takes the previous one's outputs) with unit
    /// observation statistics. `None` when the layers do not chain or there are none.
    pub fn new(layers: Vec<Layer>, activation: Activation) -> Option<PolicyNet> {
        let first = layers.first()?;
        let inputs = first.inputs();
        let chained = layers
            .iter()
            .all(|l| l.weight.len() == l.inputs() * l.outputs())
            && layers.windows(2).all(|w| w[1].inputs() == w[0].outputs());
        if !chained || layers.iter().any(|l| l.outputs() == 0) {
            return None;
        }
        let width = layers
            .iter()
            .map(Layer::outputs)
            .chain([inputs])
            .max()
            .unwrap_or(0);
        Some(PolicyNet {
            obs_mean: vec![0.0; inputs],
            obs_std: vec![1.0; inputs],
            layers,
            activation,
            scratch: [vec![0.0; width], vec![0.0; width]],
        })
    }

    /// Inputs the network reads.
    pub fn inputs(&self) -> usize {
        self.obs_mean.len()
    }

    /// Outputs the network writes.
    pub fn outputs(&self) -> usize {
        self.layers.last().map_or(0, Layer::outputs)
    }

    /// Weights and biases of every layer (the observation statistics excluded).
    pub fn parameter_count(&self) -> usize {
        self.layers
            .iter()
            .map(|l| l.weight.len() + l.bias.len())
            .sum()
    }

    /// Every layer's weights then bias, in layer order: the vector an evolution strategy
    /// searches.
    pub fn parameters(&self) -> Vec<f64> {
        let mut v = Vec::with_capacity(self.parameter_count());
        for l in &self.layers {
            v.extend_from_slice(&l.weight);
            v.extend_from_slice(&l.bias);
        }
        v
    }

    /// Sets every layer's weights and bias from a vector laid out as [`Self::parameters`].
    pub fn set_parameters(&mut self, values: &[f64]) -> Result<(), NetworkMismatch> {
        if values.len() != self.parameter_count() {
            return Err(NetworkMismatch::Parameters {
                given: values.len(),
                want: self.parameter_count(),
            });
        }
        let mut rest = values;
        for l in &mut self.layers {
            let (w, tail) = rest.split_at(l.weight.len());
            l.weight.copy_from_slice(w);
            let (b, tail) = tail.split_at(l.bias.len());
            l.bias.copy_from_slice(b);
            rest = tail;
        }
        Ok(())
    }

    /// The network's outputs for `input` into `out` (`input.len()` = [`Self::inputs`],
    /// `out.len()` = [`Self::outputs`]; extra values are ignored, missing ones read as 0).
    pub fn forward(&mut self, input: &[f64], out: &mut [f64]) {
        let [a, b] = &mut self.scratch;
        for (i, x) in a.iter_mut().take(self.obs_mean.len()).enumerate() {
            let v = input.get(i).copied().unwrap_or(0.0);
            *x = (v - self.obs_mean[i]) / self.obs_std[i];
        }
        let last = self.layers.len() - 1;
        let (mut from, mut to) = (a, b);
        for (k, layer) in self.layers.iter().enumerate() {
            let n_in = layer.inputs();
            for (o, y) in to.iter_mut().take(layer.outputs()).enumerate() {
                let row = &layer.weight[o * n_in..(o + 1) * n_in];
                let sum: f64 = row.iter().zip(from.iter()).map(|(w, x)| w * x).sum();
                let z = sum + layer.bias[o];
                *y = if k == last {
                    z
                } else {
                    self.activation.apply(z)
                };
            }
            std::mem::swap(&mut from, &mut to);
        }
        for (y, v) in out.iter_mut().zip(from.iter()) {
            *y = *v;
        }
    }

    /// Reads a weights file.
    pub fn read(path: &Path) -> Result<PolicyNet, PolicyError> {
        let bytes = std::fs::read(path).map_err(|source| PolicyError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        PolicyNet::from_bytes(&bytes, path)
    }

    /// Parses a weights file's bytes; `path` names it in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<PolicyNet, PolicyError> {
        let format = |cause: String| PolicyError::Format {
            file: path.to_path_buf(),
            cause,
        };
        let (_, metadata) = SafeTensors::read_metadata(bytes).map_err(|e| format(e.to_string()))?;
        let tensors = SafeTensors::deserialize(bytes).map_err(|e| format(e.to_string()))?;
        let reader = Reader {
            file: path,
            tensors: &tensors,
        };
        let activation_name = metadata
            .metadata()
            .as_ref()
            .and_then(|m| m.get("activation").cloned())
            .unwrap_or_else(|| "tanh".into());
        let activation =
            Activation::parse(&activation_name).ok_or_else(|| PolicyError::Activation {
                file: path.to_path_buf(),
                given: activation_name.clone(),
            })?;
        let mut layers = Vec::new();
        let mut inputs = None;
        loop {
            let k = layers.len();
            let name = format!("layers.{k}.weight");
            if tensors.tensor(&name).is_err() {
                break;
            }
            let (shape, weight) = reader.values(&name, None)?;
            let [outputs, n_in] = shape[..] else {
                return Err(reader.shape(&name, shape, vec![0, 0]));
            };
            if let Some(want) = inputs.filter(|&want| want != n_in) {
                return Err(reader.shape(&name, shape, vec![outputs, want]));
            }
            let (_, bias) = reader.values(&format!("layers.{k}.bias"), Some(&[outputs]))?;
            layers.push(Layer { weight, bias });
            inputs = Some(outputs);
        }
        let Some(first) = layers.first() else {
            return Err(reader.missing("layers.0.weight"));
        };
        let n_in = first.inputs();
        let (_, mean) = reader.values("obs.mean", Some(&[n_in]))?;
        let (_, std) = reader.values("obs.std", Some(&[n_in]))?;
        if let Some((index, &value)) = std.iter().enumerate().find(|(_, s)| **s <= 0.0) {
            return Err(PolicyError::Value {
                file: path.to_path_buf(),
                tensor: "obs.std".into(),
                index,
                value,
                want: "a standard deviation must be positive",
            });
        }
        let mut net = PolicyNet::new(layers, activation).ok_or_else(|| format("layers".into()))?;
        net.obs_mean = mean;
        net.obs_std = std;
        Ok(net)
    }

    /// Writes the network as a weights file (F32 values, as torch saves them; the
    /// activation in the metadata). Values beyond F32's precision are rounded.
    pub fn write(&self, path: &Path) -> Result<(), PolicyError> {
        self.write_as(path, Dtype::F32)
    }

    /// Writes the network with F64 values: exactly the weights it runs (an optimizer's
    /// best, whose score a run of the file must reproduce).
    pub fn write_exact(&self, path: &Path) -> Result<(), PolicyError> {
        self.write_as(path, Dtype::F64)
    }

    fn write_as(&self, path: &Path, dtype: Dtype) -> Result<(), PolicyError> {
        let mut named: Vec<(String, Vec<usize>, Vec<u8>)> = Vec::new();
        let bytes = |v: &[f64]| -> Vec<u8> {
            match dtype {
                Dtype::F64 => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
                _ => v.iter().flat_map(|x| (*x as f32).to_le_bytes()).collect(),
            }
        };
        for (k, l) in self.layers.iter().enumerate() {
            named.push((
                format!("layers.{k}.weight"),
                vec![l.outputs(), l.inputs()],
                bytes(&l.weight),
            ));
            named.push((
                format!("layers.{k}.bias"),
                vec![l.outputs()],
                bytes(&l.bias),
            ));
        }
        named.push((
            "obs.mean".into(),
            vec![self.inputs()],
            bytes(&self.obs_mean),
        ));
        named.push(("obs.std".into(), vec![self.inputs()], bytes(&self.obs_std)));
        let format = |cause: String| PolicyError::Format {
            file: path.to_path_buf(),
            cause,
        };
        let views = named
            .iter()
            .map(|(n, shape, data)| {
                TensorView::new(dtype, shape.clone(), data)
                    .map(|v| (n.clone(), v))
                    .map_err(|e| format(e.to_string()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let metadata = HashMap::from([("activation".to_string(), self.activation.name().into())]);
        let data =
            safetensors::serialize(views, Some(metadata)).map_err(|e| format(e.to_string()))?;
        std::fs::write(path, data).map_err(|source| PolicyError::Io {
            file: path.to_path_buf(),
            source,
        })
    }
}

/// Reads tensors of one file, naming the file and tensor in every error.
struct Reader<'a> {
    file: &'a Path,
    tensors: &'a SafeTensors<'a>,
}

impl Reader<'_> {
    fn missing(&self, tensor: &str) -> PolicyError {
        let mut held: Vec<&str> = self.tensors.names();
        held.sort_unstable();
        PolicyError::Missing {
            file: self.file.to_path_buf(),
            tensor: tensor.into(),
            held: if held.is_empty() {
                "nothing".into()
            } else {
                held.join(", ")
            },
        }
    }

    fn shape(&self, tensor: &str, given: Vec<usize>, want: Vec<usize>) -> PolicyError {
        PolicyError::Shape {
            file: self.file.to_path_buf(),
            tensor: tensor.into(),
            given,
            want,
        }
    }

    /// Tensor `name`'s shape and finite values (checked against `want` when given).
    fn values(
        &self,
        name: &str,
        want: Option<&[usize]>,
    ) -> Result<(Vec<usize>, Vec<f64>), PolicyError> {
        let view = self.tensors.tensor(name).map_err(|_| self.missing(name))?;
        let shape = view.shape().to_vec();
        if let Some(w) = want.filter(|w| *w != shape.as_slice()) {
            return Err(self.shape(name, shape, w.to_vec()));
        }
        let data = view.data();
        let values: Vec<f64> = match view.dtype() {
            Dtype::F32 => data
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
                .collect(),
            Dtype::F64 => data
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
                .collect(),
            other => {
                return Err(PolicyError::Dtype {
                    file: self.file.to_path_buf(),
                    tensor: name.into(),
                    dtype: format!("{other:?}"),
                });
            }
        };
        if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(PolicyError::Value {
                file: self.file.to_path_buf(),
                tensor: name.into(),
                index,
                value,
                want: "weights and statistics must be finite",
            });
        }
        Ok((shape, values))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder of its own for one test.
    fn dir(test: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("proleg-policy-{}-{test}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// 2 inputs -> 2 hidden (tanh) -> 1 output, values exact in F32.
    fn small() -> PolicyNet {
        let mut net = PolicyNet::new(
            vec![
                Layer {
                    weight: vec![0.5, -1.0, 2.0, 0.25],
                    bias: vec![0.125, -0.5],
                },
                Layer {
                    weight: vec![1.5, -2.0],
                    bias: vec![0.75],
                },
            ],
            Activation::Tanh,
        )
        .unwrap();
        net.obs_mean = vec![1.0, -1.0];
        net.obs_std = vec![2.0, 0.5];
        net
    }

    #[test]
    fn the_forward_pass_is_the_hand_computed_network() {
        let mut net = small();
        let mut out = [0.0];
        net.forward(&[3.0, 0.0], &mut out);
        // Normalized: (3 - 1) / 2 = 1, (0 + 1) / 0.5 = 2.
        let h0 = (0.5 * 1.0 - 1.0 * 2.0 + 0.125_f64).tanh();
        let h1 = (2.0 * 1.0 + 0.25 * 2.0 - 0.5_f64).tanh();
        let y = 1.5 * h0 - 2.0 * h1 + 0.75;
        assert_eq!(out[0], y);
        net.activation = Activation::Relu;
        net.forward(&[3.0, 0.0], &mut out);
        assert_eq!(out[0], 1.5 * 0.0 - 2.0 * 2.0 + 0.75);
    }

    #[test]
    fn weights_round_trip_through_a_file() {
        let d = dir("round-trip");
        let net = small();
        let file = d.join("p.safetensors");
        net.write(&file).unwrap();
        assert_eq!(PolicyNet::read(&file).unwrap(), net);
        std::fs::remove_dir_all(d).unwrap();
    }

    /// `net` written, then `edit` applied to its tensors, then read: the error's text.
    fn read_error(test: &str, edit: impl Fn(&mut Vec<(String, Vec<usize>, Vec<f64>)>)) -> String {
        let d = dir(test);
        let net = small();
        let mut t: Vec<(String, Vec<usize>, Vec<f64>)> = Vec::new();
        for (k, l) in net.layers.iter().enumerate() {
            t.push((
                format!("layers.{k}.weight"),
                vec![l.outputs(), l.inputs()],
                l.weight.clone(),
            ));
            t.push((
                format!("layers.{k}.bias"),
                vec![l.outputs()],
                l.bias.clone(),
            ));
        }
        t.push(("obs.mean".into(), vec![2], net.obs_mean.clone()));
        t.push(("obs.std".into(), vec![2], net.obs_std.clone()));
        edit(&mut t);
        let data: Vec<(String, Vec<usize>, Vec<u8>)> = t
            .into_iter()
            .map(|(n, s, v)| (n, s, v.iter().flat_map(|x| x.to_le_bytes()).collect()))
            .collect();
        let views = data.iter().map(|(n, s, b)| {
            (
                n.clone(),
                TensorView::new(Dtype::F64, s.clone(), b).unwrap(),
            )
        });
        let file = d.join("bad.safetensors");
        std::fs::write(&file, safetensors::serialize(views, None).unwrap()).unwrap();
        let e = PolicyNet::read(&file).unwrap_err().to_string();
        std::fs::remove_dir_all(d).unwrap();
        assert!(e.contains("bad.safetensors"), "{e}");
        e
    }

    #[test]
    fn bad_weights_files_are_errors_naming_file_and_tensor() {
        let e = read_error("shape", |t| {
            t[2].1 = vec![1, 3];
            t[2].2 = vec![1.0, 2.0, 3.0];
        });
        assert!(e.contains("layers.1.weight") && e.contains("[1, 3]"), "{e}");
        let e = read_error("nan", |t| t[1].2[1] = f64::NAN);
        assert!(e.contains("layers.0.bias[1]") && e.contains("NaN"), "{e}");
        let e = read_error("missing", |t| t.retain(|(n, _, _)| n != "obs.std"));
        assert!(e.contains("no tensor obs.std"), "{e}");
        let e = read_error("inputs", |t| {
            t[4].1 = vec![3];
            t[4].2.push(0.0);
        });
        assert!(e.contains("obs.mean") && e.contains("[3]"), "{e}");
        let e = read_error("std", |t| t[5].2[0] = 0.0);
        assert!(e.contains("obs.std[0]") && e.contains("positive"), "{e}");
        let e = read_error("empty", |t| t.clear());
        assert!(e.contains("no tensor layers.0.weight"), "{e}");
        let d = dir("garbage");
        let file = d.join("garbage.safetensors");
        std::fs::write(&file, b"not a tensor file").unwrap();
        let e = PolicyNet::read(&file).unwrap_err().to_string();
        assert!(
            e.contains("garbage.safetensors") && e.contains("not a safetensors file"),
            "{e}"
        );
        let e = PolicyNet::read(&d.join("none.safetensors"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("none.safetensors"), "{e}");
        std::fs::remove_dir_all(d).unwrap();
    }
}
