"""Learned policies as proleg runs them: a multilayer perceptron from an observation to
joint angle offsets, in the safetensors weights file of proleg's policy module.

:func:`save_policy` writes a network given as layers of (weight, bias) arrays (numpy
arrays, or anything ``numpy.asarray`` takes, such as a torch tensor's ``.detach()``);
:func:`load_policy` reads one back as a :class:`proleg._native.PolicyNet`, whose
``forward`` is the library's own (the module's) forward pass.

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
