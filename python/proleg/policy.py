"""Learned policies as proleg runs them: a multilayer perceptron from an observation to
joint angle offsets, in the safetensors weights file of proleg's policy module.

:func:`save_policy` writes a network given as layers of (weight, bias) arrays (numpy
arrays, or anything ``numpy.asarray`` takes, such as a torch tensor's ``.detach()``);
:func:`load_policy` reads one back as a :class:`proleg._native.PolicyNet`, whose
``forward`` is the library's own forward pass; :func:`save_sb3_policy` writes a
Stable-Baselines3 model's action network, :func:`torch_layers` any torch MLP's layers.

The file holds ``layers.{i}.weight`` (outputs x inputs, as torch's ``nn.Linear``),
``layers.{i}.bias``, ``obs.mean`` and ``obs.std`` as float32, and the hidden layers'
``activation`` in its metadata: Python's ``safetensors`` package and torch read it as it
is.
"""

from __future__ import annotations

import os
from typing import Iterable, Sequence

import numpy as np

from ._native import PolicyNet


def save_policy(
    path: str | os.PathLike,
    layers: Iterable[Sequence],
    activation: str = "tanh",
    obs_mean=None,
    obs_std=None,
) -> PolicyNet:
    """Writes the network of ``layers`` ((weight, bias) pairs from the input; weight of
    shape (outputs, inputs)) with its observation statistics (the network sees
    ``(obs - obs_mean) / obs_std``; zero and one when not given) to ``path``; returns it."""
    weights, biases = [], []
    for weight, bias in layers:
        weights.append(np.ascontiguousarray(np.asarray(weight, dtype=np.float64)))
        biases.append(np.ascontiguousarray(np.asarray(bias, dtype=np.float64)).reshape(-1))
    stats = [None if s is None else np.ascontiguousarray(np.asarray(s, dtype=np.float64)).reshape(-1)
             for s in (obs_mean, obs_std)]
    net = PolicyNet(weights, biases, activation, stats[0], stats[1])
    net.write(os.fspath(path))
    return net


def load_policy(path: str | os.PathLike) -> PolicyNet:
    """The network in the weights file ``path``."""
    return PolicyNet.read(os.fspath(path))


def torch_layers(modules) -> tuple[list[tuple[np.ndarray, np.ndarray]], str]:
    """The (weight, bias) pairs and hidden activation of a torch MLP given as its modules
    in order (``nn.Linear`` layers with the same ``nn.Tanh``, ``nn.ReLU`` or ``nn.Identity``
    between them); raises ``ValueError`` for anything else. torch itself is not imported."""
    names = {"Tanh": "tanh", "ReLU": "relu", "Identity": "linear"}
    layers, activations = [], set()
    for m in modules:
        kind = type(m).__name__
        if kind == "Linear":
            if m.bias is None:
                raise ValueError("a Linear layer without bias: proleg's network has biases")
            layers.append((m.weight.detach().cpu().numpy(), m.bias.detach().cpu().numpy()))
        elif kind in names:
            activations.add(names[kind])
        else:
            raise ValueError(f"a {kind} module: proleg's network has Linear layers with "
                             "Tanh, ReLU or Identity between them")
    if not layers:
        raise ValueError("no Linear layer")
    if len(activations) > 1:
        raise ValueError(f"several activations {sorted(activations)}: proleg's network has one")
    return layers, activations.pop() if activations else "linear"


def save_sb3_policy(path: str | os.PathLike, model, obs_rms=None) -> PolicyNet:
    """Writes the deterministic action network of a Stable-Baselines3 on-policy model (PPO
    or A2C with ``MlpPolicy`` on a flat Box observation: the actor's MLP, then its action
    layer) to ``path``; ``obs_rms`` (``VecNormalize.obs_rms``) adds the observation
    statistics (std = sqrt(var + 1e-8), as VecNormalize divides; its clipping is not
    kept). The network's outputs are the action means, before SB3 clips them to the action
    space."""
    policy = model.policy
    if type(policy.features_extractor).__name__ != "FlattenExtractor":
        raise ValueError(f"a {type(policy.features_extractor).__name__}: only the flat "
                         "observations of MlpPolicy are supported")
    layers, activation = torch_layers(list(policy.mlp_extractor.policy_net)
                                      + [policy.action_net])
    mean = std = None
    if obs_rms is not None:
        mean, std = np.asarray(obs_rms.mean), np.sqrt(np.asarray(obs_rms.var) + 1e-8)
    return save_policy(path, layers, activation, mean, std)
