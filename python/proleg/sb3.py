"""Stable-Baselines3's ``VecEnv`` interface over the native vector environment, so SB3
trains on it without ``DummyVecEnv``: reset on the step an episode ends (same-step), the
ended episode's last observation in ``info["terminal_observation"]`` and
``info["TimeLimit.truncated"]`` for an episode cut at its duration.

With Stable-Baselines3 installed, :class:`SB3VecEnv` is a subclass of its ``VecEnv``;
without it, a plain class with the same methods (SB3 itself is not needed to use or test
it)."""

from __future__ import annotations

import os
from typing import Any, Sequence

import numpy as np
from gymnasium import spaces

from . import _native

try:  # pragma: no cover - depends on the environment
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv as _Base

    HAVE_SB3 = True
except ImportError:
    _Base = object
    HAVE_SB3 = False


class SB3VecEnv(_Base):
    """``num_envs`` environments of a simulation file (keywords as
    :class:`proleg.ProlegEnv`'s) for Stable-Baselines3; observations float32."""

    def __init__(
        self,
        path: str | os.PathLike,
        num_envs: int = 1,
        **options: Any,
    ):
        self._venv = _native.VecEnv(
            os.fspath(path), num_envs, **{**options, "autoreset": "same_step"}
        )
        observation_space = spaces.Box(-np.inf, np.inf, (self._venv.obs_len,), np.float32)
        action_space = spaces.Box(-1.0, 1.0, (self._venv.action_len,), np.float32)
        self.render_mode = None
        if HAVE_SB3:
            super().__init__(num_envs, observation_space, action_space)
        else:
            self.num_envs = num_envs
            self.observation_space = observation_space
            self.action_space = action_space
            self.reset_infos = [{} for _ in range(num_envs)]
            self._seeds = [None] * num_envs
            self._options = [{} for _ in range(num_envs)]
        self._actions: np.ndarray | None = None
        self._next_seed: int | None = None

    def seed(self, seed: int | None = None) -> Sequence[None]:
        """The seed of the next reset (environment i gets ``seed + i``)."""
        self._next_seed = seed
        return [None] * self.num_envs

    def reset(self) -> np.ndarray:
        obs, _ = self._venv.reset(self._next_seed, None)
        self._next_seed = None
        self.reset_infos = [{} for _ in range(self.num_envs)]
        return obs.astype(np.float32)

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.ascontiguousarray(
            np.reshape(actions, (self.num_envs, -1)), dtype=np.float64
        )

    def step_wait(self):
        if self._actions is None:
            raise RuntimeError("step_wait without step_async")
        obs, rewards, terminated, truncated, info = self._venv.step(self._actions)
        self._actions = None
        dones = terminated | truncated
        infos: list[dict[str, Any]] = []
        for i in range(self.num_envs):
            one: dict[str, Any] = {
                "time": float(info["time"][i]),
                "score": float(info["score"][i]),
            }
            if dones[i]:
                one["terminal_observation"] = info["final_obs"][i].astype(np.float32)
                one["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            infos.append(one)
        return obs.astype(np.float32), rewards.astype(np.float32), dones, infos

    def close(self) -> None:
        self._venv.close()

    def get_attr(self, attr_name: str, indices=None) -> list[Any]:
        return [getattr(self, attr_name)] * len(self._indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name: str, *args, indices=None, **kwargs) -> list[Any]:
        raise AttributeError(
            f"{method_name}: the native environments have no per-environment methods"
        )

    def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
        return [False] * len(self._indices(indices))

    def _indices(self, indices) -> list[int]:
        if indices is None:
            return list(range(self.num_envs))
        if isinstance(indices, int):
            return [indices]
        return list(indices)
