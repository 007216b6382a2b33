"""Policy weights from Python: written by the package, read and run by the library's own
forward pass (the policy module's), matching a numpy network within float32 rounding; the
file is a plain safetensors file both ways; bad networks and files raise."""

from pathlib import Path

import numpy as np
import pytest
from safetensors.numpy import load_file, save_file

import proleg
from proleg.policy import load_policy, save_policy


def _numpy_forward(layers, activation, mean, std, obs):
    x = (obs - mean) / std
    act = {"tanh": np.tanh, "relu": lambda v: np.maximum(v, 0.0), "linear": lambda v: v}
    for i, (w, b) in enumerate(layers):
        x = x @ w.T + b
        if i < len(layers) - 1:
            x = act[activation](x)
    return x


def _layers(rng, sizes):
    return [(rng.normal(0, 0.5, (o, i)), rng.normal(0, 0.1, o)) for i, o in zip(sizes, sizes[1:])]


@pytest.mark.parametrize("activation", ["tanh", "relu", "linear"])
def test_proleg_acts_as_the_numpy_network_within_float32(tmp_path, activation):
    rng = np.random.default_rng(3)
    sizes = [17, 32, 32, 5]
    layers = _layers(rng, sizes)
    mean, std = rng.normal(0, 1, 17), rng.uniform(0.5, 2.0, 17)
    save_policy(tmp_path / "p.safetensors", layers, activation, mean, std)
    net = load_policy(tmp_path / "p.safetensors")
    assert (net.inputs, net.outputs, net.activation) == (17, 5, activation)
    obs = rng.normal(0, 2, (200, 17))
    ours = net.forward(obs)
    # The file holds float32: the reference network uses the stored values.
    f32 = [(w.astype(np.float32).astype(np.float64), b.astype(np.float32).astype(np.float64))
           for w, b in layers]
    ref = _numpy_forward(f32, activation, mean.astype(np.float32), std.astype(np.float32), obs)
    assert np.max(np.abs(ours - ref)) < 1e-5
    # The weights round-trip (to float32).
    for (w, b), (w2, b2) in zip(f32, net.layers()):
        assert np.array_equal(w, w2) and np.array_equal(b, b2)


def test_the_file_is_plain_safetensors_both_ways(tmp_path):
    rng = np.random.default_rng(4)
    layers = _layers(rng, [4, 8, 2])
    save_policy(tmp_path / "ours.safetensors", layers, "relu")
    tensors = load_file(str(tmp_path / "ours.safetensors"))
    assert sorted(tensors) == ["layers.0.bias", "layers.0.weight", "layers.1.bias",
                               "layers.1.weight", "obs.mean", "obs.std"]
    assert tensors["layers.0.weight"].shape == (8, 4) and tensors["layers.0.weight"].dtype == np.float32
    # Written by the safetensors package, as a torch user would save a state dict.
    theirs = {f"layers.{i}.{k}": v.astype(np.float32)
              for i, (w, b) in enumerate(layers) for k, v in (("weight", w), ("bias", b))}
    theirs["obs.mean"] = np.zeros(4, np.float32)
    theirs["obs.std"] = np.ones(4, np.float32)
    save_file(theirs, str(tmp_path / "theirs.safetensors"), metadata={"activation": "relu"})
    obs = rng.normal(0, 1, (10, 4))
    a = load_policy(tmp_path / "ours.safetensors").forward(obs)
    b = load_policy(tmp_path / "theirs.safetensors").forward(obs)
    assert np.array_equal(a, b)


def test_bad_networks_and_files_raise(tmp_path):
    rng = np.random.default_rng(5)
    layers = _layers(rng, [3, 4, 2])
    with pytest.raises(ValueError, match="do not chain"):
        save_policy(tmp_path / "x.safetensors", [layers[1], layers[0]])
    bad = [(layers[0][0].copy(), layers[0][1]), layers[1]]
    bad[0][0][1, 2] = np.nan
    with pytest.raises(ValueError, match="weights"):
        save_policy(tmp_path / "x.safetensors", bad)
    with pytest.raises(ValueError, match="activation"):
        save_policy(tmp_path / "x.safetensors", layers, "sigmoid")
    with pytest.raises(ValueError, match="obs_std"):
        save_policy(tmp_path / "x.safetensors", layers, obs_std=np.zeros(3))
    net = save_policy(tmp_path / "ok.safetensors", layers)
    with pytest.raises(ValueError, match="3"):
        net.forward(np.zeros((1, 5)))
    tensors = load_file(str(tmp_path / "ok.safetensors"))
    del tensors["obs.std"]
    save_file(tensors, str(tmp_path / "no_std.safetensors"))
    with pytest.raises(proleg.ProlegError, match=r"no_std.safetensors.*obs\.std"):
        load_policy(tmp_path / "no_std.safetensors")
    with pytest.raises(proleg.ProlegError, match="missing.safetensors"):
        load_policy(tmp_path / "missing.safetensors")


class _Tensor:
    """What torch_layers reads of a torch tensor."""

    def __init__(self, a):
        self.a = np.asarray(a, dtype=np.float32)

    def detach(self):
        return self

    def cpu(self):
        return self

    def numpy(self):
        return self.a


class Linear:
    def __init__(self, w, b):
        self.weight, self.bias = _Tensor(w), None if b is None else _Tensor(b)


class Tanh:
    pass


class ReLU:
    pass


class Dropout:
    pass


def test_torch_modules_become_the_network_and_odd_ones_raise(tmp_path):
    from proleg.policy import torch_layers

    rng = np.random.default_rng(6)
    (w0, b0), (w1, b1) = _layers(rng, [3, 5, 2])
    layers, activation = torch_layers([Linear(w0, b0), Tanh(), Linear(w1, b1)])
    assert activation == "tanh" and len(layers) == 2
    assert np.array_equal(layers[1][0], w1.astype(np.float32))
    with pytest.raises(ValueError, match="several activations"):
        torch_layers([Linear(w0, b0), Tanh(), Linear(w1, b1), ReLU(), Linear(w1.T @ w1, b1)])
    with pytest.raises(ValueError, match="Dropout"):
        torch_layers([Linear(w0, b0), Dropout(), Linear(w1, b1)])
    with pytest.raises(ValueError, match="without bias"):
        torch_layers([Linear(w0, None)])


def test_a_network_saved_from_python_runs_in_proleg_as_it_ran_in_the_environment(
    tmp_path, demo, engine
):
    """The Policy module in an actuation file, reading the weights Python wrote, writes
    the observation the residual environment gives and scales its outputs as the
    environment scales actions (22.5 deg: a quarter of the snake's 90 deg half range):
    driven by proleg alone, the robot ends where the environment driven by Python ended."""
    env = proleg.ProlegEnv(demo, engine=engine, mode="residual", duration=0.6)
    obs, _ = env.reset(seed=4)
    rng = np.random.default_rng(11)
    layers = _layers(rng, [obs.shape[0], 16, 5])
    mean, std = rng.normal(0, 0.1, obs.shape[0]), np.full(obs.shape[0], 1.5)
    weights = tmp_path / "trained.safetensors"
    save_policy(weights, layers, "tanh", mean, std)
    net = load_policy(weights)  # the file's float32 values, as the module reads them
    truncated = False
    while not truncated:
        action = net.forward(obs[None, :])[0]
        obs, _, terminated, truncated, _ = env.step(action)
        assert not terminated
    through_env = env._env.com()
    root = Path(demo).parent
    (tmp_path / "policy.actuation.xml").write_text(
        (root / "actuation/snake5p_sine40.actuation.xml")
        .read_text()
        .replace(
            "</actuation>",
            f'  <actuationModule name="Policy" weights="{weights}">\n'
            '    <jointConfiguration joints="11111"/>\n'
            "  </actuationModule>\n</actuation>",
        )
    )
    text = (root / "demo.simulation.xml").read_text()
    for part in ("robots/snake5p.robot.xml", "environments/flat.env.xml"):
        text = text.replace(part, str(root / part))
    text = text.replace("actuation/snake5p_sine40.actuation.xml", "policy.actuation.xml")
    (tmp_path / "policy.simulation.xml").write_text(text)
    sim = proleg.load(tmp_path / "policy.simulation.xml", engine=engine, seed=4)
    sim.run(0.6)
    assert np.max(np.abs(sim.com() - through_env)) < 1e-9
    assert np.linalg.norm(sim.com()[:2] - proleg.load(demo, engine=engine, seed=4).com()[:2]) > 1e-3
