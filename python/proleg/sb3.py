"""Stable-Baselines3's ``VecEnv`` interface over the native vector environment, so SB3
trains on it without ``DummyVecEnv``: reset on the step an episode ends (same-step), the
ended episode's last observation in ``info["terminal_observation"]`` and
``info["TimeLimit.truncated"]`` for an episode cut at its duration.

``engines=["rapier", "mujoco"]`` splits the environments between the engines (one native
vector environment per engine, stepped one after the other), so one policy trains on
both engines' contacts at once.

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
    :class:`proleg.ProlegEnv`'s) for Stable-Baselines3; observations float32.

    ``engines``: engine names the environments are split between, in that order (the
    first ``num_envs // len(engines)`` on the first, the remainder spread from the
    front); ``None`` (the default): all on ``engine=`` or the file's."""

    def __init__(
        self,
        path: str | os.PathLike,
        num_envs: int = 1,
        engines: Sequence[str] | None = None,
        **options: Any,
    ):
        options = {**options, "autoreset": "same_step"}
        if engines is None:
            self._parts = [_native.VecEnv(os.fspath(path), num_envs, **options)]
        else:
            if "engine" in options:
                raise ValueError("give engine= or engines=, not both")
            if not engines or len(engines) > num_envs:
                raise ValueError(
                    f"engines={list(engines)}: give one to {num_envs} engine names"
                )
            counts = [num_envs // len(engines)] * len(engines)
            for k in range(num_envs - sum(counts)):
                counts[k] += 1
            self._parts = [
                _native.VecEnv(os.fspath(path), n, engine=e, **options)
                for e, n in zip(engines, counts)
            ]
        self._starts = np.cumsum([0] + [p.num_envs for p in self._parts])
        self._venv = self._parts[0]
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
        seed = self._next_seed
        obs = [
            p.reset(None if seed is None else seed + int(start), None)[0]
            for p, start in zip(self._parts, self._starts)
        ]
        self._next_seed = None
        self.reset_infos = [{} for _ in range(self.num_envs)]
        return np.concatenate(obs).astype(np.float32)

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.ascontiguousarray(
            np.reshape(actions, (self.num_envs, -1)), dtype=np.float64
        )

    def step_wait(self):
        if self._actions is None:
            raise RuntimeError("step_wait without step_async")
        if len(self._parts) == 1:
            obs, rewards, terminated, truncated, info = self._venv.step(self._actions)
        else:
            obs, rewards, terminated, truncated, info = self._step_parts()
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

    def _step_parts(self):
        """Each engine's environments stepped on their share of the actions, the
        results joined in environment order."""
        outs = [
            p.step(self._actions[a:b])
            for p, a, b in zip(self._parts, self._starts[:-1], self._starts[1:])
        ]
        joined = [np.concatenate([o[k] for o in outs]) for k in range(4)]
        info = {
            key: np.concatenate([o[4][key] for o in outs])
            for key in ("time", "score", "final_obs")
        }
        return (*joined, info)

    def close(self) -> None:
        for p in self._parts:
            p.close()

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
